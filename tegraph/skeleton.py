"""The synchronization skeleton: module tasks, clocks, links and threads.

This is the in-memory form of a skeleton file (``docs/skeleton.md`` §1). A
design tool builds one in code with :meth:`Skeleton.from_dict` (the same
dictionary a YAML file holds) or from the dataclasses directly followed by
:meth:`Skeleton.validate`; both refuse what the file format refuses, with the
key path of the offending element.

Times are exact :class:`fractions.Fraction` values.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, Mapping

__all__ = ["Protocol", "Clock", "Task", "Link", "Skeleton"]


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
    def label(self) -> str:
        """``W:p -> R:q (PROTO)``, the link as the user wrote it."""
        return (
            f"{self.writer[0]}:{self.writer[1]} -> {self.reader[0]}:{self.reader[1]} "
            f"({self.protocol.value})"
        )


@dataclass
class Skeleton:
    """A synchronization skeleton (spec §1).

    Attributes
    ----------
    name : str
    unit : str
        Label of every time value (default ``"ms"``).
    clocks : dict of str to Clock
        All clocks, the private ``T.clock`` ones included, in file order.
    tasks : dict of str to Task
        In file order (groups and reports follow this order).
    links : list of Link
    threads : list of tuple of str
    source : str or None
        The file it was read from.
    chains : list of tuple of str
        Sensor-to-actuator chains of tasks for the latency report (spec §6).
    """

    name: str
    tasks: dict[str, Task]
    clocks: dict[str, Clock] = field(default_factory=dict)
    links: list[Link] = field(default_factory=list)
    threads: list[tuple[str, ...]] = field(default_factory=list)
    unit: str = "ms"
    source: str | None = field(default=None, compare=False)
    """Where it was read from: not part of the skeleton, so a copy read from
    another file (``load_skeleton(dump_skeleton(sk, path))``) compares equal."""
    extra: dict[str, Any] = field(default_factory=dict)
    """Keys of future format extensions; the writer refuses them (spec §6 keys
    have their own fields: ``Task.priority``, ``Task.processor``, ``chains``)."""
    chains: list[tuple[str, ...]] = field(default_factory=list)
    """Chains of tasks, sensor first, whose latency is reported (spec §6)."""

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], name: str = "skeleton",
                  source: str | None = None) -> "Skeleton":
        """Build and validate a skeleton from the dictionary a skeleton file holds.

        Parameters
        ----------
        data : mapping
            As in ``docs/skeleton.md`` §1.
        name : str
            Default name when ``data`` has no ``name`` key.
        source : str, optional
            File name to put in error messages.

        Returns
        -------
        Skeleton

        Raises
        ------
        SkeletonError
            With the key path of the first refused element.

        Examples
        --------
        >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 4}}})
        >>> sk.tasks["A"].clock, sk.clocks["A.clock"].period
        ('A.clock', Fraction(4, 1))
        """
        from .io.skeleton_file import skeleton_from_data

        return skeleton_from_data(data, default_name=name, source=source)

    def validate(self) -> "Skeleton":
        """Check the cross references of a skeleton built in code (spec §1).

        Returns the skeleton itself; raises :class:`~tegraph.errors.SkeletonError`.
        """
        from .io.skeleton_file import validate_skeleton

        validate_skeleton(self)
        return self

    def to_dict(self) -> dict[str, Any]:
        """The dictionary form (as written to a skeleton file), times as exact strings."""
        from .io.skeleton_file import skeleton_to_data

        return skeleton_to_data(self)

    def link_of_port(self, task: str, port: str) -> Link | None:
        """The link that ends or starts at ``task:port``, if any."""
        for link in self.links:
            if link.writer == (task, port) or link.reader == (task, port):
                return link
        return None
