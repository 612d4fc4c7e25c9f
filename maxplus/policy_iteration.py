"""Howard's multichain policy iteration for cycle ratios, in exact integers.

The kernel behind :func:`maxplus.cycle_ratio.max_cycle_ratio`. Arrays in,
arrays out; nothing here validates input (that is done once, at the edge).

A *policy* keeps one in-arc per node; following policy arcs backwards from
any node ends on a policy circuit. *Value determination* gives every node the
ratio ``W/T`` of the circuit it reaches (reduced fraction) and a potential
``X`` (the bias multiplied by ``T``) that is tight along policy arcs.
*Policy improvement* switches a node to an in-arc from a node of strictly
larger ratio, or, failing that, to an in-arc of the same ratio with a strictly
larger potential. A larger ratio is passed on at once to every node
downstream (each switch a strict gain over the node's current ratio, so no new
policy circuit can form and the step is a valid improvement): without that,
a long chain below a slow circuit would take one iteration per node. When
nothing improves, the potentials satisfy the optimality inequalities
everywhere: that is the certificate.

Reference: J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
algebra", IFAC Conference on System Structure and Control, 1998; A. Dasdan,
"Experimental analysis of the fastest optimum cycle ratio and mean
algorithms", ACM TODAES 9(4), 2004 (cycle-ratio form).

Every quantity is an integer (int64 when the caller has proven that no value
can exceed 2**62, Python ints in object arrays otherwise), so no comparison
needs a tolerance. Ratios are compared through their *rank* among the
distinct ratios of the current policy, computed once per iteration.
"""

from __future__ import annotations

import importlib.util
import os
from dataclasses import dataclass, replace
from functools import cmp_to_key
from typing import Any, NamedTuple

import numpy as np

from ._arrays import INT64_SAFE, abs_max, compare_ratios, float_ratios, gcd_arrays
from .errors import MaxPlusValueError

__all__ = ["howard_arrays"]


class HowardSolution(NamedTuple):
    """Optimal policy found by :func:`howard_arrays`."""

    ratio_num: np.ndarray
    ratio_den: np.ndarray
    potential: np.ndarray
    policy: np.ndarray
    iterations: int
    engine: str


ENGINE_VARIABLE = "MAXPLUS_ENGINE"
"""Environment variable that picks the kernel: ``auto`` (default), ``numpy`` or ``numba``."""

JIT_MIN_ARCS: int | None = None
"""``auto`` uses numba from this many arcs on (None: never). Measured
(``benchmarks/results/peers.md``): its import and the loading of its cached
machine code cost 0.6 - 0.9 s per process, and on SPRAND 10^6 it was no faster
than the numpy kernel (17.9 s against 16.7 s, memory latency bounds both), so
it has not earned a place in ``auto``; ``engine="numba"`` still selects it."""


