"""Tasks on different processors that never execute at the same time (ORCCAD §2.4).

The paper asks the analysis to "facilitate the assignment of MTs to processors, by
identifying those MTs which ... never execute at the very same time". In a schedule
proven by the §4b engine each task's processor time is known for ever: the stretches
before its part's regime (the *transient*, absolute times) and the stretches of one
regime (the *pattern*, repeated every ``length`` from ``start``). Two tasks execute at
the same time when a stretch of one and a stretch of the other share an instant of
positive length; this module decides it exactly, for all time, without unrolling the
regimes:

- transient against transient: two sorted lists of disjoint intervals;
- transient against a pattern: each transient stretch taken modulo the pattern's
  length (a stretch at least that long meets any non-empty pattern);
- pattern against pattern: the instants ``s_A + p + m L_A`` and ``s_B + q + n L_B``
  coincide for some integers ``m, n`` exactly when ``s_A + p`` and ``s_B + q`` are equal
  modulo ``g = gcd(L_A, L_B)`` (Bézout: ``m L_A - n L_B`` takes every multiple of ``g``),
  and every such coincidence recurs at arbitrarily late times, so the steady states
  overlap exactly when the two patterns' images on the circle of length ``g`` meet.

Times are the engine's scaled integers: exact whatever their size (numpy ``int64`` where
they fit, Python integers otherwise).

See Also
--------
tegraph.analysis.processors.schedule.schedule_on_processors : the schedule read here.

References
----------
.. [1] D. Simon et al., "Design and analysis of synchronization for real-time
   closed-loop control in robotics", IEEE Transactions on Control Systems Technology
   Systems Technology, 1998 (the ORCCAD paper), §2.4.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from .schedule import ProcessorSchedule

__all__ = ["MAX_PAIRS", "NeverTogether", "never_together"]

MAX_PAIRS = 20_000
"""Pairs of tasks on different processors examined at most; beyond, nothing is claimed."""

_INT64_SAFE = 2**62


@dataclass(frozen=True)
class _Busy:
    """One task's processor time: ``transient`` before ``start``, then ``pattern``
    (relative to ``start``, inside ``[0, length)``) every ``length``; ``length`` None:
    nothing runs after the transient."""

    transient: tuple[np.ndarray, np.ndarray]
    pattern: tuple[np.ndarray, np.ndarray]
    start: int
    length: int | None


@dataclass(frozen=True)
class NeverTogether:
    """The result of :func:`never_together`.

    ``pairs`` is None when nothing was decided, and ``why`` says why; ``left_out`` names
    the tasks of a processor not examined (they never occupy a processor, or their part
    was decided without its schedule) with the reason.
    """

    pairs: list[tuple[str, str]] | None
    examined: int = 0
    """Pairs of tasks on different processors examined."""
    why: str | None = None
    left_out: dict[str, str] = field(default_factory=dict)


def never_together(schedule: ProcessorSchedule) -> NeverTogether:
    """The pairs of tasks on different processors whose jobs never execute at once.

    Parameters
    ----------
    schedule : ProcessorSchedule
        A §4b schedule computed with its intervals (``intervals=True``, the default of
        :func:`~tegraph.analysis.processors.schedule.schedule_on_processors`).

    Returns
    -------
    NeverTogether
        The pairs, each in file order of the tasks, sorted; None with the reason where
        the schedule is not proven schedulable, holds no intervals, or has more than
        :data:`MAX_PAIRS` pairs. These are candidates to share a processor: moving a
        task changes the schedule, which the §4b engine then decides.

    Examples
    --------
    Two 1 ms tasks every 4 ms on two processors, the second released 2 ms later: they
    run at 0-1 and 2-3 in every period, never together; without the phase, together.

    >>> from tegraph.model.skeleton import Skeleton
    >>> from tegraph.model.build import build_teg
    >>> from tegraph.analysis.analyze import analyze_skeleton
    >>> from tegraph.analysis.processors.schedule import schedule_on_processors
    >>> def pairs(phase):
    ...     sk = Skeleton.from_dict({"tasks": {
    ...         "A": {"duration": 1, "period": 4, "processor": "p"},
    ...         "B": {"duration": 1, "period": 4, "phase": phase, "processor": "q"}}})
    ...     s = schedule_on_processors(sk, build_teg(sk), analyze_skeleton(sk).groups)
    ...     return never_together(s).pairs
    >>> pairs(2), pairs(0)
    ([('A', 'B')], [])
    """
    if schedule.schedulable is not True:
        return NeverTogether(None, why="the schedule on processors is not proven "
                             "schedulable: no task's processor time is known for ever")
    platform = schedule.platform
    if len(platform.processors) < 2:
        return NeverTogether([], why="one processor: no pair on different processors")
    if not schedule.with_intervals:
        return NeverTogether(None, why="the schedule was computed without its intervals")
    busy, left_out = _busy_sets(schedule)
    order = {t: i for i, t in enumerate(schedule.tasks)}
    names = sorted(busy, key=order.__getitem__)
    where = platform.processor_of
    candidates = [(a, b) for i, a in enumerate(names) for b in names[i + 1:]
                  if where[a] != where[b]]
    if len(candidates) > MAX_PAIRS:
        return NeverTogether(None, why=f"{len(candidates)} pairs of tasks on different "
                             f"processors, more than the {MAX_PAIRS} examined",
                             left_out=left_out)
    pairs = [(a, b) for a, b in candidates if not _overlap(busy[a], busy[b])]
    return NeverTogether(pairs, examined=len(candidates), left_out=left_out)


def _busy_sets(schedule: ProcessorSchedule) -> tuple[dict[str, _Busy], dict[str, str]]:
    scale = schedule.scale
    stretches: dict[str, list[tuple[int, int]]] = {}
    for _, a, b, task, _ in schedule.raw_intervals:
        stretches.setdefault(task, []).append((a, b))
    reach = max([b for _, _, b, _, _ in schedule.raw_intervals]
                + [_scaled(r["start"], scale) + 2 * _scaled(r["length"] or Fraction(0), scale)
                   for r in schedule.regimes if r["start"] is not None], default=0)
    dtype: type = np.int64 if reach < _INT64_SAFE else object  # sums stay below 2**63
    busy: dict[str, _Busy] = {}
    left_out: dict[str, str] = {}
    for regime in schedule.regimes:
        by = regime.get("by")
        for task in regime["tasks"]:
            if by is not None:
                left_out[task] = f"its part is decided by the {by}, not by its schedule"
            elif task not in stretches:
                left_out[task] = "it never occupies its processor"
            else:
                busy[task] = _split(stretches[task], regime, scale, dtype)
    return busy, left_out


def _split(stretches: list[tuple[int, int]], regime: dict, scale: int, dtype: type) -> _Busy:
    start = _scaled(regime["start"], scale)
    length = None if regime["length"] is None else _scaled(regime["length"], scale)
    trans = [(a, min(b, start)) for a, b in stretches if a < start]
    if length is None:
        return _Busy(_arrays(trans, dtype), _arrays([], dtype), start, None)
    # The engine records every stretch up to the regime's repeat at start + length.
    pattern = [(max(a, start) - start, b - start) for a, b in stretches
               if b > start and a < start + length]
    return _Busy(_arrays(trans, dtype), _arrays(pattern, dtype), start, length)


def _scaled(t: Fraction, scale: int) -> int:
    value = t * scale
    if value.denominator != 1:  # the engine's times are multiples of 1/scale
        raise ValueError(f"time {t} is not a multiple of 1/{scale}")
    return value.numerator


def _arrays(pairs: list[tuple[int, int]], dtype: type) -> tuple[np.ndarray, np.ndarray]:
    a: np.ndarray = np.array([p[0] for p in pairs], dtype=dtype)
    b: np.ndarray = np.array([p[1] for p in pairs], dtype=dtype)
    return _merged(a, b)


def _merged(starts: np.ndarray, ends: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sorted disjoint intervals covering the same instants (touching ones joined)."""
    if len(starts) == 0:
        return starts, ends
    order = np.argsort(starts, kind="stable")
    s, e = starts[order], ends[order]
    reach = np.maximum.accumulate(e)
    new = np.ones(len(s), dtype=bool)
    new[1:] = s[1:] > reach[:-1]
    first = np.flatnonzero(new)
    last = np.append(first[1:] - 1, len(s) - 1)
    return s[first], reach[last]


