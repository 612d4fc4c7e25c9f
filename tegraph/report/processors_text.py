"""The skeleton on its processors (spec §4b) in the text report of ``tegraph analyze``.

The (max,+) figures of spec §4 assume a processor per task; a controller runs on
a few, under preemptive fixed priorities. These lines put the figures on the
processors beside them, labelled so that neither is read for the other, and
say where the design section's response-time test and the exact schedule
disagree (the test is a cross-check; the schedule is the verdict).

See Also
--------
tegraph.analysis.processors.schedule_on_processors : computes them.
"""

from __future__ import annotations

from tabulate import tabulate

from ..analysis.processors.schedule import NON_PREEMPTIVE
from ..analysis.results import Report
from ._format import count, human

__all__ = ["processors_headline", "processors_problem", "render_processors",
           "replaced_priorities", "response_test_disagreements"]


def processors_headline(report: Report) -> str:
    """The header line: schedulable or not on which processors, and how it was decided.

    >>> from tegraph import Skeleton, analyze
    >>> r = analyze(Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 10}}}),
    ...             design=False)
    >>> processors_headline(r).split(" — ")[0]
    'processors:  schedulable on 1 processor (default: rate-monotonic priorities)'
    """
    s = report.schedule
    if s is None:
        return ("processors:  not considered — every task on a processor of its own "
                "(processors=False): the figures of spec §4 decide")
    where = _priority_sources(s.platform.processors)
    verdict = {True: "schedulable", False: "NOT SCHEDULABLE", None: "UNDECIDED"}[s.schedulable]
    return (f"processors:  {verdict} on {count(len(s.platform.processors), 'processor')} "
            f"({where}) — {s.method}")


def replaced_priorities(report: Report) -> list[str]:
    """Lines for the top of the report: on each processor where only some tasks declare
    a priority, which declared priorities were replaced, and why (all or none, §4b).

    >>> from tegraph import Skeleton, analyze
    >>> r = analyze(Skeleton.from_dict({"tasks": {
    ...     "A": {"duration": 1, "period": 10, "priority": 5},
    ...     "B": {"duration": 1, "period": 5}}}), design=False)
    >>> print(replaced_priorities(r)[0])  # doctest: +NORMALIZE_WHITESPACE
    priorities:  REPLACED on default: 1 of its 2 tasks declare a priority (B does not); a
    processor's priorities are all declared or none (spec §4b), so all run at the
    rate-monotonic proposal: A 5 -> 1 (declare every task's priority to keep yours;
    `tegraph rules` gives the change)
    """
    if report.platform is None:
        return []
    out = []
    for p in report.platform.replaced:
        missing = [t for t in p.tasks if t not in p.replaced]
        shown = ", ".join(missing[:_NAMED]) + (f" and {len(missing) - _NAMED} more"
                                               if len(missing) > _NAMED else "")
        changes = [f"{t} {v} -> {p.priorities[t]}" for t, v in p.replaced.items()]
        listed = ", ".join(changes[:12]) + (f" and {len(changes) - 12} more"
                                            if len(changes) > 12 else "")
        out.append(f"priorities:  REPLACED on {p.name}: {len(p.replaced)} of its "
                   f"{len(p.tasks)} tasks declare a priority ({shown} "
                   f"{'does' if len(missing) == 1 else 'do'} not); a processor's priorities "
                   "are all declared or none (spec §4b), so all run at the rate-monotonic "
                   f"proposal: {listed} (declare every task's priority to keep yours; "
                   "`tegraph rules` gives the change)")
    return out


_NAMED = 4
"""Processors named one by one in the header line; past that, grouped by where their
priorities come from (a hundred processors would fill a screen)."""


def _priority_sources(processors) -> str:
    """Where each processor's priorities come from, in file order.

    >>> from types import SimpleNamespace as P
    >>> _priority_sources([P(name="cpu0", priority_source="declared")])
    'cpu0: declared priorities'
    >>> cpus = [P(name=f"cpu{i}", priority_source="rate-monotonic") for i in range(6)]
    >>> _priority_sources(cpus)
    'rate-monotonic priorities on all 6'
    >>> cpus[4] = P(name="cpu4", priority_source="declared")
    >>> _priority_sources(cpus)
    'rate-monotonic priorities on cpu0, cpu1, cpu2 and 2 more; declared priorities on cpu4'
    """
    if len(processors) <= _NAMED:
        return ", ".join(f"{p.name}: {p.priority_source} priorities"
                         + ("" if getattr(p, "preemptive", True) else ", non-preemptive")
                         for p in processors)
    by_source: dict[str, list[str]] = {}
    for p in processors:
        by_source.setdefault(p.priority_source, []).append(p.name)
    if len(by_source) == 1:
        return f"{next(iter(by_source))} priorities on all {len(processors)}"
    return "; ".join(
        f"{source} priorities on {', '.join(names[:3])}"
        + (f" and {len(names) - 3} more" if len(names) > 3 else "")
        for source, names in by_source.items())


