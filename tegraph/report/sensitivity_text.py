"""The sensitivity report as text an engineer reads in a minute, and as a JSON document.

Three parts, most useful first: how far all the varied durations can grow
together (the scaling factor), each parameter alone (its consistent values
and what ends them), each group's period as a formula. Exact values first,
a decimal beside them; every time carries its unit; the verdict is last.
"""

from __future__ import annotations

from fractions import Fraction
from functools import cache
from typing import Any

from tabulate import tabulate

from maxplus.scalar import display_text

from ..analysis.sensitivity.results import (
    GroupFormulaReport,
    Limit,
    PaceReport,
    Scaling,
    SensitivityResult,
)
from ._format import number

__all__ = ["formula_text", "render_sensitivity"]


def formula_text(expression: Any) -> str:
    """A sympy formula as text, its numbers as the input wrote them.

    A rational prints as its exact decimal when that terminates
    (:func:`maxplus.scalar.display_text`), else as its fraction; the expression
    itself and the JSON report (``str`` of it) stay sympy-exact.

    >>> import sympy
    >>> d = sympy.Symbol("d_A", nonnegative=True)
    >>> formula_text(sympy.Max(sympy.Rational(1037, 100), d + sympy.Rational(1, 3)))
    'Max(10.37, d_A + 1/3)'
    >>> formula_text((d + sympy.Rational(1037, 100)) / 2)
    'd_A/2 + 5.185'
    """
    return _decimal_printer().doprint(expression)


@cache
def _decimal_printer() -> Any:
    # sympy is imported on first use only, as in SensitivityResult.expression: importing
    # it takes about a second that commands without formulas should not pay.
    from sympy.printing.str import StrPrinter

    class DecimalPrinter(StrPrinter):
        def _print_Rational(self, expr: Any) -> str:
            return str(display_text(Fraction(int(expr.p), int(expr.q))))

    return DecimalPrinter()


def _interval(a: Fraction, b: Fraction | None, unit: str = "", open_low: bool = False,
              open_high: bool = False, low_excluded: bool = False) -> str:
    """``[a, b]``; ``open_low``: a period's range, open at 0; ``open_high`` and
    ``low_excluded``: an end that the interval does not hold.

    >>> _interval(Fraction(0), Fraction(25, 16), open_high=True)
    '[0, 1.5625)'
    """
    u = f" {unit}" if unit else ""
    left = "(" if (open_low and a == 0) or low_excluded else "["
    if b is None:
        return f"{left}{display_text(a)}, ∞)" + u
    if a == b:
        return f"{{{display_text(a)}}}" + u
    right = ")" if open_high else "]"
    return f"{left}{display_text(a)}, {display_text(b)}{right}" + u


def _intervals(intervals, unit: str = "", open_low: bool = False) -> str:
    if not intervals:
        return "none"
    return " ∪ ".join(_interval(a, b, unit, open_low) for a, b in intervals)


def _limit(limit: Limit) -> str:
    """The full sentence, with the activation of an overrun when the analysis gave it."""
    text = limit.detail
    if limit.kind == "overrun" and limit.activation is not None:
        text = text.replace(f"{limit.task} overruns",
                            f"{limit.task} overruns (at activation {limit.activation} just "
                            "beyond)", 1)
    return text


def _short(limit: Limit) -> str:
    """A few words for a table cell."""
    if limit.kind == "overrun":
        at = f" at activation {limit.activation}" if limit.activation is not None else ""
        return f"{limit.task} overruns{at}"
    if limit.kind == "pace":
        who = (f"circuit of {', '.join(limit.tasks)}" if limit.tasks
               else "circuit " + " -> ".join(limit.events))
        against = f"clock {limit.clock}" if limit.clock else "its free-running source"
        return f"{who} slower than {against}"
    if limit.kind == "range":
        return "end of its range"
    if limit.kind == "processors" and limit.task is not None:
        if limit.activation is not None:
            return f"{limit.task} overruns at activation {limit.activation} on its processors"
        return f"{limit.task} starved on its processors"
    return limit.detail


