"""The example skeletons of ``examples/``: the analysis reproduces the figures
derived BY HAND in each file's comment block (spec ``skeleton.md`` §2-§5).

Every expected value below is copied from the derivation in the example's
own comment, not from a run of the library; where a figure can be checked on
the daters (spec §3), the first firings computed by hand are compared with
:meth:`TimedEventGraph.simulate` too.
"""

from __future__ import annotations

import json
from fractions import Fraction as F
from functools import cache

import pytest

import tegraph
from tegraph import NotLiveError, analyze, build_teg, load_skeleton
from tegraph.analysis.reorder import reorder_ports
from tegraph.model.build import last_event
from tegraph.model.skeleton import Skeleton
from tests.paths import REPO

EXAMPLES = REPO / "examples"

ALL_EXAMPLES = [
    "fig4_pipeline_unsynchronized.yaml",
    "fig4_pipeline_synchronized.yaml",
    "fig7a_circular_wait.yaml",
    "fig7b_wrong_order.yaml",
    "fig11_fixed_order.yaml",
    "fig12_double_sync.yaml",
    "computed_torque.yaml",
    "rendezvous_two_clocks.yaml",
    "overrun_in_step.yaml",
    "threads.yaml",
    "ring_two_tokens.yaml",
    "lidar_fusion_two_clocks.yaml",
    "autoware_reference_system.yaml",
    "quadrotor.yaml",
    "two_boards_can.yaml",
]


@cache
def _load(name: str) -> Skeleton:
    return load_skeleton(EXAMPLES / name)


@cache
def _report(name: str):
    return analyze(_load(name))


def report_dict(name: str) -> dict:
    """The §5 JSON document, through a real JSON round trip."""
    return json.loads(tegraph.to_json(_report(name)))


def is_rotation(got: list[str], expected: list[str]) -> bool:
    """``got`` is the circuit ``expected`` started at some event."""
    if len(got) != len(expected) or not got:
        return False
    i = expected.index(got[0]) if got[0] in expected else -1
    return i >= 0 and expected[i:] + expected[:i] == got


def daters(name: str, n: int) -> dict[str, list[F]]:
    return build_teg(_load(name)).simulate(n).to_dict()


def check_tasks(d: dict, expected: dict[str, tuple]) -> None:
    """expected: task -> (group, period, overrun_at, slack, critical) as §5 strings."""
    assert list(d["tasks"]) == list(expected)
    for task, (group, period, overrun, slack, critical) in expected.items():
        got = d["tasks"][task]
        assert (got["group"], got["period"], got["overrun_at"], got["slack"], got["critical"]) \
            == (group, period, overrun, slack, critical), task


def check_group(g: dict, tasks, clocks, period, transient) -> None:
    assert g["tasks"] == tasks
    assert g["clocks"] == clocks
    assert g["period"] == period
    assert g["transient"] == (None if transient is None
                              else {"k": transient[0], "cyclicity": transient[1]})


# ----------------------------------------------------------------------- files

def test_every_example_is_tested_and_documented():
    on_disk = sorted(p.name for p in EXAMPLES.glob("*.yaml"))
    assert on_disk == sorted(ALL_EXAMPLES)
    for name in ALL_EXAMPLES:
        text = (EXAMPLES / name).read_text()
        head = text.splitlines()[:10]
        assert all(line.startswith("#") for line in head), name
        assert "Hand derivation" in text, name


@pytest.mark.parametrize("name", ALL_EXAMPLES)
def test_report_is_spec_json(name):
    d = report_dict(name)
    for key in ("name", "unit", "live", "consistent", "deadlocks", "reorder", "groups",
                "tasks", "unbounded_places", "invariants"):
        assert key in d, key
    assert d["name"] == _load(name).name
    assert d["unit"] == "ms"
    assert d["invariants"]["computed"] is True
    assert d["invariants"]["liveness_agrees"] is True
    assert (d["reorder"] is None) == d["live"]


# ----------------------------------------------------------- Figure 4 (ASYN)

def test_fig4_unsynchronized():
    d = report_dict("fig4_pipeline_unsynchronized.yaml")
    assert d["live"] is True and d["consistent"] is True
    assert d["deadlocks"] == [] and d["reorder"] is None and d["unbounded_places"] == []
    assert len(d["groups"]) == 4
    for i, g in enumerate(d["groups"]):
        t = f"MT{i + 1}"
        check_group(g, [t], [f"{t}.clock"], "10", (1, 1))
    check_tasks(d, {
        "MT1": (0, "10", None, "9", False),
        "MT2": (1, "10", None, "8", False),
        "MT3": (2, "10", None, "8", False),
        "MT4": (3, "10", None, "9", False),
    })
    assert d["invariants"]["count"] == 8


