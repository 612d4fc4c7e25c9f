"""Text reports: :func:`render_text` renders any result of the project.

Everything here returns strings; nothing prints. The command line decides
where the strings go. One function renders each kind of result
(``render_report``, ``render_cycle_time``, ``render_rules``...);
:func:`render_text` picks it from the result's type, registered by its dotted
name and imported on first use (:mod:`.registry`): rendering an analysis loads
no explore, timeline, sensitivity or reachability code.
"""

from __future__ import annotations

from typing import Any

from tabulate import tabulate

from ..analysis.results import GroupReport, Report, TaskReport
from ..model.elements import flow_list
from ._format import count, human
from .chains_text import render_chains
from .design_text import render_latency, render_rules, render_schedulability
from .graph_text import ratio_text
from .processors_text import processors_headline, render_processors, replaced_priorities
from .registry import Renderers
from .verdict_text import problems as verdict_problems

__all__ = ["render_report", "render_text"]


def _grow(t: TaskReport, unit: str) -> str:
    """The "can grow by" cell: the exact margin, "unbounded", or "-"."""
    if t.duration_margin_state == "exact":
        return human(t.duration_margin, unit)
    return "unbounded" if t.duration_margin_state == "unbounded" else "-"


def render_report(report: Report) -> str:
    """The human report: verdicts with how they were obtained, then tables.

    Returns
    -------
    str
    """
    u = report.unit
    lines = [f"skeleton {report.name}" + (f" ({report.source})" if report.source else "")]
    verdict = "live" if report.live else "NOT LIVE (deadlock)"
    lines.append(f"liveness:    {verdict} — {report.methods.get('liveness', '')}")
    consistent = "consistent" if report.consistent else "NOT CONSISTENT"
    lines.append(f"timing:      {consistent} — {report.methods.get('timing', '')}")
    lines.append(f"periods:     {report.methods.get('periods', '')}")
    lines.append(processors_headline(report))
    lines += replaced_priorities(report)
    lines += _deadlocks(report)
    lines += _groups(report)
    lines += _tasks(report)
    lines += render_processors(report)
    lines += render_chains(report.chains, u, report.schedule is not None)
    if report.unbounded_places:
        lines.append("")
        lines.append("unbounded places (tokens pile up):")
        for p in report.unbounded_places:
            lines.append(f"  {p.src} -> {p.dst} [{p.kind}]: {p.advice}")
    inv = report.invariants
    lines.append("")
    if inv.computed:
        agree = "agrees" if inv.liveness_agrees else "DISAGREES"
        lines.append(f"invariants: {inv.count} minimal p-semiflows, {inv.unmarked} without token; "
                     f"the semiflow verdict {agree} with the circuit verdict")
    else:
        lines.append(f"invariants: not computed ({inv.reason})")
    if report.design is not None:
        lines += ["", render_rules(report.design.rules).rstrip("\n"),
                  render_schedulability(report.design.schedulability, u,
                                        report.design.cross_check).rstrip("\n")]
        lines += [render_latency(c, u).rstrip("\n") for c in report.design.latency]
    for note in report.notes:
        lines.append(f"note: {note}")
    lines.append("")
    lines.append(_verdict(report))
    return "\n".join(lines) + "\n"


def _deadlocks(report: Report) -> list[str]:
    """Each token-free circuit with its tasks, links and advice, then the reorder."""
    lines = []
    for d in report.deadlocks:
        lines.append("")
        lines.append("deadlock: token-free circuit " + " -> ".join([*d.events, d.events[0]]))
        lines.append(f"  tasks on it: {', '.join(d.tasks)}")
        if d.links:
            lines.append(f"  links on it: {'; '.join(d.links)}")
        lines.append(f"  what to change: {d.advice}")
    if report.reorder is None:
        return lines
    lines.append("")
    if report.reorder.possible:
        # Spec §4's witness, whole orders; the advice above is the repair with
        # the fewest changes, so the two may differ: say which is which.
        lines.append("reorder: a port order makes the skeleton live; one such order "
                     "(spec §4; the advice above changes fewest ports, as tegraph fix):")
        for task, order in report.reorder.orders.items():
            lines.append(f"  {task}: inputs {flow_list(order['inputs'])}, "
                         f"outputs {flow_list(order['outputs'])}")
    else:
        lines.append("reorder: no port order makes the skeleton live "
                     "(the precedence graph of reads, computes and writes has a circuit)")
    return lines


