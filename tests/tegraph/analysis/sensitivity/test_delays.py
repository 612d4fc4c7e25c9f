"""`tegraph sensitivity` varying a communication delay (spec §4d): ``network.delay`` and
``links[i].delay``, with the values derived by hand from spec §2's places and checked
against the analysis of the skeleton rebuilt at points.
"""

from __future__ import annotations

import json
import subprocess
import sys
from fractions import Fraction as F
from pathlib import Path

import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph import Skeleton
from tegraph import sensitivity as _sensitivity
from tegraph.analysis.analyze import analyze_skeleton
from tegraph.analysis.sensitivity.parameters import parse_vary, skeleton_at
from tegraph.errors import InputError
from tegraph.report import render_text, to_json

REPO = Path(__file__).resolve().parents[4]


def loop(network=1, own=0, *, same_processor=False) -> dict:
    """A (duration 1, period 10, on p) writes x (ASYN/SYN, links[0]) and z (SYN/ASYN,
    links[1]) to B (duration 2, on q; on p too with ``same_processor``).

    Spec §2's places: A's chain A.activate -> A.compute -(1)-> A.write:x -> A.write:z
    and its return A.write:z -> A.activate (1 token); B's chain B.read:x -> B.read:z ->
    B.compute and its return B.compute -(2)-> B.read:x (1 token); links[0] the place
    A.write:x -> B.read:x, links[1] the request place B.read:z -> A.write:z, each holding
    its delay (§4d: links[0] takes network.delay δ, crossing p -> q; links[1] its own e).
    The circuits: the clock's self-loop, 10; A's own chain, 1; B's own chain, 2; and
    A.activate -> A.compute -> A.write:x -> B.read:x -> B.read:z -> A.write:z -> A.activate,
    one token, 1 + δ + e. So A's group runs at max(10, 1 + δ + e): it keeps its clock's
    pace exactly while 1 + δ + e <= 10, and then activation k (released at 10k) ends at
    A.write:z(k) = 10k + 1 + δ + e <= 10(k + 1): no overrun. Past it, the circuit is
    slower than the clock and the activation place grows.
    """
    tasks = {"A": {"duration": 1, "period": 10, "outputs": ["x", "z"], "processor": "p"},
             "B": {"duration": 2, "inputs": ["x", "z"],
                   "processor": "p" if same_processor else "q"}}
    out: dict = {"name": "loop", "tasks": tasks,
                 "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"},
                           {"from": "A:z", "to": "B:z", "protocol": "SYN/ASYN"}]}
    if network is not None:
        out["network"] = {"delay": network}
    if own is not None:
        out["links"][1]["delay"] = own
    return out


def sk(**kwargs) -> Skeleton:
    return Skeleton.from_dict(loop(**kwargs))


def test_network_delay_margin_and_formula_by_hand():
    # 1 + δ + 0 <= 10: δ in [0, 9] (the class docstring of ``loop``); the formula
    # Max(10, delta_net + 1) (the circuits 1 and 2 never bind: 1 + δ >= 1, and 2 <= 10).
    r = _sensitivity(sk(), ["network.delay"], processors=False)
    m = r.margins["network.delay"]
    assert (m.nominal_consistent, m.low, m.high) == (True, 0, 9)
    assert all(c.agrees for c in m.checks) and m.checks
    (f,) = r.formulas
    d = sympy.Symbol("delta_net", nonnegative=True)
    assert sympy.simplify(f.expression() - sympy.Max(10, d + 1)) == 0


def test_a_link_s_own_delay_and_both_together():
    # links[1] alone, δ = 1: 1 + 1 + e <= 10, e in [0, 8]; together the circuit holds
    # both: Max(10, delta_net + delta_links_1 + 1).
    r = _sensitivity(sk(), ["links[1].delay", "network.delay"], processors=False)
    m = r.margins["links[1].delay"]
    assert (m.low, m.high) == (0, 8)
    assert r.margins["network.delay"].high == 9 - 0
    (f,) = r.formulas
    d, e = sympy.Symbol("delta_net", nonnegative=True), sympy.Symbol("delta_links_1",
                                                                      nonnegative=True)
    assert sympy.simplify(f.expression() - sympy.Max(10, d + e + 1)) == 0