def test_fig4_synchronized():
    d = report_dict("fig4_pipeline_synchronized.yaml")
    assert d["live"] is True and d["consistent"] is True
    assert d["unbounded_places"] == []
    assert len(d["groups"]) == 1
    check_group(d["groups"][0], ["MT1", "MT2", "MT3", "MT4"], ["rtc"], "10", (1, 1))
    check_tasks(d, {
        "MT1": (0, "10", None, "9", False),
        "MT2": (0, "10", None, "8", False),
        "MT3": (0, "10", None, "8", False),
        "MT4": (0, "10", None, "9", False),
    })
    assert d["invariants"]["count"] == 5
    r = _report("fig4_pipeline_synchronized.yaml")
    assert r.groups[0].period == 10 and r.groups[0].transient == (1, 1)
    assert [r.tasks[t].slack for t in ("MT1", "MT2", "MT3", "MT4")] == [9, 8, 8, 9]


def test_fig4_synchronized_daters():
    x = daters("fig4_pipeline_synchronized.yaml", 3)
    hand = {  # k = 1, 2 from the comment; k = 3 = k = 2 + 10
        "rtc.tick": [0, 10, 20],
        "MT1.activate": [0, 10, 20], "MT1.read:q": [0, 10, 20], "MT1.compute": [0, 10, 20],
        "MT1.write:x1": [1, 11, 21],
        "MT2.read:x1": [1, 11, 21], "MT2.compute": [1, 11, 21], "MT2.write:x2": [3, 13, 23],
        "MT3.read:x2": [3, 13, 23], "MT3.write:x3": [5, 15, 25],
        "MT4.read:x3": [5, 15, 25], "MT4.compute": [5, 15, 25], "MT4.write:u": [6, 16, 26],
    }
    for event, times in hand.items():
        assert x[event] == [F(t) for t in times], event


# ------------------------------------------------------ Figure 7a, 7b, 11

def test_fig7a_circular_wait():
    d = report_dict("fig7a_circular_wait.yaml")
    assert d["live"] is False and d["consistent"] is False
    assert len(d["deadlocks"]) == 1
    dl = d["deadlocks"][0]
    hand = ["MT1.read:b", "MT1.compute", "MT1.write:a", "MT3.read:a", "MT3.compute",
            "MT3.write:c", "MT2.read:c", "MT2.compute", "MT2.write:b"]
    assert is_rotation(dl["events"], hand), dl["events"]
    assert sorted(dl["tasks"]) == ["MT1", "MT2", "MT3"]
    assert d["reorder"]["possible"] is False
    assert d["reorder"]["orders"] == {}
    assert len(d["groups"]) == 1
    check_group(d["groups"][0], ["MT1", "MT2", "MT3"], [], None, None)
    check_tasks(d, {t: (0, None, None, None, None) for t in ("MT1", "MT2", "MT3")})
    assert d["unbounded_places"] == []
    assert d["invariants"]["count"] == 4
    with pytest.raises(NotLiveError):
        build_teg(_load("fig7a_circular_wait.yaml")).simulate(2)


def test_fig7a_reorder_names_the_three_links():
    r = _report("fig7a_circular_wait.yaml")
    assert sorted(r.reorder.links) == sorted([
        "MT2:b -> MT1:b (ASYN/SYN)", "MT3:c -> MT2:c (ASYN/SYN)", "MT1:a -> MT3:a (ASYN/SYN)"])


# The three live port orders of Figure 7b, derived by hand in its comment.
FIG7B_FIXES = [
    {"MT2": {"inputs": ["a", "c"], "outputs": ["tau"]}},                     # (b)
    {"MT1": {"inputs": ["q"], "outputs": ["d", "a"]}},                       # (c)
    {"MT1": {"inputs": ["q"], "outputs": ["d", "a"]},
     "MT2": {"inputs": ["a", "c"], "outputs": ["tau"]}},                     # (d)
]


def _apply_orders(sk: Skeleton, orders: dict) -> Skeleton:
    data = sk.to_dict()
    for task, o in orders.items():
        data["tasks"][task]["inputs"] = list(o["inputs"])
        data["tasks"][task]["outputs"] = list(o["outputs"])
    return Skeleton.from_dict(data)


