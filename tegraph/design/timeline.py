"""Timing diagram: exact preemptive fixed-priority simulation of a skeleton.

Figure 17 of the ORCCAD paper [1]_ shows the computed-torque law on one
processor under rate-monotonic priorities [2]_. :func:`simulate_timeline`
produces that diagram as data, exactly (Fractions), over the hyperperiod of
the clocks:

- each processor runs, at every instant, its most urgent *ready* task
  (larger priority first; equal priorities first come, first served; then
  file order), preempting less urgent ones;
- a task executes its chain (spec §2) when it holds the processor: it waits
  for its clock (a tick releases it; ticks are queued, as in the timed event
  graph), reads its inputs and writes its outputs in order — instantaneous,
  but blocking as the protocols say (ASYN/SYN: the reader waits for a message
  newer than its last read; SYN/ASYN: the writer waits for a request newer
  than its last write; SYN/SYN: the first to arrive waits for the other) —
  and computes for its duration, which takes processor time;
- a thread runs its tasks one after the other;
- at an instant where a computation ends and a clock ticks, the ending job
  posts its outputs before the newly released jobs are dispatched;
- a job is *late* (drawn red) when it ends after the next tick of its pacing
  clock (its own clock, else the single clock of its group): job ``j`` of a
  task with a clock is late exactly when the task *overruns at activation
  j + 1* (spec §4: tick ``j + 1`` comes while activation ``j`` has not ended,
  the end being its last write, or its computation's end without outputs);
- a skeleton that is not live is reported by its token-free circuits
  (:func:`~tegraph.analysis.deadlocks.skeleton_deadlocks`, as ``tegraph
  analyze``): the tasks of a dead group block for ever, and none of their
  jobs is called late (spec §4: the deadlock is reported instead).

The text rendering (:func:`render_timeline`) draws one row per task and the
exact order of execution; :mod:`tegraph.report.plot` draws the picture.

References
----------
.. [1] D. Simon et al., "Design and analysis of synchronization for
   real-time closed-loop control in robotics", IEEE Transactions on Control
   Systems Technology, 1998.
.. [2] C. L. Liu, J. W. Layland, "Scheduling algorithms for
   multiprogramming in a hard-real-time environment", Journal of the ACM
   20(1), 46–61, 1973.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from maxplus.scalar import display_text, exact_text

from ..analysis.deadlocks import skeleton_deadlocks
from ..analysis.results import Deadlock
from ..errors import InputError, ModelError
from ..model.build import build_teg
from ..model.limits import shown
from ..model.skeleton import Protocol, Skeleton
from .rules import synchronized_groups
from .schedulability import effective_priorities, hyperperiod

__all__ = ["MAX_JOBS", "Job", "OverrunMap", "Timeline", "simulate_timeline"]

_STEPS_PER_INSTANT = 1000
"""Budget, per chain step of the skeleton, of steps taken at one instant."""

MAX_JOBS = 100_000
"""Default bound on the jobs a simulation may run (``max_jobs``): at some ten
thousand jobs a second, a refusal comes at once where the work would take minutes.
"""


@dataclass
class Job:
    """One run of a task's chain."""

    task: str
    index: int
    """1-based activation number."""
    release: Fraction
    """When its first step became possible (a tick, or the data it waits for)."""
    finish: Fraction | None = None
    """When its last step fired; None if it runs past the horizon."""
    segments: list[tuple[Fraction, Fraction]] = field(default_factory=list)
    """Processor time, as [start, end) intervals."""
    deadline: Fraction | None = None
    """The next tick of its pacing clock (None without one)."""
    late: bool = False
    """It ends after its deadline, or is still running at a deadline within the horizon."""

    @property
    def preemptions(self) -> int:
        """How many times it lost the processor before finishing its computation."""
        return max(len(self.segments) - 1, 0)

    @property
    def overrun_at(self) -> int | None:
        """The activation at which its task overruns because of this job (late: ``index + 1``)."""
        return self.index + 1 if self.late else None


class OverrunMap(dict):
    """Task -> first activation that overruns, or None: ``timeline.overrun_at[task]``.

    Calling it, ``timeline.overrun_at(task)`` (the method of tegraph 0.x),
    still answers the same, with a :class:`DeprecationWarning`.
    """

    def __call__(self, task: str) -> int | None:
        warnings.warn("Timeline.overrun_at is an attribute now (as Report.tasks[T].overrun_at): "
                      "write timeline.overrun_at[task]", DeprecationWarning, stacklevel=2)
        return self[task]


