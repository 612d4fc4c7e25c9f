"""What :func:`~tegraph.analysis.sensitivity.sensitivity` finds, by name, exact.

Plain dataclasses with Fractions (``None`` for an unbounded end); ``to_dict``
gives the JSON document's data (``docs/report.schema.json``), exact
numbers as strings. Rendering is :mod:`tegraph.report.sensitivity_text`'s job.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from maxplus.scalar import exact_text

from .. import notebook
from ..chains import ChainFigures
from .parameters import Parameter
from .parametric import ParametricGroup

__all__ = ["PER_TASK", "PROCESSORS", "ChainAtMargins", "Check", "GroupFormulaReport", "Limit",
           "Margin", "PaceReport", "Scaling", "SensitivityResult", "Term"]

Interval = tuple[Fraction, "Fraction | None"]

PROCESSORS = "processors"
PER_TASK = "processor per task"


def _intervals(intervals: list[Interval]) -> list[list[str | None]]:
    return [[exact_text(a), exact_text(b)] for a, b in intervals]


@dataclass
class Limit:
    """Why consistent values end at a point (seen just beyond it).

    ``kind``: ``"overrun"`` (``task`` overruns; ``events`` the path of the
    unrolled graph ending its activation after the tick, or the circuit
    slower than its clock), ``"pace"`` (the group's critical circuit
    ``events`` becomes slower than the source ``source_events``: its clock's
    tick when ``clock`` is set; a place between them is unbounded),
    ``"range"`` (the range of ``parameter`` ends there), ``"group"`` (group
    ``group`` is not consistent at any value).
    """

    kind: str
    detail: str
    group: int | None = None
    task: str | None = None
    clock: str | None = None
    activation: int | None = None
    events: list[str] = field(default_factory=list)
    source_events: list[str] = field(default_factory=list)
    parameter: str | None = None
    certificate: str | None = None
    tasks: list[str] = field(default_factory=list)
    """The tasks whose events ``events`` are, in order."""

    def to_dict(self) -> dict[str, Any]:
        """The limit as the JSON report holds it."""
        return {"kind": self.kind, "group": self.group, "task": self.task, "clock": self.clock,
                "tasks": self.tasks,
                "activation": self.activation, "certificate": self.certificate,
                "events": self.events, "source_events": self.source_events,
                "parameter": self.parameter, "detail": self.detail}


@dataclass
class Check:
    """One cross-check with the analysis of spec §4 (``analyze_skeleton``) at one point."""

    what: str
    value: Fraction
    expected: bool
    found: bool | None
    """Consistent according to the analysis; None when it could not decide (budget)."""

    @property
    def agrees(self) -> bool:
        """Whether the analysis found what the sensitivity expected."""
        return self.found == self.expected

    def to_dict(self) -> dict[str, Any]:
        """The check as the JSON report holds it."""
        return {"what": self.what, "value": exact_text(self.value), "expected": self.expected,
                "found": self.found}


@dataclass
class Scaling:
    """Every varied duration multiplied by one factor α >= 0, the rest unchanged."""

    parameters: list[str]
    intervals: list[Interval]
    factor: Fraction | None
    """The upper end of the interval holding 1; None when unbounded or when 1 is not in one."""
    nominal_consistent: bool
    limits: list[Limit] = field(default_factory=list)
    """What limits the factor (at ``factor``); when 1 is inconsistent, why (at 1)."""
    nearest_below: Fraction | None = None
    nearest_above: Fraction | None = None
    """When 1 is inconsistent: the closest consistent factors below and above (None: none)."""
    limits_below: list[Limit] = field(default_factory=list)
    limits_above: list[Limit] = field(default_factory=list)
    checks: list[Check] = field(default_factory=list)
    semantics: str = PER_TASK
    """``"processors"``: live, consistent (§4) and schedulable on its processors (§4b);
    ``"processor per task"``: live and consistent (§4), every task on a processor of its own."""
    exact: bool = True
    """False: ``factor`` (or a nearest factor) is not proven; ``bounds`` says how far it is."""
    bounds: tuple[Fraction | None, Fraction | None] | None = None
    """When not exact: (proven schedulable up to, at most) for the factor."""
    per_task: Scaling | None = None
    """On processors: the same figures with a processor per task (an upper bound of
    the factor: ``docs/sensitivity.md``)."""
    breakpoints: int = 0
    """On processors: intervals of constant schedule order visited."""
    attained: bool = True
    """On processors: False when ``factor`` is a supremum that is not attained: every
    factor below it is schedulable, ``factor`` itself is not (the interval holding 1 is
    open there; ``limits`` says what happens at it)."""
    why_undecided: list[str] = field(default_factory=list)
    method: str = "with a processor per task: exact line search ((max,+) certificates)"
    """How the figure was decided (on processors: the theorem, the walk, or undecided)."""
    not_searched: str | None = None
    """On processors: why no factor was searched ("none: not schedulable as it is ...",
    or "undecided: ..." naming the budget); None: searched."""

    def to_dict(self) -> dict[str, Any]:
        """The scaling factor as the JSON report holds it."""
        out = {
            "parameters": self.parameters,
            "nominal_consistent": self.nominal_consistent,
            "factor": exact_text(self.factor),
            "limits": [x.to_dict() for x in self.limits],
            "nearest_below": exact_text(self.nearest_below),
            "nearest_above": exact_text(self.nearest_above),
            "checks": [c.to_dict() for c in self.checks],
            "semantics": self.semantics,
            "exact": self.exact,
            "bounds": None if self.bounds is None else [exact_text(b) for b in self.bounds],
            "why_undecided": self.why_undecided,
            "method": self.method,
        }
        if self.semantics == PROCESSORS:
            out["not_searched"] = self.not_searched
            out["attained"] = self.attained
        if self.per_task is not None:
            out["per_task"] = {"factor": exact_text(self.per_task.factor),
                               "intervals": _intervals(self.per_task.intervals),
                               "nominal_consistent": self.per_task.nominal_consistent,
                               "limits": [x.to_dict() for x in self.per_task.limits]}
            out["breakpoints"] = self.breakpoints
        return out


@dataclass
class Margin:
    """The consistent values of one parameter alone (the others nominal) within its range.

    Consistency is that of the groups the parameter belongs to (``groups``):
    the other groups do not depend on it.
    """

    parameter: Parameter
    groups: list[int]
    intervals: list[Interval]
    nominal_consistent: bool
    low: Fraction | None = None
    high: Fraction | None = None
    """The interval holding the nominal value (None: unbounded above, or no such interval)."""
    limits_low: list[Limit] = field(default_factory=list)
    limits_high: list[Limit] = field(default_factory=list)
    checks: list[Check] = field(default_factory=list)
    semantics: str = PER_TASK
    """As :attr:`Scaling.semantics`; on processors ``intervals`` holds the interval
    around the nominal value only (the others are not searched), or, when the nominal
    value is not schedulable, every schedulable interval found along the range."""
    low_attained: bool = True
    high_attained: bool = True
    """On processors: False when that end of the interval around the nominal value is
    a bound, not a value of it (schedulable up to the end, not at it)."""
    intervals_open: list[tuple[bool, bool]] | None = None
    """On processors: for each of ``intervals``, whether its low and high ends are
    excluded (None: every interval closed)."""
    exact: bool = True
    bounds: tuple[Fraction | None, Fraction | None] | None = None
    """When not exact: (low end at most, high end at least) proven; the ends lie
    between these and the per-task ends."""
    per_task: Margin | None = None
    why_undecided: list[str] = field(default_factory=list)
    method: str = "with a processor per task: exact line search ((max,+) certificates)"
    not_searched: str | None = None
    """As :attr:`Scaling.not_searched`, for its own part(s)."""

    def to_dict(self) -> dict[str, Any]:
        """The margin as the JSON report holds it."""
        out = self._dict()
        out.update({"semantics": self.semantics, "exact": self.exact,
                    "bounds": None if self.bounds is None
                    else [exact_text(b) for b in self.bounds],
                    "why_undecided": self.why_undecided, "method": self.method})
        if self.semantics == PROCESSORS:
            out["not_searched"] = self.not_searched
            out["low_attained"] = self.low_attained
            out["high_attained"] = self.high_attained
            out["intervals_open"] = [list(o) for o in self.intervals_open or
                                     [(False, False)] * len(self.intervals)]
        if self.per_task is not None:
            pt = self.per_task
            out["per_task"] = {"low": exact_text(pt.low) if pt.nominal_consistent else None,
                               "high": exact_text(pt.high),
                               "nominal_consistent": pt.nominal_consistent,
                               "intervals": _intervals(pt.intervals)}
        return out

    def _dict(self) -> dict[str, Any]:
        return {
            "kind": self.parameter.kind,
            "nominal": exact_text(self.parameter.nominal),
            "range": [exact_text(self.parameter.low), exact_text(self.parameter.high)],
            "range_low_open": self.parameter.low_open,
            "groups": self.groups,
            "nominal_consistent": self.nominal_consistent,
            "low": exact_text(self.low) if self.nominal_consistent else None,
            "high": exact_text(self.high),
            "intervals": _intervals(self.intervals),
            "limits_low": [x.to_dict() for x in self.limits_low],
            "limits_high": [x.to_dict() for x in self.limits_high],
            "checks": [c.to_dict() for c in self.checks],
        }


@dataclass
class Term:
    """``(constant + Σ coefficient·parameter) / tokens``: one circuit's ratio."""

    constant: Fraction
    coefficients: dict[str, int]
    tokens: int
    circuit: list[str]

    def to_dict(self) -> dict[str, Any]:
        """The term as the JSON report holds it."""
        return {"constant": exact_text(self.constant),
                "coefficients": {p: str(c) for p, c in self.coefficients.items()},
                "tokens": self.tokens, "circuit": self.circuit}


