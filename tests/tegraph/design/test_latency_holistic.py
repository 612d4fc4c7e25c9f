"""The holistic bound (Tindell and Clark 1994) beside a chain's exact latency.

A chain whose tasks run on more than one processor gets, among the bounds "over any
phases" of :func:`tegraph.design.latency.chain_latency`, the holistic analysis' bound
on its reaction (and so on its age and first use). Hand derivations in the comments;
a property checks it against the exact figures (spec §4c, a different computation:
the schedule engine's proven periodic regime) on random small skeletons with random
phases.
"""

from __future__ import annotations

import json

import jsonschema
from hypothesis import HealthCheck, assume, event, given, settings
from hypothesis import strategies as st

from tegraph import analyze, load_skeleton
from tegraph.design.holistic import HOLISTIC
from tegraph.design.latency import DAVARE, DUERR, OVER_ANY_PHASES, chain_latency
from tegraph.model.skeleton import Skeleton
from tegraph.report.design_text import render_latency
from tests.paths import REPO

SCHEMA = json.loads((REPO / "docs" / "report.schema.json").read_text())


def sender_actuator(protocol: str = "ASYN/SYN", delay=None) -> Skeleton:
    # S (1 ms every 10 ms, cpu1) writes x to A (1 ms, cpu2; no clock when it blocks).
    a = {"duration": 1, "inputs": ["x"], "processor": "cpu2"}
    if protocol == "ASYN/ASYN":
        a["period"] = 10
    link = {"from": "S:x", "to": "A:x", "protocol": protocol}
    if delay is not None:
        link["delay"] = delay
    return Skeleton.from_dict({
        "tasks": {"S": {"duration": 1, "period": 10, "outputs": ["x"], "processor": "cpu1"},
                  "A": a},
        "links": [link]})


def holistic(result) -> object:
    (b,) = [b for b in result.bounds if b.name == HOLISTIC]
    return b


def test_a_blocking_chain_across_two_processors_by_hand():
    # S alone on cpu1: released at its tick, window [0, 0], ends by 1. A blocks on x:
    # released when S has written, at 1 after the tick (window [1, 1], no jitter),
    # alone on cpu2: ends by 2. One segment (a blocking read): 10 + 2 - 0 = 12.
    # Exact (phase 0): S samples at its start 10(k-1), A posts at its end 10(k-1) + 2:
    # first use = age = 2; a change just after 0 is sampled at 10 and posted at 12:
    # reaction 12, the bound exactly. One segment: no Davare or Dürr bound.
    r = chain_latency(sender_actuator(), ["S", "A"])
    b = holistic(r)
    assert b.value == 12 and [x.name for x in r.bounds] == [HOLISTIC]
    exact = r.figures.on_processors
    assert (exact.first_use, exact.age, exact.reaction) == (2, 2, 12)
    assert exact.reaction <= b.value
    assert f"bound {OVER_ANY_PHASES} ({HOLISTIC}): 12 ms" in render_latency(r)
    doc = r.to_dict()
    jsonschema.validate(doc, {"$ref": "#/$defs/latency", "$defs": SCHEMA["$defs"]})
    assert doc["bounds"][0]["scope"] == OVER_ANY_PHASES and doc["latency"] == "2"


def test_an_asynchronous_hop_with_a_delay_by_hand():
    # S and A each on a clock of 10 ms, ASYN/ASYN with delay 3: two segments. S: window
    # [0, 0], its sample (its start) at offset 0, its write at 1: 10 + 1 - 0 = 11. A:
    # its read (at its start) at offset 0 at the earliest, its end by 1: 10 + 1 - 0 = 11.
    # Plus the hop's delay: 11 + 11 + 3 = 25. Exact (both phases 0): S writes at
    # 10(j-1) + 1, visible at 10(j-1) + 4, before A's start at 10j: A job k uses S job
    # k - 1 (sampled at 10(k-2)), posts at 10(k-1) + 1: age 11, reaction 21 <= 25.
    r = chain_latency(sender_actuator("ASYN/ASYN", delay=3), ["S", "A"])
    assert holistic(r).value == 25
    exact = r.figures.on_processors
    assert (exact.first_use, exact.age, exact.reaction) == (11, 11, 21)
    # Davare: (10 + 1) + (10 + 1) = 22, Dürr the same (the segments on different
    # processors), each plus the hop's delay (the message is visible 3 after its write).
    assert {b.name: b.value for b in r.bounds} == {DAVARE: 25, DUERR: 25, HOLISTIC: 25}
    assert "the links' delays along the chain: 3 ms" in r.bounds[0].note


