"""The consistent values along a line of parameter space, exactly.

Along a line ``θ(t) = base + t·direction`` (t in a range ``[low, high]``), the
set of t where a live group is consistent (spec §4: rate-consistent, no
overrun) is a finite union of closed intervals with exact endpoints. Two
facts give it (proofs in ``docs/sensitivity.md``):

- **No overrun is convex.** ``Y_end(θ)`` (:mod:`.oracle`) is a
  maximum of affine functions of θ (one per elementary path, +∞ past a
  circuit), so ``{t : Y_end + offset <= φ}`` is one closed interval. Its ends
  are found by Newton's method on the certificates: from a point where a task
  overruns, the certificate's root is the next point; at a feasible root the
  end is reached, exact, and every point beyond is certified infeasible. A
  certificate is an elementary path or circuit, and each is used at most
  once (the points move strictly towards the interval), so the search ends.
- **Rate consistency is a comparison of convex functions.** Every cycle time
  is the largest ratio of the circuits upstream, so a group is rate-consistent
  exactly when each *source* component (no place enters it) has the group's
  largest ratio λ. Each ratio ``ρ(t)`` is a convex piecewise-affine function
  (the upper envelope of its circuits' lines); the envelope is computed by
  Eisner and Severance's method [1]_: the lines at both ends of an interval
  meet at x; if ρ(x) is on them, ρ is their maximum there (a convex function
  below its chord), else the circuit found at x is a new line and both halves
  are refined. Then ``{t : ρ_M(t) >= λ(t) for every source M}`` is read piece
  by piece.

An unbounded range is handled by a *far point* ``T∞`` beyond every
breakpoint of every function involved: all of them are ratios
``(C + t·S)/m`` of integer sums with ``|C| <= Ĉ``, ``m <= M``, so any two meet
at ``|t| <= 2·Ĉ·M``; what holds at ``T∞`` holds for every larger t.

All points where the oracle is asked are collected from every (group, line)
pair at once, round by round, and solved as one batch
(:func:`~.oracle.evaluate`).

References
----------
.. [1] J. M. Eisner, D. G. Severance, "Mathematical techniques for efficient
   record segmentation in large shared databases", JACM 23(4), 1976 (the
   upper envelope of lines from a maximization oracle).
"""

from __future__ import annotations

import math
from collections.abc import Generator, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Literal

from .oracle import Affine, Certificate, Circuit, PointResult, evaluate
from .parametric import ParametricGroup

__all__ = ["Cause", "Line", "LineSet", "intersect", "point_causes", "solve_lines"]

Interval = tuple[Fraction, "Fraction | None"]


@dataclass(frozen=True)
class Line:
    """``θ_j(t) = base_j + t·direction_j`` (parameters not in ``base``: nominal).

    ``high`` None: unbounded. ``low_open``: the value ``low`` itself is
    excluded (a period's range that starts at 0).
    """

    base: dict[int, Fraction]
    direction: dict[int, Fraction]
    low: Fraction
    high: Fraction | None
    low_open: bool = False

    def values(self, group: ParametricGroup, nominal: Sequence[Fraction], t: Fraction
               ) -> dict[int, Fraction]:
        """The group's parameter values at ``t`` on this line (nominal where it leaves them)."""
        return {j: self.base.get(j, nominal[j]) + t * self.direction.get(j, 0)
                for j in group.params}

    def affine(self, f: Affine, nominal: Sequence[Fraction]) -> tuple[Fraction, Fraction]:
        """``f`` along the line: ``(c, s)`` with ``f(θ(t)) = c + s·t``."""
        c, s = f.const, Fraction(0)
        for j, k in f.coef:
            c += k * self.base.get(j, nominal[j])
            s += k * self.direction.get(j, 0)
        return c, s


@dataclass(frozen=True)
class Cause:
    """Why the consistent values end at a point, seen just beyond it.

    ``kind``:

    - ``"overrun"``: ``task`` (clock ``clock``) overruns; ``certificate`` is
      the path of the unrolled graph that ends its activation after the next
      tick, or the circuit upstream of it that is slower than its clock;
    - ``"pace"``: the group's critical circuit ``circuit`` becomes slower than
      the source ``source`` (a clock's tick when ``clock`` is set, else a
      free-running circuit): a place between them is unbounded.
    """

    kind: Literal["overrun", "pace"]
    group: int
    task: str | None = None
    clock: str | None = None
    certificate: Certificate | None = None
    circuit: Circuit | None = None
    source: Circuit | None = None
    activation: int | None = None
    """The activation at which the task overruns just beyond (from the oracle)."""


