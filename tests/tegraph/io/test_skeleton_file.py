"""Reading, checking and writing skeleton files (spec §1)."""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph import SkeletonError, load_skeleton
from tegraph.io.skeleton_file import dump_skeleton
from tegraph.model.skeleton import Clock, Link, Protocol, Skeleton, Task


def y(*lines: str) -> str:
    """A YAML text, one argument per line (so line numbers are easy to count)."""
    return "\n".join(lines) + "\n"


# A writer A (input w, output x) and a reader B (input x, output y); links start at line 4.
TWO = ("tasks:", "  A: {duration: 1, inputs: [w], outputs: [x]}",
       "  B: {duration: 2, inputs: [x], outputs: [y]}", "links:")


def link(src: str, dst: str, protocol: str = "ASYN/SYN") -> tuple[str, ...]:
    return (f"  - from: {src}", f"    to: {dst}", f"    protocol: {protocol}")


# (YAML text, key path, wording the message must hold, 1-based line or None)
REFUSALS = [
    # -- a key is unknown (top, clock, task, link) -----------------------------------
    pytest.param(y("tasks:", "  A: {duration: 1}", "linkz: []"), "linkz",
                 "unknown key 'linkz' (did you mean 'links'?); expected one of: name, unit, "
                 "clocks, tasks, links, threads", 3, id="unknown-top-key"),
    pytest.param(y("clocks:", "  rtc: {period: 10, offset: 1}", "tasks:",
                   "  A: {duration: 1, clock: rtc}"), "clocks.rtc.offset",
                 "unknown key 'offset'; expected one of: period, phase", 2,
                 id="unknown-clock-key"),
    pytest.param(y("tasks:", "  A:", "    duration: 1", "    wcet: 3"), "tasks.A.wcet",
                 "unknown key 'wcet'; expected one of: duration, clock, period, phase, "
                 "inputs, outputs", 4, id="unknown-task-key"),
    pytest.param(y(*TWO, *link("A:x", "B:x"), "    latency: 1"), "links[0].latency",
                 "unknown key 'latency'; expected one of: from, to, protocol, delay", 8,
                 id="unknown-link-key"),
    # -- a task, port or clock named by a link, a thread or `clock:` does not exist ---
    pytest.param(y(*TWO, *link("C:x", "B:x")), "links[0].from",
                 "no task 'C'; expected one of the tasks (A, B)", 5, id="link-unknown-task"),
    pytest.param(y(*TWO, *link("A:x", "B:z")), "links[0].to",
                 "task 'B' has no port 'z'; expected one of its input ports (x)", 6,
                 id="link-unknown-port"),
    pytest.param(y("tasks:", "  A: {duration: 1}", "threads:", "  - [A, C]"), "threads[0][1]",
                 "no task 'C'; expected one of the tasks (A)", 4, id="thread-unknown-task"),
    pytest.param(y("tasks:", "  A: {duration: 1, clock: rtc}"), "tasks.A.clock",
                 "no clock 'rtc'; expected a clock declared under clocks (none)", 2,
                 id="unknown-clock"),
    # -- a port linked in the wrong direction ----------------------------------------
    pytest.param(y(*TWO, *link("B:x", "A:w")), "links[0].from",
                 "B:x is an input port, linked in the wrong direction; expected an output port",
                 5, id="from-is-an-input"),
    pytest.param(y(*TWO, *link("A:x", "B:y")), "links[0].to",
                 "B:y is an output port, linked in the wrong direction; expected an input port",
                 6, id="to-is-an-output"),
    # -- an input port with two writers ---------------------------------------------
    pytest.param(y("tasks:", "  A: {duration: 1, outputs: [x]}", "  C: {duration: 1, outputs: [z]}",
                   "  B: {duration: 2, inputs: [x]}", "links:", *link("A:x", "B:x"),
                   *link("C:z", "B:x")), "links[1].to",
                 "the input port B:x already has a writer (links[0]: A:x -> B:x (ASYN/SYN)); "
                 "expected one writer per input port", 10, id="two-writers"),
    # -- a link joining a task to itself ---------------------------------------------
    pytest.param(y(*TWO, *link("A:x", "A:w")), "links[0]",
                 "the link joins task 'A' to itself; expected a link between two different tasks",
                 5, id="self-link"),
    # -- a port name repeated within a task -----------------------------------------
    pytest.param(y("tasks:", "  A: {duration: 1, inputs: [p], outputs: [p]}"),
                 "tasks.A.outputs[0]", "the port name 'p' is already used at tasks.A.inputs[0]; "
                 "expected port names unique within a task (inputs and outputs together)", 2,
                 id="port-in-inputs-and-outputs"),
    pytest.param(y("tasks:", "  A:", "    duration: 1", "    inputs:", "      - p", "      - q",
                   "      - p"), "tasks.A.inputs[2]", "already used at tasks.A.inputs[0]", 7,
                 id="port-twice-in-inputs"),
    # -- negative duration or phase, non-positive period -----------------------------
    pytest.param(y("tasks:", "  A: {duration: -1}"), "tasks.A.duration",
                 "expected a duration >= 0, got -1", 2, id="negative-duration"),
    pytest.param(y("clocks:", "  rtc:", "    period: 10", "    phase: -0.5", "tasks:",
                   "  A: {duration: 1, clock: rtc}"), "clocks.rtc.phase",
                 "expected a phase >= 0, got -0.5", 4, id="negative-clock-phase"),
    pytest.param(y("tasks:", "  A: {duration: 1, period: 5, phase: -1}"), "tasks.A.phase",
                 "expected a phase >= 0, got -1", 2, id="negative-task-phase"),
    pytest.param(y("clocks:", "  rtc: {period: 0}", "tasks:", "  A: {duration: 1, clock: rtc}"),
                 "clocks.rtc.period", "expected a period > 0, got 0", 2, id="zero-clock-period"),
    pytest.param(y("tasks:", "  A:", "    duration: 1", "    period: '-7/3'"), "tasks.A.period",
                 "expected a period > 0, got -7/3", 4, id="negative-task-period"),
    # -- both `clock` and `period`; `phase` without `period` -------------------------
    pytest.param(y("clocks:", "  rtc: {period: 10}", "tasks:", "  A:", "    duration: 1",
                   "    clock: rtc", "    period: 10"), "tasks.A.period",
                 "task 'A' has both 'clock' and 'period'; expected one of them", 7,
                 id="clock-and-period"),
    pytest.param(y("tasks:", "  A: {duration: 1, phase: 2}"), "tasks.A.phase",
                 "'phase' goes with 'period'; expected 'period' too", 2,
                 id="phase-without-period"),
    # -- a task in two threads, or twice in one --------------------------------------
    pytest.param(y("tasks:", "  A: {duration: 1}", "  B: {duration: 1}", "threads:", "  - [A, B]",
                   "  - [A]"), "threads[1][0]",
                 "the task 'A' is in two threads (also at threads[0][0]); expected each task in "
                 "at most one thread, once", 6, id="task-in-two-threads"),
    pytest.param(y("tasks:", "  A: {duration: 1}", "  B: {duration: 1}", "threads:",
                   "  - [A, B, A]"), "threads[0][2]",
                 "the task 'A' is again in this thread (also at threads[0][0])", 5,
                 id="task-twice-in-a-thread"),
    # -- an unknown protocol ---------------------------------------------------------
    pytest.param(y(*TWO, *link("A:x", "B:x", "SYN/FOO")), "links[0].protocol",
                 "unknown protocol 'SYN/FOO'; expected one of ASYN/ASYN, ASYN/SYN, SYN/ASYN, "
                 "SYN/SYN (case-insensitive, '-' may stand for '/')", 7, id="unknown-protocol"),
    # -- a time value that is not a finite number ------------------------------------
    pytest.param(y("tasks:", "  A: {duration: abc}"), "tasks.A.duration",
                 'expected a duration >= 0: a finite number such as 2, 0.5 or "7/3", '
                 "got the text 'abc'", 2, id="time-is-text"),
    pytest.param(y("tasks:", "  A: {duration: .inf}"), "tasks.A.duration",
                 "a finite number such as 2, 0.5 or \"7/3\", got the text '.inf'", 2,
                 id="time-is-infinity"),
    pytest.param(y("clocks:", "  rtc: {period: '7/0'}", "tasks:", "  A: {duration: 1}"),
                 "clocks.rtc.period", "expected a period > 0: a finite number such as 2, 0.5 or "
                 "\"7/3\", got '7/0', which has a zero denominator", 2, id="zero-denominator"),
    pytest.param(y("tasks:", "  A: {duration: true}"), "tasks.A.duration",
                 "a finite number such as 2, 0.5 or \"7/3\", got the boolean true", 2,
                 id="time-is-boolean"),
    pytest.param(y("tasks:", "  A: {duration: .nan}"), "tasks.A.duration",
                 "a finite number such as 2, 0.5 or \"7/3\", got the text '.nan'", 2,
                 id="time-is-nan"),
    pytest.param(y("tasks:", "  A: {duration: 1, period: 1e999999999}"), "tasks.A.period",
                 "'1e999999999' has 1,000,000,000 digits; at most 4,300 are accepted", 2,
                 id="time-exponent-huge"),
    pytest.param(y("tasks:", "  A: {duration: 1:30}"), "tasks.A.duration",
                 "a finite number such as 2, 0.5 or \"7/3\", got the text '1:30'", 2,
                 id="time-is-sexagesimal"),
    pytest.param(y("tasks:", "  A:", "    duration:"), "tasks.A.duration",
                 "a finite number such as 2, 0.5 or \"7/3\", got nothing (null)", 3,
                 id="time-is-null"),
    # -- `tasks` missing, empty or not a mapping -------------------------------------
    pytest.param(y("name: plant"), "tasks",
                 "missing; expected a mapping from task names to tasks (at least one)", None,
                 id="tasks-missing"),
    pytest.param(y("tasks: {}"), "tasks", "no task; expected at least one task", 1,
                 id="tasks-empty"),
    pytest.param(y("tasks: [A, B]"), "tasks",
                 "expected a mapping from task names to tasks, got a list", 1,
                 id="tasks-is-a-list"),
    pytest.param(y("tasks:"), "tasks",
                 "expected a mapping from task names to tasks, got nothing (null)", 1,
                 id="tasks-is-null"),
    # -- a task or port name holding ':' ---------------------------------------------
    pytest.param(y("tasks:", "  'A:1': {duration: 1}"), "tasks.A:1",
                 "the task name 'A:1' contains ':'; expected a name without ':'", 2,
                 id="colon-in-task-name"),
    pytest.param(y("tasks:", "  A: {duration: 1, inputs: ['p:q']}"), "tasks.A.inputs[0]",
                 "the port name 'p:q' contains ':'; expected a name without ':'", 2,
                 id="colon-in-port-name"),
    # -- a link endpoint not "TASK:PORT" ---------------------------------------------
    pytest.param(y(*TWO, *link("A", "B:x")), "links[0].from",
                 "expected \"TASK:PORT\" such as \"MT1:b\", got 'A'", 5, id="endpoint-no-colon"),
    pytest.param(y(*TWO, *link("A:x", ":x")), "links[0].to",
                 "expected \"TASK:PORT\" such as \"MT1:b\", got ':x'", 6, id="endpoint-no-task"),
    # -- private clocks ---------------------------------------------------------------
    pytest.param(y("clocks:", "  A.clock: {period: 5}", "tasks:", "  A: {duration: 1, period: 10}"),
                 "tasks.A.period", "its private clock 'A.clock' collides with the clock declared "
                 "at clocks.A.clock; expected distinct clock names", 4,
                 id="private-clock-collides"),
    pytest.param(y("tasks:", "  A: {duration: 1, period: 10}",
                   "  B: {duration: 1, clock: A.clock}"),
                 "tasks.B.clock", "'A.clock' is the private clock of another task", 3,
                 id="borrowed-private-clock"),
    # -- wrong types and missing required keys ---------------------------------------
    pytest.param(y("- tasks"), "", "expected a mapping with at least a 'tasks' key, got a list",
                 None, id="document-is-a-list"),
    pytest.param(y("tasks:", "  A: [1, 2]"), "tasks.A",
                 "expected a mapping of task fields (duration, clock, period, phase, inputs, "
                 "outputs, priority, processor), got a list", 2, id="task-is-a-list"),
    pytest.param(y("tasks:", "  A:"), "tasks.A",
                 "expected a mapping of task fields (duration, clock, period, phase, inputs, "
                 "outputs, priority, processor), got nothing (null)", 2, id="task-is-null"),
    pytest.param(y("clocks: [rtc]", "tasks:", "  A: {duration: 1}"), "clocks",
                 "expected a mapping from clock names to clocks, got a list", 1,
                 id="clocks-is-a-list"),
    pytest.param(y("tasks:", "  A: {duration: 1}", "links: {from: 'A:x'}"), "links",
                 "expected a list of links, got a mapping", 3, id="links-is-a-mapping"),
    pytest.param(y("tasks:", "  A: {duration: 1, inputs: x}"), "tasks.A.inputs",
                 "expected a list of port names such as [a, b], got the text 'x'", 2,
                 id="inputs-is-text"),
    pytest.param(y("tasks:", "  A: {duration: 1}", "threads: [A]"), "threads[0]",
                 "expected a list of task names such as [MT1, MT2], got the text 'A'", 3,
                 id="thread-is-text"),
    pytest.param(y("tasks:", "  A: {duration: 1}", "threads: [[]]"), "threads[0]",
                 "an empty thread; expected a list of at least one task", 3, id="empty-thread"),
    pytest.param(y("name: [a]", "tasks:", "  A: {duration: 1}"), "name",
                 "expected a name (a text), got a list", 1, id="name-is-a-list"),
    pytest.param(y("tasks:", "  A: {duration: [1]}"), "tasks.A.duration",
                 "a finite number such as 2, 0.5 or \"7/3\", got a list", 2, id="time-is-a-list"),
    pytest.param(y("tasks:", "  A: {clock: rtc}"), "tasks.A.duration",
                 "missing; expected a duration >= 0 for every task", 2, id="duration-missing"),
    pytest.param(y("clocks:", "  rtc: {phase: 1}", "tasks:", "  A: {duration: 1}"),
                 "clocks.rtc.period", "missing; expected a period > 0 for every clock", 2,
                 id="clock-period-missing"),
    pytest.param(y(*TWO, "  - from: A:x", "    to: B:x"), "links[0].protocol",
                 "missing; expected one of ASYN/ASYN, ASYN/SYN, SYN/ASYN, SYN/SYN in every link",
                 5, id="protocol-missing"),
    # -- duplicate keys (YAML would keep the last one silently) ----------------------
    pytest.param(y("tasks:", "  A: {duration: 1}", "  B: {duration: 2}", "  A: {duration: 3}"),
                 "tasks.A", "duplicate key 'A' (first at line 2); expected each key once", 4,
                 id="duplicate-task"),
    pytest.param(y("tasks:", "  A:", "    duration: 1", "    duration: 2"), "tasks.A.duration",
                 "duplicate key 'duration' (first at line 3)", 4, id="duplicate-field"),
    pytest.param(y("tasks:", "  A: {duration: 1}", "tasks:", "  B: {duration: 1}"), "tasks",
                 "duplicate key 'tasks' (first at line 1)", 3, id="duplicate-top-key"),
    # -- a link appearing twice (whatever its protocol) ------------------------------
    pytest.param(y(*TWO, *link("A:x", "B:x"), *link("A:x", "B:x", "SYN/SYN")), "links[1]",
                 "the same link as links[0] (A:x -> B:x (ASYN/SYN)); expected each link once", 8,
                 id="link-twice"),
    # -- YAML shapes that are no skeleton --------------------------------------------
    pytest.param(y("tasks:", "  ? [A, B]", "  : {duration: 1}"), "tasks",
                 "a key that is a mapping or a list; expected a name", 2, id="complex-key"),
    pytest.param(y("tasks: !!set {A}"), "tasks",
                 "unsupported YAML tag 'tag:yaml.org,2002:set'; expected plain mappings and lists",
                 1, id="set-tag"),
    pytest.param(y("tasks: &t", "  A: {duration: 1}", "  B: *t"), "tasks.B",
                 "a recursive alias; expected a tree of mappings and lists", 3,
                 id="recursive-alias"),
    # -- the file is not valid YAML / empty ------------------------------------------
    pytest.param(y("tasks:", "  A: {duration: 1}", "  B: duration: 2"), "",
                 "not valid YAML: mapping values are not allowed",
                 3, id="invalid-yaml"),
    pytest.param("", "", "the file is empty; expected a skeleton with at least 'tasks'", None,
                 id="empty-file"),
    pytest.param(y("# only a comment", ""), "", "the file is empty", None,
                 id="comments-only"),
]


