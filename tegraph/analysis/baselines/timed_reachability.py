"""Timed exploration: the ORCCAD paper's §5 search, the baseline for periods and overruns.

The paper finds a task set's steady state by walking its timed reachability
graph until a state repeats, and its temporal inconsistencies by watching for
a clock tick that finds its task still running. :func:`timed_reachability`
does exactly that on the timed event graph of a skeleton, with the
earliest-firing semantics of ``docs/skeleton.md`` §3 and exact arithmetic
(times scaled to integers by their common denominator):

* a **state** is the marking together with the remaining holding time of
  every token (0 once it is available), taken after every firing; places are
  FIFO, as the dater recurrence consumes tokens in the order they came;
* at each instant the enabled event of smallest index fires first, so the run
  is a function of the state, and a repeated state repeats forever;
* the search ends when the **whole** state repeats (the paper's criterion:
  the state space of independent groups is their product, so it grows with the
  least common multiple of their periods) or when nothing can fire any more.

Groups are independent, so each group's figures are read off the first repeat
of the state *restricted to the group*: between the two occurrences every
event of the group fired ``c0`` times in ``Δt``, so its period is
``Δt / c0``. Spec §4 counts the transient in firing indices, so the recorded
firing times give it exactly: the cyclicity ``c`` is the smallest divisor of
``c0`` for which ``x_e(k+c) = x_e(k) + c·λ`` holds over one whole cycle, and
the transient ``K`` the first index from which it holds for every event (the
repeat proves it beyond the first occurrence; before, it is checked firing by
firing). A group that repeats without time passing would fire forever at one
instant (a circuit of zero holding time): it is retired with period 0.

An **overrun** is the paper's sink-place event: when an instant ends, a
clock has ticked ``k`` times while activation ``k - 1`` of its task has not
ended: ``end(k-1) > x_tick(k)``, the end of an activation being its last write,
or, for a task without outputs, the end of its computation (spec §4, v1.1).
The first such ``k`` is the spec's ``overrun_at``; unlike the paper's sink,
the run goes on (spec §3 has no sink).

A **deadlock** is read off a state: the events that can never fire again are
the largest set ``D`` of events each of which has an empty input place (no
token, not even one still held) whose input event is in ``D`` (the first of
them to fire would need a token that only another of them can bring). ``D``
is empty exactly when the marking has no token-free circuit, which a firing
never changes in a marked graph: a group is dead from its first state or
never. A dead group reports no overrun (a clock ticking at a blocked task is
the deadlock, as ``analyze`` says, spec §4); it is explored until ``D`` holds
every event but its clocks' ticks, or until its state outside ``D`` repeats
(what still runs then runs periodically, and ``D`` is final); then it is
retired with its stuck events.
"""

from __future__ import annotations

import heapq
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from maxplus.scalar import exact_text

from ...model.budgets import DEFAULT_MAX_STATES
from ...model.build import activation_end, build_teg
from ...model.skeleton import Skeleton
from ...model.teg import TEGArrays, TimedEventGraph
from .reachability import skeleton_groups

__all__ = ["TimedExploration", "TimedGroup", "TimedTask", "timed_reachability"]

Progress = Callable[[int, int, float], None]
"""``progress(states, firings, seconds)``, called every few thousand firings."""

_POLL = 1024  # firings between two looks at the clock, the stop flag and progress
# A task of positive duration fires each of its events at most once per
# instant; only zero-duration circuits fire more. Past this many firings at one
# instant (times 2 past 100 events, 3 past 200...) without a repeated state, a
# group is taken to fire without end there.
_STALL = 1000