def test_fig7b_wrong_order():
    d = report_dict("fig7b_wrong_order.yaml")
    assert d["live"] is False and d["consistent"] is False
    assert len(d["deadlocks"]) == 1
    dl = d["deadlocks"][0]
    hand = ["MT2.read:c", "MT1.write:a", "MT1.write:d", "MT3.read:d", "MT3.compute",
            "MT3.write:c"]
    assert is_rotation(dl["events"], hand), dl["events"]
    assert sorted(dl["tasks"]) == ["MT1", "MT2", "MT3"]
    assert d["reorder"]["possible"] is True
    check_group(d["groups"][0], ["MT1", "MT2", "MT3"], ["rtc"], None, None)
    check_tasks(d, {t: (0, None, None, None, None) for t in ("MT1", "MT2", "MT3")})
    assert d["invariants"]["count"] == 5


def test_fig7b_reorder_is_one_of_the_hand_derived_fixes():
    sk = _load("fig7b_wrong_order.yaml")
    orders = _report("fig7b_wrong_order.yaml").reorder.orders
    full = {}
    for task, o in orders.items():
        # a task listed with an unchanged side keeps its declared order there
        full[task] = {"inputs": list(o["inputs"]), "outputs": list(o["outputs"])}
    assert full in FIG7B_FIXES, orders
    fixed = analyze(_apply_orders(sk, orders))
    assert fixed.live is True
    # and every hand-derived fix is live, the declared order is not
    for fix in FIG7B_FIXES:
        assert analyze(_apply_orders(sk, fix)).live is True
    assert reorder_ports(sk).possible is True


def test_fig11_fixed_order():
    d = report_dict("fig11_fixed_order.yaml")
    assert d["live"] is True and d["consistent"] is True
    assert d["deadlocks"] == [] and d["reorder"] is None and d["unbounded_places"] == []
    check_group(d["groups"][0], ["MT1", "MT2", "MT3"], ["rtc"], "10", (1, 1))
    check_tasks(d, {
        "MT1": (0, "10", None, "8", False),
        "MT2": (0, "10", None, "6", False),
        "MT3": (0, "10", None, "6", False),
    })
    assert d["invariants"]["count"] == 5


def test_fig11_daters():
    x = daters("fig11_fixed_order.yaml", 3)
    hand = {  # k = 1 and k = 2 from the comment, k = 3 = k = 2 + 10
        "rtc.tick": [0, 10, 20],
        "MT1.activate": [0, 10, 20], "MT1.read:q": [0, 10, 20], "MT1.compute": [0, 10, 20],
        "MT1.write:a": [2, 12, 22], "MT1.write:d": [2, 12, 22],
        "MT3.read:d": [2, 12, 22], "MT3.compute": [2, 12, 22], "MT3.write:c": [5, 15, 25],
        "MT2.read:c": [5, 15, 25], "MT2.compute": [5, 15, 25], "MT2.write:tau": [6, 16, 26],
    }
    assert set(x) == set(hand)  # the rendezvous is one event, named by the writer
    for event, times in hand.items():
        assert x[event] == [F(t) for t in times], event


# ------------------------------------------------------------- Figure 12

def test_fig12_double_sync():
    d = report_dict("fig12_double_sync.yaml")
    assert d["live"] is True and d["consistent"] is False
    assert d["deadlocks"] == [] and d["reorder"] is None
    assert len(d["groups"]) == 1
    check_group(d["groups"][0], ["MT1", "MT2"], ["rtc", "MT2.clock"], None, None)
    check_tasks(d, {
        "MT1": (0, "10", None, None, None),
        "MT2": (0, "10", 3, None, None),
    })
    assert [(u["from"], u["to"], u["kind"]) for u in d["unbounded_places"]] == [
        ("MT2.clock.tick", "MT2.activate", "clock-overrun")]
    assert d["invariants"]["count"] == 4
    r = _report("fig12_double_sync.yaml")
    assert r.tasks["MT2"].overrun_at == 3 and r.tasks["MT1"].overrun_at is None
    assert r.groups[0].period is None and r.groups[0].transient is None