@dataclass
class LineSet:
    """The consistent t of one group along one line, and why each end is an end."""

    intervals: list[Interval]
    causes: dict[tuple[Fraction, str], list[Cause]] = field(default_factory=dict)
    """``(t, "above")``: the causes just above an upper end t; ``"below"`` for lower ends."""
    queries: int = 0


def solve_lines(pairs: Sequence[tuple[ParametricGroup, Line]], nominal: Sequence[Fraction]
                ) -> tuple[list[LineSet], int, int]:
    """The consistent set of every (group, line) pair.

    Returns
    -------
    (list of LineSet, rounds, queries)
        One set per pair; the number of batched oracle calls and of points asked.
    """
    solvers = [_solve(g, line, nominal) for g, line in pairs]
    asked: list[list[Fraction] | None] = [next(s) for s in solvers]
    results: list[LineSet | None] = [None] * len(pairs)
    rounds = queries = 0
    while any(a is not None for a in asked):
        batch, owners = [], []
        for k, ts in enumerate(asked):
            if ts is None:
                continue
            g, line = pairs[k]
            for t in ts:
                batch.append((g, line.values(g, nominal, t)))
                owners.append((k, t))
        answers = evaluate(batch)
        rounds += 1
        queries += len(batch)
        per: dict[int, dict[Fraction, PointResult]] = {}
        for (k, t), answer in zip(owners, answers):
            per.setdefault(k, {})[t] = answer
        for k, got in per.items():
            try:
                asked[k] = solvers[k].send(got)
            except StopIteration as done:
                results[k] = done.value
                asked[k] = None
    # Type: the loop ends when every solver has returned: no result is None.
    return results, rounds, queries  # type: ignore[return-value]


def far_point(group: ParametricGroup, line: Line, nominal: Sequence[Fraction]) -> Fraction:
    """A t beyond every breakpoint of the group's functions along the line (module docstring)."""
    numbers: list[Fraction] = []
    for p in range(len(group.src)):
        j = int(group.param[p])
        if j < 0:
            numbers.append(group.const[p])
        else:
            numbers += [line.base.get(j, nominal[j]), line.direction.get(j, Fraction(0))]
    numbers += group.initial
    periods = []
    for info in group.clocks.values():
        numbers.append(info.phase)
        if info.period_param < 0:
            periods.append(info.period)
        else:
            j = info.period_param
            periods += [line.base.get(j, nominal[j]), line.direction.get(j, Fraction(0))]
    for w in group.watches:
        numbers.append(w.offset)
    numbers += periods
    scale = math.lcm(1, *(x.denominator for x in numbers))
    tokens = int(group.tokens.sum()) + 1
    biggest_period = max((abs(x) for x in periods), default=Fraction(0))
    bound = (sum(abs(x) for x in numbers) + tokens * biggest_period) * scale
    return max(Fraction(2 * math.ceil(bound) * tokens), abs(line.low)) + 1


# --------------------------------------------------------------------------- one pair


def _solve(group: ParametricGroup, line: Line, nominal: Sequence[Fraction]
           ) -> Generator[list[Fraction], dict[Fraction, PointResult], LineSet]:
    low = line.low
    moving = any(line.direction.get(j, 0) for j in group.params)
    if not moving:
        got = yield [low]
        result = got[low]
        return LineSet([(low, line.high)] if result.consistent else [], {}, 1)
    top = line.high if line.high is not None else far_point(group, line, nominal)
    known: dict[Fraction, PointResult] = {}
    got = yield [low, top]
    known.update(got)
    n_sources = len(group.sources)
    # Envelope state of each tracked function: 0 is λ, 1.. the source components.
    pieces: list[list] = [[] for _ in range(n_sources + 1)]
    pending: list[list] = [[] for _ in range(n_sources + 1)]
    for f in range(n_sources + 1):
        pending[f].append((low, top, _line(known[low], f, group, line, nominal),
                           _line(known[top], f, group, line, nominal)))
    newton = _Newton(group, line, nominal, low, top)
    while True:
        wanted: set[Fraction] = set()
        for f in range(n_sources + 1):
            pending[f] = _refine(f, pending[f], pieces[f], known, wanted,
                                 (group, line, nominal))
        point = newton.advance(known)
        if point is not None:
            wanted.add(point)
        if not wanted and newton.done and not any(pending):
            break
        if wanted:
            got = yield sorted(wanted)
            known.update(got)
    return _assemble(group, line, nominal, low, top, pieces, newton, len(known))


