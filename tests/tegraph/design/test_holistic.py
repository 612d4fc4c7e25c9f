"""Holistic analysis (Tindell and Clark 1994) against the brute-force simulator.

A sensor task S on cpu1 sends over a non-preemptive bus (the frame M, triggered by S,
above a periodic frame N) to an actuator task A on cpu2, triggered by M, under a more
urgent periodic task H there. Each expected value is either derived by hand or
measured by ``brute_force.py`` (written apart from tegraph) with random phases of the
independent clocks: every job must end within its window's bound, and the chain's
reaction within the holistic latency, whatever the phases.
"""

from __future__ import annotations

from fractions import Fraction as F

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tegraph import analyze
from tegraph.design.holistic import HOLISTIC, holistic_analysis
from tegraph.design.holistic_latency import holistic_latency
from tegraph.model.skeleton import Skeleton
from tests.tegraph.design.brute_force import SimTask, reactions, simulate


def distributed(c_s=1, c_m=2, c_n=3, c_a=1, c_h=0, t_h=5, delay=0, t_n=10):
    tasks = {
        "S": {"duration": c_s, "period": 10, "outputs": ["x"], "processor": "cpu1"},
        "M": {"duration": c_m, "inputs": ["x"], "outputs": ["y"], "processor": "can",
              "priority": 2},
        "N": {"duration": c_n, "period": t_n, "processor": "can", "priority": 1},
        "A": {"duration": c_a, "inputs": ["y"], "processor": "cpu2", "priority": 1}}
    if c_h:
        tasks["H"] = {"duration": c_h, "period": t_h, "processor": "cpu2", "priority": 2}
    return Skeleton.from_dict({
        "tasks": tasks, "processors": {"can": {"preemptive": False}},
        "links": [{"from": "S:x", "to": "M:x", "protocol": "ASYN/SYN", "delay": delay},
                  {"from": "M:y", "to": "A:y", "protocol": "ASYN/SYN"}]})


def test_jitter_is_inherited_along_the_chain_by_hand():
    # S: alone on cpu1, released at its tick, R = 1. M: released 1 after S's tick (no
    # jitter), blocked by N's 3 on the bus: R = 1 + 3 + 2 = 5 from S's tick offset 0
    # (window [1, 1], response 5 from 1: ends by 6). A: released when M ends, between
    # 1 + 2 = 3 and 6: jitter 3, alone on cpu2: R = 3 + 1 = 4 from offset 3 (ends by 7).
    # The chain S -> M -> A is one segment (blocking reads): 10 + 7 - 0 = 17.
    sk = distributed()
    h = holistic_analysis(sk)
    got = {w.task: (w.earliest, w.latest, w.response) for w in h.windows.values()}
    assert got == {"S": (0, 0, 1), "M": (1, 1, 5), "N": (0, 0, 3 + 2), "A": (3, 6, 4)}
    b = holistic_latency(sk, ["S", "M", "A"])
    assert (b.name, b.value) == (HOLISTIC, 17)


def test_a_more_urgent_task_on_the_reader_adds_its_interference():
    # H (1 every 5) above A on cpu2: A released in [3, 6] (jitter 3), C = 1, preemptive
    # with H of jitter 0: w = 1 + ceil(w/5)*1 = 2, R = J + w = 3 + 2 = 5; busy period
    # t = ceil(t/5) + ceil((t + 3)/10): 2: one instance. A ends by 3 + 5 = 8: 18.
    sk = distributed(c_h=1)
    h = holistic_analysis(sk)
    assert (h.windows["A"].earliest, h.windows["A"].response) == (3, 5)
    assert holistic_latency(sk, ["S", "M", "A"]).value == 18


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(1, 3), st.integers(1, 3), st.integers(0, 4), st.integers(1, 2),
       st.integers(0, 2), st.sampled_from([5, 10, 20]), st.integers(0, 2),
       st.sampled_from([10, 20]),
       st.fractions(0, 20, max_denominator=4), st.fractions(0, 20, max_denominator=4),
       st.fractions(0, 10, max_denominator=4))
def test_every_simulated_job_and_reaction_is_within_the_holistic_bounds(
        c_s, c_m, c_n, c_a, c_h, t_h, delay, t_n, phase_s, phase_n, phase_h):
    sk = distributed(c_s, c_m, c_n, c_a, c_h, t_h, delay, t_n)
    report = analyze(sk, design=False)
    h = holistic_analysis(sk, report)
    bound = holistic_latency(sk, ["S", "M", "A"], report, analysis=h)
    if h.why is not None:  # nothing is claimed, and it says why
        assert bound.value is None and bound.note
        return
    sim = [SimTask("S", "cpu1", 0, F(c_s), F(10), phase_s),
           SimTask("M", "can", 2, F(c_m), source="S", delay=F(delay)),
           SimTask("N", "can", 1, F(c_n), F(t_n), phase_n),
           SimTask("A", "cpu2", 1, F(c_a), source="M")]
    if c_h:
        sim.append(SimTask("H", "cpu2", 2, F(c_h), F(t_h), phase_h))
    horizon = F(200) + max(phase_s, phase_n, phase_h)
    run = simulate(sim, {"cpu1": True, "can": False, "cpu2": True}, horizon)
    # Each clocked group's ticks: S's group (S, M, A) from phase_s, N and H their own.
    origin = {"S": phase_s, "M": phase_s, "A": phase_s, "N": phase_n, "H": phase_h}
    period = {"S": F(10), "M": F(10), "A": F(10), "N": F(t_n), "H": F(t_h)}
    for t, w in h.windows.items():
        for job in run.jobs[t]:
            tick = origin[t] + (job.k - 1) * period[t]
            assert job.release >= tick + w.earliest, (t, job, w)
            assert job.release <= tick + w.latest, (t, job, w)
            if job.finish is not None:
                assert job.finish <= tick + w.earliest + w.response, (t, job, w)
    got = reactions(run, ["S", "M", "A"], since=F(0))
    assert got["reaction"] is not None and got["reaction"] <= bound.value
