"""Communication delays in a chain's latency (spec §4c, §4d), on hand-derived cases.

A message written at ``w`` is visible from ``w + delay`` on, the delay being the
link's own when it declares one (0 included), else ``network.delay`` where the two
tasks run on different declared processors (also with a processor per task), else
0. Each expected value is traced by hand in the comment above it: the schedule, the
instant each message becomes visible, which message each read sees, and the figures.
"""

from __future__ import annotations

import json
from fractions import Fraction as F

import pytest
from typer.testing import CliRunner

from tegraph import analyze, load_skeleton
from tegraph.analysis.chains import ChainFigures, chain_paths
from tegraph.cli import app
from tegraph.design.timeline import simulate_timeline
from tegraph.model.build import build_teg
from tegraph.model.skeleton import Skeleton
from tests.paths import REPO

FIG4 = ["MT1", "MT2", "MT3", "MT4"]


def figures(f: ChainFigures) -> tuple:
    return f.first_use, f.age, f.age_min, f.reaction


def fig4(delays=None, network=None, mt1_on=None) -> Skeleton:
    """Figure 4's pipeline (four ASYN/ASYN hops, clocks of 10 ms, durations 1, 2, 2, 1)
    with ``delays`` on its links (in file order, None: not declared), a ``network``
    delay, and MT1 on processor ``mt1_on`` (the others on "default")."""
    data = load_skeleton(REPO / "examples" / "fig4_pipeline_unsynchronized.yaml").to_dict()
    for link, d in zip(data["links"], delays or []):
        if d is not None:
            link["delay"] = d
    if network is not None:
        data["network"] = {"delay": network}
    if mt1_on is not None:
        data["tasks"]["MT1"]["processor"] = mt1_on
    return Skeleton.from_dict(data)


def test_a_delay_on_one_processor_makes_a_read_miss_the_message_of_its_period():
    # One processor, MT1 the most urgent (rate-monotonic, file order): 0-1 MT1, 1-3 MT2,
    # 3-5 MT3, 5-6 MT4 each period; ASYN/ASYN adds no place, so the schedule is as
    # without delay. MT1 writes x1 at 10(j-1) + 1, visible 1/2 later, at 10(j-1) + 3/2:
    # after MT2's start at 10(j-1) + 1, so MT2 job k sees MT1 job k - 1 (sample at
    # 10(k-2)), and the rest of the period as before (MT3 at 10(k-1) + 3, MT4 posts at
    # 10(k-1) + 6): 10(k-1) + 6 - 10(k-2) = 16 for every output (was 6); a change just
    # after a sample at 0 is sampled at 10 and first posted at 26: reaction 26 (was 16).
    (c,) = analyze(fig4(delays=["1/2"]), chains=[FIG4]).chains
    assert figures(c.on_processors) == (16, 16, 16, 26)
    # With a processor per task every task starts at its tick, MT2 at 10(k-1) already
    # missed the write at 10(k-1) + 1 (another processor): 1/2 more changes nothing:
    # 31, 31, 31, 41 as without delay (test_chains.py).
    assert figures(c.processor_per_task) == (31, 31, 31, 41)
    # The worst data path waits at the delayed hop: the sample of job 1 at 0, MT1's
    # write at 1, MT2's read at the start of its job 2, at 11.
    steps = [(s.task, s.k, s.at) for s in c.on_processors.worst]
    assert steps[:3] == [("MT1", 1, 0), ("MT1", 1, 1), ("MT2", 2, 11)]


def test_a_delay_of_zero_changes_nothing():
    # Declared 0 on every link, and no network delay: every message is visible at its
    # write, the figures are those without delays (test_chains.py: 6, 6, 6, 16 on the
    # one processor, 31, 31, 31, 41 with a processor per task).
    sk = fig4(delays=[0, 0, 0])
    (p,) = chain_paths(sk, build_teg(sk), [FIG4])
    assert [h.delay for h in p.hops] == [0, 0, 0]
    plain = fig4()
    (q,) = chain_paths(plain, build_teg(plain), [FIG4])
    assert [(h.write, h.read, h.blocking, h.delay) for h in p.hops] == [
        (h.write, h.read, h.blocking, h.delay) for h in q.hops]
    (c,) = analyze(sk, chains=[FIG4]).chains
    assert figures(c.on_processors) == (6, 6, 6, 16)
    assert figures(c.processor_per_task) == (31, 31, 31, 41)