def test_on_processors_the_same_margin_by_the_schedule():
    # A alone on p, B alone on q: each job starts at its release, so the schedule is
    # the (max,+) one and the margin on processors is the same [0, 9]. The part has two
    # processors: no levels, the affine-time walk of the schedule decides it.
    r = _sensitivity(sk(), ["network.delay"], formulas=False)
    m = r.margins["network.delay"]
    assert m.semantics == "processors" and m.exact
    assert (m.low, m.high) == (0, 9)
    # The end is the per-task one (the walk stops there), checked by the analysis at it
    # and just beyond.
    checks = m.checks + m.per_task.checks
    assert all(c.agrees for c in checks) and checks


def test_one_processor_a_link_s_own_delay_on_processors():
    # Both on p (links[0] crosses nothing: no network delay; δ = 0): A runs 0-1 and is
    # the only task of its clock; B, released at its reads 1 + 0, runs 1-3 (it preempts
    # nothing: A is done). A.write:z waits for B.read:z + e = 1 + e: activation k ends at
    # 10k + 1 + e, within its period while e <= 9; past it the group is slower than its
    # clock. On processors: [0, 9], as with a processor per task.
    r = _sensitivity(sk(same_processor=True), ["links[1].delay"], formulas=False)
    m = r.margins["links[1].delay"]
    assert (m.low, m.high, m.per_task.high) == (0, 9, 9)
    assert all(c.agrees for c in m.checks)


def test_no_circuit_through_the_delay_no_bound():
    # A -> B ASYN/SYN only (the brief's first shape): the link place A.write:x -> B.read:x
    # lies on no circuit (nothing goes back from B to A), so the group's period is 10
    # whatever the delay and B's reads wait longer but never pile up: [0, ∞).
    data = loop()
    data["tasks"]["A"]["outputs"] = ["x"]
    data["tasks"]["B"]["inputs"] = ["x"]
    data["links"] = data["links"][:1]
    r = _sensitivity(Skeleton.from_dict(data), ["network.delay"])
    m = r.margins["network.delay"]
    assert (m.low, m.high, m.per_task.high) == (0, None, None)
    assert r.formulas[0].expression() == 10


def test_only_a_declared_delay_is_varied():
    cases = [
        (sk(network=None), "network.delay", "network.delay is not declared"),
        (sk(), "links[0].delay", "links[0] (A:x -> B:x (ASYN/SYN)) declares no delay "
                                 "(it takes network.delay: vary network.delay)"),
        (sk(), "links[2].delay", "the file has 2 links"),
        (sk(), "links[x].delay", "expected TASK.duration, CLOCK.period, links[i].delay"),
    ]
    for skeleton, name, words in cases:
        with pytest.raises(InputError) as info:
            parse_vary(skeleton, ["A.duration", name])
        assert info.value.where == "vary[1]" and words in str(info.value)
    rendezvous = loop()
    rendezvous["links"][1] = {"from": "A:z", "to": "B:z", "protocol": "SYN/SYN", "delay": 0}
    with pytest.raises(InputError, match="rendezvous"):
        parse_vary(Skeleton.from_dict(rendezvous), ["links[1].delay"])
    crossing = loop(network=0)
    crossing["links"][1] = {"from": "A:z", "to": "B:z", "protocol": "SYN/SYN"}
    with pytest.raises(InputError, match=r"links\[1\].*rendezvous between two processors"):
        parse_vary(Skeleton.from_dict(crossing), ["network.delay"])
    (p,) = parse_vary(sk(), ["links[1].delay=0..5/2"])
    assert (p.kind, p.low, p.high, p.low_open, p.symbol) == ("delay", 0, F(5, 2), False,
                                                             "delta_links_1")


def test_the_chain_s_first_use_at_the_delay_s_margin_ends():
    # The chain A -> B follows links[0] (ASYN/SYN, δ). A samples at its start 10k (no
    # unlinked input); B reads x blocking at B.read:x(k) = A.write:x(k) + δ = 10k + 1 + δ
    # (B's previous job ended long before), z after it (at the same instant: nothing holds
    # it), and runs alone on q, so its job is 10k + 1 + δ to 10k + 3 + δ, its output (no
    # output port: its end). First use 3 + δ: 4 at the nominal δ = 1, 3 at the margin's
    # low end 0, 12 at its high end 9: each evaluated there, not taken from the nominal.
    data = loop()
    data["chains"] = [["A", "B"]]
    for processors in (True, False):
        r = _sensitivity(Skeleton.from_dict(data), ["network.delay"], formulas=False,
                         processors=processors)
        (c,) = r.chains
        low, high = c.margins["network.delay"]
        assert (c.nominal.first_use, low.first_use, high.first_use) == (4, 3, 12)


