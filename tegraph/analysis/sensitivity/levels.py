"""A part with levels decided along a line of its durations, piece by piece, exactly.

A part whose groups are periodic units and background tasks
(:mod:`~tegraph.analysis.processors.levels`) is decided at a point of a line
``θ(t) = base + t·direction`` of its durations without simulating: the units
from the most urgent down by Lehoczky, Sha and Ding's exact test
(:func:`~tegraph.analysis.processors.scaling.level_limits`, each unit's work
``c + k·t``), a background task by the utilization of the units above it.
Every condition is a comparison of an affine function of t with a constant,
so the verdict is constant between finitely many breakpoints: :class:`LevelLine`
decides every piece once (at each breakpoint and inside each gap) and
answers any point, or the germ just beside it, with the whole piece of the
same verdict around it (an :class:`~.walk.Outcome` whose cut is that piece),
so that a walk crosses the line in as many steps as the verdict changes.

Where the theorem does not decide (a unit misses its deadline and no task of
its clock closes its activations) the piece's verdict is None and the
schedule itself is simulated there (:mod:`.parts`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction

from ..processors.levels import Level, Levels
from ..processors.scaling import level_limits
from .affine import Cut
from .walk import Outcome

__all__ = ["LevelLine", "level_line"]

Affine = tuple[Fraction, Fraction]
"""``(c, k)``: the value ``c + k·t``."""


def level_line(levels: Levels, duration: Mapping[str, Affine]) -> LevelLine | str:
    """The verdicts of a part with levels along a line, or why the theorem does not apply.

    Parameters
    ----------
    levels : Levels
    duration : mapping of str to (Fraction, Fraction)
        Every task's duration on the line, ``(c, k)`` for ``c + k·t``.

    Returns
    -------
    LevelLine or str
    """
    if any(k < 0 for _, k in duration.values()):
        return "a duration decreases along the line"
    units = [(level, _sum(duration[t] for t in level.tasks)) for level in levels.levels
             if level.clock is not None]
    limits = level_limits([(c, k, level.period) for level, (c, k) in units])  # type: ignore[misc]
    if limits is None:
        return "its units have too many scheduling points (`MAX_POINTS`)"
    return LevelLine(levels, dict(duration), dict(zip((lv.tasks for lv, _ in units), limits)))


def _sum(values) -> Affine:
    c = k = Fraction(0)
    for a, b in values:
        c, k = c + a, k + b
    return c, k


@dataclass(frozen=True)
class _Piece:
    lo: Fraction | None
    lo_closed: bool
    hi: Fraction | None
    hi_closed: bool
    verdict: bool | None
    why: tuple | None


class LevelLine:
    """The part's verdict on every piece of the line (see the module docstring)."""

    def __init__(self, levels: Levels, duration: dict[str, Affine], limits: dict) -> None:
        self.levels = levels.levels
        self.duration = duration
        self.limits = limits
        self.work = {lv.tasks: _sum(duration[t] for t in lv.tasks) for lv in self.levels}
        self.pieces = self._pieces()

    # ------------------------------------------------------------- one point
    def verdict(self, t: Fraction) -> tuple[bool | None, tuple | None]:
        """The part's verdict at t (see :mod:`~tegraph.analysis.processors.levels`)."""
        if any(c + k * t < 0 for c, k in self.duration.values()):
            return False, ("per-task", None)  # outside every range (a negative duration)
        running: str | None = None  # a background task above, with work: it always has a job
        load = Fraction(0)  # utilization of the units above
        for level in self.levels:
            c, k = self.work[level.tasks]
            work = c + k * t
            if work == 0:
                continue
            if level.clock is None:
                if running is not None:
                    return False, ("starved", level.tasks[0], _behind(running))
                if load >= 1:
                    return False, ("starved", level.tasks[0], "the units above it use the "
                                   "whole processor (their utilization is 1)")
                running = level.tasks[0]
                continue
            if running is not None:
                return False, ("starved", self._first_with_work(level, t), _behind(running))
            limit = self.limits[level.tasks]
            if limit.never or (limit.high is not None and t > limit.high):
                if level.closing is not None:
                    return False, ("overrun", level.closing, 2)
                return None, ("undecided", _why_open(level))
            load += work / level.period  # type: ignore[operator]
        return True, None

    def _first_with_work(self, level: Level, t: Fraction) -> str:
        """The first task of ``level`` (each after those it waits for) with work at t: its
        job is released and never runs."""
        return next(task for task in level.tasks
                    if self.duration[task][0] + self.duration[task][1] * t > 0)

    # ------------------------------------------------------------- the pieces
    def _breakpoints(self) -> list[Fraction]:
        """Every t where a condition of :meth:`verdict` may change."""
        points: set[Fraction] = set()
        for c, k in [*self.duration.values(), *self.work.values()]:
            if k:
                points.add(-c / k)
        for limit in self.limits.values():
            if limit.high is not None:
                points.add(limit.high)
        u0 = u1 = Fraction(0)
        for level in self.levels:
            c, k = self.work[level.tasks]
            if level.clock is None:
                if u1:
                    points.add((1 - u0) / u1)
                continue
            u0 += c / level.period  # type: ignore[operator]
            u1 += k / level.period  # type: ignore[operator]
        return sorted(points)

    def _pieces(self) -> list[_Piece]:
        """The line cut at the breakpoints, each point and gap decided, neighbours of the
        same verdict (and reason) joined."""
        points = self._breakpoints()
        atoms: list[_Piece] = []
        if not points:
            return [_Piece(None, False, None, False, *self.verdict(Fraction(0)))]
        edges: list[Fraction | None] = [None, *points, None]
        for i in range(len(edges) - 1):
            lo, hi = edges[i], edges[i + 1]
            inside = _inside(lo, hi)
            atoms.append(_Piece(lo, False, hi, False, *self.verdict(inside)))
            if hi is not None:
                atoms.append(_Piece(hi, True, hi, True, *self.verdict(hi)))
        pieces = [atoms[0]]
        for atom in atoms[1:]:
            last = pieces[-1]
            if (atom.verdict, atom.why) == (last.verdict, last.why):
                pieces[-1] = _Piece(last.lo, last.lo_closed, atom.hi, atom.hi_closed,
                                    last.verdict, last.why)
            else:
                pieces.append(atom)
        return pieces

    def outcome(self, at: Fraction, side: int) -> Outcome:
        """The verdict at ``at`` (``side`` +1/-1: just above/below it), with its piece as
        the cut."""
        piece = next(p for p in self.pieces if _holds(p, at, side))
        cut = Cut(at, side)
        if piece.lo is not None:
            cut.above(piece.lo, piece.lo_closed)
        if piece.hi is not None:
            cut.below(piece.hi, piece.hi_closed)
        return Outcome(piece.verdict, cut, piece.why)


