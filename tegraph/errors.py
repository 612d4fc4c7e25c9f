"""Exceptions of the :mod:`tegraph` package.

A small hierarchy, as networkx has ``NetworkXNoCycle``: every error says
*where* the problem is in one attribute, :attr:`TegraphError.where` (a key
path such as ``tasks.MT2.inputs[1]``, a model element such as
``place p3``, or a parameter name such as ``max_bytes``), so that the command
line can print one clear line and exit with status 2, and a design tool can
point at the offending element. Library messages name parameters, never
command-line flags: the command line translates.
"""

from __future__ import annotations

from collections.abc import Sequence

__all__ = ["InputError", "ModelError", "NotLiveError", "SkeletonError", "TegraphError"]


class TegraphError(Exception):
    """Base class of every error raised by :mod:`tegraph`.

    Attributes
    ----------
    where : str
        Where the problem is: a key path, an element or a parameter name
        (empty when it concerns the whole input).
    """

    where: str = ""


class InputError(TegraphError, ValueError):
    """The user's input is refused (exit status 2 on the command line).

    Parameters
    ----------
    reason : str
        What is wrong and what is expected.
    where : str
        Where in the document, e.g. ``tasks.MT2.inputs[1]`` (empty for the
        whole file), or the name of the refused parameter.
    file : str, optional
        The file, when the input came from one.
    line : int, optional
        1-based line in the file, when known.

    Examples
    --------
    >>> str(InputError("expected a number", "tasks.A.duration", "a.yaml", 3))
    'a.yaml:3: tasks.A.duration: expected a number'
    """

    def __init__(
        self,
        reason: str,
        where: str = "",
        file: str | None = None,
        line: int | None = None,
    ) -> None:
        self.reason = reason
        self.where = where
        self.file = file
        self.line = line
        super().__init__(self._compose())

    def _compose(self) -> str:
        location = self.file or ""
        if self.line is not None and location:
            location += f":{self.line}"
        parts = [p for p in (location, self.where) if p]
        return ": ".join([*parts, self.reason])

    def with_file(self, file: str) -> InputError:
        """Return the same error, located in ``file``."""
        self.file = file
        self.args = (self._compose(),)
        return self

    def with_where(self, where: str) -> InputError:
        """Return the same error, located at ``where`` (a caller's name for the place)."""
        self.where = where
        self.args = (self._compose(),)
        return self


class SkeletonError(InputError):
    """A synchronization skeleton breaks a rule of the file format (spec §1)."""


class ModelError(TegraphError, ValueError):
    """A timed event graph or net is malformed (unknown node, negative time...).

    Parameters
    ----------
    reason : str
    where : str
        The element at fault (``place p3``, ``transition t1``...).
    """

    def __init__(self, reason: str, where: str = "") -> None:
        self.where = where
        self.reason = reason
        super().__init__(f"{where}: {reason}" if where else reason)


class NotLiveError(TegraphError):
    """A quantity needs a live graph, but a circuit carries no token.

    Attributes
    ----------
    circuit : list of str
        Names of the events on the token-free circuit, in order.
    where : str
        The circuit, as ``a -> b -> a``.
    """

    def __init__(self, circuit: Sequence[str], what: str = "") -> None:
        self.circuit = list(circuit)
        self.where = " -> ".join([*self.circuit, self.circuit[0]]) if self.circuit else ""
        super().__init__(what or f"circuit {self.where} carries no token: it never fires")