def test_fig12_daters():
    x = daters("fig12_double_sync.yaml", 4)
    hand = {
        "rtc.tick": [0, 10, 20, 30],
        "MT1.activate": [0, 10, 20, 30],
        "MT1.write:y": [1, 11, 21, 31],
        "MT2.clock.tick": [0, 4, 8, 12],
        "MT2.activate": [0, 4, 13, 23],
        "MT2.read:y": [1, 11, 21, 31],
        "MT2.compute": [1, 11, 21, 31],
        "MT2.write:u": [3, 13, 23, 33],
    }
    for event, times in hand.items():
        assert x[event] == [F(t) for t in times], event
    # the overrun condition of spec §4 on these daters: first at k = 3
    last, tick = x["MT2.write:u"], x["MT2.clock.tick"]
    assert [k for k in range(2, 5) if last[k - 2] > tick[k - 1]] == [3, 4]


# ------------------------------------------------------ computed torque

def test_computed_torque():
    d = report_dict("computed_torque.yaml")
    assert d["live"] is True and d["consistent"] is True
    assert d["unbounded_places"] == [] and d["deadlocks"] == []
    assert len(d["groups"]) == 3
    check_group(d["groups"][0], ["OBS.JL"], ["obs"], "1", (1, 1))
    check_group(d["groups"][1], ["TG.JS", "TF.TT.JS", "CO.JS"], ["ctl"], "2", (1, 1))
    check_group(d["groups"][2], ["MOD.DYN"], ["dyn"], "6", (1, 1))
    check_tasks(d, {
        "OBS.JL": (0, "1", None, "9/10", False),
        "TG.JS": (1, "2", None, "19/10", False),
        "TF.TT.JS": (1, "2", None, "9/5", False),
        "CO.JS": (1, "2", None, "17/10", False),
        "MOD.DYN": (2, "6", None, "24/5", False),
    })
    assert d["invariants"]["count"] == 8


def test_computed_torque_daters():
    x = daters("computed_torque.yaml", 2)
    hand = {
        "ctl.tick": ["0", "2"], "TG.JS.compute": ["0", "2"],
        "TG.JS.write:qd": ["1/10", "21/10"],
        "TF.TT.JS.read:qd": ["1/10", "21/10"], "TF.TT.JS.write:e": ["3/10", "23/10"],
        "CO.JS.read:e": ["3/10", "23/10"], "CO.JS.compute": ["3/10", "23/10"],
        "CO.JS.write:tau": ["3/5", "13/5"],
    }
    for event, times in hand.items():
        assert x[event] == [F(t) for t in times], event


# ------------------------------------------------------------ quadrotor

def test_quadrotor():
    # Hand derivation (the example's comment): five groups, each clocked one keeping its
    # clock's period from k = 1 (1, 2.5, 20, 100 ms), the logger without clock running
    # back to back (period 12 with a processor per task: its duration). Slack: the
    # period minus the duration, the logger 0 (critical). Circuits with a token: four
    # clock self-loops and seven task loops, 11 semiflows. On the CPU (spec §4b),
    # each unit from its tick: imu 0-0.1, att_est 0.1-0.25, rate_ctrl 0.25-0.55,
    # mixer 0.55-0.75; pos_ctrl ends at 4, gps at 20 (the recurrences of the comment);
    # the logger fills the 36 idle ms of every 100 with three jobs of 12: 100/3.
    d = report_dict("quadrotor.yaml")
    assert d["live"] is True and d["consistent"] is True and d["schedulable"] is True
    assert d["unbounded_places"] == [] and d["deadlocks"] == []
    check_group(d["groups"][0], ["imu", "att_est"], ["imu_clk"], "1", (1, 1))
    check_group(d["groups"][1], ["rate_ctrl", "mixer"], ["rate_clk"], "5/2", (1, 1))
    check_group(d["groups"][2], ["pos_ctrl"], ["pos_clk"], "20", (1, 1))
    check_group(d["groups"][3], ["gps"], ["gps_clk"], "100", (1, 1))
    check_group(d["groups"][4], ["logger"], [], "12", (1, 1))
    check_tasks(d, {
        "imu": (0, "1", None, "9/10", False), "att_est": (0, "1", None, "17/20", False),
        "rate_ctrl": (1, "5/2", None, "11/5", False),
        "mixer": (1, "5/2", None, "23/10", False),
        "pos_ctrl": (2, "20", None, "18", False), "gps": (3, "100", None, "91", False),
        "logger": (4, "12", None, "0", True),
    })
    assert d["invariants"]["count"] == 11
    on = {t: (v["on_processors"]["period"], v["on_processors"]["response"])
          for t, v in d["tasks"].items() if t != "logger"}
    assert on == {"imu": ("1", "1/10"), "att_est": ("1", "3/20"),
                  "rate_ctrl": ("5/2", "11/20"), "mixer": ("5/2", "1/5"),
                  "pos_ctrl": ("20", "4"), "gps": ("100", "20")}
    assert d["tasks"]["logger"]["on_processors"]["period"] == "100/3"


