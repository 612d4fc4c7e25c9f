"""``tegraph cycle-time``: exact periods against the shared reference values.

Every expected value is independent of the code under test: the anchors'
published or tool-computed figures (``shared/anchors``), hand computations
given in comments, or brute-force enumeration of elementary circuits.
"""

from __future__ import annotations

import itertools
import json
import subprocess
import sys
from fractions import Fraction as F

import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

import tegraph
from maxplus.cycle_ratio import max_cycle_ratio
from tegraph import cycle_time
from tegraph.cli import app
from tegraph.io.tpne import parse_tpne_teg, read_tpne_teg
from tegraph.model.teg import TimedEventGraph


def run(*args: str) -> subprocess.CompletedProcess:
    """The command line in this process (fast); ``spawn`` runs it as a real process."""
    result = CliRunner().invoke(app, list(args))
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        raise result.exception  # an uncaught error would be a traceback for the user
    return subprocess.CompletedProcess(args, result.exit_code, result.stdout, result.stderr)


def spawn(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "tegraph.cli", *args],
                          capture_output=True, text=True, timeout=120, check=False)


def brute_force_period(teg: TimedEventGraph) -> F | None:
    """Max over elementary circuits (parallel places tried one by one) of Σh/Σm."""
    G = nx.DiGraph()
    G.add_nodes_from(range(teg.n_transitions))
    between: dict[tuple[int, int], list] = {}
    for p in teg.places:
        G.add_edge(p.src, p.dst)
        between.setdefault((p.src, p.dst), []).append(p)
    best = None
    for cycle in nx.simple_cycles(G):
        hops = list(zip(cycle, cycle[1:] + cycle[:1]))
        for choice in itertools.product(*(between[h] for h in hops)):
            tokens = sum(p.tokens for p in choice)
            assert tokens > 0, "brute force is only called on live graphs"
            ratio = F(sum(p.holding for p in choice), tokens)
            best = ratio if best is None else max(best, ratio)
    return best


@pytest.fixture(scope="module")
def teg_cases(anchors):
    return {c["file"].split("/")[-1]: c
            for c in json.loads((anchors / "pnml" / "cases.json").read_text())
            ["teg_cycle_time_cases"]}


# ------------------------------------------------------------------ TimedPetriNetEditor anchors


def test_semi_netherlands_period_is_the_published_143_over_3(anchors, teg_cases):
    known = teg_cases["SemiNetherlands.teg"]["known_answers"]
    r = cycle_time(anchors / "teg" / "SemiNetherlands.teg")
    assert known["cycle_time"].startswith("143/3")
    assert r.period == F(143, 3) and r.throughput == F(3, 143)
    assert known["all_nodes_same_cycle_time"] and r.cycle_times is None
    # "max cycle ratio = 143/3 over circuit nodes 0,2,3,1": the same cyclic order
    k = r.critical_circuit.index("T0")
    assert r.critical_circuit[k:] + r.critical_circuit[:k] == ["T0", "T2", "T3", "T1"]
    assert r.certificate_verified is True and r.exit_status == 0


def test_semi_howard_cycle_time_vector_in_both_orientations(anchors, teg_cases):
    known = teg_cases["SemiHoward.teg"]["known_answers"]["cycle_time_vector"]
    r = cycle_time(anchors / "teg" / "SemiHoward.teg")
    assert [r.cycle_times[f"T{i}"] for i in range(3)] == [F(x) for x in known]  # [1, 1, 2]
    assert r.period == 2
    # Read as the editor draws it (i -> j), node 2's self-loop (2 time units,
    # 1 token) is upstream of 0 and 1: every cycle time is 2 (by hand). The
    # maximum ratio does not depend on the orientation.
    drawn = cycle_time(read_tpne_teg(anchors / "teg" / "SemiHoward.teg", orientation="from-to"))
    assert drawn.period == 2 and drawn.cycle_times is None


