"""The command line: exit statuses, output formats, refusals without tracebacks."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tegraph.cli import app
from tests.paths import REPO

LIVE = """\
name: pipeline
tasks:
  A: {duration: 2, period: 10, outputs: [x]}
  B: {duration: "7/3", inputs: [x]}
links:
  - {from: "A:x", to: "B:x", protocol: ASYN/SYN}
"""

# Figure 7a of the ORCCAD paper: each task waits to read from the next one.
CIRCULAR = """\
tasks:
  MT1: {duration: 1, inputs: [c], outputs: [a]}
  MT2: {duration: 1, inputs: [a], outputs: [b]}
  MT3: {duration: 1, inputs: [b], outputs: [c]}
links:
  - {from: "MT1:a", to: "MT2:a", protocol: ASYN/SYN}
  - {from: "MT2:b", to: "MT3:b", protocol: ASYN/SYN}
  - {from: "MT3:c", to: "MT1:c", protocol: ASYN/SYN}
"""


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "tegraph.cli", *args],
                          capture_output=True, text=True, timeout=120)


@pytest.fixture
def live_file(tmp_path: Path) -> Path:
    path = tmp_path / "pipeline.yaml"
    path.write_text(LIVE)
    return path


def test_live_and_consistent_exits_0_with_exact_figures(live_file):
    out = run("analyze", str(live_file), "--json")
    assert out.returncode == 0, out.stderr
    report = json.loads(out.stdout)
    # One group under A's clock: period 10. No path leads from B back to A, so
    # the only circuit through B.compute is B's chain (read -> compute ->
    # return place holding 7/3, 1 token): slack 10*1 - 7/3 = 23/3. A's only
    # circuit through A.compute is its chain (holding 2, 1 token): slack 8.
    assert report["groups"][0]["period"] == "10"
    assert report["tasks"]["B"]["period"] == "10"
    assert report["tasks"]["B"]["slack"] == "23/3"
    assert report["tasks"]["A"]["slack"] == "8"
    assert report["live"] is True and report["consistent"] is True
    # Like every command's document: the version and the command first.
    assert list(report)[:2] == ["schema_version", "report"]
    assert report["schema_version"] == 2 and report["report"] == "analyze"


def test_human_report_names_verdicts_and_methods(live_file):
    out = run("analyze", str(live_file))
    assert out.returncode == 0
    # The liveness line gives the verdict and its theorem ("live" alone would also
    # match the verdict line, so the test could not fail on it).
    liveness = next(line for line in out.stdout.splitlines() if line.startswith("liveness:"))
    assert liveness.split(None, 2)[1] == "live" and "Commoner's theorem" in liveness
    # 23/3 = 7.666...: a non-terminating decimal, rounded and marked.
    assert "23/3 ms (≈7.66667)" in out.stdout
    assert out.stdout.splitlines()[-1] == (
        "verdict: live, consistent and schedulable on its processors (exit status 0)")


def test_deadlock_exits_1_and_names_the_circuit(tmp_path):
    path = tmp_path / "fig7a.yaml"
    path.write_text(CIRCULAR)
    out = run("analyze", str(path), "--json")
    assert out.returncode == 1
    report = json.loads(out.stdout)
    assert report["live"] is False
    assert report["reorder"]["possible"] is False
    (deadlock,) = report["deadlocks"]
    assert sorted(deadlock["tasks"]) == ["MT1", "MT2", "MT3"]
    assert "MT1.read:c" in deadlock["events"]


@pytest.mark.parametrize("text, where", [
    ("tasks:\n  A: {duration: -1}\n", "tasks.A.duration"),
    ("tasks: {}\n", "tasks"),
    ("tasks:\n  A: {duration: 1, colour: red}\n", "tasks.A.colour"),
])
def test_refused_input_exits_2_with_one_line(tmp_path, text, where):
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    out = run("analyze", str(path))
    assert out.returncode == 2
    assert out.stdout == ""
    assert "Traceback" not in out.stderr
    line = out.stderr.strip()
    assert line.startswith("tegraph: error: ") and str(path) in line and where in line


def test_missing_file_exits_2(tmp_path):
    out = run("analyze", str(tmp_path / "nothing.yaml"))
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert "nothing.yaml" in out.stderr


def test_csv_tables_and_no_silent_overwrite(live_file, tmp_path):
    out_dir = tmp_path / "tables"
    # No directory is created silently: a missing one is refused, before any work.
    missing = run("analyze", str(live_file), "--csv", str(out_dir))
    assert missing.returncode == 2 and "no such directory" in missing.stderr
    assert not out_dir.exists()
    # A file where a directory is expected: one clear line, no errno text.
    as_file = run("analyze", str(live_file), "--csv", str(live_file))
    assert as_file.returncode == 2 and "is a file; expected a directory" in as_file.stderr
    assert "Errno" not in as_file.stderr
    out_dir.mkdir()
    assert run("analyze", str(live_file), "--csv", str(out_dir)).returncode == 0
    rows = (out_dir / "tasks.csv").read_text().splitlines()
    assert rows[0] == ('task,group,period (ms),"period (ms, decimal)",overrun,'
                       'overrun_at (activation),slack (ms),"slack (ms, decimal)",critical')
    # A: clocked, slack 8 < its period, so it never overruns; B: no clock of its own,
    # period 10, slack 23/3 (derivation in test_live_and_consistent_exits_0...).
    assert rows[1] == "A,0,10,10,never,,8,8,False"
    assert rows[2] == "B,0,10,10,no clock,,23/3,7.66666666666667,False"
    (out_dir / "tasks.csv").write_text("mine")
    again = run("analyze", str(live_file), "--csv", str(out_dir))
    assert again.returncode == 2 and "exists" in again.stderr
    assert (out_dir / "tasks.csv").read_text() == "mine"
    assert run("analyze", str(live_file), "--csv", str(out_dir), "--force").returncode == 0


def _refusal_cases():
    # The loader's own table of every refusal of spec §1 (with the key path
    # and wording each must produce), replayed through the command line.
    from tests.tegraph.io.test_skeleton_file import JSON_REFUSALS, REFUSALS

    return [pytest.param(case.values[0], case.values[1], suffix, id=case.id)
            for cases, suffix in ((REFUSALS, ".yaml"), (JSON_REFUSALS, ".json"))
            for case in cases]


@pytest.mark.parametrize("text, key_path, suffix", _refusal_cases())
def test_every_spec_refusal_exits_2_through_the_cli(tmp_path, text, key_path, suffix):
    from typer.testing import CliRunner

    from tegraph.cli import app

    path = tmp_path / f"plant{suffix}"
    path.write_text(text, encoding="utf-8")
    result = CliRunner().invoke(app, ["analyze", str(path)])
    assert result.exit_code == 2
    assert isinstance(result.exception, SystemExit)  # not an escaped error
    message = result.output.strip()
    assert message.startswith("tegraph: error: ") and str(path) in message
    assert "Traceback" not in message
    if key_path:
        assert f"{key_path}: " in message


def test_version_is_the_package_metadata():
    from importlib.metadata import version

    import maxplus
    import tegraph

    out = run("--version")
    assert out.returncode == 0 and out.stdout.strip() == f"tegraph {version('tegraph')}"
    assert tegraph.__version__ == maxplus.__version__ == version("tegraph")


@pytest.mark.parametrize("command", ["analyze", "reach", "fix", "rules", "timeline",
                                     "cycle-time", "convert"])
def test_every_command_lists_its_exit_statuses(command):
    out = run(command, "--help")
    assert out.returncode == 0
    text = " ".join(out.stdout.split())
    assert "Exit status: 0" in text and " 2 the input" in text


def test_chain_option_shows_a_readable_metavar():
    text = run("analyze", "--help").stdout
    assert "--chain A,B,C" in text and "list[str]" not in text


@pytest.mark.parametrize("args", [
    ("timeline", "{example}", "-o", "{missing}/t.svg"),
    ("convert", "{example}", "{missing}/x.dot"),
    ("fix", "{example}", "-o", "{missing}/x.yaml"),
])
def test_no_output_directory_is_created_silently(tmp_path, args):
    example = REPO / "examples" / "fig7b_wrong_order.yaml"
    missing = tmp_path / "not" / "there"
    argv = [a.format(example=example, missing=missing) for a in args]
    out = run(*argv)
    assert out.returncode == 2 and out.stdout == ""
    assert f"the directory {missing} does not exist" in out.stderr
    assert not (tmp_path / "not").exists()


def test_every_command_help_lists_its_exit_statuses_with_130():
    # main() turns Ctrl-C into exit status 130 for every command (the README says
    # so), so every --help must say it, beside 0 and 2.
    from typer.main import get_command

    group = get_command(app)
    assert len(group.commands) >= 9
    for name in group.commands:
        text = " ".join(CliRunner().invoke(app, [name, "--help"], terminal_width=200)
                        .stdout.split())
        assert "Exit status: 0" in text, name
        assert "2 the input" in text and "130 interrupted" in text, name


@pytest.mark.parametrize("example, expected", [
    # By hand in each example's header: fig7b is dead (MT1 has the clock rtc, MT2
    # and MT3 none); in overrun_in_step MT2 overruns at activation 2, MT1 never.
    ("fig7b_wrong_order.yaml", {"MT1": "not live", "MT2": "no clock", "MT3": "no clock"}),
    ("overrun_in_step.yaml", {"MT1": "never", "MT2": "at activation 2"}),
])
def test_csv_overrun_tells_never_from_no_clock_from_not_live(tmp_path, example, expected):
    import csv

    out = CliRunner().invoke(app, ["analyze", str(REPO / "examples" / example), "--csv",
                                   str(tmp_path)])
    assert out.exit_code == 1
    with open(tmp_path / "tasks.csv", newline="") as fh:
        rows = {row["task"]: row for row in csv.DictReader(fh)}
    assert {t: rows[t]["overrun"] for t in expected} == expected
    late = {t: rows[t]["overrun_at (activation)"] for t in expected}
    assert late == {t: (w.split()[-1] if w.startswith("at ") else "") for t, w in expected.items()}
