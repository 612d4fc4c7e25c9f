"""The skeleton on its processors (``docs/skeleton.md`` v1.2 §4b), decided exactly.

:func:`schedule_on_processors` runs the §4b dynamics: the events of the timed
event graph fire as early as their places allow (§3), a compute event
releases a job that its processor runs under preemptive fixed priorities
(priority descending, release ascending, file order), and the places leaving
``T.compute`` receive their token when the job has received ``duration(T)``.

The simulation is event-driven and exact (integers on the graph's common
scale); each *part* (tasks joined by a group or a processor) is simulated on
its own until a proof:

- **periodic regime**: the whole state of the part (tokens of every place,
  with the availability of those not yet available, each job's remaining
  work, the order of the pending jobs) repeats at two ticks of its slowest
  clock, up to places that only gained tokens and whose tokens were never
  the last input of their output event: then the part is periodic for ever
  and those places grow by as many tokens per regime (proof in
  ``docs/analysis.md``). Periods, responses, starved tasks, growing places
  and the overruns still to come follow from one regime;
- **nothing more happens** (a dead part);
- otherwise, once its share of ``max_events`` firings is spent, the figures left are
  null and the
  verdict is null with the reason, unless an overrun was already seen (then
  the skeleton is not schedulable, proven by the overrun itself).

Events that fire infinitely often at time 0 (an upstream closure of tasks of
duration 0 without a clock: a circuit of zero durations) are not simulated:
their tasks have period 0 and response 0, and the places from them to the
rest of the graph are unbounded (tokens pile up at once).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import breadth_first_order, connected_components

from maxplus.scalar import display_text

from ...errors import InputError, ModelError
from ...model.budgets import MAX_EVENTS
from ...model.build import UnboundedKind, activation_end, unbounded_kind
from ...model.limits import event_budget_problem
from ...model.platform import (
    Platform,
    check_groups,
    clock_hyperperiod,
    platform_of,
    processor_parts,
)
from ...model.skeleton import Skeleton
from ...model.teg import TimedEventGraph
from ._engine import AFTER_OVERRUN, PartData, PartResult, simulate_part
from .critical_instant import IndependentVerdict, independent_tasks
from .trace import ScheduleTrace, TraceRequest

__all__ = ["MAX_EVENTS", "GrowingPlace", "JobInterval", "ProcessorSchedule", "Problem",
           "TaskOnProcessors", "schedule_on_processors", "trace_schedule"]


@dataclass(frozen=True)
class JobInterval:
    """A stretch of processor time given to activation ``k`` of ``task``."""

    processor: str
    start: Fraction
    end: Fraction
    task: str
    k: int


# Slots: one per task, 100,000 of them in a report of 100,000 tasks (80 bytes each
# against some 250 with a ``__dict__``).
@dataclass(slots=True)
class TaskOnProcessors:
    """The §4b figures of one task (None where undefined or undecided)."""

    period: Fraction | None = None
    overrun_at: int | None = None
    response: Fraction | None = None
    """From release (its reads done) to the job's end: the largest over the regime."""
    starved: bool = False
    """Proven: a job of the task never receives its duration."""
    decided: bool = False
    """The figures are proven (a regime, or nothing more happens); False: budget."""
    response_from_tick: Fraction | None = None
    """From its clock's tick ``x_C.tick(k)`` to the end of job k: the largest over the
    regime (v1.3); None without a clock, or where ticks pile up (it grows without bound)."""
    starved_since: Fraction | None = None
    """Starved: the release of its job that never ends."""
    stopped_after: int | None = None
    """Proven: no job is ever released after activation ``stopped_after`` (the number of
    jobs it had), although none of its jobs is starved: it waits for events that never
    fire again. None when it runs on (or is starved itself)."""
    waits_for: tuple[str, ...] = ()
    """A stopped task: the starved tasks whose jobs it waits for, through the places
    of the graph (in file order)."""


@dataclass(frozen=True)
class Problem:
    """What makes a schedule not schedulable, at the instant it shows (§4b).

    Every command lists these in one order, earliest first
    (:attr:`ProcessorSchedule.problems`): an overrun at its clock's tick
    ``x_C.tick(k)``, a starved task at the release of the job that never ends.
    """

    kind: str
    """``"overrun"`` or ``"starved"``."""
    task: str
    at: Fraction | None
    """The instant: the overrun's tick, the starved job's release (None: not known,
    a part decided by a theorem)."""
    k: int | None
    """The activation: ``overrun_at`` for an overrun; None for a starved task."""


@dataclass(frozen=True)
class GrowingPlace:
    """An unbounded place on processors."""

    place: int
    src: str
    dst: str
    kind: UnboundedKind
    group: int
    per_regime: int | None
    """Tokens gained per regime of its part; None: infinitely many at time 0."""


