"""Affine times ``c + k·t`` that record where each comparison keeps its answer.

The §4b engine (:func:`~tegraph.analysis.processors._engine.simulate_part`)
only adds times, multiplies them by numbers and compares them. Run on
:class:`Lin` numbers, evaluated at one point ``t0`` of a line (or just above
or below it, the germ ``t0 ± ε``: value first, then slope), each comparison
answers as at that point and narrows a shared :class:`Cut` to the set of t
where it would answer the same: a half-line, or the point ``t0`` alone when
two different affine times tie there. When the run ends, the cut is an
interval on which the engine takes exactly the same steps (the proof is in
``docs/sensitivity.md``, *On processors*).
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

__all__ = ["Cut", "Lin", "lin"]

class Cut:
    """The evaluation point (``at``, ``side``: 0 at it, +1 just above, -1 just below)
    and the interval of t where every comparison made so far answers the same."""

    __slots__ = ("at", "side", "lo", "lo_closed", "hi", "hi_closed")

    def __init__(self, at: Fraction, side: int) -> None:
        self.at, self.side = at, side
        self.lo: Fraction | None = None  # None: unbounded
        self.lo_closed = True
        self.hi: Fraction | None = None
        self.hi_closed = True

    def sign(self, c: Any, k: Any) -> int:
        """The sign of ``c + k·t`` at the evaluation point, recording where it holds."""
        v = c + k * self.at
        if v > 0:
            s = 1
        elif v < 0:
            s = -1
        elif k == 0 or self.side == 0:
            s = 0
        else:  # just beside a root: the slope decides
            s = self.side if k > 0 else -self.side
        if k:
            r = Fraction(-c) / k
            if s == 0:
                self.above(r, True)
                self.below(r, True)
            elif (s > 0) == (k > 0):
                self.above(r, False)
            else:
                self.below(r, False)
        return s

    def above(self, r: Fraction, closed: bool) -> None:
        """Keep t >= r (closed) or t > r."""
        if self.lo is None or r > self.lo or (r == self.lo and not closed):
            self.lo, self.lo_closed = r, closed

    def below(self, r: Fraction, closed: bool) -> None:
        """Keep t <= r (closed) or t < r."""
        if self.hi is None or r < self.hi or (r == self.hi and not closed):
            self.hi, self.hi_closed = r, closed

    def meet(self, other: Cut) -> None:
        """Narrow this cut to its intersection with ``other``."""
        if other.lo is not None:
            self.above(other.lo, other.lo_closed)
        if other.hi is not None:
            self.below(other.hi, other.hi_closed)


def lin(c: Any, k: Any, cut: Cut) -> Any:
    """``c + k·t`` as a :class:`Lin`, or the plain number ``c`` when ``k`` is 0."""
    return Lin(c, k, cut) if k else c


class Lin:
    """``c + k·t`` (k != 0; a constant is a plain number), compared at ``cut``'s point.

    Only what the engine does is defined: sums, differences, products by a
    number, comparisons, truth and hashing (equal at the point: same hash).
    """

    __slots__ = ("c", "k", "cut")

    def __init__(self, c: Any, k: Any, cut: Cut) -> None:
        self.c, self.k, self.cut = c, k, cut

    def __add__(self, o: Any) -> Any:
        if isinstance(o, Lin):
            return lin(self.c + o.c, self.k + o.k, self.cut)
        return Lin(self.c + o, self.k, self.cut)

    __radd__ = __add__

    def __sub__(self, o: Any) -> Any:
        if isinstance(o, Lin):
            return lin(self.c - o.c, self.k - o.k, self.cut)
        return Lin(self.c - o, self.k, self.cut)

    def __rsub__(self, o: Any) -> Any:
        return Lin(o - self.c, -self.k, self.cut)

    def __neg__(self) -> Lin:
        return Lin(-self.c, -self.k, self.cut)

    def __mul__(self, o: Any) -> Any:
        if isinstance(o, Lin):
            raise TypeError("a product of two times is not affine")
        return lin(self.c * o, self.k * o, self.cut)

    __rmul__ = __mul__

    def _sign(self, o: Any) -> int:
        if isinstance(o, Lin):
            return self.cut.sign(self.c - o.c, self.k - o.k)
        return self.cut.sign(self.c - o, self.k)

    def __lt__(self, o: Any) -> bool:
        return self._sign(o) < 0

    def __le__(self, o: Any) -> bool:
        return self._sign(o) <= 0

    def __gt__(self, o: Any) -> bool:
        return self._sign(o) > 0

    def __ge__(self, o: Any) -> bool:
        return self._sign(o) >= 0

    def __eq__(self, o: object) -> bool:
        if not isinstance(o, (Lin, int, Fraction)):
            return NotImplemented
        return self._sign(o) == 0

    def __ne__(self, o: object) -> bool:
        if not isinstance(o, (Lin, int, Fraction)):
            return NotImplemented
        return self._sign(o) != 0

    def __bool__(self) -> bool:
        return self.cut.sign(self.c, self.k) != 0

    def __hash__(self) -> int:
        # Equal objects must hash alike: at the point, equal values; beside it,
        # equal values and slopes (a plain number never equals a Lin there).
        v = self.c + self.k * self.cut.at
        return hash(v) if self.cut.side == 0 else hash((v, self.k))

    def __repr__(self) -> str:
        return f"Lin({self.c} + {self.k}·t)"
