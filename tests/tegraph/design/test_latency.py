"""A chain's latency in the design tools: the exact figures (spec §4c), the published
bounds over any phases beside them.

Exact values are traced by hand on the daters written out in each example's
comment block (spec §3: with a processor per task) or on the schedule (§4b);
bounds are summed by hand from the periods and the response times (themselves
derived by hand in test_schedulability.py). The figures themselves are tested at
length in tests/tegraph/analysis/test_chains*.py.
"""

from __future__ import annotations

from fractions import Fraction as F

import pytest

from tegraph import SkeletonError, load_skeleton
from tegraph.design.latency import DAVARE, DUERR, chain_latency, parse_chain
from tegraph.model.skeleton import Skeleton
from tegraph.report.design_text import render_latency
from tests.paths import REPO

EXAMPLES = REPO / "examples"


def bounds(result) -> dict[str, F | None]:
    return {b.name: b.value for b in result.bounds}


def test_synchronized_pipeline_of_figure_4_is_under_one_period():
    # Example daters: MT1.read:q(k) = 10(k-1), w4(k) = MT4.write:u(k) = 10(k-1) + 6;
    # each read takes the message of the same k (ASYN/SYN, r_i(k) >= w_(i-1)(k) and
    # w_(i-1)(k+1) = 10k + ... > r_i(k)): latency 6 < 10, one group: no bound.
    sk = load_skeleton(EXAMPLES / "fig4_pipeline_synchronized.yaml")
    r = chain_latency(sk, ["MT1", "MT2", "MT3", "MT4"])
    assert (r.kind, r.value, r.in_periods) == ("exact", 6, F(3, 5))
    (seg,) = r.segments
    assert (seg.start, seg.end, seg.period) == ("MT1.read:q", "MT4.write:u", 10)
    assert r.bounds == [] and r.value < seg.period
    assert r.figures.processor_per_task.age == 6


def test_unsynchronized_pipeline_of_figure_4_exact_beside_its_bounds():
    sk = load_skeleton(EXAMPLES / "fig4_pipeline_unsynchronized.yaml")
    r = chain_latency(sk, ["MT1", "MT2", "MT3", "MT4"])
    assert [h.links for h in r.hops] == [["MT1:x1 -> MT2:x1 (ASYN/ASYN)"],
                                         ["MT2:x2 -> MT3:x2 (ASYN/ASYN)"],
                                         ["MT3:x3 -> MT4:x3 (ASYN/ASYN)"]]
    # One processor, rate-monotonic with ties in file order: MT1 4 > MT2 3 > MT3 2 > MT4 1.
    # Response times: 1, 1+2 = 3, 3+2 = 5, 5+1 = 6 (all released at 0, none preempted).
    # Davare: (10+1) + (10+3) + (10+5) + (10+6) = 55.
    # Dürr: each next segment has a lower priority: 10 + max(R - 10, 0) = 10 for MT1..MT3,
    # the last one 10 + 6 = 16: 46.
    assert bounds(r) == {DAVARE: 55, DUERR: 46}
    # The exact first use on its processors (the schedule 0-1, 1-3, 3-5, 5-6: every read
    # sees the message of its period, spec §4c's example): 6, never the bound.
    assert (r.kind, r.value, r.in_periods) == ("exact", 6, F(3, 5))
    # Where the bounds' assumptions hold, the exact reaction is within them.
    assert r.figures.on_processors.reaction == 16 <= 46
    text = render_latency(r)
    assert "bound over any phases (Davare et al. 2007): 55 ms" in text
    assert "bound over any phases (Dürr et al. 2019): 46 ms" in text
    assert "exactly 6 ms" in text and "at most" not in text
    doc = r.to_dict()
    assert [b["scope"] for b in doc["bounds"]] == ["over any phases"] * 2
    assert doc["latency"] == "6" and doc["kind"] == "exact"


def test_cyclicity_two_ring():
    # ring_two_tokens with a processor per task, in units of 1/3 ms: B.compute(k) = rx(k),
    # A's write wx(k) is the last one <= rx(k) (wx(k+1) > rx(k) in the table), A reads y
    # at ry(k) >= wy(k) and wy(k+1) > ry(k): data of C's k-th activation. k=3: cb 22 + 6
    # - cc 14 = 14; k=4: 28 + 6 - 20 = 14: 14/3 ms, i.e. two periods of 7/3.
    sk = load_skeleton(EXAMPLES / "ring_two_tokens.yaml")
    r = chain_latency(sk, ["C", "A", "B"])
    assert r.figures.processor_per_task.age == F(14, 3)
    assert (r.segments[0].start, r.segments[0].end) == ("the start of C", "the end of B")


def test_rendezvous_and_sensorless_start():
    # rendezvous_two_clocks: P.compute(k) = 5(k-1), Q.write:y(k) = 9/2 + 5(k-1): 9/2.
    sk = load_skeleton(EXAMPLES / "rendezvous_two_clocks.yaml")
    assert chain_latency(sk, ["P", "Q"]).figures.processor_per_task.age == F(9, 2)