# Keyword-only: twelve fields, several of the same type; a positional call cannot be read.
@dataclass(kw_only=True)
class ProcessorSchedule:
    """The result of :func:`schedule_on_processors` (times in the skeleton's unit)."""

    platform: Platform
    schedulable: bool | None
    exact: bool
    method: str
    why_undecided: str | None
    tasks: dict[str, TaskOnProcessors]
    group_periods: list[Fraction | None]
    """``period_on_processors`` of each group, in the order of ``groups``."""
    unbounded: list[GrowingPlace]
    raw_intervals: list[tuple[str, int, int, str, int]] = field(repr=False)
    """(processor, start, end, task, k) with times scaled by ``scale``."""
    scale: int
    regimes: list[dict[str, Any]] = field(default_factory=list)
    """Per part: its tasks, ``start`` and ``length`` of the regime proven (None: not
    found; ``length`` None: nothing happens after ``start``); ``"by": "critical
    instant"`` for a part decided by that theorem, whose ``intervals`` are only a
    quick look at its start."""
    events: int = 0
    """Event firings simulated in all."""
    trace: ScheduleTrace | None = field(default=None, repr=False)
    """What ``trace`` asked to record (spec §4c), None when nothing was asked."""
    with_intervals: bool = True
    """Whether ``raw_intervals`` holds every job's processor time (``intervals=True``)."""
    problems: list[Problem] = field(default_factory=list)
    """Every overrun and starved task, earliest first (then file order): the one order
    of every command's verdict and lists. Growing places have no instant of their
    own: they are :attr:`unbounded`."""

    @property
    def intervals(self) -> list[JobInterval]:
        """Processor time given to each job, up to the proof, by processor then start."""
        if not hasattr(self, "_intervals"):
            order = {p.name: i for i, p in enumerate(self.platform.processors)}
            raw = sorted(self.raw_intervals, key=lambda r: (order[r[0]], r[1]))
            f = self.scale
            self._intervals = [JobInterval(p, Fraction(a, f), Fraction(b, f), t, k)
                               for p, a, b, t, k in raw]
        return self._intervals

    @property
    def starved(self) -> list[str]:
        """The starved tasks, in file order."""
        return [t for t, r in self.tasks.items() if r.starved]

    @property
    def stopped(self) -> list[str]:
        """The tasks that never run again behind a starved task, in file order."""
        return [t for t, r in self.tasks.items() if r.stopped_after is not None]


def schedule_on_processors(skeleton: Skeleton, teg: TimedEventGraph, groups: Sequence[Any], *,
                           platform: Platform | None = None,
                           max_events: int = MAX_EVENTS,
                           intervals: bool = True,
                           trace: TraceRequest | None = None) -> ProcessorSchedule:
    """Decide the skeleton on its processors (§4b), exactly.

    Parameters
    ----------
    skeleton : Skeleton
    teg : TimedEventGraph
        ``build_teg(skeleton)``.
    groups : sequence of GroupReport
        ``analyze_skeleton(skeleton).groups`` (``tasks``, ``clocks``, ``live``
        are read): the groups are computed once, by the caller.
    platform : Platform, optional
        Default :func:`~tegraph.model.platform.platform_of` (``report.platform``).
    max_events : int
        Budget of event firings in all (:data:`MAX_EVENTS`), shared among the parts.
    intervals : bool
        Keep each job's processor time (``intervals``, for drawing a timeline);
        False leaves them out (the figures and the verdict are the same), which
        ``analyze`` does: at 10^6 firings they take hundreds of MiB.
    trace : TraceRequest, optional
        Events and tasks whose instants to record for the chains of §4c
        (``schedule.trace``); the figures and the verdict are the same.

    Returns
    -------
    ProcessorSchedule

    Raises
    ------
    InputError
        ``max_events`` is not an integer >= 1.

    Examples
    --------
    B (period 4) is preempted at 2 by the more urgent A (period 2):

    >>> from tegraph.analysis.analyze import analyze_skeleton
    >>> from tegraph.model.build import build_teg
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2},
    ...                                    "B": {"duration": 2, "period": 4}}})
    >>> s = schedule_on_processors(sk, build_teg(sk), analyze_skeleton(sk).groups)
    >>> s.schedulable, str(s.tasks["B"].response), str(s.tasks["B"].period)
    (True, '4', '4')
    >>> [(i.task, str(i.start), str(i.end)) for i in s.intervals[:4]]
    [('A', '0', '1'), ('B', '1', '2'), ('A', '2', '3'), ('B', '3', '4')]
    >>> s.regimes[0]["start"], s.regimes[0]["length"]  # B's job still ends at 4 there
    (Fraction(4, 1), Fraction(4, 1))
    """
    problem = event_budget_problem(max_events)
    if problem is not None:
        raise InputError(problem, "max_events")
    if "compute" not in teg.attrs:
        raise ModelError("not built from a skeleton (no 'compute' in attrs)", "teg")
    check_groups(skeleton, groups)
    if platform is None:
        platform = platform_of(skeleton, groups)
    net = _Net(skeleton, teg, groups, platform)
    out = _Outcome(net, max_events, trace)
    _simulate_parts(net, out, net.parts(trace=trace), max_events, intervals)
    schedule = out.finish()
    schedule.with_intervals = intervals
    return schedule


