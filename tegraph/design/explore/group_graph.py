"""A group's timed event graph in every configuration of its chosen links, from few builds.

The variants of a design space differ in the protocols of a few links and the periods
of a few clocks. Inside one group (a fixed set of tasks), :func:`~tegraph.model.build.
build_teg` of a configuration differs from that of the *template* (every chosen link
of the group ASYN/ASYN, which adds no place and merges no event) only by what each
chosen link's own protocol contributes (spec §2): a place of the link (ASYN/SYN,
SYN/ASYN), or the reader's read event merged into the writer's write event
(SYN/SYN); a chosen clock's period is the holding time of the places whose
:class:`~tegraph.model.build.HoldingSource` is that clock's period.

Nothing of that is restated here: each link's contribution is *read* from
``build_teg`` itself, once per link and protocol, by comparing its graph with the
template's (:meth:`GroupGraph.edit`); a configuration's arrays are then the
template's with those edits applied, in the place order ``build_teg`` gives (link
places among the links, in file order). When a comparison does not have that shape
(a contribution this reading does not recognise), :meth:`GroupGraph.arrays` returns
None and the caller builds the graph (the same result, slower). Events are numbered
as the template's: a merged-away read event stays as an isolated node, which touches
no place, so no cycle time a place reads and no circuit changes; the cycle times of
the rest are those of ``build_teg``'s graph up to that renumbering.

Building a 20-task group costs about 1 ms; its arrays from the template, some 30 µs.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from fractions import Fraction
from typing import Any

import numpy as np

from maxplus.scalar import int_array

from ...model.build import build_teg, holding_sources
from ...model.skeleton import Protocol, Skeleton
from ...model.teg import Place, TimedEventGraph

__all__ = ["GroupArrays", "GroupGraph"]


@dataclass(frozen=True)
class LinkEdit:
    """What one chosen link at one protocol changes in the template's graph.

    Attributes
    ----------
    merge : dict of int to int
        Template event -> the template event it becomes (a SYN/SYN read merged into
        the write).
    places : tuple of (int, Place)
        Each place the link adds, with the number of template places before it; its
        ``src``/``dst`` are template events.
    """

    merge: dict[int, int]
    places: tuple[tuple[int, Place], ...]


@dataclass(frozen=True)
class GroupArrays:
    """The arrays of one configuration's graph, as :meth:`TimedEventGraph.arrays` gives
    them (holding times scaled to integers) and what names its places.

    Attributes
    ----------
    src, dst, holding, tokens : numpy.ndarray
        One entry per place, in ``build_teg``'s place order.
    scale : int
        The holding times are ``holding / scale``.
    n_nodes : int
        Events (the template's).
    names : tuple of str
        Event names (the template's; a merged event is named as ``build_teg`` names it).
    where : numpy.ndarray
        Each place's index among the template's places, or ``-1 - i`` for the i-th of
        ``added``.
    template, added : tuple of Place
        The template's places, and those the chosen links add (:meth:`place`).
    """

    src: np.ndarray
    dst: np.ndarray
    holding: np.ndarray
    tokens: np.ndarray
    scale: int
    n_nodes: int
    names: tuple[str, ...]
    where: np.ndarray
    template: tuple[Place, ...]
    added: tuple[Place, ...]

    def place(self, k: int) -> Place:
        """The ``k``-th place (its kind and origin as ``build_teg`` gives them)."""
        w = int(self.where[k])
        return self.template[w] if w >= 0 else self.added[-1 - w]


class GroupGraph:
    """The template graph of one group and the edits of its chosen links.

    Parameters
    ----------
    part : Skeleton
        The group cut out of a variant (:meth:`Skeleton.restricted_to`).
    chosen : mapping of int to tuple of Protocol
        Index in ``part.links`` of each chosen link inside the group -> its choices.
    clocks : collection of str
        The chosen clocks (their periods vary).
    """

    def __init__(self, part: Skeleton, chosen: Mapping[int, tuple[Protocol, ...]],
                 clocks: Any) -> None:
        links = list(part.links)
        for i in chosen:
            links[i] = replace(links[i], protocol=Protocol.ASYN_ASYN)
        self.part = replace(part, links=links)
        self.chosen = dict(chosen)
        self.teg: TimedEventGraph = build_teg(self.part)
        a = self.teg.arrays()
        self.src, self.dst, self.tokens = a.src, a.dst, a.tokens
        self.holding, self.scale = a.holding, a.scale
        self.names = self.teg.transition_names
        self.index = {name: i for i, name in enumerate(self.names)}
        sources = holding_sources(self.teg)
        # The places whose holding time is a chosen clock's period.
        self.clock_places = {c: np.flatnonzero([s.kind == "period" and s.owner == c
                                                for s in sources]) for c in clocks}
        self.edits: dict[tuple[int, Protocol], LinkEdit | None] = {}

    def edit(self, link: int, protocol: Protocol) -> LinkEdit | None:
        """What ``link`` (an index in ``part.links``) at ``protocol`` changes, read from
        ``build_teg``; None when the change is not a merge of events and added places
        of holding time 0 (the caller then builds the graph)."""
        key = (link, protocol)
        if key not in self.edits:
            self.edits[key] = self._read_edit(link, protocol)
        return self.edits[key]

    def _read_edit(self, link: int, protocol: Protocol) -> LinkEdit | None:
        if protocol is Protocol.ASYN_ASYN:
            return LinkEdit({}, ())
        links = list(self.part.links)
        links[link] = replace(links[link], protocol=protocol)
        teg = build_teg(replace(self.part, links=links))
        names, index = teg.transition_names, self.index
        if not set(names) <= index.keys():
            return None
        own = [k for k, p in enumerate(teg.places)
               if isinstance(p.origin, dict) and p.origin.get("link_index") == link]
        others = [p for k, p in enumerate(teg.places) if k not in set(own)]
        template = self.teg.places
        if len(others) != len(template):
            return None
        merge: dict[int, int] = {}
        for p, q in zip(others, template):
            if (p.kind, p.origin, p.tokens, p.holding, p.initial) != \
                    (q.kind, q.origin, q.tokens, q.holding, q.initial):
                return None
            for new, old in ((index[names[p.src]], q.src), (index[names[p.dst]], q.dst)):
                if new != old and merge.setdefault(old, new) != new:
                    return None
        if set(names) != set(self.names) - {self.names[e] for e in merge}:
            return None
        sources = holding_sources(teg)
        added = []
        for n, k in enumerate(own):
            p = teg.places[k]
            if sources[k].kind != "none" or p.initial:
                return None
            added.append((k - n, replace(p, src=index[names[p.src]], dst=index[names[p.dst]])))
        return LinkEdit(merge, tuple(added))

    def arrays(self, protocols: Mapping[int, Protocol],
               periods: Mapping[str, Fraction]) -> GroupArrays | None:
        """The arrays of the group's graph with ``protocols`` on its chosen links (part
        index -> protocol) and ``periods`` on its chosen clocks; None when an edit is
        not recognised (:meth:`edit`)."""
        edits = []
        for link in sorted(protocols):
            e = self.edit(link, protocols[link])
            if e is None:
                return None
            edits.append(e)
        src, dst, holding, tokens = self.src, self.dst, self.holding, self.tokens
        scale = self.scale
        if periods:
            holding, scale = self._holding(periods)
        added = tuple(p for e in edits for _, p in e.places)
        where = np.arange(len(self.src))
        if added:
            # np.insert keeps the given order at equal positions: the links' places in
            # file order, as build_teg adds them.
            at = [k for e in edits for k, _ in e.places]
            src = np.insert(src, at, [p.src for p in added])
            dst = np.insert(dst, at, [p.dst for p in added])
            tokens = np.insert(tokens, at, [p.tokens for p in added])
            holding = np.insert(holding, at, 0)
            where = np.insert(where, at, -1 - np.arange(len(added)))
        merge = {a: b for e in edits for a, b in e.merge.items()}
        if merge:
            if merge.keys() & set(merge.values()):  # a chain of merges: not one edit each
                return None
            node = np.arange(len(self.names))
            node[list(merge)] = list(merge.values())
            src, dst = node[src], node[dst]
        return GroupArrays(src, dst, holding, tokens, scale, len(self.names), self.names, where,
                           self.teg.places, added)

    def _holding(self, periods: Mapping[str, Fraction]) -> tuple[np.ndarray, int]:
        """The template's holding times with ``periods`` on the chosen clocks' places,
        scaled to integers (by a multiple of the template's scale), and the scale."""
        scale = math.lcm(self.scale, *(p.denominator for p in periods.values()))
        factor = scale // self.scale
        values = [int(h) * factor for h in self.holding.tolist()]
        for c, period in periods.items():
            for k in self.clock_places[c].tolist():
                values[k] = int(period * scale)
        return int_array(values), scale
