"""`explore -o FILE --resume` reads back only its own results files, every cell checked,
and never changes a byte of a file it refuses.

Each refusal is one line on stderr naming the file, the line (row) and the column,
exit status 2, and the file is left byte for byte as it was; a file cut mid-row by a
kill is still resumed.
"""

from __future__ import annotations

import csv
from pathlib import Path

import pytest
from typer.testing import CliRunner

from tegraph import InputError, load_skeleton
from tegraph.api import explore
from tegraph.cli import app
from tests.paths import REPO

FIG4 = str(REPO / "examples" / "fig4_pipeline_synchronized.yaml")
# 4 protocols x 3 periods = 12 variants; objectives period and load only.
ARGS = ["--link", "MT1:x1 -> MT2:x1", "--clock", "rtc=5,10,20", "--objective", "period,load",
        "--workers", "0"]
SMALL = {"links": ["MT1:x1 -> MT2:x1"], "clocks": {"rtc": [5, 10, 20]},
         "objectives": ["period", "load"]}


def invoke(target: Path, *more: str):
    return CliRunner().invoke(app, ["explore", FIG4, *ARGS, "-o", str(target), *more])


def refused(target: Path, words: str, *more: str) -> str:
    """Run with --resume; assert one-line refusal, exit 2, file unchanged."""
    before = target.read_bytes()
    out = invoke(target, "--resume", *more)
    assert out.exit_code == 2, (out.stdout, out.stderr)
    assert "Traceback" not in out.stderr and len(out.stderr.strip().splitlines()) == 1
    assert words in out.stderr, out.stderr
    assert str(target) in out.stderr
    assert target.read_bytes() == before  # not a byte changed (no truncation)
    return out.stderr


@pytest.fixture
def results(tmp_path) -> Path:
    """A complete results file of this exploration (12 rows)."""
    target = tmp_path / "r.csv"
    explore(load_skeleton(FIG4), **SMALL, workers=0, output=target)
    return target


def rewrite(target: Path, row: int, column: str, value: str) -> None:
    """Set one cell (row 1 is the first after the header), keeping the CSV quoting."""
    with open(target, newline="", encoding="utf-8") as f:
        table = list(csv.reader(f))
    table[row][table[0].index(column)] = value
    with open(target, "w", newline="", encoding="utf-8") as f:
        csv.writer(f).writerows(table)


# ----------------------------------------------------------------- no data loss on resume

def test_a_users_own_csv_is_refused_and_left_whole(tmp_path):
    # Before: the last line had no end of line, so it was "cut by a kill" and the file
    # was truncated before its header was even read.
    target = tmp_path / "mine.csv"
    target.write_bytes(b"my,own,data\n1,2,3\n4,5,6")
    refused(target, "the header is not that of this exploration's results")
    target.write_bytes(b"my,own,data\n1,2,3\n4,5,6\n")
    refused(target, ":1: the header")


def test_a_file_of_another_space_or_skeleton_is_refused_and_left_whole(results, tmp_path):
    # Same header (same links, clocks and objectives), another skeleton: the duration of
    # MT1 changed, so the fingerprint differs; the last row cut as a kill would leave it.
    other = tmp_path / "other.yaml"
    other.write_text(Path(FIG4).read_text().replace("duration: 1", "duration: 1.5", 1))
    assert other.read_text() != Path(FIG4).read_text()
    data = results.read_bytes()
    results.write_bytes(data[: len(data) - 7])  # cut mid-row
    out = CliRunner().invoke(app, ["explore", str(other), *ARGS, "-o", str(results),
                                   "--resume"])
    assert out.exit_code == 2 and "another exploration" in out.stderr
    assert ":2: row 1, column 'space'" in out.stderr
    assert results.read_bytes() == data[: len(data) - 7]


def test_a_file_of_other_choices_is_refused(results):
    before = results.read_bytes()
    out = CliRunner().invoke(app, ["explore", FIG4, "--link", "MT1:x1 -> MT2:x1",
                                   "--clock", "rtc=5,10", "--objective", "period,load",
                                   "--workers", "0", "-o", str(results), "--resume"])
    assert out.exit_code == 2 and "another exploration" in out.stderr
    assert results.read_bytes() == before


def test_an_empty_file_is_resumed_as_a_table_with_no_row(tmp_path):
    # A run killed before its header: nothing to lose, the run starts it.
    target = tmp_path / "r.csv"
    target.write_bytes(b"")
    out = invoke(target, "--resume")
    assert out.exit_code == 0, out.stderr
    assert len(target.read_text().splitlines()) == 13


def test_a_header_cut_by_a_kill_is_resumed(results):
    header = results.read_bytes().splitlines(keepends=True)[0]
    results.write_bytes(header[:17])
    out = invoke(results, "--resume")
    assert out.exit_code == 0, out.stderr
    assert results.read_bytes().splitlines(keepends=True)[0] == header
    assert len(results.read_bytes().splitlines()) == 13


