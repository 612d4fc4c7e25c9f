"""How much the execution times may grow, and each period as an exact formula.

``sensitivity`` answers, exactly, for the parameters named by ``vary``
(durations ``TASK.duration``, periods ``CLOCK.period`` and the declared delays
``network.delay`` and ``links[i].delay``, spec §4d):

- **scaling**: the factors α >= 0 by which all the varied durations can be
  multiplied together with the skeleton consistent (spec §4), as a union of
  closed intervals, and the *scaling factor*, the upper end of the one that
  holds 1 (the critical scaling factor of Lehoczky, Sha and Ding [1]_, here
  for synchronized task sets), with what limits it;
- **margins**: for each parameter alone, its consistent values within its
  range (for a duration: how far it can really grow, overruns included);
- **period formulas**: each live group's cycle time as the maximum of
  non-redundant circuit ratios over the box of its parameters (a sympy
  ``Max``), and where a clocked group keeps pace with its clock.

How each figure is proven is in ``docs/sensitivity.md``; in
short, the consistent set along a line is read off exact certificates
(:mod:`.line`), the formulas come from cutting planes
(:mod:`.formulas`), and each finite end reported is checked
again with :func:`~tegraph.analysis.analyze.analyze_skeleton` (consistent at
the end, not just beyond), unless ``verify`` is False.

References
----------
.. [1] J. Lehoczky, L. Sha, Y. Ding, "The rate monotonic scheduling algorithm:
   exact characterization and average case behavior", RTSS 1989.
.. [2] A. H. Ghamarian, M. C. W. Geilen, T. Basten, S. Stuijk, "Parametric
   throughput analysis of synchronous data flow graphs", DATE 2008.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from maxplus.scalar import display_text

from ...errors import InputError
from ...model.limits import event_budget_problem
from ...model.skeleton import Skeleton
from ...model.skeleton.checks import Locator, check_chain
from ...model.structure import Structure
from ..processors import MAX_EVENTS
from .chains import chains_at_margins
from .formulas import GroupFormula, period_formulas
from .line import Cause, Line, LineSet, intersect, point_causes, solve_lines
from .margins import duration_margins
from .on_processors import margin_on, scaling_on
from .oracle import evaluate
from .parameters import Parameter, parse_vary, skeleton_at
from .parametric import ParametricGroup, parametric_groups
from .parts import ProcessorLine
from .results import (
    Check,
    GroupFormulaReport,
    Limit,
    Margin,
    PaceReport,
    Scaling,
    SensitivityResult,
    Term,
)
from .simulation import RUN_BUDGETS
from .walk import Outcome

__all__ = ["duration_margins", "sensitivity"]

Interval = tuple[Fraction, "Fraction | None"]
_NUDGE = Fraction(1, 10**9)
_SHORT_STEPS = 1_000


def sensitivity(skeleton: Skeleton, vary: Any = None, *, formulas: bool = True,
                max_formula_parameters: int = 6, verify: bool = True,
                margins: bool = True, processors: bool = True,
                max_events: int = MAX_EVENTS,
                progress: Callable[[int, int, int], None] | None = None,
                chains: Sequence[Sequence[str]] = ()) -> SensitivityResult:
    """Scaling factor, margins and period formulas of a skeleton, exact.

    Parameters
    ----------
    skeleton : Skeleton
    vary : None, sequence of str or mapping
        The parameters (see :func:`~.parameters.parse_vary`): texts
        ``TASK.duration``, ``CLOCK.period``, ``network.delay``, ``links[i].delay``,
        each optionally ``=LOW..HIGH``.
        Default: every task's duration over ``[0, ∞)``.
    formulas : bool
        Compute the period formulas (the part that costs most with many
        parameters per group).
    max_formula_parameters : int
        A group depending on more varied parameters than this gets its
        critical terms and exact partial derivatives at the nominal point
        instead of a formula over the whole box.
    verify : bool
        Check every finite end reported with ``analyze_skeleton`` on its
        group (consistent at the end, not just beyond).
    margins : bool
        Compute each parameter's margin (one line search per parameter: the
        part that costs most on thousands of tasks); without it, ``margins``
        is empty.
    processors : bool
        The scaling factor and the margins on the skeleton's processors (spec
        §4b: live, consistent and schedulable under preemptive fixed
        priorities), each with its figure with a processor per task beside it
        (``per_task``); False: with a processor per task only (spec §4, the
        v1.1 answers). The period formulas are always with a processor per task.
    max_events : int
        On processors: the budget of event firings of each simulation of a
        part of the schedule at one point, and of each figure (the scaling
        factor, one margin) in all; the whole run on processors, the nominal
        verdict included, fires at most ``RUN_BUDGETS`` (20) times as many
        (``simulation.Budget``). A figure cut by a budget is undecided
        and says which.
    progress : callable, optional
        On processors, called as ``progress(figures_done, figures, firings)``
        after each simulation and each figure (for a progress bar).
    chains : sequence of task-name sequences
        Chains besides the skeleton's own: for each, its first use (spec §4c) at the
        nominal values, at the scaling factor and at each end of every margin
        (``result.chains``, :mod:`tegraph.analysis.sensitivity.chains`), on processors
        or with a processor per task as the figures are.

    Returns
    -------
    SensitivityResult
        ``scaling`` (None when no duration is varied): the consistent factors
        as closed intervals and ``factor``, with its limits (on processors:
        the interval holding 1, ``semantics`` and ``exact`` say which and how); ``margins``: per
        parameter name, its consistent values and the interval around the
        nominal value, with the cause at each end; ``formulas``: per live
        group, the non-redundant terms of its cycle time and where it keeps
        pace with each clock; ``checks``, ``methods`` and ``effort`` say how
        each was obtained (oracle calls, points, cross-check analyses).

    Raises
    ------
    InputError
        ``vary`` names an unknown parameter, or a range that is malformed,
        empty or negative (``where``: ``vary[i]``).
    SkeletonError
        A chain names an unknown task, a task twice, or two unlinked tasks.

    See Also
    --------
    duration_margins : the margin of every duration, fast enough for every analysis.
    tegraph.analysis.analyze.analyze_skeleton : the figures at one point.

    Notes
    -----
    Every time is exact (Fractions, in the skeleton's unit). Consistency is
    not monotone in the durations (a slower producer can bound a place), so
    the consistent factors and values are unions of closed intervals. The
    methods and proofs: ``docs/sensitivity.md``.

    References
    ----------
    .. [1] J. Lehoczky, L. Sha, Y. Ding, "The rate monotonic scheduling algorithm:
       exact characterization and average case behavior", RTSS 1989 (the
       critical scaling factor).
    .. [2] A. H. Ghamarian, M. C. W. Geilen, T. Basten, S. Stuijk, "Parametric
       throughput analysis of synchronous data flow graphs", DATE 2008.
    .. [3] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, "Synchronization
       and Linearity", Wiley 1992, Thm 3.112 (cycle time as a maximum of
       circuit ratios).

    Examples
    --------
    One task of duration 2 on a clock of period 10: its duration may grow to
    10 (a factor 5), and its group's cycle time is ``Max(10, d_A)``:

    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 10}}})
    >>> r = sensitivity(sk)
    >>> r.scaling.factor, r.margins["A.duration"].high
    (Fraction(5, 1), Fraction(10, 1))
    >>> r.formulas[0].expression()
    Max(10, d_A)

    With B (duration 4, period 10) on the same processor, less urgent, both
    may grow by 10/6 together (B then ends at 10, its next tick), while with a
    processor per task the factor is 10/4:

    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 5},
    ...                                    "B": {"duration": 4, "period": 10}}})
    >>> r = sensitivity(sk, formulas=False)
    >>> r.scaling.semantics, r.scaling.factor, r.scaling.per_task.factor
    ('processors', Fraction(5, 4), Fraction(5, 2))
    """
    _check_max_events(max_events)
    for k, chain in enumerate(chains):  # refused before any work
        check_chain(skeleton, chain, ("chain", k), Locator())
    started = time.perf_counter()
    params = parse_vary(skeleton, vary)
    context, result = _nominal(skeleton, params, started)
    context.named = vary is not None
    has_durations = any(p.kind == "duration" for p in params)
    figures = _Figures(int(has_durations) + (len(params) if margins else 0), progress)
    on = _processors_part(context, result, max_events, figures) if processors else None
    if has_durations:
        _scaling_part(context, result, on, verify, figures)
    if margins:
        _margins_part(context, result, on, verify, figures)
    if on is not None:
        budget = on.spend
        result.notes.append(
            f"on processors: {budget.spent:,} event firings simulated in all, of the run's "
            f"budget of {budget.total:,} ({budget.total // budget.max_events} × `max_events`)")
    if formulas:
        _formulas_part(context, result, max_formula_parameters)
    result.chains = chains_at_margins(skeleton, chains, params, result.scaling, result.margins,
                                      processors=processors, max_events=max_events)
    result.methods = _methods(result, max_formula_parameters, verify)
    result.notes += _closing_notes(result)
    return result


def _check_max_events(max_events: Any) -> None:
    problem = event_budget_problem(max_events)
    if problem is not None:
        raise InputError(problem, "max_events")


def _nominal(skeleton: Skeleton, params: tuple[Parameter, ...],
             started: float) -> tuple[_Context, SensitivityResult]:
    """The groups and their verdicts at the nominal values: the result's frame and the
    context every figure shares."""
    nominal = [p.nominal for p in params]
    structure = Structure.of(skeleton)  # once: the groups here and the analysis on processors
    groups = parametric_groups(skeleton, params, structure)
    live = [g for g in groups if g.live]
    at_nominal = dict(zip([g.index for g in live],
                          evaluate([(g, g.values({}, nominal)) for g in live])))
    fine = {g.index: g.live and at_nominal[g.index].consistent for g in groups}
    result = SensitivityResult(name=skeleton.name, unit=skeleton.unit, parameters=params,
                               live=all(g.live for g in groups),
                               consistent=all(fine.values()),
                               groups=[list(g.tasks) for g in groups], scaling=None,
                               margins={}, formulas=None, source=skeleton.source)
    result.models = {g.index: g for g in live}
    result.effort["setup"] = {"rounds": 1, "points": len(live), "analyses": 0,
                              "seconds": time.perf_counter() - started}
    return _Context(skeleton, params, nominal, groups, fine, at_nominal,
                    structure), result


@dataclass
class _Figures:
    """The figures (scaling factor, margins) decided so far on processors, of
    ``total``, for the caller's ``progress``."""

    total: int
    progress: Callable[[int, int, int], None] | None
    done: int = 0

    def report(self, spent: int) -> None:
        if self.progress is not None:
            self.progress(self.done, self.total, spent)


