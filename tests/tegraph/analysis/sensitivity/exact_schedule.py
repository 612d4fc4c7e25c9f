"""The reference the sensitivity tests hold their figures to: the exact schedule."""

from __future__ import annotations

from tegraph import Skeleton
from tegraph.analysis.analyze import analyze_skeleton
from tegraph.analysis.processors import schedule_on_processors
from tegraph.model.build import build_teg


def on_schedule(sk: Skeleton) -> bool | None:
    """Consistent (§4) and schedulable (§4b) by the exact schedule, not by a theorem or
    the walk of the sensitivity analysis."""
    report = analyze_skeleton(sk, processors=False, semiflow_max_places=0)
    if not report.consistent:
        return False
    return schedule_on_processors(sk, build_teg(sk), report.groups,
                                  intervals=False).schedulable