def _refine(f: int, pending: list, pieces: list, known: dict[Fraction, PointResult],
            wanted: set[Fraction], where: tuple[ParametricGroup, Line, Sequence[Fraction]]
            ) -> list:
    """One round on function f's envelope: each pending segment ``(a, b, la, lb)``
    whose end lines agree, or that the value where they meet confirms, becomes
    pieces; one whose meeting point is known to lie above them is split there; one
    whose meeting point is not known yet stays, and the point is ``wanted``.
    Returns the segments still pending."""
    still = []
    for a, b, la, lb in pending:
        if la[:2] == lb[:2] or a == b:
            pieces.append((a, b, la))
            continue
        x = _meet(la, lb)
        if not a <= x <= b:
            raise AssertionError("internal error: envelope lines meet outside")
        if x in known:
            value, lx = _value(known[x], f), _line(known[x], f, *where)
            if value == la[0] + la[1] * x:
                pieces += [(a, x, la), (x, b, lb)]
            else:
                still += [(a, x, la, lx), (x, b, lx, lb)]
        else:
            still.append((a, b, la, lb))
            wanted.add(x)
    return still


def _value(result: PointResult, f: int) -> Fraction:
    if f == 0:
        return result.cycle_time_max
    return result.cycle_time[result.group.sources[f - 1]]


def _line(result: PointResult, f: int, group: ParametricGroup, line: Line,
          nominal: Sequence[Fraction]) -> tuple[Fraction, Fraction, Circuit]:
    circuit = (result.critical_circuit() if f == 0
               else result.circuit(group.sources[f - 1]))
    c, s = line.affine(circuit.holding, nominal)
    return c / circuit.tokens, s / circuit.tokens, circuit


def _meet(la, lb) -> Fraction:
    if la[1] == lb[1]:
        raise AssertionError("internal error: parallel envelope lines")
    return (lb[0] - la[0]) / (la[1] - lb[1])


class _Newton:
    """Both ends of the interval without overrun, by Newton steps on certificates."""

    def __init__(self, group: ParametricGroup, line: Line, nominal: Sequence[Fraction],
                 low: Fraction, top: Fraction) -> None:
        self.group, self.line, self.nominal = group, line, nominal
        self.low, self.top = low, top
        self.phase = "upper" if group.watches else "done"
        self.at = top
        self.upper: Fraction | None = top
        self.lower: Fraction | None = low
        self.empty = False
        self.cut: dict[str, list[Certificate]] = {"upper": [], "lower": []}

    @property
    def done(self) -> bool:
        return self.phase == "done"

    def advance(self, known: dict[Fraction, PointResult]) -> Fraction | None:
        """Step while answers are known; return the next point to ask, or None."""
        while self.phase != "done":
            if self.at not in known:
                return self.at
            violations = known[self.at].violations
            if not violations:
                if self.phase == "upper":
                    self.upper, self.phase, self.at = self.at, "lower", self.low
                    continue
                self.lower, self.phase = self.at, "done"
                return None
            lines = [(self.line.affine(c.excess, self.nominal), c) for c in violations]
            if self.phase == "upper":
                if any(s <= 0 for (_, s), _ in lines):
                    self._nothing()
                    return None
                roots = [(-c / s, cert) for (c, s), cert in lines]
                step = min(r for r, _ in roots)
                if step < self.low:
                    self._nothing()
                    return None
                self.cut["upper"] = [cert for r, cert in roots if r == step]
            else:
                if any(s >= 0 for (_, s), _ in lines):
                    raise AssertionError("internal error: an overrun certificate that grows "
                                         "towards a point without overrun")
                roots = [(-c / s, cert) for (c, s), cert in lines]
                step = max(r for r, _ in roots)
                self.cut["lower"] = [cert for r, cert in roots if r == step]
            self.at = step
        return None

    def _nothing(self) -> None:
        self.empty, self.phase = True, "done"
        self.upper = self.lower = None


def _assemble(group, line, nominal, low, top, pieces, newton: _Newton, n_queries: int
              ) -> LineSet:
    far = line.high is None
    for f in range(len(pieces)):
        pieces[f].sort(key=lambda piece: piece[0])
    lam = pieces[0]
    rc: list[Interval] | None = None
    for f in range(1, len(pieces)):
        keep = _at_least(pieces[f], lam)
        rc = keep if rc is None else intersect(rc, keep)
    rc = rc if rc is not None else [(low, top)]
    if newton.empty:
        no_overrun: list[Interval] = []
    else:
        # Type: a Newton search that is not empty found its lower end (None above: unbounded).
        no_overrun = [(newton.lower, newton.upper)]  # type: ignore[list-item]
    intervals = intersect(rc, no_overrun)
    if far:
        intervals = [(a, None if b == top else b) for a, b in intervals]
    causes: dict[tuple[Fraction, str], list[Cause]] = {}
    for a, b in intervals:
        for t, side in ((a, "below"), (b, "above")):
            if t is None or (side == "below" and t == low) or (side == "above" and t == top):
                continue
            found = []
            bound = newton.lower if side == "below" else newton.upper
            if t == bound:
                for cert in newton.cut["lower" if side == "below" else "upper"]:
                    watch = group.watches[cert.watch]
                    found.append(Cause("overrun", group.index, watch.task, watch.clock, cert))
            found += _pace_causes(group, pieces, t, side)
            causes[t, side] = found
    return LineSet(intervals, causes, n_queries)