def _processors_part(ctx: _Context, result: SensitivityResult, max_events: int,
                     figures: _Figures) -> ProcessorLine:
    clock = time.perf_counter()
    on = _nominal_on_processors(ctx, result, max_events)
    if figures.progress is not None:
        on.progress = lambda: figures.report(on.spend.spent)
    result.effort["processors"] = ctx.effort(clock)
    return on


def _scaling_part(ctx: _Context, result: SensitivityResult, on: ProcessorLine | None,
                  verify: bool, figures: _Figures) -> None:
    clock = time.perf_counter()
    result.scaling = _scaling(ctx, verify)
    if on is not None:
        result.scaling = scaling_on(ctx, on, result.scaling, verify)
        figures.done += 1
    result.effort["scaling"] = ctx.effort(clock)


def _margins_part(ctx: _Context, result: SensitivityResult, on: ProcessorLine | None,
                  verify: bool, figures: _Figures) -> None:
    clock = time.perf_counter()
    result.margins = _margins(ctx, verify)
    if on is not None:
        for name, m in result.margins.items():
            result.margins[name] = margin_on(ctx, on, m, verify)
            figures.done += 1
            figures.report(on.spend.spent)
    result.effort["margins"] = ctx.effort(clock)


def _formulas_part(ctx: _Context, result: SensitivityResult, max_parameters: int) -> None:
    clock = time.perf_counter()
    live = list(result.models.values())
    found, rounds, points = period_formulas(live, ctx.params, max_parameters)
    result.formulas = [_formula_report(g, f, ctx.params, ctx.at_nominal[g.index])
                       for g, f in zip(live, found)]
    result.effort["formulas"] = {"rounds": rounds, "points": points, "analyses": 0,
                                 "seconds": time.perf_counter() - clock}


