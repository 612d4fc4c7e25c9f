"""Threads and schedulability under preemptive fixed priorities (ORCCAD §6).

The timed event graph gives each task its period as if every task had its
own processor. On a real processor the tasks share the time; section 6 of the
ORCCAD paper (Simon et al. [1]_) assigns one priority per synchronized
group, rate-monotonic [3]_, and states two conditions:

- a group (or a thread) fits its period when ``τ >= Σ d`` — for a thread
  this falls out of the thread circuit of the timed event graph (one token,
  holding ``Σ d``), whose cycle time is therefore at least ``Σ d``;
- a set of groups fits one processor when ``Σ_i D_i·T/τ_i <= T``, with ``D_i``
  the work of group i on that processor per period ``τ_i`` and ``T`` the
  hyperperiod (least common multiple of the ``τ_i``). This is the processor
  utilization ``Σ D_i/τ_i <= 1``: necessary for any scheduler, sufficient for
  rate-monotonic priorities when the periods divide one another (harmonic).

The exact test is the response-time analysis of Joseph and Pandya [2]_:
the worst response time of a unit released with all more urgent units
(critical instant) is the least fixed point of
``R = C + Σ_{j more urgent} ceil(R/T_j)·C_j``; it meets its implicit deadline
(its period) iff ``R <= T``. Everything is computed in exact Fractions.

A *unit* is what the scheduler sees: the tasks of one group on one processor
with one priority and one rate (one unit per group and processor when Rule 4
is followed). Units of equal priority are counted as interfering with each
other (their order is unknown). Not modelled: release jitter across
processors, blocking on shared resources, context-switch costs.

References
----------
.. [1] D. Simon et al., "Design and analysis of synchronization for
   real-time closed-loop control in robotics", IEEE Transactions on Control
   Systems Technology, 1998.
.. [2] M. Joseph, P. Pandya, "Finding response times in a real-time
   system", The Computer Journal 29(5), 390–395, 1986.
.. [3] C. L. Liu, J. W. Layland, "Scheduling algorithms for
   multiprogramming in a hard-real-time environment", Journal of the ACM
   20(1), 46–61, 1973.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from maxplus.scalar import exact_text

from ..analysis.analyze import analyze_skeleton
from ..analysis.results import Report
from ..model.skeleton import Skeleton
from .rules import is_automaton, proposed_priorities

__all__ = [
    "PAPER_TEST",
    "RTA_TEST",
    "ProcessorVerdict",
    "Schedulability",
    "ThreadVerdict",
    "UnitVerdict",
    "effective_priorities",
    "hyperperiod",
    "response_time",
    "schedulability",
]

RTA_TEST = "response-time analysis (Joseph and Pandya 1986)"
PAPER_TEST = "utilization over the hyperperiod, sum D_i*T/tau_i <= T (ORCCAD section 6)"
_MAX_ITERATIONS = 1_000_000


def hyperperiod(periods: Iterable[Fraction]) -> Fraction:
    """Least common multiple of positive rationals: ``lcm(numerators)/gcd(denominators)``.

    Parameters
    ----------
    periods : iterable of Fraction
        Positive periods (ints and Fractions alike).

    Returns
    -------
    Fraction
        The least positive rational that every period divides an integer
        number of times; 1 for no period.

    See Also
    --------
    schedulability : uses it for the paper's utilization condition.

    Examples
    --------
    >>> hyperperiod([Fraction(1), Fraction(2), Fraction(6)])
    Fraction(6, 1)
    >>> hyperperiod([Fraction(3, 2), Fraction(5, 4)])
    Fraction(15, 2)
    """
    num, den = 1, 0
    for p in periods:
        p = Fraction(p)
        num = math.lcm(num, p.numerator)
        den = math.gcd(den, p.denominator)
    return Fraction(num, den or 1)


def response_time(cost: Fraction, interferers: Iterable[tuple[Fraction, Fraction]]
                  ) -> Fraction | None:
    """Worst-case response time by Joseph and Pandya's recurrence [1]_, exactly.

    Parameters
    ----------
    cost : Fraction
        Execution time ``C`` of the unit per release.
    interferers : iterable of (C_j, T_j)
        Cost and period of every more urgent unit on the processor.

    Returns
    -------
    Fraction or None
        The least fixed point of ``R = C + Σ ceil(R/T_j)·C_j`` (the response
        of the first release at the critical instant, also when it exceeds
        the period); None when the interferers leave no time (``Σ C_j/T_j >= 1``).

    See Also
    --------
    schedulability : the response time of every unit of a skeleton.

    References
    ----------
    .. [1] M. Joseph, P. Pandya, "Finding response times in a real-time
       system", The Computer Journal 29(5), 390–395, 1986.

    Examples
    --------
    Figure 17's low-priority MOD.DYN (C = 1.2) under OBS.JL (0.1 every 1)
    and the control group (0.6 every 2): 1.2 + 2·0.1 + 1·0.6 = 2.

    >>> F = Fraction
    >>> response_time(F(6, 5), [(F(1, 10), F(1)), (F(3, 5), F(2))])
    Fraction(2, 1)
    """
    pairs = [(Fraction(c), Fraction(t)) for c, t in interferers if c]
    cost = Fraction(cost)
    if cost == 0:
        # No work: the release completes at once, whatever the interference
        # (the recurrence below could otherwise wander under a full load).
        return Fraction(0)
    if pairs and sum(c / t for c, t in pairs) >= 1 and cost > 0:
        return None
    r = cost + sum(c for c, _ in pairs)
    for _ in range(_MAX_ITERATIONS):
        nxt = cost + sum(math.ceil(r / t) * c for c, t in pairs)
        if nxt == r:
            return r
        r = nxt
    return None  # pragma: no cover - the recurrence converges when the load is below 1


@dataclass
class UnitVerdict:
    """Response-time verdict of one unit (a group's tasks on one processor)."""

    processor: str | None
    group: int
    tasks: list[str]
    priority: int
    period: Fraction | None
    cost: Fraction
    response_time: Fraction | None
    schedulable: bool | None
    margin: Fraction | None
    """``period - response_time``: how late the unit may still finish."""
    test: str = RTA_TEST
    note: str = ""

    def to_dict(self) -> dict[str, Any]:
        return {"processor": self.processor, "group": self.group, "tasks": self.tasks,
                "priority": self.priority, "period": exact_text(self.period),
                "cost": exact_text(self.cost), "response_time": exact_text(self.response_time),
                "schedulable": self.schedulable, "margin": exact_text(self.margin),
                "test": self.test, "note": self.note}


@dataclass
class ProcessorVerdict:
    """Both tests on one processor."""

    processor: str | None
    priority_source: str
    """``"declared"`` or ``"rate-monotonic"``."""
    hyperperiod: Fraction | None
    demand: Fraction | None
    """``Σ D_i·T/τ_i``: the work of one hyperperiod."""
    condition_holds: bool | None
    condition_margin: Fraction | None
    """``T - demand``."""
    units: list[UnitVerdict] = field(default_factory=list)

    @property
    def schedulable(self) -> bool | None:
        """Every analyzed unit meets its period (None when none could be analyzed)."""
        verdicts = [u.schedulable for u in self.units if u.schedulable is not None]
        return all(verdicts) if verdicts else None

    def to_dict(self) -> dict[str, Any]:
        return {"processor": self.processor, "priority_source": self.priority_source,
                "hyperperiod": exact_text(self.hyperperiod), "demand": exact_text(self.demand),
                "condition": PAPER_TEST, "condition_holds": self.condition_holds,
                "condition_margin": exact_text(self.condition_margin),
                "schedulable": self.schedulable, "units": [u.to_dict() for u in self.units]}


@dataclass
class ThreadVerdict:
    """A thread: its period, its load ``Σ d`` and whether it fits its pace."""

    index: int
    tasks: list[str]
    load: Fraction
    period: Fraction | None
    """Cycle time of the thread's tasks in the timed event graph (>= load)."""
    pace: Fraction | None
    """Period of the fastest clock of its group; None for a free-running thread."""
    fits: bool | None
    margin: Fraction | None

    def to_dict(self) -> dict[str, Any]:
        return {"index": self.index, "tasks": self.tasks, "load": exact_text(self.load),
                "period": exact_text(self.period), "pace": exact_text(self.pace),
                "fits": self.fits, "margin": exact_text(self.margin)}


@dataclass
class Schedulability:
    """Threads, the paper's condition and response times, per processor."""

    processors: list[ProcessorVerdict]
    threads: list[ThreadVerdict]
    priorities: dict[str, int]
    notes: list[str] = field(default_factory=list)

    @property
    def schedulable(self) -> bool | None:
        verdicts = [p.schedulable for p in self.processors if p.schedulable is not None]
        return all(verdicts) if verdicts else None

    def unit_of(self, task: str) -> UnitVerdict | None:
        """The unit that holds ``task``."""
        for p in self.processors:
            for u in p.units:
                if task in u.tasks:
                    return u
        return None

    def to_dict(self) -> dict[str, Any]:
        return {"schedulable": self.schedulable, "priorities": self.priorities,
                "threads": [t.to_dict() for t in self.threads],
                "processors": [p.to_dict() for p in self.processors], "notes": self.notes}


def effective_priorities(skeleton: Skeleton) -> tuple[dict[str, int], dict[str | None, str]]:
    """The priority of every task, and where it comes from on each processor.

    A processor whose tasks all declare a ``priority`` uses them; otherwise
    all its tasks get the rate-monotonic proposal of
    :func:`tegraph.design.rules.proposed_priorities` (and the source says so).

    Parameters
    ----------
    skeleton : Skeleton
        Tasks with their processors and optional declared priorities.

    Returns
    -------
    (dict, dict)
        ``task -> priority`` (larger is more urgent) and ``processor ->
        "declared" or "rate-monotonic"``.

    See Also
    --------
    tegraph.design.rules.proposed_priorities : the rate-monotonic proposal
        (ORCCAD rule 4 [1]_, after Liu and Layland [2]_).

    References
    ----------
    .. [1] D. Simon et al., "Design and analysis of synchronization for
       real-time closed-loop control in robotics", IEEE Transactions on Control
       Systems Technology, 1998.
    .. [2] C. L. Liu, J. W. Layland, "Scheduling algorithms for
       multiprogramming in a hard-real-time environment", Journal of the ACM
       20(1), 46–61, 1973.

    Examples
    --------
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 4},
    ...                                    "B": {"duration": 1, "period": 2}}})
    >>> effective_priorities(sk)
    ({'A': 1, 'B': 2}, {None: 'rate-monotonic'})
    """
    proposal = proposed_priorities(skeleton)
    on: dict[str | None, list[str]] = {}
    for name, task in skeleton.tasks.items():
        on.setdefault(task.processor, []).append(name)
    priorities: dict[str, int] = {}
    source: dict[str | None, str] = {}
    for processor, tasks in on.items():
        declared = all(skeleton.tasks[t].priority is not None for t in tasks)
        source[processor] = "declared" if declared else "rate-monotonic"
        for t in tasks:
            priorities[t] = skeleton.tasks[t].priority if declared else proposal[t]  # type: ignore[assignment]
    return {t: priorities[t] for t in skeleton.tasks}, source


def schedulability(skeleton: Skeleton, report: Report | None = None) -> Schedulability:
    """Threads, the paper's condition and Joseph-Pandya response times.

    Parameters
    ----------
    skeleton : Skeleton
        The tasks with their durations, processors and priorities.
    report : Report, optional
        ``analyze_skeleton(skeleton)``, computed when not given: the periods come
        from its cycle times.

    Returns
    -------
    Schedulability
        Per processor its units (with response times) and the paper's
        utilization condition; per thread its verdict; the priorities used.

    See Also
    --------
    response_time : the recurrence of one unit.
    effective_priorities : where the priorities come from.
    hyperperiod : the ``T`` of the paper's condition.
    tegraph.design.latency.chain_latency : uses the response times.

    Notes
    -----
    The paper's condition is section 6 of the ORCCAD paper [1]_; the exact
    test is Joseph and Pandya's response-time analysis [2]_ under
    rate-monotonic [3]_ or declared priorities.

    References
    ----------
    .. [1] D. Simon et al., "Design and analysis of synchronization for
       real-time closed-loop control in robotics", IEEE Transactions on Control
       Systems Technology, 1998.
    .. [2] M. Joseph, P. Pandya, "Finding response times in a real-time
       system", The Computer Journal 29(5), 390–395, 1986.
    .. [3] C. L. Liu, J. W. Layland, "Scheduling algorithms for
       multiprogramming in a hard-real-time environment", Journal of the ACM
       20(1), 46–61, 1973.

    Examples
    --------
    The computed-torque law of Figure 17 on one processor: the paper's
    condition gives 0.1·6 + 0.6·3 + 1.2·1 = 3.6 <= 6, and MOD.DYN, preempted
    by OBS.JL, finishes at 2.

    >>> from tegraph import load_skeleton
    >>> s = schedulability(load_skeleton("examples/computed_torque.yaml"))
    >>> p = s.processors[0]
    >>> p.demand, p.hyperperiod
    (Fraction(18, 5), Fraction(6, 1))
    >>> [(u.tasks[0], str(u.response_time)) for u in p.units]
    [('OBS.JL', '1/10'), ('TG.JS', '7/10'), ('MOD.DYN', '2')]
    """
    if report is None:
        report = analyze_skeleton(skeleton)
    priorities, source = effective_priorities(skeleton)
    notes: list[str] = []
    units: dict[str | None, list[UnitVerdict]] = {p: [] for p in source}
    for g in report.groups:
        parts: dict[tuple, list[str]] = {}
        for t in g.tasks:
            task = skeleton.tasks[t]
            rate = g.period if g.rate_consistent else report.tasks[t].period
            parts.setdefault((task.processor, priorities[t], rate), []).append(t)
        if g.live and not g.rate_consistent:
            notes.append(f"group {g.index} ({', '.join(g.tasks)}) is not rate-consistent: its "
                         "tasks are analyzed at their own cycle times")
        for (processor, priority, rate), tasks in parts.items():
            cost = sum((skeleton.tasks[t].duration for t in tasks), Fraction(0))
            note = ""
            if not g.live:
                note = "deadlock: the group never runs its period (see the liveness report)"
            elif not g.clocks:
                note = "no clock: its period is its own cycle time (Rule 3)"
            if any(is_automaton(t) for t in tasks):
                note = "the automaton, taken as periodic at the rate of its messages"
            units[processor].append(UnitVerdict(processor, g.index, tasks, priority, rate,
                                                Fraction(cost), None, None, None, note=note))
    processors = [_processor(p, source[p], us, skeleton.unit) for p, us in units.items()]
    return Schedulability(processors, _threads(skeleton, report), priorities, notes)


def _processor(name: str | None, source: str, units: list[UnitVerdict], unit: str
               ) -> ProcessorVerdict:
    active = [u for u in units if u.period]  # dead groups and zero periods are left out
    # Load of each priority level and of everything above it, so that a unit left no
    # time is settled without the recurrence (many groups on one processor stay cheap).
    level: dict[int, Fraction] = {}
    tied: dict[int, int] = {}
    for v in active:
        level[v.priority] = level.get(v.priority, Fraction(0)) + v.cost / v.period  # type: ignore[operator]
        tied[v.priority] = tied.get(v.priority, 0) + 1
    above: dict[int, Fraction] = {}
    running = Fraction(0)
    for prio in sorted(level, reverse=True):
        above[prio] = running
        running += level[prio]
    for u in units:
        if not u.period:
            if not u.note:
                u.note = "no time passes in its period: not analyzed"
            continue
        load = above[u.priority] + level[u.priority] - u.cost / u.period
        if load >= 1 and u.cost > 0:
            u.response_time = None
        else:
            others = [v for v in active if v is not u and v.priority >= u.priority]
            u.response_time = response_time(u.cost, [(v.cost, v.period) for v in others])  # type: ignore[misc]
        if u.response_time is None:
            u.schedulable = False
            u.note = (u.note + "; " if u.note else "") + "more urgent units leave it no time"
        else:
            u.schedulable = u.response_time <= u.period
            u.margin = u.period - u.response_time
        if tied[u.priority] > 1:
            u.note = (u.note + "; " if u.note else "") + (
                f"shares priority {u.priority} with {tied[u.priority] - 1} other unit(s), "
                "counted as interference")
    units.sort(key=lambda u: (-u.priority, u.group))
    if not active:
        return ProcessorVerdict(name, source, None, None, None, None, units)
    T = hyperperiod(u.period for u in active)  # type: ignore[misc]
    demand = sum((u.cost * (T / u.period) for u in active), Fraction(0))  # type: ignore[operator]
    return ProcessorVerdict(name, source, T, demand, demand <= T, T - demand, units)


def _threads(sk: Skeleton, report: Report) -> list[ThreadVerdict]:
    out = []
    for i, thread in enumerate(sk.threads):
        load = sum((sk.tasks[t].duration for t in thread), Fraction(0))
        first = report.tasks[thread[0]]
        clocks = report.groups[first.group].clocks
        pace = min((sk.clocks[c].period for c in clocks), default=None)
        period = first.period
        if period is None:
            fits, margin = None, None
        elif pace is None:  # free-running: the thread sets its own pace
            fits, margin = True, period - load
        else:
            fits, margin = load <= pace, pace - load
        out.append(ThreadVerdict(i, list(thread), Fraction(load), period, pace, fits, margin))
    return out


