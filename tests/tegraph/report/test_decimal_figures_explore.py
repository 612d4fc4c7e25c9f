"""explore's text prints the decimals the user wrote.

Before, ``--clock c1=5.43,2.715`` came back as ``clock c1: 543/100, 543/200 ms``, the
constraints as ``latency A,B,C <= 46/5 ms`` and the front's clock column as fractions.
The JSON report keeps its exact strings. Expected texts are written by hand.
"""

from __future__ import annotations

import json

from typer.testing import CliRunner

from tegraph.cli import app

# c1 is chosen; A reads nothing, B follows A's group, C reads B's last value on its own
# clock and processor. On one processor with A and B, C's clock c2 (10.37 ms) and c1 =
# 1038412611.331 ms would have a hyperperiod of about 10^13 ms, too long for the exact
# schedule's budget (the variant would be rejected as undecided, spec v1.2 §4b).
SKELETON = """\
clocks:
  c1: {period: 5.43}
  c2: {period: 10.37, phase: 0.125}
tasks:
  A: {duration: 1.21, clock: c1, outputs: [x]}
  B: {duration: 2.5, inputs: [x], outputs: [y]}
  C: {duration: 0.333, clock: c2, inputs: [y], processor: cpu2}
links:
  - {from: "A:x", to: "B:x", protocol: ASYN/SYN}
  - {from: "B:y", to: "C:y", protocol: ASYN/ASYN}
"""


def _explore(tmp_path, *options):
    path = tmp_path / "dec.yaml"
    path.write_text(SKELETON, encoding="utf-8")
    result = CliRunner().invoke(app, ["explore", str(path), "--workers", "0",
                                      "--clock", "c1=5.43,2.715,1038412611.331", *options])
    return result


def test_the_choices_and_constraints_print_as_written(tmp_path):
    result = _explore(tmp_path, "--max-latency", "A,B=1e9", "--require", "B.period<=1100000000.5")
    text = result.output
    assert "clock c1: 5.43, 2.715, 1038412611.331 ms" in text, text
    assert ("constraints: B.period <= 1100000000.5 ms; latency A,B on processors <= 1000000000 "
            "ms") in text
    # (A rejection's reason, "A, B responds in 371/100 ms > period 543/200 ms", is
    # written by tegraph.design.explore.evaluate, not by this report.)


def test_the_front_table_prints_exact_decimals(tmp_path):
    text = _explore(tmp_path).output
    rows = text[text.index("\nPareto front:"):text.index("\npruning rules")].splitlines()
    cells = {cell for row in rows for cell in row.split()}
    # Each kept clock choice of the front is printed exactly, never as a rounded float
    # (tabulate alone prints 1038412611.331 as 1.03841e+09) nor as 543/200.
    # The front (2.715 ms is rejected: A and B take 1.21 + 2.5 = 3.71 ms > 2.715 ms).
    assert {"5.43", "1038412611.331"} <= cells
    assert not any("e+" in c or c in ("543/100", "543/200") for c in cells), text


def test_json_keeps_the_exact_strings(tmp_path):
    report = json.loads(_explore(tmp_path, "--json").output)
    assert report["choices"]["clocks"]["c1"] == ["543/100", "543/200", "1038412611331/1000"]