def render_processors(report: Report) -> list[str]:
    """The table of each task on its processor: period, overrun, response (spec §4b)."""
    s = report.schedule
    if s is None:
        return []
    u = report.unit
    rows = []
    for name, t in report.tasks.items():  # file order, as the table above
        f = s.tasks[name]
        if f.starved:
            overrun = "starved (never ends)"
        elif f.overrun_at is not None:
            overrun = f"at activation {f.overrun_at}"
        elif t.clock is None:
            overrun = "no clock"
        elif not report.groups[t.group].live:
            overrun = "not live"
        else:
            overrun = "never" if f.decided else "undecided (budget)"
        rows.append([name, s.platform.processor_of[name], s.platform.priority[name],
                     human(f.period, u), overrun, human(f.response, u)])
    lazy = [p.name for p in s.platform.processors if not p.preemptive]
    kind = ("preemptive fixed priorities" if not lazy else
            f"fixed priorities, preemptive but on {', '.join(lazy)} (non-preemptive, §4d)")
    lines = ["", f"on its processors (spec §4b: {kind}, larger is more "
             "urgent; the figures above assume a processor per task):",
             tabulate(rows, headers=["task", "processor", "priority", "period", "overrun",
                                     "response"]),
             "response: the longest time from a job's release (its reads done) to its end, "
             "preemption included, over the periodic regime"]
    for g in s.unbounded:
        per = ("" if g.per_regime is None
               else f", {count(g.per_regime, 'token')} more each regime")
        lines.append(f"growing place on processors: {g.src} -> {g.dst} [{g.kind}]{per}")
    if s.why_undecided:
        lines.append(f"undecided: {s.why_undecided}")
    lines += [f"cross-check: {d}" for d in response_test_disagreements(report)]
    return lines


def processors_problem(report: Report) -> str | None:
    """What the schedule on processors adds to the verdict line, or None when nothing."""
    s = report.schedule
    if s is None or s.schedulable is True:
        return None
    if s.schedulable is None:
        if s.why_undecided and s.why_undecided.startswith("not computed"):
            return f"schedulability on its processors UNDECIDED: {NON_PREEMPTIVE} (see above)"
        return "schedulability on its processors UNDECIDED within the budget (see above)"
    found = [f"{t} starved (a job never ends)" for t in s.starved]
    late = [(f.overrun_at, t) for t, f in s.tasks.items() if f.overrun_at is not None]
    if late:
        k, first = min(late)
        more = f" and {len(late) - 1} more" if len(late) > 1 else ""
        found.append(f"{first} overruns at activation {k}{more}")
    if s.unbounded:
        found.append(count(len(s.unbounded), "growing place"))
    if not found:  # only dead groups: the deadlock is the problem, said already
        return None
    return "NOT SCHEDULABLE on its processors: " + ", ".join(found)


def response_test_disagreements(report: Report) -> list[str]:
    """Units where the design section's response-time test and the exact schedule differ.

    A unit is a group's tasks on one processor; the exact schedule says it meets
    its period when none of them overruns or starves and no place of its group
    grows. Units the test leaves undecided, without a period, or in a group that
    is not rate-consistent with a processor per task, are not compared.
    """
    s, design = report.schedule, report.design
    if s is None or design is None:
        return []
    growing = {g.group for g in s.unbounded}
    out = []
    for proc in design.schedulability.processors:
        for unit in proc.units:
            # Only where §4 finds the group rate-consistent: elsewhere it misses its
            # period with a processor per task already, whatever the processor does.
            if (unit.schedulable is None or unit.period is None
                    or not report.groups[unit.group].rate_consistent):
                continue
            figures = [s.tasks[t] for t in unit.tasks]
            if not all(f.decided for f in figures):
                continue
            exact = unit.group not in growing and not any(
                f.overrun_at is not None or f.starved for f in figures)
            if exact != unit.schedulable:
                test = "meets" if unit.schedulable else "misses"
                truth = "meets it" if exact else "does not"
                out.append(f"group {unit.group} ({', '.join(unit.tasks)}) on "
                           f"{unit.processor}: the response-time test says it "
                           f"{test} its period ({human(unit.period, report.unit)}); the exact "
                           f"schedule {truth} (the schedule decides the verdict)")
    return out
