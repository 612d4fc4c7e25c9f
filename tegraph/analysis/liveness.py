"""Liveness of a timed event graph by the token-free-circuit criterion.

A marked graph is live if and only if every circuit carries at least one
token (Commoner, Holt, Even and Pnueli [1]_; see also Murata [2]_; Theorem 2 of
the ORCCAD paper [3]_). So liveness is decided in linear time by the strongly
connected components of the subgraph of 0-token places: every non-trivial
component (or 0-token self-loop) holds a token-free circuit, a deadlock whose
events never fire.

References
----------
.. [1] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed
   graphs", Journal of Computer and System Sciences 5(5), 511–523, 1971.
.. [2] T. Murata, "Petri nets: properties, analysis and applications",
   Proceedings of the IEEE 77(4), 541–580, 1989.
.. [3] D. Simon et al., "Design and analysis of synchronization for
   real-time closed-loop control in robotics", IEEE Transactions on Control
   Systems Technology, 1998.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import breadth_first_order, connected_components

__all__ = ["token_free_circuits", "dead_events"]


def token_free_circuits(src: np.ndarray, dst: np.ndarray, tokens: np.ndarray,
                        n_events: int) -> list[list[int]]:
    """One token-free circuit per strongly connected part of the 0-token graph.

    Parameters
    ----------
    src, dst : numpy.ndarray of int
        Input and output event of every place.
    tokens : numpy.ndarray of int
        Initial tokens of every place.
    n_events : int
        Number of events (transitions).

    Returns
    -------
    list of list of int
        Each circuit as the places it goes through, in order
        (``dst[c[k]] == src[c[k+1]]``); empty when the graph is live.
        Circuits are listed in the order of their smallest event.

    See Also
    --------
    dead_events : the events these circuits starve.
    tegraph.analysis.deadlocks.skeleton_deadlocks : the circuits named by
        tasks and links.
    tegraph.analysis.invariants.minimal_semiflows : the semiflow cross-check.

    Notes
    -----
    The graph is live exactly when the list is empty, by Commoner's theorem
    [1]_, [2]_.

    References
    ----------
    .. [1] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed
       graphs", Journal of Computer and System Sciences 5(5), 511–523, 1971.
    .. [2] T. Murata, "Petri nets: properties, analysis and applications",
       Proceedings of the IEEE 77(4), 541–580, 1989.

    Examples
    --------
    Places 0 -> 1 and 1 -> 0 without tokens, 1 -> 2 and 2 -> 1 with one:

    >>> token_free_circuits(np.array([0, 1, 1, 2]), np.array([1, 0, 2, 1]),
    ...                     np.array([0, 0, 1, 1]), 3)
    [[0, 1]]
    """
    zero = np.flatnonzero(np.asarray(tokens) == 0)
    if len(zero) == 0:
        return []
    s, d = src[zero], dst[zero]
    graph = sp.csr_matrix((np.ones(len(zero), dtype=np.int8), (s, d)), shape=(n_events, n_events))
    n_comp, label = connected_components(graph, directed=True, connection="strong")
    size = np.bincount(label, minlength=n_comp)
    inside = label[s] == label[d]
    circuits: dict[int, list[int]] = {}
    # Self-loops first: the shortest possible witness.
    for k in np.flatnonzero(inside & (s == d)).tolist():
        circuits.setdefault(int(label[s[k]]), [int(zero[k])])
    out_place: dict[int, int] = {}
    for k in np.flatnonzero(inside & (s != d) & (size[label[s]] > 1)).tolist():
        out_place.setdefault(int(s[k]), int(zero[k]))
    for comp in np.flatnonzero(size > 1).tolist():
        if comp in circuits:
            continue
        start = int(np.flatnonzero(label == comp).min())
        circuits[comp] = _walk_to_circuit(start, out_place, dst)
    order = sorted(circuits.values(), key=lambda c: min(int(src[p]) for p in c))
    return [_rotate_to_smallest(c, src) for c in order]


def _walk_to_circuit(start: int, out_place: dict[int, int], dst: np.ndarray) -> list[int]:
    """Follow out-places inside one strongly connected class until a node repeats."""
    seen: dict[int, int] = {}
    walk: list[int] = []
    node = start
    while node not in seen:
        seen[node] = len(walk)
        place = out_place[node]
        walk.append(place)
        node = int(dst[place])
    return walk[seen[node]:]


def _rotate_to_smallest(circuit: list[int], src: np.ndarray) -> list[int]:
    first = min(range(len(circuit)), key=lambda k: int(src[circuit[k]]))
    return circuit[first:] + circuit[:first]


def dead_events(src: np.ndarray, dst: np.ndarray, tokens: np.ndarray, n_events: int) -> np.ndarray:
    """Boolean mask of the events that never fire: on or downstream of a token-free circuit.

    An event downstream of a dead event waits, in some firing, for a token that
    never comes (after it has used up the tokens already on the way).

    Parameters
    ----------
    src, dst : numpy.ndarray of int
        Input and output event of every place.
    tokens : numpy.ndarray of int
        Initial tokens of every place.
    n_events : int
        Number of events (transitions).

    Returns
    -------
    numpy.ndarray of bool
        True for each event that fires only finitely often.

    See Also
    --------
    token_free_circuits : the circuits the dead events start from.

    Examples
    --------
    >>> dead_events(np.array([0, 1, 1]), np.array([1, 0, 2]), np.array([0, 0, 1]), 4).tolist()
    [True, True, True, False]
    """
    circuits = token_free_circuits(src, dst, tokens, n_events)
    roots = sorted({int(src[p]) for c in circuits for p in c})
    # Breadth-first search from a virtual event joined to every dead one.
    graph = sp.csr_matrix(
        (np.ones(len(src) + len(roots), dtype=np.int8),
         (np.r_[src, np.full(len(roots), n_events)], np.r_[dst, roots])),
        shape=(n_events + 1, n_events + 1),
    )
    reached = breadth_first_order(graph, n_events, directed=True, return_predecessors=False)
    mask = np.zeros(n_events + 1, dtype=bool)
    mask[reached] = True
    return mask[:n_events]
