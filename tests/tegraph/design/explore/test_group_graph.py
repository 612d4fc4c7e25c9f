"""A group's graph made from its template and its chosen links' edits (each read on the
link's two tasks alone) equals the graph ``build_teg`` builds for that configuration:
place by place, in order, the same ends (by event name), tokens, holding time, kind
and owner."""

from __future__ import annotations

from dataclasses import replace
from fractions import Fraction

from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph import Skeleton, load_skeleton
from tegraph.design.explore.group_graph import GroupGraph, link_edit
from tegraph.design.explore.incremental import _LINK, place_owner
from tegraph.model.build import build_teg
from tegraph.model.skeleton import Protocol
from tests.paths import REPO
from tests.tegraph.skeleton_corpus import random_skeleton


def _owner(sk: Skeleton):
    """A place's owner as the judge names it (kind, index in the file of ``sk``)."""
    tasks = {t: i for i, t in enumerate(sk.tasks)}
    clocks = {c: i for i, c in enumerate(sk.clocks)}
    links, threads = range(len(sk.links)), range(len(sk.threads))
    return lambda p: place_owner(p.origin, tasks, clocks, links, threads)


def _built(sk: Skeleton) -> list[tuple]:
    """Each place of ``build_teg(sk)``: its ends by name, tokens, holding, kind, owner."""
    teg = build_teg(sk)
    names, owner = teg.transition_names, _owner(sk)
    return [(names[p.src], names[p.dst], p.tokens, p.holding, p.kind, owner(p))
            for p in teg.places]


def _from_template(sk: Skeleton, graph: GroupGraph, protocols, periods) -> list[tuple]:
    edits = []
    for i in sorted(protocols):
        edit = link_edit(sk, i, protocols[i], protocols.keys())
        assert edit is not None  # every edit of spec §2 is recognised
        edits.append(((_LINK, i), edit))
    a = graph.arrays(edits, periods)
    return [(a.names[int(a.src[k])], a.names[int(a.dst[k])], int(a.tokens[k]),
             Fraction(int(a.holding[k]), a.scale), a.kinds[k], a.owners[k])
            for k in range(len(a.src))]


def _configure(sk: Skeleton, protocols: dict[int, Protocol], periods: dict) -> Skeleton:
    links = list(sk.links)
    for i, p in protocols.items():
        links[i] = replace(links[i], protocol=p)
    clocks = {c: replace(k, period=periods.get(c, k.period)) for c, k in sk.clocks.items()}
    return replace(sk, links=links, clocks=clocks)


@settings(max_examples=150, deadline=None)
@given(st.randoms(use_true_random=False))
def test_template_graph_equals_the_built_one(rng):
    sk = Skeleton.from_dict(random_skeleton(rng, max_tasks=6, max_ports=3))
    chosen = [i for i in range(len(sk.links)) if rng.random() < 0.7]
    clocks = [c for c in sk.clocks if rng.random() < 0.7]
    graph = GroupGraph(sk, chosen, clocks, _owner(sk))
    for _ in range(6):  # several configurations of one template (its edits are kept)
        protocols = {i: rng.choice(list(Protocol)) for i in chosen}
        periods = {c: rng.choice([Fraction(1, 3), Fraction(2), Fraction(7, 2), Fraction(10)])
                   for c in clocks}
        assert _from_template(sk, graph, protocols, periods) == \
            _built(_configure(sk, protocols, periods))


def test_a_rendezvous_is_the_writer_s_event_and_a_link_place_stands_among_the_links():
    """Figure 4's pipe-line: MT1:x1 -> MT2:x1 made SYN/SYN merges MT2.read:x1 into
    MT1.write:x1 (the reason names that event); ASYN/SYN adds its place."""
    sk = load_skeleton(REPO / "examples" / "fig4_pipeline_synchronized.yaml")
    first = next(i for i, x in enumerate(sk.links) if x.writer == ("MT1", "x1"))
    graph = GroupGraph(sk, [first], [], _owner(sk))
    for protocol in Protocol:
        protocols = {first: protocol}
        assert _from_template(sk, graph, protocols, {}) == \
            _built(_configure(sk, protocols, {}))
    edit = link_edit(sk, first, Protocol.SYN_SYN, [first])
    assert edit is not None and edit.merge == {"MT2.read:x1": "MT1.write:x1"}
    merged = graph.arrays([((_LINK, first), edit)], {})
    ends = {(merged.names[int(s)], merged.names[int(d)])
            for s, d in zip(merged.src, merged.dst)}
    assert ("MT1.write:x1", "MT2.compute") in ends
    assert all("MT2.read:x1" not in pair for pair in ends)
