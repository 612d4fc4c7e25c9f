"""Exact dater simulation, periodic regime detection and overrun search.

The daters of a timed event graph follow (``docs/skeleton.md`` §3)::

    x_e(k) = max over places p into e of  x_src(p)(k - m_p) + h_p   if k > m_p
                                          a_p                       otherwise

All times are scaled to integers by their common denominator, so every value
here is an exact int64. Events are computed level by level in a topological
order of the 0-token places, each level one numpy operation (a long, thin
chain: one place at a time, in Python), and all groups of a skeleton advance
together.

**Periodic regime, proven.** For a set ``S`` of events closed under
predecessors (no place enters ``S`` from outside) whose events all have the
cycle time λ, the (max,+) recurrence is homogeneous: adding a constant to
every ``x_e(k-m)`` adds it to ``x_e(k)``. Hence if the state
``(x(j-M+1), ..., x(j))`` restricted to ``S`` equals an earlier one shifted by
``c·λ`` (``M`` the largest token count), it does so forever after: the
regime ``x_e(k+c) = x_e(k) + c·λ`` holds for every ``k >= j-M+1-c``. The first
repetition found gives the smallest such ``k`` (the transient) and, with it,
the smallest ``c`` (the cyclicity): a shorter period or an earlier start
would have repeated sooner (see the proof in ``docs/analysis.md``). This is
the (max,+) counterpart of the ORCCAD paper's search for a repeated marking
(§5), and it needs no reachability graph.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal, NamedTuple

import numpy as np

from ..errors import ModelError

__all__ = ["DaterSimulation", "Regime", "OverrunWatch", "certain_overrun", "explore"]

_NONE = np.iinfo(np.int64).min // 4
_BIG_NONE = -(2**256)
_INT64_ROOM = 2**60


def _step_room(tokens: np.ndarray, holding: np.ndarray, initial: np.ndarray) -> int:
    """The most one step of :class:`DaterSimulation` adds to the daters it starts from.

    A dater is an initial availability time, or a dater of the history plus a
    marked place's holding time, then plus the holding times along a path of
    token-free places (each place once: they form no circuit). Python ints, exact.

    >>> _step_room(np.array([1, 0, 0]), np.array([4, 2**62, 3]), np.array([1, 0, 0]))
    4611686018427387912
    """
    marked = tokens > 0
    return (sum(map(abs, holding[~marked].tolist()))
            + max(map(abs, holding[marked].tolist()), default=0)
            + max(map(abs, initial[marked].tolist()), default=0))


class DaterSimulation:
    """Step-by-step exact daters ``x(1), x(2), ...`` of the events in ``active``.

    Parameters
    ----------
    src, dst, tokens : numpy.ndarray of int64
        Places (input event, output event, initial tokens).
    holding, initial : numpy.ndarray of int64
        Holding times and availability times of initial tokens, scaled.
    n_events : int
    active : numpy.ndarray of bool, optional
        Events to simulate (default all); places touching other events are
        ignored, so ``active`` must be closed under predecessors and free of
        token-free circuits.

    Examples
    --------
    A clock of period 4 and phase 1 (self-loop, 1 token, available at 1) and a
    task ``compute`` of duration 3 it activates (return place, 1 token):

    >>> sim = DaterSimulation(np.array([0, 0, 1]), np.array([0, 1, 1]), np.array([1, 0, 1]),
    ...                       np.array([4, 0, 3]), np.array([1, 0, 0]), 2)
    >>> [sim.step().tolist() for _ in range(3)]
    [[1, 1], [5, 5], [9, 9]]
    """

    def __init__(self, src: np.ndarray, dst: np.ndarray, tokens: np.ndarray, holding: np.ndarray,
                 initial: np.ndarray, n_events: int, active: np.ndarray | None = None) -> None:
        if active is None:
            active = np.ones(n_events, dtype=bool)
        # Scaled times are exact int64 until they near 2**60; then (or when
        # the scaled inputs are already huge) the same code runs on Python ints.
        self.dtype: type = object if object in (holding.dtype, initial.dtype) else np.int64
        keep = active[src] & active[dst]
        if self.dtype is not object and _INT64_ROOM + _step_room(
                tokens[keep], holding[keep], initial[keep]) >= 2**62:
            # One step may add a whole token-free path's holding times to daters up to
            # _INT64_ROOM (checked after each step): in int64 that step could wrap.
            self.dtype = object
        self.none = _BIG_NONE if self.dtype is object else _NONE
        # The graph as given, for the exact overrun of a task slower than its clock.
        self.graph = (src, dst, tokens, holding, initial)
        holding, initial = holding.astype(self.dtype), initial.astype(self.dtype)
        self.n_events = n_events
        self.active = active
        self.k = 0
        self.depth = int(tokens[keep].max(initial=0))
        self.history: list[Any] = []  # x(k-depth+1) .. x(k): arrays, or lists (small graphs)
        marked = keep & (tokens > 0)
        order = np.argsort(dst[marked], kind="stable")
        self._m_src = src[marked][order]
        self._m_dst = dst[marked][order]
        self._m_tok = tokens[marked][order]
        self._m_h = holding[marked][order]
        self._m_a = initial[marked][order]
        self._m_starts, self._m_targets = _segments(self._m_dst)
        free = keep & (tokens == 0)
        self._levels, self._sequence = _levels(src[free], dst[free], holding[free], active,
                                               thin=int(keep.sum()) <= _SMALL)
        # Events with no input place at all fire at time 0 (max over nothing
        # taken as the origin of time); a skeleton never has one.
        has_input = np.zeros(n_events, dtype=bool)
        has_input[dst[keep]] = True
        self._sourceless = active & ~has_input
        # A small graph (a group's upstream closure: 500 of them at 10,000 tasks) is
        # stepped in Python lists: numpy's fixed cost a call exceeds the work.
        self._small: tuple | None = None
        if self._sequence is not None and int(keep.sum()) <= _SMALL:
            self._small = (np.flatnonzero(self._sourceless).tolist(),
                           list(zip(self._m_dst.tolist(), self._m_src.tolist(),
                                    self._m_tok.tolist(), self._m_h.tolist(),
                                    self._m_a.tolist())))
            self.history = []  # rows as lists

    def step(self) -> np.ndarray:
        """Compute and return ``x(k)`` for the next ``k`` (inactive events: a huge negative)."""
        self.k += 1
        if self._small is not None:
            return self._small_step()
        k = self.k
        x: np.ndarray = np.full(self.n_events, self.none, dtype=self.dtype)
        x[self._sourceless] = 0
        if len(self._m_src):
            late = k > self._m_tok
            value = self._m_a.copy()
            if late.any():
                # k > m >= 1 for these places, so x(k - m) is in the history.
                idx = np.flatnonzero(late)
                rows = np.stack(self.history[-self.depth:])
                back = self._m_tok[idx]
                # history[-m] is x(k - m); only rows that exist are read.
                value[idx] = rows[len(rows) - back, self._m_src[idx]] + self._m_h[idx]
            x[self._m_targets] = np.maximum.reduceat(value, self._m_starts)
        for events, starts, p_src, p_h in self._levels:
            if len(p_src):
                best = np.maximum.reduceat(x[p_src] + p_h, starts)
                x[events] = np.maximum(x[events], best)
        if self._sequence is not None:
            # A deep, thin DAG (a long chain): one place at a time in Python beats
            # a few numpy calls per level. Same maxima of the same exact integers.
            xs = x.tolist()
            for p_src, p_dst, p_h in zip(*self._sequence):
                v = xs[p_src] + p_h
                if v > xs[p_dst]:
                    xs[p_dst] = v
            x = np.array(xs, dtype=self.dtype)
        self.history.append(x)
        if len(self.history) > max(self.depth, 1):
            self.history.pop(0)
        if self.dtype is not object and int(x.max(initial=0)) > _INT64_ROOM:
            self._to_python_ints()
        return x

    def _small_step(self) -> np.ndarray:
        """:meth:`step` in Python lists: the same maxima of the same exact integers."""
        assert self._small is not None and self._sequence is not None
        k, history = self.k, self.history
        sourceless, marked = self._small
        xs = [self.none] * self.n_events
        for e in sourceless:
            xs[e] = 0
        # The places with tokens, by output event (x(k - m) is history[-m]).
        last = -1
        for d, s, m, h, a in marked:
            v = a if k <= m else history[-m][s] + h
            if d != last:
                xs[d], last = v, d
            elif v > xs[d]:
                xs[d] = v
        for p_src, p_dst, p_h in zip(*self._sequence):
            v = xs[p_src] + p_h
            if v > xs[p_dst]:
                xs[p_dst] = v
        history.append(xs)
        if len(history) > max(self.depth, 1):
            history.pop(0)
        x: np.ndarray = np.array(xs, dtype=self.dtype)
        if self.dtype is not object and max(xs, default=0) > _INT64_ROOM:
            self._to_python_ints()
        return x

    def _to_python_ints(self) -> None:
        def widen(a: np.ndarray) -> np.ndarray:
            out = a.astype(object)
            out[a == _NONE] = _BIG_NONE
            return out

        self.dtype, self.none = object, _BIG_NONE
        if self._small is not None:  # the rows are lists of Python ints already
            self.history = [[_BIG_NONE if v == _NONE else v for v in row]
                            for row in self.history]
            return
        self.history = [widen(row) for row in self.history]
        self._m_h, self._m_a = self._m_h.astype(object), self._m_a.astype(object)
        self._levels = [(e, st, ps, ph.astype(object)) for e, st, ps, ph in self._levels]
        # (the thin DAG's holdings are Python ints already)


def _segments(sorted_keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    if len(sorted_keys) == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    starts = np.flatnonzero(np.concatenate(([True], sorted_keys[1:] != sorted_keys[:-1])))
    return starts, sorted_keys[starts]


_THIN = 32
"""Fewer 0-token places than this per topological level on average: the DAG is
thin (a long chain), levels cost more as numpy calls than places as Python."""


_FEW = 256
"""Up to this many 0-token places, levels are found by :func:`_kahn_levels` at once."""

_SMALL = 128
"""Up to this many places, :class:`DaterSimulation` steps in Python lists."""


def _levels(src: np.ndarray, dst: np.ndarray, holding: np.ndarray, active: np.ndarray,
            thin: bool = False):
    """Group 0-token places by the topological level of their output event.

    Returns ``(levels, None)``, one numpy step per level, or, for a thin DAG (or
    when ``thin`` asks for it), ``([], (src, dst, holding))``: the places as lists
    in level order.
    """
    n = len(active)
    order = np.argsort(src, kind="stable")
    s_sorted, d_by_src = src[order], dst[order]
    # A few hundred places: Python's pass costs less than numpy's fixed cost per
    # level (an upstream closure of regime_bounds: ~20 events, 500 of them at 10k tasks).
    level = _breadth_levels(n, s_sorted, d_by_src, dst, active) if len(dst) > _FEW else None
    if level is None:
        level = _kahn_levels(n, s_sorted, d_by_src, dst, active)
    if (active & (level < 0)).any():
        raise ModelError("the 0-token places of the simulated events contain a circuit; "
                         "simulate live events only", "active")
    depth = int(level.max(initial=-1)) + 1
    out: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]] = []
    place_level = level[dst]
    if thin or len(dst) < _THIN * depth:
        by_level = np.lexsort((dst, place_level))
        return out, (src[by_level].tolist(), dst[by_level].tolist(),
                     holding[by_level].tolist())
    # One sort splits the places by level (a scan per level would cost depth × places).
    by_level = np.lexsort((dst, place_level))
    bounds = np.searchsorted(place_level[by_level], np.arange(1, depth + 2))
    for lev in range(depth):
        by_dst = by_level[bounds[lev]:bounds[lev + 1]]
        if len(by_dst) == 0:
            continue
        starts, events = _segments(dst[by_dst])
        out.append((events, starts, src[by_dst], holding[by_dst]))
    return out, None


def _breadth_levels(n: int, s_sorted: np.ndarray, d_by_src: np.ndarray, dst: np.ndarray,
                    active: np.ndarray) -> np.ndarray | None:
    """Levels by a numpy breadth-first pass, one pass per level; None for a thin DAG.

    A long chain would take a pass per event: when the levels since the last
    checkpoint (at ``2 * _THIN`` levels, then at each doubling of the depth)
    held fewer than ``_THIN`` places each on average, :func:`_kahn_levels`
    takes over. The checkpoints double so that a broad head followed by a long
    thin tail (a clock per task: 10,000 ticks at level 0, then a chain of
    30,000 levels) is caught after at most twice the levels of its head, and
    a broad DAG is never handed to Python.
    """
    indegree = np.bincount(dst, minlength=n)
    level = np.full(n, -1, dtype=np.int64)
    frontier = np.flatnonzero(active & (indegree == 0))
    starts_src = np.searchsorted(s_sorted, np.arange(n))
    ends_src = np.searchsorted(s_sorted, np.arange(n), side="right")
    depth = 0
    seen = 0
    checkpoint, since_depth, since_seen = 2 * _THIN, 0, 0
    remaining = indegree.copy()
    while len(frontier):
        level[frontier] = depth
        lengths = ends_src[frontier] - starts_src[frontier]
        if lengths.sum() == 0:
            break
        seen += int(lengths.sum())
        if depth == checkpoint:
            if seen - since_seen < _THIN * (depth - since_depth):
                return None
            checkpoint, since_depth, since_seen = 2 * depth, depth, seen
        idx = np.repeat(starts_src[frontier], lengths) + _ragged_arange(lengths)
        succ = d_by_src[idx]
        np.subtract.at(remaining, succ, 1)
        frontier = np.unique(succ[remaining[succ] == 0])
        depth += 1
    return level


def _kahn_levels(n: int, s_sorted: np.ndarray, d_by_src: np.ndarray, dst: np.ndarray,
                 active: np.ndarray) -> np.ndarray:
    """The same levels (longest path from a source, in places) by Kahn's algorithm in Python."""
    starts = np.searchsorted(s_sorted, np.arange(n + 1)).tolist()
    succ = d_by_src.tolist()
    remaining = np.bincount(dst, minlength=n).tolist()
    level = [-1] * n
    best = [0] * n  # the level so far; an event's is final once all its inputs are
    stack = np.flatnonzero(active & (np.bincount(dst, minlength=n) == 0)).tolist()
    for e in stack:
        level[e] = 0
    while stack:
        e = stack.pop()
        above = level[e] + 1
        for d in succ[starts[e]:starts[e + 1]]:
            if best[d] < above:
                best[d] = above
            remaining[d] -= 1
            if remaining[d] == 0:
                level[d] = best[d]
                stack.append(d)
    return np.array(level, dtype=np.int64)