@dataclass
class Timeline:
    """The result of :func:`simulate_timeline`.

    See Also
    --------
    simulate_timeline : makes it.
    tegraph.report.render_text : its text diagram.

    Examples
    --------
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 10}}})
    >>> tl = simulate_timeline(sk)
    >>> tl.horizon, tl.tasks, tl.order_of_execution()
    (Fraction(10, 1), ['A'], [('A', Fraction(0, 1), Fraction(2, 1))])
    """

    name: str
    unit: str
    horizon: Fraction
    tasks: list[str]
    """Rows: by processor, most urgent first, then file order."""
    priorities: dict[str, int]
    priority_source: dict[str | None, str]
    processors: dict[str, str | None]
    ticks: dict[str, list[Fraction]]
    """Tick times of each clock before the horizon."""
    clocks: dict[str, str | None]
    """The clock that activates each task (ticks are drawn on its row)."""
    jobs: list[Job]
    pacing: dict[str, str | None] = field(default_factory=dict)
    """The clock whose ticks each task's jobs must end by (its own, else its group's)."""
    deadlocks: list[Deadlock] = field(default_factory=list)
    """Token-free circuits of the timed event graph (empty: the skeleton is live)."""
    dead_tasks: list[str] = field(default_factory=list)
    """The tasks of the groups that hold a deadlock, in file order: never late."""
    full_horizon: Fraction | None = None
    """The default horizon (largest phase plus hyperperiod) when a shorter ``horizon``
    cut the simulation: nothing is proven past ``horizon`` then. None otherwise."""

    def order_of_execution(self, processor: str | None = None
                           ) -> list[tuple[str, Fraction, Fraction]]:
        """``(task, start, end)`` of every processor interval on ``processor``, by start."""
        out = [(j.task, a, b) for j in self.jobs for a, b in j.segments
               if self.processors[j.task] == processor]
        return sorted(out, key=lambda x: (x[1], x[2]))

    @property
    def late_jobs(self) -> list[Job]:
        return [j for j in self.jobs if j.late]

    @property
    def overrun_at(self) -> OverrunMap:
        """Each task's first activation that overruns in the horizon, or None (spec §4 numbering).

        ``timeline.overrun_at["A"]`` reads as ``report.tasks["A"].overrun_at``
        of :func:`tegraph.analyze`: the same attribute, the same numbering.
        """
        first: dict[str, int | None] = dict.fromkeys(self.tasks)
        for j in self.jobs:
            if j.late and first.get(j.task) is None:
                first[j.task] = j.overrun_at
        return OverrunMap(first)

    @property
    def exit_status(self) -> int:
        """0 no deadlock and no late job; 1 otherwise (as ``tegraph analyze``)."""
        return 1 if self.deadlocks or self.late_jobs else 0

    def to_dict(self) -> dict[str, Any]:
        """Plain data (exact times as strings)."""
        return {"name": self.name, "unit": self.unit, "horizon": exact_text(self.horizon),
                "full_horizon": exact_text(self.full_horizon),
                "priorities": self.priorities,
                "ticks": {c: [exact_text(x) for x in ts] for c, ts in self.ticks.items()},
                "deadlocks": [{"events": d.events, "tasks": d.tasks,
                               "links": [link.document() for link in d.links]}
                              for d in self.deadlocks],
                "dead_tasks": self.dead_tasks,
                "jobs": [{"task": j.task, "index": j.index, "release": exact_text(j.release),
                          "finish": exact_text(j.finish), "deadline": exact_text(j.deadline),
                          "late": j.late, "overrun_at": j.overrun_at,
                          "segments": [[exact_text(a), exact_text(b)] for a, b in j.segments]}
                         for j in self.jobs]}