def _meets(sorted_set: tuple[np.ndarray, np.ndarray], starts: np.ndarray,
           ends: np.ndarray) -> bool:
    """Whether some interval ``[starts[i], ends[i])`` meets the sorted disjoint set."""
    s1, e1 = sorted_set
    keep = starts < ends
    starts, ends = starts[keep], ends[keep]
    if len(s1) == 0 or len(starts) == 0:
        return False
    idx = np.searchsorted(e1, starts, side="right")  # the first interval ending after
    inside = idx < len(s1)
    return bool(np.any(s1[idx[inside]] < ends[inside]))


def _on_circle(starts: np.ndarray, ends: np.ndarray, offset: int,
               g: int) -> tuple[np.ndarray, np.ndarray]:
    """The instants ``offset + [starts, ends)`` modulo ``g``, as intervals in ``[0, g)``."""
    if len(starts) == 0:
        return starts, ends
    if np.any(ends - starts >= g):
        return np.array([0], dtype=starts.dtype), np.array([g], dtype=starts.dtype)
    u = (starts + offset) % g
    v = u + (ends - starts)
    wraps = v > g
    s = np.concatenate([u, np.zeros(int(wraps.sum()), dtype=starts.dtype)])
    e = np.concatenate([np.minimum(v, g), v[wraps] - g])
    return _merged(s, e)


def _transient_meets_pattern(x: _Busy, y: _Busy) -> bool:
    """Whether ``x``'s transient meets ``y``'s regime (from ``y.start`` on)."""
    if y.length is None or len(y.pattern[0]) == 0:
        return False
    starts, ends = x.transient
    starts = np.maximum(starts, y.start)
    keep = starts < ends
    starts, ends = starts[keep] - y.start, ends[keep] - y.start
    if len(starts) == 0:
        return False
    circle = _on_circle(starts, ends, 0, y.length)
    return _meets(y.pattern, *circle)


def _overlap(x: _Busy, y: _Busy) -> bool:
    if _meets(x.transient, *y.transient):
        return True
    if _transient_meets_pattern(x, y) or _transient_meets_pattern(y, x):
        return True
    if x.length is None or y.length is None:
        return False
    g = math.gcd(x.length, y.length)
    cx = _on_circle(*x.pattern, x.start, g)
    cy = _on_circle(*y.pattern, y.start, g)
    return _meets(cx, *cy)