def trace_schedule(skeleton: Skeleton, teg: TimedEventGraph, groups: Sequence[Any],
                   platform: Platform, trace: TraceRequest, *,
                   max_events: int = MAX_EVENTS,
                   cycle_times: Mapping[str, Fraction] | None = None) -> ScheduleTrace:
    """Record ``trace`` on the parts that hold its tasks, and simulate nothing else.

    The parameters are those of :func:`schedule_on_processors`, whose rules and
    proofs this runs on those parts alone (their share of ``max_events`` is the
    whole budget); only what was recorded is returned, and a part is simulated
    only to find its regime (no quick look for an early overrun). The chains of
    §4c with a processor per task (:func:`~tegraph.model.platform.processor_per_task`, where
    the schedule is §3's daters) need no other part.

    Parameters
    ----------
    cycle_times : mapping of str to Fraction, optional
        Each task's cycle time on ``platform``, where known beforehand (with a
        processor per task: §4's): a regime holds a whole number of activations of
        each task, so a part whose tasks' cycle times need more firings than its
        share before any regime can repeat is left undecided without simulating.

    Returns
    -------
    ScheduleTrace
    """
    problem = event_budget_problem(max_events)
    if problem is not None:
        raise InputError(problem, "max_events")
    check_groups(skeleton, groups)
    net = _Net(skeleton, teg, groups, platform)
    out = _Outcome(net, max_events, trace, trace_only=True)
    wanted = set(trace.tasks)
    labels = net.part_labels()
    n_parts = len({labels[i] for i, t in enumerate(net.tasks) if t in wanted}) or 1
    # (numerator, denominator) pairs: hashed for each task of each part, cheaper than Fractions.
    known = {t: (c.numerator, c.denominator) for t, c in (cycle_times or {}).items() if c}

    def promising(names: list[str]) -> bool:
        # A part whose regime cannot come within an even share is not even made.
        share = max(max_events // n_parts, 1)
        hyper, ticks = clock_hyperperiod(skeleton, names)
        needed = _least_firings(names, known)
        if ticks > share:
            out.untraced(names, _why_part(skeleton, names, hyper, ticks, True))
        elif needed > share:
            out.untraced(names, f"the part of {_shown(names)}: its tasks' cycle times need at "
                                f"least {needed:,} jobs before a periodic regime can repeat, "
                                "more than its share of `max_events`")
        return ticks <= share and needed <= share

    _simulate_parts(net, out, net.parts(trace=trace, only=wanted, keep=promising), max_events,
                    False)
    assert out.trace is not None
    return out.trace


def _simulate_parts(net: _Net, out: _Outcome, parts: Any, max_events: int,
                    intervals: bool) -> None:
    """Simulate ``parts`` (of ``net.parts``), smallest first, each with its share of what is
    left of ``max_events``, and hand each result to ``out``."""
    skeleton, platform = net.sk, net.platform
    parts = sorted(parts, key=lambda part: part[0].n_events)
    left = max_events
    for i, (data, local_tasks, local_events, local_places) in enumerate(parts):
        share = max(left // (len(parts) - i), 1)
        hyper, ticks = clock_hyperperiod(skeleton, local_tasks)
        # A regime holds a whole number of periods of every clock: it cannot be
        # proven before each clock has ticked over one hyperperiod. Past the
        # share, look only for an early overrun, and say why at once.
        too_long = ticks > share
        if too_long:  # a theorem may cross the hyperperiod where a simulation cannot
            verdict = independent_tasks(skeleton, local_tasks, platform)
            if verdict is not None:
                # The theorem decides; a quick look gives the start of the schedule
                # to draw (its intervals only: it decides nothing).
                look = simulate_part(data, min(share, QUICK_LOOK), intervals)
                left -= look.fired
                out.add_independent(verdict, local_tasks, local_events, hyper, look)
                continue
        result = simulate_part(data, min(share, QUICK_LOOK) if too_long else share, intervals)
        left -= result.fired
        out.add(result, data, local_tasks, local_events, local_places)
        if result.regime is None:
            why = _why_part(skeleton, local_tasks, hyper, ticks, too_long)
            out.undecided.append(why)
            out.untraced(local_tasks, why)


def _least_firings(tasks: list[str], cycle_times: Mapping[str, tuple[int, int]]) -> int:
    """The fewest jobs a regime of these tasks holds: each task's compute fires a whole
    number of times in it, so its length is a common multiple of their cycle times
    (``(numerator, denominator)``; the least: the lcm of the numerators over the gcd of
    the denominators)."""
    known: dict[tuple[int, int], int] = {}  # a part's tasks share a few cycle times
    for t in tasks:
        c = cycle_times.get(t)
        if c is not None:
            known[c] = known.get(c, 0) + 1
    if not known:
        return 0
    num, den = 1, 0
    for a, b in known:
        num, den = math.lcm(num, a), math.gcd(den, b)
    # least / (a / b) = (num / den) * (b / a): a whole number (least is a multiple)
    return sum(num * b // (den * a) * n for (a, b), n in known.items())


QUICK_LOOK = 10_000
"""Firings simulated, to find an early overrun, in a part whose hyperperiod alone
exceeds its share of the budget."""




def _shown(tasks: list[str]) -> str:
    return ", ".join(tasks[:3]) + (" ..." if len(tasks) > 3 else "")


def _why_part(sk: Skeleton, tasks: list[str], hyper: Fraction | None, ticks: int,
              too_long: bool) -> str:
    shown = _shown(tasks)
    if too_long:
        return (f"the part of {shown}: its clocks' hyperperiod is {display_text(hyper)} "
                f"{sk.unit}, at least {ticks:,} clock ticks before a periodic regime can "
                "repeat, more than its share of `max_events`")
    return f"the part of {shown}: no periodic regime within its share of `max_events`"


class _Net:
    """The graph as arrays, the zero-period events and the parts."""

    def __init__(self, sk: Skeleton, teg: TimedEventGraph, groups: Sequence[Any],
                 platform: Platform) -> None:
        a = teg.arrays()
        self.sk, self.teg, self.groups, self.platform = sk, teg, groups, platform
        self.scale = a.scale
        # numpy arrays, not lists: the loops over places are numpy's (a list of
        # 400,000 Python ints costs 10 MB, at 100,000 tasks, for each column).
        self.src, self.dst, self.tokens = a.src, a.dst, a.tokens
        self.hold, self.init = a.holding, a.initial
        self.n = teg.n_transitions
        self.tasks = list(sk.tasks)
        self.compute = teg.attrs["compute"]
        self.is_compute = np.zeros(self.n, dtype=bool)
        self.is_compute[np.fromiter(self.compute.values(), np.int64, len(self.compute))] = True
        self.group_of = {t: g for g, group in enumerate(groups) for t in group.tasks}
        self.zero_mask = self._zero_period()
        self.zero = set(np.flatnonzero(self.zero_mask).tolist())
        graph = sp.csr_matrix((np.ones(len(self.src), dtype=np.int8), (a.src, a.dst)),
                              shape=(self.n, self.n))
        self.scc = connected_components(graph, directed=True, connection="strong")[1]

    def _zero_period(self) -> np.ndarray:
        """Events that fire infinitely often at time 0 (see the module docstring), as a mask."""
        src, dst = self.src, self.dst
        timed = self._reach(dst[(self.hold != 0) | (self.init != 0)])
        zero = ~timed
        # Without any time upstream, every firing is at 0; finitely many when a
        # circuit without token lies upstream (it stops them), else infinitely many.
        z_src = np.flatnonzero(zero[src] & zero[dst] & (self.tokens == 0))
        if not len(z_src):
            return zero
        rows, cols = src[z_src], dst[z_src]
        g = sp.csr_matrix((np.ones(len(rows), dtype=np.int8), (rows, cols)), shape=(self.n, self.n))
        _, label = connected_components(g, directed=True, connection="strong")
        sizes = np.bincount(label)
        stuck = zero & (sizes[label] > 1)
        stuck[rows[rows == cols]] = True
        return zero & ~self._reach(np.flatnonzero(stuck))

    def _reach(self, start: np.ndarray) -> np.ndarray:
        """Mask of the events reachable from the events ``start`` (included) along places:
        a breadth-first search from one more node, linked to each of them."""
        n = self.n
        rows = np.concatenate((self.src, np.full(len(start), n, dtype=np.int64)))
        cols = np.concatenate((self.dst, np.asarray(start, dtype=np.int64)))
        graph = sp.csr_matrix((np.ones(len(rows), dtype=np.int8), (rows, cols)),
                              shape=(n + 1, n + 1))
        seen = np.zeros(n + 1, dtype=bool)
        seen[breadth_first_order(graph, n, directed=True, return_predecessors=False)] = True
        return seen[:n]

    def _union_parts(self) -> list[int]:
        """Part label of each task: tasks joined by a group or a processor."""
        part = processor_parts([g.tasks for g in self.groups], self.platform.processor_of)
        return [part[self.group_of[t]] for t in self.tasks]

    def part_labels(self) -> list[int]:
        """Part label of each task (in file order): tasks joined by a group or a processor."""
        if not hasattr(self, "_labels"):
            self._labels = self._union_parts()
        return self._labels

    def parts(self, trace: TraceRequest | None = None, only: set[str] | None = None,
              keep: Any = None):
        """For each part: its :class:`PartData` and its global tasks, events and places.

        ``trace``: what the parts record; ``only``: the parts holding one of these
        tasks alone, and of those, with ``keep``, only those whose task names it
        keeps (the others are not made)."""
        label = self.part_labels()
        index = {t: i for i, t in enumerate(self.tasks)}
        part_of_event: dict[int, int] = {}
        for e, attrs in enumerate(self.teg.transition_attrs):
            if attrs.get("tasks"):
                part_of_event[e] = label[index[attrs["tasks"][0]]]
        for t, task in self.sk.tasks.items():
            if task.clock is not None:
                part_of_event[self.teg.attrs["clocks"][task.clock]] = label[index[t]]
        # Each part's events and places, in increasing order, by numpy over the arrays
        # (tens of thousands of events and places at 10,000 tasks).
        part = np.full(self.n, -1, dtype=np.int64)
        part[np.fromiter(part_of_event, np.int64, len(part_of_event))] = np.fromiter(
            part_of_event.values(), np.int64, len(part_of_event))
        zero, src, dst = self.zero_mask, self.src, self.dst
        events = np.flatnonzero((part >= 0) & ~zero)
        members = _by_label(events, part[events])
        kept = np.flatnonzero((part[src] >= 0) & ~zero[src] & ~zero[dst])
        places = _by_label(kept, part[src[kept]])
        by_label: dict[int, list[int]] = {}
        for i, t in enumerate(self.tasks):
            if self.compute[t] not in self.zero:
                by_label.setdefault(label[i], []).append(i)
        no_place = np.zeros(0, dtype=np.int64)
        logged: dict[int, np.ndarray] = {}  # the events each part records (trace)
        started = frozenset(() if trace is None else trace.tasks)
        if trace is not None and trace.events:
            traced = np.unique(np.asarray(trace.events, dtype=np.int64))
            traced = traced[(part[traced] >= 0) & ~zero[traced]]
            logged = _by_label(traced, part[traced])
        for lab in sorted(members, key=lambda lab: members[lab][0]):
            tasks = by_label.get(lab, [])
            if only is not None and not any(self.tasks[i] in only for i in tasks):
                continue
            if keep is not None and not keep([self.tasks[i] for i in tasks]):
                continue
            yield self._part_data(tasks, members[lab], places.get(lab, no_place),
                                  None if trace is None else (logged.get(lab, no_place), started))

    def _part_data(self, tasks: list[int], events: np.ndarray, places: np.ndarray,
                   trace: tuple[np.ndarray, frozenset[str]] | None = None):
        """The part of these global tasks, events (increasing) and places, re-indexed
        locally for the engine (:class:`PartData`), with them; with ``trace`` (the
        part's events to record, the tasks whose jobs to record), what it records, in
        its local numbers."""
        event_list = events.tolist()  # freed on return
        local = dict(zip(event_list, range(len(event_list))))  # for the tasks' events
        names = [self.tasks[i] for i in tasks]
        procs: dict[str, int] = {}  # its processors, numbered in the order of its tasks
        for t in names:
            procs.setdefault(self.platform.processor_of[t], len(procs))
        watched, slowest_tick = self._watched(names, local)
        # The columns of its places by numpy: a local event is its rank among the
        # part's events (increasing), its index in ``events``.
        src, dst = self.src[places], self.dst[places]
        tokens = self.tokens[places]
        caps = np.where(self.scc[src] == self.scc[dst], -1, tokens + 2).tolist()
        data = PartData(
            n_events=len(event_list),
            p_src=np.searchsorted(events, src).tolist(),
            p_dst=np.searchsorted(events, dst).tolist(),
            p_tokens=tokens.tolist(), p_hold=_ints(self.hold[places]),
            p_init=_ints(self.init[places]),
            p_job=self.is_compute[src].tolist(),
            # None (counted exactly) on a circuit, where the circuit's tokens bound
            # its count; else its initial tokens + 2.
            p_cap=[None if c < 0 else c for c in caps],
            compute_task=self._compute_task(tasks, event_list, local),
            # int(duration * scale), on ints (a duration is >= 0: floor is truncation)
            duration=[_floor_scaled(self.sk.tasks[t].duration, self.scale) for t in names],
            priority=[self.platform.priority[t] for t in names], file_index=tasks,
            processor=[procs[self.platform.processor_of[t]] for t in names],
            n_processors=len(procs),
            end_event=[_end_event(self.teg, t, local) for t in names],
            watched=watched, snapshot_place=self._snapshot_place(src, dst, events, slowest_tick),
            preemptive=[self.platform.preemptive(p) for p in procs])
        if trace is not None:
            data.logged = [local[e] for e in trace[0].tolist()]
            data.started = [j for j, t in enumerate(names) if t in trace[1]]
        # Its events and places stay arrays: kept for the figures until the part is
        # simulated, they cost 8 bytes each, not the 36 of a list of ints.
        return data, names, events, places

    def _compute_task(self, tasks: list[int], events: list[int],
                      local: dict[int, int]) -> list[int]:
        """``PartData.compute_task``: per local event, the local task it computes, or -1."""
        compute_task = [-1] * len(events)
        for j, i in enumerate(tasks):
            compute_task[local[self.compute[self.tasks[i]]]] = j
        return compute_task

    def _watched(self, names: list[str], local: dict[int, int]
                 ) -> tuple[dict[int, list[int]], int | None]:
        """``PartData.watched`` (local tick -> the local clocked tasks it activates) and
        the local tick of the slowest clock (the first of the slowest), or None
        without clock."""
        watched: dict[int, list[int]] = {}
        slowest: tuple[Fraction, int] | None = None
        for j, t in enumerate(names):
            clock = self.sk.tasks[t].clock
            if clock is not None:
                tick = local[self.teg.attrs["clocks"][clock]]
                watched.setdefault(tick, []).append(j)
                period = self.sk.clocks[clock].period
                if slowest is None or period > slowest[0]:
                    slowest = (period, tick)
        return watched, None if slowest is None else slowest[1]

    def _snapshot_place(self, src: np.ndarray, dst: np.ndarray, events: np.ndarray,
                        tick: int | None) -> int | None:
        """``PartData.snapshot_place``: the local self-loop place of the local ``tick``
        (the slowest clock's), None when there is no clock; ``src`` and ``dst`` are
        the global events of the part's places."""
        if tick is None:
            return None
        e = events[tick]
        return int(np.flatnonzero((src == e) & (dst == e))[0])


def _end_event(teg: TimedEventGraph, task: str, local: dict[int, int]) -> int | None:
    """The local event whose firing ends an activation of ``task`` (spec §4), or None
    when it ends with the computation: on processors, when its job finishes."""
    end = activation_end(teg, task)
    return None if end.adds_duration else local[end.event]


def _floor_scaled(t: Fraction, scale: int) -> int:
    """``int(t * scale)`` for a time ``t >= 0``, without building the product Fraction.

    >>> _floor_scaled(Fraction(7, 3), 6), _floor_scaled(Fraction(7, 3), 2)
    (14, 4)
    """
    return t.numerator * scale // t.denominator


def _ints(column: np.ndarray) -> list[int]:
    """The Python ints of an integer column (``int64``, or ``object`` past 64 bits).

    >>> _ints(np.array([3, 0])), _ints(np.array([2**70], dtype=object))
    ([3, 0], [1180591620717411303424])
    """
    return [int(v) for v in column] if column.dtype == object else column.tolist()


def _by_label(items: np.ndarray, labels: np.ndarray) -> dict[int, np.ndarray]:
    """``items`` (increasing) grouped by their ``labels``, each group still increasing.

    >>> {lab: group.tolist() for lab, group in
    ...  _by_label(np.array([1, 4, 6, 9]), np.array([7, 3, 7, 3])).items()}
    {3: [4, 9], 7: [1, 6]}
    """
    if not len(items):
        return {}
    order = np.argsort(labels, kind="stable")
    sorted_labels = labels[order]
    cuts = np.flatnonzero(sorted_labels[1:] != sorted_labels[:-1]) + 1
    firsts = np.concatenate(([0], cuts))
    return {int(lab): chunk for lab, chunk in
            zip(sorted_labels[firsts].tolist(), np.split(items[order], cuts))}


class _Outcome:
    """The figures of every part, assembled into a :class:`ProcessorSchedule`."""

    def __init__(self, net: _Net, budget: int, trace: TraceRequest | None = None,
                 trace_only: bool = False) -> None:
        self.net = net
        self.budget = budget
        self.trace_only = trace_only
        """Only what ``trace`` asks is kept (:func:`trace_schedule`), no figure."""
        self.trace = None if trace is None else ScheduleTrace(
            net.scale, dict(net.platform.processor_of), frozenset(trace.tasks))
        self.tasks = {t: TaskOnProcessors() for t in net.tasks}
        self.unbounded: list[GrowingPlace] = []
        self.intervals: list[tuple[str, int, int, str, int]] = []
        self.regimes: list[dict[str, Any]] = []
        self.undecided: list[str] = []
        self.by_theorem = 0
        """Parts decided by the critical instant (``critical_instant.py``)."""
        self.after_overrun = 0
        """Parts whose search for a regime stopped past their first overrun (AFTER_OVERRUN)."""
        self.events = 0
        self.rate: dict[int, set] = {}
        """Group -> the cycle times of its events (None: an event that stops)."""
        self.grows: set[int] = set()
        for t in net.tasks:
            if net.compute[t] in net.zero:
                self.tasks[t] = TaskOnProcessors(Fraction(0), None, Fraction(0), False, True)
                self.untraced([t], f"{t} runs infinitely often at time 0 (a circuit of zero "
                                   "durations without a clock)")
        # The places from a zero-period event to the rest: unbounded at time 0.
        zero = net.zero_mask
        for p in np.flatnonzero(zero[net.src] & ~zero[net.dst]).tolist():
            self._grow(p, None)

    def _fraction(self, v: int) -> Fraction:
        return Fraction(v, self.net.scale)

    def untraced(self, names: Sequence[str], why: str) -> None:
        """No regime of these tasks' part to record (``trace``): ``why``."""
        if self.trace is not None:
            self.trace.undecided_part(names, why)

    def _grow(self, p: int, per: int | None) -> None:
        net = self.net
        place = net.teg.places[p]
        src, dst = int(net.src[p]), int(net.dst[p])
        # The task of its destination, else of its source (a clock's tick has none).
        owner = net.teg.transition_attrs[dst].get("tasks") or \
            net.teg.transition_attrs[src]["tasks"]
        group = net.group_of[owner[0]]
        self.grows.add(group)
        self.unbounded.append(GrowingPlace(
            p, net.teg.transition_names[src], net.teg.transition_names[dst],
            unbounded_kind(place.kind), group, per))

    def add(self, r: PartResult, d: PartData, names: list[str], events: np.ndarray,
            places: np.ndarray) -> None:
        self.events += r.fired
        self.after_overrun += r.after_overrun is not None
        procs = list(dict.fromkeys(self.net.platform.processor_of[t] for t in names))
        self.intervals += [(procs[proc], start, end, names[task], k)
                           for proc, start, end, task, k in r.intervals]
        for task, k in r.overrun_at.items():
            self.tasks[names[task]].overrun_at = k
        if self.trace is not None:
            self.trace.add_part(r, d, names, events, self.net.sk.unit)
            if self.trace_only:
                return
        if r.regime is None:
            self.regimes.append({"tasks": names, "start": None, "length": None})
            return
        if r.regime[0] == "stop":
            self.regimes.append({"tasks": names, "start": self._fraction(r.regime[1]),
                                 "length": None})
            for t in names:
                self.tasks[t].decided = True
            self._rates(events.tolist(), None)
            return
        self._regime(r, d, names, events, places)

    def add_independent(self, v: IndependentVerdict, names: list[str], events: np.ndarray,
                        hyper: Fraction | None, look: PartResult) -> None:
        """A part decided by the critical instant: its figures, and the intervals of a
        quick look at its start (``regimes`` says ``"by": "critical instant"``)."""
        self.by_theorem += 1
        self.events += look.fired
        self.untraced(names, f"the part of {', '.join(names[:3])}"
                             f"{' ...' if len(names) > 3 else ''} is decided by the critical "
                             "instant, without simulating its regime (its hyperperiod is too "
                             "long)")
        procs = list(dict.fromkeys(self.net.platform.processor_of[t] for t in names))
        self.intervals += [(procs[proc], start, end, names[task], k)
                           for proc, start, end, task, k in look.intervals]
        for t, r in v.response.items():
            fig = self.tasks[t]
            if t == v.late:
                fig.overrun_at, fig.decided = 2, True
            else:
                # Each job is released at its tick (every job ends by the next one), so
                # the time from the tick is the time from the release.
                fig.period, fig.response, fig.decided = v.period[t], r, True
                fig.response_from_tick = r
        met = {t for t in v.period}
        self.regimes.append({"tasks": names, "start": None if v.late else Fraction(0),
                             "length": None if v.late else hyper, "by": "critical instant"})
        for e in events.tolist():  # _rate reads the task events (a clock's has no task)
            owner = self.net.teg.transition_attrs[e].get("tasks")
            if owner and owner[0] in met:
                self._rate(e, v.period[owner[0]])

    def _rate(self, event: int, value: Fraction | None) -> None:
        self._rates([event], value)

    def _rates(self, events: list[int], value: Fraction | None) -> None:
        """The cycle time ``value`` for the groups of these events (a clock's has none)."""
        attrs, group_of = self.net.teg.transition_attrs, self.net.group_of
        groups = set()
        for event in events:
            tasks = attrs[event].get("tasks")
            if tasks:
                groups.add(group_of[tasks[0]])
        for g in groups:
            self.rate.setdefault(g, set()).add(value)

    def _regime(self, r: PartResult, d: PartData, names: list[str], events: np.ndarray,
                places: np.ndarray) -> None:
        # Type: called only for a part whose regime was found.
        t1, t2, old, new, growing = r.regime  # type: ignore[misc]
        length = t2 - t1
        self.regimes.append({"tasks": names, "start": self._fraction(t1),
                             "length": self._fraction(length)})
        fired = [b - a for a, b in zip(old.fired, new.fired)]
        # The period of an event firing n times a regime: one Fraction per count
        # (a part of 10,000 tasks has a few counts and some 30,000 events), and each
        # group's set of them filled once per count (not a Fraction hash per event).
        period: dict[int, Fraction | None] = {0: None}
        for n in set(fired) - {0}:
            period[n] = Fraction(length, n * self.net.scale)
        counts: dict[int, list[int]] = {}
        for e, n in zip(events.tolist(), fired):
            counts.setdefault(n, []).append(e)
        for n, with_n in counts.items():
            self._rates(with_n, period[n])
        for p, per in growing.items():
            self._grow(int(places[p]), per)
        compute_of = {j: e for e, j in enumerate(d.compute_task) if j >= 0}
        tick_of = {j: e for e, ts in d.watched.items() for j in ts}
        stopped = []
        for j, t in enumerate(names):
            fig = self.tasks[t]
            fig.decided = True
            compute = compute_of[j]
            n = fired[compute]
            fig.starved = n == 0 and new.pending[j] >= 0
            if fig.starved:
                fig.starved_since = self._fraction(r.jobs[j][-1][0])
            elif n == 0:  # no job of its own, none to come: it waits for ever
                fig.stopped_after = new.fired[compute]
                stopped.append(j)
            if n:
                fig.period = period[n]
                fig.response = self._fraction(_response(r.jobs[j], old.fired[compute],
                                                        new.fired[compute], length))
                if j in tick_of and fired[tick_of[j]] == n:  # as many ticks as jobs
                    fig.response_from_tick = self._fraction(_response_from_tick(
                        r.jobs[j], r.tick_log[j], old.fired[compute], new.fired[compute],
                        length))
            if fig.overrun_at is None and j in r.tick_log:
                tick = tick_of[j]
                last = d.end_event[j]
                ends = (new.finished[j] - old.finished[j] if last is None
                        else fired[last])
                fig.overrun_at = _overrun_to_come(r.tick_log[j], t1, t2, fired[tick], ends)
        if stopped:
            for j, waits in _waits_for(d, fired, stopped, compute_of, names, self.tasks).items():
                self.tasks[names[j]].waits_for = waits

    def finish(self) -> ProcessorSchedule:
        net = self.net
        group_periods: list[Fraction | None] = []
        live = all(g.live for g in net.groups)
        for g, group in enumerate(net.groups):
            rates = self.rate.get(g, set())
            if all(net.compute[t] in net.zero for t in group.tasks):
                rates = {Fraction(0)}
            ok = group.live and g not in self.grows and len(rates) == 1 and None not in rates
            group_periods.append(next(iter(rates)) if ok else None)
            if not group.live:
                for t in group.tasks:
                    self.tasks[t] = TaskOnProcessors(decided=self.tasks[t].decided)
        unbounded = [u for u in self.unbounded if net.groups[u.group].live]
        index = {t: i for i, t in enumerate(net.tasks)}
        self.regimes.sort(key=lambda r: index[r["tasks"][0]])
        unbounded.sort(key=lambda u: u.place)
        verdict, why = self._verdict(live, unbounded)
        problems = self._problems()
        parts = len(self.regimes)
        simulated = parts - self.by_theorem
        lazy = [p.name for p in net.platform.processors if not p.preemptive]
        policy = (f"; non-preemptive on {', '.join(lazy)}, §4d" if lazy else "")
        method = (f"exact event-driven simulation of the schedule on processors (§4b{policy}), "
                  f"{self.events} event firings in {simulated} independent part(s); "
                  + self._proofs(simulated)) if simulated or not parts else ""
        if self.by_theorem:
            method += ("; " if method else "exact schedule on processors (§4b): ") + (
                       f"{self.by_theorem} part(s) of independent periodic tasks released "
                       "together on one processor, whose hyperperiod is too long to "
                       "simulate, decided by the critical instant (Liu and Layland 1973) "
                       "and the exact response-time test (Lehoczky, Sha and Ding 1989)")
        return ProcessorSchedule(platform=net.platform, schedulable=verdict,
                                 exact=verdict is not None, method=method, why_undecided=why,
                                 tasks=self.tasks, group_periods=group_periods,
                                 unbounded=unbounded, raw_intervals=self.intervals,
                                 scale=net.scale, regimes=self.regimes, events=self.events,
                                 trace=self.trace, problems=problems)

    def _problems(self) -> list[Problem]:
        """Every overrun (at its tick) and starved task (at its job's release), earliest
        first, then in file order."""
        sk = self.net.sk
        out: list[tuple[tuple, Problem]] = []
        for i, (t, f) in enumerate(self.tasks.items()):
            if f.overrun_at is not None:
                clock = sk.tasks[t].clock
                at = (None if clock is None else
                      sk.clocks[clock].phase + (f.overrun_at - 1) * sk.clocks[clock].period)
                out.append(((at is None, at or 0, i, 0), Problem("overrun", t, at, f.overrun_at)))
            if f.starved:
                at = f.starved_since
                out.append(((at is None, at or 0, i, 1), Problem("starved", t, at, None)))
        out.sort(key=lambda x: x[0])
        return [p for _, p in out]

    def _proofs(self, simulated: int) -> str:
        """What the simulation proved: a regime per part, or, where the budget ran out
        first, only what it exhibited (an overrun, a growing place, a starved job)."""
        proof = ("periodic regime proven by a repeated state (up to places that only gain "
                 "tokens, never taken last)")
        # A part whose simulation ran out of budget has no regime: its start is None
        # (a part that stops for ever has a start and no length).
        open_parts = sum(1 for r in self.regimes if r["start"] is None and "by" not in r)
        if not open_parts:
            return f"each part's {proof}"
        exhibited = ("only what the simulation exhibited (an overrun, a growing place, a "
                     "job that never ends) is proven")
        # A part's search stops past its first overrun before the budget (AFTER_OVERRUN).
        past = ("within as many firings again as its first overrun took (at least "
                f"1/{AFTER_OVERRUN} of its share; the overrun decides the verdict)")
        if not self.after_overrun:
            within = "within the budget"
        elif self.after_overrun == open_parts:
            within = past
        else:
            within = f"within the budget, or for {self.after_overrun} of them {past}"
        if open_parts == simulated:
            return f"no periodic regime {within}: {exhibited}"
        return (f"the {proof} in {simulated - open_parts} of them; in the other "
                f"{open_parts}, none {within}: {exhibited}")

    def _verdict(self, live: bool, unbounded: list[GrowingPlace]) -> tuple[bool | None, str | None]:
        found = (not live or unbounded or any(
            f.overrun_at is not None or f.starved for f in self.tasks.values()))
        if found:
            return False, None
        why = []
        if self.undecided:
            why.append(f"undecided within the budget of {self.budget:,} event firings "
                       f"(shared among {len(self.regimes)} independent part(s)): "
                       + "; ".join(self.undecided))
        if why:
            return None, "; ".join(why)
        return True, None


def _response(jobs: list[list], c1: int, c2: int, length: int) -> int:
    """Largest finish - release over the jobs released in the regime (numbers c1+1..c2).

    A job still running when the regime closes ends as the job running when it
    opened (job c1, which ended within the regime), one regime later.
    """
    best = 0
    for k in range(c1 + 1, c2 + 1):
        release, finish = jobs[k - 1]
        if finish is None:
            finish = jobs[c1 - 1][1] + length
        best = max(best, finish - release)
    return best


def _response_from_tick(jobs: list[list], ticks: list[tuple[int, int, int]], c1: int,
                        c2: int, length: int) -> int:
    """Largest finish - tick over the jobs released in the regime (numbers c1+1..c2).

    Job k is released by tick k (its activation takes the k-th tick's token); the
    regime holds as many ticks as jobs, so job k + n ends, and tick k + n comes,
    one regime after job k and tick k (n = c2 - c1): a job still running when the
    regime closes counts as the job n earlier, which ended.
    """
    at = {k: now for now, k, _ in ticks}
    n = c2 - c1
    best = 0
    for k in range(c1 + 1, c2 + 1):
        finish = jobs[k - 1][1]
        j = k
        while finish is None:  # the same job, one regime earlier
            j -= n
            finish = jobs[j - 1][1]
        best = max(best, finish - at[j])
    return best


def _waits_for(d: PartData, fired: list[int], stopped: list[int], compute_of: dict[int, int],
               names: list[str], figures: dict[str, TaskOnProcessors]
               ) -> dict[int, tuple[str, ...]]:
    """For each stopped task (local index), the starved tasks it waits for.

    Backwards along the places from its compute event, through the events that
    fire no more in the regime: the compute events of starved tasks met on the
    way are what it waits for (their jobs never end, so nothing after them fires).
    """
    into: dict[int, list[int]] = {}
    for s, t in zip(d.p_src, d.p_dst):
        if not fired[s]:
            into.setdefault(t, []).append(s)
    starved = {compute_of[j]: j for j, t in enumerate(names) if figures[t].starved}
    out = {}
    for j in stopped:
        seen = {compute_of[j]}
        todo = [compute_of[j]]
        found = set()
        while todo:
            e = todo.pop()
            if e in starved and starved[e] != j:
                found.add(starved[e])
            for s in into.get(e, ()):
                if s not in seen:
                    seen.add(s)
                    todo.append(s)
        out[j] = tuple(names[i] for i in sorted(found))
    return out


def _overrun_to_come(log: list[tuple[int, int, int]], t1: int, t2: int, ticks: int,
                     ends: int) -> int | None:
    """The first overrun after a proven regime [t1, t2), from the slack at its ticks.

    In the regime a task's clock ticks ``ticks`` times and its activations end
    ``ends`` times per regime, so the slack ``ends - (k - 1)`` at each tick of
    the regime falls by ``ticks - ends`` per regime: never below 0 when that
    is 0 (every tick of one regime was checked), else first after
    ``slack // fall + 1`` more regimes, at tick ``k + that * ticks``.
    """
    fall = ticks - ends
    if fall <= 0:
        return None
    return min((k + (s // fall + 1) * ticks for t, k, s in log if t1 <= t < t2), default=None)
