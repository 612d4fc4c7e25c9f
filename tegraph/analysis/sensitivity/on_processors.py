"""Sensitivity on the processors (spec §4b): the scaling factor and margins, exact.

Each figure is one line of parameters (all varied durations times one
factor α, or one parameter alone): :func:`solve_line` finds the interval of
the line holding the nominal point where the skeleton is live and consistent
(§4, the per-task answer, an upper bound) and schedulable on its processors
(§4b), by walking its parts (:mod:`.parts`) interval by interval
of constant schedule order (:mod:`.walk`). :func:`scaling_on` and
:func:`margin_on` turn the answer into the report's :class:`Scaling` and
:class:`Margin`, each end checked with ``analyze_skeleton(processors=True)``
at it and just beyond. The proof is in ``docs/sensitivity.md`` (*On
processors*).
"""

from __future__ import annotations

import operator
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from functools import partial
from typing import Any

from ...model.skeleton import Skeleton
from .affine import Cut
from .parameters import skeleton_at
from .parts import SCHEDULE, THEOREM, ProcessorLine
from .results import PROCESSORS, Check, Limit, Margin, Scaling
from .walk import MAX_STEPS, Interval, Outcome, per_task_outcome, seek, sweep, walk

__all__ = ["LineAnswer", "margin_on", "method_text", "scaling_on", "solve_line"]

_NUDGE = Fraction(1, 10**9)
_SHORT_EVENTS = 10_000


@dataclass
class LineAnswer:
    """The schedulable values along one line on processors (also live and consistent, §4)."""

    holding: bool | None
    """The start itself: live, consistent and schedulable (None: undecided)."""
    low: Fraction | None = None
    high: Fraction | None = None
    """Ends of the interval holding the start, proven (``high`` None: unbounded)."""
    low_exact: bool = True
    high_exact: bool = True
    low_attained: bool = True
    high_attained: bool = True
    """False: the end is a bound of the interval, not in it (schedulable up to it, not at it)."""
    high_bound: Fraction | None = None
    """When ``high`` is not exact: the per-task end, which the true end does not pass."""
    nearest_below: Fraction | None = None
    nearest_above: Fraction | None = None
    nearest_exact: bool = True
    steps: int = 0
    """Intervals of constant schedule order visited."""
    used: set[str] = field(default_factory=set)
    """How the parts were decided: ``"theorem"`` and/or ``"schedule"``."""
    why: list[str] = field(default_factory=list)
    """Why an end is not exact (undecided points, the step budget)."""
    at_start: Outcome | None = None
    start: Fraction | None = None
    """The nominal point of the line."""
    beyond: dict[str, Outcome] = field(default_factory=dict)
    """"high"/"low"/"below"/"above": the outcome just beyond that end (for the checks)."""


def solve_line(on: ProcessorLine, base: dict[int, Fraction], direction: dict[int, Fraction],
               start: Fraction, per_task: Sequence[Interval], *, constant_parts: bool,
               positive: bool = False, max_steps: int = MAX_STEPS) -> LineAnswer:
    """The interval of the line, holding ``start``, where the skeleton is live, consistent
    and schedulable on its processors; or, when ``start`` is not, the nearest such values.

    Parameters
    ----------
    on : ProcessorLine
    base, direction : dict of int to Fraction
        The line ``θ(t) = base + t·direction`` by parameter index (others nominal).
    start : Fraction
        The nominal point of the line.
    per_task : sequence of (Fraction, Fraction or None)
        The consistent intervals with a processor per task along the same line
        (exact, from :func:`~.line.solve_lines`); the answer lies in them.
    constant_parts : bool
        Also require the parts the line does not move (the scaling factor is
        the whole skeleton's; a margin is its own part's).
    positive : bool
        t = 0 is excluded (a period): the walk down stops above it.
    max_steps : int
        Intervals of constant order visited by each walk before it stops with a bound.

    Returns
    -------
    LineAnswer
    """
    on.used = set()
    parts = on.moving(direction)
    if constant_parts:
        fixed = _fixed_refusal(on, parts)
        if fixed is not None:
            return fixed
    firsts: dict[int, Outcome] = {}
    combined = _combined(on, base, direction, parts, per_task, positive, firsts)
    first = combined(start, 0)
    answer = LineAnswer(first.verdict, at_start=first, start=start)
    if first.verdict is True:
        holding = next((a, b) for a, b in per_task if a <= start and (b is None or start <= b))
        for up in (True, False):
            _end(on, answer, base, direction, start, holding[1] if up else holding[0], up,
                 parts, firsts, Fraction(0) if positive and not up else None, max_steps)
    else:
        _nearest(answer, combined, first, max_steps)
    answer.used = on.used
    if answer.why:
        answer.why += on.why_simulated(parts, base, direction)
    answer.why = list(dict.fromkeys(answer.why))
    return answer