def _closing_notes(result: SensitivityResult) -> list[str]:
    notes = []
    if not result.live:
        notes.append("the skeleton is not live (a circuit without token): no value of "
                     "any parameter makes it consistent; liveness does not depend on times")
    disagree = [c for c in result.checks if not c.agrees]
    if disagree:
        notes.append(f"{len(disagree)} cross-check(s) with the analysis DISAGREE, e.g. "
                     f"{disagree[0].what} at {display_text(disagree[0].value)}")
    return notes


class _Context:
    """What the parts share: the skeleton, parameters, groups and counters."""

    def __init__(self, skeleton: Skeleton, params: Sequence[Parameter],
                 nominal: list[Fraction], groups: list[ParametricGroup],
                 fine: dict[int, bool], at_nominal: dict, structure: Structure) -> None:
        self.skeleton, self.params, self.nominal = skeleton, params, nominal
        self.structure = structure
        self.groups, self.fine, self.at_nominal = groups, fine, at_nominal
        self.rounds = self.points = self.analyses = 0
        self.max_events = MAX_EVENTS
        self.named = False
        """The parameters were named (``vary``): on processors, their lines are searched
        where the nominal values are not schedulable."""
        self.schedulable: bool | None = None
        self.unschedulable: Outcome | None = None
        """On processors: the outcome why the nominal values are not schedulable."""

    def solve(self, pairs: list[tuple[ParametricGroup, Line]]) -> list[LineSet]:
        sets, rounds, points = solve_lines(pairs, self.nominal)
        self.rounds += rounds
        self.points += points
        return sets

    def effort(self, since: float) -> dict[str, int | float]:
        out = {"rounds": self.rounds, "points": self.points, "analyses": self.analyses,
               "seconds": time.perf_counter() - since}
        self.rounds = self.points = self.analyses = 0
        return out

    def consistent(self, group: ParametricGroup, values: dict[int, Fraction]):
        """The group's verdict by ``analyze_skeleton`` at ``values``, and the report."""
        from ..analyze import analyze_skeleton

        self.analyses += 1
        moved = skeleton_at(group.skeleton, self.params, {j: values[j] for j in group.params})
        # A short dater simulation first: just past a pace limit the group is
        # slower than its clock by 10^-9 of a period, and the full budget would
        # be spent (seconds) looking for an overrun that cannot change a verdict
        # already False; an early overrun (its activation is reported) is seen.
        report = analyze_skeleton(moved, max_steps=_SHORT_STEPS, semiflow_max_places=0)
        g = report.groups[0]
        if not (g.live and g.rate_consistent):
            return False, report
        if not all(t.overrun_decided for t in report.tasks.values()):
            report = analyze_skeleton(moved, semiflow_max_places=0)
        if any(t.overrun_at is not None for t in report.tasks.values()):
            return False, report
        # An overrun the analysis could not rule out within its budget: no verdict.
        return (True if all(t.overrun_decided for t in report.tasks.values()) else None), report

    def limit(self, cause: Cause) -> Limit:
        g = self.groups[cause.group]
        names = g.names
        if cause.kind == "overrun":
            cert = cause.certificate
            assert cert is not None
            if cert.kind == "path":
                events = [names[int(g.dst[cert.places[0]])]]
                events += [names[int(g.dst[p])] for p in cert.places[1:]]
                detail = (f"{cause.task} overruns: its activation ends after the next tick of "
                          f"{cause.clock}, along {' -> '.join(events)}")
            else:
                events = [names[int(g.src[p])] for p in cert.places]
                detail = (f"circuit {' -> '.join(events)} is slower than clock {cause.clock}: "
                          f"{cause.task} overruns")
            return Limit("overrun", detail, group=g.index, task=cause.task, clock=cause.clock,
                         events=events, certificate=cert.kind, tasks=_owners(g, events))
        # Type: a cause that is not an overrun is a pace cause: it has both circuits (both lines).
        circuit = [names[int(g.src[p])] for p in cause.circuit.places]  # type: ignore[union-attr]
        source = [names[int(g.src[p])] for p in cause.source.places]  # type: ignore[union-attr]
        against = (f"clock {cause.clock}" if cause.clock is not None
                   else f"the free-running circuit {' -> '.join(source)}")
        detail = (f"circuit {' -> '.join(circuit)} is slower than {against}: a place of "
                  f"group {g.index} ({', '.join(g.tasks)}) is unbounded")
        return Limit("pace", detail, group=g.index, clock=cause.clock, events=circuit,
                     source_events=source, tasks=_owners(g, circuit))


    def nominal_limits(self, g: ParametricGroup, constant: bool) -> list[Limit]:
        """Why group g is not consistent at the nominal values."""
        if not g.live:
            return [Limit("group", f"group {g.index} ({', '.join(g.tasks)}) is not live (a "
                          "circuit without token), whatever the times", g.index)]
        out = [self.limit(c) for c in point_causes(self.at_nominal[g.index])]
        if constant:
            out.insert(0, Limit("group", f"group {g.index} ({', '.join(g.tasks)}) is not "
                                "consistent and does not depend on the values varied", g.index))
        return out


