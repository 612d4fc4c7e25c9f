"""The benchmark generator's ``--non-preemptive`` and ``--delay`` (spec §4d): the files it
writes are accepted, declare what was asked, and are unchanged without the options."""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
from fractions import Fraction

from tegraph.io import load_skeleton
from tegraph.model.elements import Protocol
from tests.paths import REPO

SCRIPT = REPO / "benchmarks" / "generate_skeleton.py"
_spec = importlib.util.spec_from_file_location("generate_skeleton", SCRIPT)
assert _spec is not None and _spec.loader is not None
generate_skeleton = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(generate_skeleton)


def written(tmp_path, *args: str) -> tuple[subprocess.CompletedProcess, object]:
    out = tmp_path / ("-".join(args).replace("/", "_") + ".json")
    done = subprocess.run([sys.executable, str(SCRIPT), *args, "-o", str(out)],
                          capture_output=True, text=True)
    return done, out


def test_without_the_options_the_file_is_the_generated_document_alone(tmp_path):
    # The file is json.dumps(indent=1) of generate() then spread(), as the generator wrote
    # it before the options: no `processors:` or `network:` key, no link delay.
    done, out = written(tmp_path, "400", "--processors", "3", "--seed", "2")
    assert done.returncode == 0
    doc = generate_skeleton.spread(generate_skeleton.generate(400, seed=2), 3)
    assert out.read_text() == json.dumps(doc, indent=1)
    assert "processors" not in doc and "network" not in doc
    assert not any("delay" in link for link in doc["links"])


def test_non_preemptive_processors_and_a_network_delay(tmp_path):
    done, out = written(tmp_path, "400", "--processors", "3", "--seed", "2",
                        "--non-preemptive", "2", "--delay", "1/10")
    assert done.returncode == 0, done.stderr
    sk = load_skeleton(out)  # accepted by the checks of §4d
    plain = load_skeleton(written(tmp_path, "400", "--processors", "3", "--seed", "2")[1])
    assert sk.tasks == plain.tasks  # the same tasks on the same processors
    assert {name: p.preemptive for name, p in sk.processors.items()} == {
        "cpu0": False, "cpu1": False}  # cpu2 is not declared: preemptive, the default
    assert sk.network_delay == Fraction(1, 10)
    crossing = 0
    for link, before in zip(sk.links, plain.links, strict=True):
        assert (link.writer, link.reader, link.protocol) == (
            before.writer, before.reader, before.protocol)
        crosses = sk.tasks[link.writer[0]].runs_on != sk.tasks[link.reader[0]].runs_on
        crossing += crosses
        # Only a rendezvous across processors declares a delay of its own, 0 (§4d: a
        # SYN/SYN link cannot be delayed); every other link takes the network's across
        # processors and none within one.
        if link.protocol is Protocol.SYN_SYN and crosses:
            assert link.delay == 0
        else:
            assert link.delay is None
            assert link.effective_delay(crosses, sk.network_delay) == (
                Fraction(1, 10) if crosses else 0)
    assert crossing > 0  # round robin over 3 processors splits most groups


def test_the_first_processors_in_number_order(tmp_path):
    # cpu10 and cpu11 come after cpu9, not after cpu1 as in string order.
    done, out = written(tmp_path, "200", "--processors", "12", "--non-preemptive", "10")
    assert done.returncode == 0, done.stderr
    assert sorted(load_skeleton(out).processors) == sorted(f"cpu{i}" for i in range(10))


def test_one_processor_and_too_many(tmp_path):
    done, out = written(tmp_path, "50", "--non-preemptive", "1")
    assert done.returncode == 0, done.stderr
    assert [p.name for p in load_skeleton(out).processors.values() if not p.preemptive] == [
        "default"]
    done, out = written(tmp_path, "50", "--processors", "2", "--non-preemptive", "3")
    assert done.returncode == 2 and "the tasks run on 2 processor(s)" in done.stderr
    assert not out.exists()
