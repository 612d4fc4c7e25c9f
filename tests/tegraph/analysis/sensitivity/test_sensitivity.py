"""`tegraph sensitivity` on the paper's examples, with every value derived by hand.

The hand derivations use only spec §2-§4 (places, daters, overrun_at) and
the comments of the example files; each is written next to its assertion.
The checks against the analysis at points (examples and random skeletons) are in
``test_sensitivity_properties``.
"""

from __future__ import annotations

import json
import subprocess
import sys
from fractions import Fraction as F
from pathlib import Path

import pytest
import sympy

from tegraph import Skeleton, duration_margins, load_skeleton
from tegraph import sensitivity as _sensitivity
from tegraph.analysis.analyze import analyze_skeleton
from tegraph.analysis.sensitivity.parameters import parse_vary
from tegraph.errors import InputError
from tegraph.report import render_text, to_json

REPO = Path(__file__).resolve().parents[4]
EXAMPLES = REPO / "examples"
SCHEMA = json.loads((REPO / "docs" / "report.schema.json").read_text())


def sensitivity(*args, **kwargs):
    """The (max,+) answers (a processor per task), which this file derives by hand;
    the answers on processors are in ``test_sensitivity_processors``."""
    kwargs.setdefault("processors", False)
    return _sensitivity(*args, **kwargs)


def example(name: str) -> Skeleton:
    return load_skeleton(EXAMPLES / name)


def symbols(*names: str):
    return [sympy.Symbol(n, nonnegative=True) for n in names]


# ------------------------------------------------------------------ computed torque


def test_computed_torque_scaling_factor_and_margins():
    # Three groups (ASYN/ASYN links join nothing); no circuit crosses two tasks, so
    # each group's circuits are its clock's self-loop and one chain per task
    # (ratio = the duration). A group keeps its clock's pace iff every duration
    # is at most the period; a clocked task ends activation k-1 at
    # tick(k-1) + d <= tick(k) iff d <= period. So each duration is consistent
    # exactly on [0, period] (OBS.JL: 1; TG.JS, TF.TT.JS, CO.JS: 2; MOD.DYN: 6).
    # Scaled together by α: α/10 <= 1, α·3/10 <= 2 (CO.JS, the longest of the
    # control path), α·6/5 <= 6: α <= min(10, 20/3, 5) = 5, limited by MOD.DYN.
    r = sensitivity(example("computed_torque.yaml"))
    assert r.consistent and r.live
    assert r.scaling.factor == 5
    assert r.scaling.intervals == [(0, 5)]
    assert {x.group for x in r.scaling.limits} == {2}
    assert any(x.kind == "overrun" and x.task == "MOD.DYN" for x in r.scaling.limits)
    # Just beyond α = 5, MOD.DYN's first activation ends after 6 ms: overrun at 2.
    assert [x.activation for x in r.scaling.limits if x.kind == "overrun"] == [2]
    expected = {"OBS.JL.duration": 1, "TG.JS.duration": 2, "TF.TT.JS.duration": 2,
                "CO.JS.duration": 2, "MOD.DYN.duration": 6}
    for name, high in expected.items():
        m = r.margins[name]
        assert (m.low, m.high, m.intervals) == (0, high, [(0, high)]), name
        assert m.limits_low[0].kind == "range"
    # TF.TT.JS and CO.JS have no clock: they can only lose pace (messages pile up).
    assert {x.kind for x in r.margins["CO.JS.duration"].limits_high} == {"pace"}
    assert all(c.agrees for c in r.checks) and len(r.checks) >= 12


