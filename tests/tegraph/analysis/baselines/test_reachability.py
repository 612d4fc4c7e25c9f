"""The untimed reachability baseline (:mod:`tegraph.reachability`) and ``tegraph reach``.

Every count is checked against a value found without this module: the Model
Checking Contest's state spaces and verdicts (``shared/anchors/pnml``), a
derived net whose shortest deadlock path is recorded there, hand counts, a
plain-Python breadth-first search written here from the definition, and, on
skeletons, the structural verdict of :func:`tegraph.analyze` (token-free
circuits): a group deadlocks in the bounded exploration exactly when
``analyze`` finds it not live.
"""

from __future__ import annotations

import json
import random
import signal
import subprocess
import sys
import time
from collections import deque
from functools import cache
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

import tegraph
from tegraph import Skeleton, analyze, build_teg, load_skeleton
from tegraph.analysis.baselines.reachability import (
    bounded_net,
    reachability_graph,
    skeleton_groups,
    skeleton_reachability,
)
from tegraph.cli import app
from tegraph.io.pnml import read_pnml
from tegraph.model.convert import as_petri_net
from tegraph.model.petri import PetriNet
from tests.paths import REPO
from tests.tegraph.skeleton_corpus import random_skeleton, write_corpus
from tests.tegraph.test_cli import CIRCULAR  # Figure 7a, written once

SETTINGS = settings(max_examples=60, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])
CORPUS_SIZE = 300


# ------------------------------------------------------------------ references

def reference_bfs(net: PetriNet, cap: int = 5000):
    """Textbook BFS over tuples: (states, edges, {dead marking: distance}) or None past ``cap``."""
    pre, post = net.pre.toarray().T.tolist(), net.post.toarray().T.tolist()
    m0 = tuple(int(v) for v in net.marking)
    dist, queue, edges, dead = {m0: 0}, deque([m0]), 0, {}
    while queue:
        m = queue.popleft()
        fired = False
        for i_pre, i_post in zip(pre, post):
            if all(have >= need for have, need in zip(m, i_pre)):
                fired = True
                edges += 1
                nxt = tuple(h - a + b for h, a, b in zip(m, i_pre, i_post))
                if nxt not in dist:
                    if len(dist) >= cap:
                        return None
                    dist[nxt] = dist[m] + 1
                    queue.append(nxt)
        if not fired:
            dead[m] = dist[m]
    return len(dist), edges, dead


def replay(net: PetriNet, sequence: list[int]) -> np.ndarray:
    """Fire ``sequence`` from the initial marking, checking each firing is enabled."""
    m = net.marking.astype(np.int64).copy()
    for t in sequence:
        assert (m >= net.pre[:, t]).all(), f"{net.transitions[t]} is not enabled"
        m += net.post[:, t] - net.pre[:, t]
    return m


def enabled(net: PetriNet, m: np.ndarray) -> list[int]:
    return [t for t in range(len(net.transitions)) if (m >= net.pre[:, t]).all()]


@pytest.fixture(scope="session")
def cases(anchors: Path) -> dict:
    data = json.loads((anchors / "pnml" / "cases.json").read_text())
    return {c["mcc_instance"]: c for c in data["pnml_cases"]} | {
        "derived": data["derived_cases"][0]}


# ------------------------------------------------------------------ MCC anchors

@pytest.mark.parametrize("instance", ["CircularTrains-PT-012", "CircularTrains-PT-024",
                                      "HouseConstruction-PT-00002"])
def test_mcc_state_spaces_and_verdicts(anchors: Path, cases: dict, instance: str) -> None:
    case = cases[instance]
    net = read_pnml(anchors / "pnml" / case["file"])
    r = reachability_graph(net)
    assert r.complete and r.stopped_by is None
    assert (r.states, r.edges) == (case["state_space"]["states"], case["state_space"]["edges"])
    assert r.deadlock is case["known_answers"]["ReachabilityDeadlock"]
    for d in r.dead:
        assert (replay(net, d.firing_sequence) == d.marking).all()
        assert enabled(net, d.marking) == []


