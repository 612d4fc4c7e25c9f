"""The choices of ``explore``: which protocols a link may take, which periods a clock.

Each chosen link (named ``W:p -> R:q``, :func:`~tegraph.model.elements.link_name`)
carries the protocols it may take (:class:`LinkChoice`), each chosen clock its candidate periods
(:class:`ClockChoice`), read from the forms :func:`~.space.design_space` accepts
and checked against the skeleton. A choice is refused with an
:class:`~tegraph.errors.InputError` whose ``where`` names the parameter and the
entry (``links[1]``, ``clocks.rtc[0]``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import Any

from maxplus.scalar import exact_text, exact_time

from ...errors import InputError
from ...model.elements import link_name
from ...model.platform import link_delay
from ...model.skeleton import Protocol, Skeleton

__all__ = [
    "ClockChoice",
    "LinkChoice",
    "parse_clock_choice",
    "parse_link_choice",
    "parse_protocol",
]

_ALL = tuple(Protocol)
_PROTOCOLS = ", ".join(p.value for p in Protocol)


def parse_protocol(text: Any, where: str) -> Protocol:
    """A protocol from its text, case-insensitive, ``-`` for ``/`` (spec §1).

    >>> parse_protocol("asyn-syn", "links[0]")
    <Protocol.ASYN_SYN: 'ASYN/SYN'>
    """
    if isinstance(text, Protocol):
        return text
    spelled = "".join(str(text).split()).upper().replace("-", "/")
    for protocol in Protocol:
        if protocol.value == spelled:
            return protocol
    raise InputError(f"unknown protocol {text!r}; expected one of {_PROTOCOLS} "
                     "(case-insensitive, '-' may stand for '/')", where)


def parse_link_choice(text: str) -> tuple[str, tuple[str, ...] | None]:
    """``"W:p -> R:q=ASYN/SYN,SYN/SYN"`` -> (``"W:p -> R:q"``, protocols); no ``=``: all four.

    >>> parse_link_choice("MT1:x1->MT2:x1 = asyn/syn, SYN/SYN")
    ('MT1:x1 -> MT2:x1', ('asyn/syn', 'SYN/SYN'))
    >>> parse_link_choice("MT1:x1 -> MT2:x1")
    ('MT1:x1 -> MT2:x1', None)
    """
    link, equals, protocols = text.partition("=")
    writer, arrow, reader = link.partition("->")
    label = f"{writer.strip()} -> {reader.strip()}" if arrow else link.strip()
    if not equals:
        return label, None
    return label, tuple(p.strip() for p in protocols.split(","))


def parse_clock_choice(text: str) -> tuple[str, tuple[str, ...]]:
    """``"rtc=5,10,20"`` -> (``"rtc"``, periods as written).

    >>> parse_clock_choice("MT2.clock = 5, 7/2")
    ('MT2.clock', ('5', '7/2'))
    """
    name, _, periods = text.partition("=")
    return name.strip(), tuple(p.strip() for p in periods.split(",")) if periods.strip() else ()


@dataclass(frozen=True)
class LinkChoice:
    """A chosen link: its index in ``skeleton.links``, its name and the protocols allowed."""

    index: int
    label: str
    protocols: tuple[Protocol, ...]
    narrowed: bool = field(default=False, compare=False)
    """Given by ``links`` with fewer protocols than ``all_links`` gives the other links
    (the report says so; not part of the fingerprint)."""
    delay: Fraction = field(default=Fraction(0), compare=False)
    """The link's delay (spec §4d) where it left SYN/SYN out of ``protocols`` (a
    rendezvous is one event, which no delay separates; the report says so); else 0."""


@dataclass(frozen=True)
class ClockChoice:
    """A chosen clock: its name and its candidate periods (exact, > 0)."""

    name: str
    periods: tuple[Fraction, ...]


def _time(text: Any, where: str, what: str) -> Fraction:
    """A time > 0 read by the one exact-number parser of the files (digit bound included):
    a clock's candidate period here, a constraint's period or latency in :mod:`.objectives`."""
    try:
        value = exact_time(text if isinstance(text, str | int | Fraction) else str(text), where)
    except (ValueError, ArithmeticError, TypeError) as exc:
        said = str(exc).removeprefix(f"{where}: ")
        raise InputError(f"expected {what} > 0 such as 10, 2.5 or 7/3; {said}", where) from None
    if value <= 0:
        raise InputError(f"expected {what} > 0 such as 10, 2.5 or 7/3, got {text!r}", where)
    return value


def _link_choices(skeleton: Skeleton, links: Mapping[str, Sequence[Any] | None] | Sequence[str],
                  all_links: bool, forbidden: tuple[Protocol, ...], placed: bool = False
                  ) -> dict[int, LinkChoice]:
    """The chosen links by index, each with its allowed protocols less ``forbidden``
    (see :func:`~.space.design_space` for the forms of ``links`` and the errors); SYN/SYN left
    out where the link has a delay: where tasks run is a choice (``placed``), only its
    own (whether it crosses, and so takes the network's, is the variant's: a rendezvous
    across processors is rejected there)."""
    by_label = {link_name(k.writer, k.reader): i for i, k in enumerate(skeleton.links)}
    if isinstance(links, Mapping):
        items = [(str(label), protocols) for label, protocols in links.items()]
    else:  # "W:p -> R:q" or "W:p -> R:q=P1,P2" texts
        items = [parse_link_choice(str(text)) for text in links]
    chosen: dict[int, LinkChoice] = {}
    first: dict[int, str] = {}
    for k, (label, protocols) in enumerate(items):
        where = f"links[{k}]"
        name, _ = parse_link_choice(label)
        if name not in by_label:
            known = ", ".join(list(by_label)[:8]) + (", ..." if len(by_label) > 8 else "")
            raise InputError(f"no link {name!r} in the skeleton; expected \"WRITER:PORT -> "
                             f"READER:PORT\" of one of its links ({known or 'none'})", where)
        index = by_label[name]
        if index in chosen:
            raise InputError(f"the link {name!r} is chosen twice, by `links`{first[index][5:]} "
                             f"and `links`{where[5:]}; expected each link once (the second "
                             "would silently replace the first)", where)
        first[index] = where
        chosen[index] = LinkChoice(index, name, _allowed(name, protocols, forbidden, where))
    if all_links:
        left = tuple(p for p in _ALL if p not in forbidden)
        if not left:
            raise InputError("every protocol is forbidden; expected at least one left",
                             "forbid")
        # `links` narrows `all_links` for the links it names (the one way to vary every
        # link but restrict some): kept, and marked so that the report says it.
        for i, c in chosen.items():
            if set(c.protocols) < set(left):
                chosen[i] = replace(c, narrowed=True)
        for i, link in enumerate(skeleton.links):
            chosen.setdefault(i, LinkChoice(i, link_name(link.writer, link.reader), left))
    for i, c in chosen.items():
        link = skeleton.links[i]
        delay = (link.effective_delay(False, skeleton.network_delay) if placed
                 else link_delay(skeleton, link))
        if delay and Protocol.SYN_SYN in c.protocols:
            kept = tuple(p for p in c.protocols if p is not Protocol.SYN_SYN)
            if not kept:
                raise InputError(
                    f"the link {c.label!r} has a delay of {exact_text(delay)} {skeleton.unit} "
                    "(spec §4d), which a rendezvous cannot have (it is one event of both "
                    "tasks); expected a protocol besides SYN/SYN", "links")
            chosen[i] = replace(c, protocols=kept, delay=delay)
    for i, link in enumerate(skeleton.links):
        if i not in chosen and link.protocol in forbidden:
            raise InputError(f"the link {link_name(link.writer, link.reader)!r} is "
                             f"{link.protocol.value} in the skeleton and not chosen, so every "
                             "design would use the forbidden protocol; expected the link "
                             "chosen (`links`, or all_links)", "forbid")
    return chosen


def _allowed(name: str, protocols: Any, forbidden: tuple[Protocol, ...], where: str
             ) -> tuple[Protocol, ...]:
    """The protocols one link may take: those given (all four for None), less ``forbidden``."""
    if protocols is None:
        allowed = _ALL
    else:
        if isinstance(protocols, str | Protocol):
            protocols = [protocols]
        allowed = tuple(dict.fromkeys(parse_protocol(p, where) for p in protocols))
        if not allowed:
            raise InputError(f"no protocol allowed for {name!r}; expected at least one "
                             f"of {_PROTOCOLS}", where)
    kept = tuple(p for p in allowed if p not in forbidden)
    if not kept:
        raise InputError(f"every protocol allowed for {name!r} is forbidden by `forbid`; "
                         "expected a choice with a protocol left", where)
    return kept


def _clock_choices(skeleton: Skeleton, clocks: Mapping[str, Sequence[Any]] | Sequence[Any] | None
                   ) -> list[ClockChoice]:
    """The chosen clocks with their candidate periods, each read exactly, in the order
    given (see :func:`~.space.design_space` for the forms of ``clocks`` and the errors)."""
    clock_choices = []
    clock_first: dict[str, str] = {}
    if isinstance(clocks, Mapping):
        clock_items = [(str(n), p) for n, p in clocks.items()]
    else:  # (name, periods) pairs or "NAME=P1,P2" texts
        clock_items = [parse_clock_choice(item) if isinstance(item, str) else
                       (str(item[0]), item[1]) for item in clocks or ()]
    for k, (name, periods) in enumerate(clock_items):
        where = f"clocks.{name}"
        if name in clock_first:
            raise InputError(f"the clock {name!r} is chosen twice, by `clocks`[{clock_first[name]}]"
                             f" and `clocks`[{k}]; expected each clock once (the second would "
                             "silently replace the first)", where)
        clock_first[name] = str(k)
        if name not in skeleton.clocks:
            hint = (f" (the clock of task {name!r} is {name + '.clock'!r})"
                    if name in skeleton.tasks and name + ".clock" in skeleton.clocks else "")
            known = ", ".join(skeleton.clocks) or "none"
            raise InputError(f"no clock {name!r} in the skeleton; expected one of {known}{hint}",
                             where)
        if not any(t.clock == name for t in skeleton.tasks.values()):
            raise InputError(f"the clock {name!r} activates no task: its period changes no "
                             "figure; expected a clock that activates a task", where)
        values = [_time(text, f"{where}[{j}]", "a period")
                  for j, text in enumerate([periods] if isinstance(periods, str | int)
                                           else periods)]
        if not values:
            raise InputError(f"no period given for {name!r}; expected {name}=P1,P2,...", where)
        clock_choices.append(ClockChoice(name, tuple(dict.fromkeys(values))))
    return clock_choices
