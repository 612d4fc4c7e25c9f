"""`tegraph explore` on the command line, and its results file: JSON against the schema,
exit statuses, refusals without traceback, CSV and Parquet, resume of a cut file."""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

import jsonschema
import pytest
from typer.testing import CliRunner

from tegraph import InputError, Skeleton, load_skeleton
from tegraph.api import analyze, explore
from tegraph.cli import app
from tegraph.design.explore.space import design_space
from tegraph.report.explore_text import render_exploration
from tests.paths import REPO
from tests.tegraph.analysis.test_chains_oracle import plain_on_processors

EXAMPLES = REPO / "examples"
FIG4 = str(EXAMPLES / "fig4_pipeline_synchronized.yaml")
CHAIN = "MT1,MT2,MT3,MT4"


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "tegraph.cli", "explore", *args], cwd=REPO,
                          capture_output=True, text=True, timeout=120)


def schema() -> dict:
    """docs/report.schema.json, which describes every command's document."""
    return json.loads((REPO / "docs" / "report.schema.json").read_text())


def test_json_report_follows_the_schema_and_holds_the_front(tmp_path):
    out = CliRunner().invoke(app, [
        "explore", FIG4, "--link", "MT1:x1 -> MT2:x1=ASYN/SYN,ASYN/ASYN", "--clock",
        "rtc=5,10,20", "--chain", CHAIN, "--workers", "0", "--json", "-o",
        str(tmp_path / "r.csv")])
    assert out.exit_code == 0, out.stderr
    doc = json.loads(out.stdout)
    jsonschema.validate(doc, schema())
    assert doc["report"] == "explore" and doc["variants"] == 6 and doc["exhaustive"] is True
    assert doc["evaluated"] + doc["pruned"] == 6
    # By hand (examples/fig4_pipeline_synchronized.yaml): synchronized, 6 ms of work;
    # rtc = 10 gives load 3/5, 20 gives 3/10 with twice the period; 5 does not fit.
    # Judged on the one processor (spec §4b), the ASYN/ASYN variant at rtc = 5 is
    # schedulable: MT2 -> MT3 -> MT4, cut from MT1, run free below it, in all the time
    # MT1 leaves: 5 ms of work per round in 4/5 of the processor, one round every 25/4
    # ms, period ratio (25/4)/10 = 5/8 (MT1: 5/10), load 1; its latency on processors is
    # exact (spec §4c), the value a plain tick-by-tick run of that variant gives
    # (tests/tegraph/analysis/test_chains_oracle.py). It frees three tasks that the input
    # design runs on rtc: not kept by default, on the front with --free-running.
    front = {d["clocks"]["rtc"]: d for d in doc["front"]}
    assert set(front) == {"10", "20"}
    assert doc["rejected"]["a free-running task"] == 3  # ASYN/ASYN at 5, 10 and 20
    freed = CliRunner().invoke(app, [
        "explore", FIG4, "--link", "MT1:x1 -> MT2:x1=ASYN/SYN,ASYN/ASYN", "--clock",
        "rtc=5,10,20", "--chain", CHAIN, "--workers", "0", "--json", "--free-running"])
    with_free = {d["clocks"]["rtc"]: d for d in json.loads(freed.stdout)["front"]}
    assert set(with_free) == {"10", "20", "5"}
    assert with_free["5"]["links"] == {"MT1:x1 -> MT2:x1": "ASYN/ASYN"}
    variant = design_space(load_skeleton(FIG4), ["MT1:x1 -> MT2:x1"],
                           clocks={"rtc": [5]}, chains=[CHAIN.split(",")]).build(0)
    variant = Skeleton.from_dict({**variant.to_dict(), "chains": [CHAIN.split(",")]})
    (figures,) = analyze(variant, design=False).chains
    first_use = plain_on_processors(variant, figures.on_processors)[0]
    assert with_free["5"]["objectives"] == {f"latency:{CHAIN}": str(first_use),
                                            "period": "5/8", "load": "1"}
    assert front["10"]["links"] == {"MT1:x1 -> MT2:x1": "ASYN/SYN"}  # the front's format
    assert front["10"]["objectives"] == {f"latency:{CHAIN}": "6", "period": "1", "load": "3/5"}
    assert front["20"]["objectives"]["load"] == "3/10"
    assert front["10"]["kinds"] == {f"latency:{CHAIN}": "exact"}


