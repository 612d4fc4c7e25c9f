"""Text reports: units, decimals that cannot mislead, why a period is what it is, verdict last."""

from __future__ import annotations

import re
from fractions import Fraction

from hypothesis import given
from hypothesis import strategies as st

from tegraph import analyze, cycle_time, load_skeleton, render_text
from tegraph.report._format import decimal_text, human
from tests.paths import REPO

EXAMPLES = REPO / "examples"

fractions = st.fractions(min_value=-10**6, max_value=10**6, max_denominator=10**6)


@given(fractions, fractions)
def test_two_different_values_never_print_alike(a, b):
    if a != b:
        assert human(a, "ms") != human(b, "ms")


@given(fractions)
def test_a_fraction_never_looks_whole(value):
    # Printed as the input said it: an exact decimal when it terminates,
    # else the fraction with a rounded decimal beside that never looks whole.
    exact, _, beside = human(value, "ms").partition(" ms")
    assert Fraction(exact) == value
    if value.denominator == 1:
        assert beside == "" and exact == str(value)
    elif "/" in exact:
        digits = beside.strip(" ()").lstrip("≈")
        assert beside.startswith(" (≈") and Fraction(digits) != int(Fraction(digits))
    else:
        assert beside == "" and decimal_text(value) is None


def test_the_issue_example_slack_against_a_period():
    # 2399/20 = 119.95 exactly: printed as a decimal, exact, never rounded to "120".
    assert human(Fraction(2399, 20), "ms") == "119.95 ms"
    assert human(Fraction(120), "ms") == "120 ms"
    # 1/3 does not terminate: the fraction, and beside it a rounded decimal, marked.
    assert human(Fraction(1, 3), "ms") == "1/3 ms (≈0.333333)"


def test_huge_values_get_a_decimal_without_float_overflow():
    assert human(Fraction(10**400), "ms").endswith("(≈1.00000e+400)")


def test_ring_period_is_explained_term_by_term():
    # examples/ring_two_tokens.yaml derives the critical circuit by hand: the
    # ring through A (1 ms), B (2 ms) and C (5/3 ms) holds 2 tokens: 14/3 / 2.
    report = analyze(load_skeleton(EXAMPLES / "ring_two_tokens.yaml"))
    group = report.groups[0]
    assert group.critical_holding == Fraction(14, 3) and group.critical_tokens == 2
    text = render_text(report)
    assert "(1 + 2 + 5/3) ms over 2 tokens = 7/3 ms (≈2.33333), the period" in text


def test_every_text_report_ends_with_its_verdict():
    # Figure 7a deadlocks (circular wait of ASYN/SYN reads): exit status 1.
    dead = render_text(analyze(load_skeleton(EXAMPLES / "fig7a_circular_wait.yaml")))
    assert dead.splitlines()[-1] == ("verdict: NOT LIVE: 1 token-free circuit (group 0) "
                                     "(exit status 1)")
    fine = render_text(analyze(load_skeleton(EXAMPLES / "computed_torque.yaml")))
    assert fine.splitlines()[-1] == ("verdict: live, consistent and schedulable on its processors "
        "(exit status 0)")


def test_design_errors_with_a_clean_verdict_say_why_the_status_is_0(tmp_path):
    # Two clocks in one group that both keep pace (A every 10 ms, B every
    # 5 ms but only waiting for A's 10 ms messages would overrun; here B's
    # own clock is 10 ms too): consistent, yet rule 3 (one clock per group)
    # and rule 1 (B: clock + synchronizing input) are errors.
    path = tmp_path / "two_clocks.yaml"
    path.write_text("tasks:\n"
                    "  A: {duration: 1, period: 10, outputs: [x]}\n"
                    "  B: {duration: 1, period: 10, inputs: [x]}\n"
                    "links:\n  - {from: 'A:x', to: 'B:x', protocol: ASYN/SYN}\n")
    report = analyze(load_skeleton(path))
    assert report.exit_status == 0
    last = render_text(report).splitlines()[-1]
    assert last.startswith("verdict: live, consistent and schedulable on its processors "
                           "(exit status 0); the design section "
                           "lists 2 design-rule errors")
    assert "does not change the verdict of spec §5" in last


def test_rules_header_counts_what_it_lists():
    text = render_text(analyze(load_skeleton(EXAMPLES / "fig12_double_sync.yaml")))
    head = next(line for line in text.splitlines() if line.startswith("design rules"))
    listed = [line for line in text.splitlines() if re.match(r"  Rule \d \[", line)]
    n_error = sum("[error]" in line for line in listed)
    n_info = sum("[info]" in line for line in listed)
    assert head == f"design rules (ORCCAD section 6): {n_error} errors, {n_info} info"


def test_schedulability_columns_carry_their_unit():
    text = render_text(analyze(load_skeleton(EXAMPLES / "computed_torque.yaml")))
    assert re.search(r"period \(ms\)\s+work \(ms\)\s+group's RTA response \(ms\)\s+margin \(ms\)",
                     text)


def test_cycle_time_of_several_groups_names_each_period():
    # computed_torque: three groups on clocks of 1, 2 and 6 ms (no link
    # between them synchronizes), so the single figure is the slowest group.
    result = cycle_time(EXAMPLES / "computed_torque.yaml")
    assert [p.period for p in result.parts] == [1, 2, 6]
    assert result.unit == "ms"
    text = render_text(result)
    assert ("period:      6 ms (the slowest of 3 groups, which run at their own periods "
            "below)") in text
    assert "  group 0 [OBS.JL]: period 1 ms: obs.tick -> obs.tick: 1 ms over 1 token = 1 ms" in text
    assert text.splitlines()[-1] == "verdict: period 6 ms, certificate verified (exit status 0)"


def test_a_short_exact_decimal_far_from_one_is_exact_not_approximate():
    # 3/10^17 terminates with one significant digit: 3e-17 exactly, no "≈" (the
    # decimal alone, as the input would write it).
    assert human(Fraction(3, 10**17), "ms") == "3e-17 ms"
    assert human(Fraction(1, 256), "ms") == "0.00390625 ms"
    assert decimal_text(Fraction(1, 256)) is None


def test_json_text_is_the_standard_library_text_for_every_example(monkeypatch):
    # to_json writes with orjson; its bytes must be json.dumps(indent=2)'s, for analyze and
    # sensitivity documents alike, and the json fallback must give the same text.
    import json

    import orjson

    from tegraph import sensitivity
    from tegraph.report import to_document, to_json

    results = [analyze(load_skeleton(p)) for p in sorted((REPO / "examples").glob("*.yaml"))]
    results.append(sensitivity(load_skeleton(REPO / "examples" / "computed_torque.yaml")))
    expected = [json.dumps(to_document(r), indent=2, ensure_ascii=False) for r in results]
    assert [to_json(r) for r in results] == expected

    def refuse(*_args, **_kwargs):
        raise orjson.JSONEncodeError("as for an integer beyond 64 bits")

    monkeypatch.setattr(orjson, "dumps", refuse)
    assert [to_json(r) for r in results] == expected


def test_a_port_order_is_printed_as_the_file_writes_it():
    # examples/fig7b_wrong_order.yaml, by hand in its header: reading a before c
    # (the paper's Figure 11) makes it live; a user pastes the order into the file.
    text = render_text(analyze(load_skeleton(EXAMPLES / "fig7b_wrong_order.yaml")))
    assert "  MT2: inputs [a, c], outputs [tau]" in text.splitlines()
    assert "['a'" not in text  # no Python list syntax anywhere
