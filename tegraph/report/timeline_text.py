"""Text timing diagram of a fixed-priority simulation (ORCCAD Figure 17)."""

from __future__ import annotations

import math
from fractions import Fraction

from maxplus.scalar import display_text

from ..design.timeline import Timeline
from ._format import count

__all__ = ["render_timeline"]


def render_timeline(timeline: Timeline, width: int = 96) -> str:
    """The timing diagram as text: one row per task, then the exact order of execution.

    ``#`` the task computes, ``X`` a late job computes, ``-`` released and
    waiting (for the processor or for data); one row per clock marks its
    ticks with ``^``.
    Columns are exact when every time is a multiple of a step that fits
    ``width`` columns; otherwise each column stands for an interval.

    Returns
    -------
    str

    Examples
    --------
    >>> from tegraph import Skeleton, simulate_timeline
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2},
    ...                                    "B": {"duration": 2, "period": 4}}})
    >>> print("\\n".join(render_timeline(simulate_timeline(sk)).splitlines()[1:5]))
    A       |# # | prio 2
    B       |-#-#| prio 1
    A.clock |^ ^ |
    B.clock |^   |
    """
    u = timeline.unit
    H = timeline.horizon
    times = {Fraction(0), H}
    for j in timeline.jobs:
        times.add(j.release)
        times.update(x for seg in j.segments for x in seg)
        if j.finish is not None:
            times.add(j.finish)
    for ts in timeline.ticks.values():
        times.update(ts)
    step = _gcd_all(times)
    exact = H / step <= width
    columns = int(H / step) if exact else width
    col = H / columns
    shown = [c for c in timeline.ticks if any(timeline.clocks[t] == c for t in timeline.tasks)]
    label = max(len(t) for t in [*timeline.tasks, *shown])
    lines = [f"timeline {timeline.name}: 0 to {display_text(H)} {u}, one column = "
             f"{display_text(col)} {u}" + ("" if exact else " (approximate drawing)")]
    for t in timeline.tasks:
        row = [" "] * columns
        for j in (j for j in timeline.jobs if j.task == t):
            _paint(row, j.release, j.finish if j.finish is not None else H, col, "-", keep="#X^")
            for a, b in j.segments:
                _paint(row, a, b, col, "X" if j.late else "#")
        lines.append(f"{t:<{label}} |{''.join(row)}| prio {timeline.priorities[t]}")
    for c in shown:
        row = [" "] * columns
        for x in timeline.ticks[c]:
            row[min(int(x / col), columns - 1)] = "^"
        lines.append(f"{c:<{label}} |{''.join(row)}|")
    lines.append(_LEGEND + ("" if exact else " (a column shows # or X when the task runs at some "
                                              "time within it)"))
    lines.append("")
    lines.append("order of execution (exact):")
    processors = list(dict.fromkeys(timeline.processors[t] for t in timeline.tasks))
    for p in processors:
        if len(processors) > 1:
            lines.append(f"  processor {p or '(default)'}:")
        for task, a, b in timeline.order_of_execution(p):
            lines.append(f"  {display_text(a):>8} - {display_text(b):<8} {task}")
    lines.append("")
    for d in timeline.deadlocks:
        lines.append("DEADLOCK: token-free circuit " + " -> ".join([*d.events, d.events[0]])
                     + f" (tasks {', '.join(d.tasks)}): these events wait for each other and "
                     "never fire")
    if timeline.dead_tasks:
        lines.append(f"  not live: {', '.join(timeline.dead_tasks)} (a clock ticking at a task "
                     "blocked there is this deadlock, not an overrun)")
    for j in timeline.late_jobs:
        clock = timeline.pacing.get(j.task)
        whose = (f"its clock {clock}" if timeline.clocks[j.task] == clock
                 else f"its group's clock {clock}")
        end = (f"has not ended by the end of the simulation ({display_text(H)} {u})"
               if j.finish is None else f"runs until {display_text(j.finish)} {u}")
        lines.append(f"OVERRUN: {j.task} overruns at activation {j.overrun_at}: {whose} ticks "
                     f"at {display_text(j.deadline)} {u} while activation {j.index} {end}")
    lines.append(_verdict(timeline))
    return "\n".join(lines) + "\n"


_LEGEND = ("legend: # runs, - released and waiting (for its processor or a message), "
           "X runs late (it ends after the next tick of its pacing clock: its own, else its "
           "group's), ^ clock tick, "
           "blank idle")


def _verdict(timeline: Timeline) -> str:
    """The last line: what the simulation found, within its horizon, and the exit status."""
    u, H = timeline.unit, display_text(timeline.horizon)
    status = f" (exit status {timeline.exit_status})"
    if timeline.deadlocks:
        late = len(timeline.late_jobs)
        also = f", and {count(late, 'overrun')} elsewhere" if late else ""
        return (f"verdict: DEADLOCK ({count(len(timeline.deadlocks), 'token-free circuit')}; "
                f"{count(len(timeline.dead_tasks), 'task')} in groups that are not live)"
                f"{also}{status}")
    if timeline.late_jobs:
        tasks = list(dict.fromkeys(j.task for j in timeline.late_jobs))
        shown = ", ".join(tasks[:_NAMED]) + (
            f" and {len(tasks) - _NAMED:,} more" if len(tasks) > _NAMED else "")
        return (f"verdict: {count(len(timeline.late_jobs), 'overrun')} before {H} {u}, by "
                f"{shown}{status}")
    if timeline.full_horizon is not None:
        # A cut simulation proves nothing past its end: say so on the verdict line.
        return (f"verdict: every job ends by the next tick of its pacing clock up to {H} {u} "
                f"only (the horizon cut the simulation; the default horizon is "
                f"{display_text(timeline.full_horizon)} {u}: a later overrun is not "
                f"excluded){status}")
    return (f"verdict: every job ends by the next tick of its pacing clock (simulated up to "
            f"{H} {u}){status}")


_NAMED = 5
"""Late tasks named on the verdict line (the OVERRUN lines above name them all)."""


def _paint(row: list[str], a: Fraction, b: Fraction, col: Fraction, ch: str,
           keep: str = "") -> None:
    """Fill the columns that meet [a, b) (at least the one holding a)."""
    start = int(a / col)
    stop = max(math.ceil(b / col), start + 1)
    for k in range(start, min(stop, len(row))):
        if row[k] not in keep:
            row[k] = ch


def _gcd_all(values: set[Fraction]) -> Fraction:
    """The largest step of which every value is a multiple (exact)."""
    num, den = 0, 1
    for v in values:
        num, den = math.gcd(num * v.denominator, v.numerator * den), den * v.denominator
        g = math.gcd(num, den)
        num, den = num // g, den // g
    return Fraction(num, den) if num else Fraction(1)
