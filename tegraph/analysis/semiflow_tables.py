"""Many small Farkas tables advanced together, one numpy pass per step of all.

:func:`~tegraph.analysis.invariants.semiflow_census` enumerates the minimal
p-semiflows of a skeleton block by block: a skeleton of 10,000 tasks gives
about 120 tables of 20 to 40 rows, 1,400 elimination steps in all, and a step
on one small table costs what its few dozen numpy calls cost, whatever their
size. Here step ``s`` of every table is taken at once: the rows of all tables
are kept in one array, grouped by table, each table eliminating its own column
(chosen, combined and checked exactly as by
``tegraph.analysis.invariants._combine_open_rows``), so the tables cost
about as many numpy passes as the longest of them has steps.

A table that grows past ``MAX_ROWS`` (64) rows is left to the one-table routine
(reported in ``left``): the products that test minimality are padded to the
largest table of the pass.
"""

from __future__ import annotations

import numpy as np

__all__ = ["combine_tables"]

MAX_ROWS = 64
"""A table with more rows than this (or more semiflows found, or new rows in one step) is left."""

CHUNK_ENTRIES = 1 << 22
"""Tables are combined in chunks of similar widths, each of at most this many entries
(its tables at :data:`MAX_ROWS` rows, padded to its widest): 32 MB of int64."""


def combine_tables(tables: list[np.ndarray], budget: int
                   ) -> tuple[list[np.ndarray | None], list[int]]:
    """``tegraph.analysis.invariants._combine_open_rows`` of each table, together.

    Parameters
    ----------
    tables : list of numpy.ndarray
        Each the open rows of one table (rows × transitions, int64), at least one row.
    budget : int
        As in :func:`~tegraph.analysis.invariants.minimal_semiflows`, for each table.

    Returns
    -------
    results : list
        For each table, what ``_combine_open_rows(table, budget)`` returns (the
        minimal closed combinations in the order made, or None when the budget
        ran out); None also for the tables left.
    left : list of int
        The tables that grew past :data:`MAX_ROWS`: to be computed alone.

    Notes
    -----
    Tables are taken by increasing width, in chunks of :data:`CHUNK_ENTRIES`.

    Examples
    --------
    Two tables: a path 0 -> 1 and its way back (one circuit), and two parallel
    paths each way between two transitions (four circuits):

    >>> first = np.array([[-1, 1], [1, -1]])
    >>> second = np.array([[-1, 1], [-1, 1], [1, -1], [1, -1]])
    >>> results, left = combine_tables([first, second], 10)
    >>> [r.tolist() for r in results], left
    ([[[1, 1]], [[1, 0, 1, 0], [0, 1, 1, 0], [1, 0, 0, 1], [0, 1, 0, 1]]], [])
    """
    width = [t.shape[0] + t.shape[1] for t in tables]
    results: list[np.ndarray | None] = [None] * len(tables)
    left: list[int] = []
    chunk: list[int] = []
    for k in sorted(range(len(tables)), key=width.__getitem__) + [-1]:
        if chunk and (k < 0 or (len(chunk) + 1) * MAX_ROWS * width[k] > CHUNK_ENTRIES):
            made, grown = _combine_chunk([tables[c] for c in chunk], budget)
            for c, m in zip(chunk, made):
                results[c] = m
            left += [chunk[g] for g in grown]
            chunk = []
        chunk.append(k)
    return results, sorted(left)


