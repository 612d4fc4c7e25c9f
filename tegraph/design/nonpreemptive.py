"""The response-time cross-check on a non-preemptive processor (spec §4d).

A processor declared ``preemptive: false`` (a bus that sends one frame at a time,
a cooperative executor) never interrupts a running job: a less urgent job that has
just started delays a more urgent one by up to its whole duration, and a job that
waits may see more urgent ones overtake it. Joseph and Pandya's recurrence counts
neither; the revised analysis of Davis, Burns, Bril and Lukkien [1]_
(:func:`~tegraph.design.busy_period.busy_period_response`) counts both, over every
instance of the level-i busy period. The analysis of Tindell et al. that examines
the first instance alone is optimistic [1]_ and is not used.

**Units as periodic tasks.** As on a preemptive processor
(:mod:`tegraph.design.schedulability`), a *unit* is the tasks of one group on the
processor at one priority, taken as one periodic task: its work ``C`` (the sum of
their durations) every period of its group, ready at its activation. Without
preemption the unit's tasks are its non-preemptive *parts* (Bril et al. [2]_): more
urgent jobs may come between two of them, so the analysis takes as its last part
the shortest of them (any of them may run last: the shortest gives the largest
bound), and the part a less urgent unit blocks it with is the longest task of that
unit. A unit of one task is Davis et al.'s message exactly.

**Free-running tasks.** A unit whose group has no clock is no periodic load:
nothing paces it. It is charged to no unit's interference, but on a processor that
does not preempt, any of its jobs may have just started when a more urgent job is
released: its longest task blocks every more urgent unit (and one at its own
priority, which it may precede by release time), as a less urgent periodic unit
does. A free-running unit with work above a periodic one may take every instant: the
periodic one is left no time. Its own figures are the exact schedule's.

Each bound holds over every phase of the clocks (from each unit's activation to its
end): it is the cross-check of the exact schedule (spec §4b, §4d), never the verdict.

References
----------
.. [1] R. I. Davis, A. Burns, R. J. Bril, J. J. Lukkien, "Controller Area Network
   (CAN) schedulability analysis: refuted, revisited and revised", Real-Time
   Systems 35(3), 239–272, 2007.
.. [2] R. J. Bril, J. J. Lukkien, W. F. J. Verhaegh, "Worst-case response time
   analysis of real-time tasks under fixed-priority scheduling with deferred
   preemption", Real-Time Systems 42(1-3), 63–119, 2009.
"""

from __future__ import annotations

from bisect import bisect_left
from collections import Counter
from collections.abc import Callable, Collection, Mapping, Sequence
from fractions import Fraction
from typing import Protocol

from maxplus.scalar import display_text

from ._busy_levels import Levels
from .busy_period import BusyPeriodResponse

__all__ = ["REVISED_TEST", "Unit", "judge_non_preemptive"]

REVISED_TEST = ("revised response-time analysis for non-preemptive fixed priorities "
                "(Davis, Burns, Bril and Lukkien 2007)")
"""The test of a unit on a non-preemptive processor, as the report names it: a
cross-check over all phases, never the verdict."""


class Unit(Protocol):
    """What the cross-check reads and writes of a unit
    (:class:`~tegraph.design.schedulability.UnitVerdict` is one)."""

    group: int
    tasks: list[str]
    priority: int
    period: Fraction | None
    cost: Fraction
    response_time: Fraction | None
    schedulable: bool | None
    margin: Fraction | None
    test: str
    note: str
    bounds: tuple[Fraction, Fraction] | None


def judge_non_preemptive(units: Sequence[Unit], durations: Mapping[str, Fraction],
                         free_running: Collection[int], unit: str = "ms", *,
                         budget: int | None = None) -> None:
    """The revised analysis of every periodic unit of one non-preemptive processor.

    Sets each periodic unit's ``response_time`` (the bound, exact rational),
    ``schedulable`` (the bound within its period, or not), ``margin``, ``bounds``
    (when only bounds are known), ``test`` and ``note`` (the blocking it counts and
    the instances examined). A unit without a period (a dead group, or no time
    passing in its period) and a free-running unit are left as they are, but block
    the more urgent ones.

    Parameters
    ----------
    units : sequence of Unit
        Every unit of the processor (:class:`Unit`).
    durations : mapping of str to Fraction
        Each task's duration: the non-preemptive parts of a unit.
    free_running : collection of int
        The groups without a clock (spec §4b: least urgent under the proposal).
    unit : str
        The time unit, for the notes.
    budget : int, optional
        Most terms of the recurrences per unit
        (:data:`~tegraph.design.busy_period.BUSY_PERIOD_BUDGET`).

    Examples
    --------
    The CAN frames of Davis et al. (1 ms; 2.5, 3.5, 3.5 ms; most urgent first): 2, 3
    and 3.5 ms, the last in the second instance of its busy period.

    >>> from types import SimpleNamespace as U
    >>> F = Fraction
    >>> frames = [U(group=g, tasks=[n], priority=p, period=t, cost=F(1), response_time=None,
    ...             schedulable=None, margin=None, test="", note="", bounds=None)
    ...           for g, (n, p, t) in enumerate([("F1", 3, F(5, 2)), ("F2", 2, F(7, 2)),
    ...                                          ("F3", 1, F(7, 2))])]
    >>> judge_non_preemptive(frames, {"F1": F(1), "F2": F(1), "F3": F(1)}, ())
    >>> [(u.tasks[0], str(u.response_time), u.schedulable) for u in frames]
    [('F1', '2', True), ('F2', '3', True), ('F3', '7/2', True)]
    >>> frames[2].note
    'worst in instance 2 of 2 of its busy period (7 ms)'
    """
    periodic = [u for u in units if u.period and u.group not in free_running]
    if not periodic:
        return
    counted = {id(u) for u in periodic}
    hogs = _Hogs([v for v in units if v.group in free_running and v.cost > 0])
    blocking_at = _blocking_by_level(units, durations, counted)
    ties = Counter(u.priority for u in periodic)
    # Type: `periodic` units have a period.
    levels = Levels([(u.cost, u.period, u.priority) for u in periodic],  # type: ignore[misc]
                    (durations[t] for u in units for t in u.tasks))
    for n, u in enumerate(periodic):
        u.test = REVISED_TEST
        hog = hogs.above(u.priority)
        if hog is not None:
            u.schedulable = False
            _add_note(u, f"the free-running {', '.join(hog.tasks)} (priority {hog.priority}) "
                         "leaves it no time")
            continue
        # A job of any less urgent unit, or of a free-running or irregular one at this
        # priority (not counted as interference), may have just started.
        blocking, blocker = blocking_at(u.priority)
        parts = [durations[t] for t in u.tasks if durations[t] > 0]
        last = min(parts, default=None)
        # The interferers: every other periodic unit at this priority or above.
        result = levels.response(n, blocking=blocking, last=last, budget=budget)
        _judge(u, result, unit)
        if blocker is not None and blocking > 0:
            _add_note(u, f"blocked by up to {display_text(blocking)} {unit} ({blocker})")
        if len(parts) > 1:
            _add_note(u, f"{len(parts)} non-preemptive parts, the last taken as the shortest "
                         f"({display_text(last)} {unit})")
        if ties[u.priority] > 1:
            _add_note(u, f"shares priority {u.priority} with {ties[u.priority] - 1} other "
                         "unit(s), counted as interference")


