"""Every integer option reads the one number grammar; budgets are bounded; numbers are
echoed as written; a drawing without matplotlib is one line naming the extra.

The README's grammar: an integer, a decimal or one fraction ``p/q``; an integer option
takes such a number when its value is whole (``1e3`` is 1000) and refuses any other in
one line naming the option, exit status 2 (never typer's own usage message).
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tegraph.cli import app

ONE_TASK = "tasks:\n  A: {duration: 1, period: 4}\n"
# Clocks of 10, 10.01, 10.001 and 9.99 drift (hyperperiod some 10**7), and D -> C is a
# synchronizing link (no theorem of independent tasks decides them): no regime within a
# small budget, so the report says how many firings it simulated, the budget itself.
DRIFTING = ("tasks:\n  A: {duration: 1, period: 10}\n  B: {duration: 1, period: 10.01}\n"
            "  C: {duration: 1, period: 10.001, inputs: [x]}\n"
            "  D: {duration: 1, period: 9.99, outputs: [x]}\n"
            "links:\n  - {from: D:x, to: C:x, protocol: ASYN/SYN}\n")


def _file(tmp_path: Path, text: str = ONE_TASK, name: str = "s.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _run(*args: str):
    return CliRunner().invoke(app, [str(a) for a in args])


def _one_line_refusal(result, option: str) -> str:
    """The refusal's line: exit 2, one line on stderr naming ``option``, no usage text."""
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1, result.output
    assert lines[0].startswith(f"tegraph: error: {option}: "), lines[0]
    assert "Usage" not in result.output and "Traceback" not in result.output
    return lines[0]


# (command, the option, what else the command needs)
INTEGER_OPTIONS = [
    ("analyze", "--max-steps", []),
    ("analyze", "--max-events", []),
    ("timeline", "--max-events", []),
    ("timeline", "--width", []),
    ("sensitivity", "--max-events", []),
    ("explore", "--max-events", ["--clock", "A.clock=4,8"]),
    ("explore", "--max-variants", ["--clock", "A.clock=4,8"]),
    ("explore", "--batch-size", ["--clock", "A.clock=4,8"]),
    ("explore", "--workers", ["--clock", "A.clock=4,8"]),
    ("reach", "--max-states", []),
    ("reach", "--max-firings", []),
    ("cycle-time", "--max-states", []),
    ("cycle-time", "--max-firings", []),
]


@pytest.mark.parametrize("command, option, rest", INTEGER_OPTIONS)
@pytest.mark.parametrize("value", ["2.5", "abc", "1/3", "0x10"])
def test_an_integer_option_refuses_a_non_integer_in_one_line(tmp_path, command, option, rest,
                                                             value):
    # before: typer's multi-line "Invalid value for '--max-events': '2.5' is not a
    # valid integer" with the usage text
    line = _one_line_refusal(_run(command, _file(tmp_path), option, value, *rest), option)
    assert f"'{value}'" in line


@pytest.mark.parametrize("command, option, rest", INTEGER_OPTIONS)
def test_an_integer_option_takes_the_number_grammar(tmp_path, command, option, rest):
    # 1e2 = 100 and 200/2 = 100 are whole: accepted wherever 100 is (exit 0 or 1); for
    # --workers (at most the machine's cores) 0e0 = 0/3 = 0.0 = 0, this process
    values = ("0e0", "0/3", "0.0") if option == "--workers" else ("1e2", "200/2", "100.0")
    for value in values:
        result = _run(command, _file(tmp_path), option, value, *rest)
        assert result.exit_code in (0, 1), (value, result.output)


def test_1e3_events_is_a_budget_of_1000_firings(tmp_path):
    # The drifting clocks never repeat within 1000 firings: the simulation spends all
    # of them and says so ("1000 event firings in 1 independent part(s)").
    result = _run("analyze", _file(tmp_path, DRIFTING), "--max-events", "1e3")
    assert result.exit_code == 1, result.output
    assert "1000 event firings in 1 independent part(s)" in result.output


@pytest.mark.parametrize("option, value, bounds", [
    ("--width", "9", "(from 10 to 10,000)"), ("--width", "1e9", "(from 10 to 10,000)"),
    ("--max-steps", "0", "(at least 1)"), ("--workers", "-1", "(at least 0)"),
    ("--max-variants", "0", "(at least 1)"), ("--batch-size", "0", "(at least 1)"),
])
def test_an_integer_out_of_its_bounds_is_refused_in_one_line(tmp_path, option, value, bounds):
    # --width 1e9 would have drawn rows of a billion columns (several GB)
    command = "timeline" if option == "--width" else (
        "analyze" if option == "--max-steps" else "explore")
    rest = ["--clock", "A.clock=4,8"] if command == "explore" else []
    line = _one_line_refusal(_run(command, _file(tmp_path), option, value, *rest), option)
    assert bounds in line