def test_text_ends_with_the_verdict_and_names_the_method(tmp_path):
    # [test] installs matplotlib; a narrower install skips with the reason.
    pytest.importorskip("matplotlib", reason="--plot draws with matplotlib (the [plot] extra)")
    plot = tmp_path / "front.svg"
    # A separate process: the command as a user runs it, progress bar off (no terminal).
    out = run(FIG4, "--link", "MT1:x1 -> MT2:x1", "--clock", "rtc=10,20", "--chain", CHAIN,
              "--workers", "0", "--plot", str(plot))
    assert out.returncode == 0, out.stderr
    assert out.stderr == f"wrote {plot}\n"  # beside the report: its verdict stays last
    lines = out.stdout.strip().splitlines()
    assert lines[-1].startswith("verdict: ") and "exhaustive" in lines[-1]
    assert "L1 = MT1:x1 -> MT2:x1" in out.stdout and "Pareto front" in out.stdout
    assert plot.read_text().lstrip().startswith(("<?xml", "<svg"))


def test_no_design_kept_exits_1(tmp_path):
    # Every candidate period of A's clock is shorter than its 3 ms: never schedulable.
    path = tmp_path / "slow.yaml"
    path.write_text("tasks:\n  A: {duration: 3, period: 10}\n")
    out = CliRunner().invoke(app, ["explore", str(path), "--clock", "A.clock=1,2",
                                   "--workers", "0"])
    assert out.exit_code == 1, out.stderr
    assert "verdict: no variant is live, consistent and schedulable" in out.stdout


@pytest.mark.parametrize("args, words", [
    (["--link", "MT1:x1 -> MT9:x1"], "--link[0]: no link 'MT1:x1 -> MT9:x1'"),
    (["--link", "MT1:x1 -> MT2:x1=ASYN/FOO"], "--link[0]: unknown protocol 'ASYN/FOO'"),
    (["--clock", "nope=1"], "--clock nope: no clock 'nope'"),
    (["--clock", "rtc="], "--clock rtc: no period given"),
    (["--clock", "rtc=0"], "--clock rtc[0]: expected a period > 0"),
    (["--all-links", "--objective", "latency"], "--objective[0]: the objective latency needs"),
    (["--all-links", "--chain", "MT1,MT3"], "--chain[0][1]: no link from MT1 to MT3"),
    ([], "--link: nothing to explore"),
    (["--all-links", "--workers", "2", "--scheduler", "tcp://127.0.0.1:1"],
     "--workers: give either --scheduler or --workers"),
    (["--all-links", "-o", "/no/such/dir/r.csv"], "-o: the directory '/no/such/dir' does not"),
    (["--all-links", "-o", "r.txt"], "expected a file name ending in .csv or .parquet"),
    (["--all-links", "--resume"], "--resume: nothing to resume without an -o file"),
    (["--all-links", "--plot", "f.pdf"], "--plot: cannot draw to 'f.pdf'"),
])
def test_refusals_exit_2_with_one_line(args, words):
    # In this process (click's runner): the refusals happen before any work.
    out = CliRunner().invoke(app, ["explore", FIG4, *args])
    assert out.exit_code == 2, out.stdout
    assert words in out.stderr and "Traceback" not in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1


def test_a_scheduler_that_does_not_answer_exits_2_within_its_timeout():
    out = CliRunner().invoke(app, ["explore", FIG4, "--all-links", "--scheduler",
                                   "tcp://127.0.0.1:9", "--timeout", "1"])
    assert out.exit_code == 2
    assert "--scheduler: no Dask scheduler answers at 'tcp://127.0.0.1:9'" in out.stderr


def test_an_existing_file_needs_resume_or_force(tmp_path):
    target = tmp_path / "r.csv"
    target.write_text("precious\n")

    def invoke(*args):
        return CliRunner().invoke(app, ["explore", FIG4, "--all-links", "--workers", "0",
                                        "-o", str(target), *args])

    out = invoke()
    assert out.exit_code == 2 and "exists already; expected --resume" in out.stderr
    assert target.read_text() == "precious\n"
    # A file of something else is not resumed into either.
    out = invoke("--resume")
    assert out.exit_code == 2 and "another exploration" in out.stderr
    out = invoke("--force")
    assert out.exit_code == 0 and len(target.read_text().splitlines()) == 65


def rows(path: Path) -> list[dict]:
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


SMALL = {"links": ["MT1:x1 -> MT2:x1"], "clocks": {"rtc": [5, 10, 20]},
         "chains": [CHAIN.split(",")]}  # 12 variants


