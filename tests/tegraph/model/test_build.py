"""Tests of tegraph.build: the TEG of a skeleton, rule by rule (spec §2).

Skeletons are built from the dataclasses directly. Every expected firing time
is derived by hand from the spec §3 recursion in the comments.
"""

from __future__ import annotations

from fractions import Fraction as F
from pathlib import Path

import networkx as nx
import numpy as np
import pytest

from tegraph.errors import ModelError, NotLiveError
from tegraph.io.skeleton_file import load_skeleton
from tegraph.model.build import (
    PLACE_KINDS,
    ActivationEnd,
    HoldingSource,
    activation_end,
    build_teg,
    compute_events,
    first_event,
    holding_sources,
    last_event,
    task_chain,
)
from tegraph.model.skeleton import Clock, Link, Protocol, Skeleton, Task
from tegraph.model.teg import TimedEventGraph


def skeleton(tasks, clocks=(), links=(), threads=()):
    return Skeleton("test", {t.name: t for t in tasks}, {c.name: c for c in clocks},
                    list(links), [tuple(t) for t in threads])


def names(g, indices):
    return [g.transition_names[i] for i in indices]


def edges(g, kind=None):
    """(src name, dst name, tokens, holding) of every place (of one kind)."""
    return [(g.transition_names[p.src], g.transition_names[p.dst], p.tokens, p.holding)
            for p in g.places if kind is None or p.kind == kind]


def zero_token_graph(g):
    z = nx.DiGraph()
    z.add_nodes_from(g.transition_names)
    z.add_edges_from((a, b) for a, b, m, _ in edges(g) if m == 0)
    return z


# --------------------------------------------------------------------------- Figure 8
# The paper's W for Figure 8 (rows p1..p7, columns t1..t6). Its real-time clock
# has two transitions, t1 (ticks, activates the task: p3 = t1 -> t3) and t2
# (circuit p1 = t2 -> t1, p2 = t1 -> t2); the task is t3 activate, t4 read,
# t5 compute, t6 write, with p5 = t3->t4, p6 = t4->t5, p7 = t5->t6 and the
# marked return p4 = t6 -> t3.
PAPER_W = np.array([
    [-1, 1, 0, 0, 0, 0],
    [1, -1, 0, 0, 0, 0],
    [1, 0, -1, 0, 0, 0],
    [0, 0, -1, 0, 0, 1],
    [0, 0, 1, -1, 0, 0],
    [0, 0, 0, 1, -1, 0],
    [0, 0, 0, 0, 1, -1],
])


def fig8():
    return skeleton([Task("MT", F(3), clock="rtc", inputs=("in",), outputs=("out",))],
                    [Clock("rtc", F(10))])


def test_figure_8_events_places_and_incidence_against_the_paper():
    g = build_teg(fig8())
    assert g.transition_names == ("rtc.tick", "MT.activate", "MT.read:in", "MT.compute",
                                  "MT.write:out")
    assert edges(g) == [("rtc.tick", "rtc.tick", 1, 10), ("rtc.tick", "MT.activate", 0, 0),
                        ("MT.activate", "MT.read:in", 0, 0), ("MT.read:in", "MT.compute", 0, 0),
                        ("MT.compute", "MT.write:out", 0, 3),
                        ("MT.write:out", "MT.activate", 1, 0)]
    W = g.incidence_matrix().toarray()
    # Our clock is ONE event rtc.tick with a self-loop (a zero row of W, place 0),
    # where the paper has t1 and t2. Merging the paper's t1 and t2 (adding their
    # columns) makes p1 and p2 zero rows, i.e. both become our self-loop. Column
    # map: rtc.tick = t1 + t2, MT.activate = t3, read = t4, compute = t5,
    # write = t6. Row map (paper p1..p7 -> our place): p1, p2 -> 0 (self-loop),
    # p3 -> 1 (activation), p4 -> 5 (return), p5 -> 2, p6 -> 3, p7 -> 4.
    merge = np.zeros((6, 5), dtype=int)
    for t, col in enumerate([0, 0, 1, 2, 3, 4]):
        merge[t, col] = 1
    rows = [0, 0, 1, 5, 2, 3, 4]
    assert (PAPER_W @ merge).tolist() == W[rows].tolist()
    # On the task's places (p3..p7), which do not touch t2, W is the paper's
    # exactly, up to that permutation, and so is the initial marking M0.
    assert W[rows[2:]].tolist() == PAPER_W[2:][:, [0, 2, 3, 4, 5]].tolist()
    assert g.arrays().tokens[rows[2:]].tolist() == [0, 1, 0, 0, 0]


