"""Each group's cycle time as an exact formula of the parameters, and where it keeps pace.

A group's cycle time is ``λ(θ) = max over its circuits γ of (c_γ + g_γ·θ)/m_γ``
(Baccelli et al. [1]_, Thm 3.112): a convex piecewise-affine function whose
pieces are circuits. Over a box of a few parameters, the *non-redundant*
terms (those that are the maximum on a full-dimensional part of the box) are
found by cutting planes with Howard's policy iteration [2]_ as the
separation oracle:

1. ``F`` is the maximum of the terms known (first: the critical circuit at
   the nominal point); ``E = {(θ, z) : θ in the box, z >= every term}`` is
   kept with its vertices and rays (:mod:`.polyhedra`).
2. At each vertex ``(θ_v, F(θ_v))`` Howard gives ``λ(θ_v)``; along each ray
   ``(r, r_z)`` of an unbounded box the largest slope ``max_γ g_γ·r / m_γ``.
   A larger value comes with its critical circuit: a new term, a cut.
3. When no vertex and no ray is cut, ``F = λ`` on the whole box: on a cell
   of F (where one term t is the maximum), ``λ`` is convex, so at a convex
   combination of vertices and rays ``λ <= Σ α·λ(v) + Σ μ·slope(r) =
   Σ α·t(v) + Σ μ·t'(r) = t``; and ``λ >= F`` always.

Each new term is a circuit not yet known (it exceeds F where found), so the
loop ends. A term is non-redundant when it spans a facet of E.

The region where a clocked group *keeps pace* with its clock C (``λ = P_C``)
is ``{θ in the box : t(θ) <= P_C(θ)}`` for each term t; redundant
inequalities are dropped one at a time (each tested against the others and
the box).

With more parameters than a formula is worth, the figures at the nominal
point are given instead: the one-sided partial derivatives of λ, which are
the largest and smallest slopes among the critical circuits. Those are the
circuits of the *tight* subgraph of Howard's potentials, so each derivative
is one more cycle-ratio problem (the slope as weight) on that subgraph.

References
----------
.. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
   and Linearity*, Wiley, 1992.
.. [2] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
   J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
   algebra", IFAC Conference on System Structure and Control, 1998.
"""

from __future__ import annotations

from collections.abc import Generator, Sequence
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from maxplus import max_cycle_ratio

from .oracle import Affine, Circuit, PointResult, _affine, _policy_circuit, evaluate
from .parameters import Parameter
from .parametric import ParametricGroup
from .polyhedra import Polyhedron, affine_rank

__all__ = ["GroupFormula", "PaceInequality", "PaceRegion", "period_formulas"]


@dataclass(frozen=True)
class PaceInequality:
    """``circuit``'s ratio at most the clock's period: ``Σ coef·θ <= bound``."""

    coefficients: tuple[tuple[int, Fraction], ...]
    bound: Fraction
    circuit: Circuit


@dataclass
class PaceRegion:
    """Where a clocked group keeps pace with ``clock`` (``λ = P``), inside the box."""

    clock: str
    inequalities: list[PaceInequality]
    empty: bool
    blocking: Circuit | None = None
    """When empty because of a circuit that never fits the period: that circuit."""


@dataclass
class GroupFormula:
    """A group's cycle time as a function of its parameters.

    ``exact``: ``terms`` are the non-redundant terms over the whole box (the
    cycle time is their maximum everywhere in it). Otherwise they are the
    critical terms at the nominal point only, and ``derivatives`` the exact
    one-sided partial derivatives there.
    """

    group: int
    params: tuple[int, ...]
    exact: bool
    terms: list[Circuit]
    derivatives: dict[int, tuple[Fraction, Fraction]]
    regions: list[PaceRegion] = field(default_factory=list)
    queries: int = 0