def test_syn_asyn_reader_gets_the_previous_message():
    # A (clock ca, 10, phase 0, d 1) posts x SYN/ASYN to B (clock cb, 10, phase 5, d 2).
    # A.write:x(k) = max(10(k-1) + 1, B.read:x(k)) = 10(k-1) + 5 = B.read:x(k): the k-th
    # write waits for the k-th request, so the k-th read (non-blocking, at B's start: the
    # same instant, another processor) sees write k-1, posted at 10(k-2) + 5, from A's
    # computation at 10(k-2). B.write:u(k) = 10(k-1) + 7. Latency 10(k-1) + 7 - 10(k-2) = 17.
    sk = Skeleton.from_dict({
        "clocks": {"ca": {"period": 10}, "cb": {"period": 10, "phase": 5}},
        "tasks": {"A": {"duration": 1, "clock": "ca", "outputs": ["x"]},
                  "B": {"duration": 2, "clock": "cb", "inputs": ["x"], "outputs": ["u"]}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "SYN/ASYN"}]})
    assert chain_latency(sk, ["A", "B"]).figures.processor_per_task.age == 17
    # On their one processor A's write at 5 ended before B's job started at 5: seen
    # (spec §4c), 10(k-1) + 7 - 10(k-1) = 7.
    assert chain_latency(sk, ["A", "B"]).figures.on_processors.age == 7
    # The same with ASYN/SYN: B waits for A's message of the same k (posted at
    # 10(k-1) + 1 <= B.activate): 10(k-1) + 7 - 10(k-1) = 7.
    data = sk.to_dict()
    data["links"][0]["protocol"] = "ASYN/SYN"
    assert chain_latency(Skeleton.from_dict(data), ["A", "B"]).figures.processor_per_task.age == 7


def test_two_asynchronous_links_between_groups():
    # MOD.DYN -> CO.JS (M and N, ASYN/ASYN). Davare: (T 6 + R 2) + (T 2 + R 7/10) = 107/10.
    # CO.JS's group has the higher priority (2 > 1): Dürr keeps the full term: 107/10.
    sk = load_skeleton(EXAMPLES / "computed_torque.yaml")
    r = chain_latency(sk, ["MOD.DYN", "CO.JS"])
    assert bounds(r) == {DAVARE: F(107, 10), DUERR: F(107, 10)}
    assert [s.start for s in r.segments] == ["MOD.DYN.read:q", "CO.JS.read:M"]


def test_duerr_shrinks_the_term_before_a_lower_priority_segment():
    # A (2 ms, d 1/2, priority 2) -> B (4 ms, d 1, priority 1), ASYN/ASYN, one processor.
    # R_A = 1/2; R_B: R0 = 3/2, 1 + ceil(3/4)*1/2 = 3/2.
    # Davare: (2 + 1/2) + (4 + 3/2) = 8. Dürr: A's term 2 + max(1/2 - 4, 0) = 2,
    # B's 4 + 3/2: 15/2.
    sk = Skeleton.from_dict({
        "tasks": {"A": {"duration": "1/2", "period": 2, "outputs": ["x"]},
                  "B": {"duration": 1, "period": 4, "inputs": ["x"]}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/ASYN"}]})
    r = chain_latency(sk, ["A", "B"])
    assert bounds(r) == {DAVARE: 8, DUERR: F(15, 2)}
    # Exactly: A runs 2i to 2i + 1/2 (its start is its sample), B (no output: its end is
    # its output) 4k + 1/2 to 4k + 3/2; B's start 4k + 1/2 sees A's write at 4k + 1/2
    # (same processor, A's job ended before): first use 3/2 ms, under both bounds.
    assert r.value == F(3, 2)


def test_unschedulable_groups_have_no_bound():
    # A misses its period (3 every 2): no bound applies, and no figure on processors
    # (its overrun is found; the search for a regime stops soon after).
    sk = Skeleton.from_dict({
        "tasks": {"A": {"duration": 3, "period": 2, "outputs": ["x"]},
                  "B": {"duration": 1, "period": 4, "inputs": ["x"]}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/ASYN"}]})
    r = chain_latency(sk, ["A", "B"])
    assert bounds(r) == {DAVARE: None, DUERR: None}
    assert (r.kind, r.value) == ("undecided", None) and r.why_undecided


def test_chains_from_the_file_and_the_command_line(tmp_path):
    f = tmp_path / "ct.yaml"
    f.write_text((EXAMPLES / "computed_torque.yaml").read_text()
                 + "chains:\n  - [TG.JS, TF.TT.JS, CO.JS]\n")
    sk = load_skeleton(f)
    # Group 1 daters (example comment): TG.JS.compute(k) = 2(k-1), CO.JS.write:tau(k) =
    # 2(k-1) + 3/5.
    assert chain_latency(sk, sk.chains[0]).value == F(3, 5)
    assert parse_chain(" TG.JS ,TF.TT.JS,CO.JS") == ("TG.JS", "TF.TT.JS", "CO.JS")


@pytest.mark.parametrize("chain, key_path, wording", [
    (["TG.JS", "CO.JS"], "chain[0][1]", "no link from TG.JS to CO.JS"),
    (["TG.JS", "NOPE"], "chain[0][1]", "no task 'NOPE'"),
    (["TG.JS", "TF.TT.JS", "TG.JS"], "chain[0][2]", "already at chain[0][0]"),
    ([], "chain[0]", "an empty chain"),
])
def test_refused_chains(chain, key_path, wording):
    # A chain given as a parameter (the first of the `chains` argument) is
    # located by the parameter, not in the skeleton's file.
    sk = load_skeleton(EXAMPLES / "computed_torque.yaml")
    with pytest.raises(SkeletonError) as info:
        chain_latency(sk, chain, path=("chain", 0))
    assert info.value.where == key_path and wording in info.value.reason
    assert info.value.file is None


def test_refused_chain_of_the_file_names_the_file():
    sk = load_skeleton(EXAMPLES / "computed_torque.yaml")
    with pytest.raises(SkeletonError) as info:
        chain_latency(sk, ["TG.JS", "NOPE"], path=("chains", 0))
    assert info.value.where == "chains[0][1]"
    assert info.value.file == str(EXAMPLES / "computed_torque.yaml")