def _fixed_refusal(on: ProcessorLine, parts: list[int]) -> LineAnswer | None:
    """The answer when a part the line does not move is not schedulable (or undecided)
    at the nominal values; None when all are.

    Those parts keep their nominal events (no time of theirs depends on t): their
    outcome at the nominal values, decided once.
    """
    for i in range(len(on.parts)):
        if i not in parts:
            fixed = on.nominal_outcomes[i]
            if fixed.verdict is not True:
                return LineAnswer(fixed.verdict, used=on.used, why=[why_text(fixed)])
    return None


def _nearest(answer: LineAnswer, combined: Callable[[Fraction, int], Outcome],
             first: Outcome, max_steps: int) -> None:
    """The start is not schedulable (or undecided): the nearest values that are, each
    side, into ``answer``."""
    if first.verdict is None:
        answer.why.append(why_text(first))
    for up in (True, False):
        found, exact, out, steps = seek(combined, first, up, max_steps)
        answer.steps += steps
        answer.nearest_exact = answer.nearest_exact and exact
        setattr(answer, "nearest_above" if up else "nearest_below", found)
        if out is not None:
            answer.beyond["above" if up else "below"] = out
        if not exact:
            answer.why.append(why_text(out) if out is not None and out.why
                              else f"stopped after {max_steps} intervals of constant order")


def _combined(on: ProcessorLine, base: dict[int, Fraction], direction: dict[int, Fraction],
              parts: list[int], per_task: Sequence[Interval], positive: bool,
              firsts: dict[int, Outcome]) -> Callable[[Fraction, int], Outcome]:
    """The verdict of every moving part and of the per-task answer at once, with their cut.

    Its first call (at the start) keeps each part's outcome in ``firsts``: the
    walks start from them instead of simulating the start again.
    """
    def combined(t: Fraction, side: int) -> Outcome:
        if positive and (t < 0 or (t == 0 and side <= 0)):
            cut = Cut(t, side)
            cut.below(Fraction(0), True)
            return Outcome(False, cut, ("per-task", None))
        out = per_task_outcome(per_task, t, side)
        if out.verdict is not True:
            return out
        verdict: bool | None = True
        why = None
        keep = not firsts
        for i in parts:
            o = on.evaluate(i, base, direction, t, side)
            if keep:
                firsts[i] = o
            if o.verdict is False:
                return o
            out.cut.meet(o.cut)
            if o.verdict is None:
                verdict, why = None, o.why
        return Outcome(verdict, out.cut, why)
    return combined


def _end(on: ProcessorLine, answer: LineAnswer, base: dict[int, Fraction],
         direction: dict[int, Fraction], start: Fraction, per_task_end: Fraction | None,
         up: bool, parts: list[int], firsts: dict[int, Outcome], floor: Fraction | None,
         max_steps: int) -> None:
    """One end of the interval holding ``start``: the nearest end over the moving parts.

    Each part is walked up to the nearest end found so far (``best``, first the
    per-task end): the interval holding start is the intersection of each
    part's and the per-task one. A walk that stops undecided proves its part
    only up to where it stopped (``proven``): the end is then a bound.
    """
    best = proven = per_task_end
    attained = True  # the per-task intervals are closed
    source: Outcome | None = None
    closer = operator.lt if up else operator.gt
    for i in parts:
        w = walk(partial(on.evaluate, i, base, direction), start, up,
                 best, max_steps=max_steps, first=firsts[i], floor=floor)
        answer.steps += w.steps
        if not w.exact:
            assert w.end is not None  # a walk stops undecided at an end it reached
            answer.why.append(w.why_stopped or "undecided")
            if proven is None or closer(w.end, proven):
                proven = w.end
            continue
        if not w.capped:
            # Unbounded (None) only while nothing bounds the walk: then proven is None too,
            # since every later walk is capped by `best`.
            best, source, attained = w.end, w.beyond, w.attained
            if proven is None or (best is not None and closer(best, proven)):
                proven = best
    exact = proven == best
    if up:
        answer.high, answer.high_exact = proven, exact
        answer.high_attained = attained or not exact
        answer.high_bound = None if exact else best
    else:
        answer.low, answer.low_exact = proven, exact
        answer.low_attained = attained or not exact
    if source is not None and exact:
        answer.beyond["high" if up else "low"] = source