# --------------------------------------------------------------------------- scaling


@dataclass
class _Box:
    """The factors the varied durations' own ranges allow, ``[low, high]``, and whose
    range ends each side (a factor moves every varied duration at once)."""

    low: Fraction = Fraction(0)
    high: Fraction | None = None
    low_by: str | None = None
    high_by: str | None = None
    impossible: str | None = None
    """A duration that is 0 with a range excluding 0: no factor brings it in."""

    @property
    def empty(self) -> bool:
        return self.impossible is not None or (self.high is not None and self.low > self.high)


def _factor_box(params: Sequence[Parameter], nominal: list[Fraction],
                durations: list[int]) -> _Box:
    box = _Box()
    for j in durations:
        p, d = params[j], nominal[j]
        if d == 0:
            if p.low > 0:
                box.impossible = p.name
            continue
        if p.low / d > box.low:
            box.low, box.low_by = p.low / d, p.name
        if p.high is not None and (box.high is None or p.high / d < box.high):
            box.high, box.high_by = p.high / d, p.name
    return box


def _scaling(ctx: _Context, verify: bool) -> Scaling:
    params, nominal = ctx.params, ctx.nominal
    durations = [j for j, p in enumerate(params) if p.kind == "duration"]
    box = _factor_box(params, nominal, durations)
    line = Line({j: Fraction(0) for j in durations}, {j: nominal[j] for j in durations},
                box.low, box.high)
    names = [params[j].name for j in durations]
    blocked = _blocked(ctx, line, set(durations))
    if box.empty or blocked:
        return Scaling(names, intervals=[], factor=None, nominal_consistent=False,
                       limits=_refusal(ctx, blocked, box))
    moving = [g for g in ctx.groups if g.live and any(line.direction.get(j) for j in g.params)]
    sets = ctx.solve([(g, line) for g in moving])
    overall: list[Interval] = [(box.low, box.high)]
    for s in sets:
        overall = intersect(overall, s.intervals)
    scaling = _scaling_from(ctx, names, overall, moving, sets, box)
    if verify:
        _check_scaling(ctx, scaling, moving, sets, line)
    return scaling