def period_formulas(groups: Sequence[ParametricGroup], params: Sequence[Parameter],
                    max_parameters: int = 6) -> tuple[list[GroupFormula], int, int]:
    """The cycle-time formula of every live group (module docstring).

    Parameters
    ----------
    groups : sequence of ParametricGroup
        The live groups, from
        :func:`tegraph.analysis.sensitivity.parametric.parametric_groups`.
    params : sequence of Parameter
        The varied parameters and their boxes, from
        :func:`tegraph.analysis.sensitivity.parameters.parse_vary`.
    max_parameters : int
        A group with more parameters than this gets the derivatives at the
        nominal point instead of an exact formula.

    Returns
    -------
    (list of GroupFormula, rounds, queries)
        One formula per group, the batched oracle calls and the points asked.

    See Also
    --------
    tegraph.analysis.sensitivity.sensitivity : the analysis that reports them.
    maxplus.max_cycle_ratio : the oracle at each point.

    Notes
    -----
    The cycle time is the maximum of the circuits' ratios [1]_, a convex
    piecewise-affine function of the parameters; its pieces are found by
    cutting planes, each oracle call a policy iteration [2]_.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992.
    .. [2] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
       J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
       algebra", IFAC Conference on System Structure and Control, 1998.

    Examples
    --------
    One task of duration θ under a clock of period 5: ``λ(θ) = max(θ, 5)``,
    and the task keeps pace with its clock while ``θ <= 5``:

    >>> from tegraph.model.skeleton import Skeleton
    >>> from tegraph.analysis.sensitivity.parameters import parse_vary
    >>> from tegraph.analysis.sensitivity.parametric import parametric_groups
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 5}}})
    >>> ps = parse_vary(sk)
    >>> (f,), rounds, queries = period_formulas(parametric_groups(sk, ps), ps)
    >>> f.exact, [(t.holding.coef, str(t.holding.const), t.tokens) for t in f.terms]
    (True, [(((0, 1),), '0', 1), ((), '5', 1)])
    >>> q, = f.regions[0].inequalities
    >>> q.coefficients, q.bound
    (((0, Fraction(1, 1)),), Fraction(5, 1))
    """
    nominal = [p.nominal for p in params]
    exact = [g for g in groups if len(g.params) <= max_parameters]
    solvers = [_cutting_planes(g, params) for g in exact]
    out: dict[int, GroupFormula] = {}
    asked: list[list[tuple] | None] = [next(s) for s in solvers]
    rounds = queries = 0
    while any(a is not None for a in asked):
        batch, owners = [], []
        for k, qs in enumerate(asked):
            for q in qs or ():
                batch.append((exact[k], *q))
                owners.append(k)
        answers = evaluate(batch, overruns=False)
        rounds += 1
        queries += len(batch)
        per: dict[int, list[PointResult]] = {}
        for k, a in zip(owners, answers):
            per.setdefault(k, []).append(a)
        for k, got in per.items():
            try:
                asked[k] = solvers[k].send(got)
            except StopIteration as done:
                out[exact[k].index] = done.value
                asked[k] = None
    rest = [g for g in groups if len(g.params) > max_parameters]
    if rest:
        rounds += 2
        queries += len(rest)
        for formula in _at_nominal(rest, nominal):
            out[formula.group] = formula
    for g in groups:
        out[g.index].regions = _pace_regions(g, out[g.index], params)
    return [out[g.index] for g in groups], rounds, queries


def _box(params: Sequence[Parameter], dims: Sequence[int], extra: int = 0) -> Polyhedron:
    n = len(dims) + extra
    box = Polyhedron(n)
    for i, j in enumerate(dims):
        unit = tuple(Fraction(int(k == i)) for k in range(n))
        box.add((tuple(-x for x in unit), -params[j].low))
        high = params[j].high
        if high is not None:
            box.add((unit, high))
    return box


