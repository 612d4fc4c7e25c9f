"""Dense (max,+) matrix algebra: sums, products, powers, closures, residuals.

Convention (the whole package): ``x(k+1) = A ⊗ x(k)``, i.e.
``x_i(k+1) = max_j (A[i][j] + x_j(k))``, so ``A[i][j]`` is the weight of the
arc ``j -> i`` and ε = -inf. ``(A ⊗ B)[i][k] = max_j (A[i][j] + B[j][k])`` is
then the best weight of a path ``k -> j -> i``; ``A^k[i][j]`` the best weight of
a path of ``k`` arcs from ``j`` to ``i``, and ``A*[i][j]`` the best weight of any
path from ``j`` to ``i`` (Baccelli, Cohen, Olsder, Quadrat, *Synchronization
and Linearity*, 1992, §2.3 and §3.2; "BCOQ" below).

Every function accepts nested lists or arrays (validated by
:func:`maxplus.scalar.exact_matrix` / :func:`~maxplus.scalar.exact_vector`, so
a bad entry raises :class:`~maxplus.errors.MaxPlusValueError` naming it) and
returns exact values: object ndarrays of ``Fraction`` / ``EPS`` (and ``TOP`` =
+inf for residuals only), scalars as ``Fraction`` / ``EPS``. Inside, the work
is done on scaled integers (float64 when exact, Python ints otherwise), see
:func:`maxplus.scalar.to_scaled`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from fractions import Fraction
from typing import Any

import numpy as np

from .errors import MaxPlusValueError, PositiveCircuitError
from .scalar import (
    EPS,
    Scalar,
    common_denominator,
    exact,
    exact_matrix,
    exact_vector,
    from_scaled,
    is_eps,
    to_scaled,
)

__all__ = [
    "identity",
    "left_residual",
    "oplus",
    "otimes",
    "plus",
    "power",
    "right_residual",
    "solve",
    "star",
]


# --------------------------------------------------------------------------- operands


def _rank(value: Any) -> int:
    """0 for a scalar, 1 for a vector, 2 for a matrix, without building an array
    (``np.asarray`` of a ragged list would fail before we can name the row)."""
    if isinstance(value, np.ndarray):
        return value.ndim
    if isinstance(value, (list, tuple)):
        return 2 if any(isinstance(e, (list, tuple, np.ndarray)) for e in value) else 1
    return 0


def _operand(value: Any, name: str, square: bool = False) -> tuple[Any, int]:
    """Validate a scalar, vector or matrix; return (exact value, rank)."""
    rank = _rank(value)
    if rank == 0:
        item = value.item() if isinstance(value, np.ndarray) else value
        return exact(item, name), 0
    if rank == 1:
        entries = exact_vector(value, name)
        if not entries:
            raise MaxPlusValueError("the vector is empty", name)
        vec = np.empty(len(entries), dtype=object)
        vec[:] = entries
        return vec, 1
    if rank == 2:
        return exact_matrix(value, name, square=square), 2
    raise MaxPlusValueError(f"expected a scalar, vector or matrix, got {rank} dimensions", name)


def _square(value: Any, name: str = "A") -> np.ndarray:
    """A validated square matrix (a fresh object array: the input is never touched)."""
    if _rank(value) != 2:
        raise MaxPlusValueError("expected a square matrix (list of rows)", name)
    return exact_matrix(value, name, square=True)


def _object_ints(array: np.ndarray) -> np.ndarray:
    """Scaled float64 array -> object array of Python ints (and -inf)."""
    if array.dtype == object:
        return array
    out = np.empty(array.shape, dtype=object)
    flat = out.reshape(-1)
    for k, v in enumerate(array.ravel().tolist()):
        flat[k] = v if math.isinf(v) else int(v)
    return out


def _scale_together(arrays: Sequence[np.ndarray], growth: int = 2) -> tuple[list[np.ndarray], int]:
    """Scale exact object arrays by one common denominator, in one dtype.

    float64 is used only when every array qualifies (see
    :func:`maxplus.scalar.to_scaled`); mixing float64 with Python ints would
    silently round, so one object array turns them all into object arrays.
    """
    scale = common_denominator(v for a in arrays for v in a.ravel().tolist())
    scaled = [to_scaled(a, scale, growth)[0] for a in arrays]
    if any(s.dtype == object for s in scaled):
        scaled = [_object_ints(s) for s in scaled]
    return scaled, scale


def _identity_scaled(n: int, dtype: Any = float) -> np.ndarray:
    """The (max,+) identity E on scaled integers (0 on the diagonal, -inf elsewhere)."""
    out = np.full((n, n), -np.inf, dtype=dtype)
    zero = 0 if np.dtype(dtype) == object else 0.0  # a Python int keeps object sums exact
    for i in range(n):
        out[i, i] = zero
    return out


def _product_scaled(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """``X ⊗ Y`` of two scaled 2-D arrays of one dtype.

    The loop runs over the inner dimension so memory stays O(rows × cols)
    (the broadcast ``X[:, :, None] + Y[None]`` would need rows × inner × cols).
    """
    out = np.full((X.shape[0], Y.shape[1]), -np.inf, dtype=X.dtype)
    for j in range(X.shape[1]):
        np.maximum(out, X[:, j, None] + Y[None, j, :], out=out)
    return out


# --------------------------------------------------------------------------- basic operations


def identity(n: int) -> np.ndarray:
    """The (max,+) identity matrix E: 0 on the diagonal, ε elsewhere.

    Parameters
    ----------
    n : int
        Size, at least 1.

    Returns
    -------
    numpy.ndarray of dtype object

    Raises
    ------
    MaxPlusValueError
        ``n`` is not a positive integer.

    Examples
    --------
    >>> identity(2).tolist()
    [[Fraction(0, 1), -inf], [-inf, Fraction(0, 1)]]
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise MaxPlusValueError(f"expected a positive integer size, got {n!r}", "n")
    return from_scaled(_identity_scaled(int(n)), 1)