def test_howard2_json_period_circuit_and_the_editors_eigenvector(anchors, teg_cases):
    known = teg_cases["Howard2.json"]["known_answers"]
    r = cycle_time(anchors / "teg" / "Howard2.json")
    assert r.period == F(known["cycle_time"]).limit_denominator() == F(13, 2)
    # "T0 -> P0(5,2 tok) -> T2 -> P2(3) -> T1 -> P1(5) -> T0"
    k = r.critical_circuit.index("T0")
    assert r.critical_circuit[k:] + r.critical_circuit[:k] == ["T0", "T2", "T1"]
    assert r.place_labels[k:] + r.place_labels[:k] == ["P0", "P2", "P1"]
    # The editor runs Howard on the transposed arcs: its eigenvector [0, 5, 8, 1]
    # is the bias of the reversed graph (unique up to a constant: one critical class).
    g = tegraph.read(anchors / "teg" / "Howard2.json").to_teg().arrays()
    rev = max_cycle_ratio(g.dst, g.src, g.holding, g.tokens, n_nodes=g.n_transitions)
    bias = [b - rev.bias[0] for b in rev.bias]
    assert bias == [F(x) for x in known["eigenvector"]]


def test_event_graph_with_an_input_transition_explains_its_missing_cycle_time(anchors):
    r = cycle_time(anchors / "teg" / "EventGraph.json")
    # Circuits: x1 -> x2 -> x1 via P3, P4: (1 + 1) / (1 + 1) = 1; x1's self-loop
    # P2: 1 / 2. y is downstream of both; u has no input place at all.
    assert r.period == 1
    assert r.cycle_times == {"u": None, "x1": 1, "x2": 1, "y": 1}
    assert any("u" in n and "no circuit upstream" in n for n in r.notes)
    assert r.exit_status == 0


# ------------------------------------------------------------------ SDF3 anchors


def _sdf_case_list():
    # parametrization happens before fixtures exist
    from tests.paths import ANCHORS

    return json.loads((ANCHORS / "sdf" / "cases.json").read_text())["cases"]


@pytest.mark.parametrize("case", _sdf_case_list(), ids=lambda c: c["name"])
def test_sdf3_period_equals_the_shared_reference(anchors, case):
    r = cycle_time(anchors / "sdf" / case["sdf_xml"])
    assert r.period == F(case["period_fraction"])
    assert r.throughput == 1 / F(case["period_fraction"])
    assert r.n_transitions == case["hsdf_actors"]
    assert r.certificate_verified is True
    # the reported circuit attains the period: Σ holding / Σ tokens over its places
    arcs = tegraph.read(anchors / "sdf" / case["sdf_xml"]).to_arcs()
    places = r.critical_places
    total = F(int(arcs.holding[places].sum()), int(arcs.tokens[places].sum()))
    assert total == F(case["critical_cycle"]["sum_weight"], case["critical_cycle"]["sum_tokens"])


@pytest.mark.parametrize("case", _sdf_case_list(), ids=lambda c: c["name"])
def test_hsdf_edge_list_gives_the_same_period(anchors, case):
    r = cycle_time(anchors / "sdf" / case["hsdf_edge_list"])
    assert r.model == "arc list" and r.period == F(case["period_fraction"])
    assert r.n_places == case["hsdf_arcs"]


def test_cli_cycle_time_json_on_sdf3(anchors):
    out = run("cycle-time", str(anchors / "sdf" / "xml" / "samplerate.xml"), "--json")
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    assert doc["period"] == "960" and doc["throughput"] == "1/960"  # cases.json
    assert doc["certificate_verified"] is True
    assert len(doc["critical_circuit"]) == 160  # cases.json: critical cycle of 160 arcs
    # The expansion is not strongly connected: firings upstream of the bottleneck
    # run faster; none is slower than the period, the circuit's run at it.
    times = {k: F(v) for k, v in doc["cycle_times"].items()}
    assert max(times.values()) == 960
    assert all(times[e] == 960 for e in doc["critical_circuit"])


# ------------------------------------------------------------------ PNML anchors


