"""The event-driven §4b simulation of one interacting part of a skeleton.

A *part* is a set of tasks closed under "same group" and "same processor":
nothing outside it can change what happens inside, so each part reaches its
own periodic regime (a whole skeleton of independent parts would otherwise
need the least common multiple of their periods). The state of a part, and
the proof that it repeats, are described in ``docs/analysis.md``
(*The schedule on processors*); this module implements them on scaled
integers (every time multiplied by the graph's common denominator).

Time advances from instant to instant: the next instant is the earliest of a
token becoming available (a clock tick) and a running job ending. At an
instant: the jobs that end deliver their tokens, then every event whose input
places all hold an available token fires (as often as it can), compute events
release jobs (a job of duration 0 ends at once), then each processor takes
its most urgent pending job: a preemptive one at once, a non-preemptive one
(§4d) only when it runs none, so that a job released at the instant the
processor becomes free takes part in the choice. A non-preemptive processor's
running job leaves its heap when it starts (a more urgent job may come above
it while it runs); a preemptive one's stays at the top until it ends.

:meth:`_Part.run` is the loop written in Python, on any numbers the rules can
add and compare. Where setup.py built them, :func:`simulate_part` runs the same
loop compiled (``_engine_loop.pxi``): on int64 times (``_engine_kernel``), else
on 192-bit ones (``_engine_kernel_wide``), with the same order of firings and
the same result, six to nine times faster; the Python loop serves the rest (the
affine times of the sensitivity analysis, Fractions, times past 2**189).
"""

from __future__ import annotations

import heapq
from abc import ABC, abstractmethod
from collections import deque
from collections.abc import MutableSequence, Sequence
from dataclasses import dataclass, field
from operator import itemgetter
from typing import Any

from . import _loops

__all__ = ["AFTER_OVERRUN", "PartData", "PartResult", "simulate_part"]

_KEEP = 8
"""Snapshots kept per key: a bounded place counted above its cap can still
repeat with an earlier one than the latest of its key."""

AFTER_OVERRUN = 10
"""Once an overrun is exhibited (the verdict, proven), the search for a regime
(the other figures) goes on for as many firings again as the overrun took, and
at least a tenth (``1 / AFTER_OVERRUN``) of the budget. The figures that need
the regime then stay null, as when the budget is spent: on drifting,
overrunning groups no regime comes, and its search alone would spend the whole
budget after the verdict is known."""


@dataclass
class PartData:
    """One part, re-indexed locally (events, places, tasks 0..n-1), scaled integers."""

    n_events: int
    p_src: list[int]
    p_dst: list[int]
    p_tokens: list[int]
    p_hold: list[int]
    p_init: list[int]
    p_job: list[bool]
    """The place leaves a compute event: its token comes when the job ends."""
    p_cap: list[int | None]
    """Counts above the cap are one key (None: exact, the place is on a circuit)."""
    compute_task: list[int]
    """Event -> local task whose compute it is, or -1."""
    duration: list[int]
    priority: list[int]
    file_index: list[int]
    processor: list[int]
    n_processors: int
    end_event: list[int | None]
    """Last event of the task's chain when it has outputs; None: its end is the job's end."""
    watched: dict[int, list[int]]
    """Tick event -> clocked tasks it activates (their overruns are watched)."""
    snapshot_place: int | None
    """The self-loop place of the slowest clock: states are compared at its ticks
    (every instant when the part has no clock)."""
    logged: list[int] = field(default_factory=list)
    """Events whose firing instants are recorded (``PartResult.firings``): the reads,
    writes, sensors and outputs of the chains asked for (spec §4c)."""
    started: list[int] = field(default_factory=list)
    """Tasks whose jobs' starts are recorded (``PartResult.starts``)."""
    preemptive: list[bool] = field(default_factory=list)
    """Per processor (§4d): False where a running job is never interrupted (empty: every
    processor preemptive)."""