@dataclass
class PaceReport:
    """Where a clocked group keeps pace with ``clock``: every inequality holds."""

    clock: str
    empty: bool
    inequalities: list[tuple[dict[str, Fraction], Fraction, list[str]]]
    """``(coefficients, bound, circuit)``: ``Σ coefficient·parameter <= bound``."""
    blocking: list[str] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        """The keep-pace region as the JSON report holds it."""
        return {"clock": self.clock, "empty": self.empty, "blocking_circuit": self.blocking,
                "inequalities": [{"coefficients": {p: exact_text(c) for p, c in co.items()},
                                  "bound": exact_text(b), "circuit": circ}
                                 for co, b, circ in self.inequalities]}


@dataclass
class GroupFormulaReport:
    """One live group's cycle time as a function of its parameters."""

    group: int
    tasks: list[str]
    clocks: list[str]
    parameters: list[str]
    exact: bool
    cycle_time: Fraction
    """At the nominal point."""
    rate_consistent: bool
    terms: list[Term]
    derivatives: dict[str, tuple[Fraction, Fraction]]
    """One-sided partial derivatives at the nominal point: (left, right)."""
    pace: list[PaceReport]
    symbols: dict[str, str]

    def expression(self) -> Any:
        """The formula as a sympy expression (``Max`` of the terms, exact rationals)."""
        import sympy

        symbol = {p: sympy.Symbol(s, nonnegative=True) for p, s in self.symbols.items()}
        parts = [(sympy.Rational(t.constant.numerator, t.constant.denominator)
                  + sum((c * symbol[p] for p, c in t.coefficients.items()), sympy.Integer(0)))
                 / t.tokens for t in self.terms]
        return sympy.Max(*parts) if len(parts) > 1 else parts[0]

    def to_dict(self) -> dict[str, Any]:
        """The group's formula as the JSON report holds it."""
        return {
            "group": self.group,
            "tasks": self.tasks,
            "clocks": self.clocks,
            "parameters": self.parameters,
            "exact": self.exact,
            "cycle_time": exact_text(self.cycle_time),
            "rate_consistent": self.rate_consistent,
            "period_terms": [t.to_dict() for t in self.terms],
            "expression": str(self.expression()),
            "derivatives": {p: {"left": exact_text(a), "right": exact_text(b)}
                            for p, (a, b) in self.derivatives.items()},
            "keeps_pace": [r.to_dict() for r in self.pace],
        }