def render_sensitivity(result: SensitivityResult) -> str:
    """The human report (see the module docstring).

    Returns
    -------
    str
    """
    u = result.unit
    n_params = len(result.parameters)
    lines = [f"sensitivity of {result.name}" + (f" ({result.source})" if result.source else "")
             + f": {n_params} parameter{'s' * (n_params != 1)}, times in {u}"]
    lines.append("at the nominal values: " + _nominal(result))
    lines.append("consistent means live, every group rate-consistent, no overrun (spec §4); "
                 "a duration or period may make it so again further on (it is not monotone)")
    if result.processors:
        lines.append("schedulable means also no overrun, no growing place, no starved task "
                     "on its processors under preemptive fixed priorities (spec §4b): the "
                     "figures below are on its processors unless marked 'per task' (every "
                     "task on a processor of its own, §4, an upper bound of them)")
    if result.scaling is not None:
        lines += ["", *_scaling_lines(result)]
    lines += ["", *_margin_lines(result)]
    if result.chains:
        lines += ["", *_chain_lines(result)]
    if result.formulas is not None:
        lines += ["", *_formula_lines(result)]
    lines.append("")
    lines.append("how:")
    for key, text in result.methods.items():
        lines.append(f"  {key}: {text}")
    for note in result.notes:
        lines.append(f"note: {note}")
    lines.append("")
    lines.append(_verdict(result))
    return "\n".join(lines) + "\n"


def _nominal(result: SensitivityResult) -> str:
    text = "consistent" if result.consistent else "NOT CONSISTENT"
    if not result.processors:
        return text + " (every task on a processor of its own)"
    on = {True: "schedulable", False: "NOT SCHEDULABLE",
          None: "schedulability UNDECIDED"}[result.schedulable]
    return f"{text} with a processor per task, {on} on its processors"


def _scaling_lines(result: SensitivityResult) -> list[str]:
    s = result.scaling
    assert s is not None
    if s.per_task is not None:
        return _scaling_on_lines(result)
    count = len(s.parameters)
    lines = [f"all {count} varied duration{'s' * (count != 1)} multiplied by one factor α "
             "(the other times unchanged), every task on a processor of its own:"]
    lines.append("  consistent for " + (f"α in {_intervals(s.intervals)}" if s.intervals
                                         else "no α"))
    if s.nominal_consistent:
        if s.factor is None:
            lines.append("  scaling factor: none: nothing finite limits it (α can grow "
                         "without bound)")
        else:
            lines.append(f"  scaling factor {number(s.factor)} with a processor per task: the "
                         f"durations can all grow {number(s.factor)} times together")
            for limit in s.limits:
                lines.append(f"    limit: {_limit(limit)}")
    else:
        lines.append("  α = 1 (the nominal durations) is NOT consistent:")
        for limit in s.limits:
            lines.append(f"    because {_limit(limit)}")
        below = "none" if s.nearest_below is None else number(s.nearest_below)
        above = "none" if s.nearest_above is None else number(s.nearest_above)
        lines.append(f"  nearest consistent factors: below {below}, above {above}")
    return lines


def _scaling_on_lines(result: SensitivityResult) -> list[str]:
    s = result.scaling
    assert s is not None and s.per_task is not None
    pt = s.per_task
    count = len(s.parameters)
    lines = [f"all {count} varied duration{'s' * (count != 1)} multiplied by one factor α "
             "(the other times unchanged), ON ITS PROCESSORS:"]
    how = (f"exact: every breakpoint between is decided, {s.breakpoints} interval"
           f"{'s' * (s.breakpoints != 1)} of constant verdict walked")
    if s.not_searched is not None:
        lines.append(f"  scaling factor on its processors: {s.not_searched}")
        for limit in s.limits:
            lines.append(f"    because {_limit(limit)}")
    elif s.nominal_consistent:
        low, high = s.intervals[0]
        if s.exact and s.factor is not None:
            lines.append(f"  schedulable for α in {_interval(low, high, open_high=not s.attained)}"
                         f" (the interval holding 1; {how})")
            if s.attained:
                lines.append(f"  scaling factor {number(s.factor)} on its processors: the "
                             f"durations can all grow {number(s.factor)} times together")
            else:
                lines.append(f"  scaling factor {number(s.factor)} on its processors, a "
                             "supremum NOT attained: the durations can all grow together by "
                             f"any factor below {number(s.factor)}, not by {number(s.factor)} "
                             "itself")
        elif s.exact:
            lines.append(f"  schedulable for α in [{display_text(low)}, ∞) ({how})")
            lines.append("  scaling factor: none: nothing finite limits it")
        else:
            proven, most = s.bounds  # type: ignore[misc]
            lines.append(f"  scaling factor on its processors: a BOUND only, between "
                         f"{number(proven)} (schedulable on [1, {display_text(proven)}], "
                         "every breakpoint in between decided) and "
                         + ("∞" if most is None else number(most))
                         + " (the factor with a processor per task, an upper bound)")
            for why in s.why_undecided:
                lines.append(f"    undecided: {why}")
        for limit in s.limits:
            lines.append(f"    limit: {_limit(limit)}")
    else:
        lines.append("  α = 1 (the nominal durations) is NOT schedulable on its processors:")
        for limit in s.limits:
            lines.append(f"    because {_limit(limit)}")
        for why in s.why_undecided:
            lines.append(f"    undecided: {why}")
        below = "none" if s.nearest_below is None else number(s.nearest_below)
        above = "none" if s.nearest_above is None else number(s.nearest_above)
        lines.append(f"  nearest schedulable factors: below {below}, above {above}"
                     + ("" if s.exact else " (NOT exact: a search stopped, see 'undecided')"))
    per = ("none" if pt.factor is None else number(pt.factor)) if pt.nominal_consistent \
        else "1 is not consistent"
    lines.append(f"  per task (every task on a processor of its own, §4): consistent for α in "
                 f"{_intervals(pt.intervals)}; scaling factor {per} with a processor per task")
    lines.append(f"  method: {s.method}")
    return lines