class _Hogs:
    """The free-running units with work: which one, first in the processor's order,
    lies above a priority."""

    def __init__(self, hogs: list[Unit]) -> None:
        ranked = sorted(range(len(hogs)), key=lambda n: -hogs[n].priority)
        self._priorities = [-hogs[n].priority for n in ranked]  # ascending, for bisect
        self._first: list[Unit | None] = [None]
        first = None
        for n in ranked:  # the earliest of the most urgent `m`, for each prefix `m`
            first = n if first is None else min(first, n)
            self._first.append(hogs[first])

    def above(self, priority: int) -> Unit | None:
        return self._first[bisect_left(self._priorities, -priority)]


def _blocking_by_level(units: Sequence[Unit], durations: Mapping[str, Fraction],
                       counted: set[int]) -> Callable[[int], tuple[Fraction, str | None]]:
    """The longest task (the first of the longest, in the processor's order) of the
    units less urgent than each priority, or at it and not counted as interference."""
    # Each unit's longest task, ranked by duration, then by the unit's place.
    longest = {}
    for n, v in enumerate(units):
        if v.tasks:
            t = max(v.tasks, key=lambda t: durations[t])
            longest[n] = ((durations[t], -n), t)
    below: dict[int, tuple[tuple[Fraction, int], str] | None] = {}
    best = None
    by_priority: dict[int, list[int]] = {}
    for n, v in enumerate(units):
        by_priority.setdefault(v.priority, []).append(n)
    for p in sorted(by_priority):
        below[p] = best
        for n in by_priority[p]:
            if n in longest and (best is None or longest[n][0] > best[0]):
                best = longest[n]

    answers: dict[int, tuple[Fraction, str | None]] = {}

    def at(priority: int) -> tuple[Fraction, str | None]:
        if priority in answers:
            return answers[priority]
        found = below[priority]  # the priority of a unit of the processor
        for n in by_priority.get(priority, ()):
            if n in longest and id(units[n]) not in counted and (
                    found is None or longest[n][0] > found[0]):
                found = longest[n]
        answers[priority] = (Fraction(0), None) if found is None else (found[0][0], found[1])
        return answers[priority]

    return at


def _judge(u: Unit, result: BusyPeriodResponse, unit: str) -> None:
    period = u.period
    assert period is not None  # the caller judges periodic units only
    if result.status == "no time":
        u.schedulable = False
        _add_note(u, "more urgent units leave it no time")
    elif result.status == "unbounded":
        u.schedulable = False
        _add_note(u, "its priority level needs more than the processor: its responses grow "
                     "without bound")
    elif result.status == "exact":
        value = result.value
        assert value is not None
        u.response_time, u.schedulable, u.margin = value, value <= period, period - value
        if result.busy_period:
            _add_note(u, f"worst in instance {(result.worst_instance or 0) + 1} of "
                         f"{result.instances} of its busy period "
                         f"({display_text(result.busy_period)} {unit})")
    else:
        lo, hi = result.lower, result.upper
        assert lo is not None and hi is not None
        u.bounds = (lo, hi)
        why = ("its priority level uses the whole processor and its busy period never ends"
               if result.status == "endless" else
               f"the recurrences stopped by their budget of {result.terms:,} terms")
        span = f"response between {display_text(lo)} and {display_text(hi)} {unit}, {why}"
        if lo > period:
            u.schedulable, text = False, f"{span}: above the period"
        elif hi <= period:
            u.schedulable, text = True, f"{span}: within the period"
        else:
            text = f"undecided ({'budget' if result.status == 'budget' else 'bounds'}): {span}"
        _add_note(u, text)


def _add_note(u: Unit, text: str) -> None:
    u.note = (u.note + "; " if u.note else "") + text