def _at_least(upper: list, lower: list) -> list[Interval]:
    """Where the piecewise-affine ``upper >= lower`` (both on the same contiguous domain)."""
    cuts = sorted({a for a, _, _ in upper} | {b for _, b, _ in upper}
                  | {a for a, _, _ in lower} | {b for _, b, _ in lower})
    out: list[Interval] = []
    for u, v in zip(cuts, cuts[1:]):
        mid = (u + v) / 2
        lu, ll = _piece_line(upper, mid), _piece_line(lower, mid)
        c, s = lu[0] - ll[0], lu[1] - ll[1]
        if s == 0:
            segment = (u, v) if c >= 0 else None
        else:
            root = -c / s
            if s > 0:
                segment = (max(u, root), v) if root <= v else None
            else:
                segment = (u, min(v, root)) if root >= u else None
        if segment is not None:
            out = _union_append(out, segment)
    if len(cuts) == 1:  # a single point
        lu, ll = _piece_line(upper, cuts[0]), _piece_line(lower, cuts[0])
        if lu[0] + lu[1] * cuts[0] >= ll[0] + ll[1] * cuts[0]:
            out = [(cuts[0], cuts[0])]
    return out


def _piece_line(pieces: list, t: Fraction, side: str = "") -> tuple:
    for a, b, ln in pieces:
        if (a <= t < b) if side == "above" else (a < t <= b) if side == "below" else a <= t <= b:
            return ln
    return pieces[-1][2] if side == "above" else pieces[0][2]


def _union_append(out: list[Interval], segment: Interval) -> list[Interval]:
    if out and out[-1][1] is not None and segment[0] <= out[-1][1]:
        out[-1] = (out[-1][0], segment[1])
    else:
        out.append(segment)
    return out


def _pace_causes(group: ParametricGroup, pieces: list, t: Fraction, side: str) -> list[Cause]:
    """The sources that fall behind the group's largest ratio just beyond t."""
    lam = _piece_line(pieces[0], t, side)
    out = []
    for f in range(1, len(pieces)):
        src = _piece_line(pieces[f], t, side)
        c, s = src[0] - lam[0], src[1] - lam[1]
        value = c + s * t
        behind = value < 0 or (value == 0 and (s < 0 if side == "above" else s > 0))
        if behind:
            event = group.sources[f - 1]
            clock = next((name for name, info in group.clocks.items() if info.tick == event),
                         None)
            out.append(Cause("pace", group.index, clock=clock, circuit=lam[2], source=src[2]))
    return out


def point_causes(result: PointResult) -> list[Cause]:
    """Why a group is not consistent at one point: its overruns, the sources left behind."""
    group = result.group
    out = []
    for cert in result.violations:
        watch = group.watches[cert.watch]
        out.append(Cause("overrun", group.index, watch.task, watch.clock, cert))
    top = result.cycle_time_max
    critical = result.critical_circuit()
    for event in group.sources:
        if result.cycle_time[event] < top:
            clock = next((n for n, info in group.clocks.items() if info.tick == event), None)
            out.append(Cause("pace", group.index, clock=clock, circuit=critical,
                             source=result.circuit(event)))
    return out


def intersect(a: list[Interval], b: list[Interval]) -> list[Interval]:
    """Intersection of two sorted unions of closed intervals (None: unbounded above).

    >>> F = Fraction
    >>> intersect([(F(0), F(2)), (F(3), None)], [(F(1), F(4))])
    [(Fraction(1, 1), Fraction(2, 1)), (Fraction(3, 1), Fraction(4, 1))]
    """
    out: list[Interval] = []
    i = j = 0
    while i < len(a) and j < len(b):
        lo = max(a[i][0], b[j][0])
        ha, hb = a[i][1], b[j][1]
        hi = ha if hb is None else hb if ha is None else min(ha, hb)
        if hi is None or lo <= hi:
            out.append((lo, hi))
        if hb is None or (ha is not None and ha <= hb):
            i += 1
        else:
            j += 1
    return out