def test_computed_torque_period_formulas():
    # Each group's cycle time is the largest of its clock period and its
    # durations (one chain per task, no other circuit).
    r = sensitivity(example("computed_torque.yaml"))
    obs, tg, tf, co, dyn = symbols("d_OBS.JL", "d_TG.JS", "d_TF.TT.JS", "d_CO.JS", "d_MOD.DYN")
    assert [f.expression() for f in r.formulas] == [
        sympy.Max(1, obs), sympy.Max(2, tg, tf, co), sympy.Max(6, dyn)]
    control = r.formulas[1]
    assert control.exact and control.rate_consistent and control.cycle_time == 2
    (pace,) = control.pace
    assert pace.clock == "ctl" and not pace.empty
    assert sorted((list(c.items()), b) for c, b, _ in pace.inequalities) == [
        ([("CO.JS.duration", 1)], 2), ([("TF.TT.JS.duration", 1)], 2),
        ([("TG.JS.duration", 1)], 2)]


def test_computed_torque_duration_margins_are_period_minus_duration():
    # Same derivation: each task alone may grow to its clock's period.
    sk = example("computed_torque.yaml")
    assert duration_margins(sk) == {"OBS.JL": F(9, 10), "TG.JS": F(19, 10),
                                    "TF.TT.JS": F(9, 5), "CO.JS": F(17, 10),
                                    "MOD.DYN": F(24, 5)}


# ------------------------------------------------------------------ Figure 12


def test_fig12_no_factor_helps():
    # MT2 is bound to rtc (10 ms, through y) and to its own clock (4 ms): the
    # group's cycle time is at least 10 (rtc's self-loop) while MT2.clock's
    # tick runs every 4, so the place MT2.clock.tick -> MT2.activate is
    # unbounded whatever the durations: no factor and no duration helps.
    r = sensitivity(example("fig12_double_sync.yaml"))
    assert not r.consistent
    assert r.scaling.intervals == [] and r.scaling.factor is None
    assert not r.scaling.nominal_consistent
    assert (r.scaling.nearest_below, r.scaling.nearest_above) == (None, None)
    pace = [x for x in r.scaling.limits if x.kind == "pace"]
    assert pace and pace[0].clock == "MT2.clock" and pace[0].events == ["rtc.tick"]
    for name in ("MT1.duration", "MT2.duration"):
        assert r.margins[name].intervals == [] and not r.margins[name].nominal_consistent
    (formula,) = r.formulas
    mt1, mt2 = symbols("d_MT1", "d_MT2")
    assert formula.expression() == sympy.Max(10, mt1, mt2)
    never = next(p for p in formula.pace if p.clock == "MT2.clock")
    assert never.empty and never.blocking == ["rtc.tick"]
    assert r.exit_status == 1


def test_fig12_equal_periods_are_the_only_repair():
    # With the periods varied one at a time, the group is consistent only when
    # both clocks have one period: rtc = 4 (MT1 ends at 4(k-1) + 1, MT2 at
    # 4(k-1) + 1 + 2 = 4k - 1 <= 4k) or MT2.clock = 10 (MT2 ends at
    # 10(k-1) + 3 <= 10k). A single point each: not monotone, not an interval.
    r = sensitivity(example("fig12_double_sync.yaml"), ["rtc.period", "MT2.clock.period"],
                    formulas=False)
    assert r.margins["rtc.period"].intervals == [(4, 4)]
    assert r.margins["MT2.clock.period"].intervals == [(10, 10)]
    assert r.scaling is None


# ------------------------------------------------------------------ other examples


def test_overrun_in_step_nearest_factor():
    # MT2 reads y from MT1 (same 10 ms clocks, phase 0): its activation ends at
    # d1 + d2 after the tick, so it overruns iff d1 + d2 > 10. Nominal 6 + 6:
    # not consistent; scaled, 12α <= 10: α <= 5/6; alone, each d <= 4.
    r = sensitivity(example("overrun_in_step.yaml"))
    s = r.scaling
    assert not s.nominal_consistent and s.factor is None
    assert s.intervals == [(0, F(5, 6))]
    assert (s.nearest_below, s.nearest_above) == (F(5, 6), None)
    assert [x.task for x in s.limits] == ["MT2"]
    assert r.margins["MT1.duration"].intervals == [(0, 4)]
    assert not r.margins["MT1.duration"].nominal_consistent
    assert r.margins["MT2.duration"].intervals == [(0, 4)]