def _groups(report: Report) -> list[str]:
    """The groups' table (spec §4 order), then each group's critical circuit."""
    u = report.unit
    rows = []
    for g in report.groups:
        transient = ("-" if g.transient is None
                     else f"k={g.transient[0]}, cyclicity {g.transient[1]}")
        state = "dead" if not g.live else ("rate-consistent" if g.rate_consistent else "unbounded")
        rows.append([g.index, ", ".join(g.tasks), ", ".join(g.clocks) or "-", state,
                     human(g.period, u), transient])
    lines = ["", tabulate(rows, headers=["group", "tasks", "clocks", "state", "period",
                                         "transient"])]
    lines += [critical_circuit_text(g, u) for g in report.groups if g.critical_circuit]
    return lines


def _tasks(report: Report) -> list[str]:
    """The tasks' table with a processor per task, and what its margins mean."""
    u = report.unit
    rows = [[t.name, t.group, human(t.period, u), t.overrun, human(t.slack, u), _grow(t, u),
             "-" if t.critical is None else ("yes" if t.critical else "no")]
            for t in report.tasks.values()]
    lines = [""]
    if report.schedule is not None:
        lines.append("with a processor per task (spec §4, (max,+); on its processors: below):")
    lines.append(tabulate(rows, headers=["task", "group", "period", "overrun",
                                         "slack (period margin)", "can grow by", "critical"]))
    if any(t.slack is not None for t in report.tasks.values()):
        lines.append("slack: how much the task's duration may grow before its group's period "
                     "(or its clock's) is exceeded, the other durations unchanged (spec §4); "
                     "it is no overrun margin")
    if any(t.duration_margin_state != "not computed" for t in report.tasks.values()):
        lines.append("can grow by: how much the duration may grow, the others unchanged, "
                     "with its group still consistent: no overrun and every place bounded "
                     "(exact; \"-\": the group is not consistent as it is)")
    elif "duration_margins" in report.methods:
        lines.append(f"can grow by: {report.methods['duration_margins']}")
    return lines


def critical_circuit_text(group: GroupReport, unit: str) -> str:
    """Why a group's period is what it is: its critical circuit and the ratio it attains.

    ``critical circuit of group 0: a -> b -> a: (2 + 5/3 + 3) ms over 2 tokens = 10/3 ms``;
    places holding 0 are left out of the sum.
    """
    circuit = " -> ".join([*group.critical_circuit, group.critical_circuit[0]])
    text = f"critical circuit of group {group.index}: {circuit}"
    if group.critical_tokens:
        what = ("the period" if group.rate_consistent
                else "its slowest cycle time (the group is not rate-consistent)")
        text += (": " + ratio_text(group.critical_holdings, group.critical_tokens, unit)
                 + f", {what}")
    return text


def _verdict(report: Report) -> str:
    """The last line: the spec §5 verdict in one line, and why the exit status is what it is."""
    problems = verdict_problems(report)
    undecided = [t.name for t in report.tasks.values() if not t.overrun_decided]
    if not problems:
        text = ("verdict: live and consistent (exit status 0)" if report.schedule is None else
                "verdict: live, consistent and schedulable on its processors (exit status 0)")
        if undecided:
            text += (f"; {count(len(undecided), 'overrun')} undecided within the budget "
                     f"({', '.join(undecided[:3])}{' ...' if len(undecided) > 3 else ''})")
    else:
        if report.live and report.consistent and report.schedule is not None:
            problems.insert(0, "live and consistent with a processor per task, but")
        text = "verdict: " + "; ".join(problems).replace("but; ", "but ") + " (exit status 1)"
    return text + _design_addendum(report)


