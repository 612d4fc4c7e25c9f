"""Text of the design results of ORCCAD §6: rules, schedulability, latency, port repair."""

from __future__ import annotations

from tabulate import tabulate

from maxplus.scalar import display_text

from ..analysis.repair import FixResult
from ..design.cross_check import CrossCheck, UnitDisagreement
from ..design.latency import OVER_ANY_PHASES, ChainLatency
from ..design.rules import RuleFinding
from ..design.schedulability import PAPER_TEST, Schedulability
from ..design.section import DesignSection
from ..model.platform import DEFAULT_PROCESSOR
from ._format import count, number
from .chains_text import figures_text
from .verdict_text import problems

__all__ = [
    "fix_verdict",
    "render_design",
    "render_fix",
    "render_latency",
    "render_never_together",
    "render_rules",
    "render_schedulability",
]


def render_rules(findings: list[RuleFinding]) -> str:
    """The findings as text, one paragraph each (empty findings: one line).

    >>> print(render_rules([]), end="")
    design rules (ORCCAD section 6): all followed
    """
    by_severity = [(s, sum(f.severity == s for f in findings))
                   for s in ("error", "warning", "info")]
    listed = ", ".join(count(n, s) for s, n in by_severity if n)
    if not any(f.severity != "info" for f in findings):
        head = "design rules (ORCCAD section 6): all followed" + (f" ({listed})" if listed else "")
    else:
        head = f"design rules (ORCCAD section 6): {listed}"
    lines = [head]
    for f in findings:
        lines.append(f"  Rule {f.rule} [{f.severity}] {f.message}")
        lines.append(f"    what to change: {f.advice}")
    return "\n".join(lines) + "\n"


def render_design(section: DesignSection) -> str:
    """What ``tegraph rules`` prints: rules, schedulability, latencies, and the verdict last.

    The verdict is the analysis's, in the words of ``tegraph analyze`` (spec §4b on its
    processors, exactly); the response-time test above it is a cross-check. The exit
    status it names is the command's (:attr:`DesignSection.exit_status`): 1 when a rule
    is not followed (an error or a warning) or the analysis's exit status is 1.
    """
    findings, sched, unit = section.rules, section.schedulability, section.unit
    text = (render_rules(findings) + "\n"
            + render_schedulability(sched, unit, section.cross_check))
    for r in section.latency:
        text += "\n" + render_latency(r, unit)
    if section.never_together is not None:
        text += "\n" + render_never_together(section)
    counts = [(s, sum(f.severity == s for f in findings)) for s in ("error", "warning")]
    broken = ", ".join(count(n, f"design-rule {s}") for s, n in counts if n)
    report = section.analysis
    found = problems(report)
    if found:
        if report.live and report.consistent and report.schedule is not None:
            found.insert(0, "live and consistent with a processor per task, but")
        verdict = "; ".join(found).replace("but; ", "but ")
    elif report.schedule is None:
        verdict = "live and consistent with a processor per task (not on its processors)"
    else:
        verdict = "schedulable on its processors (spec §4b, exact)"
    verdict += f"; {broken}" if broken else "; design rules followed"
    return text + f"\nverdict: {verdict} (exit status {section.exit_status})\n"


def render_never_together(section: DesignSection) -> str:
    """The tasks on different processors that never run at once (ORCCAD §2.4).

    Returns
    -------
    str
    """
    n = section.never_together
    assert n is not None
    head = ("tasks that never execute at the same time (ORCCAD section 2.4; candidates to "
            "share a processor, from the proven schedule on processors, for all time):")
    if n.pairs is None:
        return f"{head}\n  not listed: {n.why}\n"
    where = section.analysis.schedule.platform.processor_of  # type: ignore[union-attr]
    lines = [head]
    if not n.pairs:
        lines.append(f"  none among the {count(n.examined, 'pair')} of tasks on different "
                     "processors")
    lines += [f"  {a} ({where[a]}) and {b} ({where[b]})" for a, b in n.pairs]
    if n.pairs:
        lines.append(f"  {len(n.pairs)} of the {count(n.examined, 'pair')} examined; moving "
                     "one onto the other's processor changes the schedule: analyze decides it")
    lines += [f"  {t} left out: {why}" for t, why in n.left_out.items()]
    return "\n".join(lines) + "\n"