@dataclass
class TimedGroup:
    """Steady state of one group, as the first repeat of its own state shows it.

    Attributes
    ----------
    index : int
    tasks : list of str
    period : Fraction or None
        ``Δt / c0`` at the repeat; None when the state did not repeat.
    transient : tuple of (int, int) or None
        ``(K, c)`` of spec §4, in firing indices.
    repeat : tuple of (Fraction, Fraction) or None
        Times at which the repeated state was first and again seen.
    states : int
        Distinct states of the group seen.
    """

    index: int
    tasks: list[str]
    period: Fraction | None = None
    transient: tuple[int, int] | None = None
    repeat: tuple[Fraction, Fraction] | None = None
    states: int = 0
    stuck_after: Fraction | None = None
    """Set for a dead group: the time of the last firing of any of its stuck
    events (0 when none ever fired); none of them fires after it."""
    stuck_events: list[str] | None = None
    """Set for a dead group: the events that never fire again (a token-free
    circuit and what waits on it), in event order, as known when the search
    left the group (a budget may stop it before more get stuck); its ticks go on."""
    stalled_at: Fraction | None = None
    """Set when the group kept firing at this instant with ever more tokens
    (a zero-duration task feeding a place that never empties): time cannot
    move past it, so the group is left out from then on."""


@dataclass
class TimedTask:
    """Figures of one task: its group's period and its first overrun.

    ``decided`` is True when ``overrun_at`` is final: the task has no clock,
    its group is dead (no overrun there, spec §4), an overrun was seen, the
    group's state repeated (every later instant replays a seen one), or the
    exploration ended by itself.
    """

    name: str
    group: int
    period: Fraction | None = None
    overrun_at: int | None = None
    decided: bool = False


