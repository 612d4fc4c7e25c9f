"""Text of the results on any event graph or net: cycle time and the state-space baselines."""

from __future__ import annotations

from fractions import Fraction
from typing import TYPE_CHECKING

import numpy as np

from maxplus.scalar import display_text

if TYPE_CHECKING:  # annotations only: the analyze report imports ratio_text, not the baselines
    from ..analysis.baselines.reachability import Reachability
    from ..analysis.baselines.timed_reachability import TimedExploration, TimedGroup
    from ..analysis.cycle_time import CycleTimeResult
from ._format import count, human, number

__all__ = ["render_cycle_time", "render_reachability", "render_timed_exploration"]


def render_cycle_time(result: CycleTimeResult) -> str:
    """The human report of ``tegraph cycle-time``."""
    head = f"{result.model} {result.name}" + (f" ({result.source})" if result.source else "")
    lines = [head, f"size:        {result.n_transitions} transitions, {result.n_places} places"]
    if not result.applicable:
        lines += _no_period_lines(result)
    elif result.token_free_circuit is not None:
        lines.append("DEADLOCK: circuit without token "
                     + " -> ".join([*result.token_free_circuit, result.token_free_circuit[0]])
                     + "; its transitions never fire (Commoner's theorem)")
    elif result.period is None:
        lines.append("period:      none (no circuit: nothing bounds the firing rate)")
    else:
        lines += _period_lines(result)
    lines.append("time:        " + ", ".join(f"{k} {v:.3f} s" for k, v in result.seconds.items()))
    lines.extend(f"note: {n}" for n in result.notes)
    lines.append(_cycle_time_verdict(result))
    return "\n".join(lines) + "\n"


def _no_period_lines(result: CycleTimeResult) -> list[str]:
    """Why a net has no period, and instead the deadlock verdict of its reachable markings."""
    lines = [f"no period:   {result.reason}"]
    if result.reachability is not None:
        lines.append("instead, the deadlock verdict of its reachable markings:")
        lines.extend("  " + line for line in render_reachability(
            result.reachability, limit=3, closing=False).splitlines())
        if result.reachability.deadlock is None:
            lines.append("to decide:   raise the budget (`max_states`, `max_seconds`)")
    return lines


def _period_lines(result: CycleTimeResult) -> list[str]:
    """The period with its proof: throughput, critical circuit and its ratio, each part's
    period, the cycle times when they differ, and the certificate's check."""
    u = result.unit
    what = "group" if result.model == "skeleton" else "part"
    several = (f" (the slowest of {len(result.parts)} {what}s, which run at their own "
               f"periods below)" if result.parts else "")
    lines = [f"period:      {human(result.period, u)}{several}"]
    what = "iterations" if result.model == "SDF graph" else "firings"
    per = "time unit" if u == "time units" else u
    lines.append("throughput:  " + ("unbounded (period 0)" if result.throughput is None
                                    else f"{number(result.throughput)} {what} per {per}"))
    lines.append("critical:    " + _circuit_text(result.critical_circuit, result.place_labels))
    lines.append("why:         " + ratio_text(result.critical_holdings,
                                              result.critical_tokens, u))
    for k, part in enumerate(result.parts):
        name = "group" if result.model == "skeleton" else "part"
        lines.append(f"  {name} {k} [{part.label}]: period {human(part.period, u)}: "
                     + " -> ".join([*part.critical_circuit, part.critical_circuit[0]])
                     + ": " + ratio_text(part.critical_holdings, part.critical_tokens, u))
    lines += _cycle_times_lines(result)
    check = {True: "verified exactly", False: "FAILED", None: "not run"}
    lines.append(f"certificate: {check[result.certificate_verified]}")
    return lines


def _cycle_times_lines(result: CycleTimeResult) -> list[str]:
    """Each transition's cycle time, when they differ (none: nothing to list)."""
    if result.cycle_times is None:
        return []
    lines = ["cycle times differ (the graph is not strongly connected):"]
    width = max(len(k) for k in result.cycle_times)
    for k, v in result.cycle_times.items():
        shown = "none (no circuit upstream: an input)" if v is None else human(v, result.unit)
        lines.append(f"  {k:<{width}}  {shown}")
    return lines


def _cycle_time_verdict(result: CycleTimeResult) -> str:
    status = f"(exit status {result.exit_status})"
    if not result.applicable:
        found = ("not searched" if result.reachability is None
                 else result.reachability.verdict())
        return f"verdict: no period (not a marked graph); reachable markings: {found} {status}"
    if result.token_free_circuit is not None:
        return f"verdict: DEADLOCK: a circuit without token never fires {status}"
    if result.period is None:
        return f"verdict: no period: the graph has no circuit {status}"
    check = {True: "certificate verified", False: "certificate FAILED",
             None: "certificate not checked"}[result.certificate_verified]
    return f"verdict: period {human(result.period, result.unit)}, {check} {status}"


def ratio_text(holdings: list[Fraction], tokens: int | None, unit: str) -> str:
    """``(2 + 5/3 + 3) ms over 2 tokens = 10/3 ms``: a circuit's ratio, term by term.

    Places holding 0 are left out of the sum.

    >>> ratio_text([Fraction(2), Fraction(0), Fraction(5, 3), Fraction(3)], 2, "ms")
    '(2 + 5/3 + 3) ms over 2 tokens = 10/3 ms (≈3.33333)'
    """
    if not tokens:
        return "-"
    terms = [h for h in holdings if h] or [Fraction(0)]
    held = (str(display_text(terms[0])) if len(terms) == 1
            else "(" + " + ".join(str(display_text(h)) for h in terms) + ")")
    ratio = sum(terms, Fraction(0)) / tokens
    return f"{held} {unit} over {count(tokens, 'token')} = {human(ratio, unit)}"