@pytest.mark.parametrize("text, key_path, wording, line", REFUSALS)
def test_yaml_refusal(tmp_path: Path, text: str, key_path: str, wording: str,
                      line: int | None) -> None:
    path = tmp_path / "plant-42.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(SkeletonError) as info:
        load_skeleton(path)
    err = info.value
    message = str(err)
    assert isinstance(err, ValueError)
    assert err.file == str(path) and message.startswith(str(path))
    assert err.where == key_path
    if key_path:
        assert f": {key_path}: " in message
    assert wording in err.reason
    assert "expected" in err.reason
    assert err.line == line
    if line is not None:
        assert message.startswith(f"{path}:{line}: ")


JSON_REFUSALS = [
    pytest.param('{\n  "tasks": {\n    "A": {"duration": 1},\n    "A": {"duration": 2}\n  }\n}',
                 "tasks.A", "duplicate key 'A' (first at line 3)", 4, id="json-duplicate-key"),
    pytest.param('{\n  "tasks": {\n    "A": {"duration": 1,}\n  }\n}', "",
                 "not valid JSON: Expecting property name enclosed in double quotes", 3,
                 id="invalid-json"),
    pytest.param('{\n  "tasks": {\n    "A": {"duration": NaN}\n  }\n}', "tasks.A.duration",
                 "got NaN", 3, id="json-nan"),
    pytest.param('{"tasks": {"A": {"duration": 1, "period": -Infinity}}}', "tasks.A.period",
                 "got infinity", 1, id="json-infinity"),
    pytest.param('{"tasks": {"A": {"duration": 1e5000}}}', "tasks.A.duration",
                 "'1E+5000' has 5,001 digits; at most 4,300 are accepted", 1,
                 id="json-huge-exponent"),
    pytest.param('{"tasks": {"A": {"duration": 1, "inputs": [true]}}}', "tasks.A.inputs[0]",
                 "expected a port name (a text), got the boolean true", 1, id="json-bool-name"),
    pytest.param("   \n", "", "the file is empty", None, id="json-empty"),
]