def _chain_lines(result: SensitivityResult) -> list[str]:
    """Each chain's first use (spec §4c) at the nominal values, at the scaling factor and at
    each end of every margin: what using a margin costs in latency."""
    u = result.unit

    def first(f: Any) -> str:
        if f is None:
            return "-"
        return "undecided" if f.first_use is None else f"{display_text(f.first_use)} {u}"

    lines = []
    for c in result.chains:
        where = "on its processors" if c.processors else "with a processor per task"
        lines.append(f"latency of the chain {' -> '.join(c.tasks)} (first use {where}, spec "
                     f"§4c): {first(c.nominal)} at the nominal values"
                     + ("" if c.at_factor is None
                        else f", {first(c.at_factor)} at the scaling factor"))
        rows = [[name, first(low), first(high)] for name, (low, high) in c.margins.items()]
        if rows:
            table = tabulate(rows, headers=["parameter", "at the margin's low end",
                                            "at its high end"], disable_numparse=True)
            lines += ["  " + row for row in table.splitlines()]
        if c.outside:
            lines.append(f"  unchanged ({first(c.nominal)}) at the margins of "
                         f"{len(c.outside)} parameter(s) outside the chain's parts")
        undecided = {f.why_undecided or "" for f in [
            c.nominal, c.at_factor, *(x for pair in c.margins.values() for x in pair)]
            if f is not None and f.first_use is None}
        lines += [f"  undecided: {why}" for why in sorted(undecided)]
    return lines


def _margin_lines(result: SensitivityResult) -> list[str]:
    if result.processors:
        return _margin_on_lines(result)
    return _margin_per_task_lines(result)


def _margin_on_lines(result: SensitivityResult) -> list[str]:
    u = result.unit
    rows = []
    for m in result.margins.values():
        p = m.parameter
        pt = m.per_task
        if m.not_searched is not None:
            undecided = m.not_searched.startswith("undecided")
            around = "UNDECIDED at nominal" if undecided else "NOT at nominal"
            grow, why = "-", "-"
        elif m.nominal_consistent and m.exact:
            grow = ("unbounded" if m.high is None else
                    f"{'' if m.high_attained else 'less than '}+{number(m.high - p.nominal)}")
            around = _interval(m.low, m.high, "", p.low_open,  # type: ignore[arg-type]
                               not m.high_attained, not m.low_attained)
            why = "; ".join(dict.fromkeys(_short(x) for x in m.limits_high)) or "-"
        elif m.nominal_consistent:
            lo, hi = m.bounds  # type: ignore[misc]
            if hi is None:
                # A walk stops undecided only at an end it reached: no proven high end
                # means the high end is exact and unbounded; the low end is the bound.
                around = f"BOUND: [{display_text(lo)}, ∞) proven"
                grow = "unbounded"
                why = "; ".join(dict.fromkeys(_short(x) for x in m.limits_high)) or "-"
            else:
                around = f"BOUND: [{display_text(lo)}, {display_text(hi)}] proven"
                grow, why = f"at least +{number(hi - p.nominal)}", "undecided beyond"
        else:
            grow, around, why = "-", "NOT at nominal", "-"
            if m.intervals:
                opens = m.intervals_open or [(False, False)] * len(m.intervals)
                around += "; schedulable on " + " ∪ ".join(
                    _interval(a, b, "", p.low_open, high_open, low_open)
                    for (a, b), (low_open, high_open) in zip(m.intervals, opens))
            elif m.exact and m.not_searched is None:
                around += "; schedulable nowhere in its range"
        if pt is None or not pt.nominal_consistent:
            per = "NOT at nominal"
            if pt is not None and pt.intervals:
                per += f"; consistent on {_intervals(pt.intervals, '', p.low_open)}"
        else:
            per = _interval(pt.low, pt.high, "", p.low_open)  # type: ignore[arg-type]
        rows.append([p.symbol, number(p.nominal), around, grow, why, per])
    lines = [f"each parameter alone, the others nominal, ON ITS PROCESSORS (schedulability "
             f"of its part: its groups and the tasks sharing their processors; times in {u}):"]
    table = tabulate(rows, headers=["parameter", "nominal", "schedulable around nominal",
                                    "can grow by", "limited above by",
                                    "per task (consistent around nominal)"])
    lines += ["  " + line for line in table.splitlines()]
    lines.append("  (on processors the interval around the nominal value is searched; where the "
                 "nominal value is not schedulable, every schedulable interval of the range of "
                 "a parameter named with --vary, or of one whose part is decided by its "
                 "levels; ')' or '(': an end excluded; the per-task column is every task on a "
                 "processor of its own, an upper bound)")
    methods: dict[str, list[str]] = {}
    for m in result.margins.values():
        methods.setdefault(m.method, []).append(m.parameter.symbol)
    for method, who in methods.items():
        lines.append(f"  method ({', '.join(who)}): {method}")
    return lines