def _blocked(ctx: _Context, line: Line, varied: set[int]) -> list[ParametricGroup]:
    """The groups inconsistent at the nominal values that no factor moves: no varied
    duration, not live, or every varied duration of theirs 0.

    ``varied`` is made once by the caller: a set per group costs O(groups × parameters).
    """
    nominal = ctx.nominal
    blocked = [g for g in ctx.groups if varied.isdisjoint(g.params) or not g.live
               or not any(nominal[j] for j in g.params if j in line.direction)]
    return [g for g in blocked if not ctx.fine[g.index]]


def _refusal(ctx: _Context, blocked: list[ParametricGroup], box: _Box) -> list[Limit]:
    """Why no factor is consistent, when that is known before any search."""
    limits = [x for g in blocked for x in ctx.nominal_limits(g, True)]
    if box.impossible is not None:
        limits.append(Limit("range", f"{box.impossible} is 0, outside its range: no factor "
                            "brings it in", parameter=box.impossible))
    return limits


def _scaling_from(ctx: _Context, names: list[str], overall: list[Interval],
                  moving: list[ParametricGroup], sets: list[LineSet], box: _Box) -> Scaling:
    """The factor from the consistent factors ``overall``: the end of the interval
    holding 1, or, when 1 is not consistent, the nearest consistent factors and why."""
    one = Fraction(1)
    holding = next(((a, b) for a, b in overall if a <= one and (b is None or one <= b)), None)
    if holding is not None:
        return Scaling(names, intervals=overall, factor=holding[1], nominal_consistent=True,
                       limits=_factor_limits(ctx, sets, box, holding[1], "above"))
    below = [b for _, b in overall if b is not None and b < one]
    above = [a for a, _ in overall if a > one]
    nb = max(below) if below else None
    na = min(above) if above else None
    scaling = Scaling(names, intervals=overall, factor=None, nominal_consistent=False,
                      nearest_below=nb, nearest_above=na,
                      limits_below=_factor_limits(ctx, sets, box, nb, "above"),
                      limits_above=_factor_limits(ctx, sets, box, na, "below"))
    scaling.limits = [x for g, s in zip(moving, sets) if not _contains(s.intervals, one)
                      for x in ctx.nominal_limits(g, False)]
    return scaling