class _Sim:
    """State of the simulation; the rules are in the module docstring."""

    def __init__(self, sk: Skeleton, priorities: dict[str, int]) -> None:
        self.sk = sk
        self.prio = priorities
        self.index = {t: i for i, t in enumerate(sk.tasks)}
        self.steps: dict[str, list[tuple[str, str]]] = {}
        for name, task in sk.tasks.items():
            chain = [("activate", "")] if task.clock else []
            chain += [("read", p) for p in task.inputs]
            chain.append(("compute", ""))
            chain += [("write", p) for p in task.outputs]
            self.steps[name] = chain
        self.pos = {t: 0 for t in sk.tasks}
        # Processor time still owed to the current computation; -1: not started.
        self.remaining: dict[str, Fraction] = {t: Fraction(-1) for t in sk.tasks}
        self.pending = {t: 0 for t in sk.tasks}
        self.fresh = [False] * len(sk.links)      # ASYN/SYN: a message not yet read
        self.requested = [False] * len(sk.links)  # SYN/ASYN: a request not yet answered
        self.into = {link.reader: i for i, link in enumerate(sk.links)}
        self.out_of: dict[tuple[str, str], list[int]] = {}
        for i, link in enumerate(sk.links):
            self.out_of.setdefault(link.writer, []).append(i)
        self.thread_of = {t: (k, j) for k, th in enumerate(sk.threads) for j, t in enumerate(th)}
        self.turn = [0] * len(sk.threads)
        self.ready_since: dict[str, Fraction | None] = {t: None for t in sk.tasks}
        self.job: dict[str, Job | None] = {t: None for t in sk.tasks}
        self.count = {t: 0 for t in sk.tasks}

    def step(self, t: str) -> tuple[str, str]:
        return self.steps[t][self.pos[t]]

    def ready(self, t: str) -> bool:
        """The current step of ``t`` can be taken as soon as ``t`` has the processor."""
        kind, port = self.step(t)
        if self.pos[t] == 0 and t in self.thread_of:
            k, j = self.thread_of[t]
            if self.turn[k] != j:
                return False
        if kind == "activate":
            return self.pending[t] > 0
        if kind == "compute":
            return True
        if kind == "read":
            i = self.into.get((t, port))
            if i is None:
                return True
            proto = self.sk.links[i].protocol
            if proto is Protocol.ASYN_SYN:
                return self.fresh[i]
            if proto is Protocol.SYN_SYN:
                return self._event_ready(self.sk.links[i].writer)
            return True
        return self._event_ready((t, port))

    def _parties(self, writer: tuple[str, str]) -> list[tuple[str, str, str]]:
        """(task, kind, port) of everyone who takes part in the write event of ``writer``."""
        return [(writer[0], "write", writer[1])] + [
            (self.sk.links[i].reader[0], "read", self.sk.links[i].reader[1])
            for i in self.out_of.get(writer, [])
            if self.sk.links[i].protocol is Protocol.SYN_SYN]

    def _event_ready(self, writer: tuple[str, str]) -> bool:
        """All parties of a (rendezvous) write are at their step, all requests are in."""
        if any(self.step(task) != (kind, port) for task, kind, port in self._parties(writer)):
            return False
        return all(self.requested[i] for i in self.out_of.get(writer, [])
                   if self.sk.links[i].protocol is Protocol.SYN_ASYN)

    def fire(self, t: str, now: Fraction, jobs: list[Job]) -> None:
        """Take the current step of ``t``, which is ready and holds its processor."""
        kind, port = self.step(t)
        if kind == "compute":
            self._start(t, now, jobs)
            if self.remaining[t] < 0:
                self.remaining[t] = Fraction(self.sk.tasks[t].duration)
            if self.remaining[t] > 0:
                return  # the main loop gives it processor time
            self.remaining[t] = Fraction(-1)
        elif kind == "read" and (i := self.into.get((t, port))) is not None:
            proto = self.sk.links[i].protocol
            if proto is Protocol.SYN_SYN:
                self._write(self.sk.links[i].writer, now, jobs)
                return
            self._start(t, now, jobs)
            if proto is Protocol.ASYN_SYN:
                self.fresh[i] = False
            elif proto is Protocol.SYN_ASYN:
                self.requested[i] = True
        elif kind == "write":
            self._write((t, port), now, jobs)
            return
        else:  # activate, or a read of an unlinked port
            self._start(t, now, jobs)
            if kind == "activate":
                self.pending[t] -= 1
        self._advance(t, now)

    def _write(self, writer: tuple[str, str], now: Fraction, jobs: list[Job]) -> None:
        for i in self.out_of.get(writer, []):
            proto = self.sk.links[i].protocol
            if proto is Protocol.ASYN_SYN:
                self.fresh[i] = True
            elif proto is Protocol.SYN_ASYN:
                self.requested[i] = False
        for task, _, _ in self._parties(writer):
            self._start(task, now, jobs)
            self._advance(task, now)

    def _start(self, t: str, now: Fraction, jobs: list[Job]) -> None:
        if self.pos[t] == 0 and (self.job[t] is None or self.job[t].finish is not None):
            self.count[t] += 1
            since = self.ready_since[t]
            self.job[t] = Job(t, self.count[t], since if since is not None else now)
            jobs.append(self.job[t])  # type: ignore[arg-type]

    def _advance(self, t: str, now: Fraction) -> None:
        self.pos[t] += 1
        if self.pos[t] == len(self.steps[t]):
            self.pos[t] = 0
            self.job[t].finish = now  # type: ignore[union-attr]
            if t in self.thread_of:
                k, j = self.thread_of[t]
                self.turn[k] = (j + 1) % len(self.sk.threads[k])


