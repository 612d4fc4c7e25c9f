"""A budget of nothing is refused in one line naming its option.

``reach --max-states 0`` is not "inconclusive, budget 0 states" with exit 0, nor
``timeline --max-jobs 0`` typer's multi-line usage error: both give the library's
one-line refusal, exit status 2, like ``--max-memory 0``.
"""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from tegraph import InputError, Skeleton
from tegraph.api import reach
from tegraph.cli import app

ONE_TASK = "tasks:\n  A: {duration: 1, period: 10}\n"


def refused_in_one_line(out, option: str) -> str:
    assert out.exit_code == 2, out.output
    lines = out.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("tegraph: error: "), out.output
    assert option in lines[0] and "Traceback" not in out.output and "Usage" not in out.output
    return lines[0]


def test_reach_refuses_a_state_budget_of_nothing_in_the_library():
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 10}}})
    with pytest.raises(InputError) as caught:
        reach(sk, max_states=0)
    assert caught.value.where == "max_states"
    assert reach(sk, max_states=1).exit_status == 0


@pytest.mark.parametrize("value", ["0", "-1"])
@pytest.mark.parametrize(("command", "option", "extra"), [
    # before: analyze, explore and sensitivity declared `min=1` on --max-events, so typer
    # printed its multi-line usage error; timeline already left the refusal to the library.
    ("analyze", "--max-events", []), ("explore", "--max-events", []),
    ("sensitivity", "--max-events", []), ("timeline", "--max-events", []),
    # before: `reach --max-states 0` answered "inconclusive, budget 0 states" with exit 0.
    ("reach", "--max-states", []), ("reach", "--max-states", ["--timed"]),
    # before: cycle-time declared `min=0`: -1 got typer's usage error, and 0 was taken
    # (exit 0). The budget is checked even on a skeleton, whose cycle time runs no
    # search, like --default-holding.
    ("cycle-time", "--max-states", [])])
def test_a_budget_of_nothing_is_refused_in_one_line(tmp_path, command, option, extra, value):
    path = tmp_path / "a.yaml"
    path.write_text(ONE_TASK)
    out = CliRunner().invoke(app, [command, str(path), option, value, *extra])
    line = refused_in_one_line(out, option)
    assert "an integer >= 1" in line or "an integer from 1 to 2**63 - 1" in line
    assert f"got {value}" in line and "inconclusive" not in line


def test_the_library_cycle_time_refuses_a_state_budget_of_nothing(tmp_path):
    from tegraph.api import cycle_time

    path = tmp_path / "a.yaml"
    path.write_text(ONE_TASK)
    with pytest.raises(InputError) as caught:
        cycle_time(path, max_states=0)
    assert caught.value.where == "max_states"
    assert cycle_time(path, max_states=1).exit_status == 0