def oplus(A: Any, B: Any) -> Any:
    """(max,+) sum ``A ⊕ B``: the entrywise maximum of two operands of one shape.

    Parameters
    ----------
    A, B : scalar, vector or matrix (nested lists or arrays)
        Same shape.

    Returns
    -------
    Fraction, EPS, or numpy.ndarray of dtype object

    Raises
    ------
    MaxPlusValueError
        A bad entry (named), or shapes that differ.

    Notes
    -----
    BCOQ 1992, §3.2 (the semiring R_max and its matrices).

    Examples
    --------
    >>> oplus([[1, None], [0, 2]], [[0, 3], [None, "5/2"]]).tolist()
    [[Fraction(1, 1), Fraction(3, 1)], [Fraction(0, 1), Fraction(5, 2)]]
    >>> oplus(3, None)
    Fraction(3, 1)
    """
    a, rank_a = _operand(A, "A")
    b, rank_b = _operand(B, "B")
    if rank_a == 0 and rank_b == 0:
        return max(a, b)
    if rank_a != rank_b or a.shape != b.shape:
        raise MaxPlusValueError(
            f"cannot add operands of shapes {np.shape(a)} and {np.shape(b)}", "B"
        )
    out = np.empty(a.shape, dtype=object)
    out.reshape(-1)[:] = [max(x, y) for x, y in zip(a.ravel().tolist(), b.ravel().tolist())]
    return out


def otimes(A: Any, B: Any) -> Any:
    """(max,+) product ``A ⊗ B``.

    Matrix-matrix ``(A ⊗ B)[i][k] = max_j (A[i][j] + B[j][k])``; a vector on the
    right is a column (``A ⊗ x`` is one step of ``x(k+1) = A ⊗ x(k)``), a vector
    on the left a row; vector ⊗ vector is the scalar ``max_i (x_i + y_i)``; a
    scalar on either side adds itself to every entry.

    Parameters
    ----------
    A, B : scalar, vector or matrix (nested lists or arrays)
        Conformable operands; matrices need not be square.

    Returns
    -------
    Fraction, EPS, or numpy.ndarray of dtype object

    Raises
    ------
    MaxPlusValueError
        A bad entry (named), or inner dimensions that differ.

    Notes
    -----
    BCOQ 1992, §3.2 (matrix product, path interpretation).

    Examples
    --------
    >>> A = [[3, 7], [2, 4]]
    >>> otimes(A, [0, 0]).tolist()
    [Fraction(7, 1), Fraction(4, 1)]
    >>> otimes(A, A).tolist()
    [[Fraction(9, 1), Fraction(11, 1)], [Fraction(6, 1), Fraction(9, 1)]]
    >>> otimes("1/2", [[1, None]]).tolist()
    [[Fraction(3, 2), -inf]]
    """
    a, rank_a = _operand(A, "A")
    b, rank_b = _operand(B, "B")
    if rank_a == 0 or rank_b == 0:
        scalar, other = (a, b) if rank_a == 0 else (b, a)
        if rank_a == 0 and rank_b == 0:
            return scalar + other
        out = np.empty(other.shape, dtype=object)
        out.reshape(-1)[:] = [scalar + v for v in other.ravel().tolist()]
        return out
    left = a if rank_a == 2 else a.reshape(1, -1)
    right = b if rank_b == 2 else b.reshape(-1, 1)
    if left.shape[1] != right.shape[0]:
        raise MaxPlusValueError(
            f"cannot multiply {'x'.join(map(str, a.shape))} by "
            f"{'x'.join(map(str, b.shape))}: inner dimensions differ", "B"
        )
    (ls, rs), scale = _scale_together([left, right], growth=2)
    result = from_scaled(_product_scaled(ls, rs), scale)
    if rank_a == 1 and rank_b == 1:
        return result[0, 0]
    if rank_b == 1:
        return result[:, 0]
    if rank_a == 1:
        return result[0, :]
    return result


