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
set of objectives. The choices themselves are read in :mod:`.choices`, the
objectives and constraints in :mod:`.objectives`.

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

from maxplus.scalar import exact_text

from ...analysis.processors.schedule import MAX_EVENTS
from ...errors import InputError
from ...model.elements import link_name
from ...model.limits import event_budget_problem
from ...model.platform import crosses, link_delay
from ...model.skeleton import Protocol, Skeleton, Task
from ...model.skeleton.checks import Locator, check_chain
from ...model.structure import Structure
from .allocation import Allocation, allocation_of
from .choices import (
    ClockChoice,
    LinkChoice,
    _clock_choices,
    _link_choices,
    parse_protocol,
)
from .objectives import (
    DEFINITIONS,
    Constraints,
    _latency_bounds,
    _objective_names,
    _requirements,
    chain_objective,
)

__all__ = ["DesignSpace", "design_space"]


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
        return [(link_name(k.writer, k.reader), link_delay(sk, k)) for k in sk.links
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