def test_overrun_margin_sees_what_slack_does_not():
    # The same with d1 = d2 = 3: slack 10 - 3 = 7 for both (their chains), but
    # MT2 ends at d1 + d2 = 6: each may grow by 10 - 6 = 4 only.
    sk = Skeleton.from_dict({"tasks": {
        "MT1": {"duration": 3, "period": 10, "outputs": ["y"]},
        "MT2": {"duration": 3, "period": 10, "inputs": ["y"], "outputs": ["u"]}},
        "links": [{"from": "MT1:y", "to": "MT2:y", "protocol": "ASYN/SYN"}]})
    report = analyze_skeleton(sk)
    assert report.tasks["MT1"].slack == 7
    assert duration_margins(sk, report) == {"MT1": 4, "MT2": 4}
    r = sensitivity(sk)
    assert r.margins["MT1.duration"].high == 7 and r.margins["MT2.duration"].high == 7


def test_rendezvous_scaling():
    # P (cp, phase 0) meets Q (cq, phase 5/2) on x: P.write:x(1) =
    # max(α, 5/2), Q ends at max(α, 5/2) + 2α <= 5/2 + 5: α <= 5/2 (for
    # α >= 5/2, 3α <= 15/2); P itself: max(α, 5/2) <= 5.
    r = sensitivity(example("rendezvous_two_clocks.yaml"))
    assert r.scaling.factor == F(5, 2)
    assert {x.task for x in r.scaling.limits if x.kind == "overrun"} == {"P", "Q"}
    # Alone: P <= 5 (its chain, and max(d, 5/2) <= 5), Q: 5/2 + d <= 15/2.
    assert r.margins["P.duration"].high == 5 and r.margins["Q.duration"].high == 5


def test_threads_sum_of_durations():
    # The thread circuit holds d_TG + d_TF + d_CO (1 token): it keeps the 2 ms
    # clock iff the sum is <= 2: α·6/5 <= 2, α <= 5/3; alone, each grows by
    # 2 - 6/5 = 4/5. The free-running thread LOG, DIAG has no clock: its
    # period d_LOG + d_DIAG follows any duration, always consistent.
    r = sensitivity(example("threads.yaml"))
    assert r.scaling.factor == F(5, 3)
    assert r.margins["TG.JS.duration"].high == F(11, 10)
    assert r.margins["CO.JS.duration"].high == F(13, 10)
    assert r.margins["LOG.duration"].intervals == [(0, None)]
    tg, tf, co, log, diag = symbols("d_TG.JS", "d_TF.TT.JS", "d_CO.JS", "d_LOG", "d_DIAG")
    assert r.formulas[0].expression() == sympy.Max(2, tg + tf + co)
    assert r.formulas[1].expression() == log + diag
    assert r.formulas[1].derivatives == {"LOG.duration": (1, 1), "DIAG.duration": (1, 1)}
    sk = example("threads.yaml")
    assert duration_margins(sk) == {"TG.JS": F(4, 5), "TF.TT.JS": F(4, 5), "CO.JS": F(4, 5),
                                    "LOG": None, "DIAG": None}


def test_ring_two_tokens_formula():
    # The ring A -> B -> C -> A holds 2 tokens (examples/ring_two_tokens.yaml):
    # its ratio is (d_A + d_B + d_C)/2; each chain is a circuit of its own.
    r = sensitivity(example("ring_two_tokens.yaml"))
    a, b, c, d = symbols("d_A", "d_B", "d_C", "d_D")
    assert r.formulas[0].expression() == sympy.Max(a, b, c, d, (a + b + c) / 2)
    ring = next(t for t in r.formulas[0].terms if t.tokens == 2)
    assert ring.coefficients == {"A.duration": 1, "B.duration": 1, "C.duration": 1}