# Keyword-only: twelve fields, several of the same type; a positional call cannot be read.
@dataclass(kw_only=True)
class TimedExploration:
    """What :func:`timed_reachability` found.

    Attributes
    ----------
    name, unit : str
    states : int
        Distinct whole states (all groups together) seen.
    firings : int
    complete : bool
        The search ended by itself: see ``ended_by``.
    ended_by : str or None
        ``"repeat"`` (the whole state repeated) or ``"quiescence"`` (nothing
        can fire any more) when complete.
    stopped_by : str or None
        ``"states"``, ``"time"`` or ``"interrupted"`` when incomplete.
    time_reached : Fraction
        Simulated time at the end.
    groups : list of TimedGroup
    tasks : dict of str to TimedTask
    max_states : int
    seconds : float
    """

    name: str
    unit: str
    states: int
    firings: int
    complete: bool
    ended_by: str | None
    stopped_by: str | None
    time_reached: Fraction
    groups: list[TimedGroup]
    tasks: dict[str, TimedTask]
    max_states: int
    seconds: float

    @property
    def overrun(self) -> bool:
        """Whether some task overran."""
        return any(t.overrun_at is not None for t in self.tasks.values())

    @property
    def deadlock(self) -> bool:
        """Whether some group is dead (it has stuck events)."""
        return any(g.stuck_events is not None for g in self.groups)

    @property
    def exit_status(self) -> int:
        """1 when an overrun or a deadlock was found, else 0 (as ``tegraph analyze``); 130
        when the search was interrupted (Ctrl-C: the command's status, its counts partial)."""
        if self.stopped_by == "interrupted":
            return 130
        return int(self.overrun or self.deadlock)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: ``states``, ``complete``, ``tasks`` and ``groups`` as spec §4 means them."""
        return {
            "name": self.name, "unit": self.unit, "mode": "timed", "states": self.states,
            "firings": self.firings, "complete": self.complete, "ended_by": self.ended_by,
            "stopped_by": self.stopped_by, "time_reached": exact_text(self.time_reached),
            "tasks": {t.name: {"group": t.group, "period": exact_text(t.period),
                               "overrun_at": t.overrun_at, "decided": t.decided}
                      for t in self.tasks.values()},
            "groups": [{"tasks": g.tasks, "period": exact_text(g.period),
                        "transient": None if g.transient is None
                        else {"k": g.transient[0], "cyclicity": g.transient[1]},
                        "states": g.states, "stuck_after": exact_text(g.stuck_after),
                        "stuck_events": g.stuck_events,
                        "stalled_at": exact_text(g.stalled_at),
                        "repeat": None if g.repeat is None
                        else [exact_text(g.repeat[0]), exact_text(g.repeat[1])]}
                       for g in self.groups],
            "max_states": self.max_states, "seconds": round(self.seconds, 6),
        }

def timed_reachability(model: Skeleton | TimedEventGraph, *, max_states: int = DEFAULT_MAX_STATES,
                       max_seconds: float | None = None, progress: Progress | None = None,
                       stop: Callable[[], bool] | None = None) -> TimedExploration:
    """Explore the timed state space of a skeleton until its whole state repeats.

    Parameters
    ----------
    model : Skeleton or TimedEventGraph
        A TEG must come from :func:`tegraph.model.build.build_teg` (task chains).
    max_states : int
        Stop (incomplete) rather than see more distinct whole states.
    max_seconds : float, optional
        Stop (incomplete) after about this long.
    progress : callable, optional
        ``progress(states, firings, seconds)``.
    stop : callable, optional
        Polled every few thousand firings; True ends the run (``"interrupted"``).

    Returns
    -------
    TimedExploration

    Examples
    --------
    The paper's double synchronization: A (duration 3) and B (duration 3)
    share a clock of period 4 and phase 1, and B also waits for A's message.
    B reads at ``4k`` and writes at ``4k + 3``, after the next tick at ``4k + 1``:
    it keeps pace (period 4) but overruns from its second activation, which
    it starts at 7 instead of 5 (so the transient is 2):

    >>> sk = Skeleton.from_dict({"clocks": {"c": {"period": 4, "phase": 1}}, "tasks": {
    ...     "A": {"duration": 3, "clock": "c", "outputs": ["x"]},
    ...     "B": {"duration": 3, "clock": "c", "inputs": ["x"], "outputs": ["y"]}},
    ...     "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]})
    >>> r = timed_reachability(sk)
    >>> r.complete, r.groups[0].period, r.groups[0].transient, r.tasks["B"].overrun_at
    (True, Fraction(4, 1), (2, 1), 2)
    """
    teg = build_teg(model) if isinstance(model, Skeleton) else model
    sim = _Simulation(teg, max_states, max_seconds, progress, stop)
    sim.run()
    return sim.result(model.name if isinstance(model, Skeleton) else teg.name,
                      model.unit if isinstance(model, Skeleton) else teg.attrs.get("unit", ""))


class _Simulation:
    """Earliest firing, one event at a time, with the repeat and overrun watches."""

    def __init__(self, teg: TimedEventGraph, max_states: int, max_seconds: float | None,
                 progress: Progress | None, stop: Callable[[], bool] | None) -> None:
        a = teg.arrays()
        self.scale = a.scale
        self.max_states, self.progress, self.stop = max_states, progress, stop
        self.start = time.perf_counter()
        self.deadline = None if max_seconds is None else self.start + max_seconds
        task_lists, members = skeleton_groups(teg)
        n = teg.n_transitions
        self.members = [m.tolist() for m in members]
        self.group_of = self._group_of(n)
        self._wire_places(a)
        self.groups = [TimedGroup(g, list(ts)) for g, ts in enumerate(task_lists)]
        self.names = teg.transition_names
        self.ticks = {e for e in range(n) if teg.transition_attrs[e].get("role") == "tick"}
        self.last_fired = [-1] * n
        # A group is dead from its first state or never (module docstring).
        self.dead = [bool(self._stuck(g)) for g in range(len(members))]
        self._watch_overruns(teg)
        self._start_run(n)

    def _group_of(self, n: int) -> list[int]:
        """Each event's group, -1 for a clock that activates nothing (it belongs to none)."""
        group_of = [-1] * n
        for g, events in enumerate(self.members):
            for e in events:
                group_of[e] = g
        return group_of

    def _wire_places(self, a: TEGArrays) -> None:
        """Each event's input places and output places with their holding times, each place's
        initial tokens (FIFO, with their availability times) and each group's places."""
        n, k = len(self.group_of), len(self.members)
        src, dst = a.src.tolist(), a.dst.tolist()
        hold, init, tokens = (v.tolist() for v in (a.holding, a.initial, a.tokens))
        self.src, self.dst = src, dst
        self.inp: list[list[int]] = [[] for _ in range(n)]
        self.out: list[list[tuple[int, int]]] = [[] for _ in range(n)]
        self.fifo: list[deque[int]] = [deque() for _ in src]
        self.places_of: list[list[int]] = [[] for _ in range(k)]
        self.inflight = [0] * k  # latest availability time put in each group
        for p, (s, d) in enumerate(zip(src, dst)):
            g = self.group_of[s]
            if g < 0:
                continue  # a clock that activates nothing: no group
            self.inp[d].append(p)
            self.out[s].append((p, int(hold[p])))
            self.fifo[p].extend([int(init[p])] * int(tokens[p]))
            self.places_of[g].append(p)
            if tokens[p]:
                self.inflight[g] = max(self.inflight[g], int(init[p]))

    def _watch_overruns(self, teg: TimedEventGraph) -> None:
        """Each task's figures, and for a clocked task of a live group what the overrun
        check needs: its clock's tick to watch and its last event, whose firings end
        its activations."""
        self.tasks: dict[str, TimedTask] = {}
        self.watch: dict[int, list[tuple[str, int]]] = {}
        self.ends: dict[int, list[tuple[str, int, deque[int]]]] = {}
        for task, chain in teg.attrs.get("chains", {}).items():
            clock = teg.transition_attrs[chain[0]].get("clock")
            g = self.group_of[chain[0]]
            # Without a clock there is nothing to overrun, and in a dead group the
            # deadlock is reported instead (spec §4): decided from the start.
            self.tasks[task] = TimedTask(task, g, decided=clock is None or self.dead[g])
            if clock is not None and not self.dead[g]:  # an activation event: the task's clock
                tick = teg.attrs["clocks"][clock]
                end = activation_end(teg, task)  # its last event, maybe plus its duration
                ended: deque[int] = deque(maxlen=2)  # end times of the last two activations
                self.watch.setdefault(tick, []).append((task, end.event))
                self.ends.setdefault(end.event, []).append(
                    (task, int(end.offset * self.scale), ended))
        self.ended = {task: ended for entries in self.ends.values()
                      for task, _, ended in entries}
        # Per event, what its firing must record (a list: looked up at every firing).
        self.end_of: list[list[tuple[str, int, deque[int]]] | None] = [
            self.ends.get(e) for e in range(teg.n_transitions)]

    def _start_run(self, n: int) -> None:
        """The state of the run before its first firing: counts, daters, seen states, clock."""
        k = len(self.members)
        self.count = [0] * n
        # Dead groups have no period: their daters are not kept.
        self.daters: list[list[int] | None] = [
            None if self.dead[self.group_of[e]] else [] for e in range(n)]
        self.log: list[list[int] | None] = [None if d else [] for d in self.dead]
        # Per group: state -> (id, time first seen, group firings by then).
        self.seen: list[dict[tuple, Any]] = [{} for _ in range(k)]
        self.current = [0] * k
        self.repeated = [False] * k
        self.whole: set[tuple[int, ...]] = set()
        self.now = 0
        self.firings = 0
        self.complete = False
        self.ended_by: str | None = None
        self.stopped_by: str | None = None
        self.version = [0] * n
        self.heap: list[tuple[int, int, int]] = []
        self.ticked: set[int] = set()
        self.instant = [-1] * k  # last instant each group fired at, and how often
        self.at_instant = [0] * k

    # ------------------------------------------------------------------ firing
    def _ready(self, e: int) -> int | None:
        """When e can fire (not before now), or None while an input place is empty."""
        when = self.now
        for p in self.inp[e]:
            f = self.fifo[p]
            if not f:
                return None
            when = max(when, f[0])
        return when

    def _schedule(self, e: int) -> None:
        self.version[e] += 1
        if self.current[self.group_of[e]] < 0:
            return  # retired
        when = self._ready(e)
        if when is not None:
            heapq.heappush(self.heap, (when, e, self.version[e]))

    def _fire(self, e: int) -> None:
        now, fifo = self.now, self.fifo
        for p in self.inp[e]:
            fifo[p].popleft()
        touched = [e]
        g = self.group_of[e]
        for p, h in self.out[e]:
            f = fifo[p]
            # A token is taken only after those before it (FIFO, as the daters
            # count firings), so it is never usable earlier than they are.
            when = now + h if not f or f[-1] <= now + h else f[-1]
            f.append(when)
            if len(f) == 1:
                touched.append(self.dst[p])
            self.inflight[g] = max(self.inflight[g], when)
        self.count[e] += 1
        if self.dead[g]:
            self.last_fired[e] = now  # what is stuck, since when
        ends = self.end_of[e]
        if ends is not None:
            for _, offset, ended in ends:
                ended.append(now + offset)
        if self.instant[g] != now:
            self.instant[g], self.at_instant[g] = now, 0
        self.at_instant[g] += 1
        if self.at_instant[g] > _STALL * (1 + len(self.members[g]) // 100):
            self._retire(g)
            self.groups[g].stalled_at = Fraction(now, self.scale)
        x = self.daters[e]
        if x is not None:
            x.append(now)
            # Type: only dead groups have no log, and their daters are None (x above).
            self.log[g].append(e)  # type: ignore[union-attr]
        if e in self.watch:
            self.ticked.add(e)
        for event in touched:
            self._schedule(event)

    def _end_instant(self) -> None:
        """Overrun check: tick k of this instant finds activation k - 1 of its task not ended."""
        for tick in self.ticked:
            k = self.count[tick]
            for task, last in self.watch[tick]:
                t = self.tasks[task]
                if t.overrun_at is not None or k < 2:
                    continue
                done = self.count[last]  # activations begun and ended, at most k
                ended = self.ended[task]
                # ended[-1] is the end of activation `done`, ended[-2] of `done - 1`.
                if done < k - 1 or ended[len(ended) - 1 - (done - (k - 1))] > self.now:
                    t.overrun_at, t.decided = k, True
        self.ticked.clear()

    def _stuck(self, g: int) -> set[int]:
        """The events of group g that can never fire again (module docstring).

        The largest set D in which each event has an empty input place whose
        input event is in D: start from every event with an empty input place
        and drop, until none is left to drop, those whose empty input places all
        come from outside D. A clock's tick is never in D (its self-loop always
        holds its token).
        """
        fifo, src = self.fifo, self.src
        feeding: dict[int, int] = {}  # event -> empty input places whose input event is in D
        for e in self.members[g]:
            empty = sum(1 for p in self.inp[e] if not fifo[p])
            if empty:
                feeding[e] = empty
        candidates = set(feeding)
        for e in candidates:  # only places from candidates count
            feeding[e] = sum(1 for p in self.inp[e] if not fifo[p] and src[p] in candidates)
        drop = [e for e, c in feeding.items() if c == 0]
        stuck = set(candidates)
        while drop:
            e = drop.pop()
            stuck.discard(e)
            for p, _ in self.out[e]:
                d = self.dst[p]
                if not fifo[p] and d in stuck:
                    feeding[d] -= 1
                    if feeding[d] == 0:
                        drop.append(d)
        return stuck

    # ------------------------------------------------------------------ states
    def _key(self, g: int, skip: set[int] | None = None) -> tuple:
        """The group's state now: per place, its available tokens and the others' residues.

        ``skip``: leave out the places into these events.

        A place is an int (all its tokens available: how many) or a tuple
        ``(available, residue, residue, ...)``. Availability never decreases
        along a place (see :meth:`_fire`), so the tokens still held are its tail,
        and a place where messages pile up costs no more than one that does not.
        """
        now, fifo = self.now, self.fifo
        parts: list[int | tuple[int, ...]] = []
        for p in self.places_of[g]:
            if skip and self.dst[p] in skip:
                continue
            f = fifo[p]
            if not f or f[-1] <= now:
                parts.append(len(f))
                continue
            held = []
            for a in reversed(f):
                if a <= now:
                    break
                held.append(a - now)
            parts.append((len(f) - len(held), *reversed(held)))
        return tuple(parts)

    def _record(self, dirty: set[int] | range) -> None:
        for g in dirty:
            if self.current[g] < 0:
                continue  # retired
            if self.dead[g]:
                self._record_dead(g)
                continue
            key = self._key(g)
            seen = self.seen[g]
            entry = seen.get(key)
            if entry is None:
                log = self.log[g]
                entry = seen[key] = (len(seen), self.now, 0 if log is None else len(log))
            # Type: dead groups were handled above: a live group has its log.
            elif not self.repeated[g] and len(self.log[g]) > entry[2]:  # type: ignore[arg-type]
                self._regime(g, entry)
            if self.current[g] >= 0:
                self.current[g] = entry[0]
        whole = tuple(self.current)
        if whole in self.whole:
            self.complete, self.ended_by = True, "repeat"
        elif len(self.whole) >= self.max_states:
            self.stopped_by = "states"
        else:
            self.whole.add(whole)

    def _record_dead(self, g: int) -> None:
        """A dead group's state: its stuck events D and the places outside D.

        Places into D only gather tokens that nothing consumes, so what still
        runs depends on the other places alone: a repeat of (D, those places)
        means it runs periodically from there, and D is final.
        """
        stuck = self._stuck(g)
        everything = all(e in stuck or e in self.ticks for e in self.members[g])
        key = (tuple(sorted(stuck)), self._key(g, skip=stuck))
        seen = self.seen[g]
        if everything or key in seen:
            self._retire(g)
        else:
            self.current[g] = seen[key] = len(seen)

    def _report_stuck(self, g: int) -> None:
        """What is stuck in dead group g now: the events that never fire again, and since when."""
        stuck = self._stuck(g)
        group = self.groups[g]
        group.stuck_events = [self.names[e] for e in sorted(stuck)]
        fired = max((self.last_fired[e] for e in stuck), default=-1)
        group.stuck_after = Fraction(max(fired, 0), self.scale)

    def _regime(self, g: int, entry: tuple[int, int, int]) -> None:
        """The group's state repeated: period, transient and cyclicity from the daters."""
        _, t0, pos = entry
        # Type: a regime is found only for a live group, which has its log.
        window = self.log[g][pos:]  # type: ignore[index]
        events = self.members[g]
        c0 = len(window) // len(events)
        fired: dict[int, int] = {}
        for e in window:
            fired[e] = fired.get(e, 0) + 1
        if any(fired.get(e, 0) != c0 for e in events):
            raise AssertionError(f"internal error: group {g} repeated with unequal firing counts")
        span = self.now - t0
        daters = [self.daters[e] for e in events]
        k, c = _transient(daters, [self.count[e] - c0 for e in events], c0, span)
        group = self.groups[g]
        group.period = Fraction(span, c0 * self.scale)
        group.transient = (k, c)
        group.repeat = (Fraction(t0, self.scale), Fraction(self.now, self.scale))
        self.repeated[g] = True
        self.log[g] = None
        for e in events:
            self.daters[e] = None
        for name in group.tasks:
            self.tasks[name].period = group.period
            self.tasks[name].decided = True
        if span == 0:
            # It would fire forever at this instant (a circuit without holding
            # time): retire it, or time would never move on.
            self._retire(g)

    def _retire(self, g: int) -> None:
        """Leave group g out from now on (its events never fire again here)."""
        if self.dead[g]:
            self._report_stuck(g)
        self.groups[g].states = len(self.seen[g])
        self.current[g] = -1
        for e in self.members[g]:
            self.version[e] += 1

    # ------------------------------------------------------------------ run
    def run(self) -> None:
        for events in self.members:
            for e in events:
                self._schedule(e)
        self._record(range(len(self.members)))
        heap, version = self.heap, self.version
        while not self.complete and self.stopped_by is None:
            while heap and heap[0][2] != version[heap[0][1]]:
                heapq.heappop(heap)
            if not heap:
                self._end_instant()
                self.complete, self.ended_by = True, "quiescence"
                break
            when, e, _ = heapq.heappop(heap)
            dirty = {self.group_of[e]}
            if when > self.now:
                self._end_instant()
                # Tokens still held somewhere age: those groups' states change.
                dirty.update(g for g, t in enumerate(self.inflight) if t > self.now)
                self.now = when
            self._fire(e)
            self.firings += 1
            self._record(dirty)
            if self.firings % _POLL == 0:
                self._poll()

    def _poll(self) -> None:
        if self.stopped_by is None and not self.complete:
            if self.stop is not None and self.stop():
                self.stopped_by = "interrupted"
            elif self.deadline is not None and time.perf_counter() > self.deadline:
                self.stopped_by = "time"
        if self.progress is not None:
            self.progress(len(self.whole), self.firings, time.perf_counter() - self.start)

    def result(self, name: str, unit: str) -> TimedExploration:
        for g, group in enumerate(self.groups):
            if self.current[g] >= 0:
                group.states = len(self.seen[g])
                if self.dead[g]:  # a budget ended the search: what is stuck so far
                    self._report_stuck(g)
        if self.complete:
            for t in self.tasks.values():
                t.decided = t.decided or self.groups[t.group].stalled_at is None
        return TimedExploration(name=name, unit=unit, states=len(self.whole),
                                firings=self.firings, complete=self.complete,
                                ended_by=self.ended_by, stopped_by=self.stopped_by,
                                time_reached=Fraction(self.now, self.scale),
                                groups=self.groups, tasks=self.tasks,
                                max_states=self.max_states,
                                seconds=time.perf_counter() - self.start)


def _transient(daters: list[list[int]], before: list[int], c0: int, span: int) -> tuple[int, int]:
    """Smallest ``(K, c)`` with ``x(k+c) = x(k) + c·span/c0`` for all events and ``k >= K``.

    ``daters[i]`` holds the scaled firing times of event i up to the second
    occurrence of the repeated state; ``before[i]`` its firings up to the
    first, after which the run repeats every ``c0`` firings and ``span`` time.

    >>> _transient([[0, 5, 7, 9, 11]], [3], 2, 4)  # x = 0, 5, 7, 9, 11, 13...: from k=2, c=1
    (2, 1)
    """
    def at(x: list[int], k: int) -> int:  # x(k), 1-based, continued by the proven cycle
        return x[k - 1] if k <= len(x) else x[k - 1 - c0] + span

    def holds(x: list[int], k: int, c: int) -> bool:
        return at(x, k + c) * c0 == at(x, k) * c0 + span * c

    cyc = next(c for c in range(1, c0 + 1) if c0 % c == 0 and all(
        holds(x, k, c) for x, n in zip(daters, before) for k in range(n + 1, n + c0 + 1)))
    first = 1
    for x, n in zip(daters, before):
        k = n
        while k >= 1 and holds(x, k, cyc):
            k -= 1
        first = max(first, k + 1)
    return first, cyc
