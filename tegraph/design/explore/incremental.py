"""Incremental judgement of variants: only the groups a choice touches are analysed again.

A variant is the input skeleton with other protocols on the chosen links and other
periods on the chosen clocks. Spec §2 builds no place between two groups
(:mod:`tegraph.model.structure`), so the timed event graph of a variant is the
disjoint union of its groups' graphs, and every figure of spec §4 that decides a
variant's consistency (liveness, cycle times, unbounded places, overruns) is, for
one group, a function of that group alone: of its tasks (fixed by the skeleton) and
of the chosen links and clocks inside it. Each group's figures are kept under that
key (:meth:`IncrementalJudge.key`): a group no choice touches is analysed once for
the whole space, a touched group once per configuration of its own choices, and a
walk that comes back to a configuration pays nothing.

The groups of a variant are those of :class:`~tegraph.model.structure.Structure`
(the one definition: a protocol that becomes synchronizing joins two groups, one that
becomes ASYN/ASYN may split one), so a key names the group's tasks. They are found
once per pattern of synchronizing chosen links (:meth:`IncrementalJudge.structure`).

Where the tasks run is a choice too (:mod:`.allocation`), a group's figures depend on
it only through the delays of the links inside it (spec §4d: a link that crosses
processors holds the network's delay), which the key then holds; a group whose
links' delays differ from the input skeleton's is built, not edited from its template.

A group's graph is not built for each configuration of its choices: it is its
template's, with each chosen link's edit read once per space from ``build_teg``
(:mod:`.group_graph`); the figures are those of the built graph.

Composed from the groups, exactly as :func:`~.evaluate.evaluate_variant` reads the
report of the whole variant:

1. **live**: every group has no token-free circuit. A variant with a dead group is
   not composed (``None``): the port repair is decided on the whole skeleton, and
   the caller judges it afresh.
2. **unbounded places** (first stage, cheap: the cycle times of the group alone,
   :func:`maxplus.max_cycle_ratio`, which refuses a token-free circuit): the whole
   report lists them in the place order of the whole graph, which
   :func:`~tegraph.model.build.build_teg` builds owner by owner (clocks, then
   each task's chain in file order, then links, then threads), each owner's places
   in the same order in a group's graph as in the whole; so the first one is the
   least by (owner kind, owner's index in the file, place index in the group), and
   their number is the sum over the groups.
3. **overruns** (second stage, only when no group has an unbounded place): the
   group's own :func:`~tegraph.analysis.analyze.analyze_skeleton` (the dater
   simulation decides each watched task on its own group's daters); the first
   overrun is the first task in file order.

A variant that is consistent is then judged on its processors (§4b) by the caller,
on the whole variant, from the report composed here (the groups' own reports, each
renumbered; tasks in file order). That judgement is not composed from parts: groups
sharing a processor are coupled (:func:`~tegraph.model.platform.processor_parts`),
and the budget of event firings is shared among the parts in an
order that depends on how many each part fired, so a part's verdict depends on the
others' (see ``docs/explore.md``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from maxplus import ZeroTokenCircuitError, max_cycle_ratio

from ...analysis.analyze import analyze_skeleton, unbounded_mask
from ...analysis.results import InvariantCheck, Report
from ...model.build import build_teg, unbounded_kind
from ...model.platform import crosses, link_delay, platform_of
from ...model.skeleton import Protocol, Skeleton, Task
from ...model.structure import Structure, design_period
from ...model.teg import TimedEventGraph
from .group_graph import GroupArrays, GroupGraph, LinkEdit, link_edit
from .space import DesignSpace

__all__ = ["IncrementalJudge", "judge_of"]

MAX_WHOLE_GRAPHS = 16
"""Whole variants' graphs kept (each as large as the skeleton) before emptying."""

MAX_CACHED = 200_000
"""Entries kept per stage before the cache is emptied (a bound on memory over a long
walk; a group is then analysed again, the result is the same)."""

# Owner kinds in the order build_teg adds their places (clock, task, link, thread).
_CLOCK, _TASK, _LINK, _THREAD = range(4)