# --------------------------------------------------------------------------- Figure 7b / 10
def fig7b(mt2_inputs):
    """MT1 (clock rtc) writes a to MT2 (SYN/SYN) then b to MT3 (ASYN/SYN); MT3
    writes c to MT2 (ASYN/SYN). The paper: MT2 reading c first deadlocks."""
    return skeleton(
        [Task("MT1", F(2), clock="rtc", outputs=("a", "b")),
         Task("MT2", F(4), inputs=mt2_inputs),
         Task("MT3", F(3), inputs=("b",), outputs=("c",))],
        [Clock("rtc", F(10))],
        [Link(("MT1", "a"), ("MT2", "a"), Protocol.SYN_SYN),
         Link(("MT1", "b"), ("MT3", "b"), Protocol.ASYN_SYN),
         Link(("MT3", "c"), ("MT2", "c"), Protocol.ASYN_SYN)])


def test_figure_7b_deadlock_counts_and_token_free_circuit():
    g = build_teg(fig7b(("c", "a")))
    # Events: rtc.tick; MT1: activate, compute, write:a, write:b; MT2: read:c,
    # (read:a is MT1.write:a), compute; MT3: read:b, compute, write:c -> 10.
    assert g.transition_names == (
        "rtc.tick", "MT1.activate", "MT1.compute", "MT1.write:a", "MT1.write:b",
        "MT2.read:c", "MT2.compute", "MT3.read:b", "MT3.compute", "MT3.write:c")
    # Places: clock 1 + activation 1 + MT1 chain 3 + return 1 + MT2 chain 2 +
    # return 1 + MT3 chain 2 + return 1 + two ASYN/SYN links = 14.
    assert g.n_places == 14
    kinds = [p.kind for p in g.places]
    assert {k: kinds.count(k) for k in set(kinds)} == {
        "clock": 1, "activation": 1, "chain": 7, "return": 3, "asyn-syn": 2}
    # The deadlock of the paper: MT2 waits for c from MT3, which waits for b
    # from MT1, which waits for MT2 at the rendezvous on a.
    expected = ["MT2.read:c", "MT1.write:a", "MT1.write:b", "MT3.read:b", "MT3.compute",
                "MT3.write:c"]
    cycles = list(nx.simple_cycles(zero_token_graph(g)))
    assert len(cycles) == 1
    c = cycles[0]
    assert c[c.index("MT2.read:c"):] + c[:c.index("MT2.read:c")] == expected
    with pytest.raises(NotLiveError) as info:
        g.simulate(1)
    assert sorted(info.value.circuit) == sorted(expected)
    tasks = {t for e in info.value.circuit for t in g.transition_attrs[g.index(e)]["tasks"]}
    assert tasks == {"MT1", "MT2", "MT3"}