def simulate_timeline(skeleton: Skeleton, horizon: Fraction | int | str | None = None,
                      max_jobs: int = MAX_JOBS) -> Timeline:
    """Simulate ``skeleton`` under preemptive fixed priorities, exactly.

    Parameters
    ----------
    skeleton : Skeleton
        Priorities as declared on each processor whose tasks all declare one,
        rate-monotonic otherwise (:func:`tegraph.design.schedulability.effective_priorities`).
    horizon : Fraction, optional
        End of the simulation. Default: the largest clock phase plus the
        hyperperiod of the clock periods; without a clock, twice the sum of
        the durations (at least 1).
    max_jobs : int
        Bound on the jobs simulated (default :data:`MAX_JOBS`). Before
        simulating, each task's jobs up to the horizon are bounded (ticks of
        its clock, horizon over duration, one more than the task it waits for
        or alternates with); past ``max_jobs`` the call is refused at once.

    Returns
    -------
    Timeline
        What runs on each processor when, up to ``horizon`` (Figure 17 of the
        ORCCAD paper [1]_ is such a diagram).

    Raises
    ------
    ModelError
        The horizon is not positive, or a task of duration 0 with nothing to
        wait for loops without time passing.
    InputError
        ``max_jobs`` is not a positive integer, or the simulation up to the
        horizon may take more jobs than ``max_jobs`` (``where`` is
        ``"max_jobs"``; the message names the horizon, the hyperperiod and the
        tasks that run most often).

    See Also
    --------
    tegraph.design.schedulability.schedulability : the response times that
        bound what the timeline shows.
    tegraph.design.schedulability.hyperperiod : the default horizon's length.
    tegraph.analyze : the analysis without processor contention.

    References
    ----------
    .. [1] D. Simon et al., "Design and analysis of synchronization for
       real-time closed-loop control in robotics", IEEE Transactions on Control
       Systems Technology, 1998.

    Examples
    --------
    B (period 4) is preempted at 2 by the more urgent A (period 2):

    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2},
    ...                                    "B": {"duration": 2, "period": 4}}})
    >>> tl = simulate_timeline(sk)
    >>> [(t, str(a), str(b)) for t, a, b in tl.order_of_execution()]
    [('A', '0', '1'), ('B', '1', '2'), ('A', '2', '3'), ('B', '3', '4')]
    """
    if isinstance(max_jobs, bool) or not isinstance(max_jobs, int) or max_jobs < 1:
        raise InputError(f"expected an integer >= 1, got {shown(repr(max_jobs), quote=False)}",
                         "max_jobs")
    priorities, source = effective_priorities(skeleton)
    clocks = skeleton.clocks
    if clocks:
        full = max(c.phase for c in clocks.values()) + hyperperiod(
            c.period for c in clocks.values())
    else:
        full = max(2 * sum((t.duration for t in skeleton.tasks.values()), Fraction(0)),
                   Fraction(1))
    horizon = full if horizon is None else Fraction(horizon)
    if horizon <= 0:
        raise ModelError(f"the horizon must be > 0, got {_time(horizon, skeleton.unit)}",
                         "timeline")
    _check_jobs(skeleton, horizon, horizon == full and bool(clocks), max_jobs)
    ticks = {c: [k.phase + n * k.period for n in range(_count(k.phase, k.period, horizon))]
             for c, k in clocks.items()}
    activated: dict[Fraction, list[str]] = {}
    for name, task in skeleton.tasks.items():
        if task.clock:
            for x in ticks[task.clock]:
                activated.setdefault(x, []).append(name)
    tick_times = sorted(activated)
    by_processor: dict[str | None, list[str]] = {}
    for name, task in skeleton.tasks.items():
        by_processor.setdefault(task.processor, []).append(name)
    sim = _Sim(skeleton, priorities)
    jobs: list[Job] = []
    running: dict[str | None, str | None] = {p: None for p in by_processor}
    now, next_tick = Fraction(0), 0
    while True:
        # Completion before release: a job whose computation ends now posts its
        # outputs before the tasks released by the ticks of this instant run.
        _dispatch(sim, by_processor, running, now, jobs)
        while next_tick < len(tick_times) and tick_times[next_tick] <= now:
            for name in activated[tick_times[next_tick]]:
                sim.pending[name] += 1  # queued, as tokens in the clock -> activate place
            next_tick += 1
        _dispatch(sim, by_processor, running, now, jobs)
        if now >= horizon:
            break
        step = min([horizon - now]
                   + ([tick_times[next_tick] - now] if next_tick < len(tick_times) else [])
                   + [sim.remaining[t] for t in running.values() if t is not None])
        for t in running.values():
            if t is None:
                continue
            segments = sim.job[t].segments  # type: ignore[union-attr]
            if segments and segments[-1][1] == now:
                segments[-1] = (segments[-1][0], now + step)
            else:
                segments.append((now, now + step))
            sim.remaining[t] -= step
        now += step
    pacing = _pacing_clocks(skeleton)
    deadlocks = skeleton_deadlocks(build_teg(skeleton))
    stuck = {t for d in deadlocks for t in d.tasks}
    dead = {t for group in synchronized_groups(skeleton) if stuck.intersection(group)
            for t in group}
    for job in jobs:
        clock = pacing[job.task]
        if clock is not None:
            k = clocks[clock]
            job.deadline = k.phase + job.index * k.period
            if job.finish is not None:
                job.late = job.finish > job.deadline
            else:  # unfinished: late if its deadline passed, or is now and it still computes
                job.late = job.deadline < horizon or (
                    job.deadline == horizon and sim.job[job.task] is job
                    and sim.remaining[job.task] > 0)
            # In a dead group the clock ticks at a blocked task: that is the
            # deadlock, reported as such, not an overrun (spec §4).
            job.late = job.late and job.task not in dead
    order = list(by_processor)
    rows = sorted(skeleton.tasks, key=lambda t: (
        order.index(skeleton.tasks[t].processor), -priorities[t], sim.index[t]))
    return Timeline(skeleton.name, skeleton.unit, horizon, rows, priorities, source,
                    {t: skeleton.tasks[t].processor for t in skeleton.tasks}, ticks,
                    {t: skeleton.tasks[t].clock for t in skeleton.tasks}, jobs, pacing,
                    deadlocks, [t for t in skeleton.tasks if t in dead],
                    full if horizon < full else None)