def test_a_row_cut_by_a_kill_is_dropped_after_every_row_is_checked(results):
    lines = results.read_bytes().splitlines(keepends=True)
    # Keep 5 rows and 9 bytes of the 6th: the variant number and part of the fingerprint.
    results.write_bytes(b"".join(lines[:6]) + lines[6][:9])
    out = invoke(results, "--resume")
    assert out.exit_code == 0, out.stderr
    variants = sorted(int(r["variant"]) for r in csv.DictReader(results.open(newline="")))
    assert variants == list(range(12))
    # A cut tail that is not the beginning of one of its rows: not a kill, refused.
    results.write_bytes(b"".join(lines[:6]) + b"my own note")
    refused(results, "the last line has no end of line and is not the beginning")


def test_a_parquet_file_not_written_by_explore_is_refused_and_left_whole(tmp_path):
    pa = pytest.importorskip("pyarrow")
    import pyarrow.parquet as pq

    target = tmp_path / "mine.parquet"
    pq.write_table(pa.table({"my": ["1"], "own": ["2"], "data": ["3"]}), target)
    refused(target, "its columns are not those of this exploration's results")
    target.write_bytes(b"not parquet at all\n")
    refused(target, "cannot read it as Parquet")


# ------------------------------------------------------- every cell checked

@pytest.mark.parametrize("column, value, words", [
    ("variant", "x7", "row 3, column 'variant': expected a variant number from 0 to 11, "
                      "got 'x7'"),
    ("variant", "12", "column 'variant': expected a variant number from 0 to 11"),
    ("variant", "1" * 5000, "(5,000 characters)"),
    ("judged", "banana", "row 3, column 'judged': expected one of analyzed, pruned, failed, "
                         "got 'banana'"),
    ("period", "-5", "row 3, column 'period': expected a number > 0, got '-5'"),
    ("period", "1e999999999", "column 'period': expected an exact number"),
    ("load", "7/0", "column 'load': expected an exact number"),
    ("kept", "maybe", "column 'kept': expected true, false or empty"),
    # Row 3 is variant 2: ASYN/ASYN (the first of the four protocols), rtc 20.
    ("link:MT1:x1 -> MT2:x1", "SYN/SYN", "variant 2 has 'ASYN/ASYN', got 'SYN/SYN'"),
    ("orders", "{not json", "column 'orders'"),
    ("seconds", "nan", "column 'seconds'"),
])
def test_a_bad_cell_is_refused_naming_file_row_and_column(results, column, value, words):
    rewrite(results, 3, column, value)
    message = refused(results, words)
    assert f"{results}:4: " in message  # the header is line 1, row 3 is line 4


def test_the_variant_cell_is_checked_against_its_choices(results):
    # Row 3 holds variant 2: link choice 0 (ASYN/ASYN, the first of all four), period 20.
    with open(results, newline="") as f:
        row = list(csv.DictReader(f))[2]
    assert row["variant"] == "2" and row["clock:rtc"] == "20"
    rewrite(results, 3, "clock:rtc", "10")
    refused(results, "row 3, column 'clock:rtc': variant 2 has '20', got '10'")


def test_a_kept_flag_that_contradicts_the_verdicts_is_refused(results):
    with open(results, newline="") as f:
        rows = list(csv.DictReader(f))
    k = next(i for i, r in enumerate(rows, start=1) if r["kept"] == "false")
    rewrite(results, k, "kept", "true")
    refused(results, "column 'kept': live, consistent, schedulable and the constraints say "
                     "false, got 'true'")


def test_bytes_that_are_not_utf8_are_refused(results):
    data = results.read_bytes()
    lines = data.splitlines(keepends=True)
    results.write_bytes(b"".join(lines[:3]) + lines[3].replace(b"analyzed", b"analyz\xe9d")
                        + b"".join(lines[4:]))
    refused(results, ":4: byte")
    assert "is not UTF-8 text" in invoke(results, "--resume").stderr


def test_the_library_refusal_names_the_file_and_line(results):
    rewrite(results, 2, "judged", "banana")
    with pytest.raises(InputError) as err:
        explore(load_skeleton(FIG4), **SMALL, workers=0, output=results, resume=True)
    assert err.value.file == str(results) and err.value.line == 3
    assert "row 2, column 'judged'" in err.value.reason


def test_a_failed_variant_does_not_make_the_verdict_say_exhaustive_not_exhaustive(
        monkeypatch):
    import tegraph.design.explore.evaluate as explore_eval

    judge = explore_eval.evaluate_variant

    def failing(space, variant, repairs=None):
        if variant == 1:
            raise RuntimeError("boom")
        return judge(space, variant, repairs)

    monkeypatch.setattr(explore_eval, "evaluate_variant", failing)
    found = explore(load_skeleton(FIG4), **SMALL, workers=0)
    assert found.count("failed") == 1 and not found.exhaustive
    assert "exhaustive, not exhaustive" not in found.verdict
    assert found.verdict.endswith("(every variant proposed, 1 failed to be judged: the exact "
                                  "front of the variants judged, not of the space)")
    assert found.rejected["failed to be judged"] == 1
