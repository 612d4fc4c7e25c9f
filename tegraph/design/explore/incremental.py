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
becomes ASYN/ASYN may split one), so a key names the group's tasks.

Composed from the groups, exactly as :func:`~.evaluate.evaluate_variant` reads the
report of the whole variant:

1. **live**: every group has no token-free circuit. A variant with a dead group is
   not composed (``None``): the port repair is decided on the whole skeleton, and
   the caller judges it afresh.
2. **unbounded places** (first stage, cheap: the token-free-circuit test and the
   cycle times of the group alone, :func:`maxplus.max_cycle_ratio`): the whole
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

A variant that is consistent is judged on its processors (§4b), where groups
sharing a processor are coupled (:func:`~tegraph.analysis.processors.platform.
processor_parts`) and the budget of event firings is shared among the parts: it is
not composed here (``None``), the caller judges it afresh.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from maxplus import max_cycle_ratio

from ...analysis.analyze import _KIND_REPORTED, analyze_skeleton
from ...analysis.liveness import token_free_circuits
from ...model.build import build_teg
from ...model.skeleton import Skeleton
from ...model.structure import Structure
from .space import DesignSpace

__all__ = ["IncrementalJudge", "judge_of"]

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
class GroupOverrun:
    """The second stage of one group: its first overrun (file order), if any.

    Attributes
    ----------
    first : tuple of (int, str, int) or None
        ``(task's index in the file, task, activation)``.
    """

    first: tuple[int, str, int] | None


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
    >>> [judge.judge(v) for v in range(space.size)]  # both consistent: judged afresh
    [None, None]
    >>> len(judge.rates)
    2
    """

    def __init__(self, space: DesignSpace) -> None:
        self.space = space
        sk = space.skeleton
        self.task_index = {name: i for i, name in enumerate(sk.tasks)}
        self.clock_index = {name: i for i, name in enumerate(sk.clocks)}
        self.chosen_link = {c.index: k for k, c in enumerate(space.links)}
        self.chosen_clock = {c.name: k for k, c in enumerate(space.clocks)}
        self.rates: dict[tuple, GroupRates] = {}
        self.overruns: dict[tuple, GroupOverrun] = {}

    def variant_skeleton(self, variant: int) -> Skeleton:
        """The skeleton of ``variant`` (as :meth:`DesignSpace.build`, not validated again:
        only protocols and periods change, each checked when the space was made)."""
        space = self.space
        links = list(space.skeleton.links)
        for choice, protocol in zip(space.links, space.protocols(variant)):
            links[choice.index] = replace(links[choice.index], protocol=protocol)
        clocks = dict(space.skeleton.clocks)
        for clock, period in zip(space.clocks, space.periods(variant)):
            clocks[clock.name] = replace(clocks[clock.name], period=period)
        return replace(space.skeleton, links=links, clocks=clocks)

    def key(self, skeleton: Skeleton, tasks: Sequence[str]) -> tuple:
        """What a group's figures depend on: its tasks, and the protocols of the chosen
        links and the periods of the chosen clocks inside it (in ``skeleton``, a
        variant)."""
        inside = set(tasks)
        links = tuple((k, skeleton.links[i].protocol.value) for i, k in self.chosen_link.items()
                      if skeleton.links[i].writer[0] in inside
                      and skeleton.links[i].reader[0] in inside)
        used = {skeleton.tasks[t].clock for t in tasks}
        clocks = tuple((k, skeleton.clocks[name].period) for name, k in self.chosen_clock.items()
                       if name in used)
        return (tuple(tasks), links, clocks)

    def judge(self, variant: int) -> tuple[Skeleton, Structure, str] | None:
        """The reason ``variant`` is not consistent (spec §4), composed from its groups.

        Returns
        -------
        tuple of (Skeleton, Structure, str) or None
            The variant's skeleton, its structure and the reason, when it is live and
            not consistent; None when it is dead or consistent (judged afresh).
        """
        sk = self.variant_skeleton(variant)
        structure = Structure.of(sk)
        keys = [self.key(sk, g) for g in structure.groups]
        rates = [self._rates(sk, g, k) for g, k in zip(structure.groups, keys)]
        if not all(r.live for r in rates):
            return None
        unbounded = [r for r in rates if r.count]
        if unbounded:
            first = min(unbounded, key=lambda r: r.first or ())
            more = sum(r.count for r in unbounded) - 1
            return sk, structure, first.text + (f" (and {more} more)" if more else "")
        late = [o.first for o in (self._overrun(sk, g, k) for g, k in zip(structure.groups, keys))
                if o.first is not None]
        if late:
            _, name, k = min(late)
            return sk, structure, f"overrun: {name} at activation {k}"
        return None

    # ------------------------------------------------------------------ stages

    def _part(self, skeleton: Skeleton, tasks: Sequence[str]) -> tuple[Skeleton, list[int],
                                                                      list[int]]:
        """The group cut out of ``skeleton`` (its tasks, the clocks they use, the links
        and threads inside it), and the file index of each of its links and threads."""
        inside = set(tasks)
        used = {skeleton.tasks[t].clock for t in tasks}
        links = [i for i, x in enumerate(skeleton.links)
                 if x.writer[0] in inside and x.reader[0] in inside]
        threads = [i for i, th in enumerate(skeleton.threads) if th[0] in inside]
        part = replace(skeleton, tasks={t: skeleton.tasks[t] for t in tasks},
                       clocks={c: v for c, v in skeleton.clocks.items() if c in used},
                       links=[skeleton.links[i] for i in links],
                       threads=[skeleton.threads[i] for i in threads], chains=[])
        return part, links, threads

    def _rates(self, skeleton: Skeleton, tasks: Sequence[str], key: tuple) -> GroupRates:
        found = self.rates.get(key)
        if found is None:
            found = self._compute_rates(skeleton, tasks)
            if len(self.rates) >= MAX_CACHED:
                self.rates.clear()
            self.rates[key] = found
        return found

    def _compute_rates(self, skeleton: Skeleton, tasks: Sequence[str]) -> GroupRates:
        part, links, threads = self._part(skeleton, tasks)
        teg = build_teg(part)
        a = teg.arrays()
        n = teg.n_transitions
        if token_free_circuits(a.src, a.dst, a.tokens, n):
            return GroupRates(False)
        mcr = max_cycle_ratio(a.src, a.dst, a.holding, a.tokens, n_nodes=n)
        num, den = mcr.cycle_time_num, mcr.cycle_time_den
        # chi_out > chi_in, compared exactly by cross-multiplication (as analyze does).
        slower = np.flatnonzero(num[a.dst] * den[a.src] > num[a.src] * den[a.dst])
        if not len(slower):
            return GroupRates(True)
        k = int(slower[0])
        place = teg.places[k]
        first = (*self._owner(place.origin, links, threads), k)
        names = teg.transition_names
        kind = _KIND_REPORTED.get(place.kind, "chain")
        return GroupRates(True, len(slower), first,  # type: ignore[arg-type]
                          f"{kind} at {names[place.src]} -> {names[place.dst]}")

    def _owner(self, origin: dict[str, Any], links: list[int], threads: list[int]
               ) -> tuple[int, int]:
        """Which part of the whole graph's place order a place of a group's graph is in."""
        if "thread" in origin:
            return _THREAD, threads[origin["thread"]]
        if "link_index" in origin:
            return _LINK, links[origin["link_index"]]
        if "task" in origin:
            return _TASK, self.task_index[origin["task"]]
        return _CLOCK, self.clock_index[origin["clock"]]

    def _overrun(self, skeleton: Skeleton, tasks: Sequence[str], key: tuple) -> GroupOverrun:
        found = self.overruns.get(key)
        if found is None:
            part, _, _ = self._part(skeleton, tasks)
            # The semiflow cross-check (no verdict depends on it) is left out.
            report = analyze_skeleton(part, semiflow_max_places=0)
            if report.unbounded_places or not report.live:  # pragma: no cover - stage 1 said
                raise AssertionError("internal error: the group's rates and analysis differ")
            late = [(self.task_index[t.name], t.name, t.overrun_at)
                    for t in report.tasks.values() if t.overrun_at is not None]
            found = GroupOverrun(late[0] if late else None)
            if len(self.overruns) >= MAX_CACHED:
                self.overruns.clear()
            self.overruns[key] = found
        return found


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