def _ragged_arange(lengths: np.ndarray) -> np.ndarray:
    """Concatenation of arange(l) for every l in lengths."""
    total = int(lengths.sum())
    offsets = np.repeat(np.cumsum(lengths) - lengths, lengths)
    return np.arange(total) - offsets


@dataclass
class Regime:
    """A set of events closed under predecessors, all of cycle time ``num/den``.

    After :func:`explore`, ``transient`` and ``cyclicity`` hold the smallest K
    and c with ``x_e(k+c) = x_e(k) + c·λ`` for all its events and all k >= K
    (None when the budget ran out first).
    """

    events: np.ndarray
    num: int
    den: int
    start: int = 1
    """States are compared only from this firing index on (see regime_bounds)."""
    transient: int | None = None
    cyclicity: int | None = None
    _seen: dict = field(default_factory=dict, repr=False)


@dataclass
class OverrunWatch:
    """Watch ``end(k-1) > x_tick(k)`` for one clocked task, ``end(k) = x_last(k) + end_offset``.

    The end of an activation (spec §4, v1.1) is its last write, or, for a
    task without outputs, the end of its computation: ``x_compute(k)`` plus
    the duration, given here scaled as ``end_offset`` (0 with outputs).
    ``regime`` is the index of a proven-periodic :class:`Regime` holding both
    events (then "never" can be proven: the difference ``end(k-1) - x_tick(k)``
    is periodic once the regime holds, a constant ``end_offset`` included), or
    None when only an overrun can end the search (``certain`` says whether an
    overrun is known to come).
    After :func:`explore`: ``overrun_at`` (int or None) and ``decided``.
    """

    last_event: int
    tick_event: int
    regime: int | None
    certain: bool = False
    end_offset: int = 0
    overrun_at: int | None = None
    decided: bool = False
    method: Literal["simulation", "max-plus powers"] = "simulation"
    """How it was decided: ``"simulation"`` (seen, or excluded by a proven regime) or
    ``"max-plus powers"`` (a certain overrun located exactly, see :func:`certain_overrun`)."""