def _inside(lo: Fraction | None, hi: Fraction | None) -> Fraction:
    """A point of the open interval (lo, hi), an end None being infinite (not both)."""
    if lo is None:
        return Fraction(hi - 1)  # type: ignore[operator]
    if hi is None:
        return Fraction(lo + 1)
    return (lo + hi) / 2


def _holds(p: _Piece, at: Fraction, side: int) -> bool:
    """Whether the piece holds ``at`` (side 0) or the germ just above or below it."""
    if side > 0:
        return (p.lo is None or p.lo <= at) and (p.hi is None or p.hi > at)
    if side < 0:
        return (p.lo is None or p.lo < at) and (p.hi is None or p.hi >= at)
    return ((p.lo is None or p.lo < at or (p.lo == at and p.lo_closed))
            and (p.hi is None or p.hi > at or (p.hi == at and p.hi_closed)))


def _behind(running: str) -> str:
    return f"{running}, more urgent and without clock, always has a job"


def _why_open(level: Level) -> str:
    return (f"the group of {', '.join(level.tasks[:3])}{' ...' if len(level.tasks) > 3 else ''} "
            f"misses its deadline as one periodic unit, but no task of its clock ends its "
            "activations after all its jobs: a late task without clock is no overrun (§4b), "
            "so the exact test of units does not decide here")
