"""Implicit (max,+) state equations and their explicit first-order form.

Convention (the whole package): ``A[i][j]`` is the weight of the arc ``j -> i``
and ε = -inf. An implicit system of order p is

    x(k) = A0 ⊗ x(k) ⊕ A1 ⊗ x(k−1) ⊕ ... ⊕ Ap ⊗ x(k−p) ⊕ B ⊗ u(k),

the dater equation of a timed event graph in which ``Al[i][j]`` is the
largest holding time of a place ``j -> i`` with l initial tokens [1]_.
``A0`` (places without token) must have no circuit at all: a circuit in
``A0`` is a set of transitions each waiting for the previous one *in the
same firing*, a deadlock. Then ``A0* = E ⊕ A0 ⊕ ... ⊕ A0^(n−1)`` and

    x(k) = A0*A1 ⊗ x(k−1) ⊕ ... ⊕ A0*Ap ⊗ x(k−p) ⊕ A0*B ⊗ u(k)

[1]_ [2]_. For p > 1 the augmented state ``X(k) = [x(k); x(k−1); ...;
x(k−p+1)]`` obeys the first-order equation ``X(k) = Â ⊗ X(k−1) ⊕ B̂ ⊗ u(k)``
with the companion matrix ``Â`` (first block row ``A0*A1 ... A0*Ap``,
identity blocks E below the diagonal).

References
----------
.. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
   and Linearity*, Wiley, 1992, §2.5, §2.5.4 and Thm 3.17.
.. [2] B. De Schutter, *Max-Algebraic System Theory for Discrete Event
   Systems*, PhD thesis, K.U.Leuven, 1996.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np

from ._arrays import find_circuit
from ._params import unmasked
from ._scaled import as_exact, product_scaled, rank_of, scale_together
from .dense import otimes, star
from .errors import MaxPlusValueError, ZeroTokenCircuitError
from .scalar import EPS, Scalar, exact_matrix, exact_vector

__all__ = ["ExplicitSystem", "simulate", "to_explicit"]


@dataclass(frozen=True)
class ExplicitSystem:
    """First-order explicit form ``X(k) = A ⊗ X(k−1) ⊕ B ⊗ u(k)``.

    Attributes
    ----------
    A : numpy.ndarray of dtype object
        (n·p) × (n·p) companion matrix; for p = 1 simply ``A0* ⊗ A1``.
    B : numpy.ndarray of dtype object or None
        (n·p) × m input matrix ``[A0* ⊗ B; ε; ...]`` (None without input).
    order : int
        p, the largest delay.
    n_states : int
        n, the size of the original state; ``X(k)[l·n:(l+1)·n] = x(k−l)``.

    See Also
    --------
    to_explicit : computes it.
    simulate : runs the implicit system directly.

    Examples
    --------
    >>> e = to_explicit([[None, None], [1, None]], [[2, None], [None, 3]])
    >>> e.order, e.n_states, e.A.tolist()
    (1, 2, [[Fraction(2, 1), -inf], [Fraction(3, 1), Fraction(3, 1)]])
    """

    A: np.ndarray
    B: np.ndarray | None
    order: int
    n_states: int


def _refuse_circuit(A0: np.ndarray) -> None:
    rows, cols = np.nonzero(np.asarray(A0 != EPS, dtype=bool))
    src, dst = cols.astype(np.int64), rows.astype(np.int64)
    arcs = find_circuit(src, dst, len(A0))
    if arcs:
        nodes = src[arcs].tolist()
        entries = ", ".join(f"A0[{int(dst[a])}][{int(src[a])}]" for a in arcs)
        path = " -> ".join(str(v) for v in [*nodes, nodes[0]])
        raise ZeroTokenCircuitError(
            [(int(dst[a]), int(src[a])) for a in arcs], nodes,
            f"A0 has the circuit {path} (entries {entries}): x(k) would wait for "
            "itself at the same k, a deadlock; A0* is defined only without circuit",
        )


def _validate(matrices: Sequence[Any], B: Any) -> tuple[list[np.ndarray], np.ndarray | None]:
    mats = [exact_matrix(unmasked(M, f"A{lag}"), f"A{lag}", square=True)
            for lag, M in enumerate(matrices)]
    n = len(mats[0])
    for lag, M in enumerate(mats):
        if len(M) != n:
            raise MaxPlusValueError(f"expected {n}x{n} like A0, got {len(M)}x{len(M)}", f"A{lag}")
    inputs = None
    if B is not None:
        inputs = exact_matrix(unmasked(B, "B"), "B", square=False)
        if len(inputs) != n:
            raise MaxPlusValueError(f"expected {n} rows like A0, got {len(inputs)}", "B")
    _refuse_circuit(mats[0])
    return mats, inputs


def to_explicit(A0: Any, A1: Any, *higher: Any, B: Any = None) -> ExplicitSystem:
    """Explicit first-order form of ``x(k) = A0 x(k) ⊕ A1 x(k−1) ⊕ ... ⊕ B u(k)``.

    Parameters
    ----------
    A0 : square matrix
        Same-instant dependencies; must have no circuit.
    A1, *higher : square matrices
        ``Al`` multiplies ``x(k−l)``; p = 1 + len(higher).
    B : matrix, optional
        n × m input matrix.

    Returns
    -------
    ExplicitSystem
        ``.A`` (``A0* ⊗ A1`` when p = 1, the companion matrix otherwise),
        ``.B`` (``A0* ⊗ B`` padded with ε rows), ``.order``, ``.n_states``.

    Raises
    ------
    MaxPlusValueError
        A bad entry (named) or mismatched sizes.
    ZeroTokenCircuitError
        ``A0`` has a circuit; ``.nodes`` lists it and the message names its entries.

    See Also
    --------
    simulate : the dater trajectory of the same system.
    maxplus.dense.star : ``A0*``.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, Thm 3.17 and §2.5.4.
    .. [2] B. De Schutter, *Max-Algebraic System Theory for Discrete Event
       Systems*, PhD thesis, K.U.Leuven, 1996.

    Examples
    --------
    >>> s = to_explicit([[None, None], [1, None]], [[2, None], [None, 3]], B=[[0], [None]])
    >>> s.A.tolist(), s.B.tolist()
    ([[Fraction(2, 1), -inf], [Fraction(3, 1), Fraction(3, 1)]], [[Fraction(0, 1)], [Fraction(1, 1)]])
    """  # noqa: E501
    mats, inputs = _validate([A0, A1, *higher], B)
    n, p = len(mats[0]), len(mats) - 1
    closure = star(mats[0])  # no circuit, so no PositiveCircuitError
    blocks = [otimes(closure, M) for M in mats[1:]]
    big = np.full((n * p, n * p), EPS, dtype=object)
    for lag, block in enumerate(blocks):
        big[:n, lag * n:(lag + 1) * n] = block
    for lag in range(1, p):
        # x(k−lag) in X(k) is x(k−1−(lag−1)) in X(k−1): an identity block.
        for i in range(n):
            big[lag * n + i, (lag - 1) * n + i] = Fraction(0)
    big_b = None
    if inputs is not None:
        big_b = np.full((n * p, inputs.shape[1]), EPS, dtype=object)
        big_b[:n] = otimes(closure, inputs)
    return ExplicitSystem(big, big_b, p, n)


def _initial_states(initial: Any, n: int, p: int) -> list[list[Scalar]]:
    """``[x(0), x(−1), ..., x(1−p)]``, missing ones ε."""
    if initial is None:
        return [[EPS] * n for _ in range(p)]
    if rank_of(initial) == 1:
        given = [exact_vector(unmasked(initial, "initial"), "initial")]
    elif rank_of(initial) == 2:
        given = [exact_vector(unmasked(v, f"initial[{k}]"), f"initial[{k}]")
                 for k, v in enumerate(initial)]
    else:
        raise MaxPlusValueError("expected x(0) or a list [x(0), x(-1), ...]", "initial")
    if len(given) > p:
        raise MaxPlusValueError(f"expected at most {p} initial states (order p={p}), "
                                f"got {len(given)}", "initial")
    for k, v in enumerate(given):
        if len(v) != n:
            raise MaxPlusValueError(f"expected {n} entries, got {len(v)}", f"initial[{k}]")
    return given + [[EPS] * n for _ in range(p - len(given))]


def simulate(A0: Any, A1: Any, *higher: Any, B: Any = None, initial: Any = None,
             inputs: Any = None, steps: int | None = None) -> np.ndarray:
    """Dater trajectory ``x(0), x(1), ..., x(steps)`` of an implicit system, exact.

    ``x(k) = A0 x(k) ⊕ A1 x(k−1) ⊕ ... ⊕ Ap x(k−p) ⊕ B u(k)`` for k >= 1,
    computed through :func:`to_explicit`.

    Parameters
    ----------
    A0, A1, *higher : square matrices
        As in :func:`to_explicit`.
    B : matrix, optional
        n × m input matrix (required with ``inputs``).
    initial : vector or list of vectors, optional
        ``x(0)``, or ``[x(0), x(−1), ..., x(1−p)]``; missing ones are ε
        (default: ε everywhere).
    inputs : vector or matrix, optional
        A vector of length m: the same ``u(k)`` for every k; a matrix of
        ``steps`` rows: row ``k−1`` is ``u(k)``. ε input when omitted.
    steps : int, optional
        Number of steps (default: the number of rows of ``inputs``).

    Returns
    -------
    numpy.ndarray of dtype object
        (steps + 1) × n; row k is ``x(k)`` (row 0 is the given ``x(0)``).

    Raises
    ------
    MaxPlusValueError
        A bad entry, mismatched sizes, or a missing ``steps`` / ``B``.
    ZeroTokenCircuitError
        ``A0`` has a circuit.

    See Also
    --------
    to_explicit : the explicit first-order form used here.
    maxplus.transient.trajectory_transient : when such a trajectory turns periodic.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992, §2.5.
    .. [2] B. De Schutter, *Max-Algebraic System Theory for Discrete Event
       Systems*, PhD thesis, K.U.Leuven, 1996 (max-plus-linear systems with inputs).

    Examples
    --------
    Two machines (rates 5 and 6) feed an assembly step (De Schutter [2]_):

    >>> A0 = [[None, None, None], [None, None, None], [6, 6, None]]
    >>> A1 = [[5, None, None], [None, 6, None], [None, None, 3]]
    >>> x = simulate(A0, A1, B=[[2], [0], [None]], inputs=[0], steps=3)
    >>> [[int(v) for v in row] for row in x[1:]]
    [[2, 0, 8], [7, 6, 13], [12, 12, 18]]
    """
    system = to_explicit(A0, A1, *higher, B=B)
    n, p = system.n_states, system.order
    if steps is not None and (isinstance(steps, bool) or not isinstance(steps, (int, np.integer))
                              or steps < 0):
        raise MaxPlusValueError(f"expected a non-negative integer, got {steps!r}", "steps")
    u_rows: np.ndarray | None = None
    if inputs is not None:
        if system.B is None:
            raise MaxPlusValueError("inputs need an input matrix B", "B")
        m = system.B.shape[1]
        if rank_of(inputs) == 1:
            row = exact_vector(unmasked(inputs, "inputs"), "inputs")
            if len(row) != m:
                raise MaxPlusValueError(f"expected {m} inputs like the columns of B, "
                                        f"got {len(row)}", "inputs")
            if steps is None:
                raise MaxPlusValueError("a constant input needs the number of steps", "steps")
            u_rows = np.empty((steps, m), dtype=object)
            for k in range(steps):
                u_rows[k] = row
        else:
            u_rows = exact_matrix(unmasked(inputs, "inputs"), "inputs", square=False)
            if u_rows.shape[1] != m:
                raise MaxPlusValueError(f"expected {m} columns like B, got {u_rows.shape[1]}",
                                        "inputs")
            steps = len(u_rows) if steps is None else steps
            if len(u_rows) < steps:
                raise MaxPlusValueError(f"expected {steps} rows (one u(k) per step), "
                                        f"got {len(u_rows)}", "inputs")
    if steps is None:
        raise MaxPlusValueError("the number of steps is missing", "steps")
    steps = int(steps)
    state = np.empty((n * p, 1), dtype=object)
    state[:, 0] = [v for x in _initial_states(initial, n, p) for v in x]
    operands = [system.A, state]
    if u_rows is not None and steps:
        assert system.B is not None
        operands += [system.B, u_rows[:steps].T.copy()]
    # Every value is a sum of at most steps+1 matrix entries and one initial or
    # input value: that growth keeps the float64 path exact.
    scaled, scale = scale_together(operands, growth=steps + 3)
    big_a, current = scaled[0], scaled[1]
    out = np.empty((steps + 1, n), dtype=current.dtype)
    out[0] = current[:n, 0]
    for k in range(1, steps + 1):
        current = product_scaled(big_a, current)
        if len(scaled) > 2:
            drive = product_scaled(scaled[2], scaled[3][:, k - 1:k])
            current = np.maximum(current, drive)
        out[k] = current[:n, 0]
    return as_exact(out, scale)