@dataclass
class _Envelope:
    """The terms found so far and their upper envelope: ``E`` is the set of points
    ``(θ, y)`` of the box with ``y`` above every term (one row per term)."""

    dims: Sequence[int]
    E: Polyhedron
    terms: dict[tuple, Circuit] = field(default_factory=dict)
    rows: dict[int, tuple] = field(default_factory=dict)
    """Row index in ``E`` -> term key."""

    def add(self, circuit: Circuit) -> None:
        key = circuit.key()
        if key in self.terms:
            return
        self.terms[key] = circuit
        m = circuit.tokens
        a = tuple(Fraction(circuit.holding.coefficient(j), m) for j in self.dims) \
            + (Fraction(-1),)
        self.rows[self.E.add((a, -circuit.holding.const / m))] = key

    def unchecked(self, checked: set[tuple]) -> list[tuple[bool, tuple]]:
        """The vertices and rays of E not yet checked (rays along y alone need none)."""
        p = len(self.dims)
        return [(is_vertex, point) for is_vertex, point, _ in self.E.generator_items()
                if (is_vertex, point) not in checked and (is_vertex or any(point[:p]))]

    def refine(self, unchecked_points: list[tuple[bool, tuple]], got: list[PointResult],
               checked: set[tuple]) -> None:
        """A generator whose true cycle time is above E's adds its critical circuit as
        a term; one that is not is checked for good."""
        p = len(self.dims)
        known = set(self.terms)
        for (is_vertex, point), answer in zip(unchecked_points, got):
            if answer.cycle_time_max > point[p]:
                circuit = answer.critical_circuit()
                if circuit.key() in known:
                    raise AssertionError("internal error: a known term exceeds the envelope")
                self.add(circuit)
            else:
                checked.add((is_vertex, point))

    def facets(self) -> list[Circuit]:
        """The non-redundant terms: those whose row is a facet of E, sorted."""
        items = self.E.generator_items()
        dimension = affine_rank([x for v, x, _ in items if v], [x for v, x, _ in items if not v])
        kept = []
        for row, key in self.rows.items():
            face = [(v, x) for v, x, mask in items if mask >> row & 1]
            rank = affine_rank([x for v, x in face if v], [x for v, x in face if not v])
            if rank == dimension - 1:
                kept.append(self.terms[key])
        kept.sort(key=lambda c: (c.tokens, c.holding.const, c.holding.coef))
        return kept


def _cutting_planes(group: ParametricGroup, params: Sequence[Parameter]
                    ) -> Generator[list[tuple], list[PointResult], GroupFormula]:
    dims = group.params
    nominal = {j: params[j].nominal for j in dims}
    got = yield [(nominal,)]
    envelope = _Envelope(dims, _box(params, dims, extra=1))
    n_queries = 1
    envelope.add(got[0].critical_circuit())
    checked: set[tuple] = set()
    while True:
        unchecked_points = envelope.unchecked(checked)
        if not unchecked_points:
            break
        got = yield [({j: point[i] for i, j in enumerate(dims)},) if is_vertex
                     else ({j: point[i] for i, j in enumerate(dims)}, True)
                     for is_vertex, point in unchecked_points]
        n_queries += len(unchecked_points)
        envelope.refine(unchecked_points, got, checked)
    kept = envelope.facets()
    derivatives = _derivatives_from_terms(kept, dims, nominal)
    return GroupFormula(group.index, dims, exact=True, terms=kept, derivatives=derivatives,
                        queries=n_queries)


def _derivatives_from_terms(terms: list[Circuit], dims: Sequence[int],
                            nominal: dict[int, Fraction]) -> dict[int, tuple[Fraction, Fraction]]:
    values = [c.ratio(nominal) for c in terms]
    top = max(values)
    active = [c for c, v in zip(terms, values) if v == top]
    out = {}
    for j in dims:
        slopes = [Fraction(c.holding.coefficient(j), c.tokens) for c in active]
        out[j] = (min(slopes), max(slopes))
    return out