def test_figure_7b_reordered_is_live_and_runs_at_the_clock_period():
    g = build_teg(fig7b(("a", "c")))
    assert g.n_transitions == 10 and g.n_places == 14
    assert nx.is_directed_acyclic_graph(zero_token_graph(g))
    # k = 1: tick 0, MT1 starts 0, rendezvous a at 0 + 2 = 2, write:b 2; MT3
    # reads b at 2, writes c at 5; MT2 reads c at max(2, 5) = 5, computes from 5.
    # k = 2: tick 10 > 2 so MT1 starts 10, a at max(12, 5 + 4) = 12, MT3 reads 12,
    # c at 15, MT2 at 15: every event repeats with period 10 from k = 1.
    d = g.simulate(4)
    for k in range(1, 5):
        assert d["MT1.compute"][k - 1] == 10 * (k - 1)
        assert d["MT1.write:a"][k - 1] == 10 * (k - 1) + 2
        assert d["MT3.write:c"][k - 1] == 10 * (k - 1) + 5
        assert d["MT2.compute"][k - 1] == 10 * (k - 1) + 5


# --------------------------------------------------------------------------- protocols
def pair(protocol, writer_first=True, reader_duration=F(7)):
    w = Task("W", F(1), clock="c", outputs=("p",))
    r = Task("R", reader_duration, inputs=("q",))
    return skeleton([w, r] if writer_first else [r, w], [Clock("c", F(5))],
                    [Link(("W", "p"), ("R", "q"), protocol)])


@pytest.mark.parametrize("writer_first", [True, False])
def test_syn_syn_is_one_event_on_both_chains(writer_first):
    g = build_teg(pair(Protocol.SYN_SYN, writer_first))
    assert "R.read:q" not in g.transition_names and g.n_transitions == 5
    e = g.index("W.write:p")
    assert g.transition_attrs[e] == {
        "role": "rendezvous", "tasks": ("W", "R") if writer_first else ("R", "W"),
        "ports": (("W", "p"), ("R", "q")), "clock": None}
    assert names(g, task_chain(g, "W")) == ["W.activate", "W.compute", "W.write:p"]
    assert names(g, task_chain(g, "R")) == ["W.write:p", "R.compute"]
    assert sorted(edges(g, "chain") + edges(g, "return")) == sorted([
        ("W.activate", "W.compute", 0, 0), ("W.compute", "W.write:p", 0, 1),
        ("W.write:p", "W.activate", 1, 0),
        ("W.write:p", "R.compute", 0, 0), ("R.compute", "W.write:p", 1, 7)])
    assert g.n_places == 7  # + clock self-loop + activation
    # x_e(k) = max(x_W.compute(k) + 1, x_R.compute(k-1) + 7), x_W.activate(k) =
    # max(5(k-1), x_e(k-1)): e = 1, 8, 15, 22 (R's 7 dominates) and W.activate =
    # 0, max(5, 1) = 5, max(10, 8) = 10, max(15, 15) = 15, max(20, 22) = 22.
    d = g.simulate(5)
    assert d["W.write:p"] == [F(1), F(8), F(15), F(22), F(29)]
    assert d["R.compute"] == d["W.write:p"]
    assert d["W.activate"] == [F(0), F(5), F(10), F(15), F(22)]


def test_one_output_port_rendezvous_with_two_readers():
    sk = skeleton([Task("W", F(1), outputs=("p",)), Task("R1", F(1), inputs=("q",)),
                   Task("R2", F(1), inputs=("q",))],
                  links=[Link(("W", "p"), ("R1", "q"), Protocol.SYN_SYN),
                         Link(("W", "p"), ("R2", "q"), Protocol.SYN_SYN)])
    g = build_teg(sk)
    assert g.transition_names == ("W.compute", "W.write:p", "R1.compute", "R2.compute")
    assert g.transition_attrs[1]["tasks"] == ("W", "R1", "R2")
    assert g.transition_attrs[1]["ports"] == (("W", "p"), ("R1", "q"), ("R2", "q"))


def test_asyn_syn_place_goes_writer_to_reader():
    g = build_teg(pair(Protocol.ASYN_SYN, reader_duration=F(3)))
    assert edges(g, "asyn-syn") == [("W.write:p", "R.read:q", 0, 0)]
    assert g.places[-1].origin == {"link": "W:p -> R:q (ASYN/SYN)", "link_index": 0}
    # W: write at 5(k-1) + 1; R (3 < 5) waits for each message: reads at 5(k-1) + 1.
    assert g.simulate(4)["R.read:q"] == [F(5 * (k - 1) + 1) for k in range(1, 5)]


