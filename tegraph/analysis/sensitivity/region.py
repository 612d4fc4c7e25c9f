"""The consistent region of a group in the plane of two parameters, exactly.

The map of two parameters (``tegraph sensitivity --plot`` with two ``--vary``)
shades where a group is *consistent* (spec §4: rate-consistent and no
overrun), not only where it keeps pace with its clocks: a design that keeps
pace may still overrun (``examples/overrun_in_step.yaml`` at its nominal
durations). The region is computed by cutting planes over the oracle of
:mod:`.oracle`, and it is exact, for these reasons:

- *Keeping pace* with every clock is a polygon ``Q`` (the inequalities of the
  period formula, :class:`~.results.PaceReport`). When every event
  of the group is downstream of a clock's tick, its cycle time is at least
  that clock's period, so inside ``Q`` (where no circuit is slower than any
  clock, so all periods are equal) every cycle time is the period: ``Q`` is
  exactly where the group is rate-consistent. Otherwise the region is not
  computed, and the drawing says why.
- *No overrun* is ``N = ∩ {excess_c <= 0}`` over the finitely many
  certificates ``c`` of the oracle (an elementary path or circuit; each
  ``excess`` is affine in the parameters, the periods included), and at
  every point that overruns some certificate is positive (module docstring
  of :mod:`.oracle`). ``N`` is convex.
- The loop keeps a convex polygon ``R ⊇ Q ∩ N``: it starts at ``Q`` and cuts
  each vertex that overruns by the certificate found there (positive at that
  vertex, so the vertex is removed, and never met again). It stops when every
  vertex is consistent: then ``R``, the hull of consistent points of the
  convex ``Q ∩ N``, is inside it, so ``R = Q ∩ N``. It terminates because
  each cut adds a certificate not cut before and there are finitely many.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from functools import cmp_to_key

from .oracle import evaluate
from .parametric import ParametricGroup
from .polyhedra import Polyhedron

__all__ = ["ConsistentRegion", "consistent_region"]

Point = tuple[Fraction, Fraction]
_MAX_CUTS = 10_000


@dataclass
class ConsistentRegion:
    """Where one group is consistent in a window of the plane (x, y), the rest nominal.

    Attributes
    ----------
    vertices : list of (Fraction, Fraction)
        The convex polygon's vertices in order (empty: consistent nowhere in the
        window; one or two points: a point or a segment). Meaningful when
        ``why_not`` is None.
    overrun_edges : list of ((Fraction, Fraction), (Fraction, Fraction), str)
        The polygon's edges where an overrun begins just beyond, each with the
        task that overruns there.
    why_not : str or None
        Why the region could not be computed exactly (nothing is claimed then).
    nominal_consistent : bool
        The group's verdict at the nominal values (spec §4, by the same oracle).
    """

    vertices: list[Point] = field(default_factory=list)
    overrun_edges: list[tuple[Point, Point, str]] = field(default_factory=list)
    why_not: str | None = None
    nominal_consistent: bool = False


def consistent_region(group: ParametricGroup, x: int, y: int,
                      window: tuple[Fraction, Fraction, Fraction, Fraction],
                      pace: Sequence[tuple[Fraction, Fraction, Fraction]],
                      nominal: Sequence[Fraction]) -> ConsistentRegion:
    """The exact region of ``window`` where ``group`` is consistent (see the module docstring).

    Parameters
    ----------
    group : ParametricGroup
        A live group that depends on parameter ``x`` or ``y``.
    x, y : int
        Indices of the two parameters of the plane.
    window : (x0, x1, y0, y1)
        The box drawn.
    pace : sequence of (a, b, bound)
        Where the group keeps pace with every clock: ``a·x + b·y <= bound``
        (the other parameters at their nominal values).
    nominal : sequence of Fraction
        Every parameter's nominal value.

    Returns
    -------
    ConsistentRegion
    """
    (at_nominal,) = evaluate([(group, group.values({}, nominal))])
    region = _region(group, x, y, window, pace, nominal)
    region.nominal_consistent = at_nominal.consistent
    return region


def _region(group: ParametricGroup, x: int, y: int,
            window: tuple[Fraction, Fraction, Fraction, Fraction],
            pace: Sequence[tuple[Fraction, Fraction, Fraction]],
            nominal: Sequence[Fraction]) -> ConsistentRegion:
    if not group.clocks:
        return ConsistentRegion(why_not="the group has no clock: its consistency region is "
                                        "not drawn")
    orphan = _not_downstream_of_a_tick(group)
    if orphan is not None:
        return ConsistentRegion(why_not=f"{orphan} is downstream of no clock tick: the "
                                        "consistent region is not drawn (not computed exactly)")
    x0, x1, y0, y1 = window
    poly = Polyhedron(2)
    for side in (((Fraction(-1), Fraction(0)), -x0), ((Fraction(1), Fraction(0)), x1),
                 ((Fraction(0), Fraction(-1)), -y0), ((Fraction(0), Fraction(1)), y1)):
        poly.add(side)
    for a, b, bound in pace:
        poly.add(((a, b), bound))
    cuts: list[tuple[Fraction, Fraction, Fraction, str]] = []
    for _ in range(_MAX_CUTS):
        vertices = [(v[0], v[1]) for v in poly.vertices()]
        if not vertices:
            return ConsistentRegion()
        results = evaluate([(group, group.values({x: vx, y: vy}, nominal))
                            for vx, vy in vertices])
        cut = False
        for result in results:
            if not result.rate_consistent:
                return ConsistentRegion(why_not="a point where the group keeps pace with "
                                                "every clock is not rate-consistent: the "
                                                "consistent region is not drawn")
            for cert in result.violations:
                a, b, c = _in_plane(cert.excess, x, y, nominal)
                row = (a, b, -c)  # excess = a·x + b·y + c <= 0
                if any(row == k[:3] for k in cuts):
                    continue
                if a == 0 and b == 0:
                    return ConsistentRegion()  # it overruns everywhere in the plane
                cuts.append((*row, group.watches[cert.watch].task))
                poly.add(((a, b), -c))
                cut = True
                break  # one certificate per vertex, then look at the new polygon
        if not cut:
            return ConsistentRegion(_ordered(vertices), _edges(_ordered(vertices), cuts))
    raise AssertionError(f"internal error: more than {_MAX_CUTS} overrun certificates "
                         "in one group")  # finitely many certificates: see the docstring


def _in_plane(f, x: int, y: int, nominal: Sequence[Fraction]
              ) -> tuple[Fraction, Fraction, Fraction]:
    """An affine function of the parameters as ``a·x + b·y + c``, the others nominal."""
    a = b = Fraction(0)
    c = Fraction(f.const)
    for j, k in f.coef:
        if j == x:
            a += k
        elif j == y:
            b += k
        else:
            c += k * nominal[j]
    return a, b, c


def _not_downstream_of_a_tick(group: ParametricGroup) -> str | None:
    """The name of an event no clock tick reaches, or None."""
    succ: dict[int, list[int]] = {}
    for s, d in zip(group.src.tolist(), group.dst.tolist()):
        succ.setdefault(s, []).append(d)
    seen = {info.tick for info in group.clocks.values()}
    stack = list(seen)
    while stack:
        for d in succ.get(stack.pop(), ()):
            if d not in seen:
                seen.add(d)
                stack.append(d)
    missing = [e for e in range(group.n_events) if e not in seen]
    return group.names[missing[0]] if missing else None


def _ordered(points: list[Point]) -> list[Point]:
    """The vertices of a convex polygon in counter-clockwise order, exactly.

    Sorted by angle around an interior point with exact comparisons (half-plane,
    then the sign of a cross product), never by floating-point angles.
    """
    if len(points) < 3:
        return sorted(points)
    n = len(points)
    cx = sum(p[0] for p in points) / n
    cy = sum(p[1] for p in points) / n

    def half(p: Point) -> int:
        dx, dy = p[0] - cx, p[1] - cy
        return 0 if dy > 0 or (dy == 0 and dx > 0) else 1

    def compare(p: Point, q: Point) -> int:
        hp, hq = half(p), half(q)
        if hp != hq:
            return hp - hq
        cross = (p[0] - cx) * (q[1] - cy) - (p[1] - cy) * (q[0] - cx)
        return -1 if cross > 0 else (1 if cross < 0 else 0)

    return sorted(points, key=cmp_to_key(compare))


def _edges(vertices: list[Point], cuts) -> list[tuple[Point, Point, str]]:
    """The polygon's edges that lie on an overrun certificate's line."""
    if len(vertices) < 2:
        return []
    out = []
    pairs = list(zip(vertices, vertices[1:] + vertices[:1])) if len(vertices) > 2 else [
        (vertices[0], vertices[1])]
    for u, v in pairs:
        for a, b, bound, task in cuts:
            if a * u[0] + b * u[1] == bound and a * v[0] + b * v[1] == bound:
                out.append((u, v, task))
                break
    return out
