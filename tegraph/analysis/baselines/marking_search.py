"""The breadth-first search of reachable markings under budgets: the kernel of
:mod:`tegraph.analysis.baselines.reachability`.

Markings are stored as the bytes of the narrowest unsigned dtype that holds
them (widened when a place outgrows it) in one dictionary, a level of markings
at a time in numpy; parent pointers give every dead marking a shortest firing
sequence. Arc weights come in sparse (places x transitions).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np
import scipy.sparse as sp

__all__ = ["INT64_MAX", "Progress", "breadth_first"]

Progress = Callable[[int, int, float], None]
"""``progress(states, edges, seconds)``, called between batches of markings."""

# Work arrays of a batch stay near this many elements (a few MiB).
_BATCH_ELEMENTS = 1 << 20
_DTYPES = (np.uint8, np.uint16, np.uint32, np.int64)
INT64_MAX = int(np.iinfo(np.int64).max)
"""The most tokens a place holds in a search (markings are int64)."""
# Bytes a stored marking costs besides its places: the bytes object, its slot in
# the dictionary, the parent and transition of its shortest path.
_STATE_OVERHEAD = 150

@dataclass
class _Run:
    states: int
    edges: int
    stopped_by: str | None
    dead: list[tuple[np.ndarray, list[int]]] = field(default_factory=list)


class _Codec:
    """Markings as bytes of the narrowest unsigned dtype that holds them."""

    def __init__(self, n_places: int, top: int) -> None:
        self.n_places = n_places
        self.level = 0
        self.dtype: type[np.integer] = _DTYPES[0]
        self.largest = int(np.iinfo(self.dtype).max)
        self.fit(top, {})

    def fit(self, top: int, visited: dict[bytes, int]) -> dict[bytes, int]:
        """Widen (re-keying ``visited``) until ``top`` tokens fit in a place."""
        if top <= self.largest:
            return visited
        old = self.dtype
        while top > self.largest:
            self.level += 1
            self.dtype = _DTYPES[self.level]
            self.largest = int(np.iinfo(self.dtype).max)
        return {np.frombuffer(k, dtype=old).astype(self.dtype).tobytes(): v
                for k, v in visited.items()}

    def keys(self, rows: np.ndarray) -> list[bytes]:
        if self.n_places == 0:
            return [b""] * len(rows)
        packed = np.ascontiguousarray(rows.astype(self.dtype, copy=False))
        rows_as_bytes = packed.view(np.dtype((np.void, packed.itemsize * self.n_places)))
        # Each unstructured void row gives one bytes object (numpy's stubs allow a tuple,
        # the item of a structured void; older stubs say Any: a cast suits both).
        return cast(list[bytes], rows_as_bytes.ravel().tolist())


def breadth_first(pre: Any, post: Any, m0: np.ndarray, max_states: int, deadline: float | None,
         progress: Progress | None, stop: Callable[[], bool] | None, start: float,
         max_memory: int) -> _Run:
    """Level-by-level breadth-first search; states are numbered in discovery order.

    ``pre`` and ``post`` are sparse (places x transitions): enabledness reads
    the input arcs only, a successor adds the sparse incidence row of its
    transition, so no work array has more than a batch of markings' places.
    """
    net = _Arcs(pre, post)
    m0 = np.asarray(m0, dtype=np.int64)
    if max_states < 1:
        return _Run(0, 0, "states")
    search = _Search(net, m0, max_states, max_memory)
    if search.cap < 1:
        return _Run(0, 0, search.cap_reason)
    return search.run(deadline, progress, stop, start)


class _Arcs:
    """The net as the search reads it: input arcs sorted by transition, incidence rows."""

    def __init__(self, pre: Any, post: Any) -> None:
        pre_t = sp.csr_array(pre, dtype=np.int64).T.tocsr()  # (T, P): input arcs by transition
        inc = (sp.csr_array(post, dtype=np.int64).T
               - sp.csr_array(pre, dtype=np.int64).T).tocsr()
        inc.sum_duplicates()
        inc.eliminate_zeros()
        self.inc = inc
        self.n_t, self.n_p = pre_t.shape
        # Input arcs sorted by transition: enabledness is an AND over each run of arcs.
        pre_t.sum_duplicates()
        self.arc_t = np.repeat(np.arange(self.n_t), np.diff(pre_t.indptr))
        self.arc_p, self.arc_w = pre_t.indices, pre_t.data
        self.fed, self.starts = np.unique(self.arc_t, return_index=True)
        # The most one firing adds to a place: a marking above INT64_MAX - grow could overflow.
        self.grow = int(inc.data.max(initial=0))
        # Small nets add dense incidence rows (one numpy call); large ones the sparse entries.
        self.dense_inc = inc.toarray() if self.n_t * self.n_p <= _BATCH_ELEMENTS else None

    def enabled(self, marks: np.ndarray) -> np.ndarray:
        """(markings x transitions): which transitions each marking enables."""
        enabled = np.ones((len(marks), self.n_t), dtype=bool)
        if len(self.arc_t):
            ok = marks[:, self.arc_p] >= self.arc_w
            enabled[:, self.fed] = np.logical_and.reduceat(ok, self.starts, axis=1)
        return enabled

    def successors(self, marks: np.ndarray, rows: np.ndarray, trans: np.ndarray) -> np.ndarray:
        """``marks[rows]`` after firing ``trans``, pair by pair."""
        if self.dense_inc is not None:
            return marks[rows] + self.dense_inc[trans]
        return _successors(marks, self.inc, rows, trans)


class _Search:
    """One search: the markings seen (numbered), their shortest paths, the level expanded."""

    def __init__(self, net: _Arcs, m0: np.ndarray, max_states: int, max_memory: int) -> None:
        self.net, self.max_states, self.max_memory = net, max_states, max_memory
        self.codec = _Codec(net.n_p, int(m0.max(initial=0)))
        self.cap, self.cap_reason = self._state_cap()
        self.visited: dict[bytes, int] = {self.codec.keys(m0[None, :])[0]: 0}
        self.parent, self.via = [-1], [-1]
        self.result = _Run(1, 0, None)
        self.dead_index: list[int] = []
        self.level, self.level_lo = m0[None, :].astype(self.codec.dtype), 0
        self.rows_per_batch = max(1, _BATCH_ELEMENTS // max(1, len(net.arc_t), net.n_t, net.n_p))
        self.pairs = max(1, _BATCH_ELEMENTS // max(1, net.n_p))

    def _state_cap(self) -> tuple[int, str]:
        """The most states the search may store, and the budget that sets it."""
        by_memory = self.max_memory // (
            2 * self.net.n_p * np.dtype(self.codec.dtype).itemsize + _STATE_OVERHEAD)
        return ((self.max_states, "states") if self.max_states <= by_memory
                else (by_memory, "memory"))

    def run(self, deadline: float | None, progress: Progress | None,
            stop: Callable[[], bool] | None, start: float) -> _Run:
        """Expand level after level, batch by batch, until none is left or a budget ends it."""
        result = self.result
        while len(self.level) and result.stopped_by is None:
            grown: list[np.ndarray] = []
            for b0 in range(0, len(self.level), self.rows_per_batch):
                marks = self.level[b0:b0 + self.rows_per_batch].astype(np.int64)
                if self._may_overflow(marks):
                    result.stopped_by = "tokens"
                    break
                self._expand(marks, self.level_lo + b0, grown)
                if result.stopped_by is None:
                    result.stopped_by = _interruption(stop, deadline)
                if progress is not None:
                    progress(result.states, result.edges, time.perf_counter() - start)
                if result.stopped_by is not None:
                    break
            self.level_lo += len(self.level)
            self.level = np.concatenate(grown) if grown else self.level[:0]
        self._trace_dead()
        return result

    def _may_overflow(self, marks: np.ndarray) -> bool:
        """Whether a firing from ``marks`` could exceed INT64_MAX tokens in a place
        (only 64-bit markings can: narrower ones are below 2**32)."""
        grow = self.net.grow
        return self.codec.dtype is np.int64 and bool(grow) and int(marks.max()) > INT64_MAX - grow

    def _expand(self, marks: np.ndarray, origin: int, grown: list[np.ndarray]) -> None:
        """Note the dead markings of a batch (numbered from ``origin``) and append the new
        markings its firings reach to ``grown``, pairs of (marking, transition) at a time."""
        enabled = self.net.enabled(marks)
        for r in np.flatnonzero(~enabled.any(axis=1)).tolist():
            self.dead_index.append(origin + r)
            self.result.dead.append((marks[r].copy(), []))
        rows, trans = np.nonzero(enabled)  # row-major: state by state, then transition
        for p0 in range(0, len(rows), self.pairs):
            r_s, t_s = rows[p0:p0 + self.pairs], trans[p0:p0 + self.pairs]
            succ = self.net.successors(marks, r_s, t_s)
            self._widen(int(succ.max(initial=0)))
            new = self._number(succ, origin, r_s, t_s)
            if new:
                grown.append(succ[new].astype(self.codec.dtype))
            if self.result.stopped_by is not None:
                break

    def _widen(self, top: int) -> None:
        """Widen the stored markings to hold ``top`` tokens; wider ones, fewer fit the memory."""
        level_dtype = self.codec.dtype
        self.visited = self.codec.fit(top, self.visited)
        if self.codec.dtype is not level_dtype:
            self.cap, self.cap_reason = self._state_cap()

    def _number(self, succ: np.ndarray, origin: int, rows: np.ndarray,
                trans: np.ndarray) -> list[int]:
        """Number the successors not seen before, with their parent and transition; the
        indices in ``succ`` of the new ones. Counts the edges; stops at the state cap."""
        run, visited = self.result, self.visited
        new: list[int] = []
        for j, key in enumerate(self.codec.keys(succ)):
            n = run.states
            if visited.setdefault(key, n) == n:
                if n >= self.cap:
                    del visited[key]
                    run.stopped_by = self.cap_reason
                    run.edges += j
                    return new
                run.states = n + 1
                self.parent.append(origin + int(rows[j]))
                self.via.append(int(trans[j]))
                new.append(j)
        run.edges += len(rows)
        return new

    def _trace_dead(self) -> None:
        """Give each dead marking its shortest firing sequence, by the parent pointers."""
        for k, index in enumerate(self.dead_index):
            seq = []
            while index > 0:
                seq.append(self.via[index])
                index = self.parent[index]
            self.result.dead[k] = (self.result.dead[k][0], seq[::-1])


def _interruption(stop: Callable[[], bool] | None, deadline: float | None) -> str | None:
    """Why the search must end now: ``"interrupted"``, ``"time"``, or None to go on."""
    if stop is not None and stop():
        return "interrupted"
    if deadline is not None and time.perf_counter() > deadline:
        return "time"
    return None


def _successors(marks: np.ndarray, inc: sp.csr_array, rows: np.ndarray,
                trans: np.ndarray) -> np.ndarray:
    """``marks[rows] + inc[trans]``, adding only the nonzero entries of each incidence row."""
    succ = marks[rows]
    lo, hi = inc.indptr[trans], inc.indptr[trans + 1]
    counts = hi - lo
    total = int(counts.sum())
    if total:
        first = np.cumsum(counts) - counts
        pos = np.arange(total) - np.repeat(first - lo, counts)  # the arcs of each row, in turn
        # a canonical CSR row names each place once, so no (row, place) pair repeats
        succ[np.repeat(np.arange(len(trans)), counts), inc.indices[pos]] += inc.data[pos]
    return succ