def render_schedulability(result: Schedulability, unit: str = "ms",
                          cross: CrossCheck | None = None) -> str:
    """Threads and the per-processor response-time test as text, with its cross-check.

    The test is ORCCAD §6's: it is compared with the exact schedule on processors
    (``cross``, :mod:`tegraph.design.cross_check`), which decides the verdict.

    Returns
    -------
    str
    """
    lines = []
    if result.threads:
        lines.append("threads (a thread's period is at least the sum of its durations):")
        for t in result.threads:
            if t.fits is None:
                verdict = "not live"
            else:
                pace = ("free-running" if t.pace is None
                        else f"paced at {display_text(t.pace)} {unit}")
                verdict = (f"{'fits' if t.fits else 'DOES NOT FIT'} ({pace}, margin "
                           f"{display_text(t.margin)} {unit})")
            lines.append(f"  thread {t.index} [{', '.join(t.tasks)}]: load {display_text(t.load)} "
                         f"{unit}, period {display_text(t.period) or '-'} {unit}: {verdict}")
    for p in result.processors:
        name = ("default processor" if p.processor in (None, DEFAULT_PROCESSOR)
                else f"processor {p.processor}")
        kind = "preemptive" if p.preemptive else "NON-PREEMPTIVE"
        lines.append(f"response-time test on the {name} (ORCCAD section 6, a cross-check of "
                     f"the exact schedule; {kind} fixed priorities, {p.priority_source} "
                     "priorities, larger is more urgent):")
        if p.hyperperiod is not None:
            holds = "holds" if p.condition_holds else "FAILS"
            lines.append(f"  {PAPER_TEST}: T = {display_text(p.hyperperiod)} {unit}, "
                         f"sum = {display_text(p.demand)} {unit}: {holds} (margin "
                         f"{display_text(p.condition_margin)} {unit}; free-running groups "
                         "are no periodic load)")
        rows = []
        for u in p.units:
            verdict = ("undecided" if u.undecided else "-" if u.schedulable is None
                       else ("yes" if u.schedulable else "NO"))
            rows.append([u.group, ", ".join(u.tasks), u.priority, number(u.period),
                         number(u.cost), number(u.response_time), number(u.margin), verdict,
                         u.note])
        bound = p.cross_check  # the figures are bounds over all phases there
        table = tabulate(rows, headers=["group", "tasks", "priority", f"period ({unit})",
                                        f"work ({unit})",
                                        f"group's RTA response {'bound ' if bound else ''}"
                                        f"({unit})",
                                        f"margin ({unit})",
                                        "bound within period" if bound else "meets period",
                                        "note"],
                         disable_numparse=True)
        lines.extend("  " + row for row in table.splitlines())
        if p.cross_check:
            held = {True: "every bound within its period", False: "a bound above its period",
                    None: "bounds not all known"}[p.bounds_within_periods]
            lines.append(f"  cross-check over all phases (never the verdict): {p.test}; each "
                         f"response is a bound whatever the clocks' phases: {held}")
        else:
            lines.append(f"  test: {p.test}")
    if result.processors:
        lines.append("group's RTA response: the test's worst case for the group's whole work "
                     "of one period, released with every more urgent group at once (critical "
                     "instant); \"meets period\" of a free-running group: it gets time")
    lines.extend(f"note: {n}" for n in result.notes)
    if cross is not None:
        lines.append(_cross_check_line(cross))
        lines.extend(f"  {_disagreement(d, unit)}" for d in cross.disagreements)
        if cross.bounds_compared:
            lines.append(_bounds_line(cross))
            lines.extend(f"  {_disagreement(d, unit)}" for d in cross.bound_disagreements)
    return "\n".join(lines) + "\n"


def _cross_check_line(cross: CrossCheck) -> str:
    """Whether the response-time test agrees with the exact schedule, in one line."""
    says = {True: "schedulable", False: "NOT schedulable", None: "undecided"}
    scope = " on the preemptive processors" if cross.preemptive_only else ""
    head = f"cross-check: the response-time test{scope} says {says[cross.says]}"
    if not cross.on_processors:
        return head + ("; the exact schedule on processors was not computed (every task on "
                       "a processor of its own): nothing to compare")
    exact = f"the exact schedule (spec §4b, the verdict) says {says[cross.exact]}"
    if cross.agrees is None:
        return f"{head}; {exact}: not compared (a verdict is undecided)"
    if cross.agrees:
        return f"{head}; {exact}: they agree"
    extra = ("" if cross.disagreements else " (the test sees only processor time: waits on "
             "messages, double synchronizations and growing places are the schedule's)")
    return f"{head}; {exact}: they DISAGREE{extra}"


def _bounds_line(cross: CrossCheck) -> str:
    """Whether the bounds over all phases hold in the exact schedule, in one line."""
    n = cross.bounds_compared
    head = (f"cross-check over all phases: {n} unit(s) on non-preemptive processors whose "
            "bound is within the period")
    if cross.bounds_agree:
        return f"{head}: each meets its period in the exact schedule, as its bound says"
    return (f"{head}: {len(cross.bound_disagreements)} miss(es) it in the exact schedule: "
            "the bound DISAGREES with the verdict")