def howard_arrays(src: np.ndarray, dst: np.ndarray, w: np.ndarray, t: np.ndarray,
                  n: int, engine: str | None = None) -> HowardSolution:
    """Optimal policy of a graph in which every node has at least one in-arc.

    Parameters
    ----------
    src, dst : numpy.ndarray of int64
        Arcs; every node in ``range(n)`` must be the ``dst`` of some arc.
    w, t : numpy.ndarray
        Integer weights and token counts (int64, or object for Python ints of
        any size), with no circuit of zero tokens.
    n : int
        Number of nodes.
    engine : {"auto", "numpy", "numba"}, optional
        Kernel: numba's compiled loops when installed (int64 arithmetic only),
        else numpy; default from the environment variable ``MAXPLUS_ENGINE``,
        else ``"auto"`` (numba from ``JIT_MIN_ARCS`` arcs on when it can be imported).

    Returns
    -------
    HowardSolution
        Per node: the cycle time ``ratio_num/ratio_den`` (lowest terms), the
        potential (bias times ``ratio_den``) and the index of its policy arc;
        the number of value determinations and the kernel used.

    Examples
    --------
    Circuit 0 -> 1 -> 0 of ratio (5+3)/2 and a self-loop of ratio 3 on node 1:

    >>> sol = howard_arrays(np.array([0, 1, 1]), np.array([1, 0, 1]),
    ...     np.array([5, 3, 3]), np.array([1, 1, 1]), 2, engine="numpy")
    >>> (sol.ratio_num // sol.ratio_den).tolist(), sol.policy.tolist()
    ([4, 4], [1, 0])
    """
    engine = engine or os.environ.get(ENGINE_VARIABLE, "auto")
    if engine not in ("auto", "numpy", "numba"):
        raise MaxPlusValueError(f"expected 'auto', 'numpy' or 'numba', got {engine!r}", "engine")
    if engine == "numba" and not _jit_available():
        raise MaxPlusValueError("the numba kernel needs the optional package numba", "engine")
    arcs = _InArcs.build(src, dst, w, t, n)
    limits = _int64_limits(w, t, n)
    if limits is not None:
        if engine == "numba" or (engine == "auto" and JIT_MIN_ARCS is not None
                                 and len(src) >= JIT_MIN_ARCS and _jit_available()):
            from .policy_iteration_jit import howard_jit

            pol = arcs.initial_policy()
            s64 = arcs.as_int64()
            W, T, X, iterations, ok = howard_jit(s64.s_src, s64.s_dst, s64.s_w, s64.s_t,
                                                 s64.starts, s64.out_order, pol, n, limits)
            if ok:
                return HowardSolution(W, T, X, arcs.order[pol], iterations, "numba")
        else:
            try:
                return _howard(arcs.as_int64(), limits)
            except _LeavesInt64:
                pass
    return _howard(arcs.as_object(), None)


def _jit_available() -> bool:
    return importlib.util.find_spec("numba") is not None


class _LeavesInt64(Exception):
    """A potential grew past what int64 arithmetic can carry exactly."""


def _objects(a: np.ndarray) -> np.ndarray:
    out = np.empty(len(a), dtype=object)
    out[:] = a.tolist()
    return out


def _int64_limits(w: np.ndarray, t: np.ndarray, n: int) -> int | None:
    """Slack that int64 arithmetic leaves for potentials, or None when int64 cannot be used.

    A policy path or circuit has at most ``n`` distinct arcs, so its weight
    sum is at most ``S_w = min(Σ|w|, n·max|w|)`` in absolute value and its token
    sum at most ``S_t``; ratios ``W/T`` and path sums then stay within those,
    products ``W·t``, ``w·T`` and a fresh potential ``w_path·T - W·t_path``
    within ``2·S_w·S_t``. The potential a circuit keeps from earlier iterations
    is checked at run time against the returned slack.
    """
    if w.dtype == object or t.dtype == object:
        return None
    w_max, t_max = abs_max(w), abs_max(t)
    if w_max * len(w) < INT64_SAFE:
        w_sum = int(np.abs(w).sum())
    else:
        w_sum = w_max * len(w)  # an upper bound is enough here
    t_sum = int(t.sum()) if t_max * len(t) < INT64_SAFE else t_max * len(t)
    s_w, s_t = min(w_sum, n * w_max), min(t_sum, n * t_max)
    fixed = 2 * s_w * s_t + w_max * s_t + s_w * t_max
    slack = INT64_SAFE - 2 * fixed
    return slack if slack > 0 else None


