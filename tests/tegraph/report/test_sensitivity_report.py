"""The sensitivity report as a reader sees it (issue 21 review, items 2b and 3).

Expected texts and regions are derived by hand in the comments.
"""

from __future__ import annotations

import json

import sympy
from typer.testing import CliRunner

from tegraph.cli import app
from tegraph.report.sensitivity_text import formula_text

# One group {A, B}: A on its 10.37 ms clock, B reads A's output ASYN/SYN. Its circuits:
# the clock's self-loop (10.37 over one token), A's chain (d_A), B's chain (d_B over one
# token, B follows A's activations). With both varied over [0, 12] each term is the
# largest somewhere, so the period is Max(10.37, d_A, d_B): 1037/100 terminates, 10.37.
DECIMAL = """\
tasks:
  A: {duration: 1.21, period: 10.37, outputs: [x]}
  B: {duration: 2.5, inputs: [x]}
links:
  - {from: "A:x", to: "B:x", protocol: ASYN/SYN}
"""


def test_the_formula_prints_its_numbers_as_decimals(tmp_path):
    path = tmp_path / "dec.yaml"
    path.write_text(DECIMAL, encoding="utf-8")
    args = ["sensitivity", str(path), "--vary", "A.duration=0..12", "--vary", "B.duration=0..12"]
    text = CliRunner().invoke(app, args).output
    assert "Max(10.37, d_A, d_B) (exact over the whole range)" in text, text
    assert "1037/100" not in text
    # The JSON document keeps sympy's exact text.
    report = json.loads(CliRunner().invoke(app, [*args, "--json"]).output)
    assert report["groups"][0]["expression"] == "Max(1037/100, d_A, d_B)"


def test_formula_text_keeps_fractions_that_do_not_terminate():
    d = sympy.Symbol("d", nonnegative=True)
    # (d + 1037/100)/3 = d/3 + 1037/300: 300 = 2^2·3·5^2 does not terminate.
    assert formula_text((d + sympy.Rational(1037, 100)) / 3) == "d/3 + 1037/300"
    assert formula_text(sympy.Max(sympy.Rational(-1, 8), d - sympy.Rational(5, 2))) == (
        "Max(-0.125, d - 2.5)")
    # A terminating decimal of more than 30 digits stays a fraction (display_text's limit).
    assert formula_text(d + sympy.Rational(1, 2**110)) == f"d + 1/{2**110}"
