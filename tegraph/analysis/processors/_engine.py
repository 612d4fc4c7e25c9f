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
its most urgent pending job.
"""

from __future__ import annotations

import heapq
from collections import deque
from dataclasses import dataclass, field

__all__ = ["PartData", "PartResult", "simulate_part"]

_KEEP = 8
"""Snapshots kept per key: a bounded place counted above its cap can still
repeat with an earlier one than the latest of its key."""


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


@dataclass
class Snapshot:
    """The counters at a compared instant t (before anything happens at t)."""

    time: int
    counts: tuple[int, ...]
    fired: tuple[int, ...]
    finished: tuple[int, ...]
    pending: tuple[int, ...]
    """Remaining work of each task's job, -1 without one."""


class _Part:
    """The state of one part under simulation (rules in the module docstring)."""

    def __init__(self, d: PartData) -> None:
        self.d = d
        n = d.n_events
        self.inputs: list[list[int]] = [[] for _ in range(n)]
        self.outputs: list[list[int]] = [[] for _ in range(n)]
        self.job_out: list[list[int]] = [[] for _ in d.duration]
        for p, (s, t) in enumerate(zip(d.p_src, d.p_dst)):
            self.inputs[t].append(p)
            if d.p_job[p]:
                self.job_out[d.compute_task[s]].append(p)
            else:
                self.outputs[s].append(p)
        self.queues = [deque([a] * m) for a, m in zip(d.p_init, d.p_tokens)]
        self.tight = [-1] * len(d.p_src)
        self.future: list[tuple[int, int]] = [(a, t) for a, t, m in zip(
            d.p_init, d.p_dst, d.p_tokens) if m and a > 0]
        heapq.heapify(self.future)
        self.fired = [0] * n
        self.finished = [0] * len(d.duration)
        self.remaining = [-1] * len(d.duration)
        self.heaps: list[list[tuple[int, int, int, int]]] = [[] for _ in range(d.n_processors)]
        self.result = PartResult(jobs=[[] for _ in d.duration])
        self.ticked: list[int] = []
        self.segment: list[list[int] | None] = [None] * d.n_processors
        self.count = 0
        self.started = False

    # ------------------------------------------------------------ an instant
    def instant(self, now: int, ending: list[int], budget: int) -> None:
        work = [] if self.started else list(range(self.d.n_events))
        self.started = True
        for task in ending:
            self._end_job(task, now, work)
        while self.future and self.future[0][0] <= now:
            work.append(heapq.heappop(self.future)[1])
        while work and self.count <= budget:
            e = work.pop()
            while self._enabled(e, now) and self.count <= budget:
                self._fire(e, now, work)
        self._check_ticks(now)

    def _enabled(self, e: int, now: int) -> bool:
        for p in self.inputs[e]:
            q = self.queues[p]
            if not q or q[0] > now:
                return False
        return True

    def _fire(self, e: int, now: int, work: list[int]) -> None:
        d = self.d
        self.count += 1
        self.fired[e] += 1
        for p in self.inputs[e]:
            if self.queues[p].popleft() == now:
                self.tight[p] = now
        task = d.compute_task[e]
        if task >= 0:
            self.result.jobs[task].append([now, None])
            if d.duration[task] == 0:
                self._end_job(task, now, work)
            else:
                self.remaining[task] = d.duration[task]
                heapq.heappush(self.heaps[d.processor[task]],
                               (-d.priority[task], now, d.file_index[task], task))
        for p in self.outputs[e]:
            at = now + d.p_hold[p]
            self.queues[p].append(at)
            if at == now:
                work.append(d.p_dst[p])
            else:
                heapq.heappush(self.future, (at, d.p_dst[p]))
        if e in d.watched:
            self.ticked.append(e)

    def _end_job(self, task: int, now: int, work: list[int]) -> None:
        self.remaining[task] = -1
        self.finished[task] += 1
        self.result.jobs[task][-1][1] = now
        for p in self.job_out[task]:
            self.queues[p].append(now)
            work.append(self.d.p_dst[p])

    def ends(self, task: int) -> int:
        last = self.d.end_event[task]
        return self.finished[task] if last is None else self.fired[last]

    def _check_ticks(self, now: int) -> None:
        # After the whole instant: an activation ending at the tick is in time (§4).
        for e in self.ticked:
            k = self.fired[e]
            for task in self.d.watched[e]:
                slack = self.ends(task) - (k - 1)
                self.result.tick_log.setdefault(task, []).append((now, k, slack))
                if slack < 0 and task not in self.result.overrun_at:
                    self.result.overrun_at[task] = k
        self.ticked = []

    # ------------------------------------------------------------ processors
    def advance(self, now: int) -> tuple[int | None, list[int]]:
        """Run each processor's most urgent job up to the next instant; return it and the ends."""
        nxt = self.future[0][0] if self.future else None
        for heap in self.heaps:
            if heap:
                at = now + self.remaining[heap[0][3]]
                nxt = at if nxt is None or at < nxt else nxt
        if nxt is None:
            return None, []
        ending = []
        for proc, heap in enumerate(self.heaps):
            if not heap:
                continue
            task = heap[0][3]
            self._record(proc, task, now, nxt)
            self.remaining[task] -= nxt - now
            if self.remaining[task] == 0:
                heapq.heappop(heap)
                ending.append(task)
        return nxt, ending

    def _record(self, proc: int, task: int, start: int, end: int) -> None:
        k = len(self.result.jobs[task])
        seg = self.segment[proc]
        if seg is not None and seg[3] == task and seg[4] == k and seg[2] == start:
            seg[2] = end
            return
        self.flush(proc)
        self.segment[proc] = [proc, start, end, task, k]

    def flush(self, proc: int) -> None:
        seg = self.segment[proc]
        if seg is not None:
            self.result.intervals.append(tuple(seg))  # type: ignore[arg-type]
            self.segment[proc] = None

    # ------------------------------------------------------------ snapshots
    def key(self, now: int) -> tuple:
        d = self.d
        counts = tuple(len(q) if cap is None or len(q) < cap else cap
                       for q, cap in zip(self.queues, d.p_cap))
        # Tokens not yet available (clock self-loops), relative to now.
        ahead = tuple(tuple(max(a - now, 0) for a in q) for q, h, job in zip(
            self.queues, d.p_hold, d.p_job) if h and not job)
        # Only the order of the pending jobs matters, not their release times:
        # a job released later comes after every pending one of its priority.
        order = tuple(tuple(x[3] for x in sorted(heap)) for heap in self.heaps)
        return counts, ahead, tuple(self.remaining), order

    def snapshot(self, now: int) -> Snapshot:
        return Snapshot(now, tuple(len(q) for q in self.queues), tuple(self.fired),
                        tuple(self.finished), tuple(self.remaining))

    def repeats(self, old: Snapshot, new: Snapshot) -> dict[int, int] | None:
        """The growing places when ``new`` repeats ``old`` up to them (proof in docs), else None."""
        d = self.d
        growing = {}
        for p, (a, b) in enumerate(zip(old.counts, new.counts)):
            if a == b:
                continue
            # A place may differ only by gaining tokens, taken without ever being
            # the latest input of its output event, and available once put.
            if b < a or self.tight[p] >= old.time or (d.p_hold[p] and not d.p_job[p]):
                return None
            growing[p] = b - a
        return growing


def simulate_part(d: PartData, budget: int) -> PartResult:
    """Simulate one part until its state repeats, nothing more happens, or ``budget`` firings."""
    part = _Part(d)
    seen: dict[tuple, list[Snapshot]] = {}
    now, ending = 0, []
    while True:
        if d.snapshot_place is None or part.queues[d.snapshot_place][0] == now:
            if _compare(part, seen, now):
                break
        part.instant(now, ending, budget)
        if part.count > budget:
            part.result.budget_spent = True
            break
        nxt, ending = part.advance(now)
        if nxt is None:
            part.result.regime = ("stop", now)
            break
        now = nxt
    for proc in range(d.n_processors):
        part.flush(proc)
    part.result.fired = part.count
    part.result.intervals.sort(key=lambda s: (s[0], s[1]))
    return part.result


def _compare(part: _Part, seen: dict[tuple, list[Snapshot]], now: int) -> bool:
    key = part.key(now)
    snap = part.snapshot(now)
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