# --------------------------------------------------------------- extras

def test_rendezvous_two_clocks():
    d = report_dict("rendezvous_two_clocks.yaml")
    assert d["live"] is True and d["consistent"] is True
    assert d["unbounded_places"] == []
    check_group(d["groups"][0], ["P", "Q"], ["cp", "cq"], "5", (1, 1))
    check_tasks(d, {
        "P": (0, "5", None, "4", False),
        "Q": (0, "5", None, "3", False),
    })
    assert d["invariants"]["count"] == 4
    x = daters("rendezvous_two_clocks.yaml", 2)
    hand = {
        "cp.tick": ["0", "5"], "cq.tick": ["5/2", "15/2"],
        "P.activate": ["0", "5"], "P.compute": ["0", "5"],
        "Q.activate": ["5/2", "15/2"], "P.write:x": ["5/2", "15/2"],
        "Q.compute": ["5/2", "15/2"], "Q.write:y": ["9/2", "19/2"],
    }
    assert set(x) == set(hand)  # no event "Q.read:x": merged into the rendezvous
    for event, times in hand.items():
        assert x[event] == [F(t) for t in times], event


def test_rendezvous_slack_is_exact():
    """Growing P by its slack (4 -> duration 5) keeps the period 5 and no overrun."""
    data = _load("rendezvous_two_clocks.yaml").to_dict()
    data["tasks"]["P"]["duration"] = "5"
    r = analyze(Skeleton.from_dict(data))
    assert r.consistent and r.groups[0].period == 5 and r.tasks["P"].critical is True


def test_overrun_in_step():
    d = report_dict("overrun_in_step.yaml")
    assert d["live"] is True and d["consistent"] is False
    assert d["unbounded_places"] == []
    check_group(d["groups"][0], ["MT1", "MT2"], ["MT1.clock", "MT2.clock"], "10", (2, 1))
    check_tasks(d, {
        "MT1": (0, "10", None, "4", False),
        "MT2": (0, "10", 2, "4", False),
    })
    assert d["invariants"]["count"] == 4
    x = daters("overrun_in_step.yaml", 3)
    assert x["MT2.activate"] == [0, 12, 22]
    assert x["MT2.read:y"] == [6, 16, 26]
    assert x["MT2.write:u"] == [12, 22, 32]
    assert x["MT1.write:y"] == [6, 16, 26]


def test_threads_clocked_pipeline():
    d = report_dict("threads.yaml")
    assert d["live"] is True
    check_group(d["groups"][0], ["TG.JS", "TF.TT.JS", "CO.JS"], ["ctl"], "2", (1, 1))
    for t in ("TG.JS", "TF.TT.JS", "CO.JS"):
        got = d["tasks"][t]
        assert (got["group"], got["period"], got["overrun_at"], got["slack"], got["critical"]) \
            == (0, "2", None, "4/5", False), t
    x = daters("threads.yaml", 2)
    hand = {
        "TG.JS.activate": ["0", "2"], "TG.JS.write:qd": ["3/10", "23/10"],
        "TF.TT.JS.read:qd": ["3/10", "23/10"], "TF.TT.JS.write:e": ["7/10", "27/10"],
        "CO.JS.read:e": ["7/10", "27/10"], "CO.JS.write:tau": ["6/5", "16/5"],
    }
    for event, times in hand.items():
        assert x[event] == [F(t) for t in times], event


def test_threads_free_running_period_is_the_sum():
    """A thread of tasks without outputs: the thread place leaves T.compute,
    so it holds duration(T) (spec §2), and the period is 1/3 + 1/2 = 5/6."""
    d = report_dict("threads.yaml")
    check_group(d["groups"][1], ["LOG", "DIAG"], [], "5/6", (1, 1))
    for t in ("LOG", "DIAG"):
        got = d["tasks"][t]
        assert (got["group"], got["period"], got["overrun_at"], got["slack"], got["critical"]) \
            == (1, "5/6", None, "0", True), t
    x = daters("threads.yaml", 3)
    assert x["LOG.compute"] == [F(0), F(5, 6), F(5, 3)]
    assert x["DIAG.compute"] == [F(1, 3), F(7, 6), F(2)]
    assert d["consistent"] is True
    assert d["invariants"]["count"] == 11


