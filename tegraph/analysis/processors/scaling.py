"""The critical scaling factor of Lehoczky, Sha and Ding, exact, for independent units.

For a part that satisfies the hypotheses of :mod:`.critical_instant`
(independent periodic tasks released together on one preemptive processor,
deadline = period, distinct priorities: ``critical_instant._independent`` is the
one test of them, and declines a non-preemptive processor, where a running job
blocks a more urgent one and no scheduling point below counts it), Lehoczky,
Sha and Ding's exact test [1]_ reads:
task i meets every deadline iff there is a *scheduling point*
``t in S_i = {k T_j : j at least as urgent as i, k = 1 .. floor(T_i / T_j)}``
(``T_i`` is one of them) with ``W_i(t) <= t``, where
``W_i(t) = sum over j at least as urgent as i of C_j ceil(t / T_j)`` is the
work released in ``[0, t)`` by task i and the more urgent ones.

Multiplying every duration by ``a`` multiplies every ``W_i(t)`` by ``a``, so
task i meets every deadline iff ``a <= max_{t in S_i} t / W_i(t)``, and the
whole part iff ``a <= a* = min_i max_{t in S_i} t / W_i(t)``: the *critical
scaling factor* [1]_, exact, and the schedulable factors are the closed
interval ``[0, a*]`` (monotone: each ``W_i`` grows with ``a``).

One duration ``C_m`` alone (:func:`duration_margin`) enters ``W_i`` for the
tasks i at most as urgent as m with the coefficient ``ceil(t / T_m)``, so task
i meets every deadline iff ``C_m <= max_{t in S_i} (t - W_i(t) + C_m
ceil(t/T_m)) / ceil(t/T_m)``, and the part iff ``C_m`` is at most the minimum
of those over the tasks i at most as urgent as m: again a closed interval
from 0, the others' durations fixed.

Along any line of the durations (each ``C_j = c_j + k_j t`` with ``k_j >= 0``:
all times one factor, one alone, or any mix), ``W_i(s) = a_s + b_s t`` at each
scheduling point, so unit i meets every deadline exactly for the t with
``t <= max_{s in S_i, b_s > 0} (s - a_s) / b_s`` (every t when some point has
``b_s = 0`` and ``a_s <= s``): :func:`level_limits`, for the units of
:mod:`tegraph.analysis.processors.levels` as well as for single tasks.

§4b's overrun is the classical deadline miss here: while no job is late, each
job is released at its tick and the schedule is the classical one; the first
job still running at its next tick is the first deadline miss (an activation
ending at the tick is in time, as ``<=`` above). The proof is in
``docs/sensitivity.md`` (*On processors*).

References
----------
.. [1] J. Lehoczky, L. Sha, Y. Ding, "The rate monotonic scheduling algorithm:
   exact characterization and average case behavior", IEEE Real-Time Systems
   Symposium, 166–171, 1989.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction

__all__ = ["MAX_POINTS", "LineLimit", "ScalingLimit", "critical_scaling_factor",
           "duration_margin", "level_limits"]

MAX_POINTS = 1_000_000
"""Scheduling points examined in all before giving up (None is returned)."""


@dataclass(frozen=True)
class ScalingLimit:
    """The exact bound and the task that sets it (the first, most urgent first, at the min)."""

    value: Fraction | None
    """None: unbounded (the tasks concerned have no work)."""
    task: int | None


def _points(periods: Sequence[Fraction], i: int, budget: list[int]) -> list[Fraction] | None:
    """S_i: the multiples k T_j <= T_i of the periods of tasks 0..i (most urgent first)."""
    out = {periods[i]}
    for j in range(i + 1):
        n = int(periods[i] // periods[j])
        budget[0] -= n
        if budget[0] < 0:
            return None
        out.update(k * periods[j] for k in range(1, n + 1))
    return sorted(out)


def _ceil(t: Fraction, p: Fraction) -> int:
    return -(-t // p)


def critical_scaling_factor(tasks: Sequence[tuple[Fraction, Fraction]], *,
                            max_points: int = MAX_POINTS) -> ScalingLimit | None:
    """``a* = min_i max_{t in S_i} t / W_i(t)`` (see the module docstring).

    Parameters
    ----------
    tasks : sequence of (duration, period)
        Most urgent first; periods > 0, durations >= 0.
    max_points : int
        Budget of scheduling points; None is returned past it.

    Returns
    -------
    ScalingLimit or None
        ``value`` None when no task has work (every factor is schedulable).

    Examples
    --------
    Liu and Layland's pair (2, 5), (2, 7): task 2 meets its deadline iff
    ``2a + 2a <= 5`` (t = 5) or ``2·2a + 2a <= 7`` (t = 7), so ``a* = max(5/4, 7/6)``:

    >>> r = critical_scaling_factor([(Fraction(2), Fraction(5)), (Fraction(2), Fraction(7))])
    >>> r.value, r.task
    (Fraction(5, 4), 1)
    """
    periods = [p for _, p in tasks]
    budget = [max_points]
    best: Fraction | None = None
    who: int | None = None
    for i in range(len(tasks)):
        points = _points(periods, i, budget)
        if points is None:
            return None
        top: Fraction | None = Fraction(0)
        for t in points:
            work = sum((c * _ceil(t, p) for c, p in tasks[:i + 1]), Fraction(0))
            if work == 0:
                top = None  # no work up to i: any factor
                break
            top = max(top, t / work)  # type: ignore[type-var]
        if top is not None and (best is None or top < best):
            best, who = top, i
    return ScalingLimit(best, who)


def duration_margin(tasks: Sequence[tuple[Fraction, Fraction]], m: int, *,
                    max_points: int = MAX_POINTS) -> ScalingLimit | None:
    """The largest duration of task ``m`` alone keeping every deadline (see the docstring).

    Parameters
    ----------
    tasks : sequence of (duration, period)
        Most urgent first; ``tasks[m]``'s duration is the one varied.
    m : int
    max_points : int

    Returns
    -------
    ScalingLimit or None
        ``value`` None: unbounded (not possible here: task m's own deadline
        bounds it by its period); negative: no value of ``C_m >= 0`` is
        schedulable (``task`` misses its deadline whatever ``C_m``).

    Examples
    --------
    Under (2, 5), the second task (period 7) may take 3 (it ends at 7 after
    being preempted at 5), not more:

    >>> duration_margin([(Fraction(2), Fraction(5)), (Fraction(2), Fraction(7))], 1).value
    Fraction(3, 1)
    """
    periods = [p for _, p in tasks]
    budget = [max_points]
    for i in range(m):  # the more urgent tasks do not depend on C_m: each must pass as is
        points = _points(periods, i, budget)
        if points is None:
            return None
        if not any(sum((c * _ceil(t, p) for c, p in tasks[:i + 1]), Fraction(0)) <= t
                   for t in points):
            return ScalingLimit(Fraction(-1), i)
    best: Fraction | None = None
    who: int | None = None
    for i in range(m, len(tasks)):
        points = _points(periods, i, budget)
        if points is None:
            return None
        top: Fraction | None = None
        for t in points:
            n = _ceil(t, periods[m])
            rest = sum((c * _ceil(t, p) for j, (c, p) in enumerate(tasks[:i + 1]) if j != m),
                       Fraction(0))
            value = (t - rest) / n
            top = value if top is None else max(top, value)
        if top is not None and (best is None or top < best):
            best, who = top, i
    return ScalingLimit(best, who)


@dataclass(frozen=True)
class LineLimit:
    """Where one unit meets every deadline along a line of the durations: the t <= ``high``."""

    high: Fraction | None
    """None: every t (``never`` False) or no t (``never`` True)."""
    never: bool = False


def level_limits(units: Sequence[tuple[Fraction, Fraction, Fraction]], *,
                 max_points: int = MAX_POINTS) -> list[LineLimit] | None:
    """For each unit along a line, the t where it meets every deadline (exact test).

    Parameters
    ----------
    units : sequence of (c, k, period)
        Most urgent first; the unit's work on the line is ``c + k·t``, ``k >= 0``.
    max_points : int
        Budget of scheduling points; None is returned past it.

    Returns
    -------
    list of LineLimit or None
        Unit i meets every deadline, its work and that of the more urgent units
        released together at 0 (Lehoczky, Sha and Ding's test, module docstring),
        exactly for the t of its limit.

    Examples
    --------
    Liu and Layland's pair again, the second duration ``t`` (``duration_margin``):
    the first meets its deadline for every t, the second for ``t <= 3``; all
    durations times t (``critical_scaling_factor``): ``t <= 5/4`` for the second.

    >>> F = Fraction
    >>> [x.high for x in level_limits([(F(2), F(0), F(5)), (F(0), F(1), F(7))])]
    [None, Fraction(3, 1)]
    >>> [x.high for x in level_limits([(F(0), F(2), F(5)), (F(0), F(2), F(7))])]
    [Fraction(5, 2), Fraction(5, 4)]
    """
    # On integers: every time times the lcm D of the denominators (a ceiling
    # ceil(s/T) and the ratio (s - a)/b do not change), each ratio kept as a pair.
    scale = math.lcm(*(x.denominator for unit in units for x in unit)) if units else 1
    c = [int(x * scale) for x, _, _ in units]
    k = [int(x * scale) for _, x, _ in units]
    periods = [int(p * scale) for _, _, p in units]
    left = max_points
    out = []
    for i in range(len(units)):
        points = {periods[i]}
        for j in range(i + 1):
            n = periods[i] // periods[j]
            left -= n
            if left < 0:
                return None
            points.update(range(periods[j], n * periods[j] + 1, periods[j]))
        best: tuple[int, int] | None = None  # (numerator, denominator > 0)
        every = False
        for point in points:
            ceils = [-(-point // periods[j]) for j in range(i + 1)]
            a = sum(cj * n for cj, n in zip(c, ceils))
            b = sum(kj * n for kj, n in zip(k, ceils))
            if b == 0:
                if a <= point:
                    every = True
                    break
                continue
            if best is None or (point - a) * best[1] > best[0] * b:
                best = (point - a, b)
        out.append(LineLimit(None) if every else
                   LineLimit(None if best is None else Fraction(*best), never=best is None))
    return out
