"""Spectral theory of (max,+) matrices: eigenvalue, cycle-time vector, Howard,
Karp; and the namespace of the critical-graph functions.

Convention (the whole package): ``x(k+1) = A ⊗ x(k)``, ``A[i][j]`` is the
weight of the arc ``j -> i``, ε = -inf, and eigenvectors are right
eigenvectors, ``A ⊗ v = λ ⊗ v``.

* The eigenvalue of an irreducible matrix is its maximum cycle mean, and for
  any matrix with a circuit the maximum cycle mean λ is its largest
  eigenvalue [1]_.
* ``χ_i = lim x_i(k)/k`` is the largest cycle mean over the strongly connected
  classes upstream of ``i`` [1]_; it needs no circuit *through* i.
* The critical graph, eigenvectors, eigenspace and cyclicity
  (:mod:`maxplus._critical`) are re-exported here; transients are in
  :mod:`maxplus.transient`.

:func:`eigenvalue` and :func:`cycle_time_vector` run a dense Howard policy
iteration [2]_ in exact integers (:mod:`maxplus._max_mean`) and check an
integer potential certificate before answering; :func:`howard` returns the
sparse kernel's policy and bias (:func:`maxplus.cycle_ratio.max_cycle_ratio`);
:func:`karp` [3]_ is an independent implementation kept as a cross-check.

References
----------
.. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
   and Linearity*, Wiley, 1992, Thm 3.23 and Thm 3.112.
.. [2] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
   J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
   algebra", IFAC Conference on System Structure and Control, 1998.
.. [3] R. M. Karp, "A characterization of the minimum cycle mean in a
   digraph", Discrete Mathematics 23(3), 309–311, 1978.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np

from . import _kernels
from ._critical import CriticalGraph, critical_graph, cyclicity, eigenspace, eigenvector
from ._graphs import adjacency, is_strongly_connected, strong_classes
from ._integer_matrix import integer_matrix, plain_int_rows
from ._max_mean import cycle_times, max_cycle_mean, max_cycle_mean_rows
from ._scaled import bottom, scaled, square_matrix
from .cycle_ratio import max_cycle_ratio

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

    See Also
    --------
    howard : computes it.
    maxplus.max_cycle_ratio : the same on sparse arc arrays, with tokens.

    Examples
    --------
    >>> h = howard([[1, 5], [3, 2]])
    >>> h.eigenvalue, h.bias, h.policy, h.circuit
    (Fraction(4, 1), [Fraction(0, 1), Fraction(-1, 1)], [1, 0], [0, 1])
    """

    eigenvalue: Fraction | None
    cycle_time_vector: list[Fraction | None]
    bias: list[Fraction | None]
    policy: list[int | None]
    circuit: list[int]


def is_irreducible(A: Any) -> bool:
    """True when the graph of A is strongly connected and has a circuit.

    A 1×1 matrix ``[[ε]]`` has no circuit and counts as reducible here (it has
    no finite eigenvalue).

    Parameters
    ----------
    A : square matrix (nested lists or 2-D array)

    Returns
    -------
    bool

    Raises
    ------
    MaxPlusValueError
        A bad entry (named) or a non-square matrix.

    See Also
    --------
    eigenvalue : the unique eigenvalue of an irreducible matrix.
    maxplus.spectral.eigenspace : defined here for irreducible matrices only.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, §2.3 (a matrix is irreducible iff its
       graph is strongly connected).

    Examples
    --------
    >>> is_irreducible([[1, 2], [3, 4]]), is_irreducible([[1, None], [None, 2]])
    (True, False)
    """
    return is_strongly_connected(integer_matrix(A).finite)


# --------------------------------------------------------------------------- Karp