def _factor_limits(ctx: _Context, sets: list[LineSet], box: _Box, t: Fraction | None,
                   side: str) -> list[Limit]:
    """What ends the consistent factors at t on ``side`` (the groups' causes, a range)."""
    if t is None:
        return []
    out = [ctx.limit(c) for s in sets for c in s.causes.get((t, side), [])]
    if side == "above" and t == box.high:
        out.append(Limit("range", f"the range of {box.high_by} ends here",
                         parameter=box.high_by))
    if side == "below" and t == box.low and box.low_by is not None:
        out.append(Limit("range", f"the range of {box.low_by} starts here",
                         parameter=box.low_by))
    return out


def _owners(g: ParametricGroup, events: list[str]) -> list[str]:
    index = {name: e for e, name in enumerate(g.names)}
    return list(dict.fromkeys(t for name in events for t in g.event_owners[index[name]]))


def _contains(intervals: list[Interval], t: Fraction) -> bool:
    return any(a <= t and (b is None or t <= b) for a, b in intervals)


def _beyond(t: Fraction, intervals: list[Interval], side: str) -> Fraction | None:
    """A point just past the end t (above or below), before any other consistent value."""
    if side == "above":
        step = t * _NUDGE if t > 0 else _NUDGE
        nxt = min((a for a, _ in intervals if a > t), default=None)
        return t + step if nxt is None else min(t + step, (t + nxt) / 2)
    step = t * _NUDGE
    if step == 0:
        return None
    prev = max((b for _, b in intervals if b is not None and b < t), default=None)
    return t - step if prev is None else max(t - step, (t + prev) / 2)


def _check_scaling(ctx: _Context, scaling: Scaling, moving, sets, line: Line) -> None:
    if scaling.nominal_consistent:
        ends = [(scaling.factor, "above")]
    else:
        ends = [(scaling.nearest_below, "above"), (scaling.nearest_above, "below")]
    for end, side in ends:
        if end is None:
            continue
        limiting = [(g, s) for g, s in zip(moving, sets) if (end, side) in s.causes]
        beyond = _beyond(end, scaling.intervals, side)
        for g, _ in limiting:
            verdict, _ = ctx.consistent(g, line.values(g, ctx.nominal, end))
            scaling.checks.append(Check(f"scaling: group {g.index} at the factor", end, True,
                                        verdict))
            if beyond is not None and (line.high is None or beyond <= line.high):
                verdict, report = ctx.consistent(g, line.values(g, ctx.nominal, beyond))
                scaling.checks.append(Check(f"scaling: group {g.index} just beyond", beyond,
                                            False, verdict))
                _activations(scaling.limits + scaling.limits_below + scaling.limits_above,
                             g, report)