RECORD_LIMIT = 1 << 24
"""Most dater values :func:`explore` records (128 MiB of int64)."""


def explore(sim: DaterSimulation, scale: int, regimes: list[Regime], watches: list[OverrunWatch],
            max_steps: int = 100_000, record: tuple[np.ndarray, list] | None = None) -> int:
    """Advance the daters until every regime is found and every watch decided.

    Parameters
    ----------
    sim : DaterSimulation
    scale : int
        Common denominator of the scaled times.
    regimes : list of Regime
        Filled in place.
    watches : list of OverrunWatch
        Filled in place.
    max_steps : int
        Budget on the firing index k.
    record : (events, rows), optional
        ``x(k)[events]`` is appended to ``rows`` at each step while a regime is still
        to be found (the daters a chain's latency reads, spec §4c; none is needed
        past the step that proves the last regime), and while ``rows`` holds fewer than
        :data:`RECORD_LIMIT` values (past it, a regime's figures are left to whoever
        reads them: its rows stop short of its transient plus its cyclicity).

    Returns
    -------
    int
        The number of steps simulated.
    """
    pending_regimes = set(range(len(regimes)))
    pending_watches = _locate_certain_overruns(sim, watches)
    depth = max(sim.depth, 1)
    window: list[np.ndarray] = []
    previous: np.ndarray | None = None
    while (pending_regimes or pending_watches) and sim.k < max_steps:
        x = sim.step()
        k = sim.k
        if (record is not None and pending_regimes
                and (len(record[1]) + 1) * len(record[0]) <= RECORD_LIMIT):
            record[1].append(x[record[0]])
        window.append(x)
        if len(window) > depth:
            window.pop(0)
        if previous is not None:
            for w in list(pending_watches):
                watch = watches[w]
                if previous[watch.last_event] + watch.end_offset > x[watch.tick_event]:
                    watch.overrun_at, watch.decided = k, True
                    pending_watches.discard(w)
        previous = x
        if k < depth:
            continue
        for r in list(pending_regimes):
            if _repeated(regimes[r], window, k, depth, scale):
                pending_regimes.discard(r)
        for w in list(pending_watches):
            watch = watches[w]
            if watch.regime is not None and watch.regime not in pending_regimes:
                regime = regimes[watch.regime]
                assert regime.transient is not None and regime.cyclicity is not None
                # Every residue of k modulo the cyclicity has been checked from
                # the transient on: the difference is periodic from there.
                if k >= regime.transient + regime.cyclicity:
                    watch.decided = True
                    pending_watches.discard(w)
    return sim.k


