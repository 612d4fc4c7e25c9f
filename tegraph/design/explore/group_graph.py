"""A group's timed event graph in every configuration of its chosen links, from few builds.

The variants of a design space differ in the protocols of a few links and the periods
of a few clocks. Inside one group (a fixed set of tasks), :func:`~tegraph.model.build.build_teg`
of a configuration differs from that of the *template* (every chosen link
of the group ASYN/ASYN, which adds no place and merges no event) only by what each
chosen link's own protocol contributes (spec §2): a place of the link (ASYN/SYN,
SYN/ASYN), or the reader's read event merged into the writer's write event
(SYN/SYN); a chosen clock's period is the holding time of the places whose
:class:`~tegraph.model.build.HoldingSource` is that clock's period.

Nothing of that is restated here: each link's contribution is *read* from
``build_teg`` itself, once per link and protocol, by comparing the graph of the
link's two tasks alone with the link at that protocol and at ASYN/ASYN
(:func:`link_edit`; events by name, so one reading serves every group the link lies
in). A configuration's arrays are then the template's with those edits applied, the
link's places before the first place of a later owner (``build_teg`` adds places
owner by owner: clocks, tasks, links, threads, each in file order). When a comparison
does not have that shape (a contribution this reading does not recognise),
:func:`link_edit` returns None and the caller builds the graph (the same result,
slower). Events are numbered as the template's: a merged-away read event stays as an
isolated node, which touches no place, so no cycle time a place reads and no circuit
changes; the cycle times of the rest are those of ``build_teg``'s graph up to that
renumbering.

Building a group's graph afresh is what a variant would otherwise cost; its arrays
from the template cost a small fraction of that, and a link's edit is read once per
space.
"""

from __future__ import annotations

import math
from bisect import bisect_left
from collections.abc import Callable, Collection, Mapping, Sequence
from dataclasses import dataclass, replace
from fractions import Fraction

import numpy as np

from maxplus.scalar import int_array

from ...model.build import build_teg, holding_sources
from ...model.skeleton import Protocol, Skeleton
from ...model.teg import Place, TimedEventGraph

__all__ = ["GroupArrays", "GroupGraph", "LinkEdit", "link_edit"]


@dataclass(frozen=True)
class LinkEdit:
    """What one chosen link at one protocol changes in a graph where it is ASYN/ASYN.

    Read from ``build_teg`` on the link's two tasks alone (:func:`link_edit`); events
    by name, so that it applies to every group the link lies in.

    Attributes
    ----------
    merge : dict of str to str
        Event -> the event it becomes (a SYN/SYN read merged into the write).
    places : tuple of (str, str, Place)
        Each place the link adds: its input and output events' names, and the place
        (its tokens and kind; its ``src``, ``dst`` and ``origin`` are the two-task
        graph's).
    """

    merge: dict[str, str]
    places: tuple[tuple[str, str, Place], ...]


def link_edit(skeleton: Skeleton, link: int, protocol: Protocol,
              chosen: Collection[int]) -> LinkEdit | None:
    """What ``skeleton.links[link]`` at ``protocol`` changes, read from ``build_teg``
    on the link's two tasks (the ``chosen`` links ASYN/ASYN, the others as they are);
    None when the change is not a merge of events and added places of holding time 0
    with no initial time (the caller then builds the graph)."""
    if protocol is Protocol.ASYN_ASYN:
        return LinkEdit({}, ())
    x = skeleton.links[link]
    pair = [t for t in skeleton.tasks if t in (x.writer[0], x.reader[0])]
    links = [replace(y, protocol=Protocol.ASYN_ASYN) if i in chosen else y
             for i, y in enumerate(skeleton.links)]
    # The two tasks alone, without threads (a thread may run through other tasks; its
    # places are no link's).
    base = replace(replace(skeleton, links=links).restricted_to(pair), threads=[])
    links = links[:]  # base may hold the list itself
    links[link] = replace(x, protocol=protocol)
    mine = replace(replace(skeleton, links=links).restricted_to(pair), threads=[])
    own_index = next(i for i, y in enumerate(mine.links) if y is links[link])
    old, new = build_teg(base), build_teg(mine)
    old_names, names = old.transition_names, new.transition_names
    if not set(names) <= set(old_names):
        return None
    own = [k for k, p in enumerate(new.places)
           if isinstance(p.origin, dict) and p.origin.get("link_index") == own_index]
    others = [p for k, p in enumerate(new.places) if k not in set(own)]
    if len(others) != len(old.places):
        return None
    merge: dict[str, str] = {}
    for p, q in zip(others, old.places):
        if (p.kind, p.origin, p.tokens, p.holding, p.initial) != \
                (q.kind, q.origin, q.tokens, q.holding, q.initial):
            return None
        for now, was in ((names[p.src], old_names[q.src]), (names[p.dst], old_names[q.dst])):
            if now != was and merge.setdefault(was, now) != now:
                return None
    if set(names) != set(old_names) - merge.keys():
        return None
    sources = holding_sources(new)
    added = []
    for k in own:
        p = new.places[k]
        if sources[k].kind != "none" or p.initial:
            return None
        added.append((names[p.src], names[p.dst], p))
    return LinkEdit(merge, tuple(added))