def test_many_parameters_give_nominal_derivatives():
    # Above the formula limit: the terms critical at nominal and one-sided
    # derivatives. In the threads group at nominal the clock (2) is critical,
    # alone: every derivative is 0.
    r = sensitivity(example("threads.yaml"), max_formula_parameters=1)
    control = r.formulas[0]
    assert not control.exact
    assert control.derivatives == {p: (0, 0) for p in control.parameters}
    # The free thread: both durations on the only critical circuit, slope 1.
    assert r.formulas[1].exact is False
    assert r.formulas[1].derivatives == {"LOG.duration": (1, 1), "DIAG.duration": (1, 1)}


# ------------------------------------------------------------------ input


def test_vary_refusals_name_the_parameter():
    sk = example("computed_torque.yaml")
    with pytest.raises(InputError, match="unknown parameter 'X.duration'") as err:
        parse_vary(sk, ["X.duration"])
    assert err.value.where == "vary[0]"
    with pytest.raises(InputError, match="empty"):
        parse_vary(sk, ["MOD.DYN.duration=3..1"])
    with pytest.raises(InputError, match="below 0"):
        parse_vary(sk, ["MOD.DYN.duration=-1..2"])
    with pytest.raises(InputError, match="a period is > 0"):
        parse_vary(sk, ["dyn.period=0..2"])
    with pytest.raises(InputError, match="twice"):
        parse_vary(sk, ["dyn.period", "dyn.period=1..2"])
    with pytest.raises(InputError, match="not an exact number"):
        parse_vary(sk, ["dyn.period=x..2"])
    # MOD.DYN's nominal duration is 6/5 ms: a range must hold it (margins start there).
    with pytest.raises(InputError, match="leaves out its nominal value 6/5"):
        parse_vary(sk, ["MOD.DYN.duration=3..3"])
    with pytest.raises(InputError, match="nominal value 6"):
        parse_vary(sk, ["dyn.period=1..5"])


def test_ranges_are_exact_and_respected():
    r = sensitivity(example("computed_torque.yaml"), ["MOD.DYN.duration=0.5..5/2"])
    m = r.margins["MOD.DYN.duration"]
    assert (m.low, m.high) == (F(1, 2), F(5, 2))
    assert [x.kind for x in m.limits_low] == [x.kind for x in m.limits_high] == ["range"]
    # α·6/5 within [1/2, 5/2]: α in [5/12, 25/12], both ends set by the range.
    assert r.scaling.intervals == [(F(5, 12), F(25, 12))]
    assert r.scaling.factor == F(25, 12)


def test_private_clock_period_by_task_name():
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 3, "period": 4}}})
    r = sensitivity(sk, ["A.clock.period"])
    # d = 3 keeps pace with period P iff 3 <= P; the default range is (0, ∞).
    assert r.margins["A.clock.period"].intervals == [(3, None)]
    assert r.margins["A.clock.period"].parameter.low_open


def test_not_live_nothing_is_consistent():
    r = sensitivity(example("fig7a_circular_wait.yaml"))
    assert not r.live and r.scaling.intervals == []
    assert all(m.intervals == [] for m in r.margins.values())
    assert any("not live" in x.detail for x in r.scaling.limits)


# ------------------------------------------------------------------ output


def test_json_document_follows_its_schema():
    jsonschema = pytest.importorskip("jsonschema")
    for name in ("computed_torque.yaml", "fig12_double_sync.yaml", "threads.yaml"):
        doc = json.loads(to_json(sensitivity(example(name))))
        jsonschema.validate(doc, SCHEMA)
        assert doc["report"] == "sensitivity"
    doc = json.loads(to_json(sensitivity(example("computed_torque.yaml"))))
    assert doc["scaling_factor"] == "5"
    assert doc["margins"]["CO.JS.duration"]["high"] == "2"
    assert doc["groups"][1]["period_terms"][0]["coefficients"] in (
        {"TG.JS.duration": "1"}, {"TF.TT.JS.duration": "1"}, {"CO.JS.duration": "1"})