def test_syn_asyn_place_goes_reader_to_writer():
    g = build_teg(pair(Protocol.SYN_ASYN, reader_duration=F(25)))
    assert edges(g, "syn-asyn") == [("R.read:q", "W.write:p", 0, 0)]
    # R runs freely: reads at 25(k-1). W.write(k) = max(W.compute(k) + 1, 25(k-1)),
    # W.activate(k) = max(5(k-1), W.write(k-1)): write 1, 25, 50, 75; activate 0, 5, 25, 50.
    d = g.simulate(4)
    assert d["R.read:q"] == [F(0), F(25), F(50), F(75)]
    assert d["W.write:p"] == [F(1), F(25), F(50), F(75)]
    assert d["W.activate"] == [F(0), F(5), F(25), F(50)]


def test_asyn_asyn_adds_nothing():
    g = build_teg(pair(Protocol.ASYN_ASYN))
    assert g.n_places == 7 and "R.read:q" in g.transition_names
    assert nx.number_weakly_connected_components(g.to_networkx()) == 2


# ------------------------------------------------------------------------ chains, clocks, threads
@pytest.mark.parametrize("duration, expected", [
    # x_tick(k) = 1 + 4(k-1); x_activate(k) = max(x_tick(k), x_compute(k-1) + d).
    (F(3), [F(1), F(5), F(9), F(13)]),        # 3 <= 4: follows the clock
    (F(5), [F(1), F(6), F(11), F(16)]),       # 5 > 4: 1 + 5(k-1), the clock overruns
])
def test_clocked_task_period_4_phase_1(duration, expected):
    g = build_teg(skeleton([Task("T", duration, clock="c")], [Clock("c", F(4), F(1))]))
    assert edges(g) == [("c.tick", "c.tick", 1, 4), ("c.tick", "T.activate", 0, 0),
                        ("T.activate", "T.compute", 0, 0), ("T.compute", "T.activate", 1, duration)]
    assert g.places[0].initial == 1
    d = g.simulate(4)
    assert d["c.tick"] == [F(1), F(5), F(9), F(13)]
    assert d["T.activate"] == expected and d["T.compute"] == expected


def test_one_event_chain_is_a_self_loop_on_compute():
    g = build_teg(skeleton([Task("X", F(5, 2))]))
    assert g.transition_names == ("X.compute",)
    assert edges(g) == [("X.compute", "X.compute", 1, F(5, 2))] and g.places[0].kind == "return"
    assert g.incidence_matrix().toarray().tolist() == [[0]]
    assert g.simulate(3)["X.compute"] == [F(0), F(5, 2), F(5)]
    assert first_event(g, "X") == last_event(g, "X") == 0


def test_chain_order_and_duration_on_the_place_leaving_compute():
    g = build_teg(skeleton([Task("T", F(7), clock="c", inputs=("i1", "i2"), outputs=("o1", "o2"))],
                           [Clock("c", F(9))]))
    assert names(g, task_chain(g, "T")) == ["T.activate", "T.read:i1", "T.read:i2", "T.compute",
                                            "T.write:o1", "T.write:o2"]
    held = [(a, b) for a, b, _, h in edges(g) if h != 0 and a != b]
    assert held == [("T.compute", "T.write:o1")]
    assert edges(g, "return") == [("T.write:o2", "T.activate", 1, 0)]
    roles = [a["role"] for a in g.transition_attrs]
    assert roles == ["tick", "activate", "read", "read", "compute", "write", "write"]
    assert g.transition_attrs[1]["clock"] == "c" and g.transition_attrs[0]["clock"] == "c"
    # Without outputs the return place leaves compute: it holds the duration.
    g2 = build_teg(skeleton([Task("T", F(7), inputs=("i",))]))
    assert edges(g2) == [("T.read:i", "T.compute", 0, 0), ("T.compute", "T.read:i", 1, 7)]


