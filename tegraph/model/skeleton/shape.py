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
    def name(self) -> str: ...

    @property
    def unit(self) -> str: ...

    @property
    def tasks(self) -> Mapping[str, Task]: ...

    @property
    def clocks(self) -> Mapping[str, Clock]: ...

    @property
    def links(self) -> Sequence[Link]: ...

    @property
    def threads(self) -> Sequence[Sequence[str]]: ...

    @property
    def chains(self) -> Sequence[Sequence[str]]: ...

    @property
    def source(self) -> str | None: ...

    @property
    def extra(self) -> Mapping[str, Any]: ...

    @property
    def processors(self) -> Mapping[str, Processor]: ...

    @property
    def network_delay(self) -> Fraction | None: ...
