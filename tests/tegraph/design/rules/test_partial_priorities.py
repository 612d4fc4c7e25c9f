"""A partial declaration of priorities is said at the top of the report and is a Rule 4 error.

The contract (spec §4b) is all or none per processor: where only some tasks of a
processor declare a priority, every task there runs at the rate-monotonic proposal,
and the declared ones are replaced. The report says which, and why; ``rules`` makes
it an error whose machine-applicable change completes the declaration.
"""

from __future__ import annotations

import json

from typer.testing import CliRunner

from tegraph import analyze
from tegraph.cli import app
from tegraph.design.rules import FindingKind, apply_change, check_rules
from tegraph.design.rules.priorities import completion, proposed_priorities
from tegraph.model.skeleton import Skeleton
from tegraph.model.structure import Structure
from tegraph.report import render_text

# A quadrotor's shape (issue: declared priorities replaced silently): imu 1 ms, the
# rate loop 2.5 ms with its mixer, the position loop 20 ms, the GPS 100 ms, a clockless
# logger, on one CPU; four of the six declare a priority.
QUAD = {"tasks": {
    "imu": {"duration": 0.1, "period": 1, "priority": 50},
    "rate": {"duration": 0.5, "period": 2.5, "outputs": ["u"], "priority": 40},
    "mixer": {"duration": 0.1, "inputs": ["u"]},
    "pos": {"duration": 2, "period": 20, "priority": 30},
    "gps": {"duration": 5, "period": 100},
    "logger": {"duration": 1, "priority": 1}},
    "links": [{"from": "rate:u", "to": "mixer:u", "protocol": "ASYN/SYN"}]}


def quad() -> Skeleton:
    return Skeleton.from_dict(QUAD)


def test_the_report_says_at_its_top_which_were_replaced():
    r = analyze(quad(), margins_max_tasks=0)
    # Rate-monotonic, by hand: imu 1 ms -> 5, {rate, mixer} 2.5 ms -> 4, pos 20 ms -> 3,
    # gps 100 ms -> 2, logger (no clock) -> 1.
    (p,) = r.platform.processors
    assert p.priorities == {"imu": 5, "rate": 4, "mixer": 4, "pos": 3, "gps": 2, "logger": 1}
    assert p.replaced == {"imu": 50, "rate": 40, "pos": 30, "logger": 1}
    lines = render_text(r).splitlines()
    top = next(i for i, line in enumerate(lines) if line.startswith("priorities:"))
    assert top <= 5  # among the headline lines, before any table
    assert ("REPLACED on default: 4 of its 6 tasks declare a priority (mixer, gps do not)"
            in lines[top])
    assert "imu 50 -> 5, rate 40 -> 4, pos 30 -> 3, logger 1 -> 1" in lines[top]
    assert "all declared or none (spec §4b)" in lines[top]
    doc = r.to_dict()
    assert doc["processors"][0]["replaced_priorities"] == {"imu": 50, "rate": 40, "pos": 30,
                                                            "logger": 1}


def test_nothing_is_said_when_the_declaration_is_whole_or_empty():
    full = json.loads(json.dumps(QUAD))
    full["tasks"]["mixer"]["priority"] = 40
    full["tasks"]["gps"]["priority"] = 20
    for data in (full, {"tasks": {t: {k: v for k, v in body.items() if k != "priority"}
                                  for t, body in QUAD["tasks"].items()},
                        "links": QUAD["links"]}):
        r = analyze(Skeleton.from_dict(data), margins_max_tasks=0)
        assert r.platform.replaced == [] and "REPLACED" not in render_text(r)
        assert r.to_dict()["processors"][0]["replaced_priorities"] == {}
        assert not [f for f in r.design.rules if f.kind is FindingKind.RULE4_PARTIAL]


def test_rules_make_it_an_error_whose_change_completes_it():
    sk = quad()
    (f,) = [f for f in check_rules(sk, processors=False) if f.rule == 4]
    assert (f.kind, f.severity, f.tasks) == (FindingKind.RULE4_PARTIAL, "error",
                                             ("mixer", "gps"))
    # mixer joins its group's declared 40 (one priority per group); gps (100 ms) goes
    # between pos's 30 and logger's 1, just below pos: 29.
    assert f.change is not None and f.change.priorities == (("mixer", 40), ("gps", 29))
    assert f.change.to_dict()["priorities"] == [{"task": "mixer", "priority": 40},
                                                {"task": "gps", "priority": 29}]
    fixed = apply_change(sk, f.change)
    assert {t: x.priority for t, x in fixed.tasks.items()} == {
        "imu": 50, "rate": 40, "mixer": 40, "pos": 30, "gps": 29, "logger": 1}
    assert [g for g in check_rules(fixed, processors=False) if g.rule == 4] == []
    r = analyze(fixed, margins_max_tasks=0)
    assert r.platform.processors[0].priority_source == "declared"


def test_no_room_between_the_declared_ones_declares_the_proposal():
    # A (5 ms) declares 2, C (20 ms) declares 3: B (10 ms) belongs between them in
    # rate-monotonic order, and no integer lies below 2 and above 3. The change is the
    # proposal for the whole processor: A 3, B 2, C 1.
    sk = Skeleton.from_dict({"tasks": {
        "A": {"duration": 1, "period": 5, "priority": 2},
        "B": {"duration": 1, "period": 10},
        "C": {"duration": 1, "period": 20, "priority": 3}}})
    values, kept = completion(sk, Structure.of(sk), list(sk.tasks), proposed_priorities(sk))
    assert (values, kept) == ({"A": 3, "B": 2, "C": 1}, False)
    (f,) = [f for f in check_rules(sk, processors=False) if f.kind is FindingKind.RULE4_PARTIAL]
    assert "declare the proposal for the whole processor" in f.advice
    assert f.change is not None and f.change.priorities == (("A", 3), ("B", 2), ("C", 1))


def test_groups_above_below_and_the_automaton():
    # FAST (1 ms) and SLOW (50 ms) declare none; MID (10 ms) declares 7; RTA none:
    # FAST above MID (8), SLOW below (6), the automaton above all (9).
    sk = Skeleton.from_dict({"tasks": {
        "FAST": {"duration": 0, "period": 1}, "MID": {"duration": 1, "period": 10, "priority": 7},
        "SLOW": {"duration": 1, "period": 50}, "RTA": {"duration": 0}}})
    values, kept = completion(sk, Structure.of(sk), list(sk.tasks), proposed_priorities(sk))
    assert (values, kept) == ({"FAST": 8, "SLOW": 6, "RTA": 9}, True)


def test_the_command_line_rules_exit_1(tmp_path):
    f = tmp_path / "quad.json"
    f.write_text(json.dumps(QUAD))
    result = CliRunner().invoke(app, ["rules", str(f)])
    assert result.exit_code == 1, result.output
    assert "all declared or none" in result.output and "mixer: 40, gps: 29" in result.output
