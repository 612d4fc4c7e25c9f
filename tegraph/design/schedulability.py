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
(its period) iff ``R <= T``. Everything is computed exactly. The iteration
starts from a proven lower bound of the fixed point and runs within a stated
budget (:data:`RTA_BUDGET` terms per unit); a unit whose budget runs out gets
proven bounds on its response time and is "undecided (budget)" unless they
settle its test (see :func:`response_time_bounds`).

A *unit* is what the scheduler sees: the tasks of one group on one processor
with one priority and one rate (one unit per group and processor when Rule 4
is followed). Units of equal priority are counted as interfering with each
other (their order is unknown). A unit whose group has no clock is no
periodic load: nothing paces it, so it runs whenever its processor lets it (in
the idle time, at the lowest priority under the rate-monotonic proposal). It is
charged to no other unit's response time and to no sum of the paper's
condition; it gets processor time when the periodic units at its priority and
above leave some (their utilization is below 1) and no free-running unit is
more urgent, and a unit below it gets none. Not modelled: release jitter across
processors, blocking on shared resources, context-switch costs.

The recurrence has no blocking term: it holds under preemption only. On a
processor declared ``preemptive: false`` (spec §4d) a less urgent job already
running delays a more urgent one, which it does not count: there the units are
bounded by the revised analysis of Davis, Burns, Bril and Lukkien
(:mod:`tegraph.design.nonpreemptive`,
:data:`~tegraph.design.nonpreemptive.REVISED_TEST`), over every phase of the clocks.
That is a cross-check of the exact schedule (spec §4d), never the verdict: such a
processor's ``schedulable`` is None, its ``bounds_within_periods`` says what the
bounds show, and each processor's entry names its test.
The priorities are the platform's (:func:`tegraph.model.platform.platform_of`,
``report.platform``): the ones the exact schedule runs.

These tests are a cross-check of the exact schedule on processors (spec §4b,
:func:`~tegraph.analysis.processors.schedule_on_processors`), which decides
the verdict of every command; :mod:`tegraph.design.cross_check` says where
they agree.

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

from maxplus.scalar import display_text, exact_text

from ..analysis.analyze import analyze_skeleton
from ..analysis.results import Report
from ..errors import InputError, TegraphError
from ..model.platform import Platform, hyperperiod, is_automaton, platform_of
from ..model.skeleton import Skeleton
from ..model.structure import Structure, design_period
from .nonpreemptive import REVISED_TEST, judge_non_preemptive

__all__ = [
    "PAPER_TEST",
    "REVISED_TEST",
    "RTA_BUDGET",
    "RTA_TEST",
    "ProcessorVerdict",
    "ResponseTime",
    "Schedulability",
    "ThreadVerdict",
    "UndecidedError",
    "UnitVerdict",
    "effective_priorities",
    "hyperperiod",
    "response_time",
    "response_time_bounds",
    "schedulability",
]

RTA_TEST = "response-time analysis (Joseph and Pandya 1986)"
"""The test of a unit on a preemptive processor, as the report names it."""
PAPER_TEST = "utilization over the hyperperiod, sum D_i*T/tau_i <= T (ORCCAD section 6)"
RTA_BUDGET = 1_000_000
"""Most terms ``ceil(t/T_j)*C_j`` the recurrence evaluates for one unit (about a
second): past it the unit's test is "undecided (budget)", with proven bounds."""


@dataclass(frozen=True)
class ResponseTime:
    """What the recurrence proved about one unit's response time.

    Attributes
    ----------
    status : str
        ``"exact"`` (the least fixed point was reached: ``value``), ``"no time"``
        (the more urgent units use the whole processor: no fixed point, the unit
        never completes) or ``"budget"`` (the budget ran out first: only the
        bounds are known, and the test is undecided unless they settle it).
    value : Fraction or None
        The exact response time (status ``"exact"``).
    lower, upper : Fraction or None
        Proven bounds ``lower <= R <= upper`` (both equal to ``value`` when
        exact; None for ``"no time"``).
    terms : int
        Terms ``ceil(t/T_j)*C_j`` evaluated.
    """

    status: str
    value: Fraction | None
    lower: Fraction | None
    upper: Fraction | None
    terms: int