@pytest.mark.parametrize("text, key_path, wording, line", JSON_REFUSALS)
def test_json_refusal(tmp_path: Path, text: str, key_path: str, wording: str,
                      line: int | None) -> None:
    path = tmp_path / "plant-42.json"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(SkeletonError) as info:
        load_skeleton(path)
    err = info.value
    assert err.file == str(path) and str(err).startswith(str(path))
    assert err.where == key_path
    assert wording in err.reason and "expected" in err.reason
    assert err.line == line


# YAML 1.1 reads these plain scalars as numbers (0x1A is 26, 0b11 is 3, 1:30 is 90,
# 1__0 is 10, .inf is infinity); the number grammar of docs/skeleton.md has none of
# them, so each is refused at its key path, with the text as written.
OUTSIDE_THE_GRAMMAR = ["0x1A", "-0x1A", "0x_1A", "0b11", "+0b1_1", "0o17", "1:30",
                       "-1:30", "1:30.5", "190:20:30", ".inf", "-.Inf", "+.INF", ".nan",
                       ".NaN", "1__0", "1_", "1_.5"]


@pytest.mark.parametrize("text", OUTSIDE_THE_GRAMMAR)
def test_yaml_numbers_outside_the_grammar_are_refused(tmp_path: Path, text: str) -> None:
    path = tmp_path / "forms.yaml"
    path.write_text(y("tasks:", f"  A: {{duration: 1, period: {text}}}"))
    with pytest.raises(SkeletonError) as info:
        load_skeleton(path)
    err = info.value
    assert (err.file, err.where, err.line) == (str(path), "tasks.A.period", 2)
    assert err.reason == ('expected a period > 0: a finite number such as 2, 0.5 or "7/3", '
                          f"got the text {text!r}")


