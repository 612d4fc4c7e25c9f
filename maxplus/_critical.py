"""The critical graph of a (max,+) matrix, its eigenvectors and its cyclicity.

With λ the maximum cycle mean, a node c is critical iff ``(A − λ)^+[c][c] = 0``
and an arc ``j -> i`` is critical iff it lies on a circuit of mean λ; the
critical columns of ``(A − λ)^+`` are eigenvectors, those of distinct classes
of the critical graph span the eigenspace of an irreducible A, and the
cyclicity (lcm over these classes of the gcd of their circuit lengths) is the
eventual period of the powers of A [1]_ [2]_. The public functions are
importable from :mod:`maxplus.spectral` and :mod:`maxplus`.

References
----------
.. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
   and Linearity*, Wiley, 1992, §3.7 and Thm 3.109.
.. [2] P. Butkovič, *Max-linear Systems: Theory and Algorithms*, Springer,
   2010, §4.3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np

from ._closure import plus_scaled
from ._graphs import adjacency, is_strongly_connected, period, strong_classes
from ._integer_matrix import from_exact
from ._max_mean import max_cycle_mean
from ._scaled import as_exact, scaled, square_matrix, times
from .errors import ReducibleMatrixError

__all__ = [
    "CriticalGraph",
    "critical_closure",
    "critical_graph",
    "cyclicity",
    "cyclicity_of",
    "eigenspace",
    "eigenvector",
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

    See Also
    --------
    critical_graph : computes it.
    cyclicity : the cyclicity, from the critical classes.

    Examples
    --------
    >>> g = critical_graph([[1, 5], [3, 2]])
    >>> g.eigenvalue, g.nodes, g.arcs, g.components
    (Fraction(4, 1), [0, 1], [(0, 1), (1, 0)], [[0, 1]])
    """

    eigenvalue: Fraction | None
    nodes: list[int]
    arcs: list[tuple[int, int]]
    components: list[list[int]]


def critical_closure(M: np.ndarray) -> tuple[CriticalGraph, np.ndarray | None, int]:
    """Critical graph of the exact matrix M, with ``(A − λ)^+`` scaled and its scale.

    The closure is None (and the scale 1) when M has no circuit.

    >>> g, P, scale = critical_closure(np.array([[Fraction(1)]], dtype=object))
    >>> g.nodes, P.tolist(), scale
    ([0], [[0.0]], 1)
    """
    lam = max_cycle_mean(from_exact(M))
    if lam is None:
        return CriticalGraph(None, [], [], []), None, 1
    shifted = np.empty(M.shape, dtype=object)
    shifted.reshape(-1)[:] = [times(v, -lam) for v in M.ravel().tolist()]
    # No circuit of A − λ is positive, so its closure exists.
    N, scale = scaled(shifted, growth=len(M) + 2)
    P = plus_scaled(N, shifted)
    nodes = np.flatnonzero(np.asarray(np.diagonal(P) == 0, dtype=bool)).tolist()
    # Arc j -> i lies on a circuit of mean λ iff its weight in A − λ plus the
    # best return path i -> j (P[j, i]) is 0, the largest possible value.
    on_zero_circuit = np.asarray(N + P.T == 0, dtype=bool) & adjacency(M)
    heads, tails = np.nonzero(on_zero_circuit)
    arcs = sorted(zip(tails.tolist(), heads.tolist()))
    _, labels = strong_classes(on_zero_circuit)
    groups: dict[int, list[int]] = {}
    for v in nodes:
        groups.setdefault(int(labels[v]), []).append(v)
    components = sorted(groups.values(), key=lambda c: c[0])
    return CriticalGraph(lam, nodes, arcs, components), P, scale


