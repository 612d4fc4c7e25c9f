"""The skeleton on its processors (spec §4b) in the text report of ``tegraph analyze``.

The (max,+) figures of spec §4 assume a processor per task; a controller runs on
a few, under preemptive fixed priorities. These lines put the figures on the
processors beside them, labelled so that neither is read for the other (the
design section says where its response-time test, a cross-check, and the exact
schedule disagree: :mod:`tegraph.design.cross_check`).

See Also
--------
tegraph.analysis.processors.schedule_on_processors : computes them.
"""

from __future__ import annotations

from tabulate import tabulate

from ..analysis.results import Report
from ._format import count, human

__all__ = ["processors_headline", "render_processors", "replaced_priorities"]


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
    """The table of each task on its processor: period, overrun, responses (spec §4b)."""
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
        elif f.stopped_after is not None:
            overrun = "stopped (never runs again)"
        elif t.clock is None:
            overrun = "no clock"
        elif not report.groups[t.group].live:
            overrun = "not live"
        else:
            overrun = "never" if f.decided else "undecided (budget)"
        rows.append([name, s.platform.processor_of[name], s.platform.priority[name],
                     human(f.period, u), overrun, human(f.response, u),
                     human(f.response_from_tick, u)])
    lazy = [p.name for p in s.platform.processors if not p.preemptive]
    kind = ("preemptive fixed priorities" if not lazy else
            f"fixed priorities, preemptive but on {', '.join(lazy)} (non-preemptive, §4d)")
    lines = ["", f"on its processors (spec §4b: {kind}, larger is more "
             "urgent; the figures above assume a processor per task):",
             tabulate(rows, headers=["task", "processor", "priority", "period", "overrun",
                                     "response from release", "response from tick"]),
             "response from release: the longest time from a job's release (its reads done) "
             "to its end, preemption included, over the periodic regime",
             "response from tick: the longest time from its clock's tick to the end of the "
             "job it activates (the worst-case response of response-time analyses; "
             "\"-\" without a clock, or where ticks pile up)"]
    for name in s.stopped:
        f = s.tasks[name]
        since = (f"after activation {f.stopped_after}" if f.stopped_after
                 else "from the start (no job at all)")
        why = (f"it waits, through the graph's places, for {', '.join(f.waits_for)}, "
               "starved: a job that never ends writes nothing more"
               if f.waits_for else "it waits for events that never fire again")
        lines.append(f"stopped on processors: {name} never runs again {since}: {why}")
    for g in s.unbounded:
        per = ("" if g.per_regime is None
               else f", {count(g.per_regime, 'token')} more each regime")
        lines.append(f"growing place on processors: {g.src} -> {g.dst} [{g.kind}]{per}")
    if s.why_undecided:
        lines.append(f"undecided: {s.why_undecided}")
    return lines
