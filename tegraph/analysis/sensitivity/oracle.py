"""The exact verdict of spec §4 at many parameter points at once, with certificates.

A *query* is a group (:class:`~.parametric.ParametricGroup`) and a value
for each of its parameters. The answer holds every cycle time (Howard policy
iteration, :func:`maxplus.max_cycle_ratio`), whether the group is
rate-consistent, and for each clocked task either "no overrun" or a
*certificate*: an affine function of the parameters that is positive at the
query and positive only where the task overruns. Certificates are what the
breakpoint searches of :mod:`.line` cut with.

**Overruns without simulation.** Let C be the clock of T (period P, phase φ)
and ``y_e(k) = x_e(k) - k·P``. The recurrence of spec §3 becomes
``y_e(k) = max_p y_src(k - m_p) + h_p - m_p·P`` (or ``a_p - k·P`` for
``k <= m_p``), so ``Y_e = sup_k y_e(k)`` is the longest path to e from a
virtual source with an arc of weight ``a_p - P`` into the output event of
every marked place p and weights ``w_p = h_p - m_p·P`` on the places: every
path of the unrolled graph is one of these paths and conversely. ``Y_e`` is
finite exactly when no circuit upstream of e has a positive weight, i.e. when
``χ_e <= P``. T never overruns (``end_T(k-1) <= φ + (k-1)·P`` for every
k >= 2) exactly when ``Y_end + offset <= φ``. Hence the certificates:

- ``χ_end > P``: the policy circuit of ``end`` (ratio ``χ_end``), whose weight
  ``Σh - m·P`` is positive: wherever it is positive, ``Y_end`` is infinite;
- otherwise, if ``Y_end + offset > φ``: the longest path (an elementary path
  of the Bellman-Ford tree), ``a_p0 - P + Σ (h_p - m_p·P) + offset - φ``:
  wherever it is positive, so is ``Y_end + offset - φ``.

Both are affine in the parameters: a holding is a constant or one parameter
(:mod:`.parametric`), and P is a constant or a parameter.

Each query is scaled to integers by its own common denominator, and the
queries are solved together, as one disjoint union of graphs, by one Howard
run and one vectorized Bellman-Ford: components never compare their values
with each other, so each keeps its own exact scale.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from maxplus import max_cycle_ratio
from maxplus.scalar import INT64_SAFE

from .parametric import ParametricGroup

__all__ = ["Affine", "Certificate", "Circuit", "PointResult", "evaluate", "longest_paths"]

_NEG = -(2**62)


@dataclass(frozen=True)
class Affine:
    """``const + Σ coef·θ_j`` over parameter indices j.

    >>> f = Affine(Fraction(1), ((0, 2), (3, -1)))
    >>> f({0: Fraction(5), 3: Fraction(1, 2)})
    Fraction(21, 2)
    """

    const: Fraction
    coef: tuple[tuple[int, int], ...] = ()

    def __call__(self, values: Mapping[int, Fraction]) -> Fraction:
        return self.const + sum((c * values[j] for j, c in self.coef), Fraction(0))

    def slope(self, direction: Mapping[int, Fraction]) -> Fraction:
        """Rate of change along ``direction`` (a vector of parameter increments)."""
        return sum((c * direction.get(j, Fraction(0)) for j, c in self.coef), Fraction(0))

    def coefficient(self, j: int) -> int:
        """The coefficient of parameter ``j`` (0 when it does not appear)."""
        return dict(self.coef).get(j, 0)


def _affine(group: ParametricGroup, places: Sequence[int], const: Fraction = Fraction(0),
            extra: Mapping[int, int] | None = None) -> Affine:
    """Sum of the holdings of ``places``, plus ``const`` and the ``extra`` coefficients."""
    coef: dict[int, int] = dict(extra or {})
    total = const
    for p in places:
        j = int(group.param[p])
        if j < 0:
            total += group.const[p]
        else:
            coef[j] = coef.get(j, 0) + 1
    return Affine(total, tuple(sorted((j, c) for j, c in coef.items() if c)))


@dataclass(frozen=True)
class Circuit:
    """A circuit of a group: its places in order, total holding (affine) and tokens."""

    group: int
    places: tuple[int, ...]
    holding: Affine
    tokens: int

    def ratio(self, values: Mapping[int, Fraction]) -> Fraction:
        """The circuit's holding time over its tokens at ``values``."""
        return self.holding(values) / self.tokens

    def key(self) -> tuple:
        """The circuit's ratio as a function (two circuits with one function are one term)."""
        return (self.holding.const / self.tokens,
                tuple((j, Fraction(c, self.tokens)) for j, c in self.holding.coef))


