"""Text of the results on any event graph or net: cycle time and the state-space baselines."""

from __future__ import annotations

import numpy as np

from maxplus.scalar import exact_text

from ..analysis.cycle_time import CycleTimeResult
from ..analysis.reachability import Reachability
from ..analysis.timed_reachability import TimedExploration
from ._format import count, human_plain

__all__ = ["render_cycle_time", "render_reachability", "render_timed_exploration"]


def render_cycle_time(result: CycleTimeResult) -> str:
    """The human report of ``tegraph cycle-time``."""
    head = f"{result.model} {result.name}" + (f" ({result.source})" if result.source else "")
    lines = [head, f"size:        {result.n_transitions} transitions, {result.n_places} places"]
    if not result.applicable:
        lines.append(f"no period:   {result.reason}")
        if result.reachability is not None:
            lines.append("instead, the deadlock verdict of its reachable markings:")
            lines.extend("  " + line
                         for line in render_reachability(result.reachability, limit=3).splitlines())
            if result.reachability.deadlock is None:
                lines.append("to decide:   raise the budget (`max_states`, `max_seconds`)")
    elif result.token_free_circuit is not None:
        lines.append("DEADLOCK: circuit without token "
                     + " -> ".join([*result.token_free_circuit, result.token_free_circuit[0]])
                     + "; its transitions never fire (Commoner's theorem)")
    elif result.period is None:
        lines.append("period:      none (no circuit: nothing bounds the firing rate)")
    else:
        lines.append(f"period:      {human_plain(result.period)}")
        what = "iterations" if result.model == "SDF graph" else "firings"
        lines.append("throughput:  " + ("unbounded (period 0)" if result.throughput is None
                                        else f"{human_plain(result.throughput)} {what} per time unit"))
        lines.append("critical:    " + _circuit_text(result.critical_circuit, result.place_labels))
        if result.cycle_times is not None:
            lines.append("cycle times differ (the graph is not strongly connected):")
            width = max(len(k) for k in result.cycle_times)
            for k, v in result.cycle_times.items():
                shown = "none (no circuit upstream: an input)" if v is None else human_plain(v)
                lines.append(f"  {k:<{width}}  {shown}")
        check = {True: "verified exactly", False: "FAILED", None: "not run"}
        lines.append(f"certificate: {check[result.certificate_verified]}")
    lines.append("time:        " + ", ".join(f"{k} {v:.3f} s" for k, v in result.seconds.items()))
    lines.extend(f"note: {n}" for n in result.notes)
    return "\n".join(lines) + "\n"


def _circuit_text(events: list[str], places: list[str]) -> str:
    if not events:
        return "-"
    parts = []
    for e, p in zip(events, places):
        parts.append(f"{e} -[{p}]->")
    return " ".join(parts) + f" {events[0]}"


def render_reachability(result: Reachability, limit: int = 10) -> str:
    """The untimed reachability baseline: counts, verdict, the first ``limit`` dead markings."""
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
    return "\n".join(lines)


def render_timed_exploration(result: TimedExploration) -> str:
    """The timed exploration (ORCCAD §5): how it ended, each group's figures, overruns."""
    u = result.unit
    if result.ended_by == "repeat":
        head = f"complete: the whole state repeated at time {exact_text(result.time_reached)} {u}"
    elif result.complete:
        head = f"complete: nothing fires after time {exact_text(result.time_reached)} {u}"
    else:
        why = {"states": f"budget {result.max_states:,} states reached",
               "time": "time budget reached", "interrupted": "interrupted"}
        head = f"inconclusive ({why.get(result.stopped_by or '', 'stopped')})"
    lines = [(f"{result.name}: timed exploration, {result.states:,} state"
              f"{'s' * (result.states != 1)}, {result.firings:,} firing"
              f"{'s' * (result.firings != 1)}; {head}")]
    for g in result.groups:
        if g.stalled_at is not None:
            lines.append(f"  group {g.index} ({', '.join(g.tasks)}): fires without end at "
                         f"time {exact_text(g.stalled_at)} {u} (zero-duration tasks)")
        elif g.stuck_after is not None:
            lines.append(f"  group {g.index} ({', '.join(g.tasks)}): deadlock, nothing "
                         f"fires after time {exact_text(g.stuck_after)} {u}")
        elif g.period is None:
            lines.append(f"  group {g.index} ({', '.join(g.tasks)}): no repeated state")
        else:
            k, c = g.transient  # type: ignore[misc]
            lines.append(f"  group {g.index} ({', '.join(g.tasks)}): period "
                         f"{exact_text(g.period)} {u}, transient k={k}, cyclicity {c}")
    for t in result.tasks.values():
        if t.overrun_at is not None:
            lines.append(f"  {t.name} overruns at activation {t.overrun_at}")
        elif not t.decided:
            lines.append(f"  {t.name}: overrun undecided")
    return "\n".join(lines)