@pytest.mark.parametrize("text", ["0x1A", "0b11", "1:30", "1__0"])
def test_a_priority_outside_the_grammar_is_refused(tmp_path: Path, text: str) -> None:
    path = tmp_path / "prio.yaml"
    path.write_text(y("tasks:", f"  A: {{duration: 1, period: 10, priority: {text}}}"))
    with pytest.raises(SkeletonError) as info:
        load_skeleton(path)
    assert info.value.where == "tasks.A.priority"
    assert f"got the text {text!r}" in info.value.reason


def test_yaml_numbers_of_the_grammar_are_read_as_written(tmp_path: Path) -> None:
    # Each by hand: 0_10 is ten (an underscore between digits; 010 is ten, not octal
    # eight), +.5 a half, "1." one, 1.5e3 fifteen hundred, 1_000 a thousand.
    path = tmp_path / "forms.yaml"
    path.write_text(y("tasks:", "  A: {duration: 0_10, period: 1_000}",
                      "  B: {duration: +.5}", "  C: {duration: 1.}", "  D: {duration: 1.5e3}"))
    sk = load_skeleton(path)
    assert [t.duration for t in sk.tasks.values()] == [10, Fraction(1, 2), 1, 1500]
    assert sk.clocks["A.clock"].period == 1000