def _combine_chunk(tables: list[np.ndarray], budget: int
                   ) -> tuple[list[np.ndarray | None], list[int]]:
    """:func:`combine_tables` on one chunk."""
    n_tables = len(tables)
    n_open = np.array([len(t) for t in tables], dtype=np.int64)
    columns = [np.flatnonzero(t.any(axis=0)) for t in tables]
    xw = int(n_open.max(initial=0))
    cw = max((len(c) for c in columns), default=0)
    # All rows in one array [X | R], grouped by table (`tab`), in each table's order;
    # X over the table's open rows, R over its touched columns, both padded with 0.
    rows = np.zeros((int(n_open.sum()), xw + cw), dtype=np.int64)
    tab = np.repeat(np.arange(n_tables), n_open)
    at = 0
    for table, cols in zip(tables, columns):
        n = len(table)
        rows[at:at + n, :n] = np.eye(n, dtype=np.int64)
        rows[at:at + n, xw:xw + len(cols)] = table[:, cols]
        at += n
    done = np.ones((n_tables, cw), dtype=bool)  # padding columns are never chosen
    for t, cols in enumerate(columns):
        done[t, :len(cols)] = False
    failed = np.zeros(n_tables, dtype=bool)
    left = np.zeros(n_tables, dtype=bool)
    made_tab: list[np.ndarray] = []  # the semiflows found, step by step
    made_rows: list[np.ndarray] = []
    closed_tab = np.zeros(0, dtype=np.int64)  # their supports, for minimality
    closed_support = np.zeros((0, xw))
    every = np.arange(n_tables)
    while True:
        active = ~done.all(axis=1)
        if not active.any():
            break
        positive, negative = rows[:, xw:] > 0, rows[:, xw:] < 0
        n_pos = _count_per_table(tab, positive, n_tables, cw)
        n_neg = _count_per_table(tab, negative, n_tables, cw)
        cost = n_pos * n_neg
        cost[done] = np.iinfo(np.int64).max
        j = np.argmin(cost, axis=1)
        done[every[active], j[active]] = True
        p, q = n_pos[every, j], n_neg[every, j]
        n_rows = np.bincount(tab, minlength=n_tables)
        # Only open rows are candidates (closed ones are semiflows): as in the sparse table.
        over = active & (n_rows - p - q + p * q > budget)
        too_large = active & ~over & (p * q > MAX_ROWS)
        failed |= over
        left |= too_large
        stop = over | too_large
        done[stop] = True
        col = np.where((active & ~stop)[tab], rows[np.arange(len(rows)), xw + j[tab]], 0)
        both = active & ~stop & (p > 0) & (q > 0)
        new, new_tab = _combinations(rows, tab, col, both, p, q)
        kept = ~stop[tab] & (col == 0)
        if len(new):
            g = np.gcd.reduce(new[:, :xw], axis=1)  # > 0: X rows are >= 0 and not 0
            new //= g[:, None]
            support = (new[:, :xw] > 0).astype(np.float64)
            keep = _minimal(support, new_tab, (rows[kept, :xw] > 0).astype(np.float64),
                            tab[kept], closed_support, closed_tab, n_tables)
            new, new_tab, support = new[keep], new_tab[keep], support[keep]
            closed = ~new[:, xw:].any(axis=1)
            made_tab.append(new_tab[closed])
            made_rows.append(new[closed, :xw])
            closed_tab = np.concatenate([closed_tab, new_tab[closed]])
            closed_support = np.vstack([closed_support, support[closed]])
            rows = np.vstack([rows[kept], new[~closed]])
            tab = np.concatenate([tab[kept], new_tab[~closed]])
            # Each table's kept rows, then its new open rows: one stable sort by table.
            order = np.argsort(tab, kind="stable")
            rows, tab = rows[order], tab[order]
        else:
            rows, tab = rows[kept], tab[kept]
        grown = (np.bincount(tab, minlength=n_tables) > MAX_ROWS) | (
            np.bincount(closed_tab, minlength=n_tables) > MAX_ROWS)
        if grown.any():
            left |= grown & ~failed
            done[grown] = True
            rows, tab = rows[~grown[tab]], tab[~grown[tab]]
    found_tab = np.concatenate(made_tab + [np.zeros(0, dtype=np.int64)])
    found = np.vstack(made_rows + [np.zeros((0, xw), dtype=np.int64)])
    order = np.argsort(found_tab, kind="stable")  # each table's in the order made
    bounds = np.searchsorted(found_tab[order], np.arange(n_tables + 1)).tolist()
    results: list[np.ndarray | None] = [
        None if failed[t] or left[t] else found[order[bounds[t]:bounds[t + 1]], :n_open[t]]
        for t in range(n_tables)]
    return results, np.flatnonzero(left).tolist()