def test_circular_trains_is_live_untimed_and_unit_timed(anchors):
    path = anchors / "pnml" / "CircularTrains-PT-012.pnml"
    r = cycle_time(path)  # MCC: MARKED_GRAPH true, Liveness true
    assert r.applicable and r.token_free_circuit is None and r.period == 0
    assert r.throughput is None and any("no timing" in n for n in r.notes)
    net = tegraph.read(path)
    net.holding = [F(1)] * len(net.places)  # every place holds 1, for the brute force
    teg = net.to_teg()
    assert sum(1 for _ in nx.simple_cycles(nx.DiGraph(teg.to_networkx()))) == 42  # cases.json
    timed = cycle_time(path, default_holding=1)
    assert timed.period == brute_force_period(teg) == 3


@pytest.mark.parametrize("size", ["024", "048"])
def test_larger_circular_trains_are_live(anchors, size):
    r = cycle_time(anchors / "pnml" / f"CircularTrains-PT-{size}.pnml", default_holding=1)
    assert r.token_free_circuit is None and r.applicable  # MCC Liveness true
    assert r.seconds["analysis"] < 5  # "the structural answer must come back instantly"


def test_house_construction_is_not_a_marked_graph(anchors):
    out = spawn("cycle-time", str(anchors / "pnml" / "HouseConstruction-PT-00002.pnml"))
    # MCC verdict file: "place p1 is not of a marked graph"; ReachabilityDeadlock TRUE
    assert out.returncode == 1, out.stderr
    assert "not a marked graph" in out.stdout and "'p1'" in out.stdout
    assert "deadlock: 1 dead marking reached" in out.stdout
    doc = json.loads(run("cycle-time", str(anchors / "pnml" / "HouseConstruction-PT-00002.pnml"),
                         "--json").stdout)
    assert doc["applicable"] is False and doc["period"] is None and "p1" in doc["reason"]
    reach = doc["reachability"]
    # cases.json state_space: 1,501 states, 4,780 edges
    assert (reach["states"], reach["edges"], reach["complete"]) == (1501, 4780, True)
    assert reach["deadlock"] is True


def test_house_construction_dead_marking_replays(anchors):
    net = tegraph.read(anchors / "pnml" / "HouseConstruction-PT-00002.pnml")
    r = cycle_time(net)
    (dead,) = r.reachability.dead
    marking = net.marking.copy()
    for t in dead.firing_sequence:  # fire by hand: every step enabled, the end enables nothing
        assert (marking >= net.pre[:, t]).all()
        marking += net.post[:, t] - net.pre[:, t]
    assert (marking == dead.marking).all()
    assert not any((marking >= net.pre[:, t]).all() for t in range(len(net.transitions)))


def test_choice_net_without_deadlock_exits_0(tmp_path):
    # p0 (1 token) -> t1 or t2 -> p1 -> t3 -> p0: p0 has two output transitions,
    # so no (max,+) figures; by hand the reachable markings are (1,0) and
    # (0,1), each enabling a transition: 2 states, 3 edges, no deadlock.
    from tegraph.model.petri import PetriNet

    pre = np.array([[1, 1, 0], [0, 0, 1]])
    post = np.array([[0, 0, 1], [1, 1, 0]])
    net = PetriNet("choice", ["p0", "p1"], ["t1", "t2", "t3"], pre, post, np.array([1, 0]))
    path = tmp_path / "choice.pnml"
    tegraph.write(net, path)
    out = run("cycle-time", str(path))
    assert out.returncode == 0, out.stderr
    assert "no period:" in out.stdout and "no deadlock (2 states, complete)" in out.stdout
    r = cycle_time(path)
    assert (r.reachability.states, r.reachability.edges) == (2, 3) and r.period is None


def test_reachability_budget_is_inconclusive_not_a_guess(anchors):
    out = run("cycle-time", str(anchors / "pnml" / "HouseConstruction-PT-00002.pnml"),
              "--max-states", "100", "--json")
    reach = json.loads(out.stdout)["reachability"]
    assert out.returncode == 0 and reach["complete"] is False and reach["deadlock"] is None
    assert reach["stopped_by"] == "states" and reach["states"] == 100