def test_house_construction_deadlocks_are_all_found_at_their_shortest(anchors: Path) -> None:
    net = read_pnml(anchors / "pnml" / "HouseConstruction-PT-00002.pnml")
    states, edges, dead = reference_bfs(net)
    r = reachability_graph(net)
    assert (r.states, r.edges) == (states, edges)
    assert {tuple(d.marking.tolist()): len(d.firing_sequence) for d in r.dead} == dead


def test_derived_deadlock_and_its_shortest_path(anchors: Path, cases: dict) -> None:
    """CircularTrains-PT-012 without the token of Section_3 (cases.json, 'derived')."""
    net = read_pnml(anchors / "pnml" / "CircularTrains-PT-012.pnml")
    net.marking[net.places.index("Section_3")] = 0
    expected = cases["derived"]["expected"]
    r = reachability_graph(net)
    assert (r.states, r.edges, len(r.dead)) == (expected["bfs_states"], expected["bfs_edges"],
                                                expected["deadlocks"])
    path = [net.transitions[t] for t in r.dead[0].firing_sequence]
    assert path == expected["shortest_deadlock_path"].split()
    assert enabled(net, replay(net, r.dead[0].firing_sequence)) == []


# ------------------------------------------------------------------ budgets and hooks

def test_state_budget_gives_an_inconclusive_answer(anchors: Path) -> None:
    net = read_pnml(anchors / "pnml" / "CircularTrains-PT-012.pnml")
    r = reachability_graph(net, max_states=50)
    assert (r.states, r.complete, r.stopped_by, r.deadlock) == (50, False, "states", None)
    assert r.verdict() == "inconclusive (budget 50 states reached)"
    # Exactly enough room is not a budget stop (195 states, anchor).
    assert reachability_graph(net, max_states=195).complete


def test_a_deadlock_found_before_the_budget_is_conclusive() -> None:
    # p0 -> p1 with 300 tokens (also past the uint8 range): 301 markings in a line.
    net = PetriNet("line", ["p0", "p1"], ["t"], np.array([[1], [0]]), np.array([[0], [1]]),
                   np.array([300, 0]))
    full = reachability_graph(net)
    assert (full.states, full.edges, full.deadlock) == (301, 300, True)
    assert full.dead[0].marking.tolist() == [0, 300] and full.dead[0].firing_sequence == [0] * 300
    # The budget stops it before the dead marking: unknown, not "no deadlock".
    assert reachability_graph(net, max_states=300).deadlock is None


def test_time_budget_stop_flag_and_progress(anchors: Path) -> None:
    net = read_pnml(anchors / "pnml" / "CircularTrains-PT-024.pnml")
    r = reachability_graph(net, max_seconds=0)
    assert r.stopped_by == "time" and not r.complete and 0 < r.states < 86_515
    calls: list[tuple[int, int]] = []
    r = reachability_graph(net, progress=lambda s, e, sec: calls.append((s, e)),
                           stop=lambda: len(calls) >= 3)
    assert r.stopped_by == "interrupted" and r.deadlock is None
    assert calls == sorted(calls) and calls[-1] == (r.states, r.edges)
    assert r.verdict() == f"inconclusive (interrupted after {r.states:,} states)"


@st.composite
def small_nets(draw) -> PetriNet:
    n_p, n_t = draw(st.integers(1, 4)), draw(st.integers(1, 4))
    weights = st.lists(st.lists(st.sampled_from([0, 0, 1, 1, 2]), min_size=n_t, max_size=n_t),
                       min_size=n_p, max_size=n_p)
    pre, post = np.array(draw(weights)), np.array(draw(weights))
    marking = np.array(draw(st.lists(st.integers(0, 3), min_size=n_p, max_size=n_p)))
    return PetriNet("n", [f"p{i}" for i in range(n_p)], [f"t{i}" for i in range(n_t)],
                    pre, post, marking)


