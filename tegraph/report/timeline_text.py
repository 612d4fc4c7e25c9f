"""Text timing diagram of the schedule on processors (ORCCAD Figure 17), lane per processor."""

from __future__ import annotations

import math
from fractions import Fraction

from maxplus.scalar import display_text

from ..design.timeline import Timeline, TimelineChain
from ._format import count
from .chains_text import CHAIN_FIGURES_MEANING, figures_text

__all__ = ["render_timeline"]

_SYMBOLS = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789"
_LISTED = 200
"""Intervals listed exactly (the lanes and the -o drawing show them all)."""


def render_timeline(timeline: Timeline, width: int = 96) -> str:
    """The timing diagram as text: a lane per processor, the exact order of execution,
    the proof and the verdict (its last line).

    In a lane each task's letter marks when its jobs run, ``.`` idle; a row per
    clock marks its ticks ``^`` (``!`` a tick at which a task overruns). Columns
    are exact when every time is a multiple of a step that fits ``width``
    columns; otherwise each column stands for an interval (``+``: several jobs).

    Returns
    -------
    str

    Examples
    --------
    >>> from tegraph import Skeleton, simulate_timeline
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2},
    ...                                    "B": {"duration": 2, "period": 4}}})
    >>> print("\\n".join(render_timeline(simulate_timeline(sk)).splitlines()[1:4]))
    default |ABABABAB| A = A (prio 2), B = B (prio 1)
    A.clock |^ ^ ^ ^ |
    B.clock |^   ^   |
    """
    tl, u, H = timeline, timeline.unit, timeline.horizon
    exact, columns = _columns(tl, width)
    col = (H - tl.start) / columns
    used = [c for c in tl.ticks if any(tl.clocks[t] == c for t in tl.tasks)]
    label = max(len(x) for x in [*tl.processors, *used])
    lines = [f"timeline {tl.name} on its processors: {display_text(tl.start)} to "
             f"{display_text(H)} {u}, one column = "
             f"{display_text(col)} {u}" + ("" if exact else " (approximate drawing)")]
    lines += _lanes(tl, columns, label)
    lines += _clock_rows(tl, used, columns, label)
    lines += _chain_rows(tl, columns, label)
    lines.append("legend: a letter: that task's job runs (key after each lane); . idle; "
                 "^ clock tick; ! a tick at which a task overruns"
                 + ("; chain rows: s its sample, w a write, r a read, o its output (the "
                    "worst data path)" if any(c.figures.worst for c in tl.chains) else "")
                 + ("" if exact else "; + several jobs within the column"))
    lines.append("")
    lines += _order_of_execution(tl)
    lines.append("")
    lines += _blocking(tl)
    lines += _chains(tl)
    lines += _findings(tl)
    lines.append(f"method: {tl.schedule.method}")
    lines.append(_verdict(tl))
    return "\n".join(lines) + "\n"


def _columns(tl: Timeline, width: int) -> tuple[bool, int]:
    """Whether the drawing is exact, and its number of columns: exact when every time
    drawn is a multiple of a step of which the horizon holds at most ``width``."""
    a = tl.start
    times = {Fraction(0), tl.horizon - a} | {x - a for i in tl.visible for x in (i.start, i.end)}
    times |= {x - a for ts in tl.ticks.values() for x in ts if a <= x <= tl.horizon}
    step = _gcd_all(times)
    exact = (tl.horizon - a) / step <= width
    return exact, int((tl.horizon - a) / step) if exact else width


def _lanes(tl: Timeline, columns: int, label: int) -> list[str]:
    """A row per processor: its jobs' letters (one per task, the same in every lane)
    and the key of its letters, by priority."""
    col = (tl.horizon - tl.start) / columns
    symbol = {t: _SYMBOLS[n] if n < len(_SYMBOLS) else "*" for n, t in enumerate(tl.tasks)}
    lanes: dict[str, list] = {p: [] for p in tl.processors}
    for i in tl.visible:
        lanes[i.processor].append(i)
    lines = []
    for proc in tl.schedule.platform.processors:
        row = ["."] * columns
        for i in lanes[proc.name]:
            _paint(row, i.start - tl.start, i.end - tl.start, col, symbol[i.task])
        kind = "" if proc.preemptive else "non-preemptive; "
        lines.append(f"{proc.name:<{label}} |{''.join(row)}| "
                     f"{kind}{_lane_key(tl, proc.tasks, symbol)}")
    return lines