def why_text(out: Outcome | None) -> str:
    """What an outcome that is not schedulable (or undecided) shows, in words."""
    if out is None or out.why is None:
        return "undecided"
    kind, a, *rest = out.why
    if kind == "undecided":
        return str(a)
    if kind == "overrun":
        return f"{a} overruns at activation {rest[0]} on its processors"
    if kind == "grows":
        return f"the place {a} grows on its processors"
    if kind == "starved":
        because = f": {rest[0]}" if rest else ""
        return f"{a} never gets enough of its processor (starved){because}"
    if kind == "saturated":
        return (f"the processor {a} is asked for more than all its time (each group's "
                "tasks once per period of its clock)")
    if kind == "not live":
        return "the skeleton is not live (a circuit without token)"
    return "not consistent with a processor per task"


def not_searched(verdict: bool | None, out: Outcome | None, what: str) -> str:
    """Why no figure on processors is searched: the nominal values are not schedulable
    (or undecided) on ``what`` (the skeleton, or a parameter's part)."""
    if verdict is None:
        return (f"undecided: {what} at the nominal values is undecided on its processors "
                f"({why_text(out)}); nothing searched")
    return f"none: not schedulable as it is ({why_text(out)}); nothing searched"


def _not_consistent() -> str:
    return ("none: not consistent as it is with a processor per task, so not schedulable "
            "on its processors either; nothing searched")


def method_text(answer: LineAnswer) -> str:
    """How the figure on processors was decided, for the report."""
    ways = []
    if THEOREM in answer.used:
        ways.append("each group one periodic unit of its summed work at its own priority on "
                    "one processor (a task without clock: a background task in the idle "
                    "time), decided level by level from the most urgent down by Lehoczky, "
                    "Sha and Ding's exact test (1989)")
    if SCHEDULE in answer.used:
        ways.append(f"the exact §4b schedule run on affine times, {answer.steps} interval"
                    f"{'s' * (answer.steps != 1)} of constant event order walked")
    if not ways:
        ways.append("the per-task answer (no part of the schedule moves on this line)")
    text = "on its processors: " + "; ".join(ways)
    if answer.why:
        text += "; UNDECIDED beyond what is proven: " + "; ".join(dict.fromkeys(answer.why))
    return text


# --------------------------------------------------------------------------- the report


def limit_on(outcome: Outcome, at_end: bool = False) -> Limit:
    """What the exact schedule shows just beyond an end (``at_end``: at the end itself,
    an end that the interval does not hold)."""
    kind, a, *rest = outcome.why  # type: ignore[misc]
    where = "on its processors, at the end itself" if at_end else "on its processors"
    if kind == "overrun":
        return Limit("processors", f"{where}, {a} overruns: activation {rest[0] - 1} "
                     f"has not ended at tick {rest[0]}", task=a, activation=rest[0], tasks=[a])
    if kind == "grows":
        return Limit("processors", f"{where}, the place {a} grows by tokens every "
                     "regime (unbounded)", events=a.split(" -> "))
    if kind == "starved":
        because = f": {rest[0]}" if rest else ""
        return Limit("processors", f"{where}, {a} never gets enough of its "
                     f"processor (starved){because}", task=a, tasks=[a])
    if kind == "saturated":
        return Limit("processors", f"on its processors, {why_text(outcome)}: some group "
                     "falls behind its clock")
    return Limit("processors", f"undecided on its processors: {a}")


def _limits(answer: LineAnswer, key: str, per_task: list[Limit]) -> list[Limit]:
    out = answer.beyond.get(key)
    if out is None or out.why is None or out.why[0] == "per-task":
        return list(per_task)
    attained = answer.high_attained if key == "high" else answer.low_attained
    return [limit_on(out, at_end=key in ("high", "low") and not attained)]


