"""Exceptions of the :mod:`maxplus` package.

Every error carries *where* the problem is: the offending entry of an input,
or the circuit (as node or arc indices) that makes a quantity undefined.
"""

from __future__ import annotations

from collections.abc import Sequence

__all__ = [
    "MaxPlusError",
    "MaxPlusValueError",
    "PositiveCircuitError",
    "ZeroTokenCircuitError",
    "ReducibleMatrixError",
    "CertificateError",
]


class MaxPlusError(Exception):
    """Base class of every error raised by :mod:`maxplus`."""


class MaxPlusValueError(MaxPlusError, ValueError):
    """An input is malformed: ragged, non-square, NaN, +inf, text that is no number.

    Attributes
    ----------
    where : str
        The offending entry, e.g. ``"A[1][2]"`` or ``"tokens[7]"``.
    """

    def __init__(self, message: str, where: str = "") -> None:
        self.where = where
        super().__init__(f"{where}: {message}" if where else message)


class PositiveCircuitError(MaxPlusError):
    """The Kleene star diverges: the graph has a circuit of positive weight.

    Attributes
    ----------
    circuit : list of int
        Nodes of the circuit in order, ``circuit[0] -> circuit[1] -> ...``.
    weight : Fraction
        Its total weight.
    """

    def __init__(self, circuit: Sequence[int], weight: object) -> None:
        self.circuit = list(circuit)
        self.weight = weight
        path = " -> ".join(str(i) for i in [*self.circuit, self.circuit[0]])
        super().__init__(
            f"the star diverges: circuit {path} has positive weight {weight}"
        )


class ZeroTokenCircuitError(MaxPlusError, ValueError):
    """A circuit carries no token, so its cycle ratio is infinite (a deadlock).

    Attributes
    ----------
    circuit : list
        The arcs of the circuit, in order: arc indices for arc arrays, matrix
        entries ``(i, j)`` (the arc ``j -> i``) for a matrix.
    nodes : list of int
        Nodes visited, ``nodes[i]`` is the source of ``circuit[i]``.
    """

    def __init__(self, circuit: Sequence[int] | Sequence[tuple[int, int]], nodes: Sequence[int],
                 what: str = "") -> None:
        self.circuit: list[int | tuple[int, int]] = list(circuit)
        self.nodes = list(nodes)
        path = " -> ".join(str(i) for i in [*self.nodes, self.nodes[0]])
        super().__init__(
            what or f"circuit {path} (arcs {self.circuit}) carries no token: "
            "its cycle ratio is infinite"
        )


class ReducibleMatrixError(MaxPlusError, ValueError):
    """An operation defined for irreducible matrices only got a reducible one."""


class CertificateError(MaxPlusError):
    """A certificate does not prove the value it claims."""