def _margin_per_task_lines(result: SensitivityResult) -> list[str]:
    u = result.unit
    rows = []
    for m in result.margins.values():
        p = m.parameter
        if m.nominal_consistent:
            grow = "unbounded" if m.high is None else f"+{number(m.high - p.nominal)}"
            # Type: a margin consistent at nominal has its low end.
            around = _interval(m.low, m.high, "", p.low_open)  # type: ignore[arg-type]
            why = "; ".join(dict.fromkeys(_short(x) for x in m.limits_high)) or "-"
            others = [iv for iv in m.intervals if iv != (m.low, m.high)]
        else:
            grow, around, why = "-", "NOT at nominal", "-"
            others = m.intervals
        rows.append([p.symbol, number(p.nominal), around, grow, why,
                     _intervals(others, "", p.low_open) if others else "-"])
    lines = [f"each parameter alone, the others nominal (consistency of its group, every "
             f"task on a processor of its own; times in {u}):"]
    table = tabulate(rows, headers=["parameter", "nominal", "consistent around nominal",
                                    "can grow by", "limited above by", "other consistent values"])
    lines += ["  " + line for line in table.splitlines()]
    lines.append("  (a duration's 'can grow by' sees overruns, which the slack of `analyze` "
                 "does not; full paths and circuits: in the JSON document)")
    return lines


def _formula_lines(result: SensitivityResult) -> list[str]:
    u = result.unit
    lines = ["period of each live group as a function of its parameters (cycle time, "
             f"in {u}; its period where rate-consistent; "
             + ", ".join(f"{p.symbol} = {p.name}" for p in result.parameters[:6])
             + (", ..." if len(result.parameters) > 6 else "") + "):"]
    still = [f for f in result.formulas or () if not f.parameters]
    symbol = {p.name: p.symbol for p in result.parameters}
    for f in result.formulas or ():
        if f.parameters:
            lines += _group_formula_lines(f, symbol)
    if still:
        shown = ", ".join(str(f.group) for f in still[:12]) + (", ..." if len(still) > 12 else "")
        lines.append(f"  groups {shown}: do not depend on the varied parameters "
                     f"({len(still)} group{'s' * (len(still) != 1)})")
    return lines


def _group_formula_lines(f: GroupFormulaReport, symbol: dict[str, str]) -> list[str]:
    """One group's period formula (or its critical terms), derivatives and pace regions."""
    clocks = f", clocks {', '.join(f.clocks)}" if f.clocks else ", no clock"
    head = f"  group {f.group} ({', '.join(f.tasks)}{clocks}): "
    if f.exact:
        lines = [head + f"{formula_text(f.expression())} (exact over the whole range)"]
    else:
        lines = [head + f"{number(f.cycle_time)} at nominal, {len(f.parameters)} "
                 "parameters: only the terms critical there and the exact one-sided "
                 "derivatives",
                 f"    critical terms: {formula_text(f.expression())}"]
    moving = {p: d for p, d in f.derivatives.items() if d != (Fraction(0), Fraction(0))}
    if moving:
        lines.append("    at nominal, d(period)/d(parameter) (left, right): "
                     + ", ".join(f"{p} ({display_text(a)}, {display_text(b)})"
                                 for p, (a, b) in moving.items()))
    lines += [_pace_line(region, symbol) for region in f.pace]
    return lines