def _count_per_table(tab: np.ndarray, mask: np.ndarray, n_tables: int, cw: int) -> np.ndarray:
    """``[t, c]``: how many rows of table ``t`` have ``mask`` in column ``c``."""
    rows, cols = np.nonzero(mask)
    return np.bincount(tab[rows] * cw + cols, minlength=n_tables * cw).reshape(n_tables, cw)


def _combinations(rows: np.ndarray, tab: np.ndarray, col: np.ndarray, both: np.ndarray,
                  p: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each positive row with each negative row of its table (tables ``both``), in the
    one-table order: positive rows in order, each with the negative rows in order."""
    pos = np.flatnonzero((col > 0) & both[tab])
    neg = np.flatnonzero((col < 0) & both[tab])
    if len(pos) == 0:
        return np.zeros((0, rows.shape[1]), dtype=np.int64), np.zeros(0, dtype=np.int64)
    first_neg = np.searchsorted(tab[neg], np.arange(len(both)))
    times = q[tab[pos]]
    a = np.repeat(pos, times)
    offsets = np.arange(int(times.sum())) - np.repeat(np.cumsum(times) - times, times)
    b = neg[np.repeat(first_neg[tab[pos]], times) + offsets]
    new = (-col[b])[:, None] * rows[a] + col[a][:, None] * rows[b]
    return new, tab[a]


def _minimal(new: np.ndarray, new_tab: np.ndarray, old: np.ndarray, old_tab: np.ndarray,
             closed: np.ndarray, closed_tab: np.ndarray, n_tables: int) -> np.ndarray:
    """Which new rows are minimal within their table, as
    :func:`~tegraph.analysis.invariants._minimal_new_supports` decides against the
    table's kept rows and semiflows (``old`` then ``closed``), all tables at once.

    The supports (0/1 floats, exact counts through BLAS) are padded to one
    array per kind, ``[table, row, place]``, for batched products.
    """
    both_old = np.vstack([old, closed])
    both_old_tab = np.concatenate([old_tab, closed_tab])
    tables = np.unique(new_tab)
    slot = np.full(n_tables, -1, dtype=np.int64)
    slot[tables] = np.arange(len(tables))
    new_pad, new_at, new_ok = _pad(new, slot[new_tab], len(tables))
    mine = slot[both_old_tab] >= 0
    old_pad, _, old_ok = _pad(both_old[mine], slot[both_old_tab[mine]], len(tables))
    old_size = old_pad.sum(axis=2)
    hits = np.matmul(new_pad, old_pad.transpose(0, 2, 1)) == old_size[:, None, :]
    bad = (hits & old_ok[:, None, :]).any(axis=2)
    new_size = new_pad.sum(axis=2)
    hits = np.matmul(new_pad, new_pad.transpose(0, 2, 1)) == new_size[:, None, :]
    # Dropped when it holds a new support smaller, or of equal size and earlier.
    width = new_pad.shape[1]
    key = new_size * width + np.arange(width)
    smaller = key[:, None, :] < key[:, :, None]
    bad |= (hits & smaller & new_ok[:, None, :]).any(axis=2)
    return ~bad[slot[new_tab], new_at]


def _pad(values: np.ndarray, group: np.ndarray, n_groups: int
         ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows grouped by ``group`` (sorted or not, order kept within a group) into a
    zero-padded ``[group, position, column]`` array; each row's position, and the mask
    of real entries."""
    order = np.argsort(group, kind="stable")
    counts = np.bincount(group, minlength=n_groups)
    width = int(counts.max(initial=0))
    position = np.empty(len(group), dtype=np.int64)
    position[order] = np.arange(len(group)) - np.repeat(np.cumsum(counts) - counts, counts)
    out = np.zeros((n_groups, width, values.shape[1]))
    out[group, position] = values
    ok = np.zeros((n_groups, width), dtype=bool)
    ok[group, position] = True
    return out, position, ok