def test_max_seconds_takes_the_number_grammar(tmp_path):
    assert _run("reach", _file(tmp_path), "--max-seconds", "1/2").exit_code == 0
    _one_line_refusal(_run("reach", _file(tmp_path), "--max-seconds", "-1"), "--max-seconds")
    _one_line_refusal(_run("reach", _file(tmp_path), "--max-seconds", "x"), "--max-seconds")


# ------------------------------------------------------------------ the largest budget

@pytest.mark.parametrize("command, rest", [
    ("analyze", []), ("timeline", []), ("sensitivity", []),
    ("explore", ["--clock", "A.clock=4,8"]),
])
@pytest.mark.parametrize("value", [str(2**63), "1e29"])
def test_a_budget_past_64_bits_is_refused(tmp_path, command, rest, value):
    # before: analyze and timeline ended in OverflowError (the compiled loop counts in
    # a C ssize_t); explore judged no variant and reported an empty front (exit 1)
    line = _one_line_refusal(_run(command, _file(tmp_path), "--max-events", value, *rest),
                             "--max-events")
    assert "from 1 to 2**63 - 1 = 9223372036854775807" in line


def test_the_largest_budget_is_taken_and_said_in_help(tmp_path):
    assert _run("analyze", _file(tmp_path), "--max-events", str(2**63 - 1)).exit_code == 0
    for command in ("analyze", "timeline", "sensitivity", "explore"):
        help_text = " ".join(_run(command, "--help").output.split())
        assert "from 1 to 2**63 - 1" in help_text, command


# ------------------------------------------------------------------ numbers as written

@pytest.mark.parametrize("args, text", [
    (["sensitivity", None, "--vary", "A.duration=-0.15..2"],
     "the range of A.duration starts below 0 (-0.15)"),
    (["sensitivity", None, "--vary", "A.duration=1.5..0.25"],
     "the range of A.duration is empty (1.5..0.25)"),
    (["cycle-time", None, "--default-holding", "-0.15"], "got -0.15"),
])
def test_a_negative_decimal_is_echoed_as_written(tmp_path, args, text):
    # before: "-3/20" (the exact value's fraction), which the user never wrote
    args = [str(_file(tmp_path)) if a is None else a for a in args]
    result = _run(*args)
    assert result.exit_code == 2 and text in result.output, result.output
    assert "3/20" not in result.output


@pytest.mark.parametrize("key, written", [("duration", "-0.15"), ("duration", "-1.5e-1"),
                                          ("phase", "-0.15")])
def test_a_negative_time_in_a_file_is_echoed_as_written(tmp_path, key, written):
    body = {"duration": "1", "phase": "0"}
    body[key] = written
    path = _file(tmp_path, f"tasks:\n  A: {{period: 4, duration: {body['duration']}, "
                           f"phase: {body['phase']}}}\n")
    result = _run("analyze", path)
    assert result.exit_code == 2
    assert f"got {written}" in result.output and "3/20" not in result.output


def test_a_negative_time_given_to_the_library_is_printed_in_decimal():
    from fractions import Fraction

    from tegraph import Skeleton
    from tegraph.errors import InputError

    for value in (Fraction(-3, 20), -0.15):
        with pytest.raises(InputError, match=r"got -0\.15$"):
            Skeleton.from_dict({"tasks": {"A": {"duration": value, "period": 4}}})


# ------------------------------------------------------------------ without matplotlib

@pytest.mark.parametrize("args", [
    ["timeline", None, "-o", "{out}.png"],
    ["explore", None, "--clock", "A.clock=4,8", "--plot", "{out}.png"],
    ["sensitivity", None, "--vary", "A.duration", "--plot", "{out}.svg"],
])
def test_without_matplotlib_a_drawing_is_one_line_naming_the_extra(tmp_path, monkeypatch, args):
    # `pip install .` installs no matplotlib; the plot extra of the source directory does
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    out = tmp_path / "drawing"
    args = [str(_file(tmp_path)) if a is None else a.format(out=out) for a in args]
    result = _run(*args)
    option = "-o" if args[0] == "timeline" else "--plot"
    line = _one_line_refusal(result, option)
    assert "pip install '.[plot]'" in line
    assert not list(tmp_path.glob("drawing*"))