@dataclass(frozen=True)
class GroupArrays:
    """The arrays of one configuration's graph, as :meth:`TimedEventGraph.arrays` gives
    them (holding times scaled to integers), and what names its places.

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
    kinds, owners : list
        Each place's kind and owner (:class:`GroupGraph`).
    """

    src: np.ndarray
    dst: np.ndarray
    holding: np.ndarray
    tokens: np.ndarray
    scale: int
    n_nodes: int
    names: tuple[str, ...]
    kinds: list[str]
    owners: list[tuple[int, int]]


class GroupGraph:
    """The template graph of one group, to which chosen links' edits apply.

    Parameters
    ----------
    part : Skeleton
        The group cut out of a variant (:meth:`Skeleton.restricted_to`).
    chosen : collection of int
        Index in ``part.links`` of each chosen link inside the group (ASYN/ASYN in the
        template).
    clocks : collection of str
        The chosen clocks (their periods vary).
    owner : callable
        A place of the template's graph -> its owner as ``(kind, index in the file)``,
        kinds numbered in the order ``build_teg`` adds them (clocks, tasks, links,
        threads), so that the owners of the places in order are sorted; a link's places
        go before the first place of a larger owner (:meth:`arrays`).
    """

    def __init__(self, part: Skeleton, chosen: Collection[int], clocks: Collection[str],
                 owner: Callable[[Place], tuple[int, int]]) -> None:
        links = [replace(x, protocol=Protocol.ASYN_ASYN) if i in chosen else x
                 for i, x in enumerate(part.links)]
        self.teg: TimedEventGraph = build_teg(replace(part, links=links))
        a = self.teg.arrays()
        self.src, self.dst, self.tokens = a.src, a.dst, a.tokens
        self.holding, self.scale = a.holding, a.scale
        self.names = self.teg.transition_names
        self.index = {name: i for i, name in enumerate(self.names)}
        self.kinds = [p.kind for p in self.teg.places]
        self.owners = [owner(p) for p in self.teg.places]
        sources = holding_sources(self.teg)
        # The places whose holding time is a chosen clock's period.
        self.clock_places = {c: np.flatnonzero([s.kind == "period" and s.owner == c
                                                for s in sources]) for c in clocks}

    def arrays(self, edits: Sequence[tuple[tuple[int, int], LinkEdit]],
               periods: Mapping[str, Fraction]) -> GroupArrays:
        """The arrays of the group's graph with ``edits`` (each with its link's owner,
        in file order) and ``periods`` on its chosen clocks."""
        src, dst, holding, tokens = self.src, self.dst, self.holding, self.tokens
        kinds, owners = self.kinds, self.owners
        scale = self.scale
        if periods:
            holding, scale = self._holding(periods)
        index = self.index
        added = [(bisect_left(owners, owner), owner, a, b, p)
                 for owner, e in edits for a, b, p in e.places]
        if added:
            # np.insert keeps the given order at equal positions: the links' places in
            # file order, as build_teg adds them.
            at = [k for k, *_ in added]
            src = np.insert(src, at, [index[a] for _, _, a, _, _ in added])
            dst = np.insert(dst, at, [index[b] for _, _, _, b, _ in added])
            tokens = np.insert(tokens, at, [p.tokens for *_, p in added])
            holding = np.insert(holding, at, 0)
            kinds, owners = kinds[:], owners[:]
            for shift, (k, owner, _, _, p) in enumerate(added):
                kinds.insert(k + shift, p.kind)
                owners.insert(k + shift, owner)
        merge = {index[a]: index[b] for _, e in edits for a, b in e.merge.items()}
        if merge:
            node = np.arange(len(self.names))
            node[list(merge)] = list(merge.values())
            src, dst = node[src], node[dst]
        return GroupArrays(src, dst, holding, tokens, scale, len(self.names), self.names,
                           kinds, owners)

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