def scaling_on(ctx: Any, on: ProcessorLine, pt: Scaling, verify: bool) -> Scaling:
    """The scaling factor on processors, within the one with a processor per task ``pt``.

    ``ctx`` is the sensitivity's context (``skeleton``, ``params``, ``nominal``,
    ``analyses``, ``max_events``).
    """
    durations = [j for j, p in enumerate(ctx.params) if p.kind == "duration"]
    s = Scaling(pt.parameters, intervals=[], factor=None, nominal_consistent=False,
                semantics=PROCESSORS, per_task=pt)
    if not pt.intervals:  # no factor is consistent: none is schedulable either
        s.limits = list(pt.limits)
        s.method = "on its processors: no factor is consistent with a processor per task"
        return s
    why = _scaling_not_searched(ctx, on, pt, s)
    if why is not None:
        return _unsearched(s, why, ctx.schedulable is None or why.startswith("undecided"))
    on.spend.start_figure()
    answer = solve_line(on, {j: Fraction(0) for j in durations},
                        {j: ctx.nominal[j] for j in durations}, Fraction(1), pt.intervals,
                        constant_parts=True)
    s.breakpoints, s.why_undecided, s.method = answer.steps, answer.why, method_text(answer)
    if answer.holding:
        _factor_holding(s, answer, pt)
    else:
        _factor_nearest(s, answer, pt)
    if verify:
        _check(ctx, s.checks, "scaling",
               lambda t: {j: t * ctx.nominal[j] for j in durations}, answer,
               on.tasks_of(on.moving({j: ctx.nominal[j] for j in durations})))
    return s


def _scaling_not_searched(ctx: Any, on: ProcessorLine, pt: Scaling, s: Scaling) -> str | None:
    """Why no factor is searched (setting what limits it into ``s``); None: searched.

    The nominal values not schedulable (or undecided): no figure, at once. The
    factors elsewhere are not searched (each would cost a whole schedule per
    interval of constant order), as no margin is.
    """
    if not pt.nominal_consistent:
        s.limits = list(pt.limits)
        return _not_consistent()
    if ctx.schedulable is not True:
        if ctx.unschedulable is not None and ctx.unschedulable.why and \
                ctx.unschedulable.why[0] in ("overrun", "grows", "starved"):
            s.limits = [limit_on(ctx.unschedulable)]
        why = not_searched(ctx.schedulable, ctx.unschedulable, "the skeleton")
        if ctx.schedulable is None:
            why = "; ".join([why, *on.why_simulated(
                [i for i, o in enumerate(on.nominal_outcomes) if o.verdict is None])])
        return why
    if on.spend.run_left <= 0:
        return "undecided: " + on.spend.cap()[1] + "; nothing searched"
    return None


def _factor_holding(s: Scaling, answer: LineAnswer, pt: Scaling) -> None:
    """1 is schedulable: the interval holding it, its end and what limits it."""
    s.nominal_consistent = True
    s.intervals = [(answer.low, answer.high)]  # type: ignore[list-item]
    s.exact = answer.high_exact and answer.low_exact
    if answer.high_exact:
        s.factor = answer.high
        s.attained = answer.high_attained
    else:
        s.bounds = (answer.high, answer.high_bound)
    s.limits = _limits(answer, "high", pt.limits if pt.factor == answer.high else [])


def _factor_nearest(s: Scaling, answer: LineAnswer, pt: Scaling) -> None:
    """1 is not schedulable (or undecided): why, and the nearest factors that are."""
    s.exact = answer.holding is False and answer.nearest_exact
    s.nearest_below, s.nearest_above = answer.nearest_below, answer.nearest_above
    start = answer.at_start
    s.limits = ([limit_on(start)] if start is not None and start.why is not None
                and start.why[0] != "per-task" else list(pt.limits))
    if s.nearest_below is not None:
        s.limits_below = _limits(answer, "below", pt.limits_below)
    if s.nearest_above is not None:
        s.limits_above = _limits(answer, "above", pt.limits_above)