def _activations(limits: list[Limit], g: ParametricGroup, report) -> None:
    for limit in limits:
        if limit.kind == "overrun" and limit.group == g.index and limit.activation is None:
            limit.activation = report.tasks[limit.task].overrun_at


# --------------------------------------------------------------------------- margins


def _margins(ctx: _Context, verify: bool) -> dict[str, Margin]:
    params = ctx.params
    pairs, owners = [], []
    lines = {}
    for j, p in enumerate(params):
        lines[j] = Line({j: Fraction(0)}, {j: Fraction(1)}, p.low, p.high, p.low_open)
        for g in ctx.groups:
            if j in g.params and g.live:
                pairs.append((g, lines[j]))
                owners.append(j)
    sets = ctx.solve(pairs)
    by_param: dict[int, list[tuple[ParametricGroup, LineSet]]] = {}
    for (g, _), j, s in zip(pairs, owners, sets):
        by_param.setdefault(j, []).append((g, s))
    out = {}
    for j, p in enumerate(params):
        mine = [g for g in ctx.groups if j in g.params]
        found = by_param.get(j, [])
        intervals: list[Interval] = [(p.low, p.high)]
        if any(not g.live for g in mine):
            intervals = []
        for _, s in found:
            intervals = intersect(intervals, s.intervals)
        holding = next(((a, b) for a, b in intervals
                        if a <= p.nominal and (b is None or p.nominal <= b)), None)
        margin = Margin(p, groups=[g.index for g in mine], intervals=intervals,
                        nominal_consistent=holding is not None)
        if holding is not None:
            margin.low, margin.high = holding
            margin.limits_low = _ends(ctx, found, holding[0], "below", p)
            margin.limits_high = _ends(ctx, found, holding[1], "above", p)
            if verify:
                _check_margin(ctx, margin, found, lines[j])
        out[p.name] = margin
    return out


def _ends(ctx: _Context, found, t: Fraction | None, side: str, p: Parameter) -> list[Limit]:
    if t is None:
        return []
    limits = [ctx.limit(c) for _, s in found for c in s.causes.get((t, side), [])]
    if (side == "below" and t == p.low) or (side == "above" and t == p.high):
        limits.append(Limit("range", f"the range of {p.name} "
                            + ("starts here" if side == "below" else "ends here"),
                            parameter=p.name))
    return limits


def _check_margin(ctx: _Context, margin: Margin, found, line: Line) -> None:
    p = margin.parameter
    for end, side in ((margin.low, "below"), (margin.high, "above")):
        if end is None or (side == "below" and end == p.low) or (side == "above"
                                                                 and end == p.high):
            continue
        beyond = _beyond(end, margin.intervals, side)
        for g, _ in found:
            verdict, _ = ctx.consistent(g, line.values(g, ctx.nominal, end))
            margin.checks.append(Check(f"{p.name} = end ({side})", end, True, verdict))
            if beyond is not None:
                verdict, report = ctx.consistent(g, line.values(g, ctx.nominal, beyond))
                margin.checks.append(Check(f"{p.name} just {side}", beyond, False, verdict))
                _activations(margin.limits_low if side == "below" else margin.limits_high,
                             g, report)


# --------------------------------------------------------------------------- on processors


def _nominal_on_processors(ctx: _Context, result: SensitivityResult,
                           max_events: int) -> ProcessorLine:
    """The nominal verdict on processors, each part decided once, and the parts ready
    for the lines.

    The verdict is §4b's (``analyze_skeleton(processors=True)``), computed part by
    part here so that each line reuses the outcome of the parts it does not move;
    an overrun ends a part's simulation at once (the engine would go on looking
    for a regime, which ``analyze`` needs for its figures, not for a verdict).
    """
    from ..analyze import analyze_skeleton

    ctx.analyses += 1
    # The groups (and liveness) only: the schedule is decided by the parts below.
    report = analyze_skeleton(ctx.skeleton, semiflow_max_places=0, structure=ctx.structure)
    result.processors = True
    ctx.max_events = max_events
    on = ProcessorLine(ctx.skeleton, ctx.params, ctx.nominal, report.groups, max_events,
                       nominal_platform=report.platform)
    ctx.schedulable, ctx.unschedulable = on.decide_nominal(report.live)
    result.schedulable = ctx.schedulable
    return on