def _disagreement(d: UnitDisagreement, unit: str) -> str:
    test = ("gets processor time" if d.period is None and d.test
            else "gets no processor time" if d.period is None
            else f"{'meets' if d.test else 'misses'} its period ({display_text(d.period)} "
                 f"{unit})")
    return (f"group {d.group} ({', '.join(d.tasks)}) on {d.processor}: the test says it "
            f"{test}; the exact schedule: {d.why}")


def render_latency(result: ChainLatency, unit: str = "ms") -> str:
    """One chain's latency as text: the exact figures (spec §4c), the groups and hops it
    crosses, and the published bounds over any phases beside them.

    Returns
    -------
    str
    """
    f = result.figures
    lines = [f"latency of the chain {' -> '.join(result.chain)} (spec §4c, exact for the "
             "declared phases):"]
    if f.on_processors is not f.processor_per_task:
        lines.append(f"  on its processors: {figures_text(f.on_processors, unit)}")
    lines.append(f"  with a processor per task: {figures_text(f.processor_per_task, unit)}")
    for i, s in enumerate(result.segments):
        if i:
            h = result.hops[i - 1]
            lines.append(f"  asynchronous hop {h.writer} -> {h.reader} ({'; '.join(h.links)})")
        period = f"period {display_text(s.period)} {unit}" if s.period is not None else "no period"
        lines.append(f"  group {s.group} [{', '.join(s.tasks)}] ({period}): {s.start} -> {s.end}")
    for b in result.bounds:
        value = f"{display_text(b.value)} {unit}" if b.value is not None else "not applicable"
        lines.append(f"  bound {OVER_ANY_PHASES} ({b.name}): {value} [{b.formula}; {b.note}]")
    if result.value is None:
        lines.append(f"  latency: undecided ({result.why_undecided})")
    else:
        periods = result.in_periods
        extra = "" if periods is None else (
            f" = {display_text(periods)} sampling period(s) of "
            f"{display_text(result.segments[0].period)} {unit}")
        where = " on its processors" if f.on_processors is not f.processor_per_task else ""
        lines.append(f"  latency (first use{where}): exactly {display_text(result.value)} "
                     f"{unit}{extra}")
    return "\n".join(lines) + "\n"


def render_fix(result: FixResult, name: str = "skeleton") -> str:
    """What :func:`~tegraph.analysis.repair.fix_ports` found, as text for the terminal.

    >>> from tegraph import Skeleton, fix_ports
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2}}})
    >>> print(render_fix(fix_ports(sk), "demo"), end="")
    demo: already live; no port order changed
    """
    if result.status == "already live":
        return f"{name}: already live; no port order changed\n"
    lines = []
    for c in result.deadlocks:
        lines.append(f"{name}: deadlock: token-free circuit " + " -> ".join([*c, c[0]]))
    if result.status == "impossible":
        circuit = " -> ".join([*result.circuit, result.circuit[0]]) if result.circuit else ""
        lines.append(f"{name}: no port order makes it live: the circular wait {circuit} "
                     "holds whatever the order of reads and writes")
        if result.links:
            lines.append("turn one of these links asynchronous (ASYN/ASYN), and give its "
                         "reader a clock in place of the wait (Rules 1 and 3): "
                         + "; ".join(result.links))
        else:
            lines.append("the circuit passes only through threads and task chains: split "
                         "the thread, or reorder the tasks in it")
        return "\n".join(lines) + "\n"
    if result.threads:
        lines.append(f"{name}: no port order makes it live, a thread order does; changed:")
        for t in result.threads:
            lines.append(f"  threads[{t.index}] [{', '.join(t.before)}] -> "
                         f"[{', '.join(t.after)}]: {t.reason}")
    else:
        lines.append(f"{name}: a port order makes it live; changed:")
    for change in result.changes:
        lines.append(f"  {change.task} {change.side} [{', '.join(change.before)}] -> "
                     f"[{', '.join(change.after)}]: {change.reason}")
    lines.append("every other declared port order is kept")
    return "\n".join(lines) + "\n"


def fix_verdict(result: FixResult) -> str:
    """The last line of ``tegraph fix``: live or not, and the exit status."""
    if result.status == "already live":
        return "verdict: already live, nothing to change (exit status 0)"
    if result.live:
        threads = f"{count(len(result.threads), 'thread')} and " if result.threads else ""
        return (f"verdict: live after reordering {threads}"
                f"{count(len(result.changes), 'port list')} (exit status 0)")
    return "verdict: no port order makes it live (exit status 1)"
