"""Vertices and rays of small polyhedra, exactly: the double description method.

A polyhedron ``{x in Q^n : a_i·x <= b_i}`` is homogenized into the cone
``{(x, s) : a_i·x - b_i·s <= 0, s >= 0}``; its extreme rays with ``s > 0`` are
the vertices ``x = y/s``, those with ``s = 0`` the rays. The method of Motzkin
et al. [1]_ adds one inequality at a time to a cone known by its extreme rays:
the rays on the wrong side are dropped and each adjacent pair across the new
hyperplane gives a new ray on it; two rays are adjacent when no third ray is
tight on every inequality both are tight on (the combinatorial test of Fukuda
and Prodon [2]_). Everything is in Python integers: each ray is kept divided
by the gcd of its entries.

Used for a handful of parameters (the period formulas of
:mod:`.formulas`, at most about six), where the cost, cubic in the
number of rays per inequality, is small; the cone must be pointed (every
coordinate bounded below), which the boxes of parameter ranges ensure.

References
----------
.. [1] T. S. Motzkin, H. Raiffa, G. L. Thompson, R. M. Thrall, "The double
   description method", Contributions to the Theory of Games II, 1953.
.. [2] K. Fukuda, A. Prodon, "Double description method revisited",
   Combinatorics and Computer Science, LNCS 1120, 1996.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction

__all__ = ["Polyhedron", "affine_rank"]

Row = tuple[tuple[Fraction, ...], Fraction]


@dataclass
class Polyhedron:
    """``{x : a·x <= b for each row (a, b)}`` with its vertices and rays kept up to date.

    Parameters
    ----------
    dimension : int
    rows : sequence of (a, b)
        The first inequalities; they must bound every coordinate below (a
        pointed polyhedron) once all are added.

    Examples
    --------
    The triangle ``x >= 0, y >= 0, x + y <= 2``:

    >>> F = Fraction
    >>> P = Polyhedron(2, [((F(-1), F(0)), F(0)), ((F(0), F(-1)), F(0)),
    ...                    ((F(1), F(1)), F(2))])
    >>> [tuple(map(str, v)) for v in sorted(P.vertices())]
    [('0', '0'), ('0', '2'), ('2', '0')]
    >>> P.rays()
    []
    """

    dimension: int

    def __init__(self, dimension: int, rows: Sequence[Row] = ()) -> None:
        self.dimension = dimension
        # Row 0 is the homogenizing coordinate's s >= 0 (-s <= 0); row k+1 is
        # the caller's k-th row, and bit r of a mask is row r.
        self.rows: list[tuple[int, ...]] = [tuple([0] * dimension + [-1])]
        self.generators: list[list[int]] = []
        self.tight: list[int] = []
        self.started = False
        self._start()
        for row in rows:
            self.add(row)

    def add(self, row: Row) -> int:
        """Add the inequality ``a·x <= b``; return its index (0 for the first added)."""
        a, b = row
        scale = math.lcm(1, *(Fraction(v).denominator for v in (*a, b)))
        self.rows.append(tuple(int(Fraction(v) * scale) for v in a)
                         + (int(-Fraction(b) * scale),))
        index = len(self.rows) - 1
        if self.started:
            self._insert(index)
        else:
            self._start()
        return index - 1

    def _start(self) -> None:
        """The first cone, from n+1 independent rows, once there are; then the others."""
        basis = _independent(self.rows, self.dimension + 1)
        if basis is None:
            return
        self.started = True
        chosen = [self.rows[i] for i in basis]
        self.generators = _simplicial(chosen, self.dimension + 1)
        self.tight = [sum(1 << i for i in basis if _dot(self.rows[i], g) == 0)
                      for g in self.generators]
        for i in range(len(self.rows)):
            if i not in basis:
                self._insert(i)

    def _insert(self, index: int) -> None:
        row = self.rows[index]
        values = [_dot(row, g) for g in self.generators]
        plus = [i for i, v in enumerate(values) if v > 0]
        minus = [i for i, v in enumerate(values) if v < 0]
        keep = [i for i, v in enumerate(values) if v <= 0]
        d = self.dimension + 1
        new_gen, new_tight = [], []
        for i in plus:
            for j in minus:
                common = self.tight[i] & self.tight[j]
                if bin(common).count("1") < d - 2:
                    continue
                if any(k != i and k != j and self.tight[k] & common == common
                       for k in range(len(self.generators))):
                    continue
                vi, vj = values[i], values[j]
                ray = [vi * b - vj * a for a, b in zip(self.generators[i], self.generators[j])]
                new_gen.append(_reduced(ray))
                new_tight.append(common | (1 << index))
        self.generators = [self.generators[i] for i in keep] + new_gen
        self.tight = [self.tight[i] | ((1 << index) if values[i] == 0 else 0) for i in keep]
        self.tight += new_tight

    def _ready(self) -> None:
        if not self.started:
            raise ValueError("the polyhedron is not pointed: bound every coordinate below")

    def vertices(self) -> list[tuple[Fraction, ...]]:
        """The vertices."""
        return [p for is_vertex, p, _ in self.generator_items() if is_vertex]

    def rays(self) -> list[tuple[Fraction, ...]]:
        """The extreme rays (directions of unboundedness), each up to a positive factor."""
        return [p for is_vertex, p, _ in self.generator_items() if not is_vertex]

    def generator_items(self) -> list[tuple[bool, tuple[Fraction, ...], int]]:
        """``(is_vertex, point or ray, mask)`` for every generator; bit k of the mask: the
        k-th row added is tight on it."""
        self._ready()
        out = []
        for g, mask in zip(self.generators, self.tight):
            if g[-1] > 0:
                out.append((True, tuple(Fraction(v, g[-1]) for v in g[:-1]), mask >> 1))
            else:
                out.append((False, tuple(Fraction(v) for v in g[:-1]), mask >> 1))
        return out

    def empty(self) -> bool:
        """Whether no point satisfies every inequality."""
        self._ready()
        return not any(g[-1] > 0 for g in self.generators)


def _dot(a: Sequence[int], b: Sequence[int]) -> int:
    return sum(x * y for x, y in zip(a, b))


def _reduced(v: list[int]) -> list[int]:
    g = math.gcd(*v)
    return [x // g for x in v] if g > 1 else v


def _independent(rows: list[tuple[int, ...]], d: int) -> list[int] | None:
    """Indices of d linearly independent rows (greedy, in order), or None."""
    basis: list[list[Fraction]] = []
    pivots: list[int] = []
    chosen: list[int] = []
    for i, r in enumerate(rows):
        v = [Fraction(x) for x in r]
        for b, p in zip(basis, pivots):
            if v[p]:
                f = v[p] / b[p]
                v = [x - f * y for x, y in zip(v, b)]
        nz = next((k for k, x in enumerate(v) if x), None)
        if nz is None:
            continue
        basis.append(v)
        pivots.append(nz)
        chosen.append(i)
        if len(chosen) == d:
            return chosen
    return None


def _simplicial(rows: list[tuple[int, ...]], d: int) -> list[list[int]]:
    """Extreme rays of ``{y : R y <= 0}`` for an invertible R: the columns of ``-R^{-1}``."""
    m = [[Fraction(x) for x in r] + [Fraction(int(i == j)) for j in range(d)]
         for i, r in enumerate(rows)]
    for col in range(d):
        pivot = next(r for r in range(col, d) if m[r][col])
        m[col], m[pivot] = m[pivot], m[col]
        f = m[col][col]
        m[col] = [x / f for x in m[col]]
        for r in range(d):
            if r != col and m[r][col]:
                g = m[r][col]
                m[r] = [x - g * y for x, y in zip(m[r], m[col])]
    inverse = [row[d:] for row in m]
    out = []
    for j in range(d):
        column = [-inverse[i][j] for i in range(d)]
        scale = math.lcm(*(x.denominator for x in column))
        out.append(_reduced([int(x * scale) for x in column]))
    return out


def affine_rank(points: Sequence[Sequence[Fraction]], directions: Sequence[Sequence[Fraction]]
                ) -> int:
    """Dimension of the affine hull of ``points`` plus the cone of ``directions``.

    >>> F = Fraction
    >>> affine_rank([(F(0), F(0)), (F(1), F(1))], [])
    1
    >>> affine_rank([(F(0), F(0))], [(F(1), F(0)), (F(0), F(1))])
    2
    """
    if not points:
        return -1
    base = points[0]
    vectors = [[a - b for a, b in zip(p, base)] for p in points[1:]]
    vectors += [list(d) for d in directions]
    rank = 0
    rows = [list(map(Fraction, v)) for v in vectors]
    n = len(base)
    for col in range(n):
        pivot = next((r for r in range(rank, len(rows)) if rows[r][col]), None)
        if pivot is None:
            continue
        rows[rank], rows[pivot] = rows[pivot], rows[rank]
        for r in range(len(rows)):
            if r != rank and rows[r][col]:
                f = rows[r][col] / rows[rank][col]
                rows[r] = [x - f * y for x, y in zip(rows[r], rows[rank])]
        rank += 1
    return rank
