"""The checks and the dictionary form read a skeleton through SkeletonShape, not the class.

The import direction itself (core -> schema -> checks -> shape, type-only
imports included) is an import-linter contract of ``pyproject.toml``, run by
``tests/test_architecture.py``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import pytest

import tegraph
from tegraph.errors import SkeletonError
from tegraph.model.elements import Clock, Link, Processor, Protocol, Task
from tegraph.model.skeleton import Skeleton
from tegraph.model.skeleton.checks import Locator, check_chain, check_skeleton
from tegraph.model.skeleton.schema import skeleton_to_data
from tegraph.model.skeleton.shape import SkeletonShape


@dataclass(frozen=True)
class Shaped:
    """Not a Skeleton: only the attributes of SkeletonShape, in other containers."""

    name: str
    unit: str
    tasks: dict[str, Task]
    clocks: dict[str, Clock]
    links: tuple[Link, ...] = ()
    threads: tuple[tuple[str, ...], ...] = ()
    chains: tuple[tuple[str, ...], ...] = ()
    source: str | None = None
    extra: dict[str, Any] = field(default_factory=dict)
    processors: dict[str, Processor] = field(default_factory=dict)
    network_delay: Fraction | None = None


def _pair(protocol: Protocol = Protocol.ASYN_SYN) -> dict[str, Any]:
    # A (private clock, period 4) writes x (and y); B (no clock) reads x.
    return dict(
        name="s", unit="ms",
        tasks={"A": Task("A", Fraction(1), "A.clock", outputs=("x", "y")),
               "B": Task("B", Fraction(2), None, inputs=("x",))},
        clocks={"A.clock": Clock("A.clock", Fraction(4), private=True)},
        links=(Link(("A", "x"), ("B", "x"), protocol),),
        chains=(("A", "B"),))


def test_every_attribute_of_the_shape_is_a_field_of_the_skeleton():
    # No type checker runs yet: a renamed field would leave the Protocol stale.
    shape = {name for name, v in vars(SkeletonShape).items() if isinstance(v, property)}
    assert shape == {"name", "unit", "tasks", "clocks", "links", "threads", "chains",
                     "source", "extra", "processors", "network_delay"}
    assert shape <= {f.name for f in dataclasses.fields(Skeleton)}


def test_checks_and_writer_take_any_object_of_the_shape():
    shaped = Shaped(**_pair())
    check_skeleton(shaped, Locator())
    assert check_chain(shaped, ["A", "B"], ("chains", 0), Locator()) == ("A", "B")
    # Written as the class writes itself: the shape is all the writer reads.
    assert skeleton_to_data(shaped) == Skeleton(**{**_pair(), "links": list(_pair()["links"]),
                                                   "chains": [("A", "B")]}).to_dict()


def test_a_broken_shape_gets_the_message_a_broken_skeleton_gets():
    # B:x is read from A:x, and a second link writes it from A:y: one writer per input port.
    fields = _pair()
    fields["links"] = (*fields["links"], Link(("A", "y"), ("B", "x"), Protocol.SYN_SYN))
    with pytest.raises(SkeletonError) as shaped:
        check_skeleton(Shaped(**fields), Locator())
    with pytest.raises(SkeletonError) as real:
        Skeleton(**{**fields, "links": list(fields["links"])}).validate()
    assert str(shaped.value) == str(real.value)
    assert shaped.value.where == "links[1].to"


def test_the_public_names_still_resolve_to_the_class():
    from tegraph.model.skeleton import Clock as C
    from tegraph.model.skeleton import Protocol as P

    assert tegraph.Skeleton is Skeleton and C is Clock and P is Protocol


def test_a_links_label_is_made_once_and_leaves_equality_alone():
    # The label is cached in the instance (elements.Link.label); a link that
    # was asked for it must still equal, hash and replace like one that was not.
    asked = Link(("A", "x"), ("B", "y"), Protocol.SYN_SYN)
    fresh = Link(("A", "x"), ("B", "y"), Protocol.SYN_SYN)
    assert asked.label is asked.label
    assert asked.label == "A:x -> B:y (SYN/SYN)"  # the text by hand
    assert asked == fresh and hash(asked) == hash(fresh)
    changed = dataclasses.replace(asked, protocol=Protocol.ASYN_ASYN)
    assert changed.label == "A:x -> B:y (ASYN/ASYN)"
