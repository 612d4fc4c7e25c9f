"""Howard's policy iteration compiled with numba: the optional accelerator.

The same algorithm and the same exact integer arithmetic as
:mod:`maxplus.policy_iteration` (int64 only, under the same proven bound; the
caller falls back to the numpy kernel when the bound does not hold or a
potential outgrows it), written as plain loops that numba compiles:

* value determination walks each policy path once (``O(n)``, no pointer
  jumping): a walk backwards from an unvisited node either closes a new policy
  circuit, whose ratio ``W/T`` (lowest terms) and potentials are set from its
  smallest node, or reaches a node already valued;
* ratio improvement switches a node to an in-arc from a node of strictly larger
  ratio, and passes the larger ratio downstream through a work queue (each
  switch a strict gain, so no new policy circuit can form);
* bias improvement, when no ratio improves, switches to the in-arc of the same
  ratio with the largest strictly better potential.

numba is imported only when this module is; :func:`available` tells whether it
can be. Compiled functions are cached on disk (``cache=True``), so only the
first process on a machine pays the compilation (about 10 s).

References
----------
.. [1] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick, J.-P. Quadrat,
   "Numerical computation of spectral elements in max-plus algebra", IFAC
   Conference on System Structure and Control, 1998.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["howard_jit"]


@njit(cache=True)
def _gcd(a, b):
    a = abs(a)
    b = abs(b)
    while b:
        a, b = b, a % b
    return a


@njit(cache=True)
def _value_determination(pol, arc, n, node, first, state, stack, limit):
    """Ratio, potential of every node under ``pol``, in place; False if ``limit`` is reached.

    ``arc[a] = (tail, weight, tokens)`` and ``node[v] = (W, T, X)`` are packed
    rows: one cache line per visit instead of three (memory latency, not
    arithmetic, bounds these loops). A circuit whose smallest node keeps its
    ratio keeps that node's potential (Cochet-Terrasson et al.), which rules
    out cycling among equal ratios.
    """
    state[:] = 0
    for v0 in range(n):
        if state[v0] != 0:
            continue
        top = 0
        v = v0
        while state[v] == 0:
            state[v] = 1
            stack[top] = v
            top += 1
            v = arc[pol[v], 0]
        if state[v] == 1:
            # A new policy circuit through v: its sums and smallest node.
            sum_w = 0
            sum_t = 0
            root = v
            u = v
            while True:
                a = pol[u]
                sum_w += arc[a, 1]
                sum_t += arc[a, 2]
                u = arc[a, 0]
                root = min(root, u)
                if u == v:
                    break
            g = _gcd(sum_w, sum_t)
            if g == 0:
                g = 1
            Wc = sum_w // g
            Tc = sum_t // g
            xr = 0
            if not first and node[root, 0] == Wc and node[root, 1] == Tc:
                xr = node[root, 2]
            node[root, 0] = Wc
            node[root, 1] = Tc
            node[root, 2] = xr
            state[root] = 2
            # Backwards from the root: X[p] = X[u] - (w T - W t) on the arc p -> u;
            # the circuit's terms sum to zero, so this is the forward path sum too.
            u = root
            while True:
                a = pol[u]
                p = arc[a, 0]
                if p == root:
                    break
                x = node[u, 2] - (arc[a, 1] * Tc - Wc * arc[a, 2])
                node[p, 0] = Wc
                node[p, 1] = Tc
                node[p, 2] = x
                state[p] = 2
                if abs(x) >= limit:
                    return False
                u = p
        # The tail of the walk, nearest the valued node first.
        for k in range(top - 1, -1, -1):
            u = stack[k]
            if state[u] == 2:
                continue
            a = pol[u]
            p = arc[a, 0]
            Wp = node[p, 0]
            Tp = node[p, 1]
            x = node[p, 2] + arc[a, 1] * Tp - Wp * arc[a, 2]
            node[u, 0] = Wp
            node[u, 1] = Tp
            node[u, 2] = x
            state[u] = 2
            if abs(x) >= limit:
                return False
    return True


@njit(cache=True)
def _improve_ratios(pol, arc, starts, out_arc, out_starts, n, node, queued, queue):
    """Switch nodes to in-arcs of strictly larger ratio and pass it downstream; count switches."""
    switched = 0
    head = 0
    size = 0
    for v in range(n):
        best = -1
        bw = node[v, 0]
        bt = node[v, 1]
        for a in range(starts[v], starts[v + 1]):
            j = arc[a, 0]
            if node[j, 0] * bt > bw * node[j, 1]:
                best = a
                bw = node[j, 0]
                bt = node[j, 1]
        if best >= 0:
            pol[v] = best
            node[v, 0] = bw
            node[v, 1] = bt
            switched += 1
            if not queued[v]:
                queued[v] = True
                queue[(head + size) % n] = v
                size += 1
    while size:
        u = queue[head]
        head = (head + 1) % n
        size -= 1
        queued[u] = False
        Wu = node[u, 0]
        Tu = node[u, 1]
        for k in range(out_starts[u], out_starts[u + 1]):
            a = out_arc[k, 0]
            v = out_arc[k, 1]
            if Wu * node[v, 1] > node[v, 0] * Tu:
                pol[v] = a
                node[v, 0] = Wu
                node[v, 1] = Tu
                switched += 1
                if not queued[v]:
                    queued[v] = True
                    queue[(head + size) % n] = v
                    size += 1
    return switched


@njit(cache=True)
def _improve_bias(pol, arc, starts, n, node, old):
    """Switch nodes to a same-ratio in-arc of strictly better potential.

    Only arcs that improve under the current policy's potentials (``old``,
    Jacobi) may be chosen, which keeps Howard's convergence argument; among
    them, the choice uses potentials raised earlier in the same sweep
    (Gauss-Seidel), which carries a gain along a chain in one iteration.
    """
    switched = 0
    old[:] = node[:, 2]
    for v in range(n):
        best = -1
        Wv = node[v, 0]
        Tv = node[v, 1]
        value = old[v]
        gs = value
        for a in range(starts[v], starts[v + 1]):
            j = arc[a, 0]
            if node[j, 0] == Wv and node[j, 1] == Tv:
                c = arc[a, 1] * Tv - Wv * arc[a, 2]
                if old[j] + c > value and node[j, 2] + c > gs:
                    gs = node[j, 2] + c
                    best = a
        if best >= 0:
            pol[v] = best
            node[v, 2] = gs
            switched += 1
    return switched


@njit(cache=True)
def _howard(arc, starts, out_arc, out_starts, pol, n, limit):
    node = np.zeros((n, 3), dtype=np.int64)
    state = np.zeros(n, dtype=np.int8)
    stack = np.empty(n, dtype=np.int64)
    queued = np.zeros(n, dtype=np.bool_)
    queue = np.empty(n, dtype=np.int64)
    old = np.empty(n, dtype=np.int64)
    iterations = 0
    first = True
    while True:
        iterations += 1
        if not _value_determination(pol, arc, n, node, first, state, stack, limit):
            return node, iterations, False
        first = False
        if _improve_ratios(pol, arc, starts, out_arc, out_starts, n, node, queued, queue):
            continue
        if not _improve_bias(pol, arc, starts, n, node, old):
            return node, iterations, True


def howard_jit(s_src: np.ndarray, s_dst: np.ndarray, s_w: np.ndarray, s_t: np.ndarray,
               starts: np.ndarray, out_order: np.ndarray, pol: np.ndarray, n: int, limit: int):
    """Optimal policy, compiled; arcs sorted by head (``starts`` the CSR offsets, n + 1 long).

    Parameters
    ----------
    s_src, s_dst, s_w, s_t : numpy.ndarray of int64
        Arcs sorted by ``s_dst``.
    starts : numpy.ndarray of int64
        In-arcs of node ``v`` are ``starts[v]:starts[v + 1]``.
    out_order : numpy.ndarray of int64
        Indices of the sorted arcs, sorted by tail.
    pol : numpy.ndarray of int64
        Initial policy (an in-arc per node), changed in place.
    n : int
    limit : int
        Potentials must stay below this in absolute value (int64 exactness).

    Returns
    -------
    W, T, X : numpy.ndarray of int64
    iterations : int
    ok : bool
        False when a potential reached ``limit``: redo with Python ints.
    """
    arc = np.column_stack([s_src, s_w, s_t]).astype(np.int64)
    out_arc = np.column_stack([out_order, s_dst[out_order]]).astype(np.int64)
    out_starts = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(s_src, minlength=n), out=out_starts[1:])
    node, iterations, ok = _howard(arc, starts, out_arc, out_starts, pol, n, int(limit))
    return node[:, 0].copy(), node[:, 1].copy(), node[:, 2].copy(), iterations, ok