# --------------------------------------------------------------------------- formulas


def _formula_report(g: ParametricGroup, f: GroupFormula, params: Sequence[Parameter],
                    nominal_result) -> GroupFormulaReport:
    names = g.names

    def circuit(c) -> list[str]:
        return [names[int(g.src[p])] for p in c.places]

    terms = [Term(c.holding.const, {params[j].name: k for j, k in c.holding.coef}, c.tokens,
                  circuit(c)) for c in f.terms]
    pace = []
    for region in f.regions:
        inequalities = [({params[j].name: k for j, k in iq.coefficients if k}, iq.bound,
                         circuit(iq.circuit)) for iq in region.inequalities]
        pace.append(PaceReport(region.clock, region.empty, inequalities,
                               circuit(region.blocking) if region.blocking else []))
    return GroupFormulaReport(
        group=g.index, tasks=list(g.tasks), clocks=list(g.clocks),
        parameters=[params[j].name for j in g.params], exact=f.exact,
        cycle_time=nominal_result.cycle_time_max,
        rate_consistent=nominal_result.rate_consistent, terms=terms,
        derivatives={params[j].name: d for j, d in f.derivatives.items()}, pace=pace,
        symbols={params[j].name: params[j].symbol for j in g.params})


def _methods(result: SensitivityResult, max_parameters: int, verify: bool) -> dict[str, str]:
    effort = result.effort
    out = {}
    line = ("exact line search in each group: Newton steps on overrun certificates (longest "
            "paths, weights h - P·m) and upper envelopes of cycle ratios (Howard)")

    def spent(e: dict) -> str:
        calls, points = e["rounds"], e["points"]
        return (f"{calls:,} batched oracle call{'s' * (calls != 1)}, "
                f"{points:,} point{'s' * (points != 1)}")

    if "scaling" in effort:
        out["scaling"] = f"{line}, intersected over groups; {spent(effort['scaling'])}"
    if "margins" in effort:
        out["margins"] = f"{line}, one line per parameter; {spent(effort['margins'])}"
    else:
        out["margins"] = "not computed (`margins` False)"
    if "formulas" in effort:
        out["formulas"] = (
            f"up to {max_parameters} parameters per group: cutting planes, Howard at every "
            "vertex and ray of the box (exact double description); more: critical circuits "
            f"and one-sided derivatives at nominal; {spent(effort['formulas'])}")
    if result.processors:
        out["on processors"] = (
            "within the per-task figures above (an upper bound): the exact §4b schedule of "
            "each part (tasks joined by a group or a processor) simulated with every time an "
            "affine function of the line's parameter, so each run decides a whole interval "
            "of constant schedule order; the intervals are walked from the nominal value to "
            "the first that is not schedulable (each end decided at it and just beyond); "
            "a part whose groups are each one periodic unit of its summed work at its own "
            "priority on one processor (or a background task without clock) level by level "
            "from the most urgent down by the exact test of Lehoczky, Sha and Ding (1989), "
            "the schedule simulated only where it does not decide; a processor asked for more than "
            "all its time is proven not schedulable; each line simulates only the parts it "
            "moves (the others' events do not depend on it: their nominal verdict, decided "
            "once); nothing is searched where the nominal values are not schedulable or "
            "undecided; budgets: `max_events` firings per simulation and per figure, "
            f"{RUN_BUDGETS} × `max_events` for the whole run"
            + ("" if not result.scaling or result.scaling.exact
               else "; the scaling factor is only BOUNDED (see 'undecided')"))
    if verify:
        checks = result.checks
        bad = sum(not c.agrees for c in checks)
        where = ("analyze_skeleton on the group at each finite end and just beyond it"
                 + ("; on processors, on the skeleton of the parts the line moves "
                    "(processors=True)"
                    if result.processors else ""))
        if not checks:
            out["check"] = f"{where}: no finite end, nothing to check"
        else:
            out["check"] = (f"{where}: {len(checks):,} point{'s' * (len(checks) != 1)}, "
                            + ("all agree" if not bad else f"{bad} DISAGREE"))
    else:
        out["check"] = "not run (`verify` False)"
    return out
