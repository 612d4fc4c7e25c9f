"""Each group of a skeleton as a parametric event graph in the varied parameters.

Every holding time of the timed event graph is an affine function of the
parameters (:mod:`.parameters`): a :class:`ParametricGroup` is one group's
graph with each place holding a constant or one parameter.

This module does not restate spec §2: it reads the affine structure off the
record :func:`~tegraph.model.build.build_teg` keeps, the parameter each
holding time is (:func:`~tegraph.model.build.holding_sources`) and when each
activation ends (:func:`~tegraph.model.build.activation_end`). So a change of
spec §2 or §4 flows through.

Groups are independent (no place joins two of them), so every later step
works on one small group at a time, with its own exact scale.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from ...model.build import activation_end, build_teg, holding_sources
from ...model.skeleton import Link, Skeleton
from ...model.structure import Structure
from ...model.teg import Place
from .parameters import DELAY_KINDS, Parameter

__all__ = ["ClockInfo", "ParametricGroup", "Watch", "parametric_groups"]


@dataclass(frozen=True)
class ClockInfo:
    """A clock of a group: its tick event, its period (a parameter or a constant), phase."""

    name: str
    tick: int
    period: Fraction
    period_param: int
    phase: Fraction


@dataclass(frozen=True)
class Watch:
    """A clocked task whose overruns are watched.

    Its activation k ends at ``x_end(k) + offset`` (``offset`` its duration
    when the activation ends with its computation, spec §4, else 0:
    :class:`~tegraph.model.build.ActivationEnd`).
    """

    task: str
    clock: str
    end: int
    offset: Fraction
    offset_param: int


# Keyword-only: fourteen fields, five of them arrays of int64; a positional call cannot be read.
@dataclass(kw_only=True)
class ParametricGroup:
    """One group's timed event graph, each holding ``const + θ[param]`` (param -1: none).

    Attributes
    ----------
    index : int
        Position of the group (spec §4 order).
    tasks : tuple of str
    skeleton : Skeleton
        The group alone (:meth:`Skeleton.restricted_to`).
    names : tuple of str
        Event names.
    src, dst, tokens, param : numpy.ndarray of int64
        Per place; ``param`` is the index of the parameter it holds, or -1.
    const, initial : list of Fraction
        Per place: constant holding (0 where a parameter is held) and the
        availability time of its initial tokens.
    places : tuple of Place
        The built places (kinds and origins, for naming causes).
    clocks : dict of str to ClockInfo
    watches : list of Watch
        The clocked tasks.
    params : tuple of int
        The parameters the group depends on.
    """

    index: int
    tasks: tuple[str, ...]
    skeleton: Skeleton
    names: tuple[str, ...]
    src: np.ndarray
    dst: np.ndarray
    tokens: np.ndarray
    param: np.ndarray
    const: list[Fraction]
    initial: list[Fraction]
    places: tuple[Place, ...]
    clocks: dict[str, ClockInfo]
    watches: list[Watch]
    params: tuple[int, ...]
    live: bool = True
    component: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    """Strongly connected component of each event."""
    sources: list[int] = field(default_factory=list)
    """One event of each source component (no place enters it from another component)."""
    event_owners: tuple[tuple[str, ...], ...] = ()
    """The tasks whose chain holds each event (none for a tick)."""

    @property
    def n_events(self) -> int:
        """The number of events of the group's graph."""
        return len(self.names)

    def values(self, theta: Mapping[int, Fraction], nominal: Sequence[Fraction]
               ) -> dict[int, Fraction]:
        """The value of each of the group's parameters: ``theta`` where given, else nominal."""
        return {j: theta.get(j, nominal[j]) for j in self.params}

    def holdings(self, values: Mapping[int, Fraction]) -> list[Fraction]:
        """Holding time of every place at the parameter values ``values``."""
        return [c if j < 0 else values[j]
                for c, j in zip(self.const, self.param.tolist())]

    def period(self, clock: str, values: Mapping[int, Fraction]) -> Fraction:
        """The period of ``clock`` at ``values`` (its parameter's value, else its constant)."""
        info = self.clocks[clock]
        return info.period if info.period_param < 0 else values[info.period_param]

    def offset(self, watch: Watch, values: Mapping[int, Fraction]) -> Fraction:
        """The offset of ``watch`` at ``values`` (its parameter's value, else its constant)."""
        return watch.offset if watch.offset_param < 0 else values[watch.offset_param]


