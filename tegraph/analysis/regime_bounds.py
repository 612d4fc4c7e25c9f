"""When faster upstream events stop mattering: a proven start for a periodic regime.

A clocked task ``T`` keeps pace with its clock (period ``P``) while some events
upstream of it run faster (cycle time below ``P``): a writer on a faster clock,
say. Its group is then not rate-consistent, no full state ever repeats, and
the overrun question cannot be settled by a repeated state alone. It can be
settled this way (all bounds exact):

1. Split the upstream closure ``U`` of ``last(T)`` into ``S`` (cycle time
   ``P``) and ``F`` (cycle time below ``P``; ``F`` is closed under predecessors).
2. *Upper bound on F.* With ``μ`` the largest cycle time in ``F`` and ``V``
   the longest-path potentials of the weights ``h - μ·m`` inside ``F`` (finite,
   since no circuit of ``F`` has a ratio above ``μ``), induction on the
   recurrence gives ``x_f(k) <= V_f + k·μ + β`` for every ``k``, with ``β``
   read off the first ``M`` firings.
3. *Lower bound on S.* Let ``y`` be the daters of ``S`` with the places from
   ``F`` removed. ``y <= x`` on ``S`` (fewer constraints), and ``S`` alone is
   rate-consistent, so ``y`` reaches a proven periodic regime; from it,
   ``y_s(k) >= L_s + k·P`` for ``k`` past that regime's start.
4. A place ``f -> s`` (``m`` tokens, holding ``h``) can no longer decide
   ``x_s(k)`` once ``V_f + (k-m)·μ + β + h <= L_s + k·P``: the other places
   into ``s`` already give at least ``y_s(k)``. From the largest such ``k``
   (``K*``) on, ``S`` evolves by its own places only, so a repeated state of
   ``S`` found at indices ``>= K*`` proves its periodic regime (homogeneity).
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from .dynamics import DaterSimulation, Regime, explore

__all__ = ["autonomous_from"]


def autonomous_from(upstream: np.ndarray, cycle_time: list, period: Fraction, src: np.ndarray,
                    dst: np.ndarray, tokens: np.ndarray, holding: np.ndarray, initial: np.ndarray,
                    scale: int, n_events: int, max_steps: int) -> tuple[np.ndarray, int] | None:
    """The events ``S`` of ``upstream`` at the clock's rate and the index ``K*``.

    Parameters
    ----------
    upstream : numpy.ndarray
        A set of events closed under predecessors.
    cycle_time : list of Fraction
        Cycle time of every event (unscaled).
    period : Fraction
        The clock period ``P`` (the largest cycle time in ``upstream``).
    src, dst, tokens, holding, initial, scale, n_events
        The timed event graph as arrays (scaled times).
    max_steps : int
        Budget for the regime of the reduced system ``y``.

    Returns
    -------
    (S, K*) or None
        From firing ``K*`` on, the events ``S`` depend only on each other;
        None when the budget ran out before ``y`` became periodic.

    Notes
    -----
    Every bound is kept as an integer count of ``1/D`` time units, ``D`` the
    scale of the daters times the denominators of ``μ`` and ``P``: the same
    exact values as Fractions, without a gcd per operation (a skeleton of
    10,000 tasks asks for 500 of these proofs, with scales of 40 digits).
    """
    # Everything below works on the closure alone, renumbered 0..len(upstream)-1.
    upstream = np.asarray(upstream)
    local = np.full(n_events, -1, dtype=np.int64)
    local[upstream] = np.arange(len(upstream))
    inside = np.flatnonzero((local[src] >= 0) & (local[dst] >= 0))
    src, dst = local[src[inside]], local[dst[inside]]
    tokens, holding, initial = tokens[inside], holding[inside], initial[inside]
    global_of = upstream
    cycle_time = [cycle_time[e] for e in upstream.tolist()]
    n_events = len(upstream)
    up = np.ones(n_events, dtype=bool)
    slow_mask = np.array([c == period for c in cycle_time], dtype=bool)
    fast_mask = ~slow_mask
    slow = np.flatnonzero(slow_mask)
    crossing = np.flatnonzero(fast_mask[src] & slow_mask[dst])
    if len(crossing) == 0:
        return global_of[slow], 1
    fast = np.flatnonzero(fast_mask).tolist()
    mu = max(cycle_time[e] for e in fast)
    units = _Units(scale, mu, period)
    potential = _potentials(fast, fast_mask, units.mu, src, dst, tokens, holding, units)
    depth = max(int(tokens[up[src] & up[dst]].max(initial=0)), 1)
    beta = _beta(fast, potential, units.mu, src, dst, tokens, holding, initial, units, n_events,
                 up, depth)
    lower = _lower_bounds(slow, slow_mask, period, src, dst, tokens, holding, initial, scale,
                          n_events, {int(dst[p]) for p in crossing.tolist()}, max_steps, units)
    if lower is None:
        return None
    bounds, start = lower
    k_star = start
    gap = units.period - units.mu  # > 0: mu is a cycle time below P
    per_tick = units.per_tick
    h_list, m_list = holding[crossing].tolist(), tokens[crossing].tolist()
    for p, m, h in zip(crossing.tolist(), m_list, h_list):
        f, s = int(src[p]), int(dst[p])
        need = potential[f] - m * units.mu + beta + int(h) * per_tick - bounds[s]
        k_star = max(k_star, -(-need // gap))  # ceil(need / gap), exactly
    return global_of[slow], max(k_star, 1)


class _Units:
    """The unit ``1/D`` of :func:`autonomous_from`'s integer bounds.

    ``D = scale · den(μ) · den(P) / gcd``: a scaled dater ``x`` (in ``1/scale``)
    is ``x · per_tick`` units, and ``μ`` and ``P`` are ``mu`` and ``period`` units.
    """

    def __init__(self, scale: int, mu: Fraction, period: Fraction) -> None:
        self.D = math.lcm(scale, mu.denominator, period.denominator)
        self.per_tick = self.D // scale
        self.mu = mu.numerator * (self.D // mu.denominator)
        self.period = period.numerator * (self.D // period.denominator)


def _potentials(fast: list[int], fast_mask: np.ndarray, mu: int, src, dst, tokens, holding,
                units: _Units) -> dict[int, int]:
    """Longest-path potentials of ``h - μ·m`` inside F (Bellman-Ford from a virtual source),
    in units of ``1/D``."""
    places = np.flatnonzero(fast_mask[src] & fast_mask[dst])
    per_tick = units.per_tick
    arcs = [(a, b, int(h) * per_tick - mu * m) for a, b, h, m in zip(
        src[places].tolist(), dst[places].tolist(), holding[places].tolist(),
        tokens[places].tolist())]
    value = dict.fromkeys(fast, 0)
    for _ in range(len(value) + 1):
        changed = False
        for a, b, w in arcs:
            candidate = value[a] + w
            if candidate > value[b]:
                value[b] = candidate
                changed = True
        if not changed:
            return value
    raise AssertionError("internal error: a circuit of F exceeds its largest cycle time")


def _beta(fast: list[int], potential: dict[int, int], mu: int, src, dst, tokens, holding,
          initial, units: _Units, n_events: int, up, depth: int) -> int:
    """Smallest β with x_f(k) <= V_f + k·μ + β over the first ``depth`` firings (then all
    k), in units of ``1/D``."""
    sim = DaterSimulation(src, dst, tokens, holding, initial, n_events, up)
    per_tick = units.per_tick
    offset = [potential[f] for f in fast]
    beta = None
    for k in range(1, depth + 1):
        x = sim.step()[fast].tolist()
        gap = max(int(v) * per_tick - o for v, o in zip(x, offset)) - k * mu
        beta = gap if beta is None else max(beta, gap)
    return beta if beta is not None else 0


def _lower_bounds(slow, slow_mask, period, src, dst, tokens, holding, initial, scale, n_events,
                  targets: set[int], max_steps: int, units: _Units):
    """``L_s`` with ``y_s(k) >= L_s + k·P`` for k >= the returned start, ``y`` = S without F
    (``L_s`` in units of ``1/D``)."""
    sim = DaterSimulation(src, dst, tokens, holding, initial, n_events, slow_mask)
    regime = Regime(slow, period.numerator, period.denominator)
    rows: list[list[int]] = []
    target_list = sorted(targets)

    original_step = sim.step

    def step() -> np.ndarray:
        x = original_step()
        rows.append(x[target_list].tolist())
        return x

    # Type: the simulator's step, wrapped to record each state it reaches.
    sim.step = step  # type: ignore[method-assign]
    explore(sim, scale, [regime], [], max_steps)
    if regime.transient is None or regime.cyclicity is None:
        return None
    start, cycle = regime.transient, regime.cyclicity
    per_tick, P = units.per_tick, units.period
    bounds = {}
    for i, s in enumerate(target_list):
        bounds[s] = min(int(rows[k - 1][i]) * per_tick - k * P
                        for k in range(start, start + cycle))
    return bounds, start