@dataclass(frozen=True)
class Certificate:
    """Proof of an overrun of a watched task: ``excess > 0`` implies the overrun.

    ``kind`` is ``"circuit"`` (a circuit upstream of the task's end slower than
    its clock) or ``"path"`` (a path of the unrolled graph that ends the
    task's activation after the next tick); ``places`` are in order (for a
    path, the first is the marked place whose initial token starts it).
    """

    group: int
    watch: int
    kind: str
    places: tuple[int, ...]
    excess: Affine
    tokens: int = 0


@dataclass
class PointResult:
    """The verdict of spec §4 for one group at one parameter point."""

    group: ParametricGroup
    values: dict[int, Fraction]
    cycle_time: list[Fraction]
    policy: np.ndarray
    tight: np.ndarray | None = None
    """Per place: whether it is tight in Howard's potentials (critical circuits use only
    tight places between events of one cycle time)."""
    violations: list[Certificate] = field(default_factory=list)
    slack: list[Fraction | None] = field(default_factory=list)
    """Per watch, ``φ - Y_end - offset >= 0`` when it does not overrun, else None."""

    @property
    def cycle_time_max(self) -> Fraction:
        """The largest cycle time of the group's events at this point."""
        return max(self.cycle_time)

    @property
    def rate_consistent(self) -> bool:
        """Every event of the group has the same cycle time at this point."""
        return min(self.cycle_time) == max(self.cycle_time)

    @property
    def consistent(self) -> bool:
        """Rate-consistent and without a violated overrun condition at this point."""
        return self.rate_consistent and not self.violations

    def circuit(self, event: int) -> Circuit:
        """The policy circuit upstream of ``event``: a circuit of ratio ``cycle_time[event]``."""
        places = _policy_circuit(self.policy, self.group.src, event)
        return Circuit(self.group.index, tuple(places), _affine(self.group, places),
                       int(sum(int(self.group.tokens[p]) for p in places)))

    def critical_circuit(self) -> Circuit:
        """A circuit whose ratio is the group's largest."""
        ct = self.cycle_time  # the first of the largest, as numpy's argmax
        return self.circuit(max(range(len(ct)), key=ct.__getitem__))


def _policy_circuit(policy: np.ndarray, src: np.ndarray, event: int) -> list[int]:
    seen: dict[int, int] = {}
    walk: list[int] = []
    e = event
    while e not in seen:
        seen[e] = len(walk)
        p = int(policy[e])
        walk.append(p)
        e = int(src[p])
    # walk[i] enters the i-th visited event; the circuit is entered at e.
    circuit = walk[seen[e]:][::-1]
    # Start at the event numbered first (a tick, an activation), as a reader would.
    first = min(range(len(circuit)), key=lambda i: int(src[circuit[i]]))
    return circuit[first:] + circuit[:first]


def evaluate(queries: Sequence[tuple], overruns: bool = True) -> list[PointResult]:
    """The verdict of spec §4 of each (group, parameter values) query.

    Parameters
    ----------
    queries : sequence of (ParametricGroup, mapping) or (ParametricGroup, mapping, True)
        Each group must be live; the mapping gives a value to each of its
        parameters. With a third item True, the query is *homogeneous*: the
        constant holdings count as 0, so the cycle ratios are the slopes
        ``Σ coef·r / tokens`` of the circuits along the direction ``r`` given
        as the mapping (no overruns are decided for it).
    overruns : bool
        Also decide the overruns (with certificates); False: cycle times only.

    Returns
    -------
    list of PointResult
        In the order of ``queries``.
    """
    if not queries:
        return []
    scaled = [_scaled(q[0], q[1], len(q) > 2 and q[2]) for q in queries]
    results = _howard([q[:2] for q in queries], scaled)
    if overruns:
        _overruns([r for r, q in zip(results, queries) if not (len(q) > 2 and q[2])])
    return results