def _lane_key(tl: Timeline, tasks: tuple[str, ...], symbol: dict[str, str]) -> str:
    """The key of a lane: each task's letter and priority, highest first; ``*`` counts
    the tasks past the letters."""
    priorities = tl.priorities
    order = sorted(tasks, key=lambda t: -priorities[t])
    named = [t for t in order if symbol[t] != "*"]
    key = ", ".join(f"{symbol[t]} = {t} (prio {priorities[t]})" for t in named)
    if len(named) < len(order):
        key += f", * = the {len(order) - len(named):,} others"
    return key


def _clock_rows(tl: Timeline, used: list[str], columns: int, label: int) -> list[str]:
    """A row per clock that activates a task: ``^`` its ticks, ``!`` a tick at which one
    of its tasks overruns (drawn even at the horizon)."""
    H, a = tl.horizon, tl.start
    col = (H - a) / columns
    late: dict[str | None, set[Fraction]] = {}  # by clock (an overrunning task has one)
    for t, k in tl.overrun_at.items():
        if k is not None:
            late.setdefault(tl.clocks[t], set()).add(tl.overrun_ticks[t])
    lines = []
    for c in used:
        row = [" "] * columns
        for x in tl.ticks[c]:  # a tick at the end is drawn when it is an overrun's
            if a <= x and (x < H or x in late.get(c, ())):
                row[min(int((x - a) / col), columns - 1)] = "!" if x in late.get(c, ()) else "^"
        lines.append(f"{c:<{label}} |{''.join(row)}|")
    return lines


_MARK = {0: "s", 1: "w", 2: "r"}


def _chain_rows(tl: Timeline, columns: int, label: int) -> list[str]:
    """A row per chain with a worst data path: ``s`` its sample, ``w`` and ``r`` the
    writes and reads it passes, ``o`` its output (a later mark wins a shared column)."""
    col = tl.horizon / columns
    lines = []
    for n, c in enumerate(tl.chains, 1):
        steps = c.figures.worst
        if not steps:
            continue
        row = [" "] * columns
        for i, step in enumerate(steps):
            if step.at <= tl.horizon:
                mark = "o" if i == len(steps) - 1 else _MARK[0 if i == 0 else 2 - i % 2]
                row[min(int(step.at / col), columns - 1)] = mark
        lines.append(f"{f'chain {n}':<{label}} |{''.join(row)}|")
    return lines


def _chains(tl: Timeline) -> list[str]:
    """Each chain's figures on processors (spec §4c) and its worst data path, exactly."""
    if not tl.chains:
        return []
    u = tl.unit
    lines = []
    for n, c in enumerate(tl.chains, 1):
        lines.append(f"chain {n}, {' -> '.join(c.tasks)}, on its processors: "
                     f"{figures_text(c.figures, u)}")
        if c.figures.worst:
            lines.append("  its worst data path (the largest first use): " + _path(c, u))
    lines.append(CHAIN_FIGURES_MEANING)
    lines.append("")
    return lines


def _path(c: TimelineChain, unit: str) -> str:
    steps = c.figures.worst
    words = []
    for i, step in enumerate(steps):
        what = ("samples" if i == 0 else "posts" if i == len(steps) - 1
                else "writes" if i % 2 else "reads")
        words.append(f"{step.task}#{step.k} {what} at {display_text(step.at)} {unit} "
                     f"({step.what})")
    return ", ".join(words)


def _order_of_execution(tl: Timeline) -> list[str]:
    lines = ["order of execution (exact; T#k: activation k of T):"]
    done: dict[tuple[str, int], Fraction] = {}
    listed = 0
    lanes = _by_processor(tl)
    for proc in tl.processors:
        mine = lanes[proc]
        if len(tl.processors) > 1:
            lines.append(f"  processor {proc}:")
        for i in mine:
            key = (i.task, i.k)
            before = done.get(key, Fraction(0))
            done[key] = before + (i.end - i.start)
            if listed >= _LISTED or i.end <= tl.start:  # before the window: counted only
                continue
            listed += 1
            how = "resumes; " if before else ""
            if done[key] == tl.durations[i.task]:
                how += "ends"
            else:
                how += "preempted" if i.end < tl.horizon else "still running"
            lines.append(f"  {display_text(i.start):>8} - {display_text(i.end):<8} "
                         f"{i.task}#{i.k}  {how}")
    in_window = len(tl.visible)
    if listed < in_window:
        lines.append(f"  ... and {in_window - listed:,} more intervals up to "
                     f"{display_text(tl.horizon)} {tl.unit} (in the lanes and the -o drawing)")
    return lines