def _circuit_text(events: list[str], places: list[str]) -> str:
    if not events:
        return "-"
    parts = []
    for e, p in zip(events, places):
        parts.append(f"{e} -[{p}]->")
    return " ".join(parts) + f" {events[0]}"


def render_reachability(result: Reachability, limit: int = 10, closing: bool = True) -> str:
    """The untimed reachability baseline: counts, verdict, the first ``limit`` dead markings.

    ``closing`` ends the text with the verdict again (a long list of dead
    markings pushes the first one out of sight).
    """
    how = " (each group alone, places bounded to m + 1 tokens)" if result.bounded else ""
    head = (f"{result.net.name}: untimed reachability, {count(result.states, 'state')}, "
            f"{count(result.edges, 'edge')}{how}")
    lines = [head, result.verdict()]
    names = result.place_names()
    for d in result.dead[:limit]:
        who = ""
        if d.group is not None and result.groups is not None:
            who = f"group {d.group} ({', '.join(result.groups[d.group])}) "
        seq = [result.net.transitions[t] for t in d.firing_sequence]
        lines.append(f"  {who}stuck after {len(seq)} firing{'s' * (len(seq) != 1)}"
                     + (": " + " ".join(seq) if seq else ""))
        marked = [f"{names[p]}: {int(d.marking[p])}" for p in np.flatnonzero(d.marking)]
        lines.append("    marked places: " + (", ".join(marked) or "none"))
    if len(result.dead) > limit:
        lines.append(f"  ... and {len(result.dead) - limit} more (the JSON report lists them all)")
    if closing:
        lines.append(f"verdict: {result.verdict()} (exit status {result.exit_status})")
    return "\n".join(lines)


def render_timed_exploration(result: TimedExploration) -> str:
    """The timed exploration (ORCCAD §5): how it ended, each group's figures, overruns."""
    lines = [(f"{result.name}: timed exploration, {result.states:,} state"
              f"{'s' * (result.states != 1)}, {result.firings:,} firing"
              f"{'s' * (result.firings != 1)}; {_exploration_end(result)}")]
    lines += [_group_line(g, result.unit) for g in result.groups]
    for t in result.tasks.values():
        if t.overrun_at is not None:
            lines.append(f"  {t.name} overruns at activation {t.overrun_at}")
        elif not t.decided:
            lines.append(f"  {t.name}: overrun undecided")
    lines.append(f"verdict: {_exploration_found(result)} (exit status {result.exit_status})")
    return "\n".join(lines)


def _exploration_end(result: TimedExploration) -> str:
    """How the exploration ended: complete (a repeat, or nothing left to fire) or why not."""
    u = result.unit
    if result.ended_by == "repeat":
        return f"complete: the whole state repeated at time {display_text(result.time_reached)} {u}"
    if result.complete:
        return f"complete: nothing fires after time {display_text(result.time_reached)} {u}"
    why = {"states": f"budget {result.max_states:,} states reached",
           "time": "time budget reached", "interrupted": "interrupted"}
    return f"inconclusive ({why.get(result.stopped_by or '', 'stopped')})"


def _group_line(g: TimedGroup, u: str) -> str:
    """A group's figures: its period and transient, or what kept it from having one."""
    tasks = ", ".join(g.tasks)
    if g.stalled_at is not None:
        return (f"  group {g.index} ({tasks}): fires without end at "
                f"time {display_text(g.stalled_at)} {u} (zero-duration tasks)")
    if g.stuck_after is not None:
        return (f"  group {g.index} ({tasks}): deadlock, nothing "
                f"fires after time {display_text(g.stuck_after)} {u}")
    if g.period is None:
        return f"  group {g.index} ({tasks}): no repeated state"
    # Type: a group with a period has its transient.
    k, c = g.transient  # type: ignore[misc]
    return (f"  group {g.index} ({tasks}): period "
            f"{display_text(g.period)} {u}, transient k={k}, cyclicity {c}")


def _exploration_found(result: TimedExploration) -> str:
    """The verdict's findings: the first deadlock, overrun and endless instant, each with
    how many more; else whether the search was complete."""
    late = [t for t in result.tasks.values() if t.overrun_at is not None]
    dead = [g for g in result.groups if g.stuck_events is not None]
    stalled = [g for g in result.groups if g.stalled_at is not None]
    found_parts = []
    if dead:
        found_parts.append(f"deadlock in group {dead[0].index} ({', '.join(dead[0].tasks)})"
                           + _more_groups(dead))
    if late:
        found_parts.append(f"{late[0].name} overruns at activation {late[0].overrun_at}"
                           + (f" and {len(late) - 1:,} more" if len(late) > 1 else ""))
    if stalled:
        found_parts.append(f"group {stalled[0].index} fires without end at time "
                           f"{display_text(stalled[0].stalled_at)} {result.unit} "
                           "(zero-duration tasks)" + _more_groups(stalled))
    if found_parts:
        return "; ".join(found_parts)
    if result.complete:
        return "no overrun (every group reached a repeated state or stopped)"
    return "inconclusive: no overrun found before the budget ran out"


def _more_groups(groups: list[TimedGroup]) -> str:
    """`` and N more group(s)`` past the first of ``groups``, or nothing."""
    return f" and {count(len(groups) - 1, 'more group')}" if len(groups) > 1 else ""