@SETTINGS
@given(small_nets())
def test_matches_a_plain_breadth_first_search(net: PetriNet) -> None:
    ref = reference_bfs(net, cap=400)
    r = reachability_graph(net, max_states=400)
    pre, post = net.pre.toarray(), net.post.toarray()
    sources = [t for t in range(len(net.transitions))
               if not pre[:, t].any() and post[:, t].any()]
    if sources:  # always enabled, each firing adds a token: infinite, and nothing is dead
        assert ref is None and (r.stopped_by, r.deadlock) == ("unbounded", False)
        assert r.source_transition == net.transitions[sources[0]]
        return
    if ref is None:  # more than 400 markings: the budget must say so
        assert not r.complete and r.states == 400
        return
    states, edges, dead = ref
    assert (r.states, r.edges, r.complete) == (states, edges, True)
    assert {tuple(d.marking.tolist()): len(d.firing_sequence) for d in r.dead} == dead
    for d in r.dead:
        assert (replay(net, d.firing_sequence) == d.marking).all()


# ------------------------------------------------------------------ skeletons

def check_skeleton(sk: Skeleton) -> None:
    """Bounded per-group exploration against the token-free circuits of ``analyze``."""
    report = analyze(sk, design=False)
    teg = build_teg(sk)
    r = skeleton_reachability(teg, max_states=200_000)
    assert r.groups == [g.tasks for g in report.groups]
    if r.complete:
        assert r.deadlock is (not report.live)
        assert {d.group for d in r.dead} == {g.index for g in report.groups if not g.live}
    else:
        # A rare random skeleton has more markings than the budget (hypothesis found one
        # of over 200,000): the search must say it stopped on its budget, and a dead
        # marking it did find still proves its group not live (one direction only).
        assert r.stopped_by == "states" and r.deadlock is not False
        assert {d.group for d in r.dead} <= {g.index for g in report.groups if not g.live}
    net = PetriNet.from_teg(teg)
    circuit_events = {teg.index(e) for d in report.deadlocks for e in d.events}
    for d in r.dead:
        m = replay(net, d.firing_sequence)  # a firing sequence of the unbounded net too
        assert (m == d.marking).all()
        group_events = skeleton_groups(teg)[1][d.group].tolist()
        # No event of the group can fire once places are bounded to m + 1...
        bounded = bounded_net(net)
        m_b = np.concatenate([m, net.marking + 1 - m])
        assert not set(enabled(bounded, m_b)) & set(group_events)
        # ...and the token-free circuits analyze names are blocked for good.
        assert not set(enabled(net, m)) & circuit_events


@SETTINGS
@given(st.randoms(use_true_random=False))
def test_skeleton_deadlock_verdict_equals_the_structural_one(rng: random.Random) -> None:
    check_skeleton(Skeleton.from_dict(random_skeleton(rng)))