def test_text_report_ends_with_its_verdict():
    text = render_text(sensitivity(example("computed_torque.yaml")))
    last = text.strip().splitlines()[-1]
    assert last.startswith("verdict: consistent") and "factor 5" in last
    assert "Max(2, d_CO.JS, d_TF.TT.JS, d_TG.JS)" in text


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "tegraph.cli", *args], capture_output=True,
                          text=True, timeout=300, cwd=REPO)


def test_cli_exit_statuses_and_refusals(tmp_path):
    ok = run("sensitivity", "examples/computed_torque.yaml", "--json", "--no-processors")
    assert ok.returncode == 0, ok.stderr
    assert json.loads(ok.stdout)["scaling_factor"] == "5"
    bad = run("sensitivity", "examples/fig12_double_sync.yaml")
    assert bad.returncode == 1 and bad.stdout.strip().splitlines()[-1].startswith("verdict")
    refused = run("sensitivity", "examples/computed_torque.yaml", "--vary", "NOPE.duration")
    assert refused.returncode == 2 and "Traceback" not in refused.stderr
    assert "--vary[0]" in refused.stderr and "NOPE.duration" in refused.stderr
    empty = run("sensitivity", "examples/computed_torque.yaml", "--vary", "dyn.period=5..2")
    assert empty.returncode == 2 and "empty" in empty.stderr
    plot = run("sensitivity", "examples/computed_torque.yaml", "--plot", str(tmp_path / "x.svg"))
    assert plot.returncode == 2 and "one or two parameters" in plot.stderr


