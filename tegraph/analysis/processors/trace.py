"""What the schedule records for the chains of spec §4c, as periodic sequences of instants.

A chain's latency (:mod:`tegraph.analysis.chains`) reads, for each task it
passes, when its jobs start and end and when some of its events fire (a
read, a write, a sensor's read, an actuator's write). The schedule
(:func:`~tegraph.analysis.processors.schedule.schedule_on_processors`, or
:func:`~tegraph.analysis.processors.schedule.trace_schedule` for the parts of
the chains alone) records them while it simulates, and hands each over as
:class:`Instants`: the sequence over one period of its part's proven periodic
regime, from which every later (and, extended backwards, every earlier)
instant follows. Times are integers on the schedule's scale
(:attr:`ScheduleTrace.scale`), as the engine keeps them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from maxplus.scalar import display_text

from ._engine import PartData, PartResult

__all__ = ["Instants", "ScheduleTrace", "TraceRequest"]


@dataclass(frozen=True)
class TraceRequest:
    """What to record: the firings of some events, the jobs of some tasks.

    Attributes
    ----------
    events : tuple of int
        Events of the timed event graph (indices) whose firing instants are recorded.
    tasks : tuple of str
        Tasks whose jobs' starts and ends are recorded.
    """

    events: tuple[int, ...] = ()
    tasks: tuple[str, ...] = ()


@dataclass(frozen=True)
class Instants:
    """A non-decreasing sequence ``x(0), x(1), ...`` periodic from ``first`` on.

    ``x(first + i) = values[i]`` for ``0 <= i < n`` (``n = len(values) >= 1``) and
    ``x(i + n) = x(i) + length`` for ``i >= first``: one period of a part's regime,
    ``n`` firings (or jobs) in it. The same formula, read for ``i < first``,
    extends the regime backwards: the sequence the part would have had if it had
    always been in its regime (the figures of §4c are those of the regime).

    Examples
    --------
    Firings at 2 and 3 in each regime of length 10, from firing number 4 on:

    >>> x = Instants(4, (2, 3), 10)
    >>> [int(v) for v in x.at(np.arange(2, 8))]
    [-8, -7, 2, 3, 12, 13]
    >>> [int(v) for v in x.last_index(np.array([3, 11, 12]), inclusive=True)]
    [5, 5, 6]
    >>> [int(v) for v in x.last_index(np.array([3, 12]), inclusive=False)]
    [4, 5]
    """

    first: int
    values: tuple[int, ...]
    length: int

    @property
    def count(self) -> int:
        """Firings (or jobs) per regime."""
        return len(self.values)

    def _array(self, like: np.ndarray) -> np.ndarray:
        return np.array(self.values, dtype=like.dtype)

    def at(self, index: np.ndarray) -> np.ndarray:
        """``x(i)`` for each ``i`` of ``index`` (an integer array; int64 or Python ints)."""
        offset = index - self.first
        q = offset // self.count  # floor division on int64 and on Python ints alike
        r = (offset - q * self.count).astype(np.int64)
        return self._array(index)[r] + q * self.length

    def last_index(self, t: np.ndarray, inclusive: bool) -> np.ndarray:
        """For each time of ``t``, the largest ``i`` with ``x(i) <= t`` (``inclusive``) or
        ``x(i) < t``: the last firing by then, in the regime extended backwards.

        One period holds the values in ``[b, b + length]``, ``b = x(first)``: with
        ``q = floor((t - b) / length)``, ``u = t - q·length`` lies in ``[b, b + length)``,
        and the firings of period ``q`` up to ``u`` are the last ones (those of period
        ``q + 1`` come after ``t``). A strict bound at ``u = b`` finds none there: the
        last one is then in period ``q - 1``, the last before ``b + length``.
        """
        values = self._array(t)
        base = values[0]
        q = (t - base) // self.length
        u = t - q * self.length
        c = np.searchsorted(values, u, side="right" if inclusive else "left")
        index = self.first + q * self.count + c - 1
        if not inclusive:
            below_next = int(np.searchsorted(values, base + self.length, side="left"))
            index = np.where(c == 0, self.first + (q - 1) * self.count + below_next - 1, index)
        return index


@dataclass
class ScheduleTrace:
    """What a schedule recorded (:class:`TraceRequest`), on its parts' proven regimes.

    Attributes
    ----------
    scale : int
        Every time is an integer: the instant times ``scale``.
    processor_of : dict of str to str
        Each task's processor on the platform the schedule ran on.
    requested : frozenset of str
        The tasks asked for.
    events : dict of int to Instants
        Each recorded event whose part's regime is proven: its firing instants.
    starts, ends : dict of str to Instants
        Each recorded task whose part's regime is proven and that runs in it: the
        start (the first instant its job holds its processor, §4c) and the end
        ``f_T(k)`` of each job, by activation (index ``k - 1``).
    regime_start : dict of str to int
        Each of those tasks: the instant its part's regime starts.
    undecided : dict of str to str
        Each recorded task without those figures: why (its part has no proven regime
        within the budget, stops, was decided by a theorem that simulates no regime,
        or the task never runs in the regime).
    """

    scale: int
    processor_of: dict[str, str]
    requested: frozenset[str] = frozenset()
    events: dict[int, Instants] = field(default_factory=dict)
    starts: dict[str, Instants] = field(default_factory=dict)
    ends: dict[str, Instants] = field(default_factory=dict)
    regime_start: dict[str, int] = field(default_factory=dict)
    undecided: dict[str, str] = field(default_factory=dict)

    def undecided_part(self, tasks: Sequence[str], why: str) -> None:
        """The part of ``tasks`` gives no regime to read: ``why``, for those recorded."""
        for t in tasks:
            if t in self.requested:
                self.undecided.setdefault(t, why)

    def add_part(self, r: PartResult, d: PartData, names: Sequence[str],
                 events: Sequence[int] | np.ndarray, unit: str) -> None:
        """What the engine recorded in one part whose simulation ended with ``r.regime``
        (``events``: the global event of each local one), one period of it each.

        In the regime ``[t1, t2)`` event e fires ``new.fired[e] - old.fired[e]``
        times, all recorded (the run stops at t2). A job released in it may start or
        end after t2, but only the last one, and then as the job pending at t1 did,
        one regime earlier (the states at t1 and t2 are the same): its instant is
        that one's plus the regime's length.
        """
        if r.regime is None:
            return
        if r.regime[0] == "stop":
            self.undecided_part(names, f"the part of {_shown(names)} stops for ever at "
                                       f"{display_text(Fraction(r.regime[1], self.scale))} "
                                       f"{unit}: no periodic regime of its data")
            return
        t1, t2, old, new, _ = r.regime
        length = t2 - t1
        for e, instants in r.firings.items():
            a, b = old.fired[e], new.fired[e]
            if b > a:
                self.events[int(events[e])] = Instants(a, tuple(instants[a:b]), length)
        compute = {j: e for e, j in enumerate(d.compute_task) if j >= 0}
        for j, starts in r.starts.items():
            name = names[j]
            a, b = old.fired[compute[j]], new.fired[compute[j]]
            if b == a:
                self.undecided[name] = (
                    f"{name} is starved: its job never ends" if new.pending[j] >= 0 else
                    f"{name} never runs in the periodic regime of its part")
                continue
            self.starts[name] = Instants(a, _one_period(starts, a, b, length), length)
            self.ends[name] = Instants(a, _one_period([f for _, f in r.jobs[j]], a, b, length),
                                       length)
            self.regime_start[name] = t1


def _one_period(values: Sequence[int | None], a: int, b: int, length: int) -> tuple[int, ...]:
    """``values[a:b]``, the last one when not recorded (None, or past the list's end) as
    the one a regime before it (``values[a - 1]``) plus ``length``."""
    out = [values[i] if i < len(values) else None for i in range(a, b)]
    if out[-1] is None:
        before = values[a - 1]
        assert before is not None  # the job pending at t1 ends within the regime
        out[-1] = before + length
    assert None not in out  # only the last job of a regime can outlast it
    return tuple(out)  # type: ignore[arg-type]


def _shown(names: Sequence[str]) -> str:
    return ", ".join(names[:3]) + (" ..." if len(names) > 3 else "")
