"""Transients of (max,+) matrices and trajectories: when periodicity starts.

For irreducible A, ``A^(t+c) = λ^c ⊗ A^t`` for all large t, with c the
cyclicity of the critical graph [1]_; :func:`transient` finds the smallest
such t, and decides exactly, for reducible A, whether that identity ever
holds [2]_. :func:`trajectory_transient` does the same for one trajectory
``x(k) = A^k ⊗ x0``. Convention as in the whole package: ``A[i][j]`` is the
weight of the arc ``j -> i``.

References
----------
.. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
   and Linearity*, Wiley, 1992, Thm 3.109.
.. [2] B. De Schutter, "On the ultimate behavior of the sequence of
   consecutive powers of a matrix in the max-plus algebra", Linear Algebra
   and its Applications 307, 103–117, 2000.
"""

from __future__ import annotations

import hashlib
from collections import deque
from fractions import Fraction
from typing import Any, NamedTuple

import numpy as np

from ._critical import CriticalGraph, critical_closure, cyclicity_of
from ._graphs import (
    adjacency,
    bool_product,
    cyclic_nodes,
    downstream,
    is_strongly_connected,
    reach_closure,
    strong_classes,
)
from ._integer_matrix import from_exact
from ._max_mean import cycle_times
from ._params import unmasked, whole_number
from ._scaled import identity_scaled, product_scaled, scale_together, scaled, square_matrix, times
from .errors import MaxPlusError, MaxPlusValueError, ReducibleMatrixError
from .scalar import EPS, exact_vector
from .spectral import karp

__all__ = ["TrajectoryPeriodicity", "trajectory_transient", "transient"]


class TrajectoryPeriodicity(NamedTuple):
    """``x(k + period) = period·rate ⊗ x(k)`` for every ``k >= transient``.

    Attributes
    ----------
    transient : int
        First step from which the trajectory is periodic.
    period : int
        Its period, in steps.
    rate : Fraction or None
        The growth per step, the cycle time (None when the trajectory
        stays at ε).

    See Also
    --------
    trajectory_transient : computes it for one initial state.
    transient : the transient of every initial state.

    Examples
    --------
    From ``x(0) = (0, 0)``: ``x(1) = (5, 3)``, ``x(2) = (8, 8) = 8 ⊗ x(0)``.

    >>> trajectory_transient([[1, 5], [3, 2]], [0, 0])
    TrajectoryPeriodicity(transient=0, period=2, rate=Fraction(4, 1))
    """

    transient: int
    period: int
    rate: Fraction | None




# --------------------------------------------------------------------------- transients