def _locate_certain_overruns(sim: DaterSimulation, watches: list[OverrunWatch]) -> set[int]:
    """The watches left to simulate, once every certain overrun is located by powers.

    A task slower than its clock overruns for certain: where, exactly, without
    simulating up to it (its lag may take millions of activations to build).
    """
    pending = set(range(len(watches)))
    context: PowerContext | None = None  # shared by every certain overrun
    for w, watch in enumerate(watches):
        if not watch.certain:
            continue
        if context is None:
            context = PowerContext.of(sim.graph, sim.active)
        found = certain_overrun(sim.graph, sim.active, watch.last_event, watch.tick_event,
                                watch.end_offset, context=context)
        if found is not None:
            watch.overrun_at, watch.decided, watch.method = found, True, "max-plus powers"
            pending.discard(w)
    return pending


def _repeated(regime: Regime, window: list[np.ndarray], k: int, depth: int, scale: int) -> bool:
    """Whether the regime's state at step ``k`` repeats an earlier one (then its
    transient and cyclicity are set); else the state is remembered."""
    if k - depth + 1 < regime.start:
        return False
    # Normalized state: x·den - k·num·scale is invariant exactly when
    # x(k) = x(k') + (k-k')·λ, with λ = num/den in unscaled units.
    state = _normalized_state(window, regime.events, k, regime.num, regime.den, scale)
    earlier = regime._seen.get(state)
    if earlier is None:
        regime._seen[state] = k
        return False
    regime.cyclicity = k - earlier
    regime.transient = earlier - depth + 1
    regime._seen = {}
    return True


