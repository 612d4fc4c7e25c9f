"""The breadth-first search of reachable markings under budgets: the kernel of
:mod:`tegraph.analysis.reachability`.

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
    pre_t = sp.csr_array(pre, dtype=np.int64).T.tocsr()  # (T, P): input arcs by transition
    inc = (sp.csr_array(post, dtype=np.int64).T - sp.csr_array(pre, dtype=np.int64).T).tocsr()
    inc.sum_duplicates()
    inc.eliminate_zeros()
    n_t, n_p = pre_t.shape
    # Input arcs sorted by transition: enabledness is an AND over each run of arcs.
    pre_t.sum_duplicates()
    arc_t = np.repeat(np.arange(n_t), np.diff(pre_t.indptr))
    arc_p, arc_w = pre_t.indices, pre_t.data
    fed, starts = np.unique(arc_t, return_index=True)
    # The most one firing adds to a place: a marking above INT64_MAX - grow could overflow.
    grow = int(inc.data.max(initial=0))
    m0 = np.asarray(m0, dtype=np.int64)
    if max_states < 1:
        return _Run(0, 0, "states")
    codec = _Codec(n_p, int(m0.max(initial=0)))

    def state_cap() -> tuple[int, str]:
        by_memory = max_memory // (2 * n_p * np.dtype(codec.dtype).itemsize + _STATE_OVERHEAD)
        return (max_states, "states") if max_states <= by_memory else (by_memory, "memory")

    cap, cap_reason = state_cap()
    if cap < 1:
        return _Run(0, 0, cap_reason)
    # Small nets add dense incidence rows (one numpy call); large ones the sparse entries.
    dense_inc = inc.toarray() if n_t * n_p <= _BATCH_ELEMENTS else None
    visited: dict[bytes, int] = {codec.keys(m0[None, :])[0]: 0}
    parent, via = [-1], [-1]
    run = _Run(1, 0, None)
    dead_index: list[int] = []
    level, level_lo = m0[None, :].astype(codec.dtype), 0
    rows_per_batch = max(1, _BATCH_ELEMENTS // max(1, len(arc_t), n_t, n_p))
    pairs = max(1, _BATCH_ELEMENTS // max(1, n_p))
    while len(level) and run.stopped_by is None:
        grown: list[np.ndarray] = []
        for b0 in range(0, len(level), rows_per_batch):
            marks = level[b0:b0 + rows_per_batch].astype(np.int64)
            # only 64-bit markings can overflow (narrower ones are below 2**32)
            if codec.dtype is np.int64 and grow and int(marks.max()) > INT64_MAX - grow:
                run.stopped_by = "tokens"
                break
            enabled = np.ones((len(marks), n_t), dtype=bool)
            if len(arc_t):
                ok = marks[:, arc_p] >= arc_w
                enabled[:, fed] = np.logical_and.reduceat(ok, starts, axis=1)
            for r in np.flatnonzero(~enabled.any(axis=1)).tolist():
                dead_index.append(level_lo + b0 + r)
                run.dead.append((marks[r].copy(), []))
            rows, trans = np.nonzero(enabled)  # row-major: state by state, then transition
            for p0 in range(0, len(rows), pairs):
                r_s, t_s = rows[p0:p0 + pairs], trans[p0:p0 + pairs]
                succ = (marks[r_s] + dense_inc[t_s] if dense_inc is not None
                        else _successors(marks, inc, r_s, t_s))
                level_dtype = codec.dtype
                visited = codec.fit(int(succ.max(initial=0)), visited)
                if codec.dtype is not level_dtype:  # wider markings: fewer fit the memory
                    cap, cap_reason = state_cap()
                new: list[int] = []
                origin = level_lo + b0
                for j, key in enumerate(codec.keys(succ)):
                    n = run.states
                    if visited.setdefault(key, n) == n:
                        if n >= cap:
                            del visited[key]
                            run.stopped_by = cap_reason
                            run.edges += j
                            break
                        run.states = n + 1
                        parent.append(origin + int(r_s[j]))
                        via.append(int(t_s[j]))
                        new.append(j)
                else:
                    run.edges += len(r_s)
                if new:
                    grown.append(succ[new].astype(codec.dtype))
                if run.stopped_by is not None:
                    break
            if run.stopped_by is None:
                if stop is not None and stop():
                    run.stopped_by = "interrupted"
                elif deadline is not None and time.perf_counter() > deadline:
                    run.stopped_by = "time"
            if progress is not None:
                progress(run.states, run.edges, time.perf_counter() - start)
            if run.stopped_by is not None:
                break
        level_lo += len(level)
        level = np.concatenate(grown) if grown else level[:0]
    for k, index in enumerate(dead_index):
        seq = []
        while index > 0:
            seq.append(via[index])
            index = parent[index]
        run.dead[k] = (run.dead[k][0], seq[::-1])
    return run


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