def critical_graph(A: Any) -> CriticalGraph:
    """Critical graph of A: nodes and arcs of the circuits of maximum mean.

    Parameters
    ----------
    A : square matrix (nested lists or 2-D array)

    Returns
    -------
    CriticalGraph
        ``.eigenvalue``, ``.nodes``, ``.arcs`` (``(j, i)`` = arc ``j -> i``),
        ``.components`` (its strongly connected classes).

    Raises
    ------
    MaxPlusValueError
        A bad entry (named) or a non-square matrix.

    See Also
    --------
    eigenvector : a critical column of ``(A − λ)^+``.
    cyclicity : the period read off the critical graph.
    maxplus.spectral.eigenvalue : λ alone.

    Notes
    -----
    A node c is critical iff ``(A − λ)^+[c][c] = 0`` [1]_.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, §3.7 (critical graph).

    Examples
    --------
    >>> g = critical_graph([[1, 0], [0, 1]])
    >>> g.eigenvalue, g.nodes, g.arcs, g.components
    (Fraction(1, 1), [0, 1], [(0, 0), (1, 1)], [[0], [1]])
    """
    return critical_closure(square_matrix(A))[0]


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
    A : square matrix (nested lists or 2-D array)

    Returns
    -------
    numpy.ndarray of dtype object

    Raises
    ------
    MaxPlusValueError
        A bad entry (named) or a non-square matrix.
    ReducibleMatrixError
        A has no circuit (no finite eigenvalue).

    See Also
    --------
    eigenspace : every eigenvector of an irreducible A.
    critical_graph : where the critical node comes from.
    maxplus.spectral.eigenvalue : λ.

    Notes
    -----
    Critical columns of ``(A − λ)^+`` are eigenvectors, for any A with a
    circuit [1]_ [2]_.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, §3.7.
    .. [2] P. Butkovič, *Max-linear Systems: Theory and Algorithms*, Springer,
       2010, §4.3.

    Examples
    --------
    >>> eigenvector([[3, 7], [2, 4]]).tolist()
    [Fraction(0, 1), Fraction(-5, 2)]
    """
    graph, P, scale = critical_closure(square_matrix(A))
    _require_circuit(graph)
    assert P is not None
    return as_exact(P[:, graph.nodes[0]], scale)


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
        A bad entry (named) or a non-square matrix.
    ReducibleMatrixError
        A is reducible (its spectrum may hold other eigenvalues; use
        :func:`eigenvector`).

    See Also
    --------
    eigenvector : one eigenvector, also for reducible A.
    critical_graph : the classes behind the basis.

    Notes
    -----
    Critical columns from distinct classes are independent, those of one
    class proportional [1]_ [2]_.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, §3.7.
    .. [2] P. Butkovič, *Max-linear Systems: Theory and Algorithms*, Springer,
       2010, §4.3.

    Examples
    --------
    >>> eigenspace([[1, 0], [0, 1]]).tolist()
    [[Fraction(0, 1), Fraction(-1, 1)], [Fraction(-1, 1), Fraction(0, 1)]]
    """
    M = square_matrix(A)
    adj = adjacency(M)
    if not is_strongly_connected(adj):
        n_comp, _ = strong_classes(adj)
        raise ReducibleMatrixError(
            f"A is reducible ({n_comp} strongly connected classes, or no circuit): "
            "its eigenspace is not spanned by one eigenvalue's critical columns"
        )
    graph, P, scale = critical_closure(M)
    assert P is not None
    columns = [comp[0] for comp in graph.components]
    return as_exact(P[:, columns], scale)


def cyclicity(A: Any) -> int:
    """Cyclicity of the critical graph: lcm over its classes of the gcd of their
    circuit lengths (1 when A has no circuit).

    For irreducible A it is the period c of ``A^(k+c) = λ^c ⊗ A^k`` (large k).

    Parameters
    ----------
    A : square matrix (nested lists or 2-D array)

    Returns
    -------
    int

    Raises
    ------
    MaxPlusValueError
        A bad entry (named) or a non-square matrix.

    See Also
    --------
    critical_graph : the graph whose cyclicity this is.
    maxplus.transient.transient : when the periodic regime starts.

    Notes
    -----
    Cyclicity theorem [1]_; the gcd of one class by BFS levels [2]_, O(n + m).

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, §3.7 and Thm 3.109.
    .. [2] E. V. Denardo, "Periods of connected networks and powers of
       nonnegative matrices", Mathematics of Operations Research 2(1), 1977.

    Examples
    --------
    >>> cyclicity([[3, 7], [2, 4]]), cyclicity([[None, None, 3], [1, None, None], [None, 2, None]])
    (2, 3)
    """
    return cyclicity_of(critical_closure(square_matrix(A))[0])


def cyclicity_of(graph: CriticalGraph) -> int:
    """lcm over the classes of a critical graph of the gcd of their circuit lengths.

    >>> cyclicity_of(CriticalGraph(Fraction(1), [0, 1], [(0, 1), (1, 0)], [[0, 1]]))
    2
    """
    c = 1
    for comp in graph.components:
        members = set(comp)
        arcs = [(j, i) for j, i in graph.arcs if j in members]
        c = math.lcm(c, period(comp, arcs))
    return c
