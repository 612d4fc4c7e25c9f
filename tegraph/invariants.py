"""Minimal p-semiflows (place invariants) and the liveness cross-check.

A p-semiflow is a vector ``y >= 0``, ``y != 0``, with ``yᵀ·C = 0`` for the
incidence matrix ``C`` (places × transitions); ``yᵀ·M`` is then the same for
every reachable marking ``M``. In a marked graph the supports of the minimal
p-semiflows are exactly the elementary circuits, so the graph is live if and
only if every minimal semiflow carries a token — the check of the ORCCAD
paper (§4), made here by the Farkas algorithm of Martínez and Silva
("A simple and fast algorithm to obtain all invariants of a generalised
Petri net", 1982). Their number can grow exponentially: the enumeration runs
under a budget on the number of candidate rows and says so when it stops.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

__all__ = ["SemiflowResult", "minimal_semiflows"]


@dataclass(frozen=True)
class SemiflowResult:
    """Minimal p-semiflows of a net, or the statement that the budget ran out.

    Attributes
    ----------
    computed : bool
        False when the number of candidate rows exceeded ``budget``.
    semiflows : list of numpy.ndarray
        Each a vector of non-negative integers over the places (when computed).
    budget : int
    """

    computed: bool
    semiflows: list[np.ndarray]
    budget: int

    def unmarked(self, marking: np.ndarray) -> list[np.ndarray]:
        """The semiflows that carry no token under ``marking``."""
        return [y for y in self.semiflows if int(np.dot(y, marking)) == 0]


def minimal_semiflows(incidence: np.ndarray, budget: int = 5000) -> SemiflowResult:
    """All minimal p-semiflows of an incidence matrix, within a row budget.

    Parameters
    ----------
    incidence : numpy.ndarray
        Dense ``places × transitions`` matrix of integers (``+1`` when the
        place is an output of the transition, ``-1`` when an input).
    budget : int
        Largest number of candidate rows kept at any step.

    Returns
    -------
    SemiflowResult

    Notes
    -----
    Martínez & Silva (1982): eliminate one transition column at a time,
    combining each row with a positive entry with each row with a negative one,
    and drop every row whose support contains another row's support. The
    order of elimination does not change the result, so transitions with a
    single input and a single output place (most events of a skeleton) are
    eliminated first, all at once: in a marked graph they join places into
    paths and circuits, found as connected components.

    Examples
    --------
    A circuit of two transitions through places 0 and 1, and a self-loop place 2:

    >>> C = np.array([[-1, 1], [1, -1], [0, 0]])
    >>> [y.tolist() for y in minimal_semiflows(C).semiflows]
    [[1, 1, 0], [0, 0, 1]]
    """
    C = np.asarray(incidence, dtype=np.int64)
    n_places, n_trans = C.shape
    Y, R, done = _contract_series_transitions(C)
    for _ in range(int((~done).sum())):
        # Eliminating the column with the fewest new combinations first keeps
        # the intermediate tables small.
        cost = (R > 0).sum(axis=0) * (R < 0).sum(axis=0)
        cost[done] = np.iinfo(np.int64).max
        j = int(np.argmin(cost))
        done[j] = True
        col = R[:, j]
        pos, neg, zero = np.flatnonzero(col > 0), np.flatnonzero(col < 0), np.flatnonzero(col == 0)
        if len(zero) + len(pos) * len(neg) > budget:
            return SemiflowResult(False, [], budget)
        if len(pos) == 0 or len(neg) == 0:
            Y, R = Y[zero], R[zero]
            continue
        a = np.repeat(pos, len(neg))
        b = np.tile(neg, len(pos))
        fa, fb = -col[b][:, None], col[a][:, None]
        new_Y = fa * Y[a] + fb * Y[b]
        new_R = fa * R[a] + fb * R[b]
        g = np.gcd.reduce(new_Y, axis=1)
        g = np.where(g == 0, 1, g)[:, None]
        new_Y, new_R = new_Y // g, new_R // g
        # Rows kept from before stay minimal (their supports were minimal and
        # no new support is a proper subset of a removed row's); only the new
        # rows can contain another support.
        keep = _minimal_new_rows(Y[zero], new_Y)
        Y = np.vstack([Y[zero], new_Y[keep]])
        R = np.vstack([R[zero], new_R[keep]])
    order = sorted(range(len(Y)), key=lambda k: [-v for v in (Y[k] > 0).tolist()])
    return SemiflowResult(True, [Y[k] for k in order], budget)


def _contract_series_transitions(C: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eliminate every transition with one input and one output place at once.

    Only for marked-graph rows (each row one +1 and one -1, or all zero);
    otherwise nothing is contracted. Returns the rows (Y over places, R over
    transitions) and the mask of eliminated transitions.
    """
    n_places, n_trans = C.shape
    nonzero = (C != 0).sum(axis=1)
    marked_graph = (np.abs(C).max(initial=0) <= 1
                    and (np.isin(nonzero, (0, 2)) & ((C > 0).sum(axis=1) * 2 == nonzero)).all())
    if not marked_graph or n_places == 0:
        return np.eye(n_places, dtype=np.int64), C.copy(), np.zeros(n_trans, dtype=bool)
    ins, outs = (C < 0).sum(axis=0), (C > 0).sum(axis=0)
    series = np.flatnonzero((ins == 1) & (outs == 1))
    into = np.argmax(C[:, series] < 0, axis=0)   # the input place of each series transition
    out_of = np.argmax(C[:, series] > 0, axis=0)  # its output place
    keep = into != out_of
    join = sp.csr_matrix((np.ones(int(keep.sum())), (into[keep], out_of[keep])),
                         shape=(n_places, n_places))
    n_comp, label = connected_components(join, directed=False)
    # Each component of places joined through series transitions is a path
    # (its row: the sum of its places) or a circuit (a semiflow already).
    member = sp.csr_matrix((np.ones(n_places, dtype=np.int64), (label, np.arange(n_places))),
                           shape=(n_comp, n_places))
    Y = member.toarray()
    R = np.asarray(member @ C, dtype=np.int64)
    done = np.zeros(n_trans, dtype=bool)
    done[series[keep]] = True
    return Y, R, done


def _minimal_new_rows(old: np.ndarray, new: np.ndarray) -> np.ndarray:
    """Indices of new rows whose support contains no other row's support (first of equals)."""
    if len(new) == 0:
        return np.zeros(0, dtype=np.int64)
    S_new = (new > 0).astype(np.int32)
    size_new = S_new.sum(axis=1)
    bad = np.zeros(len(new), dtype=bool)
    if len(old):
        S_old = (old > 0).astype(np.int32)
        size_old = S_old.sum(axis=1)
        bad |= ((S_new @ S_old.T) == size_old[None, :]).any(axis=1)
    inter = S_new @ S_new.T
    contains = inter == size_new[None, :]  # contains[i, j]: support j within support i
    np.fill_diagonal(contains, False)
    strict = contains & (size_new[None, :] < size_new[:, None])
    equal = contains & (size_new[None, :] == size_new[:, None])
    earlier_equal = np.triu(equal.T, k=1).any(axis=0)
    return np.flatnonzero(~bad & ~strict.any(axis=1) & ~earlier_equal)