def margin_on(ctx: Any, on: ProcessorLine, pt: Margin, verify: bool) -> Margin:
    """One parameter's margin on processors, within the one with a processor per task."""
    p = pt.parameter
    j = ctx.params.index(p)
    m = Margin(p, groups=pt.groups, intervals=[], nominal_consistent=False,
               semantics=PROCESSORS, per_task=pt)
    if not pt.intervals:
        m.method = "on its processors: no value is consistent with a processor per task"
        return m
    # Its own part(s) only (a margin is its part's, as the per-task margin is its
    # group's). Not schedulable at the nominal value: its line is searched for the
    # values that are, when the parameter is named (``vary``) or its parts have
    # levels (decided without simulating); else nothing is searched.
    parts = on.moving({j: Fraction(1)})
    mine = [on.nominal_outcomes[i] for i in parts]
    bad = ([o for o in mine if o.verdict is False] + [o for o in mine if o.verdict is None])
    why = None
    if bad and bad[0].verdict is None:
        why = "; ".join([not_searched(None, bad[0], "its part"), *on.why_simulated(parts)])
    elif not pt.nominal_consistent or bad:
        if ctx.named or all(on.has_levels(i, {j: Fraction(1)}) for i in parts):
            if on.spend.run_left <= 0:
                return _unsearched(m, "undecided: " + on.spend.cap()[1] + "; nothing searched",
                                   True)
            return _swept(ctx, on, m, j, verify, None if not pt.nominal_consistent else bad[0])
        why = (_not_consistent() if not pt.nominal_consistent
               else not_searched(False, bad[0], "its part"))
        why += " (name it with `vary` to search its line)"
    elif on.spend.run_left <= 0:
        why = "undecided: " + on.spend.cap()[1] + "; nothing searched"
    if why is not None:
        return _unsearched(m, why, why.startswith("undecided"))
    on.spend.start_figure()
    answer = solve_line(on, {j: Fraction(0)}, {j: Fraction(1)}, p.nominal, pt.intervals,
                        constant_parts=False, positive=p.kind == "period")
    m.why_undecided, m.method = answer.why, method_text(answer)
    if answer.holding:
        m.nominal_consistent = True
        m.low, m.high = answer.low, answer.high
        m.intervals = [(answer.low, answer.high)]  # type: ignore[list-item]
        m.low_attained, m.high_attained = answer.low_attained, answer.high_attained
        m.intervals_open = [(not m.low_attained, not m.high_attained)]
        m.exact = answer.low_exact and answer.high_exact
        if not m.exact:
            m.bounds = (answer.low, answer.high)
            m.low = answer.low if answer.low_exact else None
            m.high = answer.high if answer.high_exact else None
        m.limits_low = _limits(answer, "low", pt.limits_low if pt.low == answer.low else [])
        m.limits_high = _limits(answer, "high", pt.limits_high if pt.high == answer.high else [])
    else:
        m.exact = answer.holding is False
    if verify:
        _check(ctx, m.checks, p.name, lambda t: {j: t}, answer,
               on.tasks_of(on.moving({j: Fraction(1)})))
    return m


def _swept(ctx: Any, on: ProcessorLine, m: Margin, j: int, verify: bool,
           nominal: Outcome | None) -> Margin:
    """A parameter whose nominal value is not schedulable (``nominal``: why; None: not
    consistent with a processor per task): every schedulable interval of its line."""
    pt = m.per_task
    assert pt is not None
    p = m.parameter
    on.spend.start_figure()
    on.used = set()
    direction = {j: Fraction(1)}
    parts = on.moving(direction)
    combined = _combined(on, {j: Fraction(0)}, direction, parts, pt.intervals,
                         p.kind == "period", {})
    found = sweep(combined, pt.intervals, MAX_STEPS)
    m.intervals = [(lo, hi) for lo, _, hi, _ in found.intervals]
    m.intervals_open = [(lo_open, hi_open) for _, lo_open, _, hi_open in found.intervals]
    m.exact = found.exact
    answer = LineAnswer(False, steps=found.steps, used=on.used,
                        why=[found.why, *on.why_simulated(parts, {j: Fraction(0)}, direction)]
                        if found.why else [])
    m.why_undecided = answer.why
    m.method = method_text(answer) + "; the nominal value is " + (
        "not consistent with a processor per task" if nominal is None
        else f"not schedulable ({why_text(nominal)})") + (
        ": every schedulable interval of the range searched"
        if found.exact else ": the range searched up to where it stopped")
    if verify:
        sub = ctx.skeleton.restricted_to(on.tasks_of(parts))
        for lo, lo_open, hi, hi_open in found.intervals:
            point = (lo if not lo_open else hi if hi is not None and not hi_open
                     else lo + 1 if hi is None else (lo + hi) / 2)
            m.checks.append(Check(f"{p.name} on processors, a schedulable value", point, True,
                                  verdict_on(ctx, {j: point}, sub)))
    return m