def test_thread_places_and_sequential_run():
    sk = skeleton([Task(n, F(d), outputs=("o",)) for n, d in (("A", 1), ("B", 2), ("C", 3))],
                  threads=[("A", "B", "C")])
    g = build_teg(sk)
    assert edges(g, "thread") == [("A.write:o", "B.compute", 0, 0),
                                  ("B.write:o", "C.compute", 0, 0)]
    assert edges(g, "thread-return") == [("C.write:o", "A.compute", 1, 0)]
    assert [p.origin for p in g.places if p.kind.startswith("thread")] == [
        {"thread": 0, "from": "A", "to": "B"}, {"thread": 0, "from": "B", "to": "C"},
        {"thread": 0, "from": "C", "to": "A"}]
    # One after the other: A at 6(k-1), B when A wrote (+1), C when B wrote (+1+2),
    # A again when C wrote (+6).
    d = g.simulate(3)
    assert d["A.compute"] == [F(0), F(6), F(12)]
    assert d["B.compute"] == [F(1), F(7), F(13)]
    assert d["C.compute"] == [F(3), F(9), F(15)]
    assert d["C.write:o"] == [F(6), F(12), F(18)]


def test_shared_clock_private_clock_and_provenance():
    sk = skeleton([Task("A", F(1), clock="rtc"), Task("B", F(1), clock="rtc"),
                   Task("P", F(2), clock="P.clock")],
                  [Clock("rtc", F(3)), Clock("P.clock", F(4), F(2), private=True)])
    g = build_teg(sk)
    assert g.transition_names[:2] == ("rtc.tick", "P.clock.tick")
    assert edges(g, "activation") == [("rtc.tick", "A.activate", 0, 0),
                                      ("rtc.tick", "B.activate", 0, 0),
                                      ("P.clock.tick", "P.activate", 0, 0)]
    assert [p.origin for p in g.places if p.kind in ("clock", "activation")] == [
        {"clock": "rtc"}, {"clock": "P.clock"}, {"clock": "rtc", "task": "A"},
        {"clock": "rtc", "task": "B"}, {"clock": "P.clock", "task": "P"}]
    assert {p.origin["task"] for p in g.places if p.kind in ("chain", "return")} == {"A", "B", "P"}
    assert g.transition_attrs[0] == {"role": "tick", "tasks": (), "ports": (), "clock": "rtc"}
    assert g.transition_attrs[g.index("B.compute")]["tasks"] == ("B",)
    assert compute_events(g) == {"A": g.index("A.compute"), "B": g.index("B.compute"),
                                 "P": g.index("P.compute")}
    assert g.attrs["clocks"] == {"rtc": 0, "P.clock": 1}
    assert g.simulate(2)["P.clock.tick"] == [F(2), F(6)]
    assert {p.kind for p in g.places} <= set(PLACE_KINDS)


def test_provenance_survives_networkx_round_trip():
    g = build_teg(fig7b(("a", "c")))
    h = TimedEventGraph.from_networkx(g.to_networkx())
    assert h.places == g.places and h.transition_attrs == g.transition_attrs
    assert task_chain(h, "MT2") == task_chain(g, "MT2") == [3, 5, 6]


# ------------------------------------------------ holding sources and activation ends
# Spec §2 puts duration(T) on every place leaving T.compute and period(C) on the
# self-loop of C.tick; every other place holds 0. Spec §4 (overrun_at): an
# activation ends with its last write, or, without outputs, at
# x_T.compute(k) + duration(T).


