"""The busy-period analysis of every unit of one non-preemptive processor at once.

:func:`~tegraph.design.busy_period.busy_period_response` (the reference) analyzes one
task from its own list of interferers; on a processor of ``n`` units, building,
validating and scaling that list for each unit costs ``O(n)`` Python work per unit
before the first iteration. :class:`Levels` does that work once for the processor:
its periodic units sorted most urgent first, validated once, scaled to integers by
one common denominator, their costs and periods as numpy arrays. The interferers of
a unit are then a prefix of those arrays (every unit at its priority or above) minus
the unit itself, their loads and costs prefix sums, and each step of a fixed-point
iteration one vectorized sum.

The answer is the reference's, field for field (``terms`` included):

- the recurrences run on integers at the common scale ``S``, a multiple of the
  reference's own scale ``s`` (the least common denominator of the unit's times and
  its interferers'); the fixed points, responses and busy period are the same times;
- where the reference starts an iteration at a ceiling on its scale ``s``, so does
  this one (the ceiling is taken at ``s`` and multiplied by ``S/s``): the iterates
  are the same times, so is their number, and so is every term counted;
- the hyperperiod of an endless level is ``lcm(T_j)/T``, the same ratio at any
  common scale.

Sums are taken on int64 only where they cannot overflow: each term ``N(x, T_j)·C_j``
is at most ``(x/T_j + 1)·C_j``, so the whole sum is at most ``x + Σ C_j`` (the level
needs at most the processor), and an iteration whose ``x + Σ C_j`` is not below
``2**62`` (or a processor whose scaled times are not) sums exact Python integers
instead.
"""

from __future__ import annotations

import math
from bisect import bisect_right
from collections.abc import Iterable, Sequence
from fractions import Fraction
from itertools import accumulate

import numpy as np

from ..errors import InputError
from .busy_period import BusyPeriodResponse, _budget, _time, outcome

__all__ = ["Levels"]

_LIMIT = 2**62
"""Below this, every int64 sum of the recurrences holds its exact value."""


class Levels:
    """The periodic units of one processor, most urgent first, on one integer scale.

    Parameters
    ----------
    units : sequence of (cost, period, priority)
        Every periodic unit of the processor (cost >= 0, period > 0), in any order.
    times : iterable of Fraction
        Every other time a query may pass (blockings, last parts): the common scale
        covers them.

    Examples
    --------
    Davis et al.'s three CAN frames (1 ms each; periods 2.5, 3.5 and 3.5 ms; most
    urgent first): the third frame responds in 3.5 ms, in the second instance of its
    busy period, as :func:`~tegraph.design.busy_period.busy_period_response` says.

    >>> F = Fraction
    >>> levels = Levels([(F(1), F(5, 2), 3), (F(1), F(7, 2), 2), (F(1), F(7, 2), 1)], [F(1)])
    >>> r = levels.response(2)
    >>> r.status, r.value, r.instances, r.worst_instance, r.busy_period
    ('exact', Fraction(7, 2), 2, 1, Fraction(7, 1))
    """

    def __init__(self, units: Sequence[tuple[Fraction, Fraction, int]],
                 times: Iterable[Fraction]) -> None:
        self.units = [(_time(c, "cost"), _time(t, "period", positive=True), p)
                      for c, t, p in units]
        order = sorted(range(len(units)), key=lambda n: -self.units[n][2])
        # Zero-cost units interfere with nothing: the arrays hold the others only.
        busy = [n for n in order if self.units[n][0]]
        self._priorities = [-self.units[n][2] for n in busy]  # ascending, for bisect
        self._position = {n: k for k, n in enumerate(busy)}
        costs = [self.units[n][0] for n in busy]
        periods = [self.units[n][1] for n in busy]
        # The prefix least common denominators: the reference's scale of a unit is the
        # lcm of the prefix up to its level with the denominators of its own times.
        self._lcm = [1]
        for c, t in zip(costs, periods, strict=True):
            self._lcm.append(math.lcm(self._lcm[-1], c.denominator, t.denominator))
        self.scale = math.lcm(self._lcm[-1], *(Fraction(x).denominator for x in times))
        s = self.scale
        self._c = [int(c * s) for c in costs]
        self._t = [int(t * s) for t in periods]
        self._csum = [0, *accumulate(self._c)]
        self._load = [Fraction(0)]
        for c, t in zip(costs, periods, strict=True):
            self._load.append(self._load[-1] + c / t)
        self._wide_c = np.array(self._c, dtype=object)
        self._wide_t = np.array(self._t, dtype=object)
        fits = all(x < _LIMIT for x in (*self._c, *self._t))
        self._narrow_c = np.array(self._c, dtype=np.int64) if fits else None
        self._narrow_t = np.array(self._t, dtype=np.int64) if fits else None

    def response(self, unit: int, *, blocking: Fraction | int = 0,
                 last: Fraction | int | None = None,
                 budget: int | None = None) -> BusyPeriodResponse:
        """What :func:`~tegraph.design.busy_period.busy_period_response` answers for
        unit ``unit`` (an index into ``units``) on a non-preemptive processor, its
        interferers every other unit at its priority or above, without jitter.

        Parameters
        ----------
        unit : int
            The unit's index in ``units``.
        blocking, last : Fraction
            As for :func:`~tegraph.design.busy_period.busy_period_response`; both
            among the ``times`` the levels were built with (or integers).
        budget : int, optional
            Most terms to evaluate.

        Returns
        -------
        BusyPeriodResponse
            The reference's answer, field for field.
        """
        budget = _budget(budget)
        c, t, priority = self.units[unit]
        b = _time(blocking, "blocking")
        f = c if last is None else _time(last, "last")
        if c and not 0 < f <= c:
            raise InputError(f"expected 0 < last <= cost = {c}, got {f}", "last")
        if c == 0:
            return BusyPeriodResponse("exact", Fraction(0), Fraction(0), Fraction(0), 1, 0,
                                      Fraction(0), 0)
        k = bisect_right(self._priorities, -priority)  # every unit at its priority or above
        level = self._load[k]
        load = level - c / t
        if load >= 1:
            return BusyPeriodResponse("no time", None, None, None, 0, None, None, 0)
        if level > 1:
            return BusyPeriodResponse("unbounded", None, None, None, 0, None, None, 0)
        s = self.scale
        spread = Fraction(self._csum[k], s) - c
        upper = f + (b + c - f + spread) / (1 - load)
        own = math.lcm(self._lcm[k], b.denominator, f.denominator)
        if s % own:
            raise ValueError("blocking and last must be among the times the levels were built with")
        return _Run(self, k, self._position[unit], own, budget).run(
            int(c * s), int(t * s), int(b * s), int(f * s), load, level, upper,
            level == 1 and b > 0)


