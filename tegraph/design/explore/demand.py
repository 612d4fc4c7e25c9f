"""The share of its processor a set of tasks asks: ``Σ duration / period``, exact.

Rule C (:mod:`.prune`), the ``load`` and ``busiest`` objectives (:mod:`.evaluate`) add
one such share per task of a variant: at a thousand tasks, a thousand Fraction
additions (each a gcd) per variant are a large part of judging it. The durations of one
processor and period are summed as integers over their common denominator instead, and
divided by the period once.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from fractions import Fraction

__all__ = ["processor_shares"]


def processor_shares(entries: Iterable[tuple[str, Fraction, Fraction]],
                     every: Iterable[str] = ()) -> dict[str, Fraction]:
    """``Σ duration / period`` of ``(processor, duration, period)`` entries per processor
    (each processor of ``every`` at least 0), exact; a period of 0 (a circuit of zero
    durations) takes no time.

    Parameters
    ----------
    entries : iterable of (str, Fraction, Fraction)
        A task's processor, duration and period each.
    every : iterable of str
        Processors to report even when no entry names them.

    Returns
    -------
    dict of str to Fraction
        Each processor's share, in the order first met (``every`` first).

    See Also
    --------
    tegraph.design.explore.prune.overloaded : rule C, which reads these shares.

    Examples
    --------
    >>> {p: str(v) for p, v in processor_shares([("a", Fraction(1, 3), Fraction(2)),
    ...     ("a", Fraction(1, 6), Fraction(2)), ("b", Fraction(1), Fraction(4))]).items()}
    {'a': '1/4', 'b': '1/4'}
    """
    buckets: dict[tuple[str, int, int], list[Fraction]] = {}
    for processor, duration, period in entries:
        if period:
            buckets.setdefault((processor, period.numerator, period.denominator),
                               []).append(duration)
    out = dict.fromkeys(every, Fraction(0))
    for (processor, num, den), durations in buckets.items():
        common = math.lcm(*{d.denominator for d in durations})
        total = sum(d.numerator * (common // d.denominator) for d in durations)
        out[processor] = out.get(processor, Fraction(0)) + Fraction(total * den, common * num)
    return out