def test_cli_plot_never_overwrites(tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "dyn.svg"
    args = ["sensitivity", "examples/computed_torque.yaml", "--vary", "MOD.DYN.duration",
            "--vary", "dyn.period=1..12", "--plot", str(out)]
    first = run(*args)
    assert first.returncode == 0, first.stderr
    assert out.read_text().startswith("<?xml")
    again = run(*args)
    assert again.returncode == 2 and "exists" in again.stderr
    assert run(*args, "--force").returncode == 0


# ------------------------------------------------------------------ analyze's "can grow by"


STEP = {"tasks": {
    "MT1": {"duration": 3, "period": 10, "outputs": ["y"]},
    "MT2": {"duration": 3, "period": 10, "inputs": ["y"], "outputs": ["u"]}},
    "links": [{"from": "MT1:y", "to": "MT2:y", "protocol": "ASYN/SYN"}]}


def test_analyze_shows_how_much_each_duration_may_grow():
    # MT2 ends its activation at d1 + d2 after the common tick (spec §4), so
    # each may grow by 10 - 3 - 3 = 4 ms, while the slack (a period margin,
    # each task's own chain 10 - 3) says 7 ms.
    from tegraph import analyze
    from tegraph.report import render_text, to_json

    report = analyze(Skeleton.from_dict(STEP))
    assert [(t.slack, t.duration_margin, t.duration_margin_state)
            for t in report.tasks.values()] == [(7, 4, "exact"), (7, 4, "exact")]
    text = render_text(report)
    header = next(line for line in text.splitlines() if line.startswith("task"))
    assert "slack (period margin)" in header and "can grow by" in header
    row = next(line for line in text.splitlines() if line.startswith("MT2"))
    assert row.split()[-3:] == ["4", "ms", "no"] and "7 ms" in row
    doc = json.loads(to_json(report))
    assert doc["tasks"]["MT1"]["duration_margin"] == "4"
    assert doc["tasks"]["MT1"]["duration_margin_state"] == "exact"


def test_analyze_margins_not_consistent_unbounded_and_not_computed():
    from tegraph import analyze
    from tegraph.report import render_text

    # examples/overrun_in_step.yaml: 6 + 6 > 10, MT2 overruns at activation 2:
    # no growth keeps it consistent ("-"), though each slack is 4 ms.
    step = analyze(example("overrun_in_step.yaml"))
    assert {t.duration_margin_state for t in step.tasks.values()} == {"not consistent"}
    row = next(line for line in render_text(step).splitlines() if line.startswith("MT2"))
    assert "at activation 2" in row and "4 ms" in row and " - " in row
    # threads.yaml: the free-running thread LOG, DIAG has no clock: its period
    # follows its durations, nothing limits them.
    threads = analyze(example("threads.yaml"))
    assert threads.tasks["LOG"].duration_margin_state == "unbounded"
    assert threads.tasks["TG.JS"].duration_margin == F(4, 5)
    # Above margins_max_tasks the analysis says it did not compute them.
    skipped = analyze(example("threads.yaml"), margins_max_tasks=4)
    assert {t.duration_margin_state for t in skipped.tasks.values()} == {"not computed"}
    n = len(example("threads.yaml").tasks)
    assert f"not computed: {n} tasks, more than 4" in skipped.methods["duration_margins"]
    assert "the sensitivity analysis computes them" in render_text(skipped)


def test_analyze_margins_follow_the_report_schema():
    jsonschema = pytest.importorskip("jsonschema")
    from tegraph import analyze
    from tegraph.report import to_json

    schema = json.loads((REPO / "docs" / "report.schema.json").read_text())
    for name in ("computed_torque.yaml", "overrun_in_step.yaml", "threads.yaml"):
        for limit in (2_000, 0):
            doc = json.loads(to_json(analyze(example(name), design=False,
                                             margins_max_tasks=limit)))
            jsonschema.validate(doc, schema)


# ------------------------------------------------------------------ past int64


@pytest.mark.parametrize("exponent", [17, 18, 30])
def test_times_past_int64(exponent):
    # A alone: duration d = 10^e on its clock of period P = 4·10^e. Its circuits are the
    # clock's self-loop (P) and its chain (d), so it keeps pace iff d <= P: the durations
    # can grow 4 times together (factor P/d = 4) and d alone by P - d = 3·10^e.
    # 4·10^18 and 4·10^30 are past int64 (9.2·10^18): the oracle's "unreached" sentinel
    # -2**62 lies above real values there: "an event no marked place reaches" if used.
    d, p = 10**exponent, 4 * 10**exponent
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": d, "period": p}}})
    r = sensitivity(sk)
    assert r.consistent
    assert r.scaling.factor == 4 and r.scaling.intervals == [(0, 4)]
    m = r.margins["A.duration"]
    assert (m.low, m.high) == (0, p) and m.high - d == 3 * 10**exponent
    assert duration_margins(sk) == {"A": 3 * 10**exponent}


@pytest.mark.parametrize("high", ["1e19", "1e30"])
def test_a_period_range_past_int64(high):
    # Duration 1 on a clock of period P in [10, high]: it keeps pace for every P >= 1, so
    # the whole range is consistent, without a finite end.
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 10}}})
    r = sensitivity(sk, [f"A.clock.period=10..{high}"])
    m = r.margins["A.clock.period"]
    assert m.intervals == [(10, 10 ** int(high[2:]))]
    assert r.consistent


# ------------------------------------------------------------------ the map of two


def _two_clock_map(mt2_period):
    pytest.importorskip("matplotlib")
    from tegraph.report.sensitivity_plot import sensitivity_figure

    data = example("fig12_double_sync.yaml").to_dict()
    data["tasks"]["MT2"]["period"] = mt2_period
    r = sensitivity(Skeleton.from_dict(data), ["MT1.duration=0..20", "MT2.duration=0..20"])
    (ax,) = sensitivity_figure(r).axes
    legend = ax.get_legend()
    labels = [t.get_text() for t in legend.get_texts()]
    handles = legend.legend_handles
    return ax, dict(zip(labels, handles))