def test_a_name_that_yaml_reads_as_a_number_stays_the_name(tmp_path: Path) -> None:
    path = tmp_path / "names.yaml"
    path.write_text(y("tasks:", "  A: {duration: 1, period: 10, outputs: [0x1A, .inf, 0b11]}",
                      "  B: {duration: 1, inputs: [0x1A]}",
                      "links:", "  - {from: 'A:0x1A', to: 'B:0x1A', protocol: ASYN/SYN}"))
    assert load_skeleton(path).tasks["A"].outputs == ("0x1A", ".inf", "0b11")


def test_the_cli_refuses_a_hexadecimal_period_with_exit_2(tmp_path: Path) -> None:
    from typer.testing import CliRunner

    from tegraph.cli import app

    path = tmp_path / "hex.yaml"
    path.write_text(y("tasks:", "  A: {duration: 1, period: 0x1A}"))
    result = CliRunner().invoke(app, ["cycle-time", str(path)])
    assert result.exit_code == 2
    assert f"{path}:2: tasks.A.period: " in result.output
    assert "got the text '0x1A'" in result.output and "Traceback" not in result.output


def test_missing_file_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "nowhere.yaml"
    with pytest.raises(SkeletonError) as info:
        load_skeleton(path)
    assert str(info.value) == (f"{path}: no such file; expected an existing skeleton file "
                               "(.yaml, .yml or .json)")
    assert info.value.where == "" and info.value.line is None


def test_directory_is_refused(tmp_path: Path) -> None:
    with pytest.raises(SkeletonError, match="is a directory; expected a skeleton file"):
        load_skeleton(tmp_path)


def test_binary_file_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "blob.yaml"
    path.write_bytes(b"tasks:\n  A: {duration: \xff}\n")
    with pytest.raises(SkeletonError) as info:
        load_skeleton(path)
    assert info.value.reason == ("not UTF-8 text (byte 0xff at offset 23); expected a YAML or "
                                 "JSON text file")
    assert info.value.line == 2


# ---------------------------------------------------------------------------- loads


SPEC_EXAMPLE = y(
    "name: fig7b-fixed            # optional; default: the file's stem",
    "unit: us",
    "clocks:",
    "  rtc:",
    "    period: 10",
    "    phase: 0",
    "tasks:",
    "  MT1:",
    "    duration: 2",
    "    clock: rtc",
    "    inputs: [a]",
    "    outputs: [b, c]",
    "  MT2:",
    "    duration: 4",
    "    period: 20",
    "    phase: 0",
    "    inputs: [b]",
    "links:",
    "  - from: MT1:b",
    "    to: MT2:b",
    "    protocol: ASYN/SYN",
    "threads:",
    "  - [MT1, MT2]",
)