def test_the_network_delay_applies_only_between_declared_processors():
    # Every task on "default": no link crosses processors, a network delay of 9 applies
    # to none, also with a processor per task (decided by the declared processors).
    sk = fig4(network=9)
    (p,) = chain_paths(sk, build_teg(sk), [FIG4])
    assert [h.delay for h in p.hops] == [0, 0, 0]
    (c,) = analyze(sk, chains=[FIG4]).chains
    assert figures(c.on_processors) == (6, 6, 6, 16)
    assert figures(c.processor_per_task) == (31, 31, 31, 41)
    # MT1 on cpu1: only its link to MT2 crosses, and takes the network's 9.
    sk = fig4(network=9, mt1_on="cpu1")
    (p,) = chain_paths(sk, build_teg(sk), [FIG4])
    assert [h.delay for h in p.hops] == [9, 0, 0]


def test_a_non_blocking_read_at_the_instant_a_message_arrives_from_another_processor():
    # MT1 alone on cpu1: 0-1, writes x1 at 10(j-1) + 1. MT2, MT3, MT4 on "default"
    # (rate-monotonic, file order): 0-2, 2-4, 4-5 each period.
    # - Network delay 8: x1 visible at 10(j-1) + 9, before MT2's start at 10j: MT2 job
    #   k sees MT1 job k - 1 (sample at 10(k-2)); MT3 (same processor) at 10(k-1) + 2
    #   sees MT2 job k, MT4 at 10(k-1) + 4 MT3 job k, posts at 10(k-1) + 5: 15 for
    #   every output, reaction 25. As without delay: MT2 at 10(k-1) misses the write at
    #   10(k-1) + 1 of another processor anyway.
    # - Network delay 9: x1 visible at 10j, MT2's very start (job k + 1) on another
    #   processor: a race, not seen (§4c). MT2 job k sees MT1 job k - 2: 25, reaction 35.
    assert figures(analyze(fig4(mt1_on="cpu1"), chains=[FIG4]).chains[0].on_processors) \
        == (15, 15, 15, 25)
    assert figures(analyze(fig4(network=8, mt1_on="cpu1"),
                           chains=[FIG4]).chains[0].on_processors) == (15, 15, 15, 25)
    (c,) = analyze(fig4(network=9, mt1_on="cpu1"), chains=[FIG4]).chains
    assert figures(c.on_processors) == (25, 25, 25, 35)
    # With a processor per task (--no-processors too: which links cross is decided by
    # the declared processors): each task at its tick, MT1 job j's message visible at
    # 10j, MT2 job k starts at 10(k-1): seen when 10j < 10(k-1), so job k - 2 (sample
    # at 10(k-3)); MT3 at 10k and MT4 at 10(k+1) see the previous period's, posted at
    # 10(k+1) + 1: 41 (31 without delay), reaction 51.
    assert figures(c.processor_per_task) == (41, 41, 41, 51)
    (alone,) = analyze(fig4(network=9, mt1_on="cpu1"), chains=[FIG4],
                       processors=False).chains
    assert figures(alone.on_processors) == figures(alone.processor_per_task) == (41, 41, 41, 51)


def test_a_links_own_delay_of_zero_wins_over_the_network_delay():
    # As the race above, the link MT1 -> MT2 declaring delay 0: visible at its write
    # 10(j-1) + 1, the network's 9 does not apply: 15, 15, 15, 25 on processors and
    # 31, 31, 31, 41 with a processor per task, as without any delay.
    sk = fig4(delays=[0], network=9, mt1_on="cpu1")
    (p,) = chain_paths(sk, build_teg(sk), [FIG4])
    assert [h.delay for h in p.hops] == [0, 0, 0]
    (c,) = analyze(sk, chains=[FIG4]).chains
    assert figures(c.on_processors) == (15, 15, 15, 25)
    assert figures(c.processor_per_task) == (31, 31, 31, 41)


def syn_asyn(delay) -> Skeleton:
    # W samples its sensor s and writes x to R (SYN/ASYN), R posts u; each alone on its
    # processor, clocks of 10 ms at phase 0.
    return Skeleton.from_dict({
        "tasks": {"W": {"duration": 1, "period": 10, "inputs": ["s"], "outputs": ["x"],
                        "processor": "cpu1"},
                  "R": {"duration": 1, "period": 10, "inputs": ["x"], "outputs": ["u"],
                        "processor": "cpu2"}},
        "links": [{"from": "W:x", "to": "R:x", "protocol": "SYN/ASYN", "delay": delay}]})


