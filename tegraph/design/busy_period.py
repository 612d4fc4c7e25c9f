"""Response times over the level-i busy period, with blocking and release jitter, exactly.

One task ``i`` (cost ``C``, period ``T``, release jitter ``J``) shares a processor
under fixed priorities with more urgent tasks ``j`` (``C_j``, ``T_j``, ``J_j``): job
``k`` of a task is *activated* at ``φ + (k-1)T`` and *released* somewhere in
``[φ + (k-1)T, φ + (k-1)T + J]``, for any phase ``φ`` of every task. The worst
response from activation to end, over every phase and every release in its
window, is bounded by examining every instance ``q`` of the level-i busy period
that starts at a critical instant (every task released at once, each at the end of
its jitter window):

- **the busy period**, the least fixed point of
  ``t = B + Σ_{j in hep(i)} ceil((t + J_j)/T_j)·C_j`` (``hep``: task ``i`` and the
  more urgent ones), holds ``Q = ceil((t + J)/T)`` instances of ``i``;
- **instance q** starts (non-preemptive) or ends (preemptive) at the least fixed
  point ``w(q)`` of
  ``w = B + (q+1)·C - F + Σ_{j in hp(i)} N(w + J_j, T_j)·C_j``, and responds
  ``R(q) = J + w(q) + F - q·T``; the bound is ``max_q R(q)``.

On a **non-preemptive** processor (Davis, Burns, Bril and Lukkien 2007 [1]_, eq.
12-16; Bril, Lukkien and Verhaegh 2009 [2]_ for a job of several non-preemptive
parts), ``B`` is the longest part of a less urgent task (one already running when
the busy period starts), ``F`` the job's last part (with one part, ``F = C``:
``w = B + q·C + ...``, Davis et al.'s equation) and ``N(x, T) = floor(x/T) + 1``:
the more urgent jobs released *up to and including* the instant ``w`` at which
``i`` would start, since a job released at the very instant the processor becomes
free takes part in the choice (spec §4d). This is Davis et al.'s
``ceil((w + J + τ_bit)/T)`` for a processor without bit time: the limit
``τ_bit -> 0+`` of the ceiling is ``floor + 1``; the plain ``ceil((w + J)/T)``
(``τ_bit = 0``) would miss a job released exactly at ``w`` and is optimistic.
The original CAN analysis (examining ``q = 0`` alone) is optimistic too [1]_ and is
not offered. On a **preemptive** processor (Tindell's busy period with jitter [3]_,
Joseph and Pandya's recurrence when ``J = 0`` and ``q = 0`` suffices), ``B = 0``,
``F = 0`` and ``N(x, T) = ceil(x/T)``: a job released at the instant ``i`` has
received ``C`` comes after its end.

All times are scaled to integers by their least common denominator: the
ceilings and floors are exact, and so is every bound.

References
----------
.. [1] R. I. Davis, A. Burns, R. J. Bril, J. J. Lukkien, "Controller Area Network
   (CAN) schedulability analysis: refuted, revisited and revised", Real-Time
   Systems 35(3), 239–272, 2007.
.. [2] R. J. Bril, J. J. Lukkien, W. F. J. Verhaegh, "Worst-case response time
   analysis of real-time tasks under fixed-priority scheduling with deferred
   preemption", Real-Time Systems 42(1-3), 63–119, 2009.
.. [3] K. Tindell, "Adding time-offsets to schedulability analysis", technical
   report YCS 221, University of York, 1994; K. Tindell, J. Clark, "Holistic
   schedulability analysis for distributed hard real-time systems",
   Microprocessing and Microprogramming 40, 117–134, 1994.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from fractions import Fraction

from ..errors import InputError

__all__ = ["BUSY_PERIOD_BUDGET", "BusyPeriodResponse", "busy_period_response"]

BUSY_PERIOD_BUDGET = 1_000_000
"""Most terms ``N(x, T_j)·C_j`` one task's analysis evaluates (the busy period and
every instance together; an instance with no more urgent task counts one): past it
the result holds proven bounds only."""

Interferer = Sequence[Fraction | int]
"""``(C_j, T_j)`` or ``(C_j, T_j, J_j)``: cost, period and release jitter of a more
urgent task."""


@dataclass(frozen=True)
class BusyPeriodResponse:
    """What the busy-period analysis proved about one task's worst response.

    Attributes
    ----------
    status : str
        ``"exact"``: ``value`` is ``max_q R(q)`` over the ``instances`` of a busy
        period that ends; ``"no time"``: the more urgent tasks may use the whole
        processor (``Σ_hp C_j/T_j >= 1``), the task may never run; ``"unbounded"``:
        its level uses more than the processor (``Σ_hep C_j/T_j > 1``), its
        responses grow without bound; ``"endless"``: its level uses exactly the
        whole processor and blocking or jitter keep the busy period from ever
        ending, so only ``lower <= R <= upper`` is known; ``"budget"``: the budget
        ran out first, likewise.
    value : Fraction or None
        The bound on the response from activation (status ``"exact"``).
    lower, upper : Fraction or None
        ``lower``: the largest ``R(q)`` computed (a response some phasing
        approaches); ``upper``: a proven bound on every ``R(q)``. Both ``value``
        when exact; None for ``"no time"`` and ``"unbounded"``.
    instances : int
        The instances ``q`` examined.
    worst_instance : int or None
        The ``q`` of the largest ``R(q)``.
    busy_period : Fraction or None
        The length of the level-i busy period, when it ends.
    terms : int
        Terms ``N(x, T_j)·C_j`` evaluated.
    """

    status: str
    value: Fraction | None
    lower: Fraction | None
    upper: Fraction | None
    instances: int
    worst_instance: int | None
    busy_period: Fraction | None
    terms: int


def busy_period_response(cost: Fraction | int, period: Fraction | int,
                         interferers: Iterable[Interferer], *, preemptive: bool,
                         blocking: Fraction | int = 0, jitter: Fraction | int = 0,
                         last: Fraction | int | None = None,
                         budget: int | None = None) -> BusyPeriodResponse:
    """The worst response of a task over every instance of its level-i busy period.

    Parameters
    ----------
    cost, period : Fraction
        ``C >= 0`` and ``T > 0`` of the task.
    interferers : iterable of (C_j, T_j) or (C_j, T_j, J_j)
        Every task at least as urgent on its processor (ties count as more urgent:
        their order is not known).
    preemptive : bool
        The processor's kind (spec §4b, §4d).
    blocking : Fraction
        Non-preemptive only: ``B``, the longest non-preemptive part of a less urgent
        task (0 when there is none).
    jitter : Fraction
        ``J >= 0``: the task's release may come up to ``J`` after its activation.
    last : Fraction, optional
        Non-preemptive only: ``F``, the job's last non-preemptive part,
        ``0 < F <= C`` (default ``C``: the job is one part). A job of several parts
        (a group's tasks run one after another) may be overtaken between them; the
        smallest part is the safe choice when the order is not known.
    budget : int, optional
        Most terms to evaluate (:data:`BUSY_PERIOD_BUDGET` when not given).

    Returns
    -------
    BusyPeriodResponse
        ``value`` bounds ``f - a`` over every job (``a`` its activation, ``f`` its
        end) for every phasing and every release within the jitter: exact, or
        proven bounds, or "no time"/"unbounded".

    Raises
    ------
    InputError
        A negative time, a period that is not positive, ``last`` outside ``(0, C]``
        or given with preemption, blocking with preemption, or a budget that is not
        an integer >= 1.

    See Also
    --------
    tegraph.design.schedulability.response_time_bounds : Joseph and Pandya's
        recurrence, the preemptive first instance without jitter.
    tegraph.design.nonpreemptive : the units of a non-preemptive processor.
    tegraph.design.holistic : jitter inherited along a distributed design.

    Notes
    -----
    **Why the least fixed points.** Let ``W(x) = B + (q+1)C - F + Σ N(x + J_j,
    T_j)·C_j``, the work that must be done (blocking, the earlier instances and
    this one up to its last part, the more urgent jobs released in ``[0, x]`` or
    ``[0, x)``) before ``x`` for instance q to reach its last part at ``x``. ``W``
    is a non-decreasing step function, right-continuous with ``floor + 1`` and
    left-continuous with ``ceil``; in both cases the least ``x`` with ``W(x) <= x``
    exists and is a fixed point, and it is the instant the processor first has
    nothing more urgent to do. Iterating ``W`` from any ``x_0`` below it rises
    strictly to it (``W(x) > x`` below it, and ``W(x) <= W(w) = w``). The
    starts used are ``B + (q+1)C - F + Σ C_j`` (one job of each), ``(B + (q+1)C
    - F + Σ J_j C_j/T_j)/(1 - U)`` (``N(x, T) >= x/T``, ``U = Σ_hp C_j/T_j``) and
    ``w(q-1) + C`` (each instance waits for the one before).

    **Upper bound.** ``N(x, T) < x/T + 1`` gives ``w(q) <= (B + (q+1)C - F +
    S)/(1 - U)`` with ``S = Σ_hp C_j (1 + J_j/T_j)``, so ``R(q) <= J + F + (B + C - F
    + S)/(1 - U) + q (C/(1-U) - T)``; when the level's load ``U + C/T`` is at most
    1 the coefficient of q is at most 0: the value at ``q = 0`` bounds every
    instance. It is what an endless busy period or a spent budget reports.

    References
    ----------
    .. [1] R. I. Davis, A. Burns, R. J. Bril, J. J. Lukkien, "Controller Area
       Network (CAN) schedulability analysis: refuted, revisited and revised",
       Real-Time Systems 35(3), 239–272, 2007.
    .. [2] R. J. Bril, J. J. Lukkien, W. F. J. Verhaegh, "Worst-case response
       time analysis of real-time tasks under fixed-priority scheduling with
       deferred preemption", Real-Time Systems 42(1-3), 63–119, 2009.

    Examples
    --------
    The three CAN frames of Davis et al. (1 ms each, periods 2.5, 3.5 and 3.5 ms,
    most urgent first, one non-preemptive bus): the third frame's first instance
    answers in 3 ms, its second, queued at 3.5 behind the second instances of the
    others, in 3.5 ms; examining the first instance alone (the original analysis)
    would claim 3.

    >>> F = Fraction
    >>> r = busy_period_response(1, F(7, 2), [(1, F(5, 2)), (1, F(7, 2))], preemptive=False)
    >>> r.status, r.value, r.instances, r.worst_instance, r.busy_period
    ('exact', Fraction(7, 2), 2, 1, Fraction(7, 1))
    >>> busy_period_response(1, F(5, 2), [], preemptive=False, blocking=1).value
    Fraction(2, 1)
    """
    budget = _budget(budget)
    c, t, j = (_time(cost, "cost"), _time(period, "period", positive=True),
               _time(jitter, "jitter"))
    b = _time(blocking, "blocking")
    if preemptive and (b or last is not None):
        raise InputError("blocking and a last part are for non-preemptive processors; "
                         "expected neither with preemptive=True",
                         "blocking" if b else "last")
    f = Fraction(0) if preemptive else (c if last is None else _time(last, "last"))
    if not preemptive and c and not 0 < f <= c:
        raise InputError(f"expected 0 < last <= cost = {c}, got {f}", "last")
    hp = []
    for n, x in enumerate(interferers):
        if len(x) not in (2, 3):
            raise InputError(f"expected (cost, period) or (cost, period, jitter), got {x!r}",
                             f"interferers[{n}]")
        cj = _time(x[0], f"interferers[{n}] cost")
        tj = _time(x[1], f"interferers[{n}] period", positive=True)
        jj = _time(x[2], f"interferers[{n}] jitter") if len(x) == 3 else Fraction(0)
        if cj:
            hp.append((cj, tj, jj))
    if c == 0:
        # No work: the job ends at its release (spec §4b, §4d), at most J after its
        # activation, whatever runs.
        return BusyPeriodResponse("exact", j, j, j, 1, 0, Fraction(0), 0)
    load = sum((cj / tj for cj, tj, _ in hp), Fraction(0))
    if load >= 1:
        return BusyPeriodResponse("no time", None, None, None, 0, None, None, 0)
    level = load + c / t
    if level > 1:
        return BusyPeriodResponse("unbounded", None, None, None, 0, None, None, 0)
    spread = sum((cj * (1 + jj / tj) for cj, tj, jj in hp), Fraction(0))
    upper = j + f + (b + c - f + spread) / (1 - load)
    own_drift = b + j * c / t + sum((jj * cj / tj for cj, tj, jj in hp), Fraction(0))
    return _Scaled(c, t, j, b, f, hp, preemptive, budget).run(upper, level == 1 and own_drift > 0)


class _Scaled:
    """The recurrences on integers: every time multiplied by one common denominator."""

    def __init__(self, c: Fraction, t: Fraction, j: Fraction, b: Fraction, f: Fraction,
                 hp: list[tuple[Fraction, Fraction, Fraction]], preemptive: bool,
                 budget: int) -> None:
        self.scale = math.lcm(*(x.denominator for x in (c, t, j, b, f)),
                              *(x.denominator for task in hp for x in task))
        s = self.scale
        self.c, self.t, self.j, self.b, self.f = (int(x * s) for x in (c, t, j, b, f))
        self.hp = [(int(cj * s), int(tj * s), int(jj * s)) for cj, tj, jj in hp]
        self.hep = [*self.hp, (self.c, self.t, self.j)]
        self.preemptive = preemptive
        self.budget = budget
        self.terms = 0
        self.load = Fraction(sum(Fraction(cj, tj) for cj, tj, _ in self.hp))
        self.level_load = self.load + Fraction(self.c, self.t)

    def count(self, x: int, tj: int) -> int:
        """Jobs of a task of period ``tj`` released within a window ending at ``x``."""
        return -(-x // tj) if self.preemptive else x // tj + 1

    def _fixed_point(self, base: int, start: int, tasks: list[tuple[int, int, int]],
                     count) -> int | None:
        """Least fixed point of ``x = base + Σ count(x + J_j, T_j)·C_j`` from a start
        below it; None when the budget runs out first."""
        x = start
        # An iteration over no task still evaluates the instance (one term): the budget
        # bounds the instances a unit with no interferer examines, too.
        cost = max(len(tasks), 1)
        while self.terms + cost <= self.budget:
            self.terms += cost
            nxt = base + sum(count(x + jj, tj) * cj for cj, tj, jj in tasks)
            if nxt == x:
                return x
            x = nxt
        return None

    def run(self, upper: Fraction, endless: bool) -> BusyPeriodResponse:
        s, c, t, j, b, f = self.scale, self.c, self.t, self.j, self.b, self.f
        busy = None
        if not endless:
            # The busy period (its jobs released strictly before its end), from one job
            # of each task of the level, and from the load bound when it is below 1.
            start = b + sum(cj for cj, _, _ in self.hep)
            if self.level_load < 1:
                drift = b + sum(Fraction(jj * cj, tj) for cj, tj, jj in self.hep)
                start = max(start, math.ceil(drift / (1 - self.level_load)))
            busy = self._fixed_point(b, start, self.hep, lambda x, tj: -(-x // tj))
        if busy is not None:
            instances = -(-(busy + j) // t)
        elif endless:
            # Every instance exists; those of one hyperperiod of the level give the
            # lower bound, the closed form the upper one.
            instances = math.lcm(*(tj for _, tj, _ in self.hep)) // t + 1
        else:  # the budget ran out in the busy period
            instances = 0
        worst: int | None = None
        best = j + f + b + c - f + sum(cj for cj, _, _ in self.hp)  # R(0) is at least this
        w_prev = None
        q = 0
        while q < instances:
            base = b + (q + 1) * c - f
            start = base + sum(cj for cj, _, _ in self.hp)
            if self.load < 1:
                drift = base + sum(Fraction(jj * cj, tj) for cj, tj, jj in self.hp)
                start = max(start, math.ceil(drift / (1 - self.load)))
            if w_prev is not None:
                start = max(start, w_prev + c)
            w = self._fixed_point(base, start, self.hp, self.count)
            if w is None:
                break
            r = j + w + f - q * t
            if worst is None or r > best:
                best, worst = r, q
            w_prev = w
            q += 1
        return outcome(best, s, busy, q, instances, worst, endless, upper, self.terms)


def outcome(best: int, scale: int, busy: int | None, examined: int, instances: int,
            worst: int | None, endless: bool, upper: Fraction, terms: int
            ) -> BusyPeriodResponse:
    """The response once the instances are examined (scaled integers): exact when the
    busy period ended and every instance of it was examined, else the proven bounds
    (``best`` below, ``upper`` above)."""
    lower = Fraction(best, scale)
    if busy is not None and examined == instances:
        return BusyPeriodResponse("exact", lower, lower, lower, examined, worst,
                                  Fraction(busy, scale), terms)
    status = "endless" if endless and examined == instances else "budget"
    return BusyPeriodResponse(status, None, lower, max(upper, lower), examined, worst, None,
                              terms)


def _time(value: Fraction | int, what: str, *, positive: bool = False) -> Fraction:
    if isinstance(value, bool) or not isinstance(value, (int, Fraction)):
        raise InputError(f"expected an exact time (int or Fraction), got {value!r}", what)
    x = Fraction(value)
    if x < 0 or (positive and x == 0):
        raise InputError(f"expected a time {'>' if positive else '>='} 0, got {x}", what)
    return x


def _budget(budget: int | None) -> int:
    if budget is None:
        return BUSY_PERIOD_BUDGET
    if isinstance(budget, bool) or not isinstance(budget, int) or budget < 1:
        raise InputError(f"expected an integer >= 1, got {budget!r}", "budget")
    return budget