def test_a_chain_on_one_processor_gets_no_holistic_bound():
    # Figure 4 on its one processor: the bounds are Davare's and Dürr's alone (55, 46).
    sk = load_skeleton(REPO / "examples" / "fig4_pipeline_unsynchronized.yaml")
    r = chain_latency(sk, ["MT1", "MT2", "MT3", "MT4"])
    assert [b.name for b in r.bounds] == [DAVARE, DUERR]


def test_the_holistic_bound_decides_no_exit_status(tmp_path):
    # A bound is reported beside the exact figures, never in their place: the report's
    # verdict is the same with and without the design section that holds it.
    sk = sender_actuator()
    with_design = analyze(sk, chains=[["S", "A"]])
    without = analyze(sk, chains=[["S", "A"]], design=False)
    assert with_design.schedulable == without.schedulable is True
    assert with_design.consistent == without.consistent


@st.composite
def distributed_chains(draw):
    """2 to 4 tasks T0 -> T1 -> ... on two or three processors, each hop blocking (an
    ASYN/SYN or SYN/SYN reader without a clock of its own: one group) or ASYN/ASYN (a
    reader on a clock of its own, random phase, a delay of its own or the network's),
    and a periodic interferer H on a processor: the holistic bound's domain (every task
    in a clocked group), with jitter inherited along the blocking hops."""
    n = draw(st.integers(2, 4))
    procs = ["cpu0", "cpu1", "cpu2"][:draw(st.integers(2, 3))]
    declared = draw(st.booleans())
    network = draw(st.sampled_from([None, 1, 3]))
    tasks, links = {}, []
    for i in range(n):
        spec = {"duration": draw(st.sampled_from([0, 1, 1, 2])), "inputs": [],
                "outputs": [], "processor": draw(st.sampled_from(procs))}
        protocol = None if i == 0 else draw(st.sampled_from(
            ["ASYN/ASYN", "ASYN/ASYN", "ASYN/SYN", "SYN/SYN"]))
        if protocol in (None, "ASYN/ASYN"):
            spec["period"] = draw(st.sampled_from([6, 12, 24]))
            spec["phase"] = draw(st.integers(0, 11))
        if declared:
            spec["priority"] = draw(st.integers(1, 3))
        tasks[f"T{i}"] = spec
        if protocol is not None:
            tasks[f"T{i - 1}"]["outputs"].append(f"o{i}")
            spec["inputs"].append(f"i{i}")
            link = {"from": f"T{i - 1}:o{i}", "to": f"T{i}:i{i}", "protocol": protocol}
            # A delay on a place (ASYN/SYN) is left out, as in test_chains_oracle.py (the
            # engine's memory where a task starves); a rendezvous refuses one.
            if protocol != "ASYN/ASYN":
                if network is not None:
                    link["delay"] = 0
            elif (d := draw(st.sampled_from([None, 0, 1, 4]))) is not None:
                link["delay"] = d
            links.append(link)
    if draw(st.booleans()):
        tasks["T0"]["inputs"].append("sensor")
    if draw(st.booleans()):
        tasks[f"T{n - 1}"]["outputs"].append("act")
    if draw(st.booleans()):
        tasks["H"] = {"duration": draw(st.integers(1, 2)),
                      "period": draw(st.sampled_from([4, 6, 8])),
                      "phase": draw(st.integers(0, 5)), "processor": draw(st.sampled_from(procs))}
        if declared:
            tasks["H"]["priority"] = draw(st.integers(1, 3))
    out = {"tasks": tasks, "links": links, "chains": [[f"T{i}" for i in range(n)]]}
    if network is not None:
        out["network"] = {"delay": network}
    return out


@settings(max_examples=30, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(distributed_chains())
def test_every_exact_figure_is_within_the_holistic_bound(data):
    # The holistic bound holds for any phases of the groups' clocks; the exact figures
    # are those of the declared (random) phases, one case of them: where both exist,
    # first use <= age <= reaction <= the bound (the module's claim is on the reaction).
    sk = Skeleton.from_dict(data)
    chain = list(sk.chains[0])
    assume(len({sk.tasks[t].runs_on for t in chain}) > 1)
    report = analyze(sk, design=False)
    r = chain_latency(sk, chain, report, figures=report.chains[0])
    b = holistic(r)
    exact = r.figures.on_processors
    event(f"bound: {b.value is not None}, exact: {exact.decided}")
    if b.value is None:
        assert b.note  # nothing claimed, and it says why
        return
    if exact.decided:
        assert exact.first_use <= b.value, (exact, b)
        assert exact.age <= b.value, (exact, b)
        assert exact.reaction <= b.value, (exact, b)
