"""Independent periodic tasks released together on one processor, decided without simulating.

A part of the schedule (``schedule.py``) whose tasks share no synchronizing link
(ASYN/ASYN ones add no place), no thread and no clock, each paced by a clock of
its own with phase 0, all on one *preemptive* processor with distinct priorities, is the
classical task set of Liu and Layland [1]_: synchronous periodic tasks, deadline =
period (§4b's overrun: job k-1 still running at tick k). Its clocks' hyperperiod
may be astronomically long (drifting clocks: 0.997, 1.009, 1.013 ms), which a
simulation cannot cross; a theorem does:

- **Critical instant** [1]_: a task's longest response under preemptive fixed
  priorities is that of a job released together with every more urgent task, as
  job 1 is here. Its response is the least fixed point of Joseph and Pandya's
  recurrence [2]_ ``R = C_i + sum_{j more urgent} ceil(R / T_j) C_j``, reached by
  iterating from a proven lower bound of it (``_lower_bound``; each step is one too).
- If every task has ``R_i <= T_i`` (Lehoczky, Sha and Ding's exact test [3]_), every
  job ends by the next tick: each release is its tick, the schedule repeats
  every hyperperiod from 0 (nothing is pending at a common release), the
  periodic regime starts at 0 and contains job 1, so ``response = R_i`` and
  ``period = T_i``, exactly; no place grows, no task overruns.
- Otherwise, take the most urgent task i with ``R_i > T_i``: every more urgent
  task meets its period, so the interference job 1 of i suffers is exactly the
  recurrence's, job 1 ends at ``R_i > T_i`` = tick 2: **overrun at activation 2**,
  proven; the figures of the less urgent tasks are left undecided (not needed:
  the skeleton is not schedulable).

The proof in full is in ``docs/analysis.md`` (*Independent tasks on one processor*).

References
----------
.. [1] C. L. Liu, J. W. Layland, "Scheduling algorithms for multiprogramming in
   a hard-real-time environment", Journal of the ACM 20(1), 46–61, 1973.
.. [2] M. Joseph, P. Pandya, "Finding response times in a real-time system",
   The Computer Journal 29(5), 390–395, 1986.
.. [3] J. Lehoczky, L. Sha, Y. Ding, "The rate monotonic scheduling algorithm:
   exact characterization and average case behavior", IEEE Real-Time Systems
   Symposium, 166–171, 1989.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from ...model.platform import Platform
from ...model.skeleton import Protocol, Skeleton

__all__ = ["MAX_TERMS", "IndependentVerdict", "independent_tasks"]

MAX_TERMS = 100_000
"""Steps of the recurrence, over all tasks of a part, before the theorem gives up
(the part is then simulated as any other)."""


@dataclass(frozen=True)
class IndependentVerdict:
    """What the critical instant decides for one part.

    ``response`` holds every task up to and including ``late`` (the first task, most
    urgent first, that misses its period; None when none does).
    """

    response: dict[str, Fraction]
    period: dict[str, Fraction]
    late: str | None


def independent_tasks(skeleton: Skeleton, tasks: list[str], platform: Platform, *,
                      max_terms: int = MAX_TERMS) -> IndependentVerdict | None:
    """Decide ``tasks`` by the critical instant, or None when it does not apply.

    Parameters
    ----------
    skeleton : Skeleton
    tasks : list of str
        One part of the schedule (tasks joined by a group or a processor).
    platform : Platform
    max_terms : int
        Budget of recurrence steps; None is returned past it.

    Returns
    -------
    IndependentVerdict or None

    Examples
    --------
    B (period 4, duration 2) under A (period 2, duration 1): R_B = 2 + ceil(R/2)*1
    gives 3, then 4 = 2 + 2: B ends at 4, its period.

    >>> from tegraph.model.platform import platform_of
    >>> from tegraph.analysis.analyze import analyze_skeleton
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2},
    ...                                    "B": {"duration": 2, "period": 4}}})
    >>> v = independent_tasks(sk, ["A", "B"], platform_of(sk, analyze_skeleton(sk).groups))
    >>> {t: str(r) for t, r in v.response.items()}, v.late
    ({'A': '1', 'B': '4'}, None)
    """
    if not _independent(skeleton, tasks, platform):
        return None
    order = sorted(tasks, key=lambda t: -platform.priority[t])  # most urgent first
    duration = {t: skeleton.tasks[t].duration for t in tasks}
    # Type: _independent (above) holds only when every task has its own clock.
    period = {t: skeleton.clocks[skeleton.tasks[t].clock].period for t in tasks}  # type: ignore[index]
    response: dict[str, Fraction] = {}
    terms = 0
    for i, task in enumerate(order):
        urgent = order[:i]
        r = _lower_bound(duration[task], [(duration[j], period[j]) for j in urgent])
        while True:
            terms += 1
            if terms > max_terms:
                return None
            # ceil(r / T) for Fractions: -(-num // den) on r / T
            nxt = duration[task] + sum((-(-r // period[j])) * duration[j] for j in urgent)
            if nxt == r or nxt > period[task]:
                break
            r = nxt
        response[task] = nxt
        if nxt > period[task]:
            return IndependentVerdict(response, {t: period[t] for t in order[:i]}, task)
    return IndependentVerdict(response, period, None)


def _lower_bound(c: Fraction, urgent: list[tuple[Fraction, Fraction]]) -> Fraction:
    """A proven lower bound L of the least fixed point R, with f(L) >= L: the start.

    For any set B of the more urgent tasks, ceil(R/T_j) >= 1 on B and >= R/T_j off
    it, so R >= C + sum_B C_j + R U', U' the utilization off B, and
    L_B = (C + sum_B C_j) / (1 - U') when U' < 1; f(L_B) >= C + sum_B C_j + L_B U' =
    L_B, so the iteration from the largest L_B rises to the least fixed point. B runs
    over the k tasks of longest period (k = 0..n, prefix sums): on a nearly full
    processor with a few slow tasks, one step instead of 10^5.
    """
    best = c
    slow = sorted(urgent, key=lambda job: -job[1])  # longest period first
    rest = sum((cj / tj for cj, tj in slow), Fraction(0))
    work = c
    for k in range(len(slow) + 1):
        if rest < 1:
            best = max(best, work / (1 - rest))
        if k < len(slow):
            cj, tj = slow[k]
            work += cj
            rest -= cj / tj
    return best


def _independent(sk: Skeleton, tasks: list[str], platform: Platform) -> bool:
    """The hypotheses of the theorem: see the module's docstring.

    Preemption is one of them: on a non-preemptive processor (§4d) a less urgent job
    already running blocks a more urgent one, which the recurrence does not count, so
    the theorem declines there (None), and so do those built on it (``scaling.py``
    and the sensitivity's parts).
    """
    part = set(tasks)
    if len({platform.processor_of[t] for t in tasks}) != 1:
        return False
    if not platform.all_preemptive(tasks[:1]):
        return False
    if len({platform.priority[t] for t in tasks}) != len(tasks):
        return False
    # An ASYN/ASYN link adds no place (spec §2: neither side waits): it binds nothing.
    if any((link.writer[0] in part or link.reader[0] in part)
           and link.protocol is not Protocol.ASYN_ASYN for link in sk.links):
        return False
    if any(part.intersection(thread) for thread in sk.threads):
        return False
    clocks = [sk.tasks[t].clock for t in tasks]
    if None in clocks or len(set(clocks)) != len(clocks):
        return False
    users: dict[str, int] = {}
    for task in sk.tasks.values():
        if task.clock is not None:
            users[task.clock] = users.get(task.clock, 0) + 1
    # Type: None is not among `clocks` (returned False above).
    return all(users[c] == 1 and sk.clocks[c].phase == 0 for c in clocks)  # type: ignore[index]