def test_derived_deadlock_names_the_token_free_circuit(anchors, tmp_path):
    text = (anchors / "pnml" / "CircularTrains-PT-012.pnml").read_text()
    start = text.index('<place id="Section_3">')
    end = text.index("</place>", start)
    place = text[start:end]
    assert "<initialMarking>" in place
    mutated = place[:place.index("<initialMarking>")] + place[place.index("</initialMarking>")
                                                               + len("</initialMarking>"):]
    path = tmp_path / "minus_section_3.pnml"
    path.write_text(text[:start] + mutated + text[end:])
    r = cycle_time(path)
    # cases.json derived case: t2_to_3, Section_3, t3_to_4, Section_4, t4_to_5, F3
    k = r.token_free_circuit.index("t2_to_3")
    assert r.token_free_circuit[k:] + r.token_free_circuit[:k] == ["t2_to_3", "t3_to_4",
                                                                   "t4_to_5"]
    labels = r.place_labels[k:] + r.place_labels[:k]
    assert labels == ["Section_3", "Section_4", "F3"]
    out = run("cycle-time", str(path))
    assert out.returncode == 1 and "DEADLOCK" in out.stdout and "t3_to_4" in out.stdout


# ------------------------------------------------------------------ small graphs by hand


def test_acyclic_graph_has_no_period_and_exits_0(tmp_path):
    path = tmp_path / "line.edges"
    path.write_text("0 1 5 0\n1 2 3 0\n")
    out = run("cycle-time", str(path), "--json")
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    assert doc["period"] is None and doc["throughput"] is None and doc["critical_circuit"] == []


def test_skeleton_input_gives_its_clock_period():
    sk = tegraph.Skeleton.from_dict({
        "tasks": {"A": {"duration": 2, "period": 10, "outputs": ["x"]},
                  "B": {"duration": "7/3", "inputs": ["x"]}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]})
    r = cycle_time(sk)
    # The clock self-loop (period 10, 1 token) dominates A's chain (2) and B's (7/3).
    assert r.model == "skeleton" and r.period == 10 and r.critical_circuit == ["A.clock.tick"]


def test_parallel_places_take_the_slowest():
    g = parse_tpne_teg("TimedEventGraph 2 3\n1 0: 2 1\n1 0: 7 1\n0 1: 1 1\n")
    # circuits 0 -> 1 -> 0 through either parallel place: (2+1)/2 or (7+1)/2 = 4
    assert cycle_time(g).period == 4


def test_bad_default_holding_is_refused(anchors):
    out = run("cycle-time", str(anchors / "pnml" / "CircularTrains-PT-012.pnml"),
              "--default-holding", "-1")
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert "default-holding" in out.stderr


@st.composite
def live_tegs(draw):
    n = draw(st.integers(1, 5))
    g = TimedEventGraph("random")
    for k in range(n):
        g.add_transition(f"e{k}")
    for _ in range(draw(st.integers(1, 9))):
        s, d = draw(st.integers(0, n - 1)), draw(st.integers(0, n - 1))
        g.add_place(s, d, tokens=draw(st.integers(1, 3)),
                    holding=F(draw(st.integers(0, 40)), draw(st.integers(1, 6))))
    return g


@settings(max_examples=60)
@given(live_tegs())
def test_period_equals_brute_force_enumeration(g):
    r = cycle_time(g)
    assert r.period == brute_force_period(g)
    if r.period is not None:
        # the named circuit attains it
        ps = [g.places[p] for p in r.critical_places]
        assert F(sum(p.holding for p in ps), sum(p.tokens for p in ps)) == r.period
        assert r.certificate_verified


def test_cycle_time_result_is_json_serializable_with_exact_strings():
    g = parse_tpne_teg("TimedEventGraph 1 1\n0 0: 7 3\n")
    doc = json.loads(tegraph.to_json(cycle_time(g)))
    assert doc["period"] == "7/3" and doc["throughput"] == "3/7" and doc["schema_version"] == 2
    assert np.isclose(float(F(doc["period"])), 7 / 3)