@dataclass(frozen=True)
class _InArcs:
    """Arcs sorted by head (CSR of in-arcs) and the order by tail, built once."""

    order: np.ndarray  # sorted position -> caller's arc index
    s_src: np.ndarray
    s_dst: np.ndarray
    s_w: np.ndarray
    s_t: np.ndarray
    starts: np.ndarray  # n + 1 offsets
    seg: np.ndarray  # head of each sorted arc (== s_dst)
    out_order: np.ndarray  # sorted arcs by tail, for downstream sweeps
    out_starts: np.ndarray
    out_counts: np.ndarray
    n: int

    @classmethod
    def build(cls, src, dst, w, t, n) -> _InArcs:
        order = np.argsort(dst, kind="stable")
        s_src, s_dst = src[order], dst[order]
        counts = np.bincount(dst, minlength=n)
        starts = np.zeros(n + 1, dtype=np.int64)
        np.cumsum(counts, out=starts[1:])
        out_order = np.argsort(s_src, kind="stable")
        out_counts = np.bincount(s_src, minlength=n)
        out_starts = np.r_[0, np.cumsum(out_counts)[:-1]]
        return cls(order, s_src, s_dst, w[order], t[order], starts, s_dst, out_order, out_starts,
                   out_counts, n)

    def as_int64(self) -> _InArcs:
        return replace(self, s_w=self.s_w.astype(np.int64), s_t=self.s_t.astype(np.int64))

    def as_object(self) -> _InArcs:
        return replace(self, s_w=_objects(self.s_w), s_t=_objects(self.s_t))

    def initial_policy(self) -> np.ndarray:
        """The heaviest in-arc of each node, a good first guess.

        (The in-arc of largest ``w/t`` was measured too and took more
        iterations: 40 against 32 on SPRAND 10^5, 49 against 33 on the torus.)
        """
        return self.starts[:-1] + _segment_argmax(self.s_w, self.starts[:-1], self.seg)


def _howard(arcs: _InArcs, limits: int | None) -> HowardSolution:
    s_src, s_dst, s_w, s_t, n = arcs.s_src, arcs.s_dst, arcs.s_w, arcs.s_t, arcs.n
    out_order, out_starts, out_counts = arcs.out_order, arcs.out_starts, arcs.out_counts
    pol = arcs.initial_policy()
    iterations = 0
    W = np.zeros(n, dtype=s_w.dtype)
    T = np.zeros(n, dtype=s_w.dtype)
    X = np.zeros(n, dtype=s_w.dtype)
    first = True
    check_all = True
    while True:
        W_new, T_new, X_new, rank = _value_determination(pol, s_src, s_w, s_t, n, W, T, X, first)
        iterations += 1
        if limits is not None and abs_max(X_new) >= limits:
            raise _LeavesInt64
        if check_all:
            cand = np.arange(len(s_src))
        else:
            # An arc between two nodes whose ratio and potential did not change
            # was not improving at the last full check and still is not.
            changed = (W_new != W) | (T_new != T) | (X_new != X)
            cand = np.flatnonzero(changed[s_src] | changed[s_dst])
        W, T, X, first = W_new, T_new, X_new, False
        cs, cd = s_src[cand], s_dst[cand]
        rank_src, rank_dst = rank[cs], rank[cd]
        # 1. Ratio improvement: a predecessor whose ratio is strictly larger.
        better = rank_src > rank_dst
        if better.any():
            chosen, nodes = _best_per_node(cand[better], rank_src[better], s_dst)
            pol[nodes] = chosen
            rank[nodes] = rank[s_src[chosen]]
            _sweep_downstream(pol, rank, nodes, s_src, s_dst, out_order, out_starts, out_counts)
            # Gains were not examined this round: the next round looks at all arcs.
            check_all = True
            continue
        # 2. Bias improvement among predecessors of the same ratio (then the
        #    potentials share the denominator T, so integers compare directly).
        value = X[cs] + s_w[cand] * T[cd] - W[cd] * s_t[cand]
        gain = (rank_src == rank_dst) & (value > X[cd])
        if not gain.any():
            return HowardSolution(W, T, X, arcs.order[pol], iterations, "numpy")
        chosen, nodes = _best_per_node(cand[gain], value[gain], s_dst)
        pol[nodes] = chosen
        check_all = False