def _pace_line(region: PaceReport, symbol: dict[str, str]) -> str:
    """Where the group keeps pace with one clock: never, everywhere, or inequalities."""
    if region.empty:
        why = (f": circuit {' -> '.join(region.blocking)} alone is slower"
               if region.blocking else "")
        return f"    keeps pace with clock {region.clock}: never in the range{why}"
    if not region.inequalities:
        return f"    keeps pace with clock {region.clock}: everywhere in the range"
    parts = [_inequality({symbol[n]: c for n, c in co.items()}, b)
             for co, b, _ in region.inequalities]
    return f"    keeps pace with clock {region.clock} where: " + ", ".join(parts)


def _inequality(coefficients: dict[str, Fraction], bound: Fraction) -> str:
    """``Σ c·x <= b`` with every coefficient positive: negative terms go to the right side.

    >>> F = Fraction
    >>> _inequality({"d_A": F(1), "P_c": F(-1)}, F(0)), _inequality({"d_A": F(1, 2)}, F(3))
    ('d_A <= P_c', '0.5·d_A <= 3')
    """
    def side(terms: list[tuple[str, Fraction]], constant: Fraction) -> str:
        parts = [name if c == 1 else f"{display_text(c)}·{name}" for name, c in terms]
        if constant or not parts:
            parts.append(display_text(constant) if constant >= 0 or not parts
                         else f"- {display_text(-constant)}")
        return " + ".join(parts).replace("+ - ", "- ")

    left = [(n, c) for n, c in coefficients.items() if c > 0]
    right = [(n, -c) for n, c in coefficients.items() if c < 0]
    if not left:
        return f"{side([], -bound)} <= {side(right, Fraction(0))}"
    return f"{side(left, Fraction(0))} <= {side(right, bound)}"


def _verdict(result: SensitivityResult) -> str:
    state = "consistent" if result.consistent else "NOT CONSISTENT"
    if result.processors:
        state = _nominal(result)
    parts = [f"verdict: {state} at the nominal values"]
    s = result.scaling
    if s is not None and s.per_task is not None:
        parts.append(_scaling_verdict_on(s))
    elif s is not None:
        parts.append(_scaling_verdict_per_task(s))
    checks = result.checks
    if checks:
        bad = sum(not c.agrees for c in checks)
        parts.append("every end cross-checked with the analysis" if not bad
                     else f"{bad} cross-check(s) DISAGREE")
    return "; ".join(parts) + f" (exit status {result.exit_status})"


def _scaling_verdict_on(s: Scaling) -> str:
    """The scaling factor on processors, in a few words for the verdict line."""
    where = "on its processors"
    if s.not_searched is not None:
        return (f"no scaling factor {where}: "
                + ("undecided at the nominal values" if s.not_searched.startswith("undecided")
                   else "not schedulable as it is"))
    if s.nominal_consistent and s.exact and s.factor is not None and not s.attained:
        return (f"the varied durations can grow together by any factor below "
                f"{number(s.factor)} {where} (a supremum, not attained)")
    if s.nominal_consistent and s.exact and s.factor is not None:
        return f"the varied durations can grow together by a factor {number(s.factor)} {where}"
    if s.nominal_consistent and s.exact:
        return f"the varied durations can grow together without bound {where}"
    if s.nominal_consistent:
        return f"the scaling factor {where} is only bounded (undecided)"
    if s.nearest_below is not None or s.nearest_above is not None:
        return f"some other scaling of the durations is schedulable {where}"
    if s.exact:
        return f"no scaling of the durations makes it schedulable {where}"
    return f"no schedulable scaling found {where} (undecided)"


def _scaling_verdict_per_task(s: Scaling) -> str:
    """The scaling factor with a processor per task, in a few words for the verdict line."""
    if s.nominal_consistent and s.factor is not None:
        by_range = all(x.kind == "range" for x in s.limits) and s.limits
        return (f"the varied durations can grow together by a factor "
                f"{number(s.factor)} with a processor per task"
                + (" (up to their ranges)" if by_range else ""))
    if s.nominal_consistent:
        return "the varied durations can grow together without bound"
    if s.nearest_below is not None or s.nearest_above is not None:
        return "some other scaling of the durations is consistent"
    return "no scaling of the durations makes it consistent"
