"""Minimal p-semiflows (place invariants) and the liveness cross-check.

A p-semiflow is a vector ``y >= 0``, ``y != 0``, with ``yᵀ·C = 0`` for the
incidence matrix ``C`` (places × transitions); ``yᵀ·M`` is then the same for
every reachable marking ``M``. In a marked graph the supports of the minimal
p-semiflows are exactly the elementary circuits, so the graph is live if and
only if every minimal semiflow carries a token (Commoner's theorem [1]_,
[2]_) — the check of the ORCCAD paper (§4) [3]_, made here by the Farkas
algorithm of Martínez and Silva [4]_. Their number can grow exponentially:
the enumeration runs under a budget on the number of candidate rows and says
so when it stops.

References
----------
.. [1] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed
   graphs", Journal of Computer and System Sciences 5(5), 511–523, 1971.
.. [2] T. Murata, "Petri nets: properties, analysis and applications",
   Proceedings of the IEEE 77(4), 541–580, 1989.
.. [3] D. Simon et al., "Design and analysis of synchronization for
   real-time closed-loop control in robotics", IEEE Transactions on Control
   Systems Technology, 1998.
.. [4] J. Martínez, M. Silva, "A simple and fast algorithm to obtain all
   invariants of a generalised Petri net", in C. Girault, W. Reisig (eds.),
   *Application and Theory of Petri Nets*, Informatik-Fachberichte 52,
   Springer, 1982.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from .semiflow_tables import combine_tables

__all__ = ["SemiflowCensus", "SemiflowResult", "minimal_semiflows", "semiflow_census"]


@dataclass(frozen=True)
class SemiflowResult:
    """Minimal p-semiflows of a net, or the statement that the budget ran out.

    Attributes
    ----------
    computed : bool
        False when the number of candidate rows exceeded ``budget``.
    matrix : scipy.sparse.csr_matrix
        One minimal semiflow a row (non-negative integers over the places);
        no rows when not computed.
    budget : int
    """

    computed: bool
    matrix: sp.csr_matrix
    budget: int

    @property
    def count(self) -> int:
        """Number of minimal semiflows found."""
        return int(self.matrix.shape[0])

    @property
    def semiflows(self) -> list[np.ndarray]:
        """The semiflows as dense vectors, those with the earliest places first."""
        rows = self.matrix.toarray()
        order = sorted(range(len(rows)), key=lambda k: [-v for v in (rows[k] > 0).tolist()])
        return [rows[k] for k in order]

    def unmarked(self, marking: np.ndarray) -> np.ndarray:
        """Indices (rows of ``matrix``) of the semiflows without token under ``marking``.

        Parameters
        ----------
        marking : array_like of int
            Tokens per place.

        Returns
        -------
        numpy.ndarray of int
            Rows of ``matrix`` whose support holds no token: in a marked graph,
            the circuits that deadlock.

        Examples
        --------
        >>> r = minimal_semiflows(np.array([[-1, 1], [1, -1], [0, 0]]))
        >>> r.unmarked([0, 0, 1]).tolist()
        [0]
        """
        return np.flatnonzero(self.matrix @ np.asarray(marking, dtype=np.int64) == 0)


DENSE_LIMIT = 1 << 18
"""Above this many places × transitions the sparse table is used."""


def minimal_semiflows(incidence: np.ndarray | sp.spmatrix, budget: int = 5000,
                      method: Literal["auto", "dense", "sparse"] = "auto") -> SemiflowResult:
    """All minimal p-semiflows of an incidence matrix, within a row budget.

    Parameters
    ----------
    incidence : numpy.ndarray or scipy.sparse matrix
        ``places × transitions`` matrix of integers (``+w`` when the place is
        an output of the transition with weight ``w``, ``-w`` when an input).
    budget : int
        Largest number of candidate rows (rows not yet semiflows) at any step.
    method : {"auto", "dense", "sparse"}
        Table kept as a dense array (fast on small nets) or as sparse rows
        (a step then costs what it touches); ``"auto"`` picks dense up to
        :data:`DENSE_LIMIT` entries. Both give the same semiflows.

    Returns
    -------
    SemiflowResult
        ``computed`` and one minimal semiflow per row of ``matrix``; when the
        budget ran out, ``computed`` is False and ``matrix`` has no rows.

    See Also
    --------
    SemiflowResult.unmarked : the semiflows without token under a marking.

    Notes
    -----
    The Farkas algorithm of Martínez and Silva [1]_: eliminate one transition
    column at a time, combining each row with a positive entry with each row
    with a negative one, and drop every row whose support contains another
    row's support. The
    order of elimination does not change the result, so transitions with a
    single input and a single output place (most events of a skeleton) are
    eliminated first, all at once: in a marked graph they join places into
    paths and circuits, found as connected components. On a large net the
    table is kept sparse (a semiflow of a skeleton is a short circuit), so a
    step costs in proportion to the entries it touches, not to rows × places.

    In a marked graph the minimal semiflows are the elementary circuits, and
    the net is live if and only if each carries a token [2]_, [3]_.

    References
    ----------
    .. [1] J. Martínez, M. Silva, "A simple and fast algorithm to obtain all
       invariants of a generalised Petri net", in C. Girault, W. Reisig (eds.),
       *Application and Theory of Petri Nets*, Informatik-Fachberichte 52,
       Springer, 1982.
    .. [2] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed
       graphs", Journal of Computer and System Sciences 5(5), 511–523, 1971.
    .. [3] T. Murata, "Petri nets: properties, analysis and applications",
       Proceedings of the IEEE 77(4), 541–580, 1989.

    Examples
    --------
    A circuit of two transitions through places 0 and 1, and a self-loop place 2:

    >>> C = np.array([[-1, 1], [1, -1], [0, 0]])
    >>> [y.tolist() for y in minimal_semiflows(C).semiflows]
    [[1, 1, 0], [0, 0, 1]]
    """
    C = sp.csr_matrix(incidence, dtype=np.int64)
    C.eliminate_zeros()
    n_places, n_trans = C.shape
    Y, R = _contract_series_transitions(C)
    if method == "dense" or (method == "auto" and n_places * n_trans <= DENSE_LIMIT):
        return _farkas_dense(Y, R.toarray(), budget)
    return _farkas_sparse(Y, R, budget)


@dataclass(frozen=True)
class SemiflowCensus:
    """How many minimal p-semiflows the blocks of a net have, and how many carry no token.

    Attributes
    ----------
    computed : bool
        False when the enumeration of block ``failed`` ran out of budget.
    count, unmarked : int
        Summed over the blocks (up to the failed one, excluded).
    failed : int or None
        Index of the first block whose enumeration ran out of budget.
    """

    computed: bool
    count: int
    unmarked: int
    failed: int | None = None


def semiflow_census(incidence: sp.spmatrix, blocks: list[tuple[np.ndarray, np.ndarray]],
                    marking: np.ndarray, budget: int) -> SemiflowCensus:
    """:func:`minimal_semiflows` of each block, counted, stopping at the first out of budget.

    Parameters
    ----------
    incidence : scipy.sparse matrix
        ``places × transitions`` of a whole net.
    blocks : list of (rows, columns)
        Disjoint sets of places, each with the transitions its rows touch
        (sorted): block ``b`` is ``incidence[rows][:, columns]``; no transition
        may touch places of two blocks.
    marking : numpy.ndarray of int
        Tokens per place (row of ``incidence``), >= 0.
    budget : int
        As in :func:`minimal_semiflows`, for each block.

    Returns
    -------
    SemiflowCensus
        Equal, block by block, to ``minimal_semiflows(block, budget)``: its
        ``count`` and the number of its semiflows unmarked under ``marking``.

    Notes
    -----
    The same Farkas tables, made cheaper for many small blocks: the series
    transitions of every block are contracted at once (a transition's input
    and output places lie in its block, so each block's paths and circuits are
    the same, in the same order), and a block with no open row after that (its
    places only form circuits) needs no table at all.

    Examples
    --------
    Two blocks: a circuit of two transitions through places 0 and 1 (place 1
    marked), and a circuit of one transition (place 2, no token):

    >>> C = sp.csr_matrix(np.array([[-1, 1, 0], [1, -1, 0], [0, 0, 0]]))
    >>> semiflow_census(C, [(np.array([0, 1]), np.array([0, 1])),
    ...                     (np.array([2]), np.array([2]))], np.array([0, 1, 0]), 10)
    SemiflowCensus(computed=True, count=2, unmarked=1, failed=None)
    """
    C = sp.csr_matrix(incidence, dtype=np.int64)
    order = np.concatenate([rows for rows, _ in blocks] + [np.zeros(0, dtype=np.int64)])
    C = C[order]
    C.eliminate_zeros()
    if not _marked_graph_rows(C):  # weighted rows: each block's own table, as it was
        count = unmarked = 0
        for b, (rows, columns) in enumerate(blocks):
            result = minimal_semiflows(sp.csr_matrix(incidence)[rows][:, columns], budget)
            if not result.computed:
                return SemiflowCensus(False, count, unmarked, b)
            count += result.count
            unmarked += len(result.unmarked(marking[rows]))
        return SemiflowCensus(True, count, unmarked)
    member, R = _contract_series_transitions(C)
    row_tokens = member @ np.asarray(marking, dtype=np.int64)[order]
    is_open = R.getnnz(axis=1) > 0
    # The rows of each block are consecutive (rows are numbered by their first place).
    block_of_place = np.repeat(np.arange(len(blocks)), [len(rows) for rows, _ in blocks])
    row_block = block_of_place[member.indices[member.indptr[:-1]]]
    bounds = np.searchsorted(row_block, np.arange(len(blocks) + 1)).tolist()
    # The open rows of each small block as its own table, all combined at once.
    tables: dict[int, np.ndarray] = {}
    for b, (rows, columns) in enumerate(blocks):
        opened = bounds[b] + np.flatnonzero(is_open[bounds[b]:bounds[b + 1]])
        if len(rows) * len(columns) <= DENSE_LIMIT and len(opened):
            part = R[opened]
            touched = np.unique(part.indices)  # in the block's column order (both sorted)
            tables[b] = sp.csr_matrix(
                (part.data, np.searchsorted(touched, part.indices), part.indptr),
                shape=(len(opened), len(touched))).toarray()
    combined, left = combine_tables(list(tables.values()), budget)
    made_of = dict(zip(tables, combined))
    for k in left:  # grown too large to be combined with the others
        made_of[list(tables)[k]] = _combine_open_rows(list(tables.values())[k], budget)
    count = unmarked = 0
    for b, (rows, columns) in enumerate(blocks):
        first, end = bounds[b], bounds[b + 1]
        if len(rows) * len(columns) > DENSE_LIMIT:  # the sparse table, as minimal_semiflows
            result = minimal_semiflows(sp.csr_matrix(incidence)[rows][:, columns], budget)
            if not result.computed:
                return SemiflowCensus(False, count, unmarked, b)
            count += result.count
            unmarked += len(result.unmarked(marking[rows]))
            continue
        opened = first + np.flatnonzero(is_open[first:end])
        closed_tokens = row_tokens[first:end][~is_open[first:end]]
        count += len(closed_tokens)
        unmarked += int((closed_tokens == 0).sum())
        if len(opened) == 0:
            continue
        made = made_of[b]
        if made is None:
            return SemiflowCensus(False, count - len(closed_tokens),
                                  unmarked - int((closed_tokens == 0).sum()), b)
        count += len(made)
        unmarked += int((made @ row_tokens[opened] == 0).sum())
    return SemiflowCensus(True, count, unmarked)


def _farkas_sparse(Y: sp.csr_matrix, R: sp.csr_matrix, budget: int) -> SemiflowResult:
    n_places, n_trans = Y.shape[1], R.shape[1]
    # A row whose transition part is 0 is a semiflow already: no later step
    # combines it, though new rows are still checked against its support.
    closed = R.getnnz(axis=1) == 0
    finished = Y[np.flatnonzero(closed)]
    Y, R = Y[np.flatnonzero(~closed)], R[np.flatnonzero(~closed)]
    while R.shape[0]:
        rows = R.shape[0]
        positive = R.data > 0
        n_pos = np.bincount(R.indices[positive], minlength=n_trans)
        n_neg = np.bincount(R.indices[~positive], minlength=n_trans)
        # Eliminating the column with the fewest new combinations first keeps
        # the table small; a column no row touches needs no step.
        cost = np.where(n_pos + n_neg > 0, n_pos * n_neg, np.iinfo(np.int64).max)
        j = int(np.argmin(cost))
        at_j = R.indices == j
        row_of_entry = np.repeat(np.arange(rows), np.diff(R.indptr))
        col = np.zeros(rows, dtype=np.int64)
        col[row_of_entry[at_j]] = R.data[at_j]
        pos, neg, zero = np.flatnonzero(col > 0), np.flatnonzero(col < 0), np.flatnonzero(col == 0)
        if len(zero) + len(pos) * len(neg) > budget:
            return SemiflowResult(False, sp.csr_matrix((0, n_places), dtype=np.int64), budget)
        a = np.repeat(pos, len(neg))
        b = np.tile(neg, len(pos))
        fa, fb = sp.diags(-col[b], dtype=np.int64), sp.diags(col[a], dtype=np.int64)
        new_Y = (fa @ Y[a] + fb @ Y[b]).tocsr()
        new_R = (fa @ R[a] + fb @ R[b]).tocsr()
        new_R.eliminate_zeros()  # column j cancels
        if new_Y.shape[0]:
            g = np.gcd.reduceat(new_Y.data, new_Y.indptr[:-1])
            new_Y.data //= np.repeat(g, np.diff(new_Y.indptr))
            new_R.data //= np.repeat(g, np.diff(new_R.indptr))  # R = Y·C: divisible too
        # Rows kept from before stay minimal (their supports were minimal and
        # no new support is a proper subset of a removed row's); only the new
        # rows can contain another support.
        keep = _minimal_new_rows(sp.vstack([Y[zero], finished], format="csr"), new_Y)
        new_Y, new_R = new_Y[keep], new_R[keep]
        done = new_R.getnnz(axis=1) == 0
        if done.any():
            finished = sp.vstack([finished, new_Y[np.flatnonzero(done)]], format="csr")
        Y = sp.vstack([Y[zero], new_Y[np.flatnonzero(~done)]], format="csr")
        R = sp.vstack([R[zero], new_R[np.flatnonzero(~done)]], format="csr")
    return SemiflowResult(True, finished, budget)


def _farkas_dense(Y: sp.csr_matrix, R: np.ndarray, budget: int) -> SemiflowResult:
    """The Farkas table kept dense, on the rows that are not semiflows yet.

    ``Y`` (rows over places) partitions the places (identity rows, or the paths
    and circuits of :func:`_contract_series_transitions`), so every later row,
    a non-negative combination of them, is kept as its coefficients over the
    rows still open (``R != 0``): its support over places is the disjoint union
    of theirs, so support containment, support sizes' order and the gcd are
    those of the coefficients. A row closed from the start (``R = 0``) is never
    combined, and no combination of open rows can contain its (disjoint)
    support: it only waits, in order, at the head of the result. This is the
    table over all places and rows, smaller (a skeleton's batch: 25 open rows
    of 100 instead of 256 places).
    """
    n_places = Y.shape[1]
    is_open = R.any(axis=1)
    made = _combine_open_rows(R[is_open], budget)
    if made is None:
        return SemiflowResult(False, sp.csr_matrix((0, n_places), dtype=np.int64), budget)
    rows = sp.vstack([Y[np.flatnonzero(~is_open)],
                      sp.csr_matrix(made) @ Y[np.flatnonzero(is_open)]],
                     format="csr", dtype=np.int64)
    rows.eliminate_zeros()
    rows.sort_indices()
    return SemiflowResult(True, rows, budget)


def _combine_open_rows(R: np.ndarray, budget: int) -> np.ndarray | None:
    """Farkas on the open rows ``R`` (each row a start row of the table, over the
    transitions): the minimal closed combinations, as coefficients over these rows
    in the order they were made; None when the budget ran out.

    The tables are small (a skeleton's batch: 20 to 40 rows, 1,400 steps in all
    at 10,000 tasks), so a step costs what its numpy calls cost, whatever their
    size: coefficients and transition part travel as one table ``[X | R]``, the
    rows of a column split by one stable sort of its signs, and new rows are
    checked for minimality by one product (:func:`_minimal_new_supports`).
    """
    n_open = R.shape[0]
    columns = np.flatnonzero(R.any(axis=0))  # the others need no step
    # [X | R]: X the coefficients over the open rows, R the transition part.
    table = np.hstack([np.eye(n_open, dtype=np.int64), R[:, columns]])
    finished: list[np.ndarray] = [np.zeros((0, n_open), dtype=np.int64)]
    closed_support = np.zeros((0, n_open))
    done = np.zeros(len(columns), dtype=bool)
    for _ in range(len(columns)):
        R = table[:, n_open:]
        n_pos, n_neg = (R > 0).sum(axis=0), (R < 0).sum(axis=0)
        cost = n_pos * n_neg
        cost[done] = np.iinfo(np.int64).max
        j = int(np.argmin(cost))
        done[j] = True
        p, q, rows = int(n_pos[j]), int(n_neg[j]), len(table)
        # Only open rows are candidates (closed ones are semiflows): as in the sparse table.
        if rows - p - q + p * q > budget:
            return None
        if p + q == 0:
            continue  # no row touches the column
        col = table[:, n_open + j]
        # Rows by sign, each part in table order: negative, zero, positive.
        by_sign = np.argsort(np.sign(col), kind="stable")
        neg, zero, pos = by_sign[:q], by_sign[q:rows - p], by_sign[rows - p:]
        if p == 0 or q == 0:
            table = table[zero]
            continue
        a = np.repeat(pos, q)
        b = np.tile(neg, p)
        new = (-col[b])[:, None] * table[a] + col[a][:, None] * table[b]
        g = np.gcd.reduce(new[:, :n_open], axis=1)  # > 0: X rows are >= 0 and not 0
        new //= g[:, None]
        new_support = (new[:, :n_open] > 0).astype(np.float64)
        old_support = np.vstack([(table[zero, :n_open] > 0).astype(np.float64), closed_support])
        keep = _minimal_new_supports(old_support, new_support)
        new, new_support = new[keep], new_support[keep]
        closed = ~new[:, n_open:].any(axis=1)
        if closed.any():
            finished.append(new[closed, :n_open])
            closed_support = np.vstack([closed_support, new_support[closed]])
        table = np.vstack([table[zero], new[~closed]])
    return np.vstack(finished)


def _minimal_new_supports(old: np.ndarray, new: np.ndarray) -> np.ndarray:
    """:func:`_minimal_new_rows` on supports given as 0/1 float rows.

    Products of 0/1 rows count common places exactly in float64 (far fewer than
    2**53), through BLAS; one product compares each new row with the old and the
    new rows at once.

    >>> old = np.array([[1., 1, 0, 0, 0]])
    >>> new = np.array([[1., 1, 1, 0, 0], [0, 0, 1, 1, 0], [0, 0, 1, 1, 0], [0, 0, 0, 0, 1],
    ...                 [0, 0, 1, 1, 1]])
    >>> _minimal_new_supports(old, new).tolist()  # 0 holds old 0, 2 equals 1, 4 holds 1 and 3
    [1, 3]
    """
    k, m = len(new), len(old)
    if k == 0:
        return np.zeros(0, dtype=np.int64)
    both = np.vstack([old, new])
    size = both.sum(axis=1)
    contains = (new @ both.T) == size[None, :]  # [i, l]: support l within new support i
    # A new support is dropped when it contains an old one, or a new one that is
    # smaller or of equal size and earlier: a smaller key (size, index), itself excluded.
    key = size[m:] * k + np.arange(k)
    smaller = key[None, :] < key[:, None]
    bad = contains[:, :m].any(axis=1) | (contains[:, m:] & smaller).any(axis=1)
    return np.flatnonzero(~bad)


def _contract_series_transitions(C: sp.csr_matrix) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """Eliminate every transition with one input and one output place at once.

    Only for marked-graph rows (each row one +1 and one -1, or all zero);
    otherwise nothing is contracted. Returns the rows: Y over places, R over
    transitions (the eliminated columns are 0 in R).
    """
    n_places, n_trans = C.shape
    identity = sp.identity(n_places, dtype=np.int64, format="csr")
    if not _marked_graph_rows(C) or n_places == 0:
        return identity, C.copy()
    coo = C.tocoo()
    ins = np.bincount(coo.col[coo.data < 0], minlength=n_trans)
    outs = np.bincount(coo.col[coo.data > 0], minlength=n_trans)
    series = (ins == 1) & (outs == 1)
    into = np.full(n_trans, -1)
    out_of = np.full(n_trans, -1)
    into[coo.col[coo.data < 0]] = coo.row[coo.data < 0]
    out_of[coo.col[coo.data > 0]] = coo.row[coo.data > 0]
    # A self-loop place (input and output of one transition) is a zero row of C,
    # never an input or output here; its row stays a semiflow on its own.
    joined = np.flatnonzero(series)
    join = sp.csr_matrix((np.ones(len(joined)), (into[joined], out_of[joined])),
                         shape=(n_places, n_places))
    n_comp, label = connected_components(join, directed=False)
    # Each component of places joined through series transitions is a path
    # (its row: the sum of its places) or a circuit (a semiflow already).
    member = sp.csr_matrix((np.ones(n_places, dtype=np.int64), (label, np.arange(n_places))),
                           shape=(n_comp, n_places))
    R = (member @ C).tocsr()
    R.eliminate_zeros()
    return member, R


def _marked_graph_rows(C: sp.csr_matrix) -> bool:
    """Whether each row of ``C`` (no stored zeros) is one +1 and one -1, or all zero."""
    per_row = C.getnnz(axis=1)
    positive_per_row = np.bincount(np.repeat(np.arange(C.shape[0]), per_row)[C.data > 0],
                                   minlength=C.shape[0])
    return bool(np.abs(C.data).max(initial=0) <= 1
                and (np.isin(per_row, (0, 2)) & (positive_per_row * 2 == per_row)).all())


def _minimal_new_rows(old: sp.csr_matrix, new: sp.csr_matrix) -> np.ndarray:
    """Indices of new rows whose support contains no other row's support (first of equals)."""
    if new.shape[0] == 0:
        return np.zeros(0, dtype=np.int64)
    S_new = _pattern(new)
    size_new = S_new.getnnz(axis=1)
    bad = np.zeros(new.shape[0], dtype=bool)
    if old.shape[0]:
        S_old = _pattern(old)
        inter = (S_new @ S_old.T).tocoo()
        hit = inter.data == S_old.getnnz(axis=1)[inter.col]
        bad[inter.row[hit]] = True
    inter = (S_new @ S_new.T).tocoo()
    i, k = inter.row, inter.col
    contains = (inter.data == size_new[k]) & (i != k)  # support k within support i
    strict = contains & (size_new[k] < size_new[i])
    earlier_equal = contains & (size_new[k] == size_new[i]) & (k < i)
    bad[i[strict | earlier_equal]] = True
    return np.flatnonzero(~bad)


def _pattern(m: sp.csr_matrix) -> sp.csr_matrix:
    return sp.csr_matrix((np.ones(len(m.data), dtype=np.int32), m.indices, m.indptr),
                         shape=m.shape)