@pytest.fixture(scope="session")
def corpus(tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    return write_corpus(tmp_path_factory.mktemp("corpus"), CORPUS_SIZE)


@cache
def _load(path: Path) -> Skeleton:
    return load_skeleton(path)


@pytest.mark.parametrize("seed", range(CORPUS_SIZE))
def test_corpus_deadlock_verdicts(corpus: list[Path], seed: int) -> None:
    check_skeleton(_load(corpus[seed]))


def test_corpus_is_not_trivial(corpus: list[Path]) -> None:
    """The corpus holds deadlocks and live skeletons, clocks, threads and every protocol."""
    docs = [json.loads(p.read_text()) for p in corpus]
    assert sum(not analyze(_load(p), design=False).live for p in corpus) >= 20
    assert sum(bool(d.get("threads")) for d in docs) >= 20
    protocols = {link["protocol"] for d in docs for link in d["links"]}
    assert protocols == {"ASYN/ASYN", "ASYN/SYN", "SYN/ASYN", "SYN/SYN"}


def test_bounded_net_keeps_each_place_within_its_bound() -> None:
    sk = load_skeleton(REPO / "examples" / "fig12_double_sync.yaml")
    net = PetriNet.from_teg(build_teg(sk))
    b = bounded_net(net)
    # Hand argument: p + p~ is invariant (p~ gains what p loses), so every
    # reachable marking of b keeps p within m_p + 1.
    inc = (b.post - b.pre).toarray()
    assert (inc[:len(net.places)] + inc[len(net.places):] == 0).all()
    assert (b.marking[:len(net.places)] + b.marking[len(net.places):]
            == net.marking + 1).all()


# ------------------------------------------------------------------ command line



def test_cli_untimed_json_on_a_skeleton(tmp_path: Path) -> None:
    f = tmp_path / "fig7a.yaml"
    f.write_text(CIRCULAR)
    out = CliRunner().invoke(app, ["reach", str(f), "--json"])
    assert out.exit_code == 1, out.output
    d = json.loads(out.stdout)
    assert (d["states"], d["edges"], d["complete"], d["deadlock"]) == (1, 0, True, True)
    # Every task waits to read from the previous one: stuck before any firing.
    assert d["deadlocks"] == [{"marking": {"MT1.write:a -> MT1.read:c": 1,
                                           "MT2.write:b -> MT2.read:a": 1,
                                           "MT3.write:c -> MT3.read:b": 1},
                               "firing_sequence": [], "group": 0,
                               "tasks": ["MT1", "MT2", "MT3"]}]


def test_cli_on_pnml_budget_and_refusals(anchors: Path, tmp_path: Path) -> None:
    house = anchors / "pnml" / "HouseConstruction-PT-00002.pnml"
    out = CliRunner().invoke(app, ["reach", str(house), "--json"])
    d = json.loads(out.stdout)
    assert out.exit_code == 1 and (d["states"], d["edges"], d["deadlock"]) == (1501, 4780, True)
    out = CliRunner().invoke(app, ["reach", str(house), "--max-states", "100"])
    assert out.exit_code == 0 and "inconclusive (budget 100 states reached)" in out.stdout
    out = CliRunner().invoke(app, ["reach", str(house), "--max-states", "100", "--json"])
    assert json.loads(out.stdout)["deadlock"] is None
    out = CliRunner().invoke(app, ["reach", str(house), "--timed"])
    assert out.exit_code == 2 and out.stderr.count("\n") == 1
    assert "--timed: the timed exploration needs a skeleton" in out.stderr
    out = CliRunner().invoke(app, ["reach", str(tmp_path / "missing.yaml")])
    assert out.exit_code == 2 and "Traceback" not in out.output


def test_cli_ctrl_c_prints_the_partial_counts(anchors: Path) -> None:
    """CircularTrains-PT-048 has 2.4e10 markings (anchor): only Ctrl-C ends the search."""
    proc = subprocess.Popen([sys.executable, "-m", "tegraph.cli", "reach",
                             str(anchors / "pnml" / "CircularTrains-PT-048.pnml"),
                             "--max-states", "100000000"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(4)
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130, stderr
    assert "inconclusive (interrupted after" in stdout and "Traceback" not in stderr
    states = int(stdout.split("untimed reachability, ")[1].split(" state")[0].replace(",", ""))
    assert 0 < states < 23_973_456_915


# ------------------------------------------------------------------ sizes and verdicts up front

SOURCE_NET = """{"revision": 4, "type": "Petri net", "nets": [{"name": "src",
  "places": [{"id": 0, "caption": "buffer", "tokens": 0}],
  "transitions": [{"id": 0, "caption": "produce"}, {"id": 1, "caption": "consume"}],
  "arcs": [{"from": "T0", "to": "P0"}, {"from": "P0", "to": "T1"}]}]}"""


def test_a_source_transition_is_reported_unbounded_at_once(tmp_path: Path) -> None:
    """produce has no input place: always enabled, so no marking is dead; each firing adds
    a token to buffer, so the markings 0, 1, 2... are all reachable (a search would
    exhaust its budget of states and answer nothing)."""
    f = tmp_path / "source.json"
    f.write_text(SOURCE_NET)
    net = tegraph.read(f)
    r = reachability_graph(net)
    assert (r.stopped_by, r.deadlock, r.complete, r.source_transition) == \
        ("unbounded", False, False, "produce")
    assert r.verdict().startswith(
        "unbounded: transition 'produce' has no input place, it can fire forever")
    out = CliRunner().invoke(app, ["reach", str(f), "--json"])
    assert out.exit_code == 0, out.output
    d = json.loads(out.stdout)
    assert (d["deadlock"], d["stopped_by"]) == (False, "unbounded")
    assert d["unbounded"] == "transition produce has no input place, it can fire forever"
    out = CliRunner().invoke(app, ["reach", str(f)])
    assert "unbounded: transition 'produce'" in out.stdout


def test_a_transition_without_any_place_is_explored() -> None:
    # idle touches no place: always enabled but the marking never changes, so the graph
    # is finite: 1 state, 1 edge (idle fires in place), and no dead marking
    net = PetriNet("idle", ["p"], ["idle"], np.array([[0]]), np.array([[0]]), np.array([3]))
    r = reachability_graph(net)
    assert (r.states, r.edges, r.complete, r.deadlock, r.source_transition) == \
        (1, 1, True, False, None)


def test_markings_that_would_leave_64_bits_stop_the_search() -> None:
    # t takes 1 token from p (5 tokens) and puts 2 into q (2**63 - 3): after one firing q
    # holds 2**63 - 1, the largest int64; a second firing would wrap it to a negative count
    # (before: the search went on with the wrapped, wrong markings)
    top = 2**63 - 1
    net = PetriNet("grow", ["p", "q"], ["t"], np.array([[1], [0]]), np.array([[0], [2]]),
                   np.array([5, top - 2]))
    r = reachability_graph(net)
    assert (r.stopped_by, r.states, r.deadlock) == ("tokens", 2, None)
    assert "2**63 - 1" in r.verdict()


def test_the_memory_budget_bounds_the_search_of_a_net_of_many_places(anchors: Path,
                                                                      tmp_path: Path) -> None:
    """mp3playback's expansion: 10,601 transitions and 26,493 places (cases.json of the SDF
    anchors). Before: a dense incidence of 26,493 x 10,601 (2.1 GiB, then MemoryError)."""
    net = as_petri_net(tegraph.read(anchors / "sdf" / "xml" / "mp3playback.xml"))
    assert (len(net.places), len(net.transitions)) == (26_493, 10_601)
    assert net.pre.nnz == net.post.nnz == 26_493  # a marked graph: one arc in, one out
    # a marking of 26,493 places takes 26,493 bytes (uint8) twice, plus 150: 10 MiB hold 197
    r = reachability_graph(net, max_memory=10 * 2**20)
    assert (r.stopped_by, r.states, r.deadlock) == ("memory", 197, None)
    assert "memory budget of 10 MiB" in r.verdict()
    out = tegraph.write(net, tmp_path / "mp3.pnml")  # `convert` to PNML, sparse all through
    back = tegraph.read(out)
    assert (back.pre != net.pre).nnz == 0 and (back.post != net.post).nnz == 0


def test_a_billion_tokens_are_explored_in_narrow_markings() -> None:
    # a ring a -> b -> a with 10**9 tokens: every split (k, 10**9 - k) is reachable, one new
    # marking a level; a budget of 500 states ends it, whatever the count of tokens
    net = PetriNet("ring", ["ab", "ba"], ["a", "b"], np.array([[0, 1], [1, 0]]),
                   np.array([[1, 0], [0, 1]]), np.array([0, 10**9]))
    r = reachability_graph(net, max_states=500)
    assert (r.states, r.stopped_by, r.deadlock) == (500, "states", None)
