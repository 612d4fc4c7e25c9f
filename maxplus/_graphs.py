"""Boolean graph helpers shared by the dense (max,+) modules.

A graph is a square boolean array ``adj`` with ``adj[i, j]`` true when there
is an arc ``j -> i`` (the convention of the whole package: the entry
``A[i][j]`` is the arc ``j -> i``). Nothing here knows about weights.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np
import numpy.typing as npt
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from .scalar import EPS

__all__ = [
    "adjacency",
    "bool_product",
    "cyclic_nodes",
    "downstream",
    "is_strongly_connected",
    "period",
    "reach_closure",
    "strong_classes",
]


def adjacency(M: np.ndarray) -> np.ndarray:
    """Boolean ``adj[i, j]``: the exact matrix ``M`` has an arc j -> i (a finite entry).

    >>> adjacency(np.array([[1, EPS]], dtype=object)).tolist()
    [[True, False]]
    """
    return np.asarray(M != EPS, dtype=bool)


def strong_classes(adj: np.ndarray) -> tuple[int, np.ndarray]:
    """Number of strongly connected classes and the class label of every node.

    >>> strong_classes(np.array([[False, True], [True, False]]))[0]
    1
    """
    rows, cols = np.nonzero(adj)
    n = len(adj)
    graph = sp.csr_matrix((np.ones(len(rows), dtype=np.int8), (cols, rows)), shape=(n, n))
    # scipy has no inline types (pyproject.toml: [tool.mypy]): its result is Any to mypy.
    classes: tuple[int, np.ndarray] = connected_components(graph, directed=True,
                                                           connection="strong")
    return classes


def cyclic_nodes(adj: np.ndarray) -> np.ndarray:
    """Mask of the nodes lying on some circuit.

    >>> cyclic_nodes(np.array([[True, False], [True, False]])).tolist()
    [True, False]
    """
    n_comp, labels = strong_classes(adj)
    sizes = np.bincount(labels, minlength=n_comp)
    cyclic: npt.NDArray[np.bool_] = (sizes[labels] > 1) | np.diag(adj)
    return cyclic


def is_strongly_connected(adj: np.ndarray) -> bool:
    """True for one strongly connected class with a circuit (``[[ε]]`` has none).

    >>> is_strongly_connected(np.array([[False]])), is_strongly_connected(np.array([[True]]))
    (False, True)
    """
    n_comp, _ = strong_classes(adj)
    return n_comp == 1 and (len(adj) > 1 or bool(adj[0, 0]))


def period(nodes: list[int], arcs: list[tuple[int, int]]) -> int:
    """gcd of the circuit lengths of a strongly connected graph, by BFS levels.

    Every circuit length is a sum of ``level[u] + 1 − level[v]`` over its arcs
    ``(u, v)`` (meaning ``u -> v``), and conversely these differences generate
    the same group (Denardo 1977).

    >>> period([0, 1, 2], [(0, 1), (1, 2), (2, 0)])
    3
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


def bool_product(X: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """Boolean matrix product (a path through some middle node).

    >>> bool_product(np.array([[True, False]]), np.array([[False], [True]])).tolist()
    [[False]]
    """
    # float32 counts are exact below 2**24 paths per entry (n < 2**24).
    return (X.astype(np.float32) @ Y.astype(np.float32)) > 0


def reach_closure(adj: np.ndarray) -> np.ndarray:
    """``R[i, j]``: a path (possibly empty) from j to i.

    >>> reach_closure(np.array([[False, False], [True, False]])).tolist()
    [[True, False], [True, True]]
    """
    R = adj | np.eye(len(adj), dtype=bool)
    while True:
        nxt = R | bool_product(R, R)
        if np.array_equal(nxt, R):
            return R
        R = nxt


def downstream(adj: np.ndarray, start: np.ndarray) -> np.ndarray:
    """Nodes reachable from the mask ``start`` (start included).

    >>> downstream(np.array([[False, False], [True, False]]), np.array([True, False])).tolist()
    [True, True]
    """
    reached = start.copy()
    frontier = start.copy()
    while frontier.any():
        new = adj[:, frontier].any(axis=1) & ~reached
        reached |= new
        frontier = new
    return reached
