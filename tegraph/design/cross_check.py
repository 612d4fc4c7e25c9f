"""The response-time test beside the exact schedule on processors: a cross-check.

Every command that speaks of schedulability gives one verdict, the exact one of
spec §4b (:attr:`tegraph.analysis.results.Report.schedulable`, decided by
:func:`~tegraph.analysis.processors.schedule_on_processors`). The design section
also runs the response-time analysis of ORCCAD §6 (:mod:`.schedulability`); this
module compares the two, unit by unit, and says whether they agree. The test never
decides an exit status.

A unit (a group's tasks on one processor) *meets its period* in the exact
schedule when none of its tasks overruns, starves or stops behind a starved task
and no place of its group grows; a free-running unit (no clock) *gets time* when
none of its tasks starves or stops. A unit is compared where both answers are
known: the test decided it, the schedule's figures of its tasks are proven, and
its group is rate-consistent with a processor per task (elsewhere it misses its
period whatever the processor does, which the test does not model).

On a non-preemptive processor the design section gives bounds over every phase
(the revised analysis of Davis et al. 2007), no verdict: a unit whose bound is
within its period claims it meets its period whatever the phases, so the exact
schedule, for the declared phases, must show it so; each such unit is compared
(:attr:`CrossCheck.bounds_compared`), and one where the exact schedule shows a
problem is a :attr:`CrossCheck.bound_disagreements` entry (a bound proven wrong).

See Also
--------
tegraph.design.schedulability.schedulability : the test.
tegraph.design.section.design_section : computes both.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from maxplus.scalar import exact_text

from ..analysis.processors import Problem
from ..analysis.results import Report
from .schedulability import RTA_TEST, Schedulability

__all__ = ["CrossCheck", "UnitDisagreement", "cross_check"]


@dataclass(frozen=True)
class UnitDisagreement:
    """One unit on which the test and the exact schedule differ."""

    group: int
    tasks: tuple[str, ...]
    processor: str
    period: Fraction | None
    """The unit's period in the test (None: free-running)."""
    test: bool
    """What the test says: it meets its period (free-running: it gets time)."""
    why: str
    """What the exact schedule shows, in words (earliest problem first)."""

    def to_dict(self) -> dict[str, Any]:
        """The disagreement as the JSON report holds it."""
        return {"group": self.group, "tasks": list(self.tasks), "processor": self.processor,
                "period": exact_text(self.period), "test_says": self.test,
                "schedule_says": not self.test, "why": self.why}


@dataclass
class CrossCheck:
    """The response-time test's verdict beside the exact one.

    Attributes
    ----------
    test : str
        The test's name.
    says : bool or None
        The test's verdict on every processor (None: undecided or nothing analyzed).
    exact : bool or None
        The exact verdict of spec §4b (None: undecided within its budget).
    on_processors : bool
        The exact schedule was computed (False: every task on a processor of its
        own, ``--no-processors``: nothing to compare with).
    disagreements : list of UnitDisagreement
    """

    test: str
    says: bool | None
    exact: bool | None
    on_processors: bool
    disagreements: list[UnitDisagreement] = field(default_factory=list)
    preemptive_only: bool = False
    """The test's verdict covers the preemptive processors only (others are bounded)."""
    bounds_compared: int = 0
    """Units of non-preemptive processors whose bound over all phases is within their
    period, compared with the exact schedule."""
    bound_disagreements: list[UnitDisagreement] = field(default_factory=list)
    """Those where the exact schedule shows a problem all the same."""

    @property
    def bounds_agree(self) -> bool | None:
        """Whether every bound compared holds in the exact schedule (None: none compared)."""
        if not self.bounds_compared:
            return None
        return not self.bound_disagreements

    @property
    def agrees(self) -> bool | None:
        """True when both verdicts are known and equal and no unit differs; False when
        they differ; None when there is nothing to compare."""
        if not self.on_processors or self.says is None or self.exact is None:
            return None
        return self.says == self.exact and not self.disagreements

    def to_dict(self) -> dict[str, Any]:
        """The cross-check as the JSON report holds it (``schedulability.cross_check``)."""
        return {"test": self.test, "test_says": self.says, "schedule_says": self.exact,
                "agrees": self.agrees,
                "disagreements": [d.to_dict() for d in self.disagreements],
                "bounds_compared": self.bounds_compared, "bounds_agree": self.bounds_agree,
                "bound_disagreements": [d.to_dict() for d in self.bound_disagreements]}


