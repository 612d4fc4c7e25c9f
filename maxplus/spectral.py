"""Spectral theory of (max,+) matrices: eigenvalue, eigenvectors, critical
graph, cyclicity, transients, cycle-time vector.

Convention (the whole package): ``x(k+1) = A ⊗ x(k)``, ``A[i][j]`` is the
weight of the arc ``j -> i``, ε = -inf, and eigenvectors are right
eigenvectors, ``A ⊗ v = λ ⊗ v``.

* The eigenvalue of an irreducible matrix is its maximum cycle mean
  (Baccelli, Cohen, Olsder, Quadrat, *Synchronization and Linearity*, 1992 —
  "BCOQ" — Thm 3.23); for any matrix with a circuit, the maximum cycle mean λ
  is its largest eigenvalue, with eigenvectors the critical columns of
  ``(A − λ)^+`` (BCOQ §3.7; P. Butkovič, *Max-linear Systems*, 2010, §4.3,
  also for reducible matrices).
* ``χ_i = lim x_i(k)/k`` is the largest cycle mean over the strongly connected
  classes upstream of ``i`` (BCOQ Thm 3.112); it needs no circuit *through* i.
* Transients (when ``A^(t+c) = λ^c ⊗ A^t`` starts) are in :mod:`maxplus.transient`.

:func:`eigenvalue`, :func:`cycle_time_vector` and :func:`howard` are thin
wrappers over the sparse, certified kernel
:func:`maxplus.cycle_ratio.max_cycle_ratio` (Howard's policy iteration,
Cochet-Terrasson et al. 1998); :func:`karp` (Karp 1978) is an independent
implementation kept as a cross-check. The arcs of a matrix are its finite
entries: ``A[i][j] != ε`` is an arc ``j -> i`` of weight ``A[i][j]`` and 1 token.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from .cycle_ratio import CycleRatioResult, max_cycle_ratio
from .dense import (
    _plus_scaled,
    _square,
)
from .errors import ReducibleMatrixError
from .scalar import EPS, from_scaled, to_scaled

__all__ = [
    "CriticalGraph",
    "HowardResult",
    "critical_graph",
    "cycle_time_vector",
    "cyclicity",
    "eigenspace",
    "eigenvalue",
    "eigenvector",
    "howard",
    "is_irreducible",
    "karp",
]


@dataclass(frozen=True)
class CriticalGraph:
    """The critical graph: the union of the circuits of maximum mean.

    Attributes
    ----------
    eigenvalue : Fraction or None
        The maximum cycle mean λ (None without circuit: then the graph is empty).
    nodes : list of int
        Critical nodes, increasing.
    arcs : list of (int, int)
        Critical arcs ``(j, i)`` meaning ``j -> i`` (the entry ``A[i][j]``).
    components : list of list of int
        Strongly connected classes of the critical graph, each increasing,
        ordered by their smallest node.
    """

    eigenvalue: Fraction | None
    nodes: list[int]
    arcs: list[tuple[int, int]]
    components: list[list[int]]


@dataclass(frozen=True)
class HowardResult:
    """Result of :func:`howard` (multichain policy iteration).

    Attributes
    ----------
    eigenvalue : Fraction or None
        Maximum cycle mean (None without circuit).
    cycle_time_vector : list of Fraction or None
        ``χ_i``; None for a node with no circuit upstream.
    bias : list of Fraction or None
        ``v`` with ``v_i >= v_j + A[i][j] − χ_i`` on every arc ``j -> i`` with
        ``χ_j == χ_i``, with equality on policy arcs.
    policy : list of int or None
        ``policy[i] = j``: the chosen predecessor of i (None where χ_i is None).
    circuit : list of int
        Nodes of a circuit of mean ``eigenvalue``, in order (arcs
        ``circuit[0] -> circuit[1] -> ... -> circuit[0]``); empty without circuit.
    """

    eigenvalue: Fraction | None
    cycle_time_vector: list[Fraction | None]
    bias: list[Fraction | None]
    policy: list[int | None]
    circuit: list[int]


# --------------------------------------------------------------------------- graph helpers


def _adjacency(M: np.ndarray) -> np.ndarray:
    """Boolean ``adj[i, j]``: there is an arc j -> i."""
    return np.asarray(M != EPS, dtype=bool)


def _arcs(M: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rows, cols = np.nonzero(_adjacency(M))
    weights = np.empty(len(rows), dtype=object)
    weights[:] = [M[i, j] for i, j in zip(rows.tolist(), cols.tolist())]
    return cols, rows, weights  # src = j, dst = i


def _kernel(M: np.ndarray) -> tuple[CycleRatioResult, np.ndarray]:
    src, dst, weights = _arcs(M)
    result = max_cycle_ratio(src, dst, weights, None, n_nodes=len(M))
    # Every eigenvalue and cycle time this module returns is proven exactly:
    # the certificate is checked before anything is handed out.
    result.verify()
    return result, src


def _classes(adj: np.ndarray) -> tuple[int, np.ndarray]:
    """Strongly connected classes of the graph (labels per node)."""
    rows, cols = np.nonzero(adj)
    n = len(adj)
    graph = sp.csr_matrix((np.ones(len(rows), dtype=np.int8), (cols, rows)), shape=(n, n))
    return connected_components(graph, directed=True, connection="strong")


def _cyclic_nodes(adj: np.ndarray) -> np.ndarray:
    """Nodes lying on some circuit."""
    n_comp, labels = _classes(adj)
    sizes = np.bincount(labels, minlength=n_comp)
    return (sizes[labels] > 1) | np.diag(adj)


def is_irreducible(A: Any) -> bool:
    """True when the graph of A is strongly connected and has a circuit.

    A 1×1 matrix ``[[ε]]`` has no circuit and counts as reducible here (it has
    no finite eigenvalue).

    Parameters
    ----------
    A : square matrix

    Returns
    -------
    bool

    Raises
    ------
    MaxPlusValueError
        A bad entry or a non-square matrix.

    Notes
    -----
    BCOQ 1992, §2.3 (a matrix is irreducible iff its graph is strongly connected).

    Examples
    --------
    >>> is_irreducible([[1, 2], [3, 4]]), is_irreducible([[1, None], [None, 2]])
    (True, False)
    """
    M = _square(A)
    return _irreducible(_adjacency(M))


def _irreducible(adj: np.ndarray) -> bool:
    n_comp, _ = _classes(adj)
    return n_comp == 1 and (len(adj) > 1 or bool(adj[0, 0]))


def _period(nodes: list[int], arcs: list[tuple[int, int]]) -> int:
    """gcd of the circuit lengths of a strongly connected graph (BFS levels).

    Every circuit length is a sum of ``level[u] + 1 − level[v]`` over its arcs,
    and conversely these differences generate the same group (Denardo 1977).
    """
    out: dict[int, list[int]] = {v: [] for v in nodes}
    for u, v in arcs:
        out[u].append(v)
    level = {nodes[0]: 0}
    queue = deque([nodes[0]])
    while queue:
        u = queue.popleft()
        for v in out[u]:
            if v not in level:
                level[v] = level[u] + 1
                queue.append(v)
    g = 0
    for u, v in arcs:
        g = math.gcd(g, level[u] + 1 - level[v])
    return abs(g)


def _bool_product(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    # float32 counts are exact below 2**24 paths per entry (n < 2**24).
    return (X.astype(np.float32) @ Y.astype(np.float32)) > 0


def _reach_closure(adj: np.ndarray) -> np.ndarray:
    """``R[i, j]``: a path (possibly empty) from j to i."""
    R = adj | np.eye(len(adj), dtype=bool)
    while True:
        nxt = R | _bool_product(R, R)
        if np.array_equal(nxt, R):
            return R
        R = nxt


# --------------------------------------------------------------------------- Karp


def _karp_class(S: np.ndarray) -> Fraction:
    """Max cycle mean (scaled) of a strongly connected scaled matrix, Karp 1978."""
    s = len(S)
    rows, cols = np.nonzero(np.asarray(S != -np.inf, dtype=bool))
    weights = S[rows, cols]
    # D[k, v]: best weight of a walk of exactly k arcs from node 0 to v.
    D = np.full((s + 1, s), -np.inf, dtype=S.dtype)
    D[0, 0] = 0
    for k in range(1, s + 1):
        np.maximum.at(D[k], rows, D[k - 1][cols] + weights)
    best: Fraction | None = None
    for v in range(s):
        if D[s, v] == -np.inf:
            continue
        worst = min(
            Fraction(int(D[s, v]) - int(D[k, v]), s - k)
            for k in range(s) if D[k, v] != -np.inf
        )
        best = worst if best is None else max(best, worst)
    assert best is not None  # a strongly connected class with a circuit has one
    return best


def karp(A: Any) -> Fraction | None:
    """Maximum cycle mean by Karp's algorithm, class by class (exact).

    An independent reference for :func:`eigenvalue` (which runs Howard's
    policy iteration): ``λ = max_v min_k (D_n(v) − D_k(v)) / (n − k)`` on each
    strongly connected class, ``D_k(v)`` the best walk of k arcs from a fixed
    node of the class. O(n·m) time.

    Parameters
    ----------
    A : square matrix

    Returns
    -------
    Fraction or None
        None when the graph has no circuit.

    Raises
    ------
    MaxPlusValueError
        A bad entry or a non-square matrix.

    Notes
    -----
    R. M. Karp, "A characterization of the minimum cycle mean in a digraph",
    Discrete Mathematics 23, 1978 (stated for the minimum; max is symmetric).

    Examples
    --------
    >>> karp([[3, 7], [2, 4]])
    Fraction(9, 2)
    >>> karp([[None, 1], [None, None]]) is None
    True
    """
    M = _square(A)
    S, scale = to_scaled(M, growth=len(M) + 2)
    adj = _adjacency(M)
    n_comp, labels = _classes(adj)
    best: Fraction | None = None
    for comp in range(n_comp):
        nodes = np.flatnonzero(labels == comp)
        if len(nodes) == 1 and not adj[nodes[0], nodes[0]]:
            continue
        mean = _karp_class(S[np.ix_(nodes, nodes)])
        best = mean if best is None else max(best, mean)
    return None if best is None else best / scale


# --------------------------------------------------------------------------- kernel wrappers


def eigenvalue(A: Any) -> Fraction | None:
    """Maximum cycle mean λ: the eigenvalue of an irreducible A, the largest
    eigenvalue of any A with a circuit.

    Parameters
    ----------
    A : square matrix

    Returns
    -------
    Fraction or None
        None when the graph of A has no circuit.

    Raises
    ------
    MaxPlusValueError
        A bad entry or a non-square matrix.

    Notes
    -----
    BCOQ 1992, Thm 3.23; computed by :func:`maxplus.cycle_ratio.max_cycle_ratio`
    (Cochet-Terrasson et al. 1998), certified.

    Examples
    --------
    >>> eigenvalue([[3, 7], [2, 4]])
    Fraction(9, 2)
    """
    result, _ = _kernel(_square(A))
    return result.ratio


def cycle_time_vector(A: Any) -> list[Fraction | None]:
    """Cycle-time vector ``χ_i = lim x_i(k)/k`` of ``x(k+1) = A ⊗ x(k)``.

    Also for reducible A: ``χ_i`` is the largest mean of a circuit in a class
    upstream of i (from which i can be reached). A node with no circuit
    upstream gets None (``x_i(k)`` is then ε for every k ≥ n, for any finite x(0)).

    Parameters
    ----------
    A : square matrix

    Returns
    -------
    list of Fraction or None

    Raises
    ------
    MaxPlusValueError
        A bad entry or a non-square matrix.

    Notes
    -----
    BCOQ 1992, Thm 3.112; Cochet-Terrasson et al. 1998 (multichain Howard).

    Examples
    --------
    >>> cycle_time_vector([[3, None], [2, 4]])
    [Fraction(3, 1), Fraction(4, 1)]
    >>> cycle_time_vector([[None, None], [1, None]])
    [None, None]
    """
    result, _ = _kernel(_square(A))
    return list(result.cycle_times)


def howard(A: Any) -> HowardResult:
    """Multichain policy iteration: cycle times, bias, policy, critical circuit.

    Parameters
    ----------
    A : square matrix

    Returns
    -------
    HowardResult
        ``.eigenvalue``, ``.cycle_time_vector``, ``.bias``, ``.policy``
        (``policy[i]`` = chosen predecessor j of i) and ``.circuit`` (nodes).

    Raises
    ------
    MaxPlusValueError
        A bad entry or a non-square matrix.

    Notes
    -----
    J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick, J.-P. Quadrat,
    "Numerical computation of spectral elements in max-plus algebra", IFAC
    SSC 1998. The bias of a reducible matrix is generally *not* an eigenvector.

    Examples
    --------
    >>> h = howard([[3, 7], [2, 4]])
    >>> h.eigenvalue, h.cycle_time_vector, h.policy, h.circuit
    (Fraction(9, 2), [Fraction(9, 2), Fraction(9, 2)], [1, 0], [0, 1])
    """
    result, src = _kernel(_square(A))
    policy = [None if a < 0 else int(src[a]) for a in result.policy.tolist()]
    return HowardResult(
        result.ratio, list(result.cycle_times), list(result.bias), policy, result.circuit_nodes()
    )


# --------------------------------------------------------------------------- critical graph


def _normalized_closure(M: np.ndarray, lam: Fraction) -> tuple[np.ndarray, int]:
    """``(A − λ)^+`` on scaled integers (exists: no circuit of A − λ is positive)."""
    shifted = np.empty(M.shape, dtype=object)
    shifted.reshape(-1)[:] = [v - lam for v in M.ravel().tolist()]  # ε − λ = ε
    S, scale = to_scaled(shifted, growth=len(M) + 2)
    return _plus_scaled(S, shifted), scale


def _critical(M: np.ndarray) -> tuple[CriticalGraph, np.ndarray | None, int]:
    """Critical graph, plus ``(A − λ)^+`` scaled and its scale (None without circuit)."""
    result, _ = _kernel(M)
    lam = result.ratio
    if lam is None:
        return CriticalGraph(None, [], [], []), None, 1
    P, scale = _normalized_closure(M, lam)
    nodes = [i for i in range(len(M)) if P[i, i] == 0]
    critical = set(nodes)
    arcs = []
    lam_scaled = lam * scale
    for i, j in zip(*np.nonzero(_adjacency(M))):
        i, j = int(i), int(j)
        # Arc j -> i lies on a circuit of mean λ iff its weight in A − λ plus the
        # best return path i -> j (P[j, i]) is 0, the largest possible value.
        if (i in critical and j in critical and P[j, i] != -np.inf
                and M[i, j] * scale - lam_scaled + int(P[j, i]) == 0):
            arcs.append((j, i))
    sub = np.zeros((len(M), len(M)), dtype=bool)
    for j, i in arcs:
        sub[i, j] = True
    _, labels = _classes(sub)
    groups: dict[int, list[int]] = {}
    for v in nodes:
        groups.setdefault(int(labels[v]), []).append(v)
    components = sorted(groups.values(), key=lambda c: c[0])
    return CriticalGraph(lam, nodes, sorted(arcs), components), P, scale


def critical_graph(A: Any) -> CriticalGraph:
    """Critical graph of A: nodes and arcs of the circuits of maximum mean.

    Parameters
    ----------
    A : square matrix

    Returns
    -------
    CriticalGraph
        ``.eigenvalue``, ``.nodes``, ``.arcs`` (``(j, i)`` = arc ``j -> i``),
        ``.components`` (its strongly connected classes).

    Raises
    ------
    MaxPlusValueError
        A bad entry or a non-square matrix.

    Notes
    -----
    BCOQ 1992, §3.7 (critical graph); a node c is critical iff
    ``(A − λ)^+[c][c] = 0``.

    Examples
    --------
    >>> g = critical_graph([[1, 0], [0, 1]])
    >>> g.eigenvalue, g.nodes, g.arcs, g.components
    (Fraction(1, 1), [0, 1], [(0, 0), (1, 1)], [[0], [1]])
    """
    return _critical(_square(A))[0]


def _require_circuit(graph: CriticalGraph) -> None:
    if graph.eigenvalue is None:
        raise ReducibleMatrixError(
            "A has no circuit: its only eigenvalue is ε, with no finite eigenvector"
        )


def eigenvector(A: Any) -> np.ndarray:
    """An eigenvector for the maximum cycle mean λ: ``A ⊗ v = λ ⊗ v``.

    ``v`` is the column c of ``(A − λ)^+`` for the smallest critical node c
    (``v_c = 0``). Works for reducible A too (entries of nodes not reachable
    from c are ε).

    Parameters
    ----------
    A : square matrix

    Returns
    -------
    numpy.ndarray of dtype object

    Raises
    ------
    MaxPlusValueError
        A bad entry or a non-square matrix.
    ReducibleMatrixError
        A has no circuit (no finite eigenvalue).

    Notes
    -----
    BCOQ 1992, §3.7; Butkovič 2010, §4.3 (critical columns of ``(A − λ)^+``
    are eigenvectors, for any A with a circuit).

    Examples
    --------
    >>> eigenvector([[3, 7], [2, 4]]).tolist()
    [Fraction(0, 1), Fraction(-5, 2)]
    """
    graph, P, scale = _critical(_square(A))
    _require_circuit(graph)
    assert P is not None
    return from_scaled(P[:, graph.nodes[0]], scale)


def eigenspace(A: Any) -> np.ndarray:
    """A basis of the eigenspace of an irreducible A: one column of
    ``(A − λ)^+`` per strongly connected class of the critical graph.

    Every eigenvector is ``V ⊗ α`` for the returned V and some vector α.

    Parameters
    ----------
    A : square matrix, irreducible

    Returns
    -------
    numpy.ndarray of dtype object
        n × r, one basis vector per column (r = number of critical classes),
        the column of ``(A − λ)^+`` of the smallest node of each class.

    Raises
    ------
    MaxPlusValueError
        A bad entry or a non-square matrix.
    ReducibleMatrixError
        A is reducible (its spectrum may hold other eigenvalues; use
        :func:`eigenvector`).

    Notes
    -----
    BCOQ 1992, §3.7 (critical columns from distinct classes are independent;
    those of one class are proportional); Butkovič 2010, §4.3.

    Examples
    --------
    >>> eigenspace([[1, 0], [0, 1]]).tolist()
    [[Fraction(0, 1), Fraction(-1, 1)], [Fraction(-1, 1), Fraction(0, 1)]]
    """
    M = _square(A)
    if not _irreducible(_adjacency(M)):
        n_comp, _ = _classes(_adjacency(M))
        raise ReducibleMatrixError(
            f"A is reducible ({n_comp} strongly connected classes, or no circuit): "
            "its eigenspace is not spanned by one eigenvalue's critical columns"
        )
    graph, P, scale = _critical(M)
    assert P is not None
    columns = [comp[0] for comp in graph.components]
    return from_scaled(P[:, columns], scale)


def cyclicity(A: Any) -> int:
    """Cyclicity of the critical graph: lcm over its classes of the gcd of their
    circuit lengths (1 when A has no circuit).

    For irreducible A it is the period c of ``A^(k+c) = λ^c ⊗ A^k`` (large k).

    Parameters
    ----------
    A : square matrix

    Returns
    -------
    int

    Raises
    ------
    MaxPlusValueError
        A bad entry or a non-square matrix.

    Notes
    -----
    BCOQ 1992, §3.7 and Thm 3.109; gcd by BFS levels (E. V. Denardo, "Periods of
    connected networks...", Math. Oper. Res. 1977), O(n + m).

    Examples
    --------
    >>> cyclicity([[3, 7], [2, 4]]), cyclicity([[None, None, 3], [1, None, None], [None, 2, None]])
    (2, 3)
    """
    return _cyclicity(_critical(_square(A))[0])


def _cyclicity(graph: CriticalGraph) -> int:
    c = 1
    for comp in graph.components:
        members = set(comp)
        arcs = [(j, i) for j, i in graph.arcs if j in members]
        c = math.lcm(c, _period(comp, arcs))
    return c