def test_an_asyn_asyn_delay_moves_no_period():
    # links[0] ASYN/ASYN with its own delay: no place (§2), so no period depends on it
    # and its margin is its whole range, on processors too.
    data = {"name": "aa", "tasks": {
        "A": {"duration": 1, "period": 10, "outputs": ["x"], "processor": "p"},
        "B": {"duration": 1, "period": 10, "inputs": ["x"], "processor": "q"}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/ASYN", "delay": 5}]}
    r = _sensitivity(Skeleton.from_dict(data), ["links[0].delay"])
    m = r.margins["links[0].delay"]
    assert (m.low, m.high, m.groups) == (0, None, [])
    assert [f.parameters for f in r.formulas] == [[], []]


def consistent(skeleton: Skeleton, processors: bool) -> bool:
    report = analyze_skeleton(skeleton, semiflow_max_places=0, processors=processors)
    return bool(report.live and report.consistent
                and (not processors or report.schedulable))


@settings(max_examples=12, deadline=None)
@given(network=st.fractions(0, 8, max_denominator=7), own=st.fractions(0, 1, max_denominator=5),
       d_b=st.integers(0, 3), processors=st.booleans())
def test_margin_equals_a_scan_of_rebuilt_skeletons(network, own, d_b, processors):
    # The margin found, against the analysis of the skeleton rebuilt at the ends and at
    # rational points just inside and just outside them.
    data = loop(network=str(network), own=str(own))
    data["tasks"]["B"]["duration"] = d_b
    skeleton = Skeleton.from_dict(data)
    params = parse_vary(skeleton, ["network.delay"])
    r = _sensitivity(skeleton, ["network.delay"], formulas=False, verify=False,
                     processors=processors)
    m = r.margins["network.delay"]
    assert m.nominal_consistent and m.exact
    eps = F(1, 997)
    at = lambda v: consistent(skeleton_at(skeleton, params, {0: v}), processors)  # noqa: E731
    assert at(m.low) and at(m.parameter.nominal)
    assert m.high is not None
    assert at(m.high) and at(m.high - eps) and at((m.low + m.high) / 2)
    assert not at(m.high + eps)
    # Hand: B's own circuit 2·... never binds here (d_b <= 3 < 10), so the end is 9 - e.
    assert m.high == 9 - own


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "tegraph.cli", *args], capture_output=True,
                          text=True, timeout=300, cwd=REPO)


def test_cli_varies_the_network_delay(tmp_path):
    path = tmp_path / "loop.json"
    data = loop()
    data["unit"] = "ms"
    path.write_text(json.dumps(data))
    out = run("sensitivity", str(path), "--vary", "network.delay")
    assert out.returncode == 0, out.stderr
    text = out.stdout
    assert "delta_net" in text and "network.delay" in text
    row = next(line for line in text.splitlines() if line.strip().startswith("delta_net"))
    assert "[0, 9]" in row or "0 .. 9" in row or "[0, 9" in row, row
    assert "ms" in text
    doc = json.loads(run("sensitivity", str(path), "--vary", "network.delay", "--json").stdout)
    assert doc["margins"]["network.delay"]["high"] == "9"
    refused = run("sensitivity", str(path), "--vary", "links[0].delay")
    assert refused.returncode == 2 and "Traceback" not in refused.stderr
    assert "--vary[0]" in refused.stderr and "declares no delay" in refused.stderr


def test_render_text_names_the_delay():
    r = _sensitivity(sk(), ["network.delay"], processors=False)
    assert "delta_net = network.delay" in render_text(r)


def test_json_document_of_a_delay_follows_its_schema():
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads((REPO / "docs" / "report.schema.json").read_text())
    for processors in (True, False):
        r = _sensitivity(sk(), ["network.delay", "links[1].delay=0..8"], processors=processors)
        doc = json.loads(to_json(r))
        jsonschema.validate(doc, schema)
        kinds = [p["kind"] for p in doc["parameters"]]
        assert kinds == ["network-delay", "delay"]
        assert (doc["margins"]["network.delay"]["high"],
                doc["margins"]["links[1].delay"]["high"]) == ("9", "8")