def job_bounds(skeleton: Skeleton, horizon: Fraction) -> dict[str, int | None]:
    """An upper bound on the jobs each task starts before ``horizon`` (None: no bound).

    Jobs of one task run one after the other, so a task of duration ``d > 0``
    starts at most ``horizon/d + 1`` (each started job but the last has
    computed ``d``); a clocked task at most one per tick before the horizon.
    A task waiting for another (the reader of an ASYN/SYN link its writer's
    messages, the writer of a SYN/ASYN link its reader's requests, both sides
    of a SYN/SYN link, the next task of a thread) starts at most one job more
    than that other: each wait consumes what one of its jobs produced. The
    bounds are the least fixed point of these inequalities (shortest paths of
    weight 1, by relaxation). None remains only for tasks of duration 0 with
    no clock, where nothing bounds the jobs: the simulation refuses such a
    loop at the first instant it repeats without time passing.
    """
    bound: dict[str, int | None] = {}
    for name, task in skeleton.tasks.items():
        own = []
        if task.clock:
            k = skeleton.clocks[task.clock]
            own.append(_count(k.phase, k.period, horizon))
        if task.duration > 0:
            own.append(math.floor(horizon / task.duration) + 1)
        bound[name] = min(own) if own else None
    waits: list[tuple[str, str]] = []  # (task that waits, task it waits for)
    for link in skeleton.links:
        w, r = link.writer[0], link.reader[0]
        if link.protocol is Protocol.ASYN_SYN:
            waits.append((r, w))
        elif link.protocol is Protocol.SYN_ASYN:
            waits.append((w, r))
        elif link.protocol is Protocol.SYN_SYN:
            waits += [(r, w), (w, r)]
    for thread in skeleton.threads:
        waits += [(b, a) for a, b in zip(thread, thread[1:] + thread[:1])]
    for _ in range(len(bound)):
        changed = False
        for waiter, other in waits:
            via = bound[other]
            if via is not None and (bound[waiter] is None or via + 1 < bound[waiter]):
                bound[waiter] = via + 1
                changed = True
        if not changed:
            break
    return bound