MAX_BLOCKING_SHOWN = 10
"""Blockings listed one by one (the longest of each task is always named)."""


def _blocking(tl: Timeline) -> list[str]:
    """Each job blocked by a less urgent one on a non-preemptive processor (§4d)."""
    if not tl.blocking:
        return []
    u = tl.unit
    lines = ["blocking on non-preemptive processors (§4d; a job waits for a less urgent "
             "job that holds the processor):"]
    for b in tl.blocking[:MAX_BLOCKING_SHOWN]:
        lines.append(f"  {b.task}#{b.k} on {b.processor}: {display_text(b.start)} - "
                     f"{display_text(b.end)} {u} ({display_text(b.length)} {u}), "
                     f"by {b.by}#{b.by_k}")
    if len(tl.blocking) > MAX_BLOCKING_SHOWN:
        lines.append(f"  ... {len(tl.blocking) - MAX_BLOCKING_SHOWN:,} more")
    worst: dict[str, Fraction] = {}
    for b in tl.blocking:
        worst[b.task] = max(worst.get(b.task, Fraction(0)), b.length)
    lines.append("  longest drawn: " + ", ".join(
        f"{t} {display_text(x)} {u}" for t, x in worst.items()))
    lines.append("")
    return lines


def _by_processor(tl: Timeline) -> dict[str, list]:
    lanes: dict[str, list] = {p: [] for p in tl.processors}
    for i in tl.intervals:
        lanes[i.processor].append(i)
    return lanes


def _findings(tl: Timeline) -> list[str]:
    """The proof: each part's regime, then what makes the skeleton not schedulable."""
    u, s = tl.unit, tl.schedule
    lines = []
    for r in s.regimes:
        on = ", ".join(r["tasks"][:4]) + (" ..." if len(r["tasks"]) > 4 else "")
        if r["start"] is None:
            hyper = tl.hyperperiods.get(r["tasks"][0])
            lines.append(f"{on}: no periodic regime within the budget"
                         + (f" (their clocks' hyperperiod is {display_text(hyper)} {u})"
                            if hyper is not None else ""))
        elif r["length"] is None:
            lines.append(f"{on}: nothing happens after {display_text(r['start'])} {u}")
        else:
            how = ("decided by a theorem, the critical instant (see the method): only the "
                   "start of the schedule is drawn" if r["tasks"][0] in tl.unsimulated
                   else "proven: the whole state repeats")
            lines.append(f"{on}: periodic from {display_text(r['start'])} {u}, one regime every "
                         f"{display_text(r['length'])} {u} ({how})")
    for d in tl.deadlocks:
        lines.append("DEADLOCK: token-free circuit " + " -> ".join([*d.events, d.events[0]])
                     + f" (tasks {', '.join(d.tasks)}): these events wait for each other and "
                     "never fire")
    for st in tl.stuck:
        lines.append(f"STUCK: {st.task} waits at {st.event} for ever, from "
                     f"{display_text(st.since)} {u}")
    jobs = {(j.task, j.index): j for j in tl.jobs}
    # The one order of every command: earliest first, then file order.
    for p in s.problems:
        if p.kind == "starved":
            since = "" if p.at is None else f" (released at {display_text(p.at)} {u})"
            lines.append(f"STARVED: a job of {p.task}{since} never receives its duration on "
                         f"processor {s.platform.processor_of[p.task]}")
            continue
        t, k, at = p.task, p.k, tl.overrun_ticks[p.task]
        assert k is not None  # an overrun has its activation
        job = jobs.get((t, k - 1))
        if job is None or job.finish is None:
            end = f"activation {k - 1} has not ended"
            end += (" (past the end of the drawing)" if at > tl.horizon else "")
        elif tl.ends_with_computation[t]:
            end = f"activation {k - 1} runs until {display_text(job.finish)} {u}"
        elif job.finish > at:
            end = f"activation {k - 1} computes until {display_text(job.finish)} {u}"
        else:
            end = (f"activation {k - 1} has not ended (computed by {display_text(job.finish)} "
                   f"{u}; a write still waits)")
        lines.append(f"OVERRUN: {t} overruns at activation {k}: its clock {tl.clocks[t]} ticks "
                     f"at {display_text(at)} {u} while {end}")
    for t in s.stopped:
        f = s.tasks[t]
        since = (f"after activation {f.stopped_after}" if f.stopped_after
                 else "from the start (no job at all)")
        why = (f"it waits for {', '.join(f.waits_for)}, starved" if f.waits_for
               else "it waits for events that never fire again")
        lines.append(f"STOPPED: {t} never runs again {since}: {why}")
    for g in s.unbounded:
        per = ("infinitely many at once" if g.per_regime is None
               else f"+{g.per_regime} per regime")
        lines.append(f"GROWING: place {g.src} -> {g.dst} ({g.kind}): {per}")
    lines += [f"note: {n}" for n in tl.notes]
    return lines


