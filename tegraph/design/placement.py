"""Candidates to share a processor: tasks that never execute at the same time.

ORCCAD's §2.4 asks the analysis to "facilitate the assignment of MTs to processors, by
identifying those MTs which ... never execute at the very same time". ``tegraph rules``
lists them from the schedule that the analysis proved (spec §4b): the pairs of tasks on
different processors whose processor time never overlaps, for all time
(:func:`tegraph.analysis.processors.overlap.never_together`). They are candidates, not
a verdict: moving a task onto another's processor changes the schedule, which
``tegraph analyze`` then decides.

See Also
--------
tegraph.analysis.processors.overlap : how the pairs are decided.
"""

from __future__ import annotations

from ..analysis.processors.overlap import NeverTogether, never_together
from ..analysis.processors.schedule import MAX_EVENTS, schedule_on_processors
from ..analysis.results import Report
from ..model.build import build_teg
from ..model.skeleton import Skeleton

__all__ = ["shared_processor_candidates"]


def shared_processor_candidates(skeleton: Skeleton, report: Report,
                                max_events: int = MAX_EVENTS) -> NeverTogether | None:
    """The pairs of tasks on different processors that never run at once, or None.

    Parameters
    ----------
    skeleton : Skeleton
    report : Report
        Its analysis on processors (``report.schedule``).
    max_events : int
        The budget the analysis was given: the schedule is simulated once more with
        each job's processor time (the analysis keeps only its figures).

    Returns
    -------
    NeverTogether or None
        None where the analysis was not made on processors or the skeleton runs on one
        processor (no pair to list); else the pairs, or why none is claimed.

    Examples
    --------
    >>> from tegraph.analysis.analyze import analyze_skeleton
    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "A": {"duration": 1, "period": 4, "processor": "p"},
    ...     "B": {"duration": 1, "period": 4, "phase": 2, "processor": "q"}}})
    >>> shared_processor_candidates(sk, analyze_skeleton(sk, processors=True)).pairs
    [('A', 'B')]
    """
    s = report.schedule
    if s is None or len(s.platform.processors) < 2:
        return None
    if s.schedulable is not True:
        return never_together(s)  # says why nothing is claimed
    again = schedule_on_processors(skeleton, build_teg(skeleton), report.groups,
                                   platform=s.platform, max_events=max_events)
    return never_together(again)