class UndecidedError(TegraphError):
    """The response-time recurrence ran out of its budget before its fixed point.

    Attributes
    ----------
    result : ResponseTime
        What it proved: bounds on the response time.
    """

    def __init__(self, result: ResponseTime) -> None:
        self.result = result
        super().__init__(f"response time undecided (budget of {result.terms:,} terms): "
                         f"between {exact_text(result.lower)} and {exact_text(result.upper)}")


def response_time_bounds(cost: Fraction, interferers: Iterable[tuple[Fraction, Fraction]],
                         *, budget: int | None = None) -> ResponseTime:
    """Joseph and Pandya's recurrence [1]_, exactly, from a proven lower bound, within a budget.

    Parameters
    ----------
    cost : Fraction
        Execution time ``C >= 0`` of the unit per release.
    interferers : iterable of (C_j, T_j)
        Cost ``C_j >= 0`` and period ``T_j > 0`` of every more urgent unit.
    budget : int, optional
        Most terms ``ceil(t/T_j)*C_j`` to evaluate (one iteration costs one term
        per interferer); :data:`RTA_BUDGET` when not given.

    Returns
    -------
    ResponseTime
        The exact least fixed point of ``W(t) = C + Σ ceil(t/T_j)*C_j``, "no
        time", or proven bounds when the budget ran out.

    Raises
    ------
    InputError
        ``budget`` is not an integer >= 1.

    See Also
    --------
    response_time : the exact value only.

    Notes
    -----
    **Start.** Let ``U = Σ C_j/T_j``. When ``U >= 1`` and ``C > 0`` there is no
    fixed point (``W(t) >= C + U t > t`` for every ``t > 0``): "no time". Else
    let ``t*`` be the least fixed point (it exists: ``W(u) <= u`` at ``u`` below)
    and ``C > 0``. Since ``ceil(x) >= x`` and ``ceil(x) >= 1`` for ``x > 0``,
    ``t* = W(t*) >= C + U t*`` and ``t* = W(t*) >= C + Σ C_j``; so
    ``t* >= L = max(C + Σ C_j, C/(1 - U))``. The same two inequalities hold at
    ``L`` itself: ``W(L) >= C + Σ C_j`` and ``W(L) >= C + U L >= L`` when
    ``L >= C/(1-U)``; so ``L <= W(L)``.

    **Convergence.** ``W`` is non-decreasing. From ``t_0 = L <= W(t_0)`` and
    ``t_0 <= t*``, induction gives ``t_k <= t_{k+1} = W(t_k) <= W(t*) = t*``: the
    iterates rise and never pass ``t*``. Each value is ``C + Σ n_j C_j`` with
    ``n_j <= ceil(t*/T_j)``, finitely many: the iterates stop at a fixed point
    ``<= t*``, which is ``t*`` because ``t*`` is the least. The plain start
    ``C`` (Joseph and Pandya) obeys the same argument: both reach the same
    ``t*``, and from here in no more steps (``W`` is monotone, so the higher
    start stays ahead: ``W^k(C) <= W^k(L) <= t*``): one step for the example
    below, where the plain start needs 10^7.

    **Upper bound.** ``ceil(x) < x + 1`` gives ``W(t) <= C + Σ C_j + U t``, so
    ``W(u) <= u`` at ``u = (C + Σ C_j)/(1 - U) >= L``; for ``t <= u``,
    ``W(t) <= W(u) <= u``, so the iterates from ``L`` never pass ``u``, and
    their limit ``t*`` is ``<= u``.

    **Budget.** After the first step, each step that is not the last rises by
    at least ``min C_j`` (some ``ceil`` grew by one), so the steps are at most
    ``(u - L)/min C_j + 2 <= Σ C_j/((1-U) min C_j) + 2``: few in practice, but
    many interferers against a processor loaded to ``1 - 10^-7`` can need
    millions (the gaps shrink like ``U^k``). The budget bounds the work; when
    it runs out the result holds the proven bounds ``[t_k, u]`` (status
    ``"budget"``), never "no time". The arithmetic runs on integers (every
    time scaled by the least common denominator), exactly.

    References
    ----------
    .. [1] M. Joseph, P. Pandya, "Finding response times in a real-time
       system", The Computer Journal 29(5), 390–395, 1986.

    Examples
    --------
    A unit of 10^7 under one using 9999999 of every 10^7 (``U = 1 - 10^-7``):
    the start ``C/(1-U) = 10^14`` is already the fixed point
    (``10^7 + 10^7·9999999 = 10^14``).

    >>> F = Fraction
    >>> r = response_time_bounds(F(10**7), [(F(9999999), F(10**7))])
    >>> r.status, r.value == 10**14, r.terms
    ('exact', True, 1)
    """
    budget = _budget(budget)
    pairs = [(Fraction(c), Fraction(t)) for c, t in interferers if c]
    cost = Fraction(cost)
    if cost == 0:
        # No work: the release completes at once, whatever the interference
        # (the recurrence could otherwise wander under a full load).
        return ResponseTime("exact", Fraction(0), Fraction(0), Fraction(0), 0)
    load = sum((c / t for c, t in pairs), Fraction(0))
    if load >= 1:
        return ResponseTime("no time", None, None, None, 0)
    burst = cost + sum((c for c, _ in pairs), Fraction(0))
    start = max(burst, cost / (1 - load))
    upper = burst / (1 - load)
    if not pairs:
        return ResponseTime("exact", cost, cost, cost, 0)
    # Integers: scale every time by the least common denominator (exact, and the
    # ceil of a quotient of integers is one floor division).
    scale = math.lcm(cost.denominator, start.denominator,
                     *(c.denominator for c, _ in pairs), *(t.denominator for _, t in pairs))
    c0 = int(cost * scale)
    ints = [(int(c * scale), int(t * scale)) for c, t in pairs]
    r = math.ceil(start * scale)  # start * scale is an integer: the ceil is exact
    terms = 0
    while terms + len(ints) <= budget:
        terms += len(ints)
        nxt = c0 + sum(-(-r // t) * c for c, t in ints)
        if nxt == r:
            value = Fraction(r, scale)
            return ResponseTime("exact", value, value, value, terms)
        r = nxt
    return ResponseTime("budget", None, Fraction(r, scale), upper, terms)


def response_time(cost: Fraction, interferers: Iterable[tuple[Fraction, Fraction]],
                  *, budget: int | None = None) -> Fraction | None:
    """Worst-case response time by Joseph and Pandya's recurrence [1]_, exactly.

    Parameters
    ----------
    cost : Fraction
        Execution time ``C`` of the unit per release.
    interferers : iterable of (C_j, T_j)
        Cost and period of every more urgent unit on the processor.
    budget : int, optional
        Most terms to evaluate (:data:`RTA_BUDGET` when not given).

    Returns
    -------
    Fraction or None
        The least fixed point of ``R = C + Σ ceil(R/T_j)·C_j`` (the response
        of the first release at the critical instant, also when it exceeds
        the period); None when the interferers leave no time (``Σ C_j/T_j >= 1``).

    Raises
    ------
    UndecidedError
        The budget ran out first (its ``result`` holds proven bounds).

    See Also
    --------
    response_time_bounds : the recurrence, its proof and its budget.
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
    result = response_time_bounds(cost, interferers, budget=budget)
    if result.status == "budget":
        raise UndecidedError(result)
    return result.value


def _budget(budget: int | None) -> int:
    if budget is None:
        return RTA_BUDGET
    if isinstance(budget, bool) or not isinstance(budget, int) or budget < 1:
        raise InputError(f"expected an integer >= 1, got {budget!r}", "budget")
    return budget


# Keyword-only: nine fields, several of the same type; a positional call cannot be read.
@dataclass(kw_only=True)
class UnitVerdict:
    """Response-time verdict of one unit (a group's tasks on one processor)."""

    processor: str | None
    group: int
    tasks: list[str]
    priority: int
    period: Fraction | None
    cost: Fraction
    response_time: Fraction | None
    """Exact; None when not analyzed, left no time, or the budget ran out."""
    schedulable: bool | None
    margin: Fraction | None
    """``period - response_time``: how late the unit may still finish."""
    test: str = RTA_TEST
    note: str = ""
    bounds: tuple[Fraction, Fraction] | None = None
    """Proven ``(lower, upper)`` of the response time when the recurrence's budget
    ran out before its fixed point (None otherwise); ``schedulable`` is then
    decided by them (``lower > period``: no; ``upper <= period``: yes) or None."""
    free_running: bool = False
    """Its group has no clock: no period, no periodic load; ``schedulable`` says
    whether it gets processor time at all."""

    @property
    def undecided(self) -> bool:
        """The budget ran out and the bounds do not settle the test."""
        return self.bounds is not None and self.schedulable is None

    def to_dict(self) -> dict[str, Any]:
        """The unit's verdict as the JSON report holds it."""
        bounds = None if self.bounds is None else [exact_text(b) for b in self.bounds]
        return {"processor": self.processor, "group": self.group, "tasks": self.tasks,
                "priority": self.priority, "period": exact_text(self.period),
                "cost": exact_text(self.cost), "response_time": exact_text(self.response_time),
                "response_time_bounds": bounds,
                "schedulable": self.schedulable, "margin": exact_text(self.margin),
                "free_running": self.free_running, "test": self.test, "note": self.note}


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
    preemptive: bool = True
    """False: declared ``preemptive: false`` (§4d); its units are bounded by
    :data:`~tegraph.design.nonpreemptive.REVISED_TEST`, a cross-check."""

    @property
    def test(self) -> str:
        """The response-time test of its units: :data:`RTA_TEST`, or
        :data:`~tegraph.design.nonpreemptive.REVISED_TEST` on a non-preemptive
        processor."""
        return RTA_TEST if self.preemptive else REVISED_TEST

    @property
    def cross_check(self) -> bool:
        """True on a non-preemptive processor: its units' figures are bounds over all
        phases (:data:`~tegraph.design.nonpreemptive.REVISED_TEST`), a cross-check of
        the exact schedule (spec §4d), never the verdict."""
        return not self.preemptive

    @property
    def schedulable(self) -> bool | None:
        """False when a unit misses its period; else None when a unit is undecided
        (budget), none could be analyzed, or the processor is a :attr:`cross_check`;
        else True."""
        return None if self.cross_check else self._units_meet_periods()

    @property
    def bounds_within_periods(self) -> bool | None:
        """On a :attr:`cross_check` processor: whether every unit's bound is within its
        period (True: no job misses, whatever the phases), some bound is above it
        (False: a phasing may approach that response, not a verdict on the declared
        phases) or neither is known (None). None on a preemptive processor."""
        return self._units_meet_periods() if self.cross_check else None

    def _units_meet_periods(self) -> bool | None:
        verdicts = [u.schedulable for u in self.units if u.schedulable is not None]
        if False in verdicts:
            return False
        if any(u.undecided for u in self.units):
            return None
        return all(verdicts) if verdicts else None

    def to_dict(self) -> dict[str, Any]:
        """The processor's verdict as the JSON report holds it."""
        return {"processor": self.processor, "priority_source": self.priority_source,
                "preemptive": self.preemptive, "test": self.test,
                "cross_check": self.cross_check,
                "bounds_within_periods": self.bounds_within_periods,
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
        """The thread's verdict as the JSON report holds it."""
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
    _unit_index: dict[str, UnitVerdict] | None = field(default=None, init=False, repr=False,
                                                       compare=False)

    @property
    def schedulable(self) -> bool | None:
        """False when a preemptive processor fails; else None when a unit is undecided
        (budget), a non-preemptive processor has work (:attr:`cross_checked`: its
        bounds are no verdict) or nothing could be analyzed; else True."""
        verdicts = [p.schedulable for p in self.processors if p.schedulable is not None]
        if False in verdicts:
            return False
        if self.undecided or self.cross_checked:
            return None
        return all(verdicts) if verdicts else None

    @property
    def undecided(self) -> list[UnitVerdict]:
        """The units of preemptive processors whose test the budget left undecided (a
        cross-check's undecided bound decides nothing either)."""
        return [u for p in self.processors if not p.cross_check
                for u in p.units if u.undecided]

    @property
    def cross_checked(self) -> list[ProcessorVerdict]:
        """The non-preemptive processors with work: bounded over all phases by the
        revised analysis, a cross-check, their verdict left to the exact schedule."""
        return [p for p in self.processors if p.cross_check and p.units]

    def unit_of(self, task: str) -> UnitVerdict | None:
        """The unit that holds ``task`` (the units indexed by task at the first call)."""
        if self._unit_index is None:
            self._unit_index = {}
            for p in self.processors:
                for u in p.units:
                    for t in u.tasks:
                        self._unit_index.setdefault(t, u)
        return self._unit_index.get(task)

    def to_dict(self) -> dict[str, Any]:
        """The schedulability section as the JSON report holds it."""
        return {"schedulable": self.schedulable, "priorities": self.priorities,
                "threads": [t.to_dict() for t in self.threads],
                "processors": [p.to_dict() for p in self.processors], "notes": self.notes}


def effective_priorities(skeleton: Skeleton, structure: Structure | None = None, *,
                         platform: Platform | None = None
                         ) -> tuple[dict[str, int], dict[str, str]]:
    """The priority of every task, and where it comes from on each processor.

    The platform's (:func:`tegraph.model.platform.platform_of`), which the exact
    schedule runs: a processor whose tasks all declare a ``priority`` uses them;
    otherwise all its tasks get the rate-monotonic proposal (and the source says so).

    Parameters
    ----------
    skeleton : Skeleton
        Tasks with their processors and optional declared priorities.
    structure : Structure, optional
        ``Structure.of(skeleton)``, if known (the proposal reads its groups).
    platform : Platform, optional
        ``report.platform``, if known: read, not computed again.

    Returns
    -------
    (dict, dict)
        ``task -> priority`` (larger is more urgent) and ``processor ->
        "declared" or "rate-monotonic"``.

    See Also
    --------
    tegraph.model.platform.rate_monotonic : the rate-monotonic proposal
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
    ({'A': 1, 'B': 2}, {'default': 'rate-monotonic'})
    """
    if platform is None:
        platform = platform_of(skeleton, structure)
    return dict(platform.priority), {p.name: p.priority_source for p in platform.processors}


def schedulability(skeleton: Skeleton, report: Report | None = None, *,
                   budget: int | None = None) -> Schedulability:
    """Threads, the paper's condition, Joseph-Pandya response times and, on
    non-preemptive processors, the revised bounds over all phases (a cross-check).

    Parameters
    ----------
    skeleton : Skeleton
        The tasks with their durations, processors and priorities.
    report : Report, optional
        ``analyze_skeleton(skeleton)``, computed when not given: the periods come
        from its cycle times.
    budget : int, optional
        Most terms of the response-time recurrence per unit (:data:`RTA_BUDGET`
        when not given). A unit whose budget runs out gets proven bounds and is
        "undecided (budget)" unless they settle its test; never "no time".

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
    budget = _budget(budget)
    if report is None:
        report = analyze_skeleton(skeleton)
    platform = report.platform if report.platform is not None else platform_of(
        skeleton, report.structure if report.structure is not None else report.groups)
    priorities, source = effective_priorities(skeleton, platform=platform)
    notes: list[str] = []
    units: dict[str, list[UnitVerdict]] = {p: [] for p in source}
    for g in report.groups:
        parts: dict[tuple, list[str]] = {}
        for t in g.tasks:
            task = skeleton.tasks[t]
            rate = g.period if g.rate_consistent else report.tasks[t].period
            parts.setdefault((task.runs_on, priorities[t], rate), []).append(t)
        if g.live and not g.rate_consistent:
            notes.append(f"group {g.index} ({', '.join(g.tasks)}) is not rate-consistent: its "
                         "tasks are analyzed at their own cycle times")
        for (processor, priority, rate), tasks in parts.items():
            cost = sum((skeleton.tasks[t].duration for t in tasks), Fraction(0))
            note = ""
            free = g.live and not g.clocks
            if not g.live:
                note = "deadlock: the group never runs its period (see the liveness report)"
            elif free:
                note = "no clock (Rule 3): free-running, not a periodic load"
            if any(is_automaton(t) for t in tasks) and not free:
                note = "the automaton, taken as periodic at the rate of its messages"
            units[processor].append(UnitVerdict(processor=processor, group=g.index,
                                                tasks=tasks, priority=priority,
                                                period=None if free else rate,
                                                cost=Fraction(cost), response_time=None,
                                                schedulable=None, margin=None, note=note,
                                                free_running=free))
    free_running = {g.index for g in report.groups if not g.clocks}
    durations = {t: task.duration for t, task in skeleton.tasks.items()}
    processors = [_processor(p, source[p], us, skeleton.unit, budget,
                             preemptive=platform.preemptive(p), durations=durations,
                             free_running=free_running)
                  for p, us in units.items()]
    return Schedulability(processors, _threads(skeleton, report), priorities, notes)


def _processor(name: str, source: str, units: list[UnitVerdict], unit: str,
               budget: int | None = None, *, preemptive: bool = True,
               durations: dict[str, Fraction] | None = None,
               free_running: set[int] | None = None) -> ProcessorVerdict:
    # Dead groups, zero periods and free-running units are left out of the periodic load.
    active = [u for u in units if u.period and not u.free_running]
    # Free-running work (no clock, some duration) takes every instant it is the most
    # urgent: a unit below it gets no time at all.
    hogs = [u for u in units if u.free_running and u.cost > 0]
    if not preemptive:  # blocking and every instance of the busy period: Davis et al.
        judge_non_preemptive(units, durations or {}, free_running or set(), unit,
                             budget=budget)
    # Load of each priority level and of everything above it, so that a unit left no
    # time is settled without the recurrence (many groups on one processor stay cheap).
    level: dict[int, Fraction] = {}
    tied: dict[int, int] = {}
    for v in active:
        # Type: `active` units have a period (None and 0 are left out above).
        level[v.priority] = level.get(v.priority, Fraction(0)) + v.cost / v.period  # type: ignore[operator]
        tied[v.priority] = tied.get(v.priority, 0) + 1
    above: dict[int, Fraction] = {}
    running = Fraction(0)
    for prio in sorted(level, reverse=True):
        above[prio] = running
        running += level[prio]
    for u in units:
        if not preemptive:  # judged above, free-running units included
            continue
        above_hog = next((v for v in hogs if v.priority > u.priority), None)
        if u.free_running:
            _free_running(u, above_hog, level)
            continue
        if not u.period:
            if not u.note:
                u.note = "no time passes in its period: not analyzed"
            continue
        if above_hog is not None and u.cost > 0:
            u.schedulable = False
            _add_note(u, f"the free-running {', '.join(above_hog.tasks)} (priority "
                         f"{above_hog.priority}) leaves it no time")
            continue
        tied_hog = next((v for v in hogs if v.priority == u.priority), None)
        if tied_hog is not None:
            _add_note(u, f"shares priority {u.priority} with the free-running "
                         f"{', '.join(tied_hog.tasks)}, whose work the test does not count")
        load = above[u.priority] + level[u.priority] - u.cost / u.period
        if load >= 1 and u.cost > 0:
            result = ResponseTime("no time", None, None, None, 0)
        else:
            others = [v for v in active if v is not u and v.priority >= u.priority]
            # Type: `others` are active units: each has a period.
            result = response_time_bounds(u.cost, [(v.cost, v.period) for v in others],  # type: ignore[misc]
                                          budget=budget)
        _judge(u, result, unit)
        if tied[u.priority] > 1:
            _add_note(u, f"shares priority {u.priority} with {tied[u.priority] - 1} other "
                         "unit(s), counted as interference")
    units.sort(key=lambda u: (-u.priority, u.group))
    if not active:
        return ProcessorVerdict(name, source, None, None, None, None, units, preemptive)
    # Type: `active` units have a period (None and 0 are left out above; both lines).
    T = hyperperiod(u.period for u in active)  # type: ignore[misc]
    demand = sum((u.cost * (T / u.period) for u in active), Fraction(0))  # type: ignore[operator]
    return ProcessorVerdict(name, source, T, demand, demand <= T, T - demand, units, preemptive)


def _free_running(u: UnitVerdict, above_hog: UnitVerdict | None,
                  level: dict[int, Fraction]) -> None:
    """A unit without a clock: whether its processor leaves it any time.

    The periodic units at its priority and above use ``U`` of the processor in the
    long run; it gets the rest, ``1 - U``, when that is positive and no free-running
    unit is more urgent (that one is never idle). Its period is what the schedule
    gives it: the exact schedule's figure, not this test's.
    """
    if u.cost == 0:
        u.schedulable = True
        _add_note(u, "duration 0: it needs no processor time")
        return
    if above_hog is not None:
        u.schedulable = False
        _add_note(u, f"the free-running {', '.join(above_hog.tasks)} (priority "
                     f"{above_hog.priority}) leaves it no time")
        return
    # The periodic load at its priority and above.
    load = sum((x for p, x in level.items() if p >= u.priority), Fraction(0))
    if load >= 1:
        u.schedulable = False
        _add_note(u, f"the periodic units at its priority and above use "
                     f"{display_text(load)} of the processor: none is left for it")
    else:
        u.schedulable = True
        _add_note(u, f"gets the processor time the periodic units leave "
                     f"({display_text(1 - load)} of it in the long run)")


def _add_note(u: UnitVerdict, text: str) -> None:
    u.note = (u.note + "; " if u.note else "") + text


def _judge(u: UnitVerdict, result: ResponseTime, unit: str) -> None:
    """The unit's verdict from its response time: exact, no time left, or only the
    proven bounds when the budget ran out (which may not settle it)."""
    if result.status == "no time":
        u.schedulable = False
        _add_note(u, "more urgent units leave it no time")
    elif result.status == "exact":
        u.response_time = result.value
        # Type: u is an active unit (a period; see the caller) and the recurrence gave
        # its response time (both lines).
        u.schedulable = u.response_time <= u.period  # type: ignore[operator]
        u.margin = u.period - u.response_time  # type: ignore[operator]
    else:
        lo, hi = result.lower, result.upper
        # Type: a recurrence stopped by its budget gives both bounds.
        u.bounds = (lo, hi)  # type: ignore[assignment]
        span = (f"response time between {display_text(lo)} and {display_text(hi)} "
                f"{unit}, the recurrence stopped by its budget of {result.terms:,} terms")
        # Type: u is an active unit: it has a period (here and in the elif).
        if lo > u.period:  # type: ignore[operator]
            u.schedulable = False
            why = f"{span}: above the period"
        elif hi <= u.period:  # type: ignore[operator]
            u.schedulable = True
            why = f"{span}: within the period"
        else:
            why = f"undecided (budget): {span}"
        _add_note(u, why)


def _threads(sk: Skeleton, report: Report) -> list[ThreadVerdict]:
    out = []
    for i, thread in enumerate(sk.threads):
        load = sum((sk.tasks[t].duration for t in thread), Fraction(0))
        first = report.tasks[thread[0]]
        pace = (report.structure.periods[first.group] if report.structure is not None
                else design_period(sk, report.groups[first.group].tasks))
        period = first.period
        if period is None:
            fits, margin = None, None
        elif pace is None:  # free-running: the thread sets its own pace
            fits, margin = True, period - load
        else:
            fits, margin = load <= pace, pace - load
        out.append(ThreadVerdict(i, list(thread), Fraction(load), period, pace, fits, margin))
    return out


