"""Maximum cycle mean of a dense integer matrix, certified; cycle times by classes.

Howard's policy iteration (:mod:`maxplus._dense_howard`) runs on the whole
matrix when every node has an in-arc. When its optimal policy has one mean λ
on every node (always for an irreducible matrix), the final potentials prove
λ (:mod:`maxplus._mean_certificate`, checked before λ is returned).
Otherwise the matrix is split into strongly connected classes and each class
is solved on its own: its maximum cycle mean is the eigenvalue of the class,
and the cycle time of a node is the largest one among the classes upstream
of it [1]_.

References
----------
.. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
   and Linearity*, Wiley, 1992, Thm 3.23 and Thm 3.112.
"""

from __future__ import annotations

from fractions import Fraction
from typing import NamedTuple

import numpy as np

from . import _kernels
from ._arrays import INT64_SAFE
from ._dense_howard import Ratio, optimal_policy, policy_walk
from ._graphs import strong_classes
from ._integer_matrix import IntegerMatrix, integer_matrix, rows_of
from ._mean_certificate import check_mean_certificate, check_mean_certificate_lists
from .errors import MaxPlusError

__all__ = [
    "ClassMeans",
    "class_means",
    "cycle_times",
    "max_cycle_mean",
    "max_cycle_mean_rows",
]

def _single_mean(values: np.ndarray | None, finite: np.ndarray | None,
                 rows: list[list[int | None]] | None) -> Ratio | None:
    """The certified mean when the optimal policy has one mean on every node, else None.

    Give ``rows`` (lists) for a small matrix, ``values`` and ``finite`` otherwise.
    """
    state = optimal_policy(values, finite, rows)
    if len(set(state.ratio)) > 1:
        return None
    p, q = state.ratio[0]
    walk = policy_walk(state.policy, 0)
    if rows is not None:
        check_mean_certificate_lists(rows, p, q, state.potential, walk)
    else:
        assert values is not None and finite is not None
        x = np.empty(len(state.potential), dtype=object)
        x[:] = state.potential
        if values.dtype != object and max(map(abs, state.potential)) < INT64_SAFE:
            x = x.astype(np.int64)
        check_mean_certificate(values, finite, p, q, x, walk)
    return p, q


def _solve(values: np.ndarray, finite: np.ndarray) -> Ratio | None:
    if len(finite) <= _kernels.current().dense_lists_max_nodes:
        return _single_mean(None, None, rows_of(IntegerMatrix(values, finite, 1)))
    return _single_mean(values, finite, None)


class ClassMeans(NamedTuple):
    """Strongly connected classes and the maximum cycle mean of each (scaled)."""

    labels: np.ndarray  # class of every node
    means: list[Ratio | None]  # per class; None for a class without circuit


def class_means(matrix: IntegerMatrix) -> ClassMeans:
    """The maximum cycle mean of every strongly connected class, each certified.

    Examples
    --------
    >>> from maxplus._integer_matrix import integer_matrix
    >>> cm = class_means(integer_matrix([[3, None], [2, 4]]))
    >>> cm.labels.tolist() == [0, 1] or cm.labels.tolist() == [1, 0], sorted(cm.means)
    (True, [(3, 1), (4, 1)])
    """
    values, finite = matrix.values, matrix.finite
    n_classes, labels = strong_classes(finite)
    means: list[Ratio | None] = []
    for c in range(n_classes):
        nodes = np.flatnonzero(labels == c)
        if len(nodes) == 1 and not finite[nodes[0], nodes[0]]:
            means.append(None)
            continue
        sub = np.ix_(nodes, nodes)
        mean = _solve(values[sub], finite[sub])
        if mean is None:  # an irreducible matrix has one mean everywhere
            raise MaxPlusError("a strongly connected class has two cycle means (a defect)")
        means.append(mean)
    return ClassMeans(labels, means)


def max_cycle_mean(matrix: IntegerMatrix) -> Fraction | None:
    """Maximum cycle mean of the matrix (None without circuit), certified exactly.

    Parameters
    ----------
    matrix : IntegerMatrix

    Returns
    -------
    Fraction or None

    Raises
    ------
    CertificateError
        The potentials do not prove the mean (a defect of the solver).

    Examples
    --------
    >>> from maxplus._integer_matrix import integer_matrix
    >>> max_cycle_mean(integer_matrix([[1, 5], [3, 2]]))  # circuit 0 -> 1 -> 0: (5+3)/2
    Fraction(4, 1)
    """
    values, finite = matrix.values, matrix.finite
    if finite.any(axis=1).all():  # every node has an in-arc: Howard on the whole matrix
        mean = _solve(values, finite)
        if mean is not None:
            return Fraction(mean[0], mean[1] * matrix.scale)
    return _best_class_mean(matrix)


def max_cycle_mean_rows(rows: list[list[int | None]]) -> Fraction | None:
    """:func:`max_cycle_mean` of a small matrix given as lists of ints and None.

    Examples
    --------
    >>> max_cycle_mean_rows([[1, 5], [3, 2]])
    Fraction(4, 1)
    """
    n = len(rows)
    if n <= 2:  # every elementary circuit, enumerated: the maximum of their means
        means = [Fraction(w) for i in range(n) if (w := rows[i][i]) is not None]
        if n == 2 and rows[0][1] is not None and rows[1][0] is not None:
            means.append(Fraction(rows[0][1] + rows[1][0], 2))
        return max(means, default=None)
    if all(row.count(None) < n for row in rows):  # every node has an in-arc
        mean = _single_mean(None, None, rows)
        if mean is not None:
            return Fraction(mean[0], mean[1])
    return _best_class_mean(integer_matrix(rows))


def _best_class_mean(matrix: IntegerMatrix) -> Fraction | None:
    best = max((Fraction(*m) for m in class_means(matrix).means if m is not None), default=None)
    return None if best is None else best / matrix.scale


def cycle_times(matrix: IntegerMatrix) -> list[Fraction | None]:
    """Cycle time ``χ_i`` of every node: the largest maximum cycle mean among the
    strongly connected classes from which i can be reached (None without any) [2]_.

    Each class mean is certified; the maximum is then passed down the acyclic
    graph of the classes in topological order.

    Examples
    --------
    >>> from maxplus._integer_matrix import integer_matrix
    >>> cycle_times(integer_matrix([[3, None, None], [2, 4, None], [None, 0, None]]))
    [Fraction(3, 1), Fraction(4, 1), Fraction(4, 1)]
    """
    labels, means = class_means(matrix)
    best = [None if m is None else Fraction(m[0], m[1] * matrix.scale) for m in means]
    if len(means) > 1:
        rows, cols = np.nonzero(matrix.finite)
        tail, head = labels[cols], labels[rows]  # class arcs tail -> head
        across = tail != head
        pairs = np.unique(np.stack([tail[across], head[across]], axis=1), axis=0).tolist()
        successors: list[list[int]] = [[] for _ in means]
        waiting = [0] * len(means)
        for a, b in pairs:
            successors[a].append(b)
            waiting[b] += 1
        ready = [c for c in range(len(means)) if waiting[c] == 0]
        while ready:  # Kahn's topological order of the classes
            c = ready.pop()
            for d in successors[c]:
                here, there = best[c], best[d]
                if here is not None and (there is None or here > there):
                    best[d] = here
                waiting[d] -= 1
                if waiting[d] == 0:
                    ready.append(d)
    return [best[c] for c in labels.tolist()]