def test_ring_two_tokens():
    d = report_dict("ring_two_tokens.yaml")
    assert d["live"] is True and d["consistent"] is True
    assert d["unbounded_places"] == []
    check_group(d["groups"][0], ["A", "B", "C", "D"], [], "7/3", (3, 2))
    check_tasks(d, {
        "A": (0, "7/3", None, "0", True),
        "B": (0, "7/3", None, "0", True),
        "C": (0, "7/3", None, "0", True),
        "D": (0, "7/3", None, "4/3", False),
    })
    assert d["invariants"]["count"] == 5
    r = _report("ring_two_tokens.yaml")
    assert r.groups[0].period == F(7, 3) and r.groups[0].transient == (3, 2)


def test_ring_two_tokens_daters():
    x = daters("ring_two_tokens.yaml", 6)
    third = {  # the table of the comment, in units of 1/3 ms
        "B.read:z": [0, 14, 20, 28, 34, 42], "C.compute": [0, 5, 14, 20, 28, 34],
        "C.write:y": [5, 10, 19, 25, 33, 39], "C.write:z": [5, 14, 20, 28, 34, 42],
        "A.read:y": [5, 10, 19, 25, 33, 39], "A.compute": [5, 10, 19, 25, 33, 39],
        "A.write:x": [8, 13, 22, 28, 36, 42], "B.read:x": [8, 14, 22, 28, 36, 42],
        "B.compute": [8, 14, 22, 28, 36, 42], "D.read:x": [8, 13, 22, 28, 36, 42],
        "D.compute": [8, 13, 22, 28, 36, 42],
    }
    assert set(x) == set(third)
    for event, times in third.items():
        assert x[event] == [F(t, 3) for t in times], event


def test_overrun_daters_match_report_for_every_clocked_example():
    """Spec §4 overrun_at recomputed from the daters, on every live example."""
    for name in ALL_EXAMPLES:
        r = _report(name)
        if not r.live:
            continue
        sk = _load(name)
        teg = build_teg(sk)
        n = 40
        x = teg.simulate(n)
        for t, task in sk.tasks.items():
            if task.clock is None:
                assert r.tasks[t].overrun_at is None
                continue
            # v1.1: the end of an activation; without outputs, compute + duration.
            extra = 0 if task.outputs else task.duration
            last = [v + extra for v in x[last_event(teg, t)]]
            tick = x[f"{task.clock}.tick"]
            hits = [k for k in range(2, n + 1) if last[k - 2] > tick[k - 1]]
            assert r.tasks[t].overrun_at == (hits[0] if hits else None), (name, t)


# ------------------------------------------- the Autoware reference system

# From ros-realtime/reference-system (the file's header cites the revision and paths):
# autoware_system_builder.hpp builds 6 sensors, 9 transforms, 5 fusions, 1 cyclic node,
# 1 intersection node (two callbacks, two tasks here) and 2 command nodes: 25 tasks;
# its subscriptions number 9 + 5*2 + 6 + 2 + 2 = 29 links, the cyclic node's 6 ASYN/ASYN.
# timing/default.hpp, struct Default: the clock periods below, in ms.
AUTOWARE = "autoware_reference_system.yaml"
AUTOWARE_CLOCKS = {"FrontLidarDriver": 100, "RearLidarDriver": 100, "PointCloudMap": 120,
                   "Visualizer": 60, "Lanelet2Map": 100, "EuclideanClusterSettings": 25,
                   "BehaviorPlanner": 100}
W = F("0.22837")  # README: number_crunch_limit 4096 runs 0.22837 ms on its i7


def test_autoware_reference_system_is_the_source_graph():
    sk = _load(AUTOWARE)
    assert len(sk.tasks) == 25
    assert {t: sk.clocks[task.clock].period for t, task in sk.tasks.items()
            if task.clock is not None} == AUTOWARE_CLOCKS
    protocols = [link.protocol.value for link in sk.links]
    assert len(protocols) == 29 and protocols.count("ASYN/ASYN") == 6
    assert all(link.reader[0] == "BehaviorPlanner" for link in sk.links
               if link.protocol.value == "ASYN/ASYN")
    # the sensors and the command nodes crunch nothing; every other callback crunches 4096
    idle = {*AUTOWARE_CLOCKS} - {"BehaviorPlanner"} | {"VehicleDBWSystem", "IntersectionOutput"}
    assert {t: task.duration for t, task in sk.tasks.items()} \
        == {t: (0 if t in idle else W) for t in sk.tasks}