def test_resume_drops_a_cut_last_row_and_judges_only_the_rest(tmp_path):
    sk = load_skeleton(FIG4)
    target = tmp_path / "r.csv"
    whole = explore(sk, **SMALL, workers=0, output=target)
    lines = target.read_text().splitlines(keepends=True)
    # Keep the header and 5 rows, and half of the 6th as a kill would leave it.
    target.write_text("".join(lines[:6]) + lines[6][: len(lines[6]) // 2])
    again = explore(sk, **SMALL, workers=0, output=target, resume=True)
    assert again.resumed == 5 and again.count("analyzed") == 12
    table = rows(target)
    assert sorted(int(r["variant"]) for r in table) == list(range(12))
    assert [r.variant for r in again.front] == [r.variant for r in whole.front]
    # Resuming a complete file judges nothing.
    done = explore(sk, **SMALL, workers=0, output=target, resume=True)
    assert done.resumed == 12 and done.log.batches == 0 and len(rows(target)) == 12
    # Another exploration (other objectives) is refused.
    with pytest.raises(InputError, match="another exploration") as err:
        explore(sk, SMALL["links"], clocks=SMALL["clocks"], workers=0, output=target,
                resume=True)
    assert err.value.file == str(target) and err.value.line == 1  # the header


def test_results_file_rows_hold_exact_values(tmp_path):
    target = tmp_path / "r.csv"
    found = explore(load_skeleton(FIG4), clocks={"rtc": ["10", "25/2"]}, workers=0,
                    objectives=["load"], output=target)
    by_period = {r["clock:rtc"]: r for r in rows(target)}
    # 6 ms of work every 25/2 ms: load 12/25, exactly.
    assert by_period["25/2"]["load"] == "12/25" and by_period["25/2"]["kept"] == "true"
    assert by_period["10"]["load"] == "3/5"
    assert found.space.fingerprint == by_period["10"]["space"]
    assert "verdict:" in render_exploration(found)


def test_parquet_results_are_written_and_resumed(tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    sk = load_skeleton(FIG4)
    target = tmp_path / "r.parquet"
    csv_run = tmp_path / "r.csv"
    whole = explore(sk, **SMALL, workers=0, output=target)
    table = pq.read_table(target).to_pylist()
    assert sorted(int(r["variant"]) for r in table) == list(range(12))
    assert not (tmp_path / "r.parquet.journal.csv").exists()
    kept = {int(r["variant"]) for r in table if r["kept"] == "true"}
    assert {r.variant for r in whole.front} <= kept
    # The same cells as the CSV file.
    explore(sk, **SMALL, workers=0, output=csv_run)
    by_csv = {r["variant"]: {k: v for k, v in r.items() if k != "seconds"}
              for r in rows(csv_run)}
    assert {r["variant"]: {k: v for k, v in r.items() if k != "seconds"}
            for r in table} == by_csv
    # A killed run leaves its journal: resume reads it, then writes the Parquet file.
    target.unlink()
    journal = tmp_path / "r.parquet.journal.csv"
    journal.write_text("".join(csv_run.read_text().splitlines(keepends=True)[:5]))
    again = explore(sk, **SMALL, workers=0, output=target, resume=True)
    assert again.resumed == 4 and not journal.exists()
    assert sorted(int(r["variant"]) for r in pq.read_table(target).to_pylist()) == \
        list(range(12))


def test_without_pyarrow_parquet_is_refused_before_any_work(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "pyarrow", None)
    with pytest.raises(InputError, match=r"pip install 'tegraph\[parquet\]'") as err:
        explore(load_skeleton(FIG4), all_links=True, workers=0, output=tmp_path / "r.parquet")
    assert err.value.where == "output" and not list(tmp_path.iterdir())


def test_json_report_with_processors_follows_the_schema(tmp_path):
    # The three tasks of test_allocation.three() over two alike processors: 4 variants
    # (ppp, ppq, pqp, pqq, each with its renaming); --pin none.
    from tests.tegraph.design.explore.test_allocation import three
    f = tmp_path / "three.yaml"
    import yaml
    f.write_text(yaml.safe_dump(three().to_dict()))
    out = CliRunner().invoke(app, ["explore", str(f), "--processors", "p,q", "--allocate",
                                   "tasks", "--workers", "0", "--json"])
    assert out.exit_code == 0, out.stderr
    doc = json.loads(out.stdout)
    jsonschema.validate(doc, schema())
    assert doc["variants"] == 4
    assert doc["choices"]["allocation"]["interchangeable"] == [["p", "q"]]
    assert all(set(d["processors"]) == {"A", "B", "C"} for d in doc["front"])