def _unsearched(figure: Any, why: str, undecided: bool) -> Any:
    """A figure on processors left unsearched: none (proven) or undecided, with why."""
    figure.not_searched = why
    figure.exact = not undecided
    figure.method = "on its processors: " + why
    if undecided:
        figure.why_undecided = [why]
    return figure


def _check(ctx: Any, checks: list[Check], what: str,
           values: Callable[[Fraction], dict[int, Fraction]], answer: LineAnswer,
           tasks: list[str]) -> None:
    """Each exact finite end: the whole analysis on processors at it and just beyond,
    on the skeleton of ``tasks`` alone (the parts the line moves: the others'
    events do not depend on it, and they are schedulable at the nominal values)."""
    sub = ctx.skeleton.restricted_to(tasks)
    ends = []
    if answer.holding:
        if answer.high_exact and answer.high is not None and "high" in answer.beyond:
            ends.append((answer.high, 1, answer.beyond["high"], answer.high_attained))
        if answer.low_exact and answer.low is not None and "low" in answer.beyond:
            ends.append((answer.low, -1, answer.beyond["low"], answer.low_attained))
    else:
        for key, end, side in (("above", answer.nearest_above, 1),
                               ("below", answer.nearest_below, -1)):
            if end is not None and key in answer.beyond:
                ends.append((end, -side, answer.beyond[key], True))
    start = answer.start
    for end, side, out, attained in ends:
        if not attained:
            # An open end: not schedulable at it, schedulable inside. Just inside, a
            # task starved at the end gets almost nothing (10^-9 of the processor) and
            # no schedule of a budget could show it end: the point checked inside is
            # halfway to the start.
            checks.append(Check(f"{what} on processors at the end (excluded)", end, False,
                                verdict_on(ctx, values(end), sub)))
            inside = (end + start) / 2 if start is not None and start != end else None
            if inside is not None:
                checks.append(Check(f"{what} on processors inside, halfway to the nominal",
                                    inside, True, verdict_on(ctx, values(inside), sub)))
            continue
        checks.append(Check(f"{what} on processors at the end", end, True,
                            verdict_on(ctx, values(end), sub)))
        beyond = _just(end, side, out)
        if beyond is not None:
            checks.append(Check(f"{what} on processors just beyond", beyond, False,
                                verdict_on(ctx, values(beyond), sub)))


def _just(end: Fraction, side: int, out: Outcome) -> Fraction | None:
    """A point beside ``end`` (side +1 above, -1 below) inside the piece ``out`` holds on."""
    step = abs(end) * _NUDGE or _NUDGE
    if side > 0 and out.why is not None and out.why[0] == "saturated":
        # The load grows with t past the end, so every point above it is proven
        # saturated; 10^-9 beyond, the schedule would fall behind by 10^-9 per
        # period and no analysis within its budget could see it: check a point
        # a tenth further, where it falls behind fast.
        return end + (abs(end) / 10 or Fraction(1))
    if side > 0:
        far = out.cut.hi
        return end + step if far is None or end + step < far else (end + far) / 2
    near = out.cut.lo
    t = end - step if near is None or end - step > near else (end + near) / 2
    return t if t >= 0 else None


def verdict_on(ctx: Any, values: dict[int, Fraction], sub: Skeleton | None = None
               ) -> bool | None:
    """Live, consistent and schedulable on processors, by ``analyze_skeleton``, of the
    skeleton ``sub`` (default: the whole one) with ``values``."""
    from ..analyze import analyze_skeleton

    sub = ctx.skeleton if sub is None else sub
    mine = {j: v for j, v in values.items() if ctx.params[j].applies_to(sub)}
    moved = skeleton_at(sub, ctx.params, mine)
    # A small budget first: just beyond an end the first overrun comes early, and
    # the schedule would spend its whole budget looking for a regime after it.
    for budget in dict.fromkeys((min(_SHORT_EVENTS, ctx.max_events), ctx.max_events)):
        ctx.analyses += 1
        report = analyze_skeleton(moved, processors=True, max_events=budget,
                                  semiflow_max_places=0)
        if not (report.live and report.consistent):
            return False
        if report.schedulable is not None:
            return report.schedulable
    return None
