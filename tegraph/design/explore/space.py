"""The design space of ``explore``: protocols per link, periods per clock, processors per unit.

A *variant* is one protocol for each chosen link, one period for each chosen clock
and, when processors are offered, one canonical allocation of the units (groups or
tasks) to them (:mod:`.allocation`); everything else is the input skeleton. Variants
are numbered in mixed radix, the links first (most significant, in the order chosen),
then the clocks, the allocation last, so that the clock and allocation variants of one
protocol assignment are consecutive numbers: ``variant = (protocol_index *
n_clock_variants + clock_index) * n_allocation_variants + allocation_index``.

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
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from fractions import Fraction
from functools import cached_property
from typing import Any

from maxplus.scalar import exact_text, exact_time

from ...analysis.processors.schedule import MAX_EVENTS
from ...errors import InputError
from ...model.limits import event_budget_problem
from ...model.platform import crosses, link_delay
from ...model.skeleton import Protocol, Skeleton, Task
from ...model.skeleton.checks import Locator, check_chain
from ...model.structure import Structure
from .allocation import Allocation, allocation_of

__all__ = [
    "CHAIN_FIGURES",
    "ClockChoice",
    "Constraints",
    "DesignSpace",
    "LinkChoice",
    "PLACEMENT_OBJECTIVES",
    "chain_objective",
    "design_space",
    "latency_name",
    "link_text",
    "parse_clock_choice",
    "parse_latency_bound",
    "parse_link_choice",
    "parse_period_requirement",
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


@dataclass(frozen=True)
class Constraints:
    """What every kept design must meet, besides liveness, consistency and schedulability.

    Attributes
    ----------
    periods : tuple of (task, op, period)
        The task's period (its group's, in the variant) ``=`` or ``<=`` the period.
    latencies : tuple of (chain, latency)
        The chain's first use on processors (spec §4c, exact: never a bound) at most
        this value; a variant where it is undecided does not meet it.
    forbidden : tuple of Protocol
        Protocols taken out of every chosen link's choices (a link not chosen may
        not use one either).
    free_running : bool
        Keep designs where a task runs free that the input design runs on a clock
        (its group has no clock in the variant: it runs as often as its processor
        lets it, at the lowest priority, and its rate is nobody's choice). False (the
        default): such a design is not kept.
    """

    periods: tuple[tuple[str, str, Fraction], ...] = ()
    latencies: tuple[tuple[tuple[str, ...], Fraction], ...] = ()
    forbidden: tuple[Protocol, ...] = ()
    free_running: bool = False

    def __bool__(self) -> bool:
        """True when a variant can fail them (forbidden protocols restrict the space
        instead)."""
        return bool(self.periods or self.latencies)

    def to_dict(self) -> dict[str, Any]:
        """Plain data for the report and the fingerprint."""
        return {"periods": [{"task": t, "op": op, "period": exact_text(v)}
                            for t, op, v in self.periods],
                "latencies": [{"chain": list(c), "at_most": exact_text(v)}
                              for c, v in self.latencies],
                "forbidden": [p.value for p in self.forbidden],
                "free_running": self.free_running}

    def texts(self, unit: str) -> list[str]:
        """Each constraint in words."""
        return ([f"{t}.period {op} {exact_text(v)} {unit}" for t, op, v in self.periods]
                + [f"latency {','.join(c)} <= {exact_text(v)} {unit}"
                   for c, v in self.latencies]
                + [f"no {p.value} link" for p in self.forbidden])


DEFINITIONS = 6
"""The version of the definitions of a verdict and of the objectives, part of the
fingerprint: a results file judged under other definitions is not resumed. Version 1:
the period ratio against the input group's fastest clock, no utilization, no Rule 2
count; version 2: every variant judged with a processor per task (spec §4) and the
response-time test; version 3: judged on its processors (spec v1.2 §4b, the exact
schedule within ``max_events``), the period ratio, load and utilization read on
processors; version 4: as 3, and a design where a task runs free that the input design
runs on a clock is kept only when asked (``Constraints.free_running``); version 5: as 4,
and the chains' objectives and ``max_latency`` exact on processors (spec v1.3 §4c: first
use, age, reaction), a variant whose figure is undecided rejected, never ranked by a
bound; version 6: as 5, and where the tasks run may be a choice (the allocation digits,
least significant, an allocation and its renamings over interchangeable processors one
variant), with the ``processors``, ``traffic`` and ``busiest`` objectives, and a chain's
message visible its link's communication delay after its write (spec v1.3 §4d), not at
the write."""

CURRENT_DEFINITIONS = ("each variant judged on its processors, spec §4b; a design where a "
                       "task runs free that the input design clocks is not kept unless "
                       "asked; the chains' figures exact on processors, spec §4c; where "
                       "tasks run may be chosen, one variant per allocation up to renaming")

OLDER_DEFINITIONS = {1: "the period ratio against the input group's fastest clock",
                     2: "every variant judged with a processor per task and the "
                        "response-time test, before the schedule on processors (§4b)",
                     3: "designs kept where a task runs free that the input design runs on "
                        "a clock, and a chain's latency with a processor per task, or a "
                        "published bound across groups, before its exact figures on "
                        "processors (§4c)",
                     4: "a chain's latency with a processor per task, or a published "
                        "bound across groups, before its exact figures on processors (§4c)",
                     5: "before the allocation of tasks to processors was a choice, and "
                        "a chain's messages visible at their write, before the "
                        "communication delays of the links (§4d)"}
"""What each older version of :data:`DEFINITIONS` judged differently (said when a
results file of that version is refused)."""


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
        ``period``, ``load``, ``utilization``.
    constraints : Constraints
    allocation : Allocation or None
        The processors offered to the units, when where tasks run is a choice.
    """

    skeleton: Skeleton
    links: tuple[LinkChoice, ...]
    clocks: tuple[ClockChoice, ...]
    chains: tuple[tuple[str, ...], ...]
    objectives: tuple[str, ...]
    constraints: Constraints = Constraints()
    max_events: int = MAX_EVENTS
    """Budget of event firings of each variant's schedule on processors (§4b)."""
    allocation: Allocation | None = None

    @property
    def n_allocation_variants(self) -> int:
        """Number of canonical allocations (1 when no processor is offered)."""
        return 1 if self.allocation is None else self.allocation.size

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
        return self.n_protocol_variants * self.n_clock_variants * self.n_allocation_variants

    @property
    def per_protocol(self) -> int:
        """Number of variants of one protocol assignment (consecutive numbers)."""
        return self.n_clock_variants * self.n_allocation_variants

    def split(self, variant: int) -> tuple[int, int]:
        """``(protocol_index, clock_index)`` of a variant number."""
        return divmod(variant // self.n_allocation_variants, self.n_clock_variants)

    def allocation_index(self, variant: int) -> int:
        """The number of the variant's allocation (0 when none is chosen)."""
        return variant % self.n_allocation_variants

    def processors_of(self, variant: int) -> dict[str, str]:
        """Task -> processor in ``variant``, as its skeleton declares it."""
        on = {n: t.runs_on for n, t in self.skeleton.tasks.items()}
        if self.allocation is not None:  # the tasks of no unit stay where they are
            on.update(self.allocation.task_processors(self.allocation_index(variant)))
        return on

    def placement(self, variant: int) -> dict[str, str]:
        """Each free unit's processor in ``variant`` as report texts (``A+B`` -> ``cpu1``);
        empty when no processor is offered."""
        a = self.allocation
        if a is None:
            return {}
        return {a.unit_label(u): p for u, p in
                zip(a.free, a.processors_of(self.allocation_index(variant)))}

    def crossing(self, variant: int) -> list[tuple[str, Fraction]]:
        """The links of ``variant`` whose two tasks run on different processors, each
        with its delay (spec §4d), in file order."""
        sk = self.build(variant, validate=False)
        return [(link_text(k.writer, k.reader), link_delay(sk, k)) for k in sk.links
                if crosses(sk, k)]

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

    def variant_of(self, protocols: Sequence[Protocol], periods: Sequence[Fraction],
                   allocation: int = 0) -> int:
        """The number of the variant with these choices (each must be allowed;
        ``allocation``, the allocation's number)."""
        p = 0
        for choice, protocol in zip(self.links, protocols):
            p = p * len(choice.protocols) + choice.protocols.index(protocol)
        c = 0
        for clock, period in zip(self.clocks, periods):
            c = c * len(clock.periods) + clock.periods.index(period)
        return (p * self.n_clock_variants + c) * self.n_allocation_variants + allocation

    def describe(self, variant: int) -> tuple[dict[str, str], dict[str, str]]:
        """``({link: protocol}, {clock: period})`` as report texts."""
        links = {c.label: p.value for c, p in zip(self.links, self.protocols(variant))}
        clocks = {c.name: exact_text(t) for c, t in zip(self.clocks, self.periods(variant))}
        return links, clocks

    def build(self, variant: int, validate: bool = True,
              moved: dict[tuple[str, str], Task] | None = None) -> Skeleton:
        """The skeleton of ``variant``, checked like one read from a file (``validate``
        False: not checked again, as only protocols and periods change, each checked
        when the space was made); ``moved`` keeps each task made to run elsewhere, by
        (task, processor), for the next variant that moves it there too (a task is
        immutable: one object serves every variant)."""
        links = list(self.skeleton.links)
        for choice, protocol in zip(self.links, self.protocols(variant)):
            links[choice.index] = replace(links[choice.index], protocol=protocol)
        clocks = dict(self.skeleton.clocks)
        for clock, period in zip(self.clocks, self.periods(variant)):
            clocks[clock.name] = replace(clocks[clock.name], period=period)
        changes: dict[str, Any] = {"links": links, "clocks": clocks}
        if self.allocation is not None:
            on = self.processors_of(variant)
            if moved is None:
                moved = {}
            tasks = {}
            for n, t in self.skeleton.tasks.items():
                p = on[n]
                if t.runs_on != p:
                    t = moved.get((n, p)) or moved.setdefault((n, p), replace(t, processor=p))
                tasks[n] = t
            changes["tasks"] = tasks
            used = set(on.values())
            # A `processors` entry must name a task's processor (spec §1): the declared
            # properties of a processor no unit uses in this variant are left out.
            changes["processors"] = {p: q for p, q in self.skeleton.processors.items()
                                     if p in used}
        variant_skeleton = replace(self.skeleton, **changes)
        return variant_skeleton.validate() if validate else variant_skeleton

    def starting_variant(self) -> int:
        """The input design itself, each choice replaced by the first allowed one where
        the input's protocol or period is not among the choices."""
        protocols = []
        for c in self.links:
            given = self.skeleton.links[c.index].protocol
            protocols.append(given if given in c.protocols else c.protocols[0])
        periods = []
        for k in self.clocks:
            declared = self.skeleton.clocks[k.name].period
            periods.append(declared if declared in k.periods else k.periods[0])
        return self.variant_of(protocols, periods, self.starting_allocation())

    def starting_allocation(self) -> int:
        """The number of the input's allocation: each free unit on the processor of its
        first task when offered, else on the first processor offered."""
        a = self.allocation
        if a is None:
            return 0
        tasks = self.skeleton.tasks
        return a.index_of([tasks[a.units[u][0]].runs_on
                           if tasks[a.units[u][0]].runs_on in a.offered else a.offered[0]
                           for u in a.free])

    @cached_property
    def reference_periods(self) -> dict[str, Fraction | None]:
        """Each task's designed period, in the input skeleton: its own clock's period;
        for a task without a clock, the period of the fastest clock of its group (spec
        §4 groups: tasks joined by synchronizing links, threads and shared clocks);
        None for a task whose group has no clock.

        A task's own clock states the rate it is designed for: a variant where it
        leaves a faster group to run on that clock runs it at its designed rate."""
        sk = self.skeleton
        s = Structure.of(sk)
        out = {name: period for tasks, period in zip(s.groups, s.periods) for name in tasks}
        for name, task in sk.tasks.items():
            if task.clock:
                out[name] = sk.clocks[task.clock].period
        return out

    @cached_property
    def free_running_in_input(self) -> frozenset[str]:
        """The tasks that run free in the input design (their group has no clock): the
        design runs them so, and a variant that keeps them so is kept as the input is."""
        s = Structure.of(self.skeleton)
        return frozenset(t for tasks, clocks in zip(s.groups, s.clocks) if not clocks
                         for t in tasks)

    @cached_property
    def fingerprint(self) -> str:
        """A short hash of the skeleton, the choices, the objectives, the constraints,
        the budget of each schedule (``max_events``: a variant undecided within one
        budget may be decided within another) and the version of the definitions
        (ties a results file to one exploration)."""
        return self.fingerprint_of(DEFINITIONS)

    @property
    def chains_read(self) -> tuple[tuple[str, ...], ...]:
        """The chains a variant's judgement reads (spec §4c, on its processors): those of
        a chain objective, then those of a ``max_latency`` constraint."""
        used = [o[1] for n in self.objectives if (o := chain_objective(n)) is not None]
        used += [c for c, _ in self.constraints.latencies]
        return tuple(dict.fromkeys(used))

    def fingerprint_of(self, definitions: int) -> str:
        """The fingerprint this space had under version ``definitions`` of the
        definitions (:data:`DEFINITIONS`; the older ones, to say why a file of theirs
        is refused)."""
        data: dict[str, Any] = {
            "skeleton": self.skeleton.to_dict(),
            "links": [[c.label, [p.value for p in c.protocols]] for c in self.links],
            "clocks": [[c.name, [exact_text(t) for t in c.periods]] for c in self.clocks],
            "chains": [list(c) for c in self.chains],
            "objectives": list(self.objectives),
            "constraints": self.constraints.to_dict(),
            "definitions": definitions,
        }
        if definitions < 4:  # no free-running choice before version 4
            del data["constraints"]["free_running"]
        if definitions >= 3:  # no budget before the schedule on processors
            data["max_events"] = self.max_events
        if definitions >= 6 and self.allocation is not None:
            data["allocation"] = self.allocation.to_dict()
        text = json.dumps(data, sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:16]


def _digits(index: int, radices: Sequence[int]) -> tuple[int, ...]:
    out = []
    for radix in reversed(radices):
        index, d = divmod(index, radix)
        out.append(d)
    return tuple(reversed(out))


OBJECTIVES = ("latency", "age", "reaction", "period", "load", "utilization", "processors",
              "traffic", "busiest")

PLACEMENT_OBJECTIVES = ("processors", "traffic", "busiest")
"""The objectives of where tasks run: the processors used, the links that cross
processors, the busiest processor's demand (``Σ duration/period`` at the §4 periods)."""

CHAIN_FIGURES = {"latency": "first_use", "age": "age", "reaction": "reaction"}
"""Each chain objective and the figure of spec §4c it minimizes, on processors."""


def chain_objective(name: str) -> tuple[str, tuple[str, ...]] | None:
    """``"age:A,B"`` -> (``"age"``, the chain), for a chain objective; None otherwise.

    >>> chain_objective("reaction:TG.JS,CO.JS"), chain_objective("load")
    (('reaction', ('TG.JS', 'CO.JS')), None)
    """
    key, _, chain = name.partition(":")
    return (key, tuple(chain.split(","))) if key in CHAIN_FIGURES and chain else None

_REQUIREMENT = re.compile(r"\s*(?P<task>[^=<>]+?)\.period\s*(?P<op><=|=)\s*(?P<value>\S.*?)\s*$")


def parse_period_requirement(text: str, where: str) -> tuple[str, str, str]:
    """``"CTRL.period=2"`` or ``"CTRL.period<=5/2"`` -> (task, ``=`` or ``<=``, period text).

    >>> parse_period_requirement("CTRL.period = 2", "requires[0]")
    ('CTRL', '=', '2')
    """
    found = _REQUIREMENT.fullmatch(str(text))
    if not found:
        raise InputError(f"cannot read {str(text)!r}; expected TASK.period=P or "
                         "TASK.period<=P, such as CTRL.period=2", where)
    return found["task"].strip(), found["op"], found["value"]


def parse_latency_bound(text: str, where: str) -> tuple[tuple[str, ...], str]:
    """``"A,B,C=12"`` -> (chain, latency text).

    >>> parse_latency_bound("A, B,C = 25/2", "max_latency[0]")
    (('A', 'B', 'C'), '25/2')
    """
    chain, equals, value = str(text).rpartition("=")
    names = tuple(n.strip() for n in chain.split(","))
    if not equals or not value.strip() or len(names) < 2 or not all(names):
        raise InputError(f"cannot read {str(text)!r}; expected A,B,C=LATENCY (a chain of "
                         "two tasks or more), such as MT1,MT2,MT3=12", where)
    return names, value.strip()


def _time(text: Any, where: str, what: str) -> Fraction:
    """A time > 0 read by the one exact-number parser of the files (digit bound included)."""
    try:
        value = exact_time(text if isinstance(text, str | int | Fraction) else str(text), where)
    except (ValueError, ArithmeticError, TypeError) as exc:
        said = str(exc).removeprefix(f"{where}: ")
        raise InputError(f"expected {what} > 0 such as 10, 2.5 or 7/3; {said}", where) from None
    if value <= 0:
        raise InputError(f"expected {what} > 0 such as 10, 2.5 or 7/3, got {text!r}", where)
    return value


def design_space(skeleton: Skeleton, links: Mapping[str, Sequence[Any] | None] | Sequence[str] = (),
                 all_links: bool = False,
                 clocks: Mapping[str, Sequence[Any]] | Sequence[Any] | None = None,
                 chains: Sequence[Sequence[str]] = (), objectives: Sequence[str] | None = None,
                 *, requires: Sequence[Any] = (), max_latency: Sequence[Any] = (),
                 forbid: Sequence[Any] = (), max_events: int = MAX_EVENTS,
                 free_running: bool = False, offer: Sequence[str] | str | None = None,
                 allocate: str = "groups", pin: Sequence[Any] = ()) -> DesignSpace:
    """Check the choices against the skeleton and build the design space.

    Parameters
    ----------
    skeleton : Skeleton
    links : mapping of str to protocols, or sequence of str
        ``"W:p -> R:q"`` -> the protocols allowed (texts or :class:`Protocol`;
        None: all four). A plain sequence holds ``"W:p -> R:q"`` (all four) or
        ``"W:p -> R:q=ASYN/SYN,SYN/SYN"`` texts.
    all_links : bool
        Choose every link of the skeleton (with all four protocols, less ``forbid``);
        a link also in ``links`` keeps the protocols ``links`` gives it (marked
        ``narrowed``, and said in the report).
    clocks : mapping of str to sequence of times, or sequence of pairs or texts
        Clock name (``TASK.clock`` for a task's ``period:``) -> candidate periods;
        as a sequence, ``(name, periods)`` pairs or ``"NAME=5,10"`` texts.
    chains : sequence of task-name sequences
        Chains whose latency is an objective, besides the skeleton's ``chains``.
    objectives : sequence of str, optional
        Among ``latency`` (each chain's first use on processors, spec §4c), ``age``
        and ``reaction`` (the same chain's figures), ``period``, ``load``,
        ``utilization``, ``processors`` (how many are used), ``traffic`` (how many links
        cross processors) and ``busiest`` (the busiest processor's demand, ``Σ
        duration/period`` of its tasks at their §4 periods); default: ``latency`` when
        there is a chain, ``period``, ``load``, ``utilization`` when the tasks are on
        (or offered) more than one processor (on one, it equals ``load``), and the
        last three when processors are offered.
    requires : sequence
        ``"TASK.period=P"`` or ``"TASK.period<=P"`` texts, or ``(task, op, period)``:
        a kept design runs the task at that period (its group's period).
    max_latency : sequence
        ``"A,B,C=L"`` texts or ``(chain, latency)`` pairs: a kept design's chain
        first use on processors (spec §4c, exact) is at most L; undecided is no
        proof, and the variant is rejected.
    forbid : sequence of protocols
        Protocols no link may use: taken out of every chosen link's choices.
    max_events : int
        Budget of event firings of each variant's schedule on processors (spec
        §4b; :data:`~tegraph.analysis.processors.MAX_EVENTS` by default): a variant
        whose schedule is not decided within it is rejected as undecided. A decided
        variant stops at its proof (a few hundred firings for a small pipe-line), so
        the budget is spent in full only by a variant that would be undecided.
    free_running : bool
        Keep designs where a task runs free that the input design runs on a clock
        (:class:`Constraints`); by default they are not kept.
    offer : sequence of str, or a comma-separated str, optional
        The processors the search may put the units on (:mod:`.allocation`).
    allocate : str
        ``groups`` (whole groups of spec §4 move together, the default) or ``tasks``.
    pin : sequence
        ``"TASK=PROCESSOR"`` texts: the task (its group, under ``groups``) stays there.

    Returns
    -------
    DesignSpace

    Raises
    ------
    InputError
        An unknown link, clock, task or protocol; a link or clock chosen twice
        (both occurrences named); an empty choice; a period that is not a time
        > 0; nothing chosen; an unknown objective, or ``latency`` without a
        chain; a constraint that cannot be read or names an unknown task or
        chain; a forbidden protocol on a link not chosen, or that empties a
        link's choice; ``max_events`` not an integer >= 1.

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
    problem = event_budget_problem(max_events)
    if problem is not None:
        raise InputError(problem, "max_events")
    forbidden = tuple(dict.fromkeys(parse_protocol(p, f"forbid[{k}]")
                                    for k, p in enumerate(forbid)))
    allocation = allocation_of(skeleton, offer, allocate, pin)
    chosen = _link_choices(skeleton, links, all_links, forbidden, placed=allocation is not None)
    clock_choices = _clock_choices(skeleton, clocks)
    if not chosen and not clock_choices and allocation is None:
        raise InputError("nothing to explore; expected at least one link or clock to choose, "
                         "or processors to offer (`offer`)", "links")
    all_chains = [tuple(c) for c in skeleton.chains]
    for j, chain in enumerate(chains):
        all_chains.append(check_chain(skeleton, list(chain), ("chain", j), Locator()))
    names = _objective_names(objectives, all_chains, skeleton, allocation)
    constraints = Constraints(_requirements(skeleton, requires),
                              _latency_bounds(skeleton, max_latency), forbidden,
                              free_running=bool(free_running))
    return DesignSpace(skeleton, tuple(chosen[i] for i in chosen), tuple(clock_choices),
                       tuple(dict.fromkeys(all_chains)), names, constraints, max_events,
                       allocation)


def _link_choices(skeleton: Skeleton, links: Mapping[str, Sequence[Any] | None] | Sequence[str],
                  all_links: bool, forbidden: tuple[Protocol, ...], placed: bool = False
                  ) -> dict[int, LinkChoice]:
    """The chosen links by index, each with its allowed protocols less ``forbidden``
    (see :func:`design_space` for the forms of ``links`` and the errors); SYN/SYN left
    out where the link has a delay: where tasks run is a choice (``placed``), only its
    own (whether it crosses, and so takes the network's, is the variant's: a rendezvous
    across processors is rejected there)."""
    by_label = {link_text(k.writer, k.reader): i for i, k in enumerate(skeleton.links)}
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
            chosen.setdefault(i, LinkChoice(i, link_text(link.writer, link.reader), left))
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
            raise InputError(f"the link {link_text(link.writer, link.reader)!r} is "
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
    given (see :func:`design_space` for the forms of ``clocks`` and the errors)."""
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


def _requirements(skeleton: Skeleton, requires: Sequence[Any]
                  ) -> tuple[tuple[str, str, Fraction], ...]:
    out: dict[str, tuple[str, str, Fraction]] = {}
    for k, item in enumerate(requires):
        where = f"requires[{k}]"
        task, op, text = (parse_period_requirement(item, where) if isinstance(item, str)
                          else item)
        if task not in skeleton.tasks:
            raise InputError(f"no task {task!r} in the skeleton; expected TASK.period=P with "
                             "one of its tasks", where)
        if op not in ("=", "<="):
            raise InputError(f"expected '=' or '<=', got {op!r}", where)
        if task in out:
            raise InputError(f"the period of {task!r} is required twice; expected each task "
                             "once (the second would silently replace the first)", where)
        out[task] = (task, op, _time(text, where, "a period"))
    return tuple(out.values())


def _latency_bounds(skeleton: Skeleton, bounds: Sequence[Any]
                    ) -> tuple[tuple[tuple[str, ...], Fraction], ...]:
    out: dict[tuple[str, ...], tuple[tuple[str, ...], Fraction]] = {}
    for k, item in enumerate(bounds):
        where = f"max_latency[{k}]"
        chain, text = parse_latency_bound(item, where) if isinstance(item, str) else item
        chain = check_chain(skeleton, list(chain), ("max_latency", k), Locator())
        if chain in out:
            raise InputError(f"the latency of {','.join(chain)} is bounded twice; expected "
                             "each chain once (the second would silently replace the first)",
                             where)
        out[chain] = (chain, _time(text, where, "a latency"))
    return tuple(out.values())


def _objective_names(objectives: Sequence[str] | None, chains: Sequence[tuple[str, ...]],
                     skeleton: Skeleton, allocation: Allocation | None = None
                     ) -> tuple[str, ...]:
    if objectives is None:
        processors = ({t.runs_on for t in skeleton.tasks.values()} if allocation is None
                      else set(allocation.offered))
        wanted = [o for o in OBJECTIVES if (o != "latency" or chains) and o not in (
                  "age", "reaction") and (o != "utilization" or len(processors) > 1)
                  and (o not in PLACEMENT_OBJECTIVES or allocation is not None)]
    else:
        wanted = []
        for k, name in enumerate(objectives):
            key = str(name).strip().lower()
            if key not in OBJECTIVES:
                raise InputError(f"unknown objective {name!r}; expected one of "
                                 f"{', '.join(OBJECTIVES)}", f"objectives[{k}]")
            if key in CHAIN_FIGURES and not chains:
                raise InputError(f"the objective {key} needs a chain; expected a `chain` "
                                 "or the skeleton's chains", f"objectives[{k}]")
            wanted.append(key)
        if not wanted:
            raise InputError(f"no objective; expected some of {', '.join(OBJECTIVES)}",
                             "objectives")
    out: list[str] = []
    for key in dict.fromkeys(wanted):
        if key in CHAIN_FIGURES:
            out += [f"{key}:" + ",".join(c) for c in dict.fromkeys(chains)]
        else:
            out.append(key)
    return tuple(out)


def latency_name(chain: Sequence[str]) -> str:
    """The objective name of a chain's latency.

    >>> latency_name(["TG.JS", "TF.TT.JS", "CO.JS"])
    'latency:TG.JS,TF.TT.JS,CO.JS'
    """
    return "latency:" + ",".join(chain)