def test_spec_example_loads(tmp_path: Path) -> None:
    path = tmp_path / "example.yml"
    path.write_text(SPEC_EXAMPLE)
    sk = load_skeleton(path)
    assert sk == Skeleton(
        name="fig7b-fixed",
        unit="us",
        clocks={"rtc": Clock("rtc", Fraction(10)),
                "MT2.clock": Clock("MT2.clock", Fraction(20), Fraction(0), private=True)},
        tasks={"MT1": Task("MT1", Fraction(2), "rtc", ("a",), ("b", "c")),
               "MT2": Task("MT2", Fraction(4), "MT2.clock", ("b",), ())},
        links=[Link(("MT1", "b"), ("MT2", "b"), Protocol.ASYN_SYN)],
        threads=[("MT1", "MT2")],
    )
    assert sk.source == str(path)


def test_exact_times_from_yaml(tmp_path: Path) -> None:
    path = tmp_path / "exact.yaml"
    path.write_text(y(
        "tasks:",
        "  A: {duration: '7/3', period: 0.1, phase: 2.5e-1}",
        "  B: {duration: 0.30000000000000000001}",  # more digits than a float holds
        "  C: {duration: 1e3}",                     # a string in YAML 1.1
        "  D: {duration: 010}",                     # octal 8 in YAML 1.1; ten as written
        "  E: {duration: 1_000.5}",
        "  F: {duration: ' 5/10 '}",
    ))
    sk = load_skeleton(path)
    assert sk.tasks["A"].duration == Fraction(7, 3)
    assert sk.clocks["A.clock"] == Clock("A.clock", Fraction(1, 10), Fraction(1, 4), private=True)
    assert sk.tasks["B"].duration == Fraction(30000000000000000001, 10**20)
    assert sk.tasks["C"].duration == Fraction(1000)
    assert sk.tasks["D"].duration == Fraction(10)
    assert sk.tasks["E"].duration == Fraction(2001, 2)
    assert sk.tasks["F"].duration == Fraction(1, 2)
    assert all(type(t.duration) is Fraction for t in sk.tasks.values())


def test_exact_times_from_json(tmp_path: Path) -> None:
    path = tmp_path / "exact.json"
    path.write_text(json.dumps({
        "name": "j",
        "tasks": {"A": {"duration": 0.1, "period": "7/3", "outputs": ["x"]},
                  "B": {"duration": 3, "inputs": ["x"]}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "syn-syn"}],
    }))
    sk = load_skeleton(path)
    assert sk.name == "j"
    assert sk.tasks["A"].duration == Fraction(1, 10)
    assert sk.clocks["A.clock"].period == Fraction(7, 3)
    assert sk.links == [Link(("A", "x"), ("B", "x"), Protocol.SYN_SYN)]


def test_json_errors_carry_lines(tmp_path: Path) -> None:
    path = tmp_path / "lines.json"
    path.write_text('{\n  "tasks": {\n    "A": {\n      "duration": -2\n    }\n  }\n}\n')
    with pytest.raises(SkeletonError) as info:
        load_skeleton(path)
    assert info.value.line == 4 and info.value.where == "tasks.A.duration"


def test_names_are_read_as_written(tmp_path: Path) -> None:
    # YAML 1.1 would read these as true, 1, false and null.
    path = tmp_path / "names.yaml"
    path.write_text(y("name: 2024", "unit: 1e-3", "tasks:",
                      "  on: {duration: 1, inputs: [yes, 1, off]}", "  2: {duration: 1}",
                      "threads: [[on, 2]]"))
    sk = load_skeleton(path)
    assert (sk.name, sk.unit) == ("2024", "1e-3")
    assert list(sk.tasks) == ["on", "2"]
    assert sk.tasks["on"].inputs == ("yes", "1", "off")
    assert sk.threads == [("on", "2")]


@pytest.mark.parametrize("spelling, protocol", [
    ("ASYN/ASYN", Protocol.ASYN_ASYN), ("asyn/syn", Protocol.ASYN_SYN),
    ("Syn-Asyn", Protocol.SYN_ASYN), ("syn-SYN", Protocol.SYN_SYN), ("SYN / SYN", Protocol.SYN_SYN),
])
def test_protocol_spellings(tmp_path: Path, spelling: str, protocol: Protocol) -> None:
    path = tmp_path / "p.yaml"
    path.write_text(y(*TWO, *link("A:x", "B:x", spelling)))
    assert load_skeleton(path).links[0].protocol is protocol


def test_defaults_and_shorthand_clock(tmp_path: Path) -> None:
    path = tmp_path / "my-plant.yaml"
    path.write_text(y("tasks:", "  T: {duration: 1, period: 20, phase: 5}",
                      "  U: {duration: 1, period: 8}", "links:", "threads:"))
    sk = load_skeleton(path)
    assert (sk.name, sk.unit, sk.links, sk.threads) == ("my-plant", "ms", [], [])
    assert sk.tasks["T"].clock == "T.clock"
    assert sk.clocks == {
        "T.clock": Clock("T.clock", Fraction(20), Fraction(5), private=True),
        "U.clock": Clock("U.clock", Fraction(8), Fraction(0), private=True),
    }