def power(A: Any, k: int) -> np.ndarray:
    """The k-th (max,+) power ``A^k = A ⊗ ... ⊗ A``; ``A^0 = E``.

    ``A^k[i][j]`` is the best weight of a path of exactly ``k`` arcs from ``j``
    to ``i``. Computed by repeated squaring (O(n³ log k)).

    Parameters
    ----------
    A : square matrix
    k : int
        Non-negative exponent.

    Returns
    -------
    numpy.ndarray of dtype object

    Raises
    ------
    MaxPlusValueError
        A bad entry, a non-square matrix, or ``k`` not a non-negative integer.

    Notes
    -----
    BCOQ 1992, §3.2 (path interpretation of powers).

    Examples
    --------
    >>> power([[3, 7], [2, 4]], 3).tolist()
    [[Fraction(13, 1), Fraction(16, 1)], [Fraction(11, 1), Fraction(13, 1)]]
    >>> power([[5]], 0).tolist()
    [[Fraction(0, 1)]]
    """
    M = _square(A)
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 0:
        raise MaxPlusValueError(f"expected a non-negative integer exponent, got {k!r}", "k")
    k = int(k)
    # Entries of A^k are sums of k entries of A: growth k keeps float64 exact.
    base, scale = to_scaled(M, growth=max(k, 1) + 1)
    result = _identity_scaled(len(M), base.dtype)
    while k:
        if k & 1:
            result = _product_scaled(result, base)
        k >>= 1
        if k:
            base = _product_scaled(base, base)
    return from_scaled(result, scale)


# --------------------------------------------------------------------------- closures