def _normalized_state(window: list[np.ndarray], events: np.ndarray, k: int, num: int, den: int,
                      scale: int) -> bytes | tuple:
    """The window of daters shifted back by k·λ: equal keys mean a repeated state.

    ``x·den - index·num·scale`` is the dater minus ``index·λ``, times ``den·scale``
    (λ = num/den in unscaled time units, daters scaled by ``scale``). The key is
    a function of these values alone, whatever type computed them: their int64
    bytes when every one fits in int64, else the tuple of the Python ints. (The
    products ``x·den`` may pass int64 while their differences fit: a key chosen by
    the type of the daters would tell a state from its own repeat across that
    boundary.)

    >>> a = _normalized_state([np.array([2**61])], np.array([0]), 2, 2**61, 1, 1)
    >>> b = _normalized_state([np.array([2**62], dtype=object)], np.array([0]), 3, 2**61, 1, 1)
    >>> a == b
    True
    """
    parts = []
    wide = False
    for offset, row in zip(range(len(window) - 1, -1, -1), window):
        values = row[events]
        shift = (k - offset) * num * scale
        if values.dtype != object:
            top = int(np.abs(values).max(initial=0))
            if top * den + abs(shift) >= 2**62:
                values = values.astype(object)
        wide = wide or values.dtype == object
        parts.append(values * den - shift)
    state = np.concatenate(parts)
    if wide:
        ints = state.tolist()
        if all(_INT64_MIN <= v <= _INT64_MAX for v in ints):
            return np.array(ints, dtype=np.int64).tobytes()
        # Object arrays hold pointers, so they are keyed by value, not by bytes.
        return tuple(ints)
    return state.tobytes()