@dataclass
class _Scaled:
    scale: int
    holding: np.ndarray


def _scaled(group: ParametricGroup, values: Mapping[int, Fraction],
            homogeneous: bool = False) -> _Scaled:
    holdings = group.holdings(values)
    if homogeneous:
        holdings = [h if j >= 0 else Fraction(0) for h, j in zip(holdings, group.param.tolist())]
    scale = math.lcm(*(h.denominator for h in holdings))
    ints = [h.numerator * (scale // h.denominator) for h in holdings]
    return _Scaled(scale, np.array(ints, dtype=np.int64) if _fits(ints)
                   else np.array(ints, dtype=object))


def _fits(values: Sequence[int], room: int = INT64_SAFE // 4096) -> bool:
    return all(-room < v < room for v in values)


def _howard(queries, scaled: list[_Scaled]) -> list[PointResult]:
    sizes = [g.n_events for g, _ in queries]
    node_offset = np.concatenate(([0], np.cumsum(sizes)))
    arcs = [len(g.src) for g, _ in queries]
    arc_offset = np.concatenate(([0], np.cumsum(arcs)))
    src = np.concatenate([g.src + node_offset[i] for i, (g, _) in enumerate(queries)])
    dst = np.concatenate([g.dst + node_offset[i] for i, (g, _) in enumerate(queries)])
    tokens = np.concatenate([g.tokens for g, _ in queries])
    wide = any(s.holding.dtype == object for s in scaled)
    weight = np.concatenate([s.holding.astype(object) if wide else s.holding for s in scaled])
    mcr = max_cycle_ratio(src, dst, weight, tokens, n_nodes=int(node_offset[-1]))
    num, den = mcr.cycle_time_num.tolist(), mcr.cycle_time_den.tolist()
    cert = mcr.certificate
    policy = cert.policy
    tight = _tight(src, dst, weight, tokens, cert)
    out = []
    for i, (group, values) in enumerate(queries):
        a, b = int(node_offset[i]), int(node_offset[i + 1])
        scale = scaled[i].scale
        if any(d == 0 for d in den[a:b]):
            raise AssertionError("internal error: an event of a live group has no cycle time")
        cycle_time = [Fraction(n, d * scale) for n, d in zip(num[a:b], den[a:b])]
        out.append(PointResult(group, dict(values), cycle_time, policy[a:b] - arc_offset[i],
                               tight[int(arc_offset[i]):int(arc_offset[i + 1])]))
    return out


def _tight(src, dst, weight, tokens, cert) -> np.ndarray:
    """Places between events of one cycle time whose potential inequality is an equality."""
    W, T, X = (np.asarray(a).astype(object) for a in (cert.ratio_num, cert.ratio_den,
                                                      cert.potential))
    i, j = dst, src
    same = (W[j] == W[i]) & (T[j] == T[i]) & (T[i] != 0)
    value = X[j] + weight.astype(object) * T[i] - W[i] * tokens.astype(object)
    return (same & (value == X[i])).astype(bool)


# ------------------------------------------------------------------------ overruns


def _overruns(results: list[PointResult]) -> None:
    """Fill ``violations`` and ``slack`` of each result (see the module docstring)."""
    jobs = []  # (result, clock, period, events kept) for which a longest path is needed
    for r in results:
        g = r.group
        r.slack = [None] * len(g.watches)
        need: dict[str, list[int]] = {}
        for w, watch in enumerate(g.watches):
            period = g.period(watch.clock, r.values)
            if r.cycle_time[watch.end] > period:
                circuit = r.circuit(watch.end)
                excess = _circuit_excess(g, circuit.places, watch.clock, r.values)
                r.violations.append(Certificate(g.index, w, "circuit", circuit.places, excess,
                                                circuit.tokens))
            else:
                need.setdefault(watch.clock, []).append(w)
        for clock, watched in need.items():
            period = g.period(clock, r.values)
            jobs.append((r, clock, period, watched))
    if not jobs:
        return
    paths = _longest_paths(jobs)
    for (r, clock, _, watched), (value, pred, scale) in zip(jobs, paths):
        g = r.group
        info = g.clocks[clock]
        for w in watched:
            watch = g.watches[w]
            reached = value[watch.end]
            if reached is None:
                raise AssertionError("internal error: an event no marked place reaches")
            end_value = Fraction(reached, scale) + g.offset(watch, r.values)
            margin = info.phase - end_value
            if margin >= 0:
                r.slack[w] = margin
                continue
            source, arcs = _path(pred, g, watch.end)
            extra = {}
            const = g.initial[source] - info.phase
            n_periods = 1 + sum(int(g.tokens[p]) for p in arcs)
            if info.period_param >= 0:
                extra[info.period_param] = -n_periods
            else:
                const -= n_periods * info.period
            if watch.offset_param >= 0:
                extra[watch.offset_param] = extra.get(watch.offset_param, 0) + 1
            else:
                const += watch.offset
            excess = _affine(g, arcs, const, extra)
            r.violations.append(Certificate(g.index, w, "path", (source, *arcs), excess))
    for r in results:
        r.violations.sort(key=lambda c: c.watch)


def _circuit_excess(g: ParametricGroup, places: Sequence[int], clock: str,
                    values: Mapping[int, Fraction]) -> Affine:
    """``Σ h - m·P``: positive exactly when the circuit is slower than the clock."""
    info = g.clocks[clock]
    tokens = sum(int(g.tokens[p]) for p in places)
    if info.period_param >= 0:
        return _affine(g, places, Fraction(0), {info.period_param: -tokens})
    return _affine(g, places, -tokens * info.period)


def _path(pred: list[int], g: ParametricGroup, end: int) -> tuple[int, list[int]]:
    """The longest path to ``end``: (the marked place that starts it, its places in order)."""
    arcs: list[int] = []
    e = end
    for _ in range(len(pred) + 1):
        p = pred[e]
        if p < 0:  # reached from the virtual source through marked place -p-1
            return -p - 1, arcs[::-1]
        arcs.append(p)
        e = int(g.src[p])
    raise AssertionError("internal error: the longest-path tree has a circuit")


def _longest_paths(jobs) -> list[tuple[list[int | None], list[int], int]]:
    """Longest paths of every job, on the events with χ <= P (module docstring).

    Returns, per job, the value of each event (scaled), its tree predecessor (a
    place index, or ``-p-1`` for the marked place p that starts it from the
    virtual source) and the scale.
    """
    blocks = []
    scales = []
    for r, _, period, _ in jobs:
        g = r.group
        keep = np.array([c <= period for c in r.cycle_time], dtype=bool)
        holdings = g.holdings(r.values)
        scale = math.lcm(period.denominator, *(h.denominator for h in holdings),
                         *(a.denominator for a in g.initial))
        p_int = period.numerator * (scale // period.denominator)
        arc = np.flatnonzero(keep[g.src] & keep[g.dst])
        weight = [(holdings[p].numerator * (scale // holdings[p].denominator)
                   - int(g.tokens[p]) * p_int) for p in arc.tolist()]
        start: list[int | None] = [None] * g.n_events
        start_pred = [0] * g.n_events
        for p in np.flatnonzero((g.tokens > 0) & keep[g.dst]).tolist():
            a = g.initial[p]
            v = a.numerator * (scale // a.denominator) - p_int
            e = int(g.dst[p])
            if start[e] is None or v > start[e]:
                start[e], start_pred[e] = v, -p - 1
        blocks.append((g.n_events, g.src[arc], g.dst[arc], arc, weight, start, start_pred))
        scales.append(scale)
    out = longest_paths(blocks)
    return [(value, pred, scale) for (value, pred), scale in zip(out, scales)]


def longest_paths(blocks: Sequence[tuple]) -> list[tuple[list[int | None], list[int]]]:
    """Longest paths from given starting values, in many graphs at once (Bellman-Ford).

    Parameters
    ----------
    blocks : sequence of (n, src, dst, labels, weight, start, start_pred)
        A graph of n nodes with integer arc weights, no circuit of positive
        weight; ``labels`` names each arc (reported as predecessor);
        ``start[v]`` is the value of v before any arc (None: unreached) and
        ``start_pred[v]`` what to report as its predecessor then.

    Returns
    -------
    list of (values, predecessors)
        Per block: each node's largest ``start[u] + weight of a path u -> v``
        (None: unreached), and the label of the last arc of one such path
        (``start_pred`` when it has none). Improvements are strict, so the
        predecessors form a forest even across circuits of weight 0.

    Examples
    --------
    >>> longest_paths([(3, np.array([0, 1, 0]), np.array([1, 2, 2]), np.array([7, 8, 9]),
    ...                 [2, 3, 4], [0, None, None], [-1, -1, -1])])
    [([0, 2, 5], [-1, 7, 8])]
    """
    blocks = list(blocks)
    if not blocks:
        return []
    # "Unreached" is a sentinel below every value the relaxation can produce. A
    # value is the weight of a walk of at most (rounds) arcs from a start, so it
    # lies within ±bound, bound = the largest |start| + (n + 2) × the largest
    # |weight|; -4·bound is out of reach (and int64 holds 4·bound below 2**62).
    # A fixed sentinel such as -2**62 is not out of reach: with a period of 1e30
    # (scaled) real values fall below it and would be taken for "unreached".
    n_max = max(b[0] for b in blocks)
    bound = 1 + max((abs(v) for b in blocks for v in b[5] if v is not None), default=0) + (
        n_max + 2) * max((abs(w) for b in blocks for w in b[4]), default=0)
    wide = -4 * bound <= _NEG
    dtype = object if wide else np.int64
    neg = -4 * bound if wide else _NEG
    sizes = [b[0] for b in blocks]
    offset = np.concatenate(([0], np.cumsum(sizes))).astype(np.int64)
    src = np.concatenate([np.asarray(b[1], dtype=np.int64) + offset[i]
                          for i, b in enumerate(blocks)])
    dst = np.concatenate([np.asarray(b[2], dtype=np.int64) + offset[i]
                          for i, b in enumerate(blocks)])
    label = np.concatenate([np.asarray(b[3], dtype=np.int64) for b in blocks])
    weight = np.array([w for b in blocks for w in b[4]], dtype=dtype)
    value = np.array([neg if v is None else v for b in blocks for v in b[5]], dtype=dtype)
    pred = np.array([v for b in blocks for v in b[6]], dtype=np.int64)
    order = np.argsort(dst, kind="stable")
    src, dst, weight, label = src[order], dst[order], weight[order], label[order]
    if len(dst):
        starts = np.flatnonzero(np.concatenate(([True], dst[1:] != dst[:-1])))
        targets = dst[starts]
        counts = np.diff(np.append(starts, len(dst)))
        position = np.arange(len(dst))
        for _ in range(max(sizes) + 2):
            reach = value[src] > neg // 2
            candidate = np.where(reach, value[src] + weight, neg)
            if candidate.dtype != dtype:
                candidate = candidate.astype(dtype)
            best = np.maximum.reduceat(candidate, starts)
            better = (best > value[targets]) & (best > neg // 2)
            if not better.any():
                break
            # The first arc attaining each improved maximum becomes the predecessor.
            hit = (candidate == np.repeat(best, counts)) & reach
            first = np.minimum.reduceat(np.where(hit, position, len(dst)), starts)
            improved = np.flatnonzero(better)
            value[targets[improved]] = best[improved]
            pred[targets[improved]] = label[first[improved]]
        else:
            raise AssertionError("internal error: a circuit of positive weight in a "
                                 "longest-path problem")
    out = []
    for i in range(len(blocks)):
        lo, hi = int(offset[i]), int(offset[i + 1])
        out.append(([None if v <= neg // 2 else int(v) for v in value[lo:hi].tolist()],
                    pred[lo:hi].tolist()))
    return out
