"""Independent, exact check of a maximum-cycle-mean certificate of a dense matrix.

A claim ``λ = p / q`` (scaled integers, ``q > 0``) about an integer matrix
``W`` (``W[i][j]`` the weight of the arc ``j -> i``, only where ``finite``) is
proven by

1. a closed walk ``c_0 -> c_1 -> ... -> c_0`` of L arcs and weight S with
   ``S·q = p·L``: so some circuit has mean at least λ (a closed walk splits
   into circuits, one of mean at least the walk's);
2. integer potentials ``x`` with ``q·W[i][j] − p + x_j <= x_i`` on every arc:
   summed around any circuit of L arcs and weight S this gives
   ``q·S − p·L <= 0``, so no circuit has a mean above λ.

This is the potential argument behind Karp's theorem [1]_ and Howard's
termination test [2]_. The module trusts nothing of the solver (it imports
nothing of :mod:`maxplus` but the error class and the int64 bound) and
decides every inequality in integer arithmetic: int64 when the bound allows,
Python ints otherwise.

References
----------
.. [1] R. M. Karp, "A characterization of the minimum cycle mean in a
   digraph", Discrete Mathematics 23(3), 309–311, 1978.
.. [2] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
   J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
   algebra", IFAC Conference on System Structure and Control, 1998.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ._arrays import INT64_SAFE
from .errors import CertificateError

__all__ = ["check_mean_certificate", "check_mean_certificate_lists"]


def _abs_max(a: np.ndarray) -> int:
    if a.size == 0:
        return 0
    return max(abs(int(a.max())), abs(int(a.min())))


def _check_walk(weight_of: Callable[[int, int], int | None], n: int, p: int, q: int,
                walk: Sequence[int]) -> None:
    if q <= 0:
        raise CertificateError(f"the claimed mean {p}/{q} has a denominator <= 0")
    if not walk:
        raise CertificateError("a mean is claimed without a closed walk attaining it")
    total = 0
    for a, b in zip(walk, [*walk[1:], walk[0]]):
        if not (0 <= a < n and 0 <= b < n):
            raise CertificateError(f"node {a} or {b} of the claimed circuit is out of range")
        w = weight_of(b, a)  # the arc a -> b is the entry [b][a]
        if w is None:
            raise CertificateError(f"the claimed circuit uses {a} -> {b}, which is no arc")
        total += w
    if total * q != p * len(walk):
        raise CertificateError(
            f"the claimed circuit {list(walk)} has mean {total}/{len(walk)}, not {p}/{q}"
        )


def check_mean_certificate(values: np.ndarray, finite: np.ndarray, p: int, q: int,
                           potential: np.ndarray, walk: Sequence[int]) -> None:
    """Check ``λ = p/q`` for the integer matrix ``values`` (arcs where ``finite``).

    Parameters
    ----------
    values : numpy.ndarray, int64 or object, n × n
        Integer weights (entries where ``finite`` is False are ignored).
    finite : numpy.ndarray of bool, n × n
        ``finite[i, j]``: the arc ``j -> i`` exists.
    p, q : int
        The claimed maximum cycle mean ``p / q``, ``q > 0``.
    potential : numpy.ndarray of int, length n
    walk : sequence of int
        Nodes of a closed walk of mean ``p / q``, in order.

    Raises
    ------
    CertificateError
        Naming the arc or the walk where the proof fails.

    Examples
    --------
    >>> W = np.array([[1, 5], [3, 2]])
    >>> check_mean_certificate(W, W == W, 4, 1, np.array([0, -1]), [0, 1]) is None
    True
    """
    n = len(values)
    _check_walk(lambda i, j: int(values[i, j]) if finite[i, j] else None, n, p, q, walk)
    x = np.asarray(potential)
    if x.shape != (n,):
        raise CertificateError(f"expected {n} potentials, got shape {x.shape}")
    weights = np.where(finite, values, 0)
    big = q * _abs_max(weights) + abs(p) + 2 * _abs_max(x)
    narrow = big < INT64_SAFE and values.dtype != object and x.dtype != object
    dtype = np.int64 if narrow else object
    weights, x = weights.astype(dtype), x.astype(dtype)
    slack = x[:, None] - x[None, :] - q * weights + p  # >= 0 on every arc
    broken = finite & (slack < 0)
    if broken.any():
        i, j = (int(v) for v in np.argwhere(broken)[0])
        raise CertificateError(
            f"arc {j} -> {i} violates the potential inequality: some circuit through it "
            f"may have a mean above {p}/{q}"
        )


def check_mean_certificate_lists(rows: Sequence[Sequence[int | None]], p: int, q: int,
                                 potential: Sequence[int], walk: Sequence[int]) -> None:
    """:func:`check_mean_certificate` for a small matrix as lists (``None`` = no arc).

    Python ints throughout: exact for any size, and faster than numpy below
    a few hundred entries.

    Examples
    --------
    >>> check_mean_certificate_lists([[1, 5], [3, 2]], 4, 1, [0, -1], [0, 1]) is None
    True
    >>> check_mean_certificate_lists([[1, 5], [3, 2]], 4, 1, [0, 0], [0, 1])
    Traceback (most recent call last):
    ...
    maxplus.errors.CertificateError: arc 1 -> 0 violates the potential inequality: ...
    """
    n = len(rows)
    _check_walk(lambda i, j: rows[i][j], n, p, q, walk)
    if len(potential) != n:
        raise CertificateError(f"expected {n} potentials, got {len(potential)}")
    for i, (row, x_i) in enumerate(zip(rows, potential)):
        bound = x_i + p
        for j, (w, x_j) in enumerate(zip(row, potential)):
            if w is not None and q * w + x_j > bound:
                raise CertificateError(
                    f"arc {j} -> {i} violates the potential inequality: some circuit "
                    f"through it may have a mean above {p}/{q}"
                )
