"""The design space of ``explore``: protocol choices per link, period choices per clock.

A *variant* is one protocol for each chosen link and one period for each
chosen clock; everything else is the input skeleton. Variants are numbered in
mixed radix, the links first (most significant, in the order chosen) and the
clocks last, so that the clock variants of one protocol assignment are
consecutive numbers: ``variant = protocol_index * n_clock_variants + clock_index``.

The numbering is what a results file stores and what ``resume`` skips; the
:attr:`DesignSpace.fingerprint` ties a file to one skeleton, one space and one
set of objectives.

Choices are refused with an :class:`~tegraph.errors.InputError` whose
``where`` names the parameter and the entry (``links[1]``, ``clocks.rtc[0]``).
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from fractions import Fraction
from functools import cached_property
from typing import Any

from maxplus.scalar import exact_text, exact_time

from ..errors import InputError
from ..model.skeleton import Protocol, Skeleton
from ..model.skeleton_checks import Locator, check_chain
from .synchronization import group_period, synchronized_groups

__all__ = [
    "ClockChoice",
    "DesignSpace",
    "LinkChoice",
    "design_space",
    "latency_name",
    "link_text",
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


def link_text(writer: tuple[str, str], reader: tuple[str, str]) -> str:
    """``W:p -> R:q``: how a link is named in choices, reports and result columns.

    >>> link_text(("MT1", "x1"), ("MT2", "x1"))
    'MT1:x1 -> MT2:x1'
    """
    return f"{writer[0]}:{writer[1]} -> {reader[0]}:{reader[1]}"


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


@dataclass(frozen=True)
class ClockChoice:
    """A chosen clock: its name and its candidate periods (exact, > 0)."""

    name: str
    periods: tuple[Fraction, ...]


@dataclass(frozen=True)
class DesignSpace:
    """The skeleton, the chosen links and clocks, the chains and the objectives.

    Attributes
    ----------
    skeleton : Skeleton
        The input design; every variant is this skeleton with other protocols
        on ``links`` and other periods on ``clocks``.
    links : tuple of LinkChoice
    clocks : tuple of ClockChoice
    chains : tuple of tuple of str
        Chains whose latency is an objective (the skeleton's own, then the given ones).
    objectives : tuple of str
        Names of the objectives, all minimized: ``latency:A,B,C`` per chain,
        ``period``, ``load``.
    """

    skeleton: Skeleton
    links: tuple[LinkChoice, ...]
    clocks: tuple[ClockChoice, ...]
    chains: tuple[tuple[str, ...], ...]
    objectives: tuple[str, ...]

    @property
    def n_protocol_variants(self) -> int:
        """Number of protocol assignments (product over the chosen links)."""
        return math.prod(len(c.protocols) for c in self.links)

    @property
    def n_clock_variants(self) -> int:
        """Number of period assignments (product over the chosen clocks)."""
        return math.prod(len(c.periods) for c in self.clocks)

    @property
    def size(self) -> int:
        """Number of variants."""
        return self.n_protocol_variants * self.n_clock_variants

    def split(self, variant: int) -> tuple[int, int]:
        """``(protocol_index, clock_index)`` of a variant number."""
        return divmod(variant, self.n_clock_variants)

    def protocol_digits(self, protocol_index: int) -> tuple[int, ...]:
        """The position of each link's protocol in its choice list."""
        return _digits(protocol_index, [len(c.protocols) for c in self.links])

    def clock_digits(self, clock_index: int) -> tuple[int, ...]:
        """The position of each clock's period in its choice list."""
        return _digits(clock_index, [len(c.periods) for c in self.clocks])

    def protocols(self, variant: int) -> tuple[Protocol, ...]:
        """The protocol of each chosen link in ``variant``."""
        digits = self.protocol_digits(self.split(variant)[0])
        return tuple(c.protocols[d] for c, d in zip(self.links, digits))

    def periods(self, variant: int) -> tuple[Fraction, ...]:
        """The period of each chosen clock in ``variant``."""
        digits = self.clock_digits(self.split(variant)[1])
        return tuple(c.periods[d] for c, d in zip(self.clocks, digits))

    def variant_of(self, protocols: Sequence[Protocol], periods: Sequence[Fraction]) -> int:
        """The number of the variant with these choices (each must be allowed)."""
        p = 0
        for choice, protocol in zip(self.links, protocols):
            p = p * len(choice.protocols) + choice.protocols.index(protocol)
        c = 0
        for choice, period in zip(self.clocks, periods):
            c = c * len(choice.periods) + choice.periods.index(period)
        return p * self.n_clock_variants + c

    def describe(self, variant: int) -> tuple[dict[str, str], dict[str, str]]:
        """``({link: protocol}, {clock: period})`` as report texts."""
        links = {c.label: p.value for c, p in zip(self.links, self.protocols(variant))}
        clocks = {c.name: exact_text(t) for c, t in zip(self.clocks, self.periods(variant))}
        return links, clocks  # type: ignore[return-value]

    def build(self, variant: int) -> Skeleton:
        """The skeleton of ``variant``, checked like one read from a file."""
        links = list(self.skeleton.links)
        for choice, protocol in zip(self.links, self.protocols(variant)):
            links[choice.index] = replace(links[choice.index], protocol=protocol)
        clocks = dict(self.skeleton.clocks)
        for choice, period in zip(self.clocks, self.periods(variant)):
            clocks[choice.name] = replace(clocks[choice.name], period=period)
        return replace(self.skeleton, links=links, clocks=clocks).validate()

    def starting_variant(self) -> int:
        """The input design itself, each choice replaced by the first allowed one where
        the input's protocol or period is not among the choices."""
        protocols = []
        for c in self.links:
            given = self.skeleton.links[c.index].protocol
            protocols.append(given if given in c.protocols else c.protocols[0])
        periods = []
        for c in self.clocks:
            given = self.skeleton.clocks[c.name].period
            periods.append(given if given in c.periods else c.periods[0])
        return self.variant_of(protocols, periods)

    @cached_property
    def reference_periods(self) -> dict[str, Fraction | None]:
        """Each task's designed period: the period, in the input skeleton, of the fastest
        clock of its group (spec §4 groups: tasks joined by synchronizing links,
        threads and shared clocks); None for a task whose group has no clock."""
        sk = self.skeleton
        return {name: period for tasks in synchronized_groups(sk)
                for period in [group_period(sk, tasks)] for name in tasks}

    @cached_property
    def fingerprint(self) -> str:
        """A short hash of the skeleton, the choices and the objectives (ties a results
        file to one exploration)."""
        text = json.dumps({
            "skeleton": self.skeleton.to_dict(),
            "links": [[c.label, [p.value for p in c.protocols]] for c in self.links],
            "clocks": [[c.name, [exact_text(t) for t in c.periods]] for c in self.clocks],
            "chains": [list(c) for c in self.chains],
            "objectives": list(self.objectives),
        }, sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:16]


def _digits(index: int, radices: Sequence[int]) -> tuple[int, ...]:
    out = []
    for radix in reversed(radices):
        index, d = divmod(index, radix)
        out.append(d)
    return tuple(reversed(out))


OBJECTIVES = ("latency", "period", "load")


def design_space(skeleton: Skeleton, links: Mapping[str, Sequence[Any] | None] | Sequence[str] = (),
                 all_links: bool = False, clocks: Mapping[str, Sequence[Any]] | None = None,
                 chains: Sequence[Sequence[str]] = (), objectives: Sequence[str] | None = None
                 ) -> DesignSpace:
    """Check the choices against the skeleton and build the design space.

    Parameters
    ----------
    skeleton : Skeleton
    links : mapping of str to protocols, or sequence of str
        ``"W:p -> R:q"`` -> the protocols allowed (texts or :class:`Protocol`;
        None: all four). A plain sequence of link names allows all four on each.
    all_links : bool
        Choose every link of the skeleton (with all four protocols), besides ``links``.
    clocks : mapping of str to sequence of times
        Clock name (``TASK.clock`` for a task's ``period:``) -> candidate periods.
    chains : sequence of task-name sequences
        Chains whose latency is an objective, besides the skeleton's ``chains``.
    objectives : sequence of str, optional
        Among ``latency``, ``period``, ``load``; default all three (``latency``
        only when there is a chain).

    Returns
    -------
    DesignSpace

    Raises
    ------
    InputError
        An unknown link, clock, task or protocol; a choice named twice; an empty
        choice; a period that is not a time > 0; nothing chosen; an unknown
        objective, or ``latency`` without a chain.

    Examples
    --------
    >>> sk = Skeleton.from_dict({"clocks": {"rtc": {"period": 10}}, "tasks": {
    ...     "A": {"duration": 1, "clock": "rtc", "outputs": ["x"]},
    ...     "B": {"duration": 2, "inputs": ["x"]}},
    ...     "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]})
    >>> space = design_space(sk, {"A:x -> B:x": ["ASYN/SYN", "SYN/SYN"]}, clocks={"rtc": [5, 10]})
    >>> space.size, space.describe(3)
    (4, ({'A:x -> B:x': 'SYN/SYN'}, {'rtc': '10'}))
    """
    by_label = {link_text(k.writer, k.reader): i for i, k in enumerate(skeleton.links)}
    items = list(links.items()) if isinstance(links, Mapping) else [(t, None) for t in links]
    chosen: dict[int, LinkChoice] = {}
    for k, (label, protocols) in enumerate(items):
        where = f"links[{k}]"
        name, _ = parse_link_choice(str(label))
        if name not in by_label:
            known = ", ".join(list(by_label)[:8]) + (", ..." if len(by_label) > 8 else "")
            raise InputError(f"no link {name!r} in the skeleton; expected \"WRITER:PORT -> "
                             f"READER:PORT\" of one of its links ({known or 'none'})", where)
        index = by_label[name]
        if index in chosen:
            raise InputError(f"the link {name!r} is chosen twice; expected each link once",
                             where)
        if protocols is None:
            allowed = _ALL
        else:
            if isinstance(protocols, str | Protocol):
                protocols = [protocols]
            allowed = tuple(dict.fromkeys(parse_protocol(p, where) for p in protocols))
            if not allowed:
                raise InputError(f"no protocol allowed for {name!r}; expected at least one "
                                 f"of {_PROTOCOLS}", where)
        chosen[index] = LinkChoice(index, name, allowed)
    if all_links:
        for i, link in enumerate(skeleton.links):
            chosen.setdefault(i, LinkChoice(i, link_text(link.writer, link.reader), _ALL))
    clock_choices = []
    for name, periods in (clocks or {}).items():
        where = f"clocks.{name}"
        if name not in skeleton.clocks:
            hint = (f" (the clock of task {name!r} is {name + '.clock'!r})"
                    if name in skeleton.tasks and name + ".clock" in skeleton.clocks else "")
            known = ", ".join(skeleton.clocks) or "none"
            raise InputError(f"no clock {name!r} in the skeleton; expected one of {known}{hint}",
                             where)
        if not any(t.clock == name for t in skeleton.tasks.values()):
            raise InputError(f"the clock {name!r} activates no task: its period changes no "
                             "figure; expected a clock that activates a task", where)
        values = []
        for j, text in enumerate([periods] if isinstance(periods, str | int) else periods):
            try:
                value = exact_time(text)
            except (ValueError, ArithmeticError, TypeError):
                value = None
            if value is None or value <= 0:
                raise InputError(f"expected a period > 0 such as 10, 2.5 or 7/3, got {text!r}",
                                 f"{where}[{j}]")
            values.append(value)
        if not values:
            raise InputError(f"no period given for {name!r}; expected {name}=P1,P2,...", where)
        clock_choices.append(ClockChoice(name, tuple(dict.fromkeys(values))))
    if not chosen and not clock_choices:
        raise InputError("nothing to explore; expected at least one link or clock to choose",
                         "links")
    all_chains = [tuple(c) for c in skeleton.chains]
    for j, chain in enumerate(chains):
        all_chains.append(check_chain(skeleton, list(chain), ("chain", j), Locator()))
    names = _objective_names(objectives, all_chains)
    return DesignSpace(skeleton, tuple(chosen[i] for i in chosen), tuple(clock_choices),
                       tuple(dict.fromkeys(all_chains)), names)


def _objective_names(objectives: Sequence[str] | None,
                     chains: Sequence[tuple[str, ...]]) -> tuple[str, ...]:
    if objectives is None:
        wanted = [o for o in OBJECTIVES if o != "latency" or chains]
    else:
        wanted = []
        for k, name in enumerate(objectives):
            key = str(name).strip().lower()
            if key not in OBJECTIVES:
                raise InputError(f"unknown objective {name!r}; expected one of "
                                 f"{', '.join(OBJECTIVES)}", f"objectives[{k}]")
            if key == "latency" and not chains:
                raise InputError("the objective latency needs a chain; expected a `chain` "
                                 "or the skeleton's chains", f"objectives[{k}]")
            wanted.append(key)
        if not wanted:
            raise InputError(f"no objective; expected some of {', '.join(OBJECTIVES)}",
                             "objectives")
    out: list[str] = []
    for key in dict.fromkeys(wanted):
        if key == "latency":
            out += [latency_name(c) for c in dict.fromkeys(chains)]
        else:
            out.append(key)
    return tuple(out)


def latency_name(chain: Sequence[str]) -> str:
    """The objective name of a chain's latency.

    >>> latency_name(["TG.JS", "TF.TT.JS", "CO.JS"])
    'latency:TG.JS,TF.TT.JS,CO.JS'
    """
    return "latency:" + ",".join(chain)