def parametric_groups(skeleton: Skeleton, params: Sequence[Parameter],
                      structure: Structure | None = None) -> list[ParametricGroup]:
    """Every group of the skeleton as a :class:`ParametricGroup`, in spec §4 order.

    ``structure`` is ``Structure.of(skeleton)``, if known (``report.structure``):
    its groups, so numbered as the analysis numbers them.

    Examples
    --------
    >>> from tegraph.analysis.sensitivity.parameters import parse_vary
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 5}}})
    >>> g, = parametric_groups(sk, parse_vary(sk))
    >>> g.names, g.param.tolist(), [str(c) for c in g.const]
    (('A.clock.tick', 'A.activate', 'A.compute'), [-1, -1, -1, 0], ['5', '0', '0', '0'])
    """
    by_owner = {(p.kind, p.owner): j for j, p in enumerate(params)}
    structure = Structure.of(skeleton) if structure is None else structure
    groups, group_of = structure.groups, structure.group_of
    links: list[list[Link]] = [[] for _ in groups]
    for link in skeleton.links:
        if link.protocol.synchronizing:
            links[group_of[link.writer[0]]].append(link)
    threads: list[list] = [[] for _ in groups]
    for thread in skeleton.threads:
        threads[group_of[thread[0]]].append(thread)
    out = []
    for g, tasks in enumerate(groups):
        own = [skeleton.tasks[t] for t in tasks]
        clocks = {c: skeleton.clocks[c] for c in dict.fromkeys(
            task.clock for task in own if task.clock is not None)}
        # The processors and the network go with the group: its links' delays (§4d).
        sub = Skeleton(skeleton.name, {t: skeleton.tasks[t] for t in tasks}, clocks, links[g],
                       threads[g], skeleton.unit,
                       processors={p: q for p, q in skeleton.processors.items()
                                   if any(task.runs_on == p for task in own)},
                       network_delay=skeleton.network_delay)
        local = sorted([(by_owner[("duration", t)], "duration", t) for t in tasks
                        if ("duration", t) in by_owner]
                       + [(by_owner[("period", c)], "period", c) for c in clocks
                          if ("period", c) in by_owner])
        out.append(_parametric_group(sub, g, local, by_owner))
    _structure(out)
    return out


def _parametric_group(sub: Skeleton, index: int, local: list[tuple[int, str, str]],
                      by_owner: Mapping[tuple[str, str], int]) -> ParametricGroup:
    """The group ``sub`` built once; each place holds the varied parameter its
    recorded source names, or its built (constant) holding.

    ``local``: the group's durations and periods; the delays it depends on are those
    its places hold (a link without a place, ASYN/ASYN, moves no holding time)."""
    teg = build_teg(sub)
    sources = holding_sources(teg)
    local = sorted({*local, *((by_owner[(s.kind, s.owner)], s.kind, s.owner) for s in sources
                              if s.kind in DELAY_KINDS and (s.kind, s.owner) in by_owner)})
    param_of = {(kind, owner): j for j, kind, owner in local}
    places = teg.places
    param = [param_of.get((source.kind, source.owner), -1) for source in sources]
    const = [Fraction(0) if j >= 0 else p.holding for p, j in zip(places, param)]
    ticks = teg.attrs["clocks"]
    clocks = {c: ClockInfo(c, ticks[c], clock.period, param_of.get(("period", c), -1),
                           clock.phase)
              for c, clock in sub.clocks.items()}
    watches = []
    for t, task in sub.tasks.items():
        if task.clock is None:
            continue
        end = activation_end(teg, t)
        # The end's offset is the task's duration when it is added, so it varies with it.
        watches.append(Watch(t, task.clock, end.event, end.offset,
                             param_of.get(("duration", t), -1) if end.adds_duration else -1))
    group = ParametricGroup(
        index=index, tasks=tuple(sub.tasks), skeleton=sub, names=teg.transition_names,
        src=np.array([p.src for p in places], dtype=np.int64),
        dst=np.array([p.dst for p in places], dtype=np.int64),
        tokens=np.array([p.tokens for p in places], dtype=np.int64),
        param=np.array(param, dtype=np.int64), const=const,
        initial=[p.initial for p in places], places=tuple(places), clocks=clocks,
        watches=watches, params=tuple(j for j, _, _ in local))
    group.event_owners = tuple(tuple(a.get("tasks", ())) for a in teg.transition_attrs)
    return group


def _structure(groups: Sequence[ParametricGroup]) -> None:
    """Liveness, strongly connected and source components of every group (all at once).

    They do not depend on times. A group is live when no circuit of 0-token
    places exists (spec §4); a source component is one no place enters.
    """
    if not groups:
        return
    offset = np.concatenate(([0], np.cumsum([g.n_events for g in groups])))
    n = int(offset[-1])
    src = np.concatenate([g.src + offset[i] for i, g in enumerate(groups)])
    dst = np.concatenate([g.dst + offset[i] for i, g in enumerate(groups)])
    empty = np.concatenate([g.tokens == 0 for g in groups])
    zero = sp.csr_matrix((np.ones(int(empty.sum()), dtype=np.int8), (src[empty], dst[empty])),
                         shape=(n, n))
    n_zero, zero_label = connected_components(zero, directed=True, connection="strong")
    sizes = np.bincount(zero_label, minlength=n_zero)
    dead = sizes[zero_label] > 1
    dead[src[empty & (src == dst)]] = True
    graph = sp.csr_matrix((np.ones(len(src), dtype=np.int8), (src, dst)), shape=(n, n))
    _, component = connected_components(graph, directed=True, connection="strong")
    entered = np.zeros(int(component.max()) + 1, dtype=bool)
    entered[component[dst[component[src] != component[dst]]]] = True
    for i, g in enumerate(groups):
        lo, hi = int(offset[i]), int(offset[i + 1])
        g.live = not dead[lo:hi].any()
        local = component[lo:hi]
        g.component = local - local.min()
        _, first = np.unique(local, return_index=True)
        g.sources = sorted(int(e) for e in first if not entered[local[e]])
