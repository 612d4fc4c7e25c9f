"""The v1.3 keys of spec §1: ``processors``, ``network.delay``, ``links[i].delay``.

Each refusal names its key path (and line) and says what is expected; a skeleton
with the keys goes through every writer and comes back equal.
"""

from __future__ import annotations

import dataclasses
import json
from fractions import Fraction as F

import pytest
from typer.testing import CliRunner

from tegraph import SkeletonError, load_skeleton
from tegraph.cli import app
from tegraph.io import dump_skeleton
from tegraph.model.elements import Processor
from tegraph.model.skeleton import Skeleton

BASE = ("tasks:\n"
        "  W: {duration: 1, period: 4, outputs: [a], processor: cpu1}\n"
        "  R: {duration: 1, inputs: [a], processor: can0}\n")


def refused(tmp_path, text: str) -> SkeletonError:
    f = tmp_path / "s.yaml"
    f.write_text(text)
    with pytest.raises(SkeletonError) as info:
        load_skeleton(f)
    assert str(f) in str(info.value)  # the message names the file
    return info.value


@pytest.mark.parametrize("tail, key_path, wording", [
    ("processors: {can0: false}\n", "processors.can0",
     "expected a mapping of processor properties"),
    ("processors: {gpu: {preemptive: false}}\n", "processors.gpu",
     "no task runs on processor 'gpu'"),
    ("processors: {default: {}}\n", "processors.default", "no task runs on processor 'default'"),
    ("processors: {can0: {preemptible: false}}\n", "processors.can0.preemptible",
     "unknown key 'preemptible' (did you mean 'preemptive'?)"),
    ("processors: {can0: {preemptive: 0}}\n", "processors.can0.preemptive",
     "expected true or false"),
    ("processors: {can0: {preemptive: 'false'}}\n", "processors.can0.preemptive",
     "got the text 'false'"),
    ("processors: [can0]\n", "processors", "expected a mapping from processor names"),
    ("network: {latency: 1}\n", "network.latency", "unknown key 'latency'"),
    ("network: 0.2\n", "network", "expected a mapping such as {delay: 0.2}"),
    ("network: {delay: -1}\n", "network.delay", "expected a delay >= 0, got -1"),
    ("network: {delay: .inf}\n", "network.delay", "a finite number"),
    ("links:\n  - {from: 'W:a', to: 'R:a', protocol: ASYN/SYN, delay: -0.5}\n",
     "links[0].delay", "expected a delay >= 0, got -0.5"),  # echoed as written
    ("links:\n  - {from: 'W:a', to: 'R:a', protocol: ASYN/SYN, delay: x}\n",
     "links[0].delay", "got the text 'x'"),
    ("links:\n  - {from: 'W:a', to: 'R:a', protocol: ASYN/SYN, delay: 1/0}\n",
     "links[0].delay", "zero denominator"),
    ("links:\n  - {from: 'W:a', to: 'R:a', protocol: SYN/SYN, delay: 1}\n",
     "links[0]", "a SYN/SYN link with a delay (1, its own)"),
    ("network: {delay: 2}\nlinks:\n  - {from: 'W:a', to: 'R:a', protocol: SYN/SYN}\n",
     "links[0]", "the network's, between processors 'cpu1' and 'can0'"),
])
def test_refusals_name_the_key(tmp_path, tail, key_path, wording):
    err = refused(tmp_path, BASE + tail)
    assert err.where == key_path, (err.where, err.reason)
    assert wording in err.reason and "expected" in err.reason


def test_a_rendezvous_may_keep_delay_zero():
    # Its own 0 wins over the network's; on one processor the network does not apply.
    ok = Skeleton.from_dict({"network": {"delay": 2}, "tasks": {
        "W": {"duration": 1, "period": 4, "outputs": ["a", "b"], "processor": "p"},
        "R": {"duration": 1, "inputs": ["a"], "processor": "q"},
        "S": {"duration": 1, "inputs": ["b"], "processor": "p"}},
        "links": [{"from": "W:a", "to": "R:a", "protocol": "SYN/SYN", "delay": 0},
                  {"from": "W:b", "to": "S:b", "protocol": "SYN/SYN"}]})
    assert ok.links[0].delay == 0 and ok.links[1].delay is None