@pytest.mark.parametrize("delay, expected", [
    # Delay 3: W's write waits for R's request (read at 10(k-1), travels 3): write at
    # max(10(k-1) + 1, 10(k-1) + 3) = 10(k-1) + 3, visible at 10(k-1) + 6, before R's
    # next read at 10k: R job k sees W job k - 1 (sample at its start, 10(k-2)), posts at
    # 10(k-1) + 1: 11; a sample at 10(j-1) is first replaced at the output of R job
    # j + 2, 10(j+1) + 1: reaction 21.
    (3, (11, 11, 11, 21)),
    # Delay 8: write at 10(k-1) + 8, visible at 10(k-1) + 16 = 10k + 6: R job k + 2 (at
    # 10(k+1)) is the first to see it: 10(k+1) + 1 - 10(k-1) = 21 (11 if the message
    # did not travel: only the request's place would then hold the delay); reaction 31.
    (8, (21, 21, 21, 31)),
])
def test_a_syn_asyn_link_delays_the_request_and_the_message(delay, expected):
    (c,) = analyze(syn_asyn(delay), chains=[["W", "R"]]).chains
    assert figures(c.on_processors) == figures(c.processor_per_task) == expected


RACE = """\
tasks:
  A: {duration: 1, period: 10, inputs: [s], outputs: [x], processor: cpu1}
  B: {duration: 1, period: 10, inputs: [x], outputs: [u], processor: cpu2}
network: {delay: 9}
links:
  - {from: "A:x", to: "B:x", protocol: ASYN/ASYN}
chains:
  - [A, B]
"""


@pytest.mark.parametrize("flags", [[], ["--no-processors"]])
def test_the_cli_reports_the_delayed_figures(tmp_path, flags):
    # A writes x at 10(j-1) + 1, visible 9 later at 10j: B starts at its tick 10(k-1),
    # on another processor, so the message arriving at its very start is not seen (a
    # race, §4c): B job k sees A job k - 2 (sample at 10(k-3)), posts at 10(k-1) + 1:
    # 21; reaction 31. Each task alone on its processor: the same with a processor per
    # task and on processors.
    f = tmp_path / "race.yaml"
    f.write_text(RACE)
    run = CliRunner().invoke(app, ["analyze", str(f), "--json", *flags])
    assert run.exit_code == 0, run.output
    (chain,) = json.loads(run.stdout)["chains"]
    want = {"first_use": "21", "age": "21", "age_min": "21", "reaction": "31"}
    assert {k: chain[k] for k in want} == want
    assert {k: chain["on_processors"][k] for k in want} == want
    assert F(chain["age"]) == 21


def test_the_timeline_reads_the_delays_as_analyze_does():
    # The race of test_a_non_blocking_read_at_the_instant_a_message_arrives_from_another_
    # processor (network delay 9, MT1 on cpu1): 25, 25, 25, 35 on processors; the
    # timeline's chain is the same one definition, and its worst data path waits a
    # period more at the delayed hop: MT1 writes at 1 (visible at 10), MT2 reads at the
    # start of its job 3, at 20.
    tl = simulate_timeline(fig4(network=9, mt1_on="cpu1"), chains=[FIG4])
    (c,) = tl.chains
    assert figures(c.figures) == (25, 25, 25, 35)
    steps = [(s.task, s.k, s.at) for s in c.figures.worst]
    assert steps[1:3] == [("MT1", 1, 1), ("MT2", 3, 20)]


@pytest.mark.parametrize("delay", [9, 19, 20, 29, 30, 31, 45])
def test_messages_in_flight_for_periods_pile_up_nowhere(delay):
    # A (duration 1, clock 10, on p) writes x ASYN/SYN to B (duration 2, on q): A ends
    # at 10k + 1, the message is visible at 10k + 1 + delay, B reads it then and runs
    # alone on q until 10k + 3 + delay, before the next message comes 10 ms later. The
    # link lies on no circuit: whatever the delay, ceil((delay + 1) / 10) messages are
    # in flight at most, nothing grows, B's response is 2 ms and A's 1 ms. (A state
    # taken at an instant where a message becomes visible holds one token more than
    # one taken 10 ms before that message is visible: a tick apart, not a pile-up.)
    data = {"name": "in_flight", "network": {"delay": delay},
            "tasks": {"A": {"duration": 1, "period": 10, "outputs": ["x"], "processor": "p"},
                      "B": {"duration": 2, "inputs": ["x"], "processor": "q"}},
            "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]}
    report = analyze(Skeleton.from_dict(data)).to_dict()
    assert report["schedulable"] is True and report["schedule"]["unbounded_places"] == []
    on = {t: report["tasks"][t]["on_processors"] for t in "AB"}
    assert (on["A"]["response"], on["B"]["response"], on["B"]["period"]) == ("1", "2", "10")