@dataclass
class PartResult:
    """What one simulation found (scaled integer times)."""

    fired: int = 0
    intervals: list[tuple[int, int, int, int, int]] = field(default_factory=list)
    """(processor, start, end, task, k), in time order per processor."""
    jobs: list[list[list]] = field(default_factory=list)
    """Per task: [release, finish or None] of each job, in order."""
    overrun_at: dict[int, int] = field(default_factory=dict)
    regime: tuple | None = None
    """(t1, t2, snapshot at t1, snapshot at t2, growing places {place: tokens per regime}),
    or ("stop", t) when nothing ever happens again after t."""
    tick_log: dict[int, list[tuple[int, int, int]]] = field(default_factory=dict)
    """Clocked task -> (time, k, ends - (k - 1)) at each tick of its clock."""
    budget_spent: bool = False
    after_overrun: int | None = None
    """Firings at the first overrun, when the search for a regime stopped
    :data:`AFTER_OVERRUN` rules past it (before the budget); else None."""
    firings: dict[int, list[int]] = field(default_factory=dict)
    """Each event of ``PartData.logged``: the instant of each of its firings, in order."""
    starts: dict[int, list[int]] = field(default_factory=dict)
    """Each task of ``PartData.started``: the start of each of its jobs, in order (the
    first instant the job holds its processor; its release for a job of duration 0)."""


@dataclass
class Snapshot:
    """The counters at a compared instant t (before anything happens at t)."""

    time: int
    counts: tuple[int, ...]
    fired: tuple[int, ...]
    finished: tuple[int, ...]
    pending: tuple[int, ...]
    """Remaining work of each task's job, -1 without one."""


class _States(ABC):
    """The state of a part as :func:`_compare` reads it at an instant, on either loop.

    A loop provides ``d``, ``result`` and the readings :meth:`pending`,
    :meth:`lengths`, :meth:`tokens`, :meth:`ready_jobs`, :meth:`fired_counts`,
    :meth:`finished_counts` and :meth:`tight_times` (and :meth:`ahead`, made from
    :meth:`tokens` unless the loop writes it out); the key, the snapshot and the
    proof of a repeat are made from them here, once for both. The readings are
    abstract: a loop that lacks one cannot be made.
    """

    d: PartData
    result: PartResult

    @abstractmethod
    def pending(self, now: int) -> list[int]:
        """Remaining work of each task's job at ``now``, -1 without one."""

    @abstractmethod
    def lengths(self) -> list[int]:
        """The token count of every place."""

    @abstractmethod
    def tokens(self, p: int) -> Sequence[int]:
        """The tokens of place ``p`` (the times they are available), oldest first."""

    @abstractmethod
    def ready_jobs(self) -> Sequence[Sequence[tuple[int, int, int, int]]]:
        """Per processor, its pending jobs (-priority, release, file index, task), any order."""

    @abstractmethod
    def fired_counts(self) -> Sequence[int]:
        """How many times each event has fired."""

    @abstractmethod
    def finished_counts(self) -> Sequence[int]:
        """How many jobs of each task have ended."""

    @abstractmethod
    def tight_times(self) -> Sequence[int]:
        """Per place, the last instant a token was taken there the instant it came (or -1)."""

    @abstractmethod
    def running_jobs(self) -> Sequence[int]:
        """Per processor, the task whose job it runs (-1: none)."""

    def key(self, now: int, pending: list[int], lengths: list[int]) -> tuple:
        """The state compared at ``now``, ``lengths`` the token count of each place."""
        counts = list(lengths)
        for p, cap in self.capped:  # counts above the cap are one key
            if counts[p] > cap:
                counts[p] = cap
        ahead = self.ahead(now)
        # Only the order of the pending jobs matters, not their release times:
        # a job released later comes after every pending one of its priority.
        order = tuple(tuple(x[3] for x in sorted(heap)) for heap in self.ready_jobs()
                      if len(heap) > 1)
        # A non-preemptive processor's running job is out of its heap: which one runs
        # is part of the state (on a preemptive one it is the top of the heap).
        lazy = self.lazy
        if lazy:
            held = self.running_jobs()
            return tuple(counts), ahead, tuple(pending), order, tuple(held[p] for p in lazy)
        return tuple(counts), ahead, tuple(pending), order

    @property
    def lazy(self) -> list[int]:
        """The non-preemptive processors (``PartData.preemptive``)."""
        if not hasattr(self, "_lazy"):
            self._lazy = [p for p, pre in enumerate(self.d.preemptive) if not pre]
        return self._lazy

    def ahead(self, now: int) -> tuple[tuple[int, ...], ...]:
        """The tokens of each timed place (a clock's self-loop, a link's delay) not
        available before now, relative to now; those available earlier are in the
        counts only (a place where messages pile up behind a delay keeps a key of
        bounded size). A token available at now is held here: the state is compared
        before the instant's arrivals wake their events, so it is not yet one that
        waited."""
        return tuple(tuple(a - now for a in self.tokens(p) if a >= now) for p in self.timed)

    @property
    def capped(self) -> list[tuple[int, int]]:
        """(place, cap) of the places whose count has a cap (``PartData.p_cap``)."""
        if not hasattr(self, "_capped"):
            self._capped = [(p, cap) for p, cap in enumerate(self.d.p_cap) if cap is not None]
        return self._capped

    @property
    def timed(self) -> list[int]:
        if not hasattr(self, "_timed"):
            d = self.d
            self._timed = [p for p, (h, job) in enumerate(zip(d.p_hold, d.p_job)) if h and not job]
        return self._timed

    def snapshot(self, now: int, pending: list[int], lengths: list[int]) -> Snapshot:
        return Snapshot(now, tuple(lengths), tuple(self.fired_counts()),
                        tuple(self.finished_counts()), tuple(pending))

    def repeats(self, old: Snapshot, new: Snapshot) -> dict[int, int] | None:
        """The growing places when ``new`` repeats ``old`` up to them (proof in docs), else None."""
        tight = None  # read once, when a place differs
        growing = {}
        for p, (a, b) in enumerate(zip(old.counts, new.counts)):
            if a == b:
                continue
            if tight is None:
                tight = self.tight_times()
            # A place may differ only by gaining tokens, taken without ever being the
            # latest input of its output event; the key holds its tokens not yet
            # available (``ahead``), so those it gained are available ones.
            if b < a or tight[p] >= old.time:
                return None
            growing[p] = b - a
        return growing


