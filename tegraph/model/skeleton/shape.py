"""What the checks and the dictionary form read of a skeleton: the Protocol :class:`SkeletonShape`.

:class:`~tegraph.model.skeleton.core.Skeleton` has these attributes (a
dataclass field satisfies a read-only property). The checks
(:mod:`~tegraph.model.skeleton.checks`) and the schema
(:mod:`~tegraph.model.skeleton.schema`) are typed against this Protocol, not
against the class, so that the dependency goes one way: the class imports
them to validate itself, they never import the class, not even for types.
"""

from __future__ import annotations

# `typing.Protocol` is spelled in full: in this package `Protocol` is the link
# protocol of spec §1 (tegraph.model.elements.Protocol).
import typing
from collections.abc import Mapping, Sequence
from fractions import Fraction
from typing import Any

from ..elements import Clock, Link, Processor, Task

__all__ = ["SkeletonShape"]


class SkeletonShape(typing.Protocol):
    """The attributes of a skeleton that its checks and its dictionary form read.

    Read-only properties, so that the concrete containers of
    :class:`~tegraph.model.skeleton.core.Skeleton` (``dict``, ``list`` of
    ``tuple``) satisfy the abstract ones here.
    """

    @property
    def name(self) -> str:
        """The skeleton's name."""

    @property
    def unit(self) -> str:
        """The unit of every time (``ms`` by default)."""

    @property
    def tasks(self) -> Mapping[str, Task]:
        """Task name -> task, in file order."""

    @property
    def clocks(self) -> Mapping[str, Clock]:
        """Clock name -> clock."""

    @property
    def links(self) -> Sequence[Link]:
        """The links between ports, in file order."""

    @property
    def threads(self) -> Sequence[Sequence[str]]:
        """The declared threads, each a list of task names."""

    @property
    def chains(self) -> Sequence[Sequence[str]]:
        """The declared chains, each a list of task names."""

    @property
    def source(self) -> str | None:
        """The file it was read from (None: built in code)."""

    @property
    def extra(self) -> Mapping[str, Any]:
        """Keys of the file this version does not read, kept as given."""

    @property
    def processors(self) -> Mapping[str, Processor]:
        """Processor name -> its declared properties (``processors:``)."""

    @property
    def network_delay(self) -> Fraction | None:
        """``network.delay``: the delay of a link across processors (None: not declared)."""