def _design_addendum(report: Report) -> str:
    """Under a verdict of exit status 0, what the design section lists that does not
    change it (ORCCAD §6 advice), or nothing."""
    design = report.design
    if design is None or report.exit_status != 0:
        return ""
    errors = sum(f.severity == "error" for f in design.rules)
    # With the schedule on processors deciding, the response-time test is only
    # a cross-check (its disagreements are listed above the verdict).
    fails = report.schedule is None and design.schedulability.schedulable is False
    if not (errors or fails):
        return ""
    listed = [count(errors, "design-rule error")] if errors else []
    if fails:
        listed.append("a processor that fails its schedulability test")
    return (f"; the design section lists {' and '.join(listed)}: advice of ORCCAD "
            "§6, which does not change the verdict of spec §5")


def render_text(result: Any, **options: Any) -> str:
    """The human report of any result: an analysis, a cycle time, a baseline, a design result.

    Parameters
    ----------
    result : Report, CycleTimeResult, Reachability, TimedExploration, Schedulability,
        ChainLatency, FixResult, Timeline, Exploration, DesignSection, or a list of
        RuleFinding
    **options
        Passed to the renderer of that result (``unit`` for schedulability and
        latency, ``limit`` for reachability, ``width`` for a timeline, ``name``
        for a port repair).

    Returns
    -------
    str
        The human-readable report, several lines.

    Raises
    ------
    TypeError
        For an object that is no result of this project.

    See Also
    --------
    tegraph.report.to_json : the JSON document of the same result.
    tegraph.analyze : the analysis whose report this renders most often.

    Examples
    --------
    >>> from tegraph import Skeleton, analyze
    >>> r = analyze(Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 3}}}))
    >>> render_text(r).splitlines()[0]
    'skeleton skeleton'
    """
    return _RENDERERS.find(result)(result, **options)


# Each result type by its dotted name -> "module:function(result, **options)"; the
# module is imported the first time such a result is rendered.
_RENDERERS = Renderers("text rendering", {
    "tegraph.analysis.results.Report": "tegraph.report.text:_report",
    "tegraph.analysis.cycle_time.CycleTimeResult": "tegraph.report.text:_cycle_time",
    "tegraph.analysis.baselines.reachability.Reachability": "tegraph.report.text:_reachability",
    "tegraph.analysis.baselines.timed_reachability.TimedExploration":
        "tegraph.report.text:_timed_exploration",
    "tegraph.design.schedulability.Schedulability": "tegraph.report.text:_schedulability",
    "tegraph.design.latency.ChainLatency": "tegraph.report.text:_latency",
    "tegraph.analysis.repair.FixResult": "tegraph.report.text:_fix",
    "tegraph.design.timeline.Timeline": "tegraph.report.text:_timeline",
    "builtins.list": "tegraph.report.text:_rules",
    "tegraph.design.section.DesignSection": "tegraph.report.text:_design",
    "tegraph.design.explore.exploration.Exploration": "tegraph.report.text:_exploration",
    "tegraph.analysis.sensitivity.results.SensitivityResult": "tegraph.report.text:_sensitivity",
})


# The adapters: each imports its renderer when first called.
def _report(result: Report, **_: Any) -> str:
    return render_report(result)


def _cycle_time(result: Any, **_: Any) -> str:
    from .graph_text import render_cycle_time
    return render_cycle_time(result)


def _reachability(result: Any, limit: int = 10, **_: Any) -> str:
    from .graph_text import render_reachability
    return render_reachability(result, limit)


def _timed_exploration(result: Any, **_: Any) -> str:
    from .graph_text import render_timed_exploration
    return render_timed_exploration(result)


def _schedulability(result: Any, unit: str = "ms", **_: Any) -> str:
    return render_schedulability(result, unit)


def _latency(result: Any, unit: str = "ms", **_: Any) -> str:
    return render_latency(result, unit)


def _fix(result: Any, name: str = "skeleton", **_: Any) -> str:
    from .design_text import render_fix
    return render_fix(result, name)


def _timeline(result: Any, width: int = 96, **_: Any) -> str:
    from .timeline_text import render_timeline
    return render_timeline(result, width)


def _rules(result: list, **_: Any) -> str:
    return render_rules(result)


def _design(result: Any, **_: Any) -> str:
    from .design_text import render_design
    return render_design(result)


def _exploration(result: Any, **_: Any) -> str:
    from .explore_text import render_exploration
    return render_exploration(result)


def _sensitivity(result: Any, **_: Any) -> str:
    from .sensitivity_text import render_sensitivity
    return render_sensitivity(result)
