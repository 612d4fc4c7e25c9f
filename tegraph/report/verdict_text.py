"""The verdict of an analysis in words: one wording and one order for every command.

``tegraph analyze``, ``tegraph rules`` and the design section end with the same
verdict (spec §5: live, consistent, schedulable on its processors), and name its
problems in one order, earliest in time first: an overrun at its clock's tick, a
starved task at the release of the job that never ends
(``ProcessorSchedule.problems``; with a
processor per task, the overruns of spec §4 by their ticks alike).
"""

from __future__ import annotations

from maxplus.scalar import display_text

from ..analysis.processors import Problem
from ..analysis.results import Report
from ._format import count

__all__ = ["MAX_NAMED", "problem_text", "problems", "processors_problem"]

MAX_NAMED = 3
"""Problems named one by one in a verdict line; the others are counted."""


def problem_text(p: Problem, unit: str) -> str:
    """One problem of the schedule on processors in words, with its instant.

    >>> from fractions import Fraction
    >>> problem_text(Problem("overrun", "gps", Fraction(100), 2), "ms")
    'gps overruns at activation 2 (100 ms)'
    >>> problem_text(Problem("starved", "B", Fraction(0), None), "ms")
    'B starved (its job released at 0 ms never ends)'
    """
    at = "" if p.at is None else f"{display_text(p.at)} {unit}"
    if p.kind == "overrun":
        return f"{p.task} overruns at activation {p.k}" + (f" ({at})" if at else "")
    return f"{p.task} starved (" + (f"its job released at {at} never ends)" if at
                                    else "a job never ends)")


def _named(texts: list[str]) -> str:
    """The first :data:`MAX_NAMED` texts, and how many more.

    >>> _named(["a", "b", "c", "d", "e"])
    'a, b, c and 2 more'
    """
    more = len(texts) - MAX_NAMED
    return ", ".join(texts[:MAX_NAMED]) + (f" and {more} more" if more > 0 else "")


def processors_problem(report: Report) -> str | None:
    """What the schedule on processors adds to the verdict line, or None when nothing.

    Its problems earliest first (at most :data:`MAX_NAMED` named), then its growing
    places.
    """
    s = report.schedule
    if s is None or s.schedulable is True:
        return None
    if s.schedulable is None:
        return "schedulability on its processors UNDECIDED within the budget (see above)"
    found = []
    if s.problems:
        found.append(_named([problem_text(p, report.unit) for p in s.problems]))
    if s.unbounded:
        found.append(count(len(s.unbounded), "growing place"))
    if not found:  # only dead groups: the deadlock is the problem, said already
        return None
    return "NOT SCHEDULABLE on its processors: " + ", ".join(found)


def problems(report: Report) -> list[str]:
    """What makes the exit status 1: the deadlocks, the inconsistencies, the processors."""
    out = []
    if not report.live:
        dead = sorted({report.tasks[t].group for d in report.deadlocks for t in d.tasks})
        out.append(f"NOT LIVE: {count(len(report.deadlocks), 'token-free circuit')} "
                   f"(group{'s' * (len(dead) != 1)} {', '.join(map(str, dead))})")
    inconsistent = []
    if report.unbounded_places:
        inconsistent.append(f"{count(len(report.unbounded_places), 'unbounded place')}")
    index = {t: i for i, t in enumerate(report.tasks)}
    # Earliest first, as on processors: by the tick of the overrun, then file order.
    overruns = sorted((t for t in report.tasks.values() if t.overrun_at is not None),
                      key=lambda t: (t.overrun_tick is None, t.overrun_tick or 0,
                                     index[t.name]))
    if overruns:
        inconsistent.append(_named([
            f"{t.name} overruns at activation {t.overrun_at}"
            + ("" if t.overrun_tick is None
               else f" ({display_text(t.overrun_tick)} {report.unit})")
            for t in overruns]))
    if inconsistent:
        out.append("NOT CONSISTENT: " + ", ".join(inconsistent))
    on_processors = processors_problem(report)
    if on_processors:
        out.append(on_processors)
    return out