def test_autoware_reference_system():
    # Hand derivation (the comment of the example): live (every ASYN/SYN link goes from a
    # lower rank to a higher one); three groups: the lidar and map front end (5 clocks),
    # the cluster settings (25 ms), the behavior planner's (100 ms). In the front end
    # each task runs at the slowest clock upstream: 100 on the lidar path, 120 from
    # PointCloudMap on; three ASYN/SYN places join a faster writer to a 120 ms reader
    # (messages-overwritten), so that group has no period. Groups 1 and 2 have periods
    # 25 and 100 from k = 1; nothing overruns; slack = period - duration.
    d = report_dict(AUTOWARE)
    r = _report(AUTOWARE)
    assert d["live"] is True and d["consistent"] is False
    assert d["deadlocks"] == [] and d["reorder"] is None
    front = ["FrontLidarDriver", "RearLidarDriver", "PointCloudMap", "Visualizer",
             "Lanelet2Map", "PointsTransformerFront", "PointsTransformerRear",
             "VoxelGridDownsampler", "PointCloudMapLoader", "RayGroundFilter",
             "ObjectCollisionEstimator", "ParkingPlanner", "LanePlanner", "PointCloudFusion",
             "NDTLocalizer", "Lanelet2GlobalPlanner", "Lanelet2MapLoader",
             "EuclideanClusterDetector"]
    settings = ["EuclideanClusterSettings", "EuclideanIntersection", "IntersectionOutput"]
    behavior = ["MPCController", "VehicleInterface", "BehaviorPlanner", "VehicleDBWSystem"]
    assert [g["tasks"] for g in d["groups"]] == [front, settings, behavior]
    assert [sorted(g["clocks"]) for g in d["groups"]] == [
        sorted(f"{t}.clock" for t in ("FrontLidarDriver", "RearLidarDriver", "PointCloudMap",
                                      "Visualizer", "Lanelet2Map")),
        ["EuclideanClusterSettings.clock"], ["BehaviorPlanner.clock"]]
    assert [(g.period, g.transient) for g in r.groups] == [(None, None), (25, (1, 1)),
                                                            (100, (1, 1))]
    at_120 = {"PointCloudMap", "PointCloudMapLoader", "NDTLocalizer", "Lanelet2GlobalPlanner",
              "Lanelet2MapLoader", "ParkingPlanner", "LanePlanner"}
    hand_period = {t: (120 if t in at_120 else 100) for t in front}
    hand_period |= {"Visualizer": 60} | {t: 25 for t in settings} | {t: 100 for t in behavior}
    assert {t: r.tasks[t].period for t in r.tasks} == hand_period
    assert all(r.tasks[t].overrun_at is None for t in r.tasks)
    assert all(r.tasks[t].slack is None for t in front)
    assert {t: r.tasks[t].slack for t in settings + behavior} == {
        "EuclideanClusterSettings": 25, "EuclideanIntersection": 25 - W,
        "IntersectionOutput": 25, "MPCController": 100 - W, "VehicleInterface": 100 - W,
        "BehaviorPlanner": 100 - W, "VehicleDBWSystem": 100}
    assert 25 - W == F(2477163, 100000) and 100 - W == F(9977163, 100000)
    assert not any(r.tasks[t].critical for t in settings + behavior)
    assert sorted((u["from"], u["to"], u["kind"]) for u in d["unbounded_places"]) == sorted([
        ("VoxelGridDownsampler.write:out", "NDTLocalizer.read:VoxelGridDownsampler",
         "messages-overwritten"),
        ("Visualizer.write:out", "Lanelet2GlobalPlanner.read:Visualizer",
         "messages-overwritten"),
        ("Lanelet2Map.write:out", "Lanelet2MapLoader.read:Lanelet2Map",
         "messages-overwritten")])
    assert d["invariants"]["count"] == 7 + 25  # clock self-loops + chains