@dataclass
class ChainAtMargins:
    """One chain's first use (spec §4c) at the nominal values, at the scaling factor and at
    each end of every margin (None: that end is unbounded, or the figure undecided, said
    in ``why``)."""

    tasks: tuple[str, ...]
    processors: bool
    """On the skeleton's processors (§4b); False: with a processor per task (§3)."""
    nominal: ChainFigures
    at_factor: ChainFigures | None = None
    """At the scaling factor; None: no factor was reported."""
    margins: dict[str, tuple[ChainFigures | None, ChainFigures | None]] = field(
        default_factory=dict)
    """Per parameter, at its margin's low and high ends (None: no such end)."""
    outside: list[str] = field(default_factory=list)
    """Parameters outside the chain's parts: the figure there is the nominal one."""

    def to_dict(self) -> dict[str, Any]:
        """The entry of the sensitivity's JSON ``chains``: each first use, exact."""

        def first(f: ChainFigures | None) -> dict[str, Any] | None:
            return None if f is None else {"first_use": exact_text(f.first_use),
                                           "why_undecided": f.why_undecided}

        return {"tasks": list(self.tasks), "processors": self.processors,
                "nominal": first(self.nominal), "at_factor": first(self.at_factor),
                "margins": {name: {"low": first(lo), "high": first(hi)}
                            for name, (lo, hi) in self.margins.items()},
                "outside": self.outside}


