"""The period to propose for a clock that an advised change adds (Rules 1 and 3).

A group without a clock gets one (Rule 3), a task without a synchronization may
get one of its own (Rule 1). The advisor checks such a change with a period no
group has (:attr:`~.advice.Advisor.fresh`, so that Rule 2 sees no two groups of
one rate); but a period such as ``max + 1`` makes the clocks' hyperperiod, and
so the schedule on processors, astronomically long (101 ms beside 100 ms and
2.5 ms: 10,100 ms; 10^12 + 1 beside 10^12: 10^24), and the schedule undecidable
within any budget. The proposal is taken from the skeleton's own periods instead:

- **from**: the design periods of the groups the new group is linked to (its
  *neighbours*, whose messages it reads or which read its messages); without
  any, those of the groups sharing a processor with it; without any, its own
  cycle time (with a processor per task);
- **candidates**: each of them multiplied or divided by a small factor
  (:data:`FACTORS`), at least the group's cycle time (a faster clock would
  overrun), and none equal to a neighbour's period (Rule 2 would then ask to
  synchronize the two: the change must bring no finding);
- **order**: the smallest hyperperiod with the periods around it first (a divisor
  of their hyperperiod keeps it as it is), then the longest period (the least
  load, the fewest ticks);
- **check**: the advisor judges the first :data:`TRIES` of them by the exact
  schedule on processors (spec §4b) and proposes the first schedulable one (else
  the first); without processors, the first.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from fractions import Fraction

__all__ = ["FACTORS", "TRIES", "candidate_periods", "lcm"]

FACTORS = (1, 2, 3, 4, 5, 6, 8, 10)
"""Multiples and divisors of a period around the group that are proposed."""

TRIES = 6
"""Candidate periods judged by the exact schedule, at most, per change."""


def lcm(periods: Iterable[Fraction]) -> Fraction:
    """Least common multiple of positive rationals (1 for none).

    >>> lcm([Fraction(5, 2), Fraction(1), Fraction(100)])
    Fraction(100, 1)
    >>> lcm([Fraction(100), Fraction(101)])
    Fraction(10100, 1)
    """
    num, den = 1, 0
    for p in periods:
        num, den = math.lcm(num, p.numerator), math.gcd(den, p.denominator)
    return Fraction(num, den or 1)


def candidate_periods(neighbours: Iterable[Fraction], around: Iterable[Fraction],
                      lower: Fraction | None) -> list[tuple[Fraction, Fraction]]:
    """The periods to propose for a new clock, best first, each with its hyperperiod.

    Parameters
    ----------
    neighbours : iterable of Fraction
        The design periods of the groups linked to the new group: the candidates
        are made from them, and none is proposed (Rule 2).
    around : iterable of Fraction
        The design periods of the groups sharing a processor with it: the
        candidates are made from them when there is no neighbour, and the
        hyperperiod is counted over them and the neighbours.
    lower : Fraction or None
        The group's cycle time without the clock (a faster clock overruns); when
        there is nothing to make candidates from, the candidates are its multiples.

    Returns
    -------
    list of (period, hyperperiod)
        Best first (module docstring); empty when nothing is known at all.

    Examples
    --------
    A logger linked to a 1 ms estimator and a 100 ms GPS, beside a 2.5 ms and a
    20 ms loop on its processor, with a cycle time of 1/2 ms: 50 ms keeps the
    hyperperiod at 100 ms, and 1 ms and 100 ms are its neighbours' (Rule 2).

    >>> F = Fraction
    >>> [str(p) for p, _ in candidate_periods([F(1), F(100)], [F(5, 2), F(20)], F(1, 2))[:4]]
    ['50', '100/3', '25', '20']
    >>> candidate_periods([F(10**12)], [F(20)], F(3))[0]
    (Fraction(500000000000, 1), Fraction(1000000000000, 1))
    >>> [str(p) for p, _ in candidate_periods([], [], F(4))[:3]]
    ['4', '8', '12']
    """
    near = {Fraction(p) for p in neighbours}
    others = {Fraction(p) for p in around}
    base = near or others or ({Fraction(lower)} if lower else set())
    if not base:
        return []
    reference = lcm(near | others) if near | others else Fraction(lower or 1)
    found: dict[Fraction, Fraction] = {}
    for p in base:
        for m in FACTORS:
            for value in (p * m, p / m):
                if value in near or value in found or (lower is not None and value < lower):
                    continue
                found[value] = lcm([reference, value])
    return sorted(found.items(), key=lambda x: (x[1], -x[0]))
