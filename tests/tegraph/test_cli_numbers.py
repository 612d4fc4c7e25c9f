"""Numbers given on the command line go through the one parser and its bound.

A huge number is refused by its size (never expanded), the duration margins take
the parser's values, and no option silently means something else. Expected values
are derived by hand in comments.
"""

from __future__ import annotations

import time
from fractions import Fraction as F
from pathlib import Path

import pytest
from typer.testing import CliRunner

import tegraph
from tegraph.cli import app
from tegraph.errors import InputError
from tegraph.io import load_skeleton

ONE_TASK = "tasks:\n  A: {duration: 1, period: 10}\n"
CLOCKED = "clocks:\n  rtc: {period: 10}\ntasks:\n  A: {duration: 1, clock: rtc}\n"
HUGE = "1e999999999"  # expanded, a billion-digit integer: hours


def _file(tmp_path: Path, text: str, name: str = "s.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _run(*args: str):
    start = time.perf_counter()
    result = CliRunner().invoke(app, list(args))
    assert time.perf_counter() - start < 30
    return result


@pytest.mark.parametrize("command, options", [
    ("sensitivity", ["--vary", f"A.duration=0..{HUGE}"]),
    ("timeline", ["--horizon", HUGE]),
    ("explore", ["--clock", f"rtc={HUGE}"]),
    ("cycle-time", ["--default-holding", HUGE]),
])
def test_a_huge_number_in_an_option_is_refused_by_its_size(tmp_path, command, options):
    # before: each of these ran for hours, expanding the exponent
    result = _run(command, str(_file(tmp_path, CLOCKED)), *options)
    assert result.exit_code == 2, result.output
    assert "has 1,000,000,000 digits; at most 4,300 are accepted" in result.output
    assert "Traceback" not in result.output


@pytest.mark.parametrize("command, options", [
    ("timeline", ["--horizon", "9" * 5000]),
    ("cycle-time", ["--default-holding", "9" * 5000]),
    ("sensitivity", ["--vary", "A.duration=0.." + "9" * 5000]),
])
def test_a_long_number_is_refused_by_its_size_and_not_echoed(tmp_path, command, options):
    result = _run(command, str(_file(tmp_path, ONE_TASK)), *options)
    assert result.exit_code == 2
    assert "has 5,000 digits; at most 4,300 are accepted" in result.output
    assert "9" * 100 not in result.output and "5,000 characters" in result.output


def test_timeline_horizon_nonsense_names_the_option(tmp_path):
    # before: "5/2/3" was the horizon 15/2
    result = _run("timeline", str(_file(tmp_path, ONE_TASK)), "--horizon", "5/2/3")
    assert result.exit_code == 2 and "--horizon" in result.output
    assert "got '5/2/3'" in result.output


def test_the_library_conversion_of_cycle_time_is_bounded(tmp_path):
    with pytest.raises(InputError, match="1,000,000,000 digits"):
        tegraph.cycle_time(_file(tmp_path, "0 0 1 1\n", "g.edges"), default_holding=HUGE)


# ------------------------------------------------------ a tiny duration past int64 scaling

def test_a_duration_of_1e_18_gets_its_exact_margin(tmp_path):
    # before: TypeError "both arguments should be Rational instances" in the duration
    # margins: scaled by 10**18, the longest paths left int64 and a fixed "unreached"
    # sentinel (-2**62) lay above their real values, so the path to A's end was None.
    # By hand: A alone on its own clock of period 10 ends each activation in time while
    # its duration d <= 10, so it may grow by 10 - 10**-18 (the slack bound, too).
    path = _file(tmp_path, "tasks:\n  A: {duration: 1e-18, period: 10}\n")
    report = tegraph.analyze(load_skeleton(path))
    margin = F(10) - F(1, 10**18)
    assert report.tasks["A"].duration_margin == margin == report.tasks["A"].slack
    result = _run("analyze", str(path))
    assert result.exit_code == 0 and "Traceback" not in result.output


# ------------------------------------------------- options checked even when unused

@pytest.mark.parametrize("holding", ["abc", "-1", "5/2/3"])
def test_default_holding_is_checked_even_when_unused(tmp_path, holding):
    # before: a skeleton has timing, the option was never read and exit 0 followed
    result = _run("cycle-time", str(_file(tmp_path, ONE_TASK)), "--default-holding", holding)
    assert result.exit_code == 2 and "--default-holding" in result.output


@pytest.mark.parametrize("command, option", [
    ("cycle-time", "--max-size"), ("cycle-time", "--max-memory"), ("reach", "--max-memory"),
    ("convert", "--max-size")])
def test_a_size_of_zero_is_refused(tmp_path, command, option):
    # before: cycle-time --max-size 0 read the file under the default 256M limit (0 was
    # falsy); reach --max-memory 0 on a skeleton said "inconclusive after 0 states", exit 0
    args = [command, str(_file(tmp_path, ONE_TASK)), option, "0"]
    if command == "convert":
        args.insert(2, str(tmp_path / "out.edges"))
    result = _run(*args)
    assert result.exit_code == 2, result.output
    assert f"{option}: expected a size of at least 1 byte" in result.output


def test_reach_refuses_a_memory_budget_of_zero_for_skeletons_and_nets_alike(tmp_path):
    from tegraph.analysis.baselines.reachability import reachability_graph, skeleton_reachability
    from tegraph.model.build import build_teg
    from tegraph.model.petri import PetriNet

    teg = build_teg(load_skeleton(_file(tmp_path, ONE_TASK)))
    for search, model in ((skeleton_reachability, teg),
                          (reachability_graph, PetriNet.from_teg(teg))):
        with pytest.raises(InputError, match="bytes >= 1") as info:
            search(model, max_memory=0)
        assert info.value.where == "max_memory"


def test_cycle_time_max_bytes_zero_is_not_the_default(tmp_path):
    # before: max_bytes=0 was taken for "not given" (256 MiB)
    with pytest.raises(InputError, match="above the limit of 0"):
        tegraph.cycle_time(_file(tmp_path, "0 0 1 1\n", "g.edges"), max_bytes=0)