@dataclass
class SensitivityResult:
    """Everything ``tegraph sensitivity`` reports about one skeleton.

    See Also
    --------
    tegraph.sensitivity : makes it.
    tegraph.report.to_json : its JSON document.

    Examples
    --------
    >>> from tegraph import Skeleton, sensitivity
    >>> r = sensitivity(Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 10}}}))
    >>> r.consistent, r.exit_status, [p.name for p in r.parameters]
    (True, 0, ['A.duration'])
    """

    name: str
    unit: str
    parameters: tuple[Parameter, ...]
    live: bool
    consistent: bool
    """At the nominal values."""
    groups: list[list[str]]
    scaling: Scaling | None
    margins: dict[str, Margin]
    formulas: list[GroupFormulaReport] | None
    methods: dict[str, str] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    effort: dict[str, dict[str, int | float]] = field(default_factory=dict)
    """Per part: oracle rounds (batched calls), points asked, analyses run, seconds."""
    source: str | None = None
    processors: bool = False
    """The scaling factor and margins are on the skeleton's processors (§4b)."""
    schedulable: bool | None = None
    """On processors, at the nominal values (§4b; None: undecided or not asked)."""
    chains: list[ChainAtMargins] = field(default_factory=list)
    """Each chain's first use at the nominal values, the scaling factor and the ends of
    every margin (spec §4c: what using a margin costs in latency)."""
    models: dict[int, ParametricGroup] = field(default_factory=dict, repr=False, compare=False)
    """The live groups' parametric event graphs by group index
    (:class:`~.parametric.ParametricGroup`), for drawings that ask the oracle
    again (:func:`~.region.consistent_region`); not part of the JSON."""

    def _repr_html_(self) -> str:
        """The result as a notebook shows it (:func:`tegraph.report.html.render_html`)."""
        return notebook.html(self)

    @property
    def checks(self) -> list[Check]:
        """Every cross-check against the analysis, the scaling factor's then each margin's."""
        out = list(self.scaling.checks) if self.scaling else []
        for m in self.margins.values():
            out += m.checks
        return out

    @property
    def exit_status(self) -> int:
        """0 consistent (and, on processors, schedulable) at the nominal values; 1 not
        (the sensitivity is reported anyway)."""
        if self.processors:
            return 0 if self.consistent and self.schedulable else 1
        return 0 if self.consistent else 1

    def to_dict(self) -> dict[str, Any]:
        """The body of the JSON report (``docs/report.schema.json``, ``$defs/sensitivity``)."""
        scaling = self.scaling
        return {
            "name": self.name,
            "unit": self.unit,
            "live": self.live,
            "consistent": self.consistent,
            "processors": self.processors,
            "schedulable": self.schedulable,
            "parameters": [{"name": p.name, "kind": p.kind, "nominal": exact_text(p.nominal),
                            "low": exact_text(p.low), "high": exact_text(p.high),
                            "low_open": p.low_open} for p in self.parameters],
            "scaling_factor": None if scaling is None else exact_text(scaling.factor),
            "scaling_intervals": None if scaling is None else _intervals(scaling.intervals),
            "scaling": None if scaling is None else scaling.to_dict(),
            "margins": {name: m.to_dict() for name, m in self.margins.items()},
            "groups": None if self.formulas is None else [f.to_dict() for f in self.formulas],
            "chains": [c.to_dict() for c in self.chains],
            "checks_agree": all(c.agrees for c in self.checks),
            "methods": self.methods,
            "effort": self.effort,
            "notes": self.notes,
        }