def _sweep_downstream(pol: np.ndarray, rank: np.ndarray, frontier: np.ndarray,
                      s_src: np.ndarray, s_dst: np.ndarray, out_order: np.ndarray,
                      out_starts: np.ndarray, out_counts: np.ndarray) -> None:
    """Pass larger ratio ranks downstream from ``frontier``, switching policies (in place).

    A node switches only to an in-arc whose tail ranks strictly higher, and
    takes that rank, which is then the ratio of the circuit it reaches under
    the new policy. The largest rank goes first, breadth first: a node raised
    once already holds the largest rank that can reach it from the frontier,
    so no node switches twice and the sweep touches each arc about once.
    """
    done = np.zeros(len(rank), dtype=bool)
    pending = np.unique(frontier)
    pending = pending[np.argsort(-rank[pending], kind="stable")]
    cuts = np.flatnonzero(np.diff(rank[pending])) + 1
    for level in np.split(pending, cuts):
        level = level[~done[level]]
        if len(level) == 0:
            continue
        top = rank[level[0]]
        done[level] = True
        while len(level):
            if len(level) <= 16:
                # A deep chain advances a node or two per round: numpy's
                # per-call overhead would dominate, so walk it in Python.
                level = _sweep_few(level, top, pol, rank, done, s_dst, out_order, out_starts,
                                   out_counts)
                continue
            lengths = out_counts[level]
            total = int(lengths.sum())
            if total == 0:
                break
            offsets = np.repeat(out_starts[level] - (np.cumsum(lengths) - lengths), lengths)
            arcs = np.sort(out_order[offsets + np.arange(total)])
            arcs = arcs[rank[s_dst[arcs]] < top]  # every tail here holds rank `top`
            if len(arcs) == 0:
                break
            chosen, level = _best_per_node(arcs, rank[s_src[arcs]], s_dst)
            pol[level] = chosen
            rank[level] = top
            done[level] = True


def _sweep_few(level: np.ndarray, top: Any, pol: np.ndarray, rank: np.ndarray,
               done: np.ndarray, s_dst: np.ndarray, out_order: np.ndarray,
               out_starts: np.ndarray, out_counts: np.ndarray) -> np.ndarray:
    """One round of :func:`_sweep_downstream` from a few nodes (same choices: lowest arc)."""
    best: dict[int, int] = {}
    for u in level.tolist():
        start = int(out_starts[u])
        for k in out_order[start:start + int(out_counts[u])].tolist():
            v = int(s_dst[k])
            if rank[v] < top and (v not in best or k < best[v]):
                best[v] = k
    nodes = np.array(sorted(best), dtype=np.int64)
    if len(nodes):
        pol[nodes] = [best[v] for v in nodes.tolist()]
        rank[nodes] = top
        done[nodes] = True
    return nodes


def _best_per_node(arcs: np.ndarray, key: np.ndarray, s_dst: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray]:
    """For each destination among ``arcs`` (sorted by destination), its arc of largest key."""
    d = s_dst[arcs]
    new_node = np.concatenate(([True], d[1:] != d[:-1]))
    starts = np.flatnonzero(new_node)
    segment = np.cumsum(new_node) - 1
    top = np.maximum.reduceat(key, starts)
    hit = np.flatnonzero(key == top[segment])
    first = np.concatenate(([True], segment[hit[1:]] != segment[hit[:-1]]))
    return arcs[hit[first]], d[starts]


def _lowest(values: np.ndarray) -> Any:
    if values.dtype == object:
        return min(values.tolist()) - 1 if len(values) else 0
    return np.iinfo(np.int64).min


def _segment_argmax(values: np.ndarray, starts: np.ndarray, seg: np.ndarray) -> np.ndarray:
    """Offset, within its segment, of the first maximum of each (non-empty) segment."""
    seg_max = np.maximum.reduceat(values, starts)  # object arrays too (Python ints)
    hit = np.flatnonzero(values == seg_max[seg])
    first = np.concatenate(([True], seg[hit[1:]] != seg[hit[:-1]]))
    return hit[first] - starts[seg[hit[first]]]