def _lasting_violation(adj: np.ndarray, marked: np.ndarray, start: np.ndarray,
                       budget: int) -> tuple[int, int, int, int] | None:
    """Decide whether, for all large t, every node reached from a start column by
    a walk of length t is also reached by a walk of length t through a marked node.

    Walks are tracked on two copies of the graph (not yet / already through a
    marked node). The pair of boolean matrices evolves deterministically, so
    once a state repeats (at t0 and t) the sequence is periodic from t0 and a
    violation at some time in [t0, t) recurs forever, while earlier ones die
    out. Returns None, or (node i, start column, time t, period p) of a
    violation that recurs at every t + m·p.
    """
    mark = marked[:, None]
    first = (start & ~mark, start & mark)

    def step(state: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        before, after = state
        moved_before = bool_product(adj, before)
        return moved_before & ~mark, bool_product(adj, after) | (moved_before & mark)

    def key(state: tuple[np.ndarray, np.ndarray]) -> bytes:
        raw = np.packbits(state[0]).tobytes() + np.packbits(state[1]).tobytes()
        return hashlib.blake2b(raw, digest_size=20).digest()

    seen: dict[bytes, int] = {}
    violations: list[tuple[int, int, int]] = []
    state = first
    for t in range(budget + 1):
        k = key(state)
        if k in seen:
            t0 = seen[k]
            replay = first
            for _ in range(t0):
                replay = step(replay)
            if all(np.array_equal(a, b) for a, b in zip(replay, state)):
                for when, i, col in violations:
                    if when >= t0:
                        return i, col, when, t - t0
                return None
        seen[k] = t
        bad = state[0] & ~state[1]
        if bad.any():
            i, col = np.argwhere(bad)[0]
            violations.append((t, int(i), int(col)))
        state = step(state)
    raise MaxPlusError(
        f"could not decide periodicity within max_steps={budget} steps; raise max_steps"
    )


def _check_matrix_periodicity(M: np.ndarray, graph: CriticalGraph) -> None:
    """Raise ReducibleMatrixError when ``A^(t+c) = λ^c ⊗ A^t`` holds for no t.

    Necessary: an entry fed only by circuits of mean < λ grows slower than kλ.
    Sufficient: applied to the pair (s, s), the condition puts a critical
    circuit in the class of every node s lying on a circuit; a walk of large
    length k spends a long stretch inside one class, and that stretch can be
    replaced by one of the same length through the class's critical circuit
    (in a strongly connected class all long enough lengths of the right residue
    modulo its period are realized through any given node). So for large k the
    best walk of every length is dominated by walks through the critical graph,
    whose weights are eventually λ-periodic with period c (cyclicity theorem,
    Baccelli et al. 1992, Thm 3.109; De Schutter 2000).
    """
    adj = adjacency(M)
    n = len(M)
    cyclic = cyclic_nodes(adj)
    critical = np.zeros(n, dtype=bool)
    critical[graph.nodes] = True
    R = reach_closure(adj)
    through_any = bool_product(R[:, cyclic], R[cyclic, :])
    through_critical = bool_product(R[:, critical], R[critical, :])
    bad = through_any & ~through_critical
    if bad.any():
        # A^k[i][j] then grows like the largest mean of the classes on the walks
        # j -> i, which is < λ: the ratio A^(k+c)[i][j] − A^k[i][j] never reaches cλ.
        i, j = (int(v) for v in np.argwhere(bad)[0])
        _, labels = strong_classes(adj)
        culprit = next(int(c) for c in np.flatnonzero(cyclic) if R[i, c] and R[c, j])
        members = np.flatnonzero(labels == labels[culprit]).tolist()
        mean = karp(M[np.ix_(members, members)])
        raise ReducibleMatrixError(
            f"A^(t+c) = λ^c ⊗ A^t holds for no t: the walks from node {j} to node {i} "
            f"pass through the class {members} (max cycle mean {mean}) but through no "
            f"critical circuit (mean λ = {graph.eigenvalue}), so A^k[{i}][{j}] grows "
            f"slower than kλ"
        )


def transient(A: Any, max_power: int = 10_000) -> int:
    """Smallest t >= 0 with ``A^(t+c) = λ^c ⊗ A^t``, c = :func:`~maxplus.spectral.cyclicity`.

    The identity then holds for every larger t (multiply by A). For
    irreducible A it holds eventually [1]_. For reducible A this
    is first decided exactly: it holds iff every pair (j, i) joined by a walk
    through some circuit is also joined by a walk through a circuit of mean λ
    (in particular every class with a circuit must contain a critical one).
    Without circuit (λ = ε), t is the least with ``A^(t+1) = ε``.

    Parameters
    ----------
    A : square matrix
    max_power : int
        Budget: the largest power of A (and the longest walk length in the
        decision) that may be examined.

    Returns
    -------
    int

    Raises
    ------
    MaxPlusValueError
        A bad entry or a non-square matrix.
    ReducibleMatrixError
        The identity holds for no t; the message names a pair of nodes (and
        the class whose circuits are all slower than λ).
    MaxPlusError
        The budget ``max_power`` is exceeded.

    See Also
    --------
    trajectory_transient : the same question for one trajectory.
    maxplus.spectral.cyclicity : the period c.
    maxplus.dense.power : the powers compared here.

    Notes
    -----
    Cyclicity theorem [1]_; for reducible matrices, the condition decided
    first is that of [2]_.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, Thm 3.109.
    .. [2] B. De Schutter, "On the ultimate behavior of the sequence of
       consecutive powers of a matrix in the max-plus algebra", Linear Algebra
       and its Applications 307, 103–117, 2000.

    Examples
    --------
    >>> transient([[3, 7], [2, 4]]), transient([[10, 0], [0, 9]])
    (2, 20)
    """
    max_power = whole_number(max_power, "max_power")
    M = square_matrix(A)
    graph = critical_closure(M)[0]
    n = len(M)
    c = cyclicity_of(graph)
    lam = graph.eigenvalue
    if lam is None:
        # Nilpotent: A^(t+1) = ε ⊗ A^t = ε for t >= the longest path length.
        S, _ = scaled(M, growth=n + 2)
        current = S  # A^(t+1)
        for t in range(n + 1):
            if np.all(current == -np.inf):
                return t
            current = product_scaled(current, S)
        raise AssertionError("an acyclic matrix is nilpotent of index <= n")
    if not is_strongly_connected(adjacency(M)):
        _check_matrix_periodicity(M, graph)
    shifted = np.empty(M.shape, dtype=object)
    shifted.reshape(-1)[:] = [times(v, -lam) for v in M.ravel().tolist()]
    # With N = A − λ the identity reads N^(t+c) = N^t; entries of N^t are sums
    # of t entries, so growth max_power keeps float64 exact.
    N, _ = scaled(shifted, growth=max_power + c + 2)
    window = deque([identity_scaled(n, N.dtype)])
    for _ in range(c):
        window.append(product_scaled(window[-1], N))
    t = 0
    while True:
        if np.all(np.asarray(window[0] == window[-1], dtype=bool)):
            return t
        if t + c >= max_power:
            raise MaxPlusError(
                f"the transient exceeds max_power={max_power}: A^(t+{c}) != λ^{c} ⊗ A^t "
                f"for every t <= {t}; raise max_power"
            )
        window.popleft()
        window.append(product_scaled(window[-1], N))
        t += 1


def trajectory_transient(A: Any, x0: Any, max_steps: int = 10_000) -> TrajectoryPeriodicity:
    """Smallest K, then smallest c, with ``x(k+c) = c·μ ⊗ x(k)`` for all k >= K,
    along ``x(k+1) = A ⊗ x(k)``, ``x(0) = x0``.

    Found as the first k with ``x(k) − kμ = x(K) − Kμ``; the identity then holds
    for every k >= K by homogeneity: ``x(k+c+1) = A ⊗ (cμ ⊗ x(k)) = cμ ⊗ x(k+1)``.
    ``μ`` is the growth rate of this trajectory: λ for irreducible A; for
    reducible A, the common cycle time of the nodes that x0 reaches through a
    circuit (an error when they differ); None when the trajectory dies out
    (becomes ε everywhere, then K is the first such k and c = 1).

    Parameters
    ----------
    A : square matrix
    x0 : vector
        Initial state, not ε everywhere.
    max_steps : int
        Budget on the number of steps simulated.

    Returns
    -------
    TrajectoryPeriodicity
        ``(transient K, period c, rate μ)``.

    Raises
    ------
    MaxPlusValueError
        A bad entry, a size mismatch, or ``x0`` ε everywhere.
    ReducibleMatrixError
        The trajectory never becomes periodic (nodes reached from x0 grow at
        different rates, or some residue of k grows slower than the rest).
    MaxPlusError
        The budget is exceeded.

    See Also
    --------
    transient : when the powers of A themselves turn periodic.
    maxplus.spectral.cycle_time_vector : the growth rate of every node.
    maxplus.implicit.simulate : trajectories of implicit systems.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, Thm 3.109 and §3.7 (periodic regime).
    .. [2] B. De Schutter, "On the ultimate behavior of the sequence of
       consecutive powers of a matrix in the max-plus algebra", Linear Algebra
       and its Applications 307, 103–117, 2000.

    Examples
    --------
    >>> trajectory_transient([[3, 7], [2, 4]], [0, 0])
    TrajectoryPeriodicity(transient=1, period=2, rate=Fraction(9, 2))
    """
    max_steps = whole_number(max_steps, "max_steps")
    M = square_matrix(A)
    n = len(M)
    x = exact_vector(unmasked(x0, "x0"), "x0")
    if len(x) != n:
        raise MaxPlusValueError(f"expected {n} entries to match A, got {len(x)}", "x0")
    support = np.array([v != EPS for v in x], dtype=bool)
    if not support.any():
        raise MaxPlusValueError("x0 is ε everywhere: the trajectory is trivially ε", "x0")
    adj = adjacency(M)
    nodes = np.flatnonzero(downstream(adj, support))
    sub = M[np.ix_(nodes, nodes)]
    rates = cycle_times(from_exact(sub))
    distinct = sorted({r for r in rates if r is not None})
    if len(distinct) > 1:
        slow = int(nodes[rates.index(distinct[0])])
        fast = int(nodes[rates.index(distinct[-1])])
        raise ReducibleMatrixError(
            f"the trajectory never becomes periodic: node {slow} grows at rate {distinct[0]} "
            f"and node {fast} at rate {distinct[-1]}"
        )
    rate = distinct[0] if distinct else None
    if rate is not None and not is_strongly_connected(adj):
        graph = critical_closure(sub)[0]
        marked = np.zeros(len(nodes), dtype=bool)
        marked[graph.nodes] = True
        found = _lasting_violation(adjacency(sub), marked, support[nodes][:, None], max_steps)
        if found is not None:
            i, _, t, p = found
            raise ReducibleMatrixError(
                f"the trajectory never becomes periodic: for every k ≡ {t % p} (mod {p}) "
                f"large enough, x_{int(nodes[i])}(k) only depends on walks avoiding the "
                f"circuits of mean {rate}, so it grows slower along those k"
            )
    vec = np.empty((n, 1), dtype=object)
    vec[:, 0] = x
    (S, X), scale = scale_together([M, vec], growth=max_steps + 2)
    num, den = (rate.numerator, rate.denominator) if rate is not None else (0, 1)
    state = X[:, 0]
    seen: dict[tuple[Any, ...], int] = {}
    for k in range(max_steps + 1):
        # x(k) − kμ, scaled by den so that everything stays an integer.
        key = tuple(v if v == -np.inf else int(v) * den - k * num * scale for v in state.tolist())
        if key in seen:
            return TrajectoryPeriodicity(seen[key], k - seen[key], rate)
        seen[key] = k
        state = (S + state[None, :]).max(axis=1)
    raise MaxPlusError(
        f"the trajectory is not periodic within max_steps={max_steps}; raise max_steps"
    )