def test_holding_sources_of_a_task_with_an_output_on_a_clock():
    # T (duration 3, output o) on clock c (period 2): places in build order are
    # c.tick self-loop (holds 2: period of c), c.tick -> T.activate (0),
    # T.activate -> T.compute (0), T.compute -> T.write:o (holds 3: duration of T),
    # return T.write:o -> T.activate (0: it leaves a write, not compute).
    g = build_teg(skeleton([Task("T", F(3), clock="c", outputs=("o",))], [Clock("c", F(2))]))
    none = HoldingSource("none")
    assert holding_sources(g) == (HoldingSource("period", "c"), none, none,
                                  HoldingSource("duration", "T"), none)
    assert [p.holding for p in g.places] == [2, 0, 0, 3, 0]
    # It ends with its write: nothing added after that event.
    assert activation_end(g, "T") == ActivationEnd(g.index("T.write:o"), False, F(0))


def test_holding_sources_without_outputs_and_in_a_thread():
    # A (duration 5, no outputs) and B (duration 7, output o) in a thread A, B,
    # no clock. Places: A's return A.compute -> A.compute (5), B's chain
    # B.compute -> B.write:o (7), B's return (0), then the thread places
    # A.compute -> B.compute (leaves A.compute: 5) and the thread-return
    # B.write:o -> A.compute (0).
    g = build_teg(skeleton([Task("A", F(5)), Task("B", F(7), outputs=("o",))],
                           threads=[("A", "B")]))
    dA, dB, none = HoldingSource("duration", "A"), HoldingSource("duration", "B"), \
        HoldingSource("none")
    assert [p.kind for p in g.places] == ["return", "chain", "return", "thread",
                                          "thread-return"]
    assert holding_sources(g) == (dA, dB, none, dA, none)
    assert [p.holding for p in g.places] == [5, 7, 0, 5, 0]
    # A has no outputs: its activation ends duration(A) = 5 after A.compute.
    assert activation_end(g, "A") == ActivationEnd(g.index("A.compute"), True, F(5))
    assert activation_end(g, "B") == ActivationEnd(g.index("B.write:o"), False, F(0))


def test_holding_sources_match_every_example_holding():
    # Each place holds exactly the value its source names, on every example.
    examples = sorted(Path(__file__).parents[3].joinpath("examples").glob("*.yaml"))
    assert len(examples) >= 10
    for path in examples:
        sk = load_skeleton(path)
        g = build_teg(sk)
        for p, source in zip(g.places, holding_sources(g), strict=True):
            assert p.holding == source.value(sk), (path.name, p.name)
            assert (source.kind == "period") == (p.kind == "clock")


def test_records_survive_networkx_round_trip_and_need_a_built_graph():
    g = build_teg(skeleton([Task("A", F(1))]))
    h = TimedEventGraph.from_networkx(g.to_networkx())
    assert holding_sources(h) == holding_sources(g) == (HoldingSource("duration", "A"),)
    assert activation_end(h, "A") == activation_end(g, "A") == ActivationEnd(0, True, F(1))
    with pytest.raises(ModelError, match="unknown task"):
        activation_end(g, "B")
    with pytest.raises(ModelError, match="not built from a skeleton"):
        holding_sources(TimedEventGraph())
    # A graph that has chains but no record (made by hand): refused the same way.
    bare = TimedEventGraph()
    bare.attrs["chains"] = {"A": (0,)}
    with pytest.raises(ModelError, match="no 'activation_end'"):
        activation_end(bare, "A")


def test_dangling_references_and_helpers_errors():
    with pytest.raises(ModelError, match="unknown clock"):
        build_teg(skeleton([Task("A", F(1), clock="nope")]))
    with pytest.raises(ModelError, match=r"links\[0\].*B:x"):
        build_teg(skeleton([Task("A", F(1), outputs=("p",)), Task("B", F(1))],
                           links=[Link(("A", "p"), ("B", "x"), Protocol.SYN_SYN)]))
    with pytest.raises(ModelError, match="unknown task 'Z'"):
        build_teg(skeleton([Task("A", F(1))], threads=[("A", "Z")]))
    g = build_teg(skeleton([Task("A", F(1))]))
    with pytest.raises(ModelError, match="unknown task"):
        task_chain(g, "B")
    with pytest.raises(ModelError, match="not built from a skeleton"):
        task_chain(TimedEventGraph(), "A")