_INT64_MIN, _INT64_MAX = -(2**63), 2**63 - 1


_POWER_EVENTS = 96
"""Largest upstream closure (events × token depth) located by matrix powers; a larger
one is left to the simulation (a product costs the cube of this size)."""

_MAX_DOUBLINGS = 256
"""The powers stop past 2**256 activations (then the simulation's budget answers)."""


class PowerContext(NamedTuple):
    """What :func:`certain_overrun` reads of the whole graph, made once for all its
    calls (else each call would cost the whole graph: 10,000 clocked tasks, 10,000
    passes over 140,000 places)."""

    into: dict[int, list[int]]
    """Each live event's input places (between live events)."""
    source: list[int]
    """The source event of each place."""
    loop: dict[int, list[int]]
    """Each event's self-loop places."""
    too_large: set[int]
    """Events whose upstream closure is too large for powers (so is that of every
    event downstream of them), learnt along the calls."""

    @classmethod
    def of(cls, graph: tuple, active: np.ndarray) -> PowerContext:
        src, dst = np.asarray(graph[0]), np.asarray(graph[1])
        source, target = src.tolist(), dst.tolist()
        into: dict[int, list[int]] = {}
        for p in np.flatnonzero(active[src] & active[dst]).tolist():
            into.setdefault(target[p], []).append(p)
        loop: dict[int, list[int]] = {}
        for p in np.flatnonzero(src == dst).tolist():
            loop.setdefault(source[p], []).append(p)
        return cls(into, source, loop, set())


def certain_overrun(graph: tuple, active: np.ndarray, last: int, tick: int,
                    end_offset: int = 0, *,
                    context: PowerContext | None = None) -> int | None:
    """The first activation ``k >= 2`` with ``end(k-1) > x_tick(k)``, by (max,+) powers.

    For a clocked task whose last event is slower than its clock (cycle time
    ``χ > P``): the overrun is certain, and this locates it exactly in
    ``O(n³ log k)`` (``n`` the events upstream of ``last``), however late it
    comes. The proof is in ``docs/analysis.md`` ("A certain overrun, located
    exactly"): with ``x'(k) = x(k) - kP`` the recurrence stays (max,+) linear
    (holdings ``h - mP``), the overrun condition reads ``x'_last(k-1) > φ - δ``
    (``φ`` the clock's phase, ``δ`` = ``end_offset``), and the running maximum
    ``z(i) = max_{j<=i} x'_last(j)`` is (max,+) linear and non-decreasing, so
    the first ``i`` with ``z(i) > φ - δ`` is found by doubling then halving
    powers of the one-step matrix.

    Parameters
    ----------
    graph : tuple of numpy.ndarray
        ``(src, dst, tokens, holding, initial)``, times scaled to integers.
    active : numpy.ndarray of bool
        The live events.
    last, tick : int
        The task's last event and its clock's tick.
    end_offset : int
        ``δ``: 0, or the (scaled) duration of a task without outputs.
    context : PowerContext, optional
        ``PowerContext.of(graph, active)``, made once when many tasks are located
        (else each call would cost the whole graph).

    Returns
    -------
    int or None
        ``overrun_at``; None when the closure is too large for powers, or no
        overrun comes within 2**256 activations (the caller simulates instead).

    Examples
    --------
    Duration 11 on a clock of 10 (tick 0, task ``1``, places: clock self-loop,
    tick -> compute, compute's return): activation 1 ends at 11 > tick 2 at 10.

    >>> g = (np.array([0, 0, 1]), np.array([0, 1, 1]), np.array([1, 0, 1]),
    ...      np.array([10, 0, 11]), np.array([0, 0, 0]))
    >>> certain_overrun(g, np.ones(2, dtype=bool), last=1, tick=0, end_offset=11)
    2
    """
    if context is None:
        context = PowerContext.of(graph, active)
    loop = context.loop.get(tick, [])
    if len(loop) != 1 or int(graph[2][loop[0]]) != 1:
        return None
    into = context.into
    # Most calls end here (a closure too large for powers, often known at once):
    # the arrays are read only past it.
    closure = _upstream(last, into, context.source, context.too_large)
    if closure is None:
        return None
    src, dst, tokens, holding, initial = (np.asarray(a) for a in graph)
    period, phase = int(holding[loop[0]]), int(initial[loop[0]])
    places = [p for e in closure for p in into[e]]
    depth = max(1, max(int(tokens[p]) for p in places))
    events = sorted(closure)
    n = len(events) * depth + 1
    if n > _POWER_EVENTS:
        return None
    order = _topological(events, places, src, dst, tokens)
    col = {(e, lag): i for i, (e, lag) in enumerate((e, lag) for lag in range(depth)
                                                      for e in events)}
    threshold = phase - end_offset
    # The first `depth` firings, with the initial tokens' availability times.
    history: list[dict[int, int]] = []
    best = None
    for k in range(1, depth + 1):
        history.append(_firing(order, into, graph, history, k))
        norm = history[-1][last] - k * period
        if norm > threshold:
            return k + 1
        best = norm if best is None else max(best, norm)
    state = np.zeros(n, dtype=object)
    for (e, lag), i in col.items():
        state[i] = history[depth - 1 - lag][e] - (depth - lag) * period
    state[n - 1] = best
    step = _step(order, into, graph, col, last, period)
    index = _last_below(_dense(step, n), state, threshold, n - 1)
    # z(index) <= threshold < z(index + 1): x'_last first exceeds at index + 1, and
    # activation index + 2 finds activation index + 1 unfinished.
    return None if index is None else depth + index + 2


