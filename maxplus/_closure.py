"""Closures of (max,+) matrices: ``A+``, the Kleene star ``A*``, and ``x = A x ⊕ b``.

``A*[i][j]`` is the best weight of a path from ``j`` to ``i`` (the entry
``A[i][j]`` is the arc ``j -> i``); it exists exactly when no circuit has a
positive weight, and then ``A* ⊗ b`` is the least solution of
``x = A ⊗ x ⊕ b`` [1]_. Computed by Floyd–Warshall [2]_ on scaled integers,
vectorized per pivot (O(n³)). A diverging star names one positive circuit.

The public functions are importable from :mod:`maxplus.dense` and
:mod:`maxplus`.

References
----------
.. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
   and Linearity*, Wiley, 1992, §3.2.3 and Thm 3.17.
.. [2] R. W. Floyd, "Algorithm 97: Shortest path", Communications of the
   ACM 5(6), 345, 1962.
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from typing import Any

import numpy as np

from ._graphs import adjacency, downstream
from ._scaled import (
    as_exact,
    identity_scaled,
    operand,
    product_scaled,
    scale_together,
    scaled,
    square_matrix,
)
from .errors import MaxPlusValueError, PositiveCircuitError
from .scalar import EPS, Scalar, is_eps

__all__ = ["plus", "plus_scaled", "raise_positive_circuit", "solve", "star"]


def plus_scaled(S: np.ndarray, exact_matrix_: np.ndarray,
                labels: Sequence[int] | None = None) -> np.ndarray:
    """``S+ = S ⊕ S² ⊕ ...`` on scaled integers by Floyd–Warshall (a new array).

    Raises PositiveCircuitError (with node indices mapped through ``labels``
    and the weight summed exactly from ``exact_matrix_``) when a circuit of
    positive weight exists.

    >>> plus_scaled(np.array([[-1.0, 2.0], [-3.0, -np.inf]]), None).tolist()
    [[-1.0, 2.0], [-3.0, -1.0]]
    """
    n = S.shape[0]
    D = S.copy()
    # pred[i, j]: the node just before i on the best path found from j to i.
    pred = np.tile(np.arange(n), (n, 1))
    for k in range(n):
        # D[k, k] is the best circuit through k with intermediate nodes < k. If
        # every elementary circuit had weight <= 0, all these are <= 0; an
        # elementary positive circuit is caught at its largest node.
        if D[k, k] > 0:
            raise_positive_circuit(pred, k, exact_matrix_, labels)
        candidate = D[:, k, None] + D[None, k, :]
        better = np.asarray(candidate > D, dtype=bool)
        D = np.where(better, candidate, D)
        pred = np.where(better, pred[:, k, None], pred)
    return D


def raise_positive_circuit(pred: np.ndarray, k: int, M: np.ndarray,
                           labels: Sequence[int] | None) -> None:
    """Raise PositiveCircuitError for the circuit through ``k`` found by Floyd–Warshall.

    Walks the predecessor pointers back from k; should they not close a
    positive circuit, an exact cycle-ratio search finds one instead.
    """
    nodes = [k]
    v = int(pred[k, k])
    while v != k and len(nodes) <= len(M):
        nodes.append(v)
        v = int(pred[v, k])
    circuit = nodes[::-1]  # reversed backward walk: the arcs in forward order
    weight = _circuit_weight(M, circuit)
    if v != k or len(set(circuit)) != len(circuit) or is_eps(weight) or weight <= 0:
        # Never seen to happen, but the pointer walk is only as good as its
        # invariant: fall back on an exact, certified search.
        circuit, weight = _positive_circuit_by_cycle_ratio(M)
    start = circuit.index(min(circuit))  # canonical rotation: smallest node first
    circuit = circuit[start:] + circuit[:start]
    if labels is not None:
        circuit = [int(labels[v]) for v in circuit]
    raise PositiveCircuitError(circuit, weight)


def _circuit_weight(M: np.ndarray, circuit: Sequence[int]) -> Scalar:
    total: Scalar = Fraction(0)
    for a, b in zip(circuit, [*circuit[1:], circuit[0]]):
        w = M[b, a]  # arc a -> b is the entry M[b][a]
        if is_eps(w):
            return EPS
        total = total + w
    return total


def _positive_circuit_by_cycle_ratio(M: np.ndarray) -> tuple[list[int], Scalar]:
    from .cycle_ratio import max_cycle_ratio

    rows, cols = np.nonzero(adjacency(M))
    weights = np.empty(len(rows), dtype=object)
    weights[:] = [M[i, j] for i, j in zip(rows.tolist(), cols.tolist())]
    result = max_cycle_ratio(cols, rows, weights, n_nodes=len(M))
    circuit = result.circuit_nodes
    return circuit, _circuit_weight(M, circuit)


def plus(A: Any) -> np.ndarray:
    """Weak transitive closure ``A+ = A ⊕ A² ⊕ A³ ⊕ ... = A ⊗ A*``.

    ``A+[i][j]`` is the best weight of a path of at least one arc from ``j`` to
    ``i`` (ε when there is none); ``A+[i][i]`` is the best circuit through i.

    Parameters
    ----------
    A : square matrix (nested lists or 2-D array)

    Returns
    -------
    numpy.ndarray of dtype object
        Entries Fraction or EPS.

    Raises
    ------
    MaxPlusValueError
        A bad entry (named) or a non-square matrix.
    PositiveCircuitError
        A circuit of positive weight (then the series diverges); the error
        names one such circuit and its weight.

    See Also
    --------
    star : ``A* = E ⊕ A+``.
    solve : least solution of ``x = A x ⊕ b``.
    maxplus.dense.power : one term ``A^k`` of the series.

    Notes
    -----
    Floyd–Warshall [2]_ on scaled integers, O(n³), vectorized per pivot; the
    series converges iff no circuit has positive weight [1]_.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, §3.2.3.
    .. [2] R. W. Floyd, "Algorithm 97: Shortest path", Communications of the
       ACM 5(6), 345, 1962.

    Examples
    --------
    >>> plus([[-1, 2], [-3, None]]).tolist()
    [[Fraction(-1, 1), Fraction(2, 1)], [Fraction(-3, 1), Fraction(-1, 1)]]
    """
    M = square_matrix(A)
    S, scale = scaled(M, growth=len(M) + 1)
    return as_exact(plus_scaled(S, M), scale)


def star(A: Any) -> np.ndarray:
    """Kleene star ``A* = E ⊕ A ⊕ A² ⊕ ...``; the input is not modified.

    ``A*[i][j]`` is the best weight of a path from ``j`` to ``i`` (0 on the
    diagonal at least: the empty path).

    Parameters
    ----------
    A : square matrix (nested lists or 2-D array)

    Returns
    -------
    numpy.ndarray of dtype object
        Entries Fraction or EPS.

    Raises
    ------
    MaxPlusValueError
        A bad entry (named) or a non-square matrix.
    PositiveCircuitError
        A circuit of positive weight; the error names it (``.circuit`` as nodes
        in order, ``.weight``).

    See Also
    --------
    plus : ``A+ = A ⊗ A*``.
    solve : ``A* ⊗ b`` without forming all of ``A*``.

    Notes
    -----
    Floyd–Warshall [2]_, O(n³); ``A*`` exists iff no circuit has positive
    weight [1]_.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, §3.2.3 and Thm 3.17.
    .. [2] R. W. Floyd, "Algorithm 97: Shortest path", Communications of the
       ACM 5(6), 345, 1962.

    Examples
    --------
    >>> star([[None, 2, 3], [-2, -10, -1], [-5, -2, 0]]).tolist()[0]
    [Fraction(0, 1), Fraction(2, 1), Fraction(3, 1)]
    >>> star([[0, 1], [0, None]])
    Traceback (most recent call last):
    ...
    maxplus.errors.PositiveCircuitError: the star diverges: circuit 0 -> 1 -> 0 has positive weight 1
    """  # noqa: E501
    M = square_matrix(A)
    S, scale = scaled(M, growth=len(M) + 1)
    P = plus_scaled(S, M)
    return as_exact(np.maximum(P, identity_scaled(len(M), P.dtype)), scale)


def solve(A: Any, b: Any) -> np.ndarray:
    """Least solution of ``x = A ⊗ x ⊕ b`` (``= A* ⊗ b``).

    Only the nodes downstream of the support of ``b`` matter: the solution is ε
    elsewhere, so a positive circuit that ``b`` cannot reach is harmless.

    Parameters
    ----------
    A : square matrix (nested lists or 2-D array)
    b : vector or matrix
        Right-hand side (a matrix solves one system per column).

    Returns
    -------
    numpy.ndarray of dtype object
        Same shape as ``b``.

    Raises
    ------
    MaxPlusValueError
        A bad entry (named) or mismatched sizes.
    PositiveCircuitError
        A positive circuit reachable from the support of ``b`` (no finite
        solution then exists).

    See Also
    --------
    star : the closure ``A*`` itself.
    maxplus.dense.left_residual : greatest X with ``A ⊗ X <= B``.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, Thm 3.17 (``A* b`` is the least solution).

    Examples
    --------
    >>> solve([[None, 2, 3], [-2, -10, -1], [-5, -2, 0]], [1, 2, 3]).tolist()
    [Fraction(6, 1), Fraction(4, 1), Fraction(3, 1)]
    >>> solve([[1, None], [None, None]], [None, 0]).tolist()
    [-inf, Fraction(0, 1)]
    """
    M = square_matrix(A)
    rhs, rank = operand(b, "b")
    if rank == 0:
        raise MaxPlusValueError("expected a vector or a matrix", "b")
    columns = rhs.reshape(-1, 1) if rank == 1 else rhs
    n = len(M)
    if columns.shape[0] != n:
        raise MaxPlusValueError(f"expected {n} rows to match A, got {columns.shape[0]}", "b")
    support = np.any(np.asarray(columns != EPS, dtype=bool), axis=1, keepdims=False)
    nodes = np.flatnonzero(downstream(adjacency(M), support))
    out = np.full(columns.shape, EPS, dtype=object)
    if len(nodes):
        sub = M[np.ix_(nodes, nodes)]
        (S, B), scale = scale_together([sub, columns[nodes]], growth=len(nodes) + 2)
        P = plus_scaled(S, sub, labels=nodes.tolist())
        closure = np.maximum(P, identity_scaled(len(nodes), P.dtype))
        out[nodes] = as_exact(product_scaled(closure, B), scale)
    return out[:, 0] if rank == 1 else out