def test_a_skeleton_built_in_code_is_checked_alike():
    s = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "outputs": ["x"]},
                                      "B": {"duration": 1, "inputs": ["x"]}},
                            "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]})
    bad = dataclasses.replace(s, links=[dataclasses.replace(s.links[0], delay=F(-1))])
    with pytest.raises(SkeletonError, match=r"links\[0\]\.delay: expected a delay >= 0"):
        bad.validate()
    bad = dataclasses.replace(s, processors={"default": Processor("default", "no")})
    with pytest.raises(SkeletonError, match=r"processors\.default\.preemptive: expected true"):
        bad.validate()
    bad = dataclasses.replace(s, processors={"cpu": Processor("cpu")})
    with pytest.raises(SkeletonError, match=r"processors\.cpu: no task runs on processor"):
        bad.validate()
    bad = dataclasses.replace(s, network_delay=F(-1))
    with pytest.raises(SkeletonError, match=r"network\.delay: expected a delay >= 0"):
        bad.validate()


WITH_KEYS = (BASE + "  S: {duration: 2, inputs: [b], outputs: [c]}\n"
             "  T: {duration: 1, inputs: [c]}\n"
             "processors:\n  can0: {preemptive: false}\n  default: {preemptive: true}\n"
             "network: {delay: 0.2}\n"
             "links:\n  - {from: 'W:a', to: 'R:a', protocol: ASYN/SYN}\n"
             "  - {from: 'S:c', to: 'T:c', protocol: SYN/ASYN, delay: '7/3'}\n")


def test_read_as_written(tmp_path):
    f = tmp_path / "s.yaml"
    f.write_text(WITH_KEYS.replace("outputs: [a]", "outputs: [a, b]") +
                 "  - {from: 'W:b', to: 'S:b', protocol: ASYN/ASYN, delay: 0}\n")
    s = load_skeleton(f)
    assert s.processors == {"can0": Processor("can0", False),
                            "default": Processor("default", True)}
    assert s.network_delay == F(1, 5)  # 0.2 exactly, as written
    assert [x.delay for x in s.links] == [None, F(7, 3), 0]


def test_round_trip_through_every_skeleton_writer(tmp_path):
    f = tmp_path / "s.yaml"
    f.write_text(WITH_KEYS.replace("outputs: [a]", "outputs: [a, b]") +
                 "  - {from: 'W:b', to: 'S:b', protocol: ASYN/ASYN, delay: 0}\n")
    s = load_skeleton(f)
    for suffix in (".yaml", ".json"):
        copy = load_skeleton(dump_skeleton(s, tmp_path / f"copy{suffix}"))
        assert copy == s and copy.processors == s.processors
        assert [x.delay for x in copy.links] == [None, F(7, 3), 0]
    data = json.loads((tmp_path / "copy.json").read_text())
    assert data["processors"] == {"can0": {"preemptive": False},
                                  "default": {"preemptive": True}}
    assert data["network"] == {"delay": "1/5"}
    assert [x.get("delay") for x in data["links"]] == [None, "7/3", 0]
    # `tegraph convert` writes the same skeleton file, YAML to JSON and back.
    runner = CliRunner()
    out = tmp_path / "converted.json"
    result = runner.invoke(app, ["convert", str(f), str(out)])
    assert result.exit_code == 0, result.output
    back = tmp_path / "back.yaml"
    assert runner.invoke(app, ["convert", str(out), str(back)]).exit_code == 0
    assert load_skeleton(back) == s


def test_without_the_keys_nothing_is_written_for_them(tmp_path):
    s = load_skeleton(dump_skeleton(Skeleton.from_dict({"tasks": {"A": {"duration": 1}}}),
                                    tmp_path / "a.json"))
    assert (s.processors, s.network_delay) == ({}, None)
    assert set(json.loads((tmp_path / "a.json").read_text())) == {"name", "unit", "tasks"}


def test_restricted_keeps_the_platform_of_its_tasks():
    s = Skeleton.from_dict({"network": {"delay": 1}, "processors": {
        "p": {"preemptive": False}, "q": {}}, "tasks": {
        "A": {"duration": 1, "processor": "p"}, "B": {"duration": 1, "processor": "q"}}})
    part = s.restricted_to(["A"])
    assert part.processors == {"p": Processor("p", False)} and part.network_delay == 1
    part.validate()


def test_a_chain_entry_that_is_no_task_name(tmp_path):
    # The other chain refusals of §1 (unknown task, twice, no link, empty, not a list)
    # are tests/tegraph/design/rules/test_rules.py::test_chain_refusals.
    err = refused(tmp_path, BASE +
                  "links:\n  - {from: 'W:a', to: 'R:a', protocol: ASYN/SYN}\n"
                  "chains:\n  - [W, [R]]\n")
    assert err.where == "chains[0][1]" and "expected a task name" in err.reason