def _upstream(last: int, into: dict[int, list[int]], source: list[int],
              too_large: set[int]) -> set[int] | None:
    """The events ``last`` depends on (itself included); None when they are too many
    for powers or one has no input place (not a skeleton's graph).

    ``too_large`` holds events already known to have too large a closure: one met
    upstream makes this one too large at once (and ``last`` joins them).
    """
    closure, stack = {last}, [last]
    while stack:
        for p in into.get(stack.pop(), []):
            e = source[p]
            if e not in closure:
                if e in too_large:
                    too_large.add(last)
                    return None
                closure.add(e)
                stack.append(e)
        if len(closure) >= _POWER_EVENTS:  # too large for powers: stop searching at once
            too_large.add(last)
            return None
    return None if any(e not in into for e in closure) else closure


def _firing(order: list[int], into: dict[int, list[int]], graph: tuple,
            history: list[dict[int, int]], k: int) -> dict[int, int]:
    """Firing k of the events in ``order`` (topological), from the earlier ones."""
    src, _, tokens, holding, initial = graph
    x: dict[int, int] = {}
    for e in order:
        value = None
        for p in into[e]:
            m = int(tokens[p])
            v = (int(initial[p]) if k <= m
                 else (x[int(src[p])] if m == 0 else history[-m][int(src[p])])
                 + int(holding[p]))
            value = v if value is None or v > value else value
        # Type: every event in order has an input place (certain_overrun checks it
        # first), so value is set.
        x[e] = value  # type: ignore[assignment]
    return x


def _step(order: list[int], into: dict[int, list[int]], graph: tuple,
          col: dict[tuple[int, int], int], last: int, period: int) -> list[dict[int, int]]:
    """One step X(k-1) -> X(k) of the normalized state, as (max,+) rows (column -> weight);
    the last row is the running maximum ``z`` of ``x'_last``."""
    src, _, tokens, holding, _ = graph
    rows: dict[int, dict[int, int]] = {}
    for e in order:
        row: dict[int, int] = {}
        for p in into[e]:
            m, h = int(tokens[p]), int(holding[p]) - int(tokens[p]) * period
            terms = rows[int(src[p])] if m == 0 else {col[int(src[p]), m - 1]: 0}
            for c, v in terms.items():
                if c not in row or v + h > row[c]:
                    row[c] = v + h
        rows[e] = row
    zi = len(col)
    step: list[dict[int, int]] = [dict() for _ in range(zi + 1)]
    for (e, lag), i in col.items():
        step[i] = dict(rows[e]) if lag == 0 else {col[e, lag - 1]: 0}
    step[zi] = dict(rows[last])
    step[zi][zi] = max(step[zi].get(zi, 0), 0)
    return step