def test_autoware_reference_system_daters():
    x = daters(AUTOWARE, 2)
    hand = {  # the comment's daters of groups 1 and 2, k = 1, 2
        "EuclideanClusterSettings.clock.tick": [0, 25],
        "EuclideanIntersection.read:EuclideanClusterSettings": [0, 25],
        "EuclideanIntersection.write:out": [W, 25 + W],
        "IntersectionOutput.compute": [W, 25 + W],
        "BehaviorPlanner.compute": [0, 100], "BehaviorPlanner.write:out": [W, 100 + W],
        "MPCController.write:out": [2 * W, 100 + 2 * W],
        "VehicleInterface.read:BehaviorPlanner": [2 * W, 100 + 2 * W],
        "VehicleInterface.write:out": [3 * W, 100 + 3 * W],
        "VehicleDBWSystem.compute": [3 * W, 100 + 3 * W],
    }
    for event, times in hand.items():
        assert x[event] == [F(t) for t in times], event


def test_autoware_verdicts_hold_for_the_readmes_10_ms():
    """The header's claim: with every crunching callback at 10 ms (the README's words)
    instead of 0.22837, the groups, periods and liveness are the same (every chain ratio,
    10, stays below the fastest clock of its group, 25)."""
    data = _load(AUTOWARE).to_dict()
    for task in data["tasks"].values():
        if F(str(task["duration"])) == W:
            task["duration"] = 10
    r = analyze(Skeleton.from_dict(data))
    base = _report(AUTOWARE)
    assert r.live and [(g.tasks, g.period) for g in r.groups] \
        == [(g.tasks, g.period) for g in base.groups]
    assert {t: r.tasks[t].period for t in r.tasks} == {t: base.tasks[t].period for t in r.tasks}
    assert all(r.tasks[t].overrun_at is None for t in r.tasks)


# ------------------------------------------------------------ two boards and a CAN bus

def test_two_boards_can():
    # Hand derivation (the example's comment): from the common release, diag_frame
    # (queued 0.75) holds the bus 0.75-1.75 and imu_frame, queued at 1, waits for it:
    # 1.75-2.25, ctrl 2.25-3.75, cmd_frame 3.75-4.25, motor 4.25-4.75; in the three
    # periods without a diagnostic the chain takes 4 ms. A 20 ms regime.
    d = report_dict("two_boards_can.yaml")
    assert d["live"] and d["consistent"] and d["schedulable"] is True
    assert [(p["name"], p["preemptive"]) for p in d["processors"]] == [
        ("board1", True), ("can", False), ("board2", True)]
    on = {t: (v["on_processors"]["period"], v["on_processors"]["response"])
          for t, v in d["tasks"].items()}
    assert on == {"imu": ("5", "1"), "imu_frame": ("5", "5/4"), "ctrl": ("5", "3/2"),
                  "cmd_frame": ("5", "1/2"), "motor": ("5", "1/2"),
                  "diag": ("20", "3/4"), "diag_frame": ("20", "1")}
    (chain,) = d["chains"]
    assert chain["on_processors"] == {"first_use": "19/4", "age": "19/4", "age_min": "4",
                                      "reaction": "39/4", "why_undecided": None}


def test_two_boards_can_explored():
    # The command of the example's comment. The frames stay on the bus (not offered);
    # imu, ctrl, motor and diag move between the two alike boards: 2^4 = 16 placements,
    # 8 up to renaming. The chain needs at least 1 + 0.5 + 1.5 + 0.5 + 0.5 = 4 ms; it
    # gets 4 wherever diag_frame is not queued just before imu_frame, e.g. with diag on
    # the sensor board (diag runs after imu, 1-1.75: its frame 1.75-2.75 leaves
    # imu_frame 1-1.5 and cmd_frame 3-3.5 free). Demands (C/T): imu 1/5, ctrl 3/10,
    # motor 1/10, diag 3/80; the least busiest board over two boards puts ctrl alone
    # (3/10) against the rest (27/80): 27/80, 3 processors (with the bus); one board
    # for all: 51/80, 2 processors. The declared placement (diag beside ctrl: 4.75 ms,
    # 27/80) is dominated.
    from typer.testing import CliRunner

    from tegraph.cli import app
    result = CliRunner().invoke(app, [
        "explore", str(EXAMPLES / "two_boards_can.yaml"), "--processors", "board1,board2",
        "--allocate", "tasks", "--objective", "latency", "--objective", "busiest",
        "--objective", "processors", "--json"])
    assert result.exit_code == 0, result.output
    doc = json.loads(result.output)
    assert doc["variants"] == 8 and doc["exhaustive"] is True
    front = sorted(tuple(r["objectives"].values()) for r in doc["front"])
    assert front == [("4", "27/80", "3"), ("4", "51/80", "2")]
    alone = next(r for r in doc["front"] if r["objectives"]["processors"] == "2")
    assert len(set(alone["processors"].values())) == 1