def _karp_class(S: np.ndarray) -> Fraction:
    """Max cycle mean (scaled) of a strongly connected scaled matrix [Karp 1978]."""
    s = len(S)
    low = bottom(S.dtype)
    rows, cols = np.nonzero(np.asarray(S != -np.inf, dtype=bool))
    weights = S[rows, cols]
    # D[k, v]: best weight of a walk of exactly k arcs from node 0 to v.
    D = np.full((s + 1, s), low, dtype=S.dtype)
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
    A : square matrix (nested lists or 2-D array)

    Returns
    -------
    Fraction or None
        None when the graph has no circuit.

    Raises
    ------
    MaxPlusValueError
        A bad entry (named) or a non-square matrix.

    See Also
    --------
    eigenvalue : the same number by Howard's policy iteration, certified.
    howard : cycle times, bias and policy.

    Notes
    -----
    Karp states the theorem for the minimum cycle mean [1]_; the maximum is
    symmetric. The maximum over k in place of the minimum is a known pitfall
    (it gives 5 instead of 4 on ``[[1, 5], [3, 2]]``).

    References
    ----------
    .. [1] R. M. Karp, "A characterization of the minimum cycle mean in a
       digraph", Discrete Mathematics 23(3), 309–311, 1978.

    Examples
    --------
    >>> karp([[3, 7], [2, 4]])
    Fraction(9, 2)
    >>> karp([[None, 1], [None, None]]) is None
    True
    """
    M = square_matrix(A)
    S, scale = scaled(M, growth=len(M) + 2)
    adj = adjacency(M)
    n_comp, labels = strong_classes(adj)
    best: Fraction | None = None
    for comp in range(n_comp):
        nodes = np.flatnonzero(labels == comp)
        if len(nodes) == 1 and not adj[nodes[0], nodes[0]]:
            continue
        mean = _karp_class(S[np.ix_(nodes, nodes)])
        best = mean if best is None else max(best, mean)
    return None if best is None else best / scale


# --------------------------------------------------------------------------- Howard


def eigenvalue(A: Any) -> Fraction | None:
    """Maximum cycle mean λ: the eigenvalue of an irreducible A, the largest
    eigenvalue of any A with a circuit.

    Parameters
    ----------
    A : square matrix (nested lists or 2-D array)

    Returns
    -------
    Fraction or None
        None when the graph of A has no circuit.

    Raises
    ------
    MaxPlusValueError
        A bad entry (named) or a non-square matrix.
    CertificateError
        The potentials found do not prove λ (a defect; never returned unproven).

    See Also
    --------
    karp : the same number by Karp's theorem.
    cycle_time_vector : the growth rate of every node.
    maxplus.spectral.eigenvector : an eigenvector for λ.

    Notes
    -----
    λ is the maximum cycle mean [1]_. Howard's policy iteration [2]_ runs on
    the dense matrix in exact integers (Python loops below 17 nodes, numpy
    above); its final potentials ``x`` prove λ = p/q: ``q·A[i][j] − p + x_j
    <= x_i`` on every arc bounds every circuit mean by λ, and a policy circuit
    attains it. That check is made before λ is returned. A reducible matrix
    is solved class by class.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, Thm 3.23.
    .. [2] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
       J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
       algebra", IFAC Conference on System Structure and Control, 1998.

    Examples
    --------
    >>> eigenvalue([[3, 7], [2, 4]])
    Fraction(9, 2)
    >>> eigenvalue([[1, 5], [3, 2]])  # circuit 0 -> 1 -> 0: (5 + 3)/2
    Fraction(4, 1)
    """
    rows = plain_int_rows(A)
    if rows is not None and len(rows) <= _kernels.current().dense_lists_max_nodes:
        return max_cycle_mean_rows(rows)
    return max_cycle_mean(integer_matrix(A))


def cycle_time_vector(A: Any) -> list[Fraction | None]:
    """Cycle-time vector ``χ_i = lim x_i(k)/k`` of ``x(k+1) = A ⊗ x(k)``.

    Also for reducible A: ``χ_i`` is the largest mean of a circuit in a class
    upstream of i (from which i can be reached). A node with no circuit
    upstream gets None (``x_i(k)`` is then ε for every k ≥ n, for any finite x(0)).

    Parameters
    ----------
    A : square matrix (nested lists or 2-D array)

    Returns
    -------
    list of Fraction or None

    Raises
    ------
    MaxPlusValueError
        A bad entry (named) or a non-square matrix.
    CertificateError
        A class mean is not proven (a defect).

    See Also
    --------
    eigenvalue : the largest entry.
    howard : the same vector with bias and policy.

    Notes
    -----
    Every strongly connected class gets its certified maximum cycle mean (as
    in :func:`eigenvalue`); the vector is their maximum over the classes
    upstream of each node [1]_, passed along the classes in topological order.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, Thm 3.112.

    Examples
    --------
    >>> cycle_time_vector([[3, None], [2, 4]])
    [Fraction(3, 1), Fraction(4, 1)]
    >>> cycle_time_vector([[None, None], [1, None]])
    [None, None]
    """
    return cycle_times(integer_matrix(A))


def howard(A: Any) -> HowardResult:
    """Multichain policy iteration: cycle times, bias, policy, critical circuit.

    Parameters
    ----------
    A : square matrix (nested lists or 2-D array)

    Returns
    -------
    HowardResult
        ``.eigenvalue``, ``.cycle_time_vector``, ``.bias``, ``.policy``
        (``policy[i]`` = chosen predecessor j of i) and ``.circuit`` (nodes).

    Raises
    ------
    MaxPlusValueError
        A bad entry (named) or a non-square matrix.
    CertificateError
        The kernel's certificate fails (a defect; checked before returning).

    See Also
    --------
    eigenvalue : λ alone, faster on dense matrices.
    cycle_time_vector : χ alone.
    maxplus.cycle_ratio.max_cycle_ratio : the sparse kernel behind this.

    Notes
    -----
    The bias of a reducible matrix is generally *not* an eigenvector.

    References
    ----------
    .. [1] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
       J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
       algebra", IFAC Conference on System Structure and Control, 1998.

    Examples
    --------
    >>> h = howard([[3, 7], [2, 4]])
    >>> h.eigenvalue, h.cycle_time_vector, h.policy, h.circuit
    (Fraction(9, 2), [Fraction(9, 2), Fraction(9, 2)], [1, 0], [0, 1])
    """
    M = square_matrix(A)
    rows, cols = np.nonzero(adjacency(M))
    weights = np.empty(len(rows), dtype=object)
    weights[:] = [M[i, j] for i, j in zip(rows.tolist(), cols.tolist())]
    result = max_cycle_ratio(cols, rows, weights, None, n_nodes=len(M))
    result.verify()  # nothing unproven is handed out
    policy = [None if a < 0 else int(cols[a]) for a in result.policy.tolist()]
    return HowardResult(
        result.ratio, list(result.cycle_times), list(result.bias), policy, result.circuit_nodes
    )