class _Run:
    """The recurrences of one unit: the prefix ``[0, k)`` of the levels' arrays."""

    def __init__(self, levels: Levels, k: int, me: int, own: int, budget: int) -> None:
        self.levels, self.k, self.me = levels, k, me
        self.step = levels.scale // own  # the reference's unit of time, at the common scale
        self.budget = budget
        self.terms = 0

    def _ceil(self, work: int, free: Fraction) -> int:
        """``ceil(work/free)`` on the reference's scale, at the common scale."""
        return -(-(work // self.step) * free.denominator // free.numerator) * self.step

    def _sum(self, x: int, preemptive_count: bool) -> int:
        """``Σ N(x, T_j)·C_j`` over the prefix (``ceil`` or ``floor + 1``)."""
        lv, k = self.levels, self.k
        if not k:
            return 0
        if lv._narrow_c is not None and lv._narrow_t is not None and x + lv._csum[k] < _LIMIT:
            c, t = lv._narrow_c[:k], lv._narrow_t[:k]
        else:
            c, t = lv._wide_c[:k], lv._wide_t[:k]
        n = -(-x // t) if preemptive_count else x // t + 1
        return int(np.dot(n, c))

    def _fixed_point(self, base: int, start: int, tasks: int, busy: bool,
                     own: tuple[int, int]) -> int | None:
        """Least fixed point of ``x = base + Σ N(x, T_j)·C_j`` from a start below it,
        over the prefix (``busy``: all of it, with ceilings) or the prefix without the
        unit itself (``floor + 1``); None when the budget runs out first."""
        c, t = own
        x = start
        cost = max(tasks, 1)  # as the reference counts: no interferer is one term
        while self.terms + cost <= self.budget:
            self.terms += cost
            if busy:
                nxt = base + self._sum(x, True)
            else:
                nxt = base + self._sum(x, False) - (x // t + 1) * c
            if nxt == x:
                return x
            x = nxt
        return None

    def run(self, c: int, t: int, b: int, f: int, load: Fraction, level: Fraction,
            upper: Fraction, endless: bool) -> BusyPeriodResponse:
        lv, k = self.levels, self.k
        s = lv.scale
        hep_cost = lv._csum[k]
        hp_cost = hep_cost - c
        busy = None
        if not endless:
            start = b + hep_cost
            if level < 1:
                start = max(start, self._ceil(b, 1 - level))
            busy = self._fixed_point(b, start, k, True, (c, t))
        if busy is not None:
            instances = -(-busy // t)
        elif endless:
            instances = math.lcm(*lv._t[:k]) // t + 1
        else:  # the budget ran out in the busy period
            instances = 0
        worst: int | None = None
        best = b + c + hp_cost  # R(0) is at least this
        w_prev = None
        q = 0
        while q < instances:
            base = b + (q + 1) * c - f
            start = max(base + hp_cost, self._ceil(base, 1 - load))
            if w_prev is not None:
                start = max(start, w_prev + c)
            w = self._fixed_point(base, start, k - 1, False, (c, t))
            if w is None:
                break
            r = w + f - q * t
            if worst is None or r > best:
                best, worst = r, q
            w_prev = w
            q += 1
        return outcome(best, s, busy, q, instances, worst, endless, upper, self.terms)
