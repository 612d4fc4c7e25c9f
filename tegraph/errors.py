"""Exceptions of the :mod:`tegraph` package.

A small hierarchy, as networkx has ``NetworkXNoCycle``: every error says where
the problem is (file, key path, element or circuit), so that the command line
can print one clear line and exit with status 2, and a design tool can point
at the offending element.
"""

from __future__ import annotations

from typing import Sequence

__all__ = ["TegraphError", "InputError", "SkeletonError", "ModelError", "NotLiveError"]


class TegraphError(Exception):
    """Base class of every error raised by :mod:`tegraph`."""


class InputError(TegraphError, ValueError):
    """The user's input is refused (exit status 2 on the command line).

    Attributes
    ----------
    file : str or None
        The file, when the input came from one.
    key_path : str
        Where in the document, e.g. ``tasks.MT2.inputs[1]`` (empty for the
        whole file).
    line : int or None
        1-based line in the file, when known.
    reason : str
        What is wrong and what is expected.
    """

    def __init__(
        self,
        reason: str,
        key_path: str = "",
        file: str | None = None,
        line: int | None = None,
    ) -> None:
        self.reason = reason
        self.key_path = key_path
        self.file = file
        self.line = line
        super().__init__(self._compose())

    def _compose(self) -> str:
        where = self.file or ""
        if self.line is not None and where:
            where += f":{self.line}"
        parts = [p for p in (where, self.key_path) if p]
        return ": ".join([*parts, self.reason])

    def with_file(self, file: str) -> "InputError":
        """Return the same error, located in ``file``."""
        self.file = file
        self.args = (self._compose(),)
        return self


class SkeletonError(InputError):
    """A synchronization skeleton breaks a rule of the file format (spec §1)."""


class ModelError(TegraphError, ValueError):
    """A timed event graph or net is malformed (unknown node, negative time...)."""

    def __init__(self, reason: str, element: str = "") -> None:
        self.element = element
        self.reason = reason
        super().__init__(f"{element}: {reason}" if element else reason)


class NotLiveError(TegraphError):
    """A quantity needs a live graph, but a circuit carries no token.

    Attributes
    ----------
    circuit : list of str
        Names of the events on the token-free circuit, in order.
    """

    def __init__(self, circuit: Sequence[str], what: str = "") -> None:
        self.circuit = list(circuit)
        path = " -> ".join([*self.circuit, self.circuit[0]]) if self.circuit else ""
        super().__init__(what or f"circuit {path} carries no token: it never fires")
