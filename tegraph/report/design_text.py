"""Text of the design results of ORCCAD §6: rules, schedulability, latency, port repair."""

from __future__ import annotations

from tabulate import tabulate

from maxplus.scalar import display_text

from ..analysis.repair import FixResult
from ..design.latency import OVER_ANY_PHASES, ChainLatency
from ..design.rules import RuleFinding
from ..design.schedulability import PAPER_TEST, RTA_TEST, Schedulability
from ..design.section import DesignSection
from ._format import count, number
from .chains_text import figures_text

__all__ = [
    "fix_verdict",
    "render_design",
    "render_fix",
    "render_latency",
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

    The exit status it names is the command's (:attr:`DesignSection.exit_status`): 1
    when a rule is not followed (an error or a warning) or a processor fails its
    schedulability test or has a test its budget left undecided.
    """
    findings, sched, unit = section.rules, section.schedulability, section.unit
    text = render_rules(findings) + "\n" + render_schedulability(sched, unit)
    for r in section.latency:
        text += "\n" + render_latency(r, unit)
    counts = [(s, sum(f.severity == s for f in findings)) for s in ("error", "warning")]
    broken = ", ".join(count(n, f"design-rule {s}") for s, n in counts if n)
    fails = [("default processor" if p.processor is None else f"processor {p.processor}")
             for p in sched.processors if p.schedulable is False]
    problems = ([broken] if broken else []) + [f"{name} not schedulable" for name in fails]
    undecided = ", ".join(", ".join(u.tasks) for u in sched.undecided)
    if undecided:  # no proof either way: it counts against the design, as a failure would
        problems.append(f"schedulability undecided (budget) for {undecided}")
    if problems:
        verdict = "; ".join(problems)
    else:
        sched_text = ("schedulable" if sched.schedulable
                      else "schedulability not decided (a group is not live)")
        verdict = f"design rules followed, {sched_text}"
    return text + f"\nverdict: {verdict} (exit status {section.exit_status})\n"


def render_schedulability(result: Schedulability, unit: str = "ms") -> str:
    """Threads and the per-processor verdicts as text.

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
        name = "default processor" if p.processor is None else f"processor {p.processor}"
        lines.append(f"schedulability on the {name} (preemptive fixed priorities, "
                     f"{p.priority_source} priorities; larger is more urgent):")
        if p.hyperperiod is not None:
            holds = "holds" if p.condition_holds else "FAILS"
            lines.append(f"  {PAPER_TEST}: T = {display_text(p.hyperperiod)} {unit}, "
                         f"sum = {display_text(p.demand)} {unit}: {holds} (margin "
                         f"{display_text(p.condition_margin)} {unit})")
        rows = []
        for u in p.units:
            verdict = ("undecided" if u.undecided else "-" if u.schedulable is None
                       else ("yes" if u.schedulable else "NO"))
            rows.append([u.group, ", ".join(u.tasks), u.priority, number(u.period),
                         number(u.cost), number(u.response_time), number(u.margin), verdict,
                         u.note])
        table = tabulate(rows, headers=["group", "tasks", "priority", f"period ({unit})",
                                        f"work ({unit})", f"response ({unit})",
                                        f"margin ({unit})", "meets period", "note"],
                         disable_numparse=True)
        lines.extend("  " + row for row in table.splitlines())
        lines.append(f"  test: {RTA_TEST}")
    lines.extend(f"note: {n}" for n in result.notes)
    return "\n".join(lines) + "\n"


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
    """What :func:`fix_ports` found, as text for the terminal.

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