def test_two_parameter_map_shades_where_every_clock_is_kept():
    # Figure 12 with MT2's clock at 10 like rtc: the group {MT1, MT2} has the circuits
    # rtc (10), MT2.clock (10), MT1's chain (d1) and MT2's chain (d2): its cycle time is
    # max(10, d1, d2), and it keeps pace with both clocks exactly on d1 <= 10, d2 <= 10:
    # the square [0, 10]² of the window [0, 20]².
    from matplotlib.colors import to_hex

    ax, legend = _two_clock_map(10)
    shade = "keeps pace with every clock (rtc, MT2.clock)"
    assert shade in legend
    (patch,) = [p for p in ax.patches if p.get_label() == shade]
    corners = {(float(a), float(b)) for a, b in patch.get_path().vertices}
    assert corners == {(0, 0), (10, 0), (10, 10), (0, 10)}
    # One legend entry per clock boundary, each in its own colour (they shared red).
    rtc, mt2 = (legend[f"boundary of keeping pace with {c}"] for c in ("rtc", "MT2.clock"))
    assert to_hex(rtc.get_color()) != to_hex(mt2.get_color())
    colours = [to_hex(h.get_facecolor() if hasattr(h, "get_facecolor") else h.get_color())
               for h in legend.values()]
    assert len(set(colours)) == len(colours), legend.keys()


def test_two_parameter_map_says_when_no_region_keeps_every_clock():
    # As drawn by the paper: MT2.clock at 4 while rtc is 10. The cycle time is at least
    # 10 (rtc's self-loop) > 4: MT2.clock is never kept, nothing is shaded, and the
    # legend says so instead of drawing nothing.
    ax, legend = _two_clock_map(4)
    assert "nowhere here keeps pace with every clock (rtc, MT2.clock)" in legend
    assert "MT2.clock: not kept pace with anywhere here" in legend
    assert "boundary of keeping pace with rtc" in legend
    assert not [p for p in ax.patches if str(p.get_label()).startswith("keeps pace")]


def test_each_chain_s_first_use_at_the_ends_of_the_margins_and_at_the_scaling_factor():
    # Figure 4 unsynchronized on its one processor, MT1 the most urgent (0-1, 1-3, 3-5,
    # 5-6): first use 6 (spec §4c). The scaling factor is 10/6 (the four run back to back,
    # 10 ms of work in 10): then MT4 posts at 10, 10 ms after the sample. MT1 at 0 ends at
    # its release: MT2 starts at 0 and sees its write, u at 5; at 5 (its margin's high end)
    # MT1 0-5, MT2 5-7, MT3 7-9, MT4 9-10: 10. MT2 at 0 reads at 0, before MT1's write at 1:
    # the data waits for MT2 at 10, and MT3 (after MT1 10-11) 11-13, MT4 13-14: 14; at 6:
    # MT1 0-1, MT2 1-7, MT3 7-9, MT4 9-10: 10. MT3 at 0: it reads at 10 the write of 3,
    # MT4 (after MT1, MT2) 13-14: 14; at 6: 10. MT4 at 0: it reads at 10 the write of 5:
    # 10; at 5: 10.
    sk = load_skeleton(EXAMPLES / "fig4_pipeline_unsynchronized.yaml")
    r = _sensitivity(sk, formulas=False, chains=[["MT1", "MT2", "MT3", "MT4"]])
    assert r.scaling.factor == F(5, 3)
    (c,) = r.chains
    assert (c.processors, c.nominal.first_use, c.at_factor.first_use) == (True, 6, 10)
    ends = {name: (lo.first_use, hi.first_use) for name, (lo, hi) in c.margins.items()}
    assert ends == {"MT1.duration": (5, 10), "MT2.duration": (14, 10),
                    "MT3.duration": (14, 10), "MT4.duration": (10, 10)}
    assert r.to_dict()["chains"][0]["margins"]["MT2.duration"] == {
        "low": {"first_use": "14", "why_undecided": None},
        "high": {"first_use": "10", "why_undecided": None}}
    # With a processor per task the figures are §3's: 31 at the nominal values.
    alone = sensitivity(sk, formulas=False, margins=False, chains=[["MT1", "MT2", "MT3", "MT4"]])
    assert (alone.chains[0].processors, alone.chains[0].nominal.first_use) == (False, 31)
    assert "latency of the chain MT1 -> MT2 -> MT3 -> MT4 (first use with a processor per task" \
        in render_text(alone)