def _value_determination(pol: np.ndarray, s_src: np.ndarray, s_w: np.ndarray, s_t: np.ndarray,
                         n: int, W_old: np.ndarray, T_old: np.ndarray, X_old: np.ndarray,
                         first: bool):
    """Ratio, potential and ratio rank of every node under a policy."""
    index = np.int32 if n < 2**31 else np.int64
    pred = s_src[pol].astype(index)
    nodes = np.arange(n, dtype=index)
    # 2**steps >= n jumps backwards from any node land on its policy circuit,
    # and every circuit node is hit (the jump permutes each circuit).
    steps = max(1, int(n).bit_length())
    landing = pred
    for _ in range(steps):
        landing = landing[landing]
    on_cycle = np.zeros(n, dtype=bool)
    on_cycle[landing] = True
    cycle_nodes = np.flatnonzero(on_cycle).astype(index)
    # Root of each circuit: its smallest node (min-doubling around the circuit),
    # so that an unchanged circuit keeps its root from one iteration to the next.
    local = np.full(n, -1, dtype=index)
    local[cycle_nodes] = np.arange(len(cycle_nodes), dtype=index)
    around = local[pred[cycle_nodes]]
    smallest = cycle_nodes.copy()
    for _ in range(max(1, len(cycle_nodes).bit_length())):
        smallest = np.minimum(smallest, smallest[around])
        around = around[around]
    is_root = np.zeros(n, dtype=bool)
    is_root[cycle_nodes[smallest == cycle_nodes]] = True
    # Pointer doubling over the policy forest cut at the roots: sum_w[i] and
    # sum_t[i] add weights and tokens from i (included) to jump[i] (excluded).
    # Nodes whose jump reached a root are final and drop out.
    sum_w = np.where(is_root, 0, s_w[pol])
    sum_t = np.where(is_root, 0, s_t[pol])
    jump = np.where(is_root, nodes, pred)
    active = np.flatnonzero(~is_root[jump])
    while len(active):
        target = jump[active]
        sum_w[active] += sum_w[target]
        sum_t[active] += sum_t[target]
        jump[active] = jump[target]
        active = active[~is_root[jump[active]]]
    # The circuit of root r: its nodes' policy arcs, whose sums are those of r's
    # in-arc plus the path back to r, i.e. sum over the circuit.
    roots = np.flatnonzero(is_root)
    closing = pol[roots]
    before = s_src[closing]
    W_root = s_w[closing] + sum_w[before]
    T_root = s_t[closing] + sum_t[before]
    g = gcd_arrays(W_root, T_root)
    g = np.where(g == 0, 1, g)
    W_root, T_root = W_root // g, T_root // g
    rank_root = _rank_ratios(W_root, T_root)
    slot = np.zeros(n, dtype=index)
    slot[roots] = np.arange(len(roots), dtype=index)
    which = slot[jump]
    W, T, rank = W_root[which], T_root[which], rank_root[which]
    # A circuit that was already a policy circuit keeps its root's potential
    # (Cochet-Terrasson et al.): potentials then never decrease between
    # iterations of equal ratios, which rules out cycling.
    if first:
        root_value = np.zeros(len(roots), dtype=s_w.dtype)
    else:
        keep = (W_old[roots] == W_root) & (T_old[roots] == T_root)
        root_value = np.where(keep, X_old[roots], 0)
    X = sum_w * T - W * sum_t + root_value[which]
    return W, T, X, rank


def _rank_ratios(num: np.ndarray, den: np.ndarray) -> np.ndarray:
    """Dense rank of each fraction num/den (den > 0 for used entries; 0 = unused).

    Floats sort the fractions (an accelerator only); exact cross-multiplication
    then checks every adjacent pair, and decides equality. If floats misordered
    a pair (ratios closer than float precision, or beyond float range), the
    order is redone by exact comparisons.
    """
    k = len(num)
    used = den != 0
    rank = np.full(k, -1, dtype=np.int64)
    idx = np.flatnonzero(used)
    if len(idx) == 0:
        return rank
    order = idx[np.argsort(float_ratios(num[idx], den[idx]), kind="stable")]
    step = compare_ratios(num[order[1:]], den[order[1:]], num[order[:-1]], den[order[:-1]])
    if (step < 0).any():
        def cmp(i: int, j: int) -> int:
            return (int(num[i]) * int(den[j]) > int(num[j]) * int(den[i])) - (
                int(num[i]) * int(den[j]) < int(num[j]) * int(den[i]))

        # A loop over the distinct policy circuits, not over nodes; reached only
        # when floats cannot order the ratios.
        order = np.array(sorted(idx.tolist(), key=cmp_to_key(cmp)), dtype=np.int64)
        step = compare_ratios(num[order[1:]], den[order[1:]], num[order[:-1]], den[order[:-1]])
    rank[order] = np.r_[0, np.cumsum(step != 0)]
    return rank