def _at_nominal(groups: Sequence[ParametricGroup], nominal: Sequence[Fraction]
                ) -> list[GroupFormula]:
    """Critical terms and one-sided derivatives at the nominal point (module docstring)."""
    answers = evaluate([(g, {j: nominal[j] for j in g.params}) for g in groups], overruns=False)
    # One copy of each group's tight critical subgraph per (parameter, sign), all in one
    # Howard run: the largest ratio of a copy is the largest slope sign·coef/tokens.
    copies = []  # (group position, parameter, sign, first node, first arc, local arcs)
    src, dst, weight, tokens = [], [], [], []
    nodes = arcs_so_far = 0
    for k, (g, a) in enumerate(zip(groups, answers)):
        top = a.cycle_time_max
        on_top = np.array([c == top for c in a.cycle_time], dtype=bool)
        arcs = np.flatnonzero(a.tight & on_top[g.src] & on_top[g.dst])
        for j in g.params:
            for sign in (1, -1):
                copies.append((k, j, sign, nodes, arcs_so_far, arcs))
                src.append(g.src[arcs] + nodes)
                dst.append(g.dst[arcs] + nodes)
                weight.append(np.where(g.param[arcs] == j, sign, 0))
                tokens.append(g.tokens[arcs])
                nodes += g.n_events
                arcs_so_far += len(arcs)
    slopes: dict[tuple[int, int, int], tuple[Fraction, list[int]]] = {}
    if copies:
        all_src = np.concatenate(src)
        mcr = max_cycle_ratio(all_src, np.concatenate(dst),
                              np.concatenate(weight).astype(np.int64),
                              np.concatenate(tokens), n_nodes=nodes)
        ct = mcr.cycle_times
        policy = mcr.certificate.policy
        for k, j, sign, first_node, first_arc, arcs in copies:
            n = groups[k].n_events
            finite = {e: ct_e for e in range(first_node, first_node + n)
                      if (ct_e := ct[e]) is not None}
            best = max(finite, key=finite.__getitem__)  # the first of the largest, as before
            circuit = _policy_circuit(policy, all_src, best)
            slopes[k, j, sign] = (sign * finite[best],
                                  [int(arcs[a - first_arc]) for a in circuit])
    out = []
    for k, (g, a) in enumerate(zip(groups, answers)):
        terms: dict[tuple, Circuit] = {}
        critical = a.critical_circuit()
        terms[critical.key()] = critical
        derivatives = {}
        for j in g.params:
            right, right_places = slopes[k, j, 1]
            left, left_places = slopes[k, j, -1]
            derivatives[j] = (left, right)
            for places in (right_places, left_places):
                c = Circuit(g.index, tuple(places), _affine(g, places),
                            int(sum(int(g.tokens[q]) for q in places)))
                terms.setdefault(c.key(), c)
        out.append(GroupFormula(g.index, g.params, exact=False, terms=list(terms.values()),
                                derivatives=derivatives, queries=1))
    return out


_Candidate = tuple[tuple[Fraction, ...], Fraction, Circuit]
"""``(a, b, circuit)``: the circuit keeps pace with the clock where ``a·θ <= b``."""


def _pace_regions(group: ParametricGroup, formula: GroupFormula, params: Sequence[Parameter]
                  ) -> list[PaceRegion]:
    if not formula.exact:
        return []
    dims = formula.params
    out = []
    for clock, info in group.clocks.items():
        period = (Affine(Fraction(0), ((info.period_param, 1),)) if info.period_param >= 0
                  else Affine(info.period))
        candidates, blocking = _pace_candidates(formula, period)
        if blocking is not None:
            out.append(PaceRegion(clock, [], True, blocking))
            continue
        whole = _box(params, dims)
        for a, b, _ in candidates:
            whole.add((a, b))
        if whole.empty():
            out.append(PaceRegion(clock, [], True))
            continue
        kept = _non_redundant(params, dims, candidates)
        inequalities = [PaceInequality(tuple(zip(dims, candidates[i][0])), candidates[i][1],
                                       candidates[i][2]) for i in kept]
        out.append(PaceRegion(clock, inequalities, False))
    return out


def _pace_candidates(formula: GroupFormula, period: Affine
                     ) -> tuple[list[_Candidate], Circuit | None]:
    """One inequality per term (duplicates once), and the first term slower than the
    clock whatever the parameters (``blocking``), if any."""
    dims = formula.params
    candidates: list[_Candidate] = []
    blocking = None
    for c in formula.terms:
        a = tuple(Fraction(c.holding.coefficient(j), c.tokens) - period.coefficient(j)
                  for j in dims)
        b = period.const - c.holding.const / c.tokens
        if not any(a):
            if b < 0 and blocking is None:
                blocking = c
            continue
        if all((x, y) != (a, b) for x, y, _ in candidates):
            candidates.append((a, b, c))
    return candidates, blocking


def _non_redundant(params: Sequence[Parameter], dims: Sequence[int],
                   candidates: list[_Candidate]) -> list[int]:
    """The candidates not implied by the box and the others (those kept so far and
    those still to come), by index."""
    kept: list[int] = []
    for i in range(len(candidates)):
        others = _box(params, dims)
        for k in kept + list(range(i + 1, len(candidates))):
            others.add(candidates[k][:2])
        a, b, _ = candidates[i]
        items = others.generator_items()
        exceeds = any(sum(x * y for x, y in zip(a, point)) > (b if v else 0)
                      for v, point, _ in items)
        if exceeds:
            kept.append(i)
    return kept