def _check_jobs(sk: Skeleton, horizon: Fraction, default: bool, max_jobs: int) -> None:
    """Refuse, before simulating, a horizon whose jobs may exceed ``max_jobs``."""
    bounds = job_bounds(sk, horizon)
    total = sum(b for b in bounds.values() if b is not None)
    if total <= max_jobs:
        return
    u = sk.unit
    if sk.clocks:
        hyper = hyperperiod(c.period for c in sk.clocks.values())
        why = (f"the default horizon, the largest clock phase plus the hyperperiod "
               f"{_time(hyper, u)} of the clock periods" if default
               else f"the hyperperiod of the clock periods is {_time(hyper, u)}")
    else:
        why = "no clock: the default horizon is twice the sum of the durations"
    busiest = sorted((b, t) for t, b in bounds.items() if b is not None)[::-1][:3]
    counts = ", ".join(f"{t} {_amount(b)}" for b, t in busiest)
    raise InputError(
        f"simulating up to {_time(horizon, u)} ({why}) may take {_amount(total)} jobs "
        f"({counts}), more than `max_jobs` = {max_jobs:,}: give a shorter `horizon`, or raise "
        "`max_jobs` (nothing was simulated)", "max_jobs")


def _time(value: Fraction, unit: str) -> str:
    """A time for a message: as the input wrote it, cut with its length when too long to read.

    A horizon of 2 + 2e-400 ms is a fraction of 802 characters: the message shows its
    first 40 and its length (:func:`~tegraph.model.limits.shown`, the one way messages
    shorten a value), never the whole number.

    >>> _time(Fraction(5, 2), "ms"), _time(2 + Fraction(2, 10**400), "ms")[-24:]
    ('2.5 ms', '... (802 characters) ms')
    """
    return f"{shown(display_text(value), quote=False)} {unit}"


def _amount(n: int) -> str:
    """A count as text: exact with thousands separators, or its order of magnitude."""
    if n.bit_length() <= 64:
        return f"{n:,}"
    return f"more than 10^{math.floor((n.bit_length() - 1) * math.log10(2))}"



def _count(phase: Fraction, period: Fraction, horizon: Fraction) -> int:
    """How many ticks ``phase + n*period`` fall before the horizon."""
    return 0 if phase >= horizon else math.ceil((horizon - phase) / period)


def _pacing_clocks(sk: Skeleton) -> dict[str, str | None]:
    """Each task's own clock, else the single clock of its group, else None."""
    out: dict[str, str | None] = {}
    for group in synchronized_groups(sk):
        clocks = {sk.tasks[t].clock for t in group if sk.tasks[t].clock}
        for t in group:
            own = sk.tasks[t].clock
            out[t] = own if own else (next(iter(clocks)) if len(clocks) == 1 else None)
    return out


def _dispatch(sim: _Sim, by_processor: dict[str | None, list[str]],
              running: dict[str | None, str | None], now: Fraction, jobs: list[Job]) -> None:
    """Let each processor's most urgent ready task take its instantaneous steps at ``now``."""
    fired, budget = 0, _STEPS_PER_INSTANT * (1 + sum(len(c) for c in sim.steps.values()))
    while True:
        for tasks in by_processor.values():
            for t in tasks:
                if not sim.ready(t):
                    sim.ready_since[t] = None
                elif sim.ready_since[t] is None:
                    sim.ready_since[t] = now
        progress = False
        for p, tasks in by_processor.items():
            ready = [t for t in tasks if sim.ready_since[t] is not None]
            if not ready:
                running[p] = None
                continue
            # Larger priority first; equal priorities first come, first served.
            top = min(ready, key=lambda t: (-sim.prio[t], sim.ready_since[t], sim.index[t]))
            running[p] = top
            if sim.step(top)[0] == "compute" and sim.remaining[top] > 0:
                continue
            sim.fire(top, now, jobs)
            progress = True
            fired += 1
            if fired > budget:
                raise ModelError(
                    f"{top} runs its chain again and again at {_time(now, sim.sk.unit)} "
                    "without time passing "
                    "(a task of duration 0 with nothing to wait for)", "timeline")
            break
        if not progress:
            return


