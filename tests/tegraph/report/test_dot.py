"""DOT views with the critical and token-free circuits highlighted; networkx both ways."""

from __future__ import annotations

import re
from fractions import Fraction as F

import networkx as nx
import numpy as np

import tegraph
from tegraph import to_dot
from tegraph.model.convert import from_networkx, to_networkx
from tegraph.model.petri import PetriNet
from tegraph.model.teg import TimedEventGraph
from tests.paths import REPO

EXAMPLES = REPO / "examples"


def edges(dot: str) -> dict[tuple[str, str], str]:
    """Edge (tail, head) -> its attribute text, for the single edges of a DOT text."""
    return {(m.group(1), m.group(2)): m.group(3)
            for m in re.finditer(r'^\s*"([^"]*)" -> "([^"]*)" \[(.*)\];$', dot, re.MULTILINE)}


def two_circuits() -> TimedEventGraph:
    g = TimedEventGraph("two")
    for e in "abc":
        g.add_transition(e)
    g.add_place("a", "b", 0, 2)
    g.add_place("b", "a", 1, 3)   # circuit a-b: (2 + 3) / 1 = 5
    g.add_place("b", "c", 0, 1)
    g.add_place("c", "b", 1, 1)   # circuit b-c: (1 + 1) / 1 = 2
    return g


def test_teg_view_highlights_the_critical_circuit_only():
    dot = to_dot(two_circuits())
    e = edges(dot)
    red = {k for k, v in e.items() if 'color="red"' in v}
    assert red == {("a", "b"), ("b", "a")}  # the ratio-5 circuit, by hand
    assert "period 5" in dot and 'label="a -> b\\nh=2"' in e[("a", "b")]


def test_teg_view_highlights_a_token_free_circuit():
    g = two_circuits()
    g.add_place("c", "c", 0, 1, name="stuck")  # a self-loop without token
    e = edges(to_dot(g))
    dashed = {k for k, v in e.items() if 'style="dashed"' in v}
    assert dashed == {("c", "c")} and not any('color="red"' in v for v in e.values())


def test_skeleton_view_marks_the_tasks_and_links_of_a_deadlock():
    sk = tegraph.load_skeleton(EXAMPLES / "fig7a_circular_wait.yaml")
    report = tegraph.analyze(sk)
    dot = to_dot(sk)
    orange = set(re.findall(r'"task:([^"]+)" \[shape=box, label="[^"]*", color="darkorange"',
                            dot))
    # the analyze report names the tasks on the token-free circuit independently
    assert orange == set(report.deadlocks[0].tasks) == {"MT1", "MT2", "MT3"}
    assert sum('color="darkorange"' in v for v in edges(dot).values()) == len(sk.links)


def test_skeleton_can_also_be_drawn_as_its_teg(tmp_path):
    sk = tegraph.load_skeleton(EXAMPLES / "fig4_pipeline_synchronized.yaml")
    path = tegraph.write(sk, tmp_path / "teg.dot", format="teg-dot")
    text = path.read_text()
    built = tegraph.build_teg(sk)
    assert all(f'"{name}";' in text for name in built.transition_names)
    assert len(re.findall(r'^\s*"[^"]*" -> "[^"]*" \[', text, re.MULTILINE)) == built.n_places


def test_net_view_draws_places_and_transitions(anchors):
    net = tegraph.read(anchors / "pnml" / "HouseConstruction-PT-00002.pnml")
    dot = to_dot(net)
    assert dot.count("shape=circle") == 26 and dot.count("shape=box") == 18  # cases.json sizes
    assert "not a marked graph" in dot


def test_networkx_round_trip_of_a_net_and_of_a_teg():
    net = PetriNet("n", ["p", "q"], ["a"], np.array([[1], [0]]), np.array([[0], [2]]),
                   np.array([3, 0]), [F(1, 2), F(0)], [F(0), F(0)])
    G = to_networkx(net)
    assert nx.is_bipartite(G) and G.nodes["p"]["holding"] == F(1, 2)
    back = from_networkx(G)
    assert isinstance(back, PetriNet) and back.places == ["p", "q"]
    assert back.pre.tolist() == net.pre.tolist() and back.post.tolist() == net.post.tolist()
    assert back.holding == net.holding and back.marking.tolist() == [3, 0]
    g = two_circuits()
    h = from_networkx(to_networkx(g))
    assert isinstance(h, TimedEventGraph)
    assert [(p.src, p.dst, p.tokens, p.holding) for p in h.places] == \
        [(p.src, p.dst, p.tokens, p.holding) for p in g.places]


def test_a_multi_rate_skeleton_marks_each_groups_own_critical_circuit():
    # examples/computed_torque.yaml, by hand in its header: three groups, each
    # paced by its own clock's self-loop (obs 1 ms, ctl 2 ms, dyn 6 ms). Each
    # group runs at its own period, so each clock's loop is its group's critical
    # circuit; marking only dyn's (the slowest) would call it the design's.
    dot = to_dot(tegraph.load_skeleton(EXAMPLES / "computed_torque.yaml"), view="teg")
    red = {k for k, v in edges(dot).items() if 'color="red"' in v}
    assert red == {("obs.tick", "obs.tick"), ("ctl.tick", "ctl.tick"), ("dyn.tick", "dyn.tick")}
    assert "3 parts, each at its own period (1, 2, 6)" in dot


def test_a_group_that_is_not_rate_consistent_gets_no_period_in_its_caption():
    # examples/fig12_double_sync.yaml, by hand in its header: one group bound by
    # two clocks whose parts run at 10 ms and 4 ms: it is not rate-consistent,
    # so the drawing must not call 10 "the period" of the graph.
    dot = to_dot(tegraph.load_skeleton(EXAMPLES / "fig12_double_sync.yaml"), view="teg")
    assert "no common period: cycle times 4, 10" in dot and "period 10 (" not in dot