@dataclass(frozen=True)
class GroupRates:
    """The first stage of one group: live, and its unbounded places.

    Attributes
    ----------
    live : bool
        No token-free circuit.
    count : int
        Unbounded places (0 when dead: not computed).
    first : tuple of int or None
        Where the first unbounded place stands in the whole graph's place order.
    text : str
        That place as the reason names it: ``kind at src -> dst``.
    """

    live: bool
    count: int = 0
    first: tuple[int, int, int] | None = None
    text: str = ""


@dataclass(frozen=True)
class Composed:
    """The §4 verdict of a live variant, composed from its groups.

    Attributes
    ----------
    skeleton : Skeleton
        The variant's skeleton.
    structure : Structure
        Its groups.
    reason : str
        Why it is not consistent (empty when consistent).
    report : Report or None
        When consistent: the report :func:`~tegraph.analysis.analyze.analyze_skeleton`
        gives of the whole variant, as far as the judgement on processors reads it
        (groups, tasks, structure; no semiflow cross-check); None otherwise.
    """

    skeleton: Skeleton
    structure: Structure
    reason: str = ""
    report: Report | None = None


class IncrementalJudge:
    """Judges the §4 verdict of a space's variants from cached group figures.

    Parameters
    ----------
    space : DesignSpace

    Examples
    --------
    The pipe-line of Figure 4 with its clock at 5 or 10: one group, two keys.

    >>> from tegraph import load_skeleton
    >>> from tegraph.design.explore.space import design_space
    >>> space = design_space(load_skeleton("examples/fig4_pipeline_synchronized.yaml"),
    ...                      clocks={"rtc": [5, 10]})
    >>> judge = IncrementalJudge(space)
    >>> [judge.judge(v).report is not None for v in range(space.size)]  # consistent?
    [True, True]
    >>> len(judge.rates), len(judge.reports)
    (2, 2)
    """

    def __init__(self, space: DesignSpace) -> None:
        self.space = space
        sk = space.skeleton
        self.task_index = {name: i for i, name in enumerate(sk.tasks)}
        self.clock_index = {name: i for i, name in enumerate(sk.clocks)}
        self.chosen_link = {c.index: k for k, c in enumerate(space.links)}
        self.chosen_clock = {c.name: k for k, c in enumerate(space.clocks)}
        self.rates: dict[tuple, GroupRates] = {}
        self.reports: dict[tuple, Report] = {}
        self.structures: dict[tuple[bool, ...], Structure] = {}
        self.graphs: dict[tuple[str, ...], GroupGraph] = {}
        self.edits: dict[tuple[int, Protocol], LinkEdit | None] = {}
        self.inside: dict[tuple[str, ...], tuple[int, ...]] = {}
        self.moved: dict[tuple[str, str], Task] = {}
        self.numbered: dict[tuple[tuple, int], dict[str, Any]] = {}
        self.graphs_whole: dict[tuple, TimedEventGraph] = {}

    def variant_skeleton(self, variant: int) -> Skeleton:
        """The skeleton of ``variant``, not validated again (:meth:`DesignSpace.build`)."""
        return self.space.build(variant, validate=False, moved=self.moved)

    def whole_graph(self, variant: int, skeleton: Skeleton) -> TimedEventGraph:
        """The timed event graph of ``variant`` (its ``skeleton``), built once for all
        the variants that differ from it only in where tasks run without changing
        which links cross processors where that matters.

        :func:`~tegraph.model.build.build_teg` reads the processors only through
        ``crosses`` (spec §4d: the place of a link that declares no delay holds the
        network's between two processors), so the graph is a function of the
        protocols, the clocks' periods and those links' crossing; the schedule on
        processors reads the graph and never changes it.
        """
        space = self.space
        key: tuple = (variant // space.n_allocation_variants,)
        if space.allocation is not None and skeleton.network_delay is not None:
            key += tuple(crosses(skeleton, link) for link in skeleton.links
                         if link.delay is None and link.protocol is not Protocol.ASYN_ASYN)
        graph = self.graphs_whole.get(key)
        if graph is None:
            if len(self.graphs_whole) >= MAX_WHOLE_GRAPHS:
                self.graphs_whole.clear()
            graph = self.graphs_whole[key] = build_teg(skeleton)
        return graph

    def key(self, skeleton: Skeleton, tasks: Sequence[str]) -> tuple:
        """What a group's figures depend on: its tasks, the protocols of the chosen
        links and the periods of the chosen clocks inside it (in ``skeleton``, a
        variant), and, where tasks run is a choice, the delays of its links."""
        inside = set(tasks)
        links = tuple((k, skeleton.links[i].protocol.value) for i, k in self.chosen_link.items()
                      if skeleton.links[i].writer[0] in inside
                      and skeleton.links[i].reader[0] in inside)
        used = {skeleton.tasks[t].clock for t in tasks}
        clocks = tuple((k, skeleton.clocks[name].period) for name, k in self.chosen_clock.items()
                       if name in used)
        if self.space.allocation is None:
            return (tuple(tasks), links, clocks)
        found = self.inside.get(key := tuple(tasks))
        if found is None:  # the group's links, found once per group
            if len(self.inside) >= MAX_CACHED:
                self.inside.clear()
            found = self.inside[key] = tuple(
                i for i, x in enumerate(skeleton.links)
                if x.writer[0] in inside and x.reader[0] in inside)
        delays = tuple(link_delay(skeleton, skeleton.links[i]) for i in found)
        return (tuple(tasks), links, clocks, delays)

    def judge(self, variant: int) -> Composed | None:
        """The §4 verdict of ``variant``, composed from its groups.

        Returns
        -------
        Composed or None
            None when a group is dead (the variant is judged afresh, port repair
            included).
        """
        sk = self.variant_skeleton(variant)
        structure = self.structure(sk, variant)
        keys = [self.key(sk, g) for g in structure.groups]
        rates = [self._rates(sk, g, k) for g, k in zip(structure.groups, keys)]
        if not all(r.live for r in rates):
            return None
        unbounded = [r for r in rates if r.count]
        if unbounded:
            first = min(unbounded, key=lambda r: r.first or ())
            more = sum(r.count for r in unbounded) - 1
            return Composed(sk, structure, first.text + (f" (and {more} more)" if more else ""))
        reports = [self._report(sk, g, k) for g, k in zip(structure.groups, keys)]
        # The tasks in file order (as the whole report lists them): the first late one.
        numbered = [self._numbered(r, k, i) for i, (r, k) in enumerate(zip(reports, keys))]
        tasks = {name: numbered[structure.group_of[name]][name] for name in sk.tasks}
        late = [t for t in tasks.values() if t.overrun_at is not None]
        if late:
            return Composed(sk, structure, f"overrun: {late[0].name} at activation "
                                           f"{late[0].overrun_at}")
        groups = [replace(r.groups[0], index=i) for i, r in enumerate(reports)]
        report = Report(name=sk.name, unit=sk.unit, live=True, consistent=True, deadlocks=[],
                        reorder=None, groups=groups, tasks=tasks, unbounded_places=[],
                        invariants=InvariantCheck(False, None, None,
                                                  reason="not computed (composed from groups)"),
                        source=sk.source, structure=structure,
                        # As the analysis' own report carries it: the cross-check and
                        # the schedule on processors read this one platform.
                        platform=platform_of(sk, structure))
        return Composed(sk, structure, report=report)

    def structure(self, skeleton: Skeleton, variant: int) -> Structure:
        """``Structure.of(skeleton)``, ``skeleton`` the skeleton of ``variant``.

        The groups depend only on which chosen links synchronize (clocks join by name,
        not by period; every protocol but ASYN/ASYN joins its two tasks), so they are
        found once per such pattern; a variant of a known pattern takes its groups and
        puts in its own chosen links (``by_reader``, ``by_writer``: each in the place
        of the same link of the variant that found them) and, when clocks are chosen,
        its design periods."""
        pattern = tuple(p.synchronizing for p in self.space.protocols(variant))
        found = self.structures.get(pattern)
        if found is None:
            found = Structure.of(skeleton)
            if len(self.structures) >= MAX_CACHED:
                self.structures.clear()
            self.structures[pattern] = found
            return found
        by_reader, by_writer = dict(found.by_reader), dict(found.by_writer)
        for choice in self.space.links:
            link = skeleton.links[choice.index]
            for ports, port in ((by_reader, link.reader), (by_writer, link.writer)):
                # A port's links in file order: the chosen one where it was, by its ends.
                ports[port] = tuple(link if (x.writer, x.reader) == (link.writer, link.reader)
                                    else x for x in ports[port])
        periods = (tuple(design_period(skeleton, g) for g in found.groups)
                   if self.space.clocks else found.periods)
        return replace(found, periods=periods, by_reader=by_reader, by_writer=by_writer)

    # ------------------------------------------------------------------ stages

    def _part(self, skeleton: Skeleton, tasks: Sequence[str]) -> tuple[Skeleton, list[int],
                                                                      list[int]]:
        """The group cut out of ``skeleton`` (:meth:`Skeleton.restricted_to`), and the
        file index of each of its links and threads (in the same order)."""
        inside = set(tasks)
        links = [i for i, x in enumerate(skeleton.links)
                 if x.writer[0] in inside and x.reader[0] in inside]
        threads = [i for i, th in enumerate(skeleton.threads) if th[0] in inside]
        return skeleton.restricted_to(tasks), links, threads

    def _rates(self, skeleton: Skeleton, tasks: Sequence[str], key: tuple) -> GroupRates:
        found = self.rates.get(key)
        if found is None:
            found = self._compute_rates(skeleton, tasks)
            if len(self.rates) >= MAX_CACHED:
                self.rates.clear()
            self.rates[key] = found
        return found

    def _compute_rates(self, skeleton: Skeleton, tasks: Sequence[str], *,
                       template: bool = True) -> GroupRates:
        """The group's first stage, on its graph made from the group's template
        (:class:`~.group_graph.GroupGraph`), or built (``template`` False, or an edit
        the template does not recognise): the same figures."""
        part, links, threads = self._part(skeleton, tasks)
        if template and self.space.allocation is not None:
            # The template and the edits hold the input's delays (spec §4d).
            input_sk = self.space.skeleton
            template = all(link_delay(skeleton, skeleton.links[f])
                           == link_delay(input_sk, input_sk.links[f]) for f in links)
        arrays = (self._arrays(skeleton, tuple(tasks), part, links, threads) if template
                  else None)
        if arrays is None:
            teg = build_teg(part)
            a = teg.arrays()
            src, dst, holding, tokens = a.src, a.dst, a.holding, a.tokens
            n, names = teg.n_transitions, teg.transition_names
        else:
            src, dst, holding, tokens = arrays.src, arrays.dst, arrays.holding, arrays.tokens
            n, names = arrays.n_nodes, arrays.names
        try:  # the kernel refuses a token-free circuit: the group is dead (Commoner)
            mcr = max_cycle_ratio(src, dst, holding, tokens, n_nodes=n)
        except ZeroTokenCircuitError:
            return GroupRates(False)
        slower = np.flatnonzero(unbounded_mask(mcr.cycle_time_num, mcr.cycle_time_den,
                                               src, dst))
        if not len(slower):
            return GroupRates(True)
        k = int(slower[0])
        if arrays is None:
            place = teg.places[k]
            owner, kind = self._owner(place.origin, links, threads), place.kind
        else:
            owner, kind = arrays.owners[k], arrays.kinds[k]
        first = (*owner, k)
        kind = unbounded_kind(kind)
        return GroupRates(True, len(slower), first,
                          f"{kind} at {names[int(src[k])]} -> {names[int(dst[k])]}")

    def _arrays(self, skeleton: Skeleton, tasks: tuple[str, ...], part: Skeleton,
                links: list[int], threads: list[int]) -> GroupArrays | None:
        """The arrays of the group's graph from its template and its chosen links'
        edits (:mod:`.group_graph`); None when an edit is not recognised (build it)."""
        edits = []
        for f in links:
            if f in self.chosen_link:
                edit = self._edit(f, skeleton.links[f].protocol)
                if edit is None:
                    return None
                edits.append(((_LINK, f), edit))
        targets = {b for _, e in edits for b in e.merge.values()}
        if any(a in targets for _, e in edits for a in e.merge):
            return None  # a merge into a merged event: not one edit per link
        used = {part.tasks[t].clock for t in tasks}
        clocks = [c.name for c in self.space.clocks if c.name in used]
        if not edits and not clocks:
            return None  # no choice inside: one configuration, built once for the space
        graph = self.graphs.get(tasks)
        if graph is None:
            if len(self.graphs) >= MAX_CACHED:
                self.graphs.clear()
            graph = self.graphs[tasks] = GroupGraph(
                part, {i for i, f in enumerate(links) if f in self.chosen_link}, clocks,
                lambda p: self._owner(p.origin, links, threads))
        return graph.arrays(edits, {c: part.clocks[c].period for c in clocks})

    def _edit(self, link: int, protocol: Protocol) -> LinkEdit | None:
        """What the chosen ``link`` (its index in the file) at ``protocol`` changes in a
        group's graph (:func:`~.group_graph.link_edit`), read once per space."""
        key = (link, protocol)
        if key not in self.edits:
            self.edits[key] = link_edit(self.space.skeleton, link, protocol, self.chosen_link)
        return self.edits[key]

    def _owner(self, origin: dict[str, Any], links: list[int], threads: list[int]
               ) -> tuple[int, int]:
        return place_owner(origin, self.task_index, self.clock_index, links, threads)

    def _numbered(self, report: Report, key: tuple, index: int) -> dict[str, Any]:
        """The task figures of a group's ``report`` (under ``key``) numbered as group
        ``index``, kept: a variant that only moves tasks numbers its groups alike."""
        found = self.numbered.get((key, index))
        if found is None:
            if len(self.numbered) >= MAX_CACHED:
                self.numbered.clear()
            found = self.numbered[key, index] = {
                name: replace(figures, group=index) for name, figures in report.tasks.items()}
        return found

    def _report(self, skeleton: Skeleton, tasks: Sequence[str], key: tuple) -> Report:
        """The group's own report (its one group numbered 0; the caller renumbers copies:
        what is cached is never changed)."""
        found = self.reports.get(key)
        if found is None:
            # The semiflow cross-check (no verdict depends on it) is left out.
            found = analyze_skeleton(skeleton.restricted_to(tasks), semiflow_max_places=0)
            if found.unbounded_places or not found.live:  # pragma: no cover - stage 1 said
                raise AssertionError("internal error: the group's rates and analysis differ")
            if len(self.reports) >= MAX_CACHED:
                self.reports.clear()
            self.reports[key] = found
        return found


def place_owner(origin: dict[str, Any], task_index: Mapping[str, int],
                clock_index: Mapping[str, int], links: Sequence[int], threads: Sequence[int]
                ) -> tuple[int, int]:
    """Which part of the whole graph's place order a place of a group's graph is in:
    ``(owner kind, owner's index in the file)``, from the place's origin
    (:mod:`tegraph.model.build`); ``links`` and ``threads`` give the file index of the
    group's links and threads, ``task_index`` and ``clock_index`` that of a task or a
    clock."""
    if "thread" in origin:
        return _THREAD, threads[origin["thread"]]
    if "link_index" in origin:
        return _LINK, links[origin["link_index"]]
    if "task" in origin:
        return _TASK, task_index[origin["task"]]
    return _CLOCK, clock_index[origin["clock"]]


_LAST: list[IncrementalJudge] = []


def judge_of(space: DesignSpace) -> IncrementalJudge:
    """The judge of ``space``, kept while the same space is judged (a worker judges the
    batches of one space one after the other: its cache serves them all).

    >>> from tegraph.design.explore.space import design_space
    >>> from tegraph import Skeleton
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2}}})
    >>> space = design_space(sk, clocks={"A.clock": [2, 3]})
    >>> judge_of(space) is judge_of(space)
    True
    """
    if not _LAST or _LAST[0].space is not space:
        _LAST[:] = [IncrementalJudge(space)]
    return _LAST[0]