def test_file_order_is_kept(tmp_path: Path) -> None:
    path = tmp_path / "order.yaml"
    path.write_text(y("tasks:", "  Z: {duration: 1, period: 3}", "  A: {duration: 1, clock: b}",
                      "  M: {duration: 1, clock: a}", "clocks:", "  b: {period: 2}",
                      "  a: {period: 2}"))
    sk = load_skeleton(path)
    assert list(sk.tasks) == ["Z", "A", "M"]
    # Declared clocks in file order, then the private ones in task order.
    assert list(sk.clocks) == ["b", "a", "Z.clock"]


def test_merge_keys_are_not_duplicates(tmp_path: Path) -> None:
    path = tmp_path / "merge.yaml"
    path.write_text(y("tasks:", "  A: &common {duration: 1, inputs: [x]}",
                      "  B: {<<: *common, duration: 3}"))
    sk = load_skeleton(path)
    assert sk.tasks["B"] == Task("B", Fraction(3), None, ("x",), ())


# ----------------------------------------------------------------- data and code


def test_from_dict_with_python_values() -> None:
    sk = Skeleton.from_dict(
        {"tasks": {"A": {"duration": 0.1, "outputs": ("x",)},
                   "B": {"duration": Fraction(1, 3), "inputs": ["x"]}},
         "links": [{"from": "A:x", "to": "B:x", "protocol": Protocol.SYN_ASYN}]},
        name="code",
    )
    assert sk.name == "code"
    assert sk.tasks["A"].duration == Fraction(1, 10)
    assert sk.links[0].protocol is Protocol.SYN_ASYN


def test_from_dict_refuses_with_source() -> None:
    with pytest.raises(SkeletonError) as info:
        Skeleton.from_dict({"tasks": {1: {"duration": 1}}}, source="design.py")
    assert str(info.value) == ("design.py: tasks.1: expected a task name (a text), got int 1")


def _two_tasks(**changes: object) -> Skeleton:
    sk = Skeleton(
        name="code",
        tasks={"A": Task("A", Fraction(1), "rtc", (), ("x",)),
               "B": Task("B", Fraction(2), None, ("x",), ())},
        clocks={"rtc": Clock("rtc", Fraction(5))},
        links=[Link(("A", "x"), ("B", "x"), Protocol.ASYN_SYN)],
    )
    for key, value in changes.items():
        setattr(sk, key, value)
    return sk


def test_validate_accepts_a_good_skeleton() -> None:
    sk = _two_tasks()
    assert sk.validate() is sk


@pytest.mark.parametrize("changes, key_path, wording", [
    ({"clocks": {}}, "tasks.A.clock", "no clock 'rtc'"),
    ({"links": [Link(("A", "x"), ("B", "q"), Protocol.ASYN_SYN)]}, "links[0].to",
     "task 'B' has no port 'q'"),
    ({"links": [Link(("B", "x"), ("A", "x"), Protocol.ASYN_SYN)]}, "links[0].from",
     "B:x is an input port"),
    ({"tasks": {"A": Task("A", 0.5, None, (), ("x",)), "B": Task("B", Fraction(1), None, ("x",))}},
     "tasks.A.duration", "expected a duration >= 0 as an exact Fraction or int, got float 0.5"),
    ({"tasks": {"A": Task("Z", Fraction(1))}}, "tasks.A", "the key 'A' holds the task named 'Z'"),
    ({"tasks": {"A": "not a task"}}, "tasks.A", "expected a Task, got str"),
    ({"clocks": {"rtc": Clock("Q", Fraction(5))}}, "clocks.rtc",
     "the key 'rtc' holds the clock named 'Q'"),
    ({"clocks": {"rtc": 5}}, "clocks.rtc", "expected a Clock, got int"),
    ({"clocks": {"rtc": Clock("rtc", Fraction(5)), "K": Clock("K", Fraction(1), private=True)}},
     "clocks.K", "expected private clocks only from a task's 'period' shorthand"),
    ({"threads": [("A", "B"), ("B",)]}, "threads[1][0]", "the task 'B' is in two threads"),
    ({"tasks": {}}, "tasks", "expected a mapping from task names to at least one task"),
])
def test_validate_refuses(changes: dict[str, object], key_path: str, wording: str) -> None:
    sk = _two_tasks(**changes)
    sk.source = "design.py"
    with pytest.raises(SkeletonError) as info:
        sk.validate()
    assert info.value.where == key_path
    assert wording in str(info.value)
    assert str(info.value).startswith(f"design.py: {key_path}: ")


def test_to_data_writes_shorthand_and_exact_times() -> None:
    sk = _two_tasks()
    sk.clocks["B.clock"] = Clock("B.clock", Fraction(7, 3), Fraction(1, 2), private=True)
    sk.tasks["B"] = Task("B", Fraction(2), "B.clock", ("x",), ())
    assert sk.to_dict() == {
        "name": "code", "unit": "ms",
        "clocks": {"rtc": {"period": 5}},
        "tasks": {"A": {"duration": 1, "clock": "rtc", "outputs": ["x"]},
                  "B": {"duration": 2, "period": "7/3", "phase": "1/2", "inputs": ["x"]}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}],
    }