def _verdict(tl: Timeline) -> str:
    """The last line: the proof's verdict and the exit status."""
    s, u = tl.schedule, tl.unit
    status = f" (exit status {tl.exit_status})"
    if s.schedulable is True:
        return ("verdict: schedulable on its processors (proven): no overrun, no starved "
                f"job, no growing place{status}")
    if s.schedulable is None:
        why = s.why_undecided or ""
        hyper = [h for h in tl.hyperperiods.values() if h is not None]
        if hyper and "hyperperiod" not in why:
            why += "; the clocks' hyperperiod is " + " and ".join(
                f"{display_text(h)} {u}" for h in hyper)
        why = why.removeprefix("undecided ")  # the engine's reason begins "undecided within"
        more = "" if "within the budget" not in why else " (raise `max_events` to look further)"
        return f"verdict: UNDECIDED {why}{more}{status}"
    found = []
    if tl.deadlocks:
        found.append(f"DEADLOCK ({count(len(tl.deadlocks), 'token-free circuit')}; "
                     f"{count(len(tl.dead_tasks), 'task')} in groups that are not live)")
    # The overruns and the starved tasks, the kind of the earliest problem first.
    kinds = []
    first = [p for p in s.problems if p.kind == "overrun"]  # earliest first, file order
    if first:
        x, t = tl.overrun_ticks[first[0].task], first[0].task
        kinds.append((s.problems.index(first[0]),
                      f"{t} overruns first, at activation {tl.overrun_at[t]} "
                      f"({display_text(x)} {u})" + (f", {len(first) - 1} more task(s) overrun"
                                                     if len(first) > 1 else "")))
    if s.starved:
        starved = [i for i, p in enumerate(s.problems) if p.kind == "starved"]
        text = count(len(s.starved), "starved task")
        if starved and s.problems[starved[0]].at is not None:
            p = s.problems[starved[0]]
            text += f" ({p.task} first, its job released at {display_text(p.at)} {u})"
        kinds.append((starved[0] if starved else len(s.problems), text))
    found += [text for _, text in sorted(kinds, key=lambda x: x[0])]
    if s.unbounded:
        found.append(f"{count(len(s.unbounded), 'growing place')}")
    return f"verdict: NOT schedulable on its processors: {'; '.join(found)}{status}"


def _paint(row: list[str], a: Fraction, b: Fraction, col: Fraction, ch: str) -> None:
    """Fill the columns that meet [a, b) (at least the one holding a); ``+`` where shared."""
    start = int(a / col)
    stop = max(math.ceil(b / col), start + 1)
    for k in range(start, min(stop, len(row))):
        row[k] = ch if row[k] in (".", ch) else "+"


def _gcd_all(values: set[Fraction]) -> Fraction:
    """The largest step of which every value is a multiple (exact)."""
    num, den = 0, 1
    for v in values:
        num, den = math.gcd(num * v.denominator, v.numerator * den), den * v.denominator
        g = math.gcd(num, den)
        num, den = num // g, den // g
    return Fraction(num, den) if num else Fraction(1)
