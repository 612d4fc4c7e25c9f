"""Walking a line of parameters interval by interval of constant schedule order.

An evaluation of the schedule at a point t of the line (or just beside it)
gives a verdict and the interval around t where every comparison the engine
made answers the same (:mod:`.affine`), so where the verdict is the
same. :func:`walk` moves from such an interval to the next, each end
evaluated at the end itself and just beyond it, until the verdict changes:
every breakpoint of the schedule's order in between is visited, so the end
found is exact. :func:`seek` does the same from a point that is not
schedulable, to the nearest one that is; :func:`sweep` crosses whole
intervals and keeps every schedulable piece.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from fractions import Fraction

from .affine import Cut

__all__ = ["MAX_STEPS", "Interval", "Outcome", "Sweep", "Walk", "per_task_outcome", "seek",
           "sweep", "walk"]

MAX_STEPS = 400
"""Intervals of constant order visited by one :func:`walk` before it stops with a bound."""

Interval = tuple[Fraction, "Fraction | None"]

@dataclass
class Outcome:
    """The verdict of the moving parts at one evaluation point, and where it holds."""

    verdict: bool | None
    cut: Cut
    why: tuple | None = None
    """False: ("overrun", task, k), ("grows", place name), ("starved", task[, why in
    words]), ("per-task", None); None: ("undecided", reason)."""


@dataclass
class Walk:
    """What :func:`walk` found in one direction from its start."""

    end: Fraction | None
    """The last t of the interval (None: unbounded, or nothing proven)."""
    attained: bool = True
    exact: bool = True
    """False: the walk stopped (budget, undecided): ``end`` is only proven so far."""
    beyond: Outcome | None = None
    """The outcome just beyond ``end`` (its cut reaches the next breakpoint)."""
    steps: int = 0
    capped: bool = False
    """The end is the cap given (the per-task end)."""
    why_stopped: str | None = None


def walk(evaluate: Callable[[Fraction, int], Outcome], start: Fraction, up: bool,
         cap: Fraction | None, *, floor: Fraction | None = None,
         max_steps: int = MAX_STEPS, first: Outcome | None = None) -> Walk:
    """From ``start`` (schedulable), the end of its schedulable interval upward or downward.

    ``cap``: stop there (an end already proven by other means, None: none);
    ``floor``: the lowest value of the domain when walking down.
    """
    side = 1 if up else -1
    out = first if first is not None else evaluate(start, 0)
    assert out.verdict is True
    cut = out.cut
    steps = 0
    while True:
        end, closed = (cut.hi, cut.hi_closed) if up else (cut.lo, cut.lo_closed)
        bounded = _bounded(end, closed, up, cap, floor, steps)
        if bounded is not None:
            return bounded
        assert end is not None  # _bounded stops at an unbounded end
        steps += 1
        if steps > max_steps:
            return Walk(end, attained=closed, exact=False, steps=steps,
                        why_stopped=f"stopped after {max_steps} intervals of constant order")
        nxt = evaluate(end, side if closed else 0)
        changed = _changed(end, closed, nxt, steps)
        if changed is not None:
            return changed
        cut = nxt.cut


def _bounded(end: Fraction | None, closed: bool, up: bool, cap: Fraction | None,
             floor: Fraction | None, steps: int) -> Walk | None:
    """The walk's answer when its interval reaches past what bounds it: the cap,
    no end at all, or (down) the floor; None: walk on to ``end``."""
    if end is None or (cap is not None and ((end > cap if up else end < cap)
                                            or (end == cap and closed))):
        if cap is None:
            return Walk(floor if not up else None, steps=steps)
        return Walk(cap, steps=steps, capped=True)
    if floor is not None and (end <= floor if not up else False):
        return Walk(floor, steps=steps, capped=True)
    return None


def _changed(end: Fraction, closed: bool, nxt: Outcome, steps: int) -> Walk | None:
    """The walk's answer when the verdict at (or just past) ``end`` is not schedulable
    (the end, exact) or undecided (the end, proven so far); None: still schedulable."""
    if nxt.verdict is None:
        return Walk(end, attained=closed, exact=False, beyond=nxt, steps=steps,
                    why_stopped=str(nxt.why[1]) if nxt.why else "undecided")
    if nxt.verdict is False:
        return Walk(end, attained=closed, beyond=nxt, steps=steps)
    return None


def per_task_outcome(intervals: Sequence[Interval], t: Fraction, side: int) -> Outcome:
    """Membership of t (or just beside it) in closed intervals, with the piece around it."""
    cut = Cut(t, side)
    for a, b in intervals:
        after_a = t > a or (t == a and side >= 0)
        before_b = b is None or t < b or (t == b and side <= 0)
        if after_a and before_b:
            cut.above(a, True)
            if b is not None:
                cut.below(b, True)
            return Outcome(True, cut)
    for a, b in intervals:  # the gap around t: open at the ends of its neighbours
        if b is not None and (b < t or (b == t and side > 0)):
            cut.above(b, False)
        if a > t or (a == t and side < 0):
            cut.below(a, False)
    return Outcome(False, cut, ("per-task", None))


def seek(evaluate: Callable[[Fraction, int], Outcome], first: Outcome, up: bool,
          max_steps: int) -> tuple[Fraction | None, bool, Outcome | None, int]:
    """From a point that is not schedulable, the nearest schedulable value up or down.

    Returns (value or None when there is none, exact, the outcome on the near side
    of it (not schedulable), intervals visited).
    """
    side = 1 if up else -1
    out = first
    steps = 0
    while True:
        if out.verdict is None:
            return None, False, out, steps
        cut = out.cut
        end, closed = (cut.hi, cut.hi_closed) if up else (cut.lo, cut.lo_closed)
        if end is None or end < 0:
            return None, True, out, steps
        steps += 1
        if steps > max_steps:
            return None, False, out, steps
        nxt = evaluate(end, side if closed else 0)
        if nxt.verdict is True:
            return end, True, out, steps
        out = nxt


@dataclass
class Sweep:
    """What :func:`sweep` found: the schedulable pieces, each ``(low, low excluded,
    high, high excluded)`` (high None: unbounded), in order."""

    intervals: list[tuple[Fraction, bool, Fraction | None, bool]]
    exact: bool = True
    """False: the sweep stopped (undecided, or ``max_steps``) before the end of the range."""
    steps: int = 0
    why: str | None = None


def sweep(evaluate: Callable[[Fraction, int], Outcome], intervals: Sequence[Interval],
          max_steps: int) -> Sweep:
    """Every schedulable value of the closed ``intervals``, piece by piece from the left.

    Each evaluation decides the piece around its point (its cut); the next one is
    taken at the piece's end (just beyond it when the piece holds it), so every
    breakpoint is visited and the pieces found are exact.

    >>> from tegraph.analysis.sensitivity.affine import Cut
    >>> def evaluate(t, side):  # schedulable on [1, 2) only
    ...     cut = Cut(t, side)
    ...     if t < 1 or (t == 1 and side < 0):
    ...         cut.below(Fraction(1), False)
    ...         return Outcome(False, cut)
    ...     if t < 2 or (t == 2 and side < 0):
    ...         cut.above(Fraction(1), True); cut.below(Fraction(2), False)
    ...         return Outcome(True, cut)
    ...     cut.above(Fraction(2), True)
    ...     return Outcome(False, cut)
    >>> sweep(evaluate, [(Fraction(0), Fraction(5))], 10).intervals
    [(Fraction(1, 1), False, Fraction(2, 1), True)]
    """
    found: list[tuple[Fraction, bool, Fraction | None, bool]] = []
    steps = 0
    for a, b in intervals:
        t, side = a, 0
        while True:
            steps += 1
            if steps > max_steps:
                return Sweep(found, False, steps,
                             f"stopped after {max_steps} intervals of constant order")
            out = evaluate(t, side)
            if out.verdict is None:
                why = str(out.why[1]) if out.why else "undecided"
                return Sweep(found, False, steps, why)
            hi, closed = out.cut.hi, out.cut.hi_closed
            last = hi is None or (b is not None and (hi > b or (hi == b and closed)))
            if last and b is not None:
                hi, closed = b, True
            if out.verdict:
                _join(found, (t, side > 0, hi, not closed))
            if last:
                break
            assert hi is not None
            t, side = hi, 1 if closed else 0
    return Sweep(found, True, steps)


def _join(found: list[tuple[Fraction, bool, Fraction | None, bool]],
          piece: tuple[Fraction, bool, Fraction | None, bool]) -> None:
    """Append a schedulable piece, joined to the last one when they touch."""
    if found:
        lo, lo_open, hi, hi_open = found[-1]
        if hi == piece[0] and not (hi_open and piece[1]):
            found[-1] = (lo, lo_open, piece[2], piece[3])
            return
    found.append(piece)
