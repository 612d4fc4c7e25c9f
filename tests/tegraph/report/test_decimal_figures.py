"""Figures as the input said them: decimals stay decimals, exactly.

Before, text reports printed ``543/100 ms`` and ``T = 1038412611331/1000 ms`` where
the file said 5.43 and 1038412611.331. Expected figures are derived by hand below.
"""

from __future__ import annotations

import json
from fractions import Fraction

from typer.testing import CliRunner

from maxplus.scalar import display_text
from tegraph.cli import app

# A: 5.43 ms every 1038412611.331 ms; B: 7/3 ms every 20 ms; unsynchronized (two groups).
SKELETON = """\
tasks:
  A: {duration: 5.43, period: 1038412611.331, outputs: [x]}
  B: {duration: "7/3", period: 20, inputs: [x]}
links:
  - {from: "A:x", to: "B:x", protocol: ASYN/ASYN}
"""


def _analyze(tmp_path, *options):
    path = tmp_path / "d.yaml"
    path.write_text(SKELETON, encoding="utf-8")
    result = CliRunner().invoke(app, ["analyze", str(path), *options])
    assert result.exit_code == 0, result.output
    return result.output


def test_the_analysis_text_prints_the_decimals_the_file_wrote(tmp_path):
    text = _analyze(tmp_path)
    assert "1038412611331/1000" not in text and "543/100" not in text
    assert "1038412611.331 ms" in text  # A's period
    # A's slack: 1038412611.331 - 5.43 = 1038412605.901, a terminating decimal.
    assert "1038412605.901 ms" in text
    # B's slack: 20 - 7/3 = 53/3 does not terminate: the fraction, a rounded decimal beside.
    assert "53/3 ms (≈17.6667)" in text
    # Utilization test: T = lcm(1038412611331/1000, 20) = lcm(1038412611331, 20) (the
    # numerator is odd and ends in 1: coprime to 20) = 20768252226620 ms; the sum is
    # 5.43 * T/tau_A + 7/3 * T/20 = 5.43 * 20000 + 7/3 * 1038412611331 = 7268888605117/3.
    assert "T = 20768252226620 ms, sum = 7268888605117/3 ms" in text
    assert "5.43 " in text  # A's work in the schedulability table


def test_json_keeps_its_exact_strings(tmp_path):
    report = json.loads(_analyze(tmp_path, "--json"))
    assert report["tasks"]["A"]["period"] == "1038412611331/1000"
    assert report["tasks"]["A"]["slack"] == "1038412605901/1000"
    assert report["tasks"]["B"]["slack"] == "53/3"


def test_display_text_is_exact():
    # A terminating decimal of at most 30 significant digits is printed; 1/2**110 has 77.
    for value, text in ((Fraction(543, 100), "5.43"), (Fraction(7, 3), "7/3"),
                        (Fraction(-1, 8), "-0.125"),
                        (Fraction(10**20 + 1, 10), "1" + "0" * 19 + ".1"),
                        (Fraction(1, 10**8), "1e-8"), (Fraction(1, 2**110), f"1/{2**110}")):
        assert display_text(value) == text
        assert Fraction(text) == value  # whatever is printed reads back exactly