class _Part(_States):
    """The state of one part under simulation (rules in the module docstring).

    A running job's remaining work is kept implicitly: it ends at ``done_at``
    of its processor unless preempted, so an instant costs only the
    processors it touches.
    """

    def __init__(self, d: PartData) -> None:
        self.d = d
        self.keep_intervals = True
        n = d.n_events
        # The tokens of each place, oldest first: the times they are (or become)
        # available. A list where the place lies on a circuit, whose tokens bound
        # its count (taking the oldest moves the few others); a deque elsewhere,
        # where tokens may pile up without bound. A deque costs 760 bytes even
        # empty, a list of a token 96: some 300 MB against 40 at 100,000 tasks.
        self.queues: list[MutableSequence[int]] = [
            [a] * m if cap is None else deque((a,) * m)
            for a, m, cap in zip(d.p_init, d.p_tokens, d.p_cap)]
        # The hot loop reads each event's places through their queues, bound once
        # (a firing then costs no index look-ups): (place, queue) into each event,
        # the place for the tight marks; out of each event, the places it fills at
        # once, (queue, event), and those whose token comes later, (queue, hold,
        # event), in two lists (a firing tests no hold per place); (queue, event) for
        # the places the end of each task's job fills.
        in_pairs: list[list[tuple[int, MutableSequence[int]]]] = [[] for _ in range(n)]
        out_now: list[list[tuple[MutableSequence[int], int]]] = [[] for _ in range(n)]
        out_later: list[list[tuple[MutableSequence[int], int, int]]] = [[] for _ in range(n)]
        self.job_arcs: list[list[tuple[MutableSequence[int], int]]] = [[] for _ in d.duration]
        for p, (s, t, queue, job, hold) in enumerate(zip(d.p_src, d.p_dst, self.queues,
                                                         d.p_job, d.p_hold)):
            in_pairs[t].append((p, queue))
            if job:
                self.job_arcs[d.compute_task[s]].append((queue, t))
            elif hold:
                out_later[s].append((queue, hold, t))
            else:
                out_now[s].append((queue, t))
        # After a firing, an event is tried again at once only while every input place
        # still holds a token, or when it has a self-loop (its firing refills it: tried
        # at once, the order of the firings stays that of trying every event again).
        # A place emptied by the firing can only be refilled by another event's firing,
        # which puts this event back on the list of events to try.
        loops = {s for s, t in zip(d.p_src, d.p_dst) if s == t}
        self.result = PartResult(jobs=[[] for _ in d.duration])
        # The lists the firings of the logged events go to, and the starts of the
        # started tasks (None elsewhere: nothing is recorded without a chain).
        logs: list[list[int] | None] = [None] * n
        for e in d.logged:
            logs[e] = self.result.firings[e] = []
        self.starts: list[list[int] | None] = [None] * len(d.duration)
        for task in d.started:
            self.starts[task] = self.result.starts[task] = []
        # Everything a firing of each event reads, in one tuple: (inputs, places filled
        # at once, places filled later, its task or -1, whether it is a watched tick,
        # whether it has a self-loop, the list its firings are logged to or None).
        # Tuples, not the lists they were built in: no room kept to grow (some 8 MB
        # at 10,000 tasks, most of them empty ``()``, one object for all).
        self.events = [(tuple(ins), tuple(now_), tuple(later), task, e in d.watched,
                        e in loops, log) for e, (ins, now_, later, task, log)
                       in enumerate(zip(in_pairs, out_now, out_later, d.compute_task, logs))]
        self.tight = [-1] * len(d.p_src)
        self.future: list[tuple[int, int]] = [(a, t) for a, t, m in zip(
            d.p_init, d.p_dst, d.p_tokens) if m and a > 0]
        heapq.heapify(self.future)
        self.fired = [0] * n
        self.finished = [0] * len(d.duration)
        self.remaining = [-1] * len(d.duration)
        """Work left to a pending job that is not running (-1: no job)."""
        procs = d.n_processors
        self.heaps: list[list[tuple[int, int, int, int]]] = [[] for _ in range(procs)]
        self.running = [-1] * procs
        self.run_start = [0] * procs
        self.done_at = [0] * procs
        self.stamp = [0] * procs
        self.completions: list[tuple[int, int, int]] = []
        """(time, processor, stamp): the running job's end, valid while the stamp is."""
        self.touched: set[int] = set()
        self.ticked: list[int] = []
        self.count = 0
        """Firings so far (kept by :meth:`run` when it stops or compares a state)."""

    # ------------------------------------------------------------ the run
    def run(self, budget: int) -> int:
        """Simulate from time 0 until a proof or the budget (rules of :func:`simulate_part`);
        return the last instant.

        The loop over instants, and the firings of each instant, are written out here
        in one function, on locals: some 40,000 instants and 220,000 firings on a
        part of 10,000 tasks on one processor, where a call or an attribute look-up
        per instant or per firing costs as much as its work. Only the comparisons
        of the rules are made on times, in their order (the sensitivity analysis
        runs this engine on affine times and records each comparison).
        """
        d, result = self.d, self.result
        seen: dict[tuple, list[Snapshot]] = {}
        snap_queue = None if d.snapshot_place is None else self.queues[d.snapshot_place]
        comp, stamps, future, touched = self.completions, self.stamp, self.future, self.touched
        heappop, heappush = heapq.heappop, heapq.heappush
        heaps, running, keep_intervals = self.heaps, self.running, self.keep_intervals
        remaining, done_at, run_start = self.remaining, self.done_at, self.run_start
        events, fired, tight, jobs = self.events, self.fired, self.tight, result.jobs
        finished, job_arcs, ticked = self.finished, self.job_arcs, self.ticked
        starts = self.starts
        lazy = [not pre for pre in d.preemptive] or [False] * d.n_processors
        tracing = bool(d.started)  # job starts are recorded for a chain (spec §4c)
        duration, processor, priority, file_index = (d.duration, d.processor, d.priority,
                                                     d.file_index)
        overrun_at = result.overrun_at
        limit = budget
        overrun: int | None = None
        count = 0
        cut = False
        """An event was enabled when ``count`` had reached the limit (none fired past it)."""
        work = list(range(d.n_events))  # at time 0 every event is tried
        push, pop = work.append, work.pop
        now = 0
        while True:
            if snap_queue is None or snap_queue[0] == now:
                self.count = count
                if _compare(self, seen, now):
                    return now
            # The instant: jobs that end deliver their tokens, tokens that become
            # available wake their events, every enabled event fires, then each
            # processor touched takes its most urgent job.
            while comp and comp[0][0] <= now:
                _, proc, stamp = heappop(comp)
                if stamp == stamps[proc]:  # the running job of proc is done
                    # A non-preemptive processor's job left its heap when it started.
                    task = running[proc] if lazy[proc] else heappop(heaps[proc])[3]
                    if keep_intervals:
                        self._record(proc, task, now)
                    running[proc] = -1
                    stamps[proc] += 1
                    touched.add(proc)
                    # Its job ends: the places leaving its compute receive their token.
                    remaining[task] = -1
                    finished[task] += 1
                    jobs[task][-1][1] = now
                    for q, dst in job_arcs[task]:
                        q.append(now)
                        push(dst)
            while future and future[0][0] <= now:
                push(heappop(future)[1])
            # Fire every event of ``work`` (and those it enables) as long as its input
            # places all hold an available token, until the limit of firings.
            while work:
                e = pop()
                inputs, out_now, out_later, task, watched, loop, log = events[e]
                while True:  # fire e as long as every input place has an available token
                    for _, q in inputs:
                        if not q or q[0] > now:
                            break
                    else:
                        if count >= limit:  # an event still to fire: the budget is spent
                            cut = True
                            work.clear()
                            break
                        count += 1
                        fired[e] += 1
                        again = True
                        for p, q in inputs:
                            if q[0] == now:  # the token taken came at this instant
                                tight[p] = now
                            del q[0]
                            if not q:
                                again = loop
                        if log is not None:
                            log.append(now)
                        if task >= 0:  # its job is released
                            jobs[task].append([now, None])
                            if duration[task] == 0:  # and ends at once
                                if tracing:
                                    mine = starts[task]
                                    if mine is not None:
                                        mine.append(now)
                                remaining[task] = -1
                                finished[task] += 1
                                jobs[task][-1][1] = now
                                for q, dst in job_arcs[task]:
                                    q.append(now)
                                    push(dst)
                            else:
                                remaining[task] = duration[task]
                                proc = processor[task]
                                heappush(heaps[proc],
                                         (-priority[task], now, file_index[task], task))
                                touched.add(proc)
                        for q, dst in out_now:
                            q.append(now)
                            push(dst)
                        for q, hold, dst in out_later:
                            q.append(now + hold)
                            heappush(future, (now + hold, dst))
                        if watched:
                            ticked.append(e)
                        if again:
                            continue  # try it again
                    break
            if ticked:
                self._check_ticks(now)
            if touched:
                # Each processor touched goes to its most urgent pending job, preempting
                # the running one (whose remaining work is then kept) where it may.
                for proc in touched:
                    heap = heaps[proc]
                    old = running[proc]
                    if lazy[proc]:  # it takes a job only when it runs none (§4d)
                        if old >= 0 or not heap:
                            continue
                        top = heappop(heap)[3]
                    else:
                        top = heap[0][3] if heap else -1
                        if top == old:
                            continue
                    if old >= 0:
                        remaining[old] = done_at[proc] - now
                        if keep_intervals:
                            self._record(proc, old, now)
                    running[proc] = top
                    stamps[proc] += 1
                    if top >= 0:
                        run_start[proc] = now
                        done_at[proc] = now + remaining[top]
                        heappush(comp, (done_at[proc], proc, stamps[proc]))
                        if tracing:  # the job's start: the first time it holds proc
                            mine = starts[top]
                            if mine is not None and len(mine) < len(jobs[top]):
                                mine.append(now)
                touched.clear()
            if cut:
                self.count = count
                result.budget_spent = True
                if limit < budget:
                    result.after_overrun = overrun
                return now
            if overrun is None and overrun_at:
                overrun = count
                limit = min(budget, overrun + max(overrun, budget // AFTER_OVERRUN))
            # The next instant: the earliest of a token becoming available and a
            # running job's end (completions of preempted jobs are stale).
            while comp and comp[0][2] != stamps[comp[0][1]]:
                heappop(comp)
            nxt = future[0][0] if future else None
            if comp and (nxt is None or comp[0][0] < nxt):
                nxt = comp[0][0]
            if nxt is None:
                self.count = count
                result.regime = ("stop", now)
                return now
            now = nxt

    def _check_ticks(self, now: int) -> None:
        """The slack of each clocked task at its clock's ticks of this instant.

        After the whole instant: an activation ending at the tick is in time (§4).
        On locals: at 10,000 tasks on their own clocks, 10,000 tasks per instant.
        """
        fired, finished, end_event = self.fired, self.finished, self.d.end_event
        watched, log, overrun_at = self.d.watched, self.result.tick_log, self.result.overrun_at
        for e in self.ticked:
            k = fired[e]
            for task in watched[e]:
                last = end_event[task]  # None: its activation ends with its job
                slack = (finished[task] if last is None else fired[last]) - (k - 1)
                log.setdefault(task, []).append((now, k, slack))
                if slack < 0 and task not in overrun_at:
                    overrun_at[task] = k
        self.ticked.clear()

    # ------------------------------------------------------------ processors
    def _record(self, proc: int, task: int, end: int) -> None:
        start = self.run_start[proc]
        if end > start and self.keep_intervals:
            self.result.intervals.append((proc, start, end, task, len(self.result.jobs[task])))

    def flush(self, now: int) -> None:
        for proc, task in enumerate(self.running):
            if task >= 0:
                self._record(proc, task, now)

    # ------------------------------------------------------------ snapshots
    def pending(self, now: int) -> list[int]:
        rem = list(self.remaining)
        for proc, task in enumerate(self.running):
            if task >= 0:
                rem[task] = self.done_at[proc] - now
        return rem

    def lengths(self) -> list[int]:
        return list(map(len, self.queues))

    def tokens(self, p: int) -> Sequence[int]:
        return self.queues[p]

    def ready_jobs(self) -> Sequence[Sequence[tuple[int, int, int, int]]]:
        return self.heaps

    def fired_counts(self) -> Sequence[int]:
        return self.fired

    def finished_counts(self) -> Sequence[int]:
        return self.finished

    def tight_times(self) -> Sequence[int]:
        return self.tight

    def running_jobs(self) -> Sequence[int]:
        return self.running


class _CompiledPart(_States):
    """A part under a compiled loop (the ``Kernel`` of ``module``, one of
    ``_engine_kernel`` and ``_engine_kernel_wide``): the same rules and figures as
    :class:`_Part`, on int64 or 192-bit times; the states are compared here, in Python."""

    def __init__(self, module: Any, d: PartData, keep_intervals: bool) -> None:
        self.d = d
        self.result = PartResult(jobs=[[] for _ in d.duration])
        self.kernel = module.Kernel(d, self.result, keep_intervals)

    def run(self, budget: int) -> int | None:
        """:meth:`_Part.run`; None when a time would pass the loop's bound (start again
        with more room)."""
        seen: dict[tuple, list[Snapshot]] = {}
        return self.kernel.run(budget, AFTER_OVERRUN, lambda now: _compare(self, seen, now))

    @property
    def count(self) -> int:
        return self.kernel.count

    def flush(self, now: int) -> None:
        self.kernel.flush(now)

    def pending(self, now: int) -> list[int]:
        return self.kernel.pending(now)

    def lengths(self) -> list[int]:
        return self.kernel.lengths()

    def tokens(self, p: int) -> Sequence[int]:
        return self.kernel.tokens(p)

    def ahead(self, now: int) -> tuple[tuple[int, ...], ...]:
        # Written out in the kernel: at 10,000 clocks, 10,000 places at each comparison.
        return self.kernel.ahead(self.timed, now)

    def ready_jobs(self) -> Sequence[Sequence[tuple[int, int, int, int]]]:
        return self.kernel.ready_jobs()

    def fired_counts(self) -> Sequence[int]:
        return self.kernel.fired_counts()

    def finished_counts(self) -> Sequence[int]:
        return self.kernel.finished_counts()

    def tight_times(self) -> Sequence[int]:
        return self.kernel.tight_times()

    def running_jobs(self) -> Sequence[int]:
        return self.kernel.running_jobs()


def simulate_part(d: PartData, budget: int, keep_intervals: bool = True) -> PartResult:
    """Simulate one part until its state repeats, nothing more happens, or ``budget`` firings
    (fewer once an overrun is exhibited: :data:`AFTER_OVERRUN`).

    ``keep_intervals``: record the processor time of each job (for drawing); an
    analysis that only reads the figures leaves them out (a tuple per preemption).
    """
    part: _Part | _CompiledPart | None = None
    now = None
    for module in _loops.compiled_loops(d):  # the loop is chosen there (_loops.use)
        part = _CompiledPart(module, d, keep_intervals)
        now = part.run(budget)
        if now is not None:
            break
    if now is None:  # times no compiled loop covers, or one passed its bound: Python ints
        _loops.python_loop()
        part = _Part(d)
        part.keep_intervals = keep_intervals
        now = part.run(budget)
    assert part is not None
    part.flush(now)
    part.result.fired = part.count
    part.result.intervals.sort(key=itemgetter(0, 1))
    return part.result


def _compare(part: _States, seen: dict[tuple, list[Snapshot]], now: int) -> bool:
    pending = part.pending(now)
    lengths = part.lengths()  # the count of every place, once for both
    key = part.key(now, pending, lengths)
    snap = part.snapshot(now, pending, lengths)
    earlier = seen.setdefault(key, [])
    for old in reversed(earlier):
        growing = part.repeats(old, snap)
        if growing is not None:
            part.result.regime = (old.time, now, old, snap, growing)
            return True
    earlier.append(snap)
    if len(earlier) > _KEEP:
        earlier.pop(0)
    return False