def cross_check(sched: Schedulability, report: Report) -> CrossCheck:
    """Compare the response-time test ``sched`` with the exact schedule of ``report``.

    Parameters
    ----------
    sched : Schedulability
        ``schedulability(skeleton, report)``.
    report : Report
        The analysis, on processors (``report.schedule``) or not.

    Returns
    -------
    CrossCheck

    Examples
    --------
    A clockless logger beside a task using half the processor: the test charges no
    periodic load to the logger, gives it the other half, and agrees with the schedule.

    >>> from tegraph import Skeleton, analyze
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2},
    ...                                    "LOG": {"duration": 3}}})
    >>> r = analyze(sk)
    >>> c = cross_check(r.design.schedulability, r)
    >>> c.says, c.exact, c.agrees
    (True, True, True)
    """
    s = report.schedule
    out = CrossCheck(RTA_TEST, _test_says(sched), report.schedulable, s is not None,
                     preemptive_only=any(p.cross_check for p in sched.processors))
    if s is None:
        return out
    growing = {g.group for g in s.unbounded}
    first: dict[str, Problem] = {}  # each task's earliest problem, in the one order
    for p in s.problems:
        first.setdefault(p.task, p)
    for proc in sched.processors:
        for unit in proc.units:
            if unit.schedulable is None or not report.groups[unit.group].rate_consistent:
                continue
            if proc.cross_check and not unit.schedulable:
                continue  # a bound past the period claims nothing
            if not unit.free_running and unit.period is None:
                continue
            figures = [s.tasks[t] for t in unit.tasks]
            if not all(f.decided for f in figures):
                continue
            why = _exact_problem(unit.tasks, figures, first,
                                 unit.group in growing and not unit.free_running)
            if proc.cross_check:
                out.bounds_compared += 1
                if why is not None:
                    out.bound_disagreements.append(UnitDisagreement(
                        unit.group, tuple(unit.tasks), unit.processor or "default",
                        unit.period, True, why))
                continue
            if (why is None) != unit.schedulable:
                out.disagreements.append(UnitDisagreement(
                    unit.group, tuple(unit.tasks), unit.processor or "default", unit.period,
                    unit.schedulable, why or ("every job ends in time" if not unit.free_running
                                              else "it gets processor time")))
    return out


def _test_says(sched: Schedulability) -> bool | None:
    """The test's verdict on the processors it decides (the preemptive ones): a
    non-preemptive processor's bounds are compared apart (:attr:`CrossCheck.bounds_compared`)
    and leave the test's verdict to the others."""
    tested = [p.schedulable for p in sched.processors if not p.cross_check]
    if not tested or not any(p.cross_check for p in sched.processors):
        return sched.schedulable
    if any(v is False for v in tested):
        return False
    return None if any(v is None for v in tested) else True


def _exact_problem(tasks: list[str], figures: list[Any], first: dict[str, Problem],
                   grows: bool) -> str | None:
    """What the exact schedule shows wrong with a unit (its earliest problem), or None."""
    problems = sorted((first[t] for t in tasks if t in first),
                      key=lambda p: (p.at is None, p.at or 0))
    if problems:
        p = problems[0]
        return (f"{p.task} overruns at activation {p.k}" if p.kind == "overrun"
                else f"{p.task} is starved")
    for t, f in zip(tasks, figures):
        if f.stopped_after is not None:
            waits = ", ".join(f.waits_for) or "events that never fire again"
            return f"{t} never runs again (it waits for {waits})"
    if grows:
        return "a place of its group grows"
    return None
