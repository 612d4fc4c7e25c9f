"""The elements of a synchronization skeleton: protocols, clocks, tasks and links.

Plain frozen dataclasses (``docs/skeleton.md`` §1); the skeleton that holds
them is :class:`tegraph.model.skeleton.Skeleton`. Times are exact
:class:`fractions.Fraction` values.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from fractions import Fraction

__all__ = ["Clock", "Link", "LinkLabel", "Protocol", "Task"]


class Protocol(enum.Enum):
    """Link protocol, writer side first (spec §1)."""

    ASYN_ASYN = "ASYN/ASYN"
    ASYN_SYN = "ASYN/SYN"
    SYN_ASYN = "SYN/ASYN"
    SYN_SYN = "SYN/SYN"

    @property
    def synchronizing(self) -> bool:
        """True when the link adds a place or merges events (not ASYN/ASYN)."""
        return self is not Protocol.ASYN_ASYN


@dataclass(frozen=True)
class Clock:
    """A real-time clock: ticks at ``phase + (k-1) * period``, k >= 1."""

    name: str
    period: Fraction
    phase: Fraction = Fraction(0)
    private: bool = False
    """True for the clock ``T.clock`` made by a task's ``period:`` shorthand."""


@dataclass(frozen=True)
class Task:
    """A module task: read inputs in order, compute, write outputs in order.

    ``priority`` and ``processor`` are the optional scheduling attributes of
    spec §6 (a larger priority is more urgent; ``None``: not declared, all
    such tasks share one default processor). The timed event graph ignores them.
    """

    name: str
    duration: Fraction
    clock: str | None = None
    inputs: tuple[str, ...] = ()
    outputs: tuple[str, ...] = ()
    priority: int | None = None
    processor: str | None = None


@dataclass(frozen=True)
class Link:
    """A link from the output port ``writer`` to the input port ``reader``.

    Ports are ``(task, port)`` pairs.
    """

    writer: tuple[str, str]
    reader: tuple[str, str]
    protocol: Protocol

    @property
    def label(self) -> LinkLabel:
        """``W:p -> R:q (PROTO)``, the link as the user wrote it."""
        return LinkLabel(self.writer, self.reader, self.protocol)


class LinkLabel(str):
    """A link's text ``W:p -> R:q (PROTO)`` that also knows its two ports and protocol.

    Findings, deadlocks and latency hops name links by this text in reports
    and messages; the JSON reports give each as an object (:meth:`document`),
    which a reader need not parse. Task and port names may hold any character
    but ``:``, so the text alone is not always unambiguous.

    Examples
    --------
    >>> label = LinkLabel(("A", "x"), ("B", "y"), Protocol.ASYN_SYN)
    >>> label, label.document()
    ('A:x -> B:y (ASYN/SYN)', {'from': 'A:x', 'to': 'B:y', 'protocol': 'ASYN/SYN'})
    """

    __slots__ = ("writer", "reader", "protocol")
    writer: tuple[str, str]
    reader: tuple[str, str]
    protocol: Protocol

    def __new__(cls, writer: tuple[str, str], reader: tuple[str, str],
                protocol: Protocol) -> LinkLabel:
        text = f"{writer[0]}:{writer[1]} -> {reader[0]}:{reader[1]} ({protocol.value})"
        self = super().__new__(cls, text)
        self.writer, self.reader, self.protocol = writer, reader, protocol
        return self

    def __reduce__(self) -> tuple:
        # Results travel between processes (tegraph explore on Dask workers).
        return (LinkLabel, (self.writer, self.reader, self.protocol))

    def document(self) -> dict[str, str]:
        """``{"from": "W:p", "to": "R:q", "protocol": "PROTO"}``, as the skeleton file writes it."""
        return {"from": ":".join(self.writer), "to": ":".join(self.reader),
                "protocol": self.protocol.value}
