"""The sensitivity report as a reader sees it.

Expected texts and regions are derived by hand in the comments.
"""

from __future__ import annotations

import json
from fractions import Fraction as F

import pytest
import sympy
from typer.testing import CliRunner

from tegraph import Skeleton, load_skeleton, sensitivity
from tegraph.cli import app
from tegraph.report.sensitivity_text import formula_text
from tests.paths import REPO

EXAMPLES = REPO / "examples"

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


# ------------------------------------------------- the map of two parameters

def _map(skeleton, vary):
    pytest.importorskip("matplotlib")
    from tegraph.report.sensitivity_plot import sensitivity_figure

    (ax,) = sensitivity_figure(sensitivity(skeleton, vary)).axes
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    return ax, labels


def _step(d1=6, d2=6, period=10):
    data = load_skeleton(EXAMPLES / "overrun_in_step.yaml").to_dict()
    data["tasks"]["MT1"].update(duration=d1, period=period)
    data["tasks"]["MT2"].update(duration=d2, period=period)
    return Skeleton.from_dict(data)


def _corners(artist):
    return {(float(a), float(b)) for a, b in artist.get_path().vertices}


CONSISTENT = "consistent: keeps pace with every clock and no overrun (exact)"


def test_the_map_shades_the_consistent_region_not_only_keeping_pace():
    # overrun_in_step: MT1 and MT2 on 10 ms clocks, MT2 reads MT1 ASYN/SYN. By hand
    # (the example's daters with d1, d2 for 6, 6): MT1 writes at 10(k-1) + d1 (keeps
    # pace iff d1 <= 10); MT2's activation k ends at 10(k-1) + d1 + d2 when d1 + d2 <= 10
    # (no overrun: it ends by the next tick 10k), and activation 1 ends at d1 + d2 > 10
    # = tick 2 otherwise (an overrun at activation 2). Consistent: d1 + d2 <= 10, the
    # triangle (0,0), (10,0), (0,10); keeping pace alone is the square [0, 10]².
    ax, labels = _map(_step(), ["MT1.duration=0..12", "MT2.duration=0..12"])
    (pace,) = [p for p in ax.patches
               if p.get_label() == "keeps pace with every clock (MT1.clock, MT2.clock)"]
    assert _corners(pace) == {(0, 0), (10, 0), (10, 10), (0, 10)}
    (consistent,) = [p for p in ax.patches if p.get_label() == CONSISTENT]
    assert _corners(consistent) == {(0, 0), (10, 0), (0, 10)}
    # The overrun boundary: the hypotenuse d1 + d2 = 10, MT2 overrunning beyond it.
    (edge,) = [line for line in ax.lines if line.get_label() == "an overrun begins beyond (MT2)"]
    assert {tuple(p) for p in edge.get_xydata().tolist()} == {(10.0, 0.0), (0.0, 10.0)}
    # The nominal point (6, 6) is outside (6 + 6 > 10) and says so.
    assert "nominal (6, 6): NOT CONSISTENT" in labels
    from matplotlib.colors import to_hex
    colours = [to_hex(h.get_facecolor() if hasattr(h, "get_facecolor") else h.get_color())
               for h in ax.get_legend().legend_handles]
    assert len(set(colours)) == len(colours), labels


def test_the_nominal_point_inside_says_consistent():
    # d1 = d2 = 3: 3 + 3 <= 10.
    _, labels = _map(_step(3, 3), ["MT1.duration=0..12", "MT2.duration=0..12"])
    assert "nominal (3, 3): consistent" in labels


def test_the_consistent_region_is_exact_with_decimal_periods():
    from tegraph.analysis.sensitivity.region import consistent_region

    # Periods 10.37: the triangle d1 + d2 <= 10.37 exactly (same derivation as above).
    r = sensitivity(_step(period="10.37"), ["MT1.duration=0..12", "MT2.duration=0..12"])
    (f,) = r.formulas
    pace = [(co.get("MT1.duration", F(0)), co.get("MT2.duration", F(0)), b)
            for region in f.pace for co, b, _ in region.inequalities]
    region = consistent_region(r.models[f.group], 0, 1, (F(0), F(12), F(0), F(12)), pace,
                               [F(6), F(6)])
    assert set(region.vertices) == {(0, 0), (F(1037, 100), 0), (0, F(1037, 100))}
    assert [(set(e[:2]), e[2]) for e in region.overrun_edges] == [
        ({(F(1037, 100), 0), (0, F(1037, 100))}, "MT2")]
    assert region.why_not is None and not region.nominal_consistent


def test_a_period_equal_to_another_clocks_gives_a_segment():
    # MT2's period varied: keeping pace with both clocks needs P2 = 10 (a segment of the
    # plane); on it, with d2 = 3, MT2 does not overrun iff d1 + 3 <= 10: d1 in [0, 7].
    ax, labels = _map(_step(3, 3), ["MT1.duration=0..12", "MT2.clock.period=1..20"])
    assert ("keeps pace with every clock (MT1.clock, MT2.clock) only on this segment"
            in labels)
    (seg,) = [line for line in ax.lines if line.get_label() == CONSISTENT + " only on this segment"]
    assert sorted(map(tuple, seg.get_xydata().tolist())) == [(0.0, 10.0), (7.0, 10.0)]
    assert "nominal (3, 10): consistent" in labels


def test_no_region_is_claimed_where_it_is_not_computed_exactly():
    # A clockless writer W: its events follow no clock tick, so keeping pace with R's
    # clock is not rate consistency there; nothing is shaded as consistent and the
    # legend says why, and the nominal point claims no verdict.
    sk = Skeleton.from_dict({"tasks": {"W": {"duration": 1, "outputs": ["x"]},
                                       "R": {"duration": 2, "period": 10, "inputs": ["x"]}},
                             "links": [{"from": "W:x", "to": "R:x", "protocol": "ASYN/SYN"}]})
    ax, labels = _map(sk, ["W.duration=0..20", "R.duration=0..20"])
    assert any("downstream of no clock tick: the consistent region is not drawn" in t
               for t in labels), labels
    assert not [p for p in ax.patches if str(p.get_label()).startswith("consistent")]
    assert "nominal (1, 2)" in labels


# ------------------------------------------------- a margin undecided below only


def test_a_margin_undecided_below_and_unbounded_above_is_printed_not_a_traceback():
    # fig11 on its processors, rtc.period alone, 200 firings per figure: the nominal
    # (period 10) is decided; the walk down from 10 spends its budget (the low end is
    # only bounded: proven schedulable down to some period), the walk up meets no end
    # (the high end is exact: unbounded, None). The renderer asserted a finite proven
    # high end and raised AssertionError (a traceback on the CLI).
    path = EXAMPLES / "fig11_fixed_order.yaml"
    r = sensitivity(load_skeleton(path), ["rtc.period"], formulas=False, verify=False,
                    max_events=200)
    m = r.margins["rtc.period"]
    assert r.schedulable is True and m.nominal_consistent and not m.exact
    lo, hi = m.bounds
    assert hi is None and m.high is None and lo is not None and lo <= 10
    out = CliRunner().invoke(app, ["sensitivity", str(path), "--vary", "rtc.period",
                                   "--max-events", "200", "--no-formulas", "--no-verify"])
    assert out.exit_code == 0 and out.exception is None, out.output
    row = next(line for line in out.output.splitlines()
               if line.split()[:1] == [m.parameter.symbol])
    assert f"BOUND: [{lo}, ∞) proven" in row and "unbounded" in row, row
