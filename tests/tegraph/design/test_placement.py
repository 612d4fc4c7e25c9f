"""``tegraph rules`` lists the tasks on different processors that never run at once."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
from typer.testing import CliRunner

import tegraph
from tegraph.cli import app

# Two boards, one 10 ms clock. By hand: on board1 sensor runs 0-2 and act 5-6; on
# board2 log (its own 10 ms clock, a rate-monotonic tie broken by file order) runs
# 0-1, ctrl waits for sensor's message at 2 and runs 2-5, then act reads u at 5.
# Pairs across the boards: sensor-ctrl (0-2 | 2-5), ctrl-act (2-5 | 5-6) and act-log
# (5-6 | 0-1) never meet; sensor-log (0-2 | 0-1) do. Every period repeats this.
BOARDS = """
clocks:
  c: {period: 10}
tasks:
  sensor: {duration: 2, clock: c, outputs: [y], processor: board1}
  ctrl: {duration: 3, inputs: [y], outputs: [u], processor: board2}
  act: {duration: 1, inputs: [u], processor: board1}
  log: {duration: 1, period: 10, processor: board2}
links:
  - {from: "sensor:y", to: "ctrl:y", protocol: ASYN/SYN}
  - {from: "ctrl:u", to: "act:u", protocol: ASYN/SYN}
"""


def test_the_pairs_of_the_two_boards(tmp_path):
    f = tmp_path / "boards.yaml"
    f.write_text(BOARDS)
    section = tegraph.rules(f)
    assert section.never_together.pairs == [("sensor", "ctrl"), ("ctrl", "act"),
                                            ("act", "log")]
    assert section.never_together.examined == 4
    out = CliRunner().invoke(app, ["rules", str(f), "--json"])
    assert out.exit_code == 0, out.output
    doc = json.loads(out.stdout)
    assert doc["never_together"]["pairs"] == [
        ["sensor", "ctrl"], ["ctrl", "act"], ["act", "log"]]
    schema = json.loads((Path(__file__).parents[3] / "docs" / "report.schema.json").read_text())
    jsonschema.validate(doc, schema)
    text = CliRunner().invoke(app, ["rules", str(f)]).stdout
    assert "  ctrl (board2) and act (board1)\n" in text
    assert text.rstrip().splitlines()[-1].startswith("verdict:")  # the verdict stays last


def test_one_processor_lists_nothing_and_analyze_is_unchanged(tmp_path):
    f = tmp_path / "one.yaml"
    f.write_text(BOARDS.replace("board2", "board1"))
    assert tegraph.rules(f).never_together is None
    assert "never_together" not in json.loads(
        CliRunner().invoke(app, ["rules", str(f), "--json"]).stdout)
    # analyze's design section does not simulate the schedule a second time for it
    assert tegraph.analyze(f).design.never_together is None
