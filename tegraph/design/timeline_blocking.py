"""When a job waits for a less urgent one on a non-preemptive processor: its blocking.

On a processor declared ``preemptive: false`` (spec §4d) a job released while a less
urgent job runs waits for that job to end: the *blocking* the revised analysis of
Davis et al. [1]_ bounds by the longest less urgent duration. A timing diagram
marks it (:mod:`tegraph.report.plot`): for job k of T, released at ``r_T(k)`` (the
replayed daters, :func:`.timeline_waits.replay_daters`), the stretch from ``r_T(k)``
to the end of the less urgent job running at that instant (or to T's own start,
if earlier). Interference from more urgent jobs after it is not blocking and is not
marked. Nothing here decides anything: the processor time is the engine's.

References
----------
.. [1] R. I. Davis, A. Burns, R. J. Bril and J. J. Lukkien, "Controller Area Network
   (CAN) schedulability analysis: refuted, revisited and revised", Real-Time Systems
   35(3), 2007.

See Also
--------
tegraph.design.nonpreemptive : the bounds over all phases.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction

from ..analysis.processors import JobInterval
from ..model.platform import Platform

__all__ = ["Blocking", "blockings"]


@dataclass(frozen=True)
class Blocking:
    """Job ``k`` of ``task`` waits from ``start`` to ``end`` for job ``by_k`` of the less
    urgent ``by``, which holds the non-preemptive ``processor``."""

    task: str
    k: int
    processor: str
    start: Fraction
    end: Fraction
    by: str
    by_k: int

    @property
    def length(self) -> Fraction:
        """How long the job is blocked."""
        return self.end - self.start


def blockings(intervals: Sequence[JobInterval], releases: Mapping[tuple[str, int], Fraction],
              platform: Platform) -> list[Blocking]:
    """The blocking of every drawn job on a non-preemptive processor, by start.

    Parameters
    ----------
    intervals : sequence of JobInterval
        The drawn processor time (on a non-preemptive processor, one interval a job).
    releases : mapping
        ``(task, k)`` -> the release ``r_T(k)`` of that job.
    platform : Platform
        Which processors are non-preemptive, and the priorities.

    Returns
    -------
    list of Blocking

    Examples
    --------
    L (priority 1) runs 0-3 on a bus; H (priority 2), released at 1, runs 3-4: it is
    blocked from 1 to 3 by L.

    >>> from tegraph.analysis.processors import JobInterval
    >>> from tegraph.model.platform import platform_of
    >>> from tegraph.model.skeleton import Skeleton
    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "L": {"duration": 3, "period": 10, "priority": 1, "processor": "bus"},
    ...     "H": {"duration": 1, "period": 10, "phase": 1, "priority": 2, "processor": "bus"}},
    ...     "processors": {"bus": {"preemptive": False}}})
    >>> drawn = [JobInterval("bus", Fraction(0), Fraction(3), "L", 1),
    ...          JobInterval("bus", Fraction(3), Fraction(4), "H", 1)]
    >>> [(b.task, str(b.start), str(b.end), b.by) for b in blockings(
    ...     drawn, {("L", 1): Fraction(0), ("H", 1): Fraction(1)}, platform_of(sk))]
    [('H', '1', '3', 'L')]
    """
    lazy = {p.name for p in platform.processors if not p.preemptive}
    if not lazy:
        return []
    priority = platform.priority
    lanes: dict[str, list[JobInterval]] = {}
    for i in intervals:
        if i.processor in lazy:
            lanes.setdefault(i.processor, []).append(i)
    out = []
    for proc, lane in lanes.items():
        lane.sort(key=lambda i: i.start)
        for n, i in enumerate(lane):
            r = releases.get((i.task, i.k))
            if r is None or r >= i.start:
                continue
            # The job holding the processor at r: at most one, started at or before r
            # (the lane is in start order, so it is among those before this one).
            for j in reversed(lane[:n]):
                if j.start <= r < j.end:
                    if priority[j.task] < priority[i.task]:
                        out.append(Blocking(i.task, i.k, proc, r, min(j.end, i.start),
                                            j.task, j.k))
                    break
                if j.end <= r:
                    break
    out.sort(key=lambda b: (b.start, b.processor))
    return out