def _last_below(matrix: tuple[np.ndarray, np.ndarray], state: np.ndarray, threshold: int,
                zi: int) -> int | None:
    """The largest number of steps after which ``state[zi]`` is still at most
    ``threshold`` (it is non-decreasing), by doubling then halving powers of
    ``matrix``; None when it stays below past 2**_MAX_DOUBLINGS steps."""
    finite = np.ones(len(state), dtype=bool)
    powers = [matrix]
    index = 0
    # Doubling: z(index + 2^t) > threshold for the first time at some t.
    for t in range(_MAX_DOUBLINGS):
        ahead, ahead_f = _apply(powers[t], state, finite)
        if ahead_f[zi] and ahead[zi] > threshold:
            break
        state, finite, index = ahead, ahead_f, index + 2**t
        powers.append(_square(powers[t]))
    else:
        return None
    for s in range(t - 1, -1, -1):  # halving: the largest index with z <= threshold
        ahead, ahead_f = _apply(powers[s], state, finite)
        if not (ahead_f[zi] and ahead[zi] > threshold):
            state, finite, index = ahead, ahead_f, index + 2**s
    return index


def _topological(events, places, src, dst, tokens) -> list[int]:
    """The events in an order where each 0-token place goes forward (Kahn)."""
    free = [p for p in places if int(tokens[p]) == 0]
    waiting = {e: 0 for e in events}
    after: dict[int, list[int]] = {}
    for p in free:
        waiting[int(dst[p])] += 1
        after.setdefault(int(src[p]), []).append(int(dst[p]))
    ready = [e for e in events if waiting[e] == 0]
    out = []
    while ready:
        e = ready.pop()
        out.append(e)
        for d in after.get(e, []):
            waiting[d] -= 1
            if waiting[d] == 0:
                ready.append(d)
    if len(out) != len(events):
        raise ModelError("the 0-token places of the simulated events contain a circuit; "
                         "simulate live events only", "active")
    return out


def _dense(rows: list[dict[int, int]], n: int) -> tuple[np.ndarray, np.ndarray]:
    """(values, finite) of a (max,+) matrix given by sparse rows."""
    values = np.zeros((n, n), dtype=object)
    finite = np.zeros((n, n), dtype=bool)
    for i, row in enumerate(rows):
        for j, v in row.items():
            values[i, j], finite[i, j] = v, True
    return values, finite


def _square(a: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """A ⊗ A in the (max,+) semiring, exact (Python ints; ε where ``finite`` is False)."""
    values, finite = a
    narrow = _narrow(values, finite)
    # The cube of sums is the cost: in int64 when every sum fits (exact), else
    # Python ints (powers past 2**doublings activations grow without bound).
    sums = (narrow[:, :, None] + narrow[None, :, :] if narrow is not None
            else values[:, :, None] + values[None, :, :])
    both = finite[:, :, None] & finite[None, :, :]
    return _max_over(sums, both, axis=1)


def _narrow(values: np.ndarray, finite: np.ndarray) -> np.ndarray | None:
    """``values`` as int64 (0 where not finite) when the sum of any two finite
    entries fits in int64; else None."""
    entries = values[finite].tolist()
    if entries and max(-min(entries), max(entries)) >= 2**62:
        return None
    return np.where(finite, values, 0).astype(np.int64)


def _apply(a: tuple[np.ndarray, np.ndarray], x: np.ndarray, xf: np.ndarray
           ) -> tuple[np.ndarray, np.ndarray]:
    """A ⊗ x in the (max,+) semiring, exact."""
    values, finite = a
    return _max_over(values + x[None, :], finite & xf[None, :], axis=1)


def _max_over(sums: np.ndarray, ok: np.ndarray, axis: int) -> tuple[np.ndarray, np.ndarray]:
    """The maximum over ``axis`` of the entries where ``ok``; (values, any ok)."""
    any_ok = np.asarray(ok.any(axis=axis))  # an array: ok has 2 or 3 axes
    if not ok.any():
        return np.zeros(any_ok.shape, dtype=object), any_ok
    # Below every entry that counts (int64 sums lie within ±2**63, so low does too).
    low = (min(sums[ok].tolist()) if sums.dtype == object else int(sums[ok].min())) - 1
    out = np.where(ok, sums, low).max(axis=axis)
    out = np.where(any_ok, out, 0).astype(object)
    return out, any_ok