def test_to_data_refuses_extra_keys() -> None:
    sk = _two_tasks(extra={"priority": {"A": 1}})
    with pytest.raises(SkeletonError, match=r"extra\.priority: the v1 file format has no key"):
        sk.to_dict()


# ------------------------------------------------------------------------- dumps


def test_dump_text_and_round_trip(tmp_path: Path) -> None:
    source = tmp_path / "example.yaml"
    source.write_text(SPEC_EXAMPLE)
    sk = load_skeleton(source)
    out = dump_skeleton(sk, tmp_path / "copy.yaml")
    assert out.read_text() == y(
        "name: fig7b-fixed", "unit: us", "clocks:", "  rtc:", "    period: 10", "tasks:",
        "  MT1:", "    duration: 2", "    clock: rtc", "    inputs: [a]", "    outputs: [b, c]",
        "  MT2:", "    duration: 4", "    period: 20", "    inputs: [b]", "links:",
        "- from: MT1:b", "  to: MT2:b", "  protocol: ASYN/SYN", "threads:", "- [MT1, MT2]",
    )
    again = load_skeleton(out)
    assert again == sk
    assert list(again.tasks) == list(sk.tasks) and list(again.clocks) == list(sk.clocks)


def test_dump_json_round_trip(tmp_path: Path) -> None:
    sk = Skeleton.from_dict({"tasks": {"yes": {"duration": "7/3", "period": 0.1, "phase": 1,
                                               "outputs": ["on"]},
                                       "B": {"duration": 0, "inputs": ["x"]}},
                             "links": [{"from": "yes:on", "to": "B:x", "protocol": "SYN/ASYN"}]},
                            "j")
    out = dump_skeleton(sk, tmp_path / "j.json")
    assert json.loads(out.read_text())["tasks"]["yes"] == {
        "duration": "7/3", "period": "1/10", "phase": 1, "outputs": ["on"]}
    assert load_skeleton(out) == sk


def test_dump_never_overwrites_by_default(tmp_path: Path) -> None:
    target = tmp_path / "keep.yaml"
    target.write_text("precious\n")
    sk = _two_tasks()
    with pytest.raises(FileExistsError, match="exists already; pass overwrite=True"):
        dump_skeleton(sk, target)
    assert target.read_text() == "precious\n"
    dump_skeleton(sk, target, overwrite=True)
    assert load_skeleton(target) == sk


def test_dump_refuses_an_invalid_skeleton(tmp_path: Path) -> None:
    sk = _two_tasks(clocks={})
    with pytest.raises(SkeletonError, match="tasks.A.clock: no clock 'rtc'"):
        dump_skeleton(sk, tmp_path / "bad.yaml")
    assert not (tmp_path / "bad.yaml").exists()


NAMES = st.text(alphabet="abcxyzAB01._-", min_size=1, max_size=6)
TIMES = st.fractions(min_value=0, max_value=50, max_denominator=12)


@st.composite
def skeletons(draw: st.DrawFn) -> Skeleton:
    names = draw(st.lists(NAMES, min_size=1, max_size=5, unique=True))
    clocks = {f"c{i}": Clock(f"c{i}", draw(TIMES.filter(bool)), draw(TIMES))
              for i in range(draw(st.integers(0, 2)))}
    declared = list(clocks)  # a private clock is never shared
    tasks, ports = {}, {}
    for n, name in enumerate(names):
        choice = draw(st.sampled_from(["none", "private", *declared]))
        clock = None if choice == "none" else f"{name}.clock" if choice == "private" else choice
        if choice == "private":
            clocks[clock] = Clock(clock, draw(TIMES.filter(bool)), draw(TIMES), private=True)
        k = draw(st.integers(0, 3))
        inputs, outputs = tuple(f"i{j}" for j in range(k)), (f"o{n}",)
        tasks[name] = Task(name, draw(TIMES), clock, inputs, outputs)
        ports[name] = inputs
    links, taken = [], set()
    for name in names:
        for port in ports[name]:
            writers = [w for w in names if w != name]
            if writers and draw(st.booleans()):
                w = draw(st.sampled_from(writers))
                links.append(Link((w, f"o{names.index(w)}"), (name, port),
                                  draw(st.sampled_from(list(Protocol)))))
                taken.add((name, port))
    order = draw(st.permutations(names))
    cut = draw(st.integers(0, len(order)))
    threads = [tuple(order[:cut])] if cut else []
    return Skeleton(draw(NAMES), tasks, clocks, links, threads,
                    unit=draw(st.sampled_from(["ms", "s"])))


@settings(max_examples=60)
@given(sk=skeletons(), suffix=st.sampled_from([".yaml", ".json"]))
def test_round_trip_property(tmp_path_factory: pytest.TempPathFactory, sk: Skeleton,
                             suffix: str) -> None:
    path = tmp_path_factory.mktemp("rt") / f"sk{suffix}"
    loaded = load_skeleton(dump_skeleton(sk, path))
    assert loaded == sk
    assert list(loaded.tasks) == list(sk.tasks)