def _plus_scaled(S: np.ndarray, exact_matrix_: np.ndarray, labels: Sequence[int] | None = None
                ) -> np.ndarray:
    """``S+ = S ⊕ S² ⊕ ...`` on scaled integers by Floyd–Warshall (a new array).

    Raises PositiveCircuitError (with node indices mapped through ``labels``
    and the weight summed exactly from ``exact_matrix_``) when a circuit of
    positive weight exists.
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
            _raise_positive_circuit(pred, k, exact_matrix_, labels)
        candidate = D[:, k, None] + D[None, k, :]
        better = np.asarray(candidate > D, dtype=bool)
        D = np.where(better, candidate, D)
        pred = np.where(better, pred[:, k, None], pred)
    return D


def _raise_positive_circuit(pred: np.ndarray, k: int, M: np.ndarray,
                            labels: Sequence[int] | None) -> None:
    # Walk the predecessor pointers of the paths from k back to k.
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
        total = total + M[b, a]  # arc a -> b is the entry M[b][a]
    return total


def _positive_circuit_by_cycle_ratio(M: np.ndarray) -> tuple[list[int], Scalar]:
    from .cycle_ratio import max_cycle_ratio

    rows, cols = np.nonzero(np.asarray(M != EPS, dtype=bool))
    weights = np.empty(len(rows), dtype=object)
    weights[:] = [M[i, j] for i, j in zip(rows.tolist(), cols.tolist())]
    result = max_cycle_ratio(cols, rows, weights, n_nodes=len(M))
    circuit = result.circuit_nodes()
    return circuit, _circuit_weight(M, circuit)


def plus(A: Any) -> np.ndarray:
    """Weak transitive closure ``A+ = A ⊕ A² ⊕ A³ ⊕ ... = A ⊗ A*``.

    ``A+[i][j]`` is the best weight of a path of at least one arc from ``j`` to
    ``i`` (ε when there is none); ``A+[i][i]`` is the best circuit through i.

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
    PositiveCircuitError
        A circuit of positive weight (then the series diverges); the error
        names one such circuit and its weight.

    Notes
    -----
    Floyd–Warshall on scaled integers, O(n³), vectorized per pivot. BCOQ 1992,
    §3.2.3 (A* converges iff no circuit has positive weight).

    Examples
    --------
    >>> plus([[-1, 2], [-3, None]]).tolist()
    [[Fraction(-1, 1), Fraction(2, 1)], [Fraction(-3, 1), Fraction(-1, 1)]]
    """
    M = _square(A)
    S, scale = to_scaled(M, growth=len(M) + 1)
    return from_scaled(_plus_scaled(S, M), scale)


def star(A: Any) -> np.ndarray:
    """Kleene star ``A* = E ⊕ A ⊕ A² ⊕ ...``; the input is not modified.

    ``A*[i][j]`` is the best weight of a path from ``j`` to ``i`` (0 on the
    diagonal at least: the empty path).

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
    PositiveCircuitError
        A circuit of positive weight; the error names it (``.circuit`` as nodes
        in order, ``.weight``).

    Notes
    -----
    BCOQ 1992, §3.2.3 and Thm 3.17; Floyd–Warshall (O(n³)).

    Examples
    --------
    >>> star([[None, 2, 3], [-2, -10, -1], [-5, -2, 0]]).tolist()[0]
    [Fraction(0, 1), Fraction(2, 1), Fraction(3, 1)]
    >>> star([[0, 1], [0, None]])
    Traceback (most recent call last):
    ...
    maxplus.errors.PositiveCircuitError: the star diverges: circuit 0 -> 1 -> 0 has positive weight 1
    """
    M = _square(A)
    S, scale = to_scaled(M, growth=len(M) + 1)
    P = _plus_scaled(S, M)
    return from_scaled(np.maximum(P, _identity_scaled(len(M), P.dtype)), scale)


def solve(A: Any, b: Any) -> np.ndarray:
    """Least solution of ``x = A ⊗ x ⊕ b`` (``= A* ⊗ b``).

    Only the nodes downstream of the support of ``b`` matter: the solution is ε
    elsewhere, so a positive circuit that ``b`` cannot reach is harmless.

    Parameters
    ----------
    A : square matrix
    b : vector or matrix
        Right-hand side (a matrix solves one system per column).

    Returns
    -------
    numpy.ndarray of dtype object
        Same shape as ``b``.

    Raises
    ------
    MaxPlusValueError
        A bad entry or mismatched sizes.
    PositiveCircuitError
        A positive circuit reachable from the support of ``b`` (no finite
        solution then exists).

    Notes
    -----
    BCOQ 1992, Thm 3.17 (A* b is the least solution when A* exists).

    Examples
    --------
    >>> solve([[None, 2, 3], [-2, -10, -1], [-5, -2, 0]], [1, 2, 3]).tolist()
    [Fraction(6, 1), Fraction(4, 1), Fraction(3, 1)]
    >>> solve([[1, None], [None, None]], [None, 0]).tolist()
    [-inf, Fraction(0, 1)]
    """
    M = _square(A)
    rhs, rank = _operand(b, "b")
    if rank == 0:
        raise MaxPlusValueError("expected a vector or a matrix", "b")
    columns = rhs.reshape(-1, 1) if rank == 1 else rhs
    n = len(M)
    if columns.shape[0] != n:
        raise MaxPlusValueError(f"expected {n} rows to match A, got {columns.shape[0]}", "b")
    support = np.any(np.asarray(columns != EPS, dtype=bool), axis=1, keepdims=False)
    reach = _downstream(np.asarray(M != EPS, dtype=bool), support)
    nodes = np.flatnonzero(reach)
    out = np.full(columns.shape, EPS, dtype=object)
    if len(nodes):
        sub = M[np.ix_(nodes, nodes)]
        (S, B), scale = _scale_together([sub, columns[nodes]], growth=len(nodes) + 2)
        P = _plus_scaled(S, sub, labels=nodes.tolist())
        closure = np.maximum(P, _identity_scaled(len(nodes), P.dtype))
        out[nodes] = from_scaled(_product_scaled(closure, B), scale)
    return out[:, 0] if rank == 1 else out


def _downstream(adjacency: np.ndarray, start: np.ndarray) -> np.ndarray:
    """Nodes reachable from ``start`` (``adjacency[i, j]``: arc j -> i), start included."""
    reached = start.copy()
    frontier = start.copy()
    while frontier.any():
        new = adjacency[:, frontier].any(axis=1) & ~reached
        reached |= new
        frontier = new
    return reached


# --------------------------------------------------------------------------- residuation


def _left_residual_scaled(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """``(A \\ B)[j][k] = min_i (B[i][k] - A[i][j])`` with ``x - ε = ⊤`` (+inf)."""
    m, p = A.shape[1], B.shape[1]
    out = np.full((m, p), np.inf, dtype=A.dtype)
    with np.errstate(invalid="ignore"):
        for i in range(A.shape[0]):
            row_a = A[i][:, None]
            # ε in A constrains nothing (⊤); ε in B against a finite A forces ε.
            diff = np.where(np.asarray(row_a == -np.inf, dtype=bool), np.inf, B[i][None, :] - row_a)
            np.minimum(out, diff, out=out)
    return out


def left_residual(A: Any, B: Any) -> np.ndarray:
    """Left residual ``A \\ B``: the greatest X with ``A ⊗ X ≤ B``.

    ``(A \\ B)[j][k] = min_i (B[i][k] − A[i][j])`` with the conventions
    ``x − ε = ⊤`` (+inf, ``maxplus.scalar.TOP``; also ``ε − ε = ⊤``) and
    ``ε − a = ε`` for finite a. A column of A that is all ε gives a row of ⊤.

    Parameters
    ----------
    A : matrix (n × m)
    B : matrix (n × p) or vector (n)

    Returns
    -------
    numpy.ndarray of dtype object
        m × p (a vector of length m for a vector B); entries Fraction, EPS or TOP.

    Raises
    ------
    MaxPlusValueError
        A bad entry, or A and B with different numbers of rows.

    Notes
    -----
    BCOQ 1992, §4.4 (residuation of ⊗, in matrix form).

    Examples
    --------
    >>> left_residual([[1, 2], [3, None]], [5, 6]).tolist()
    [Fraction(3, 1), Fraction(3, 1)]
    >>> left_residual([[None]], [[None]]).tolist()
    [[inf]]
    """
    a, rank_a = _operand(A, "A")
    b, rank_b = _operand(B, "B")
    if rank_a != 2 or rank_b == 0:
        raise MaxPlusValueError("expected a matrix A and a matrix or vector B", "A" if rank_a != 2 else "B")
    right = b.reshape(-1, 1) if rank_b == 1 else b
    if a.shape[0] != right.shape[0]:
        raise MaxPlusValueError(
            f"A has {a.shape[0]} rows but B has {right.shape[0]}", "B"
        )
    (sa, sb), scale = _scale_together([a, right], growth=2)
    result = from_scaled(_left_residual_scaled(sa, sb), scale)
    return result[:, 0] if rank_b == 1 else result


def right_residual(B: Any, A: Any) -> np.ndarray:
    """Right residual ``B / A``: the greatest X with ``X ⊗ A ≤ B``.

    ``(B / A)[k][i] = min_j (B[k][j] − A[i][j])``, same ⊤ conventions as
    :func:`left_residual`; ``B / A = (Aᵀ \\ Bᵀ)ᵀ``.

    Parameters
    ----------
    B : matrix (p × m) or vector (m, a row)
    A : matrix (n × m)

    Returns
    -------
    numpy.ndarray of dtype object
        p × n (a vector of length n for a vector B).

    Raises
    ------
    MaxPlusValueError
        A bad entry, or A and B with different numbers of columns.

    Notes
    -----
    BCOQ 1992, §4.4.

    Examples
    --------
    >>> right_residual([[5, 6]], [[1, 2], [3, None]]).tolist()
    [[Fraction(4, 1), Fraction(2, 1)]]
    """
    b, rank_b = _operand(B, "B")
    a, rank_a = _operand(A, "A")
    if rank_a != 2 or rank_b == 0:
        raise MaxPlusValueError("expected a matrix or vector B and a matrix A", "A" if rank_a != 2 else "B")
    left = b.reshape(1, -1) if rank_b == 1 else b
    if a.shape[1] != left.shape[1]:
        raise MaxPlusValueError(
            f"A has {a.shape[1]} columns but B has {left.shape[1]}", "B"
        )
    (sa, sb), scale = _scale_together([a, left], growth=2)
    result = from_scaled(_left_residual_scaled(sa.T.copy(), sb.T.copy()).T, scale)
    return result[0, :] if rank_b == 1 else result
