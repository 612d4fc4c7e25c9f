"""What a notebook shows for a result: the HTML is parsed back and its figures checked.

Each result type's ``_repr_html_`` is the report floor's :func:`render_html`; the
tables are read back with the standard library's HTML parser and compared with
figures derived by hand (in comments) and with the text report's verdict line.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from fractions import Fraction
from html.parser import HTMLParser

import pytest

from tegraph import Skeleton, analyze, load_skeleton, sensitivity, simulate_timeline
from tegraph.analysis import notebook
from tegraph.api import explore
from tegraph.report import plot, render_text
from tegraph.report._format import human
from tegraph.report.html import render_html
from tests.paths import REPO

TORQUE = REPO / "examples" / "computed_torque.yaml"
FIG4 = REPO / "examples" / "fig4_pipeline_synchronized.yaml"


class _Tables(HTMLParser):
    """The page's first paragraph and each table as {caption, headers, rows}."""

    def __init__(self) -> None:
        super().__init__()
        self.tables: list[dict] = []
        self.paragraphs: list[str] = []
        self._cell: list[str] | None = None
        self._row: list[str] | None = None
        self._where = ""

    def handle_starttag(self, tag, attrs):
        if tag == "table":
            self.tables.append({"caption": "", "headers": [], "rows": []})
        elif tag == "tr":
            self._row = []
        elif tag in ("td", "th", "caption", "p"):
            self._cell, self._where = [], tag

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None and self._row is not None:
            self._row.append("".join(self._cell))
        elif tag == "caption" and self._cell is not None:
            self.tables[-1]["caption"] = "".join(self._cell)
        elif tag == "p" and self._cell is not None:
            self.paragraphs.append("".join(self._cell))
        elif tag == "tr" and self._row is not None:
            key = "headers" if self._where == "th" else "rows"
            self.tables[-1][key] = self._row if key == "headers" else [*self.tables[-1]["rows"],
                                                                      self._row]
            self._row = None
        if tag in ("td", "th", "caption", "p"):
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


def parsed(page: str) -> _Tables:
    p = _Tables()
    p.feed(page)
    p.close()
    return p


def table(page: _Tables, caption_start: str) -> list[dict[str, str]]:
    t = next(t for t in page.tables if t["caption"].startswith(caption_start))
    return [dict(zip(t["headers"], row)) for row in t["rows"]]


def test_a_report_shows_its_verdict_groups_and_tasks():
    report = analyze(TORQUE)
    page = parsed(report._repr_html_())
    # The heading is the name and the text report's verdict line, word for word.
    assert page.paragraphs[0] == f"computed-torque: {render_text(report).splitlines()[-1]}"
    # computed_torque.yaml by hand: clocks obs 1, ctl 2, dyn 6 ms drive three groups
    # (OBS.JL; TG.JS -> TF.TT.JS -> CO.JS; MOD.DYN), each at its clock's period.
    groups = table(page, "groups")
    assert [(g["tasks"], g["period"]) for g in groups] == [
        ("OBS.JL", "1 ms"), ("TG.JS, TF.TT.JS, CO.JS", "2 ms"), ("MOD.DYN", "6 ms")]
    assert groups[2]["why"] == "dyn.tick -> dyn.tick: 6 ms over 1 token = 6 ms, the period"
    tasks = {t["task"]: t for t in table(page, "tasks")}
    assert list(tasks) == list(report.tasks)
    # On the one CPU, rate-monotonic: OBS.JL (1 ms) is the most urgent (3), so its job
    # of 0.1 ms is never preempted: response 0.1 ms; MOD.DYN (6 ms) the least (1).
    assert (tasks["OBS.JL"]["priority"], tasks["OBS.JL"]["response"]) == ("3", "0.1 ms")
    assert tasks["MOD.DYN"]["priority"] == "1" and tasks["MOD.DYN"]["period"] == "6 ms"
    assert all(t["processor"] == "default" for t in tasks.values())
    # Slack of OBS.JL: 1 ms period - 0.1 ms duration.
    assert tasks["OBS.JL"]["slack"] == "0.9 ms"


def test_a_dead_skeleton_shows_its_token_free_circuit():
    report = analyze(REPO / "examples" / "fig7a_circular_wait.yaml")
    page = parsed(render_html(report))
    assert "NOT LIVE" in page.paragraphs[0]
    dead = table(page, "deadlocks")
    assert len(dead) == len(report.deadlocks) >= 1
    assert dead[0]["tasks"] == ", ".join(report.deadlocks[0].tasks)


def test_a_fraction_is_shown_exactly_and_names_are_escaped():
    # A period of 7/3 ms does not terminate as a decimal: the exact fraction, the
    # rounded decimal beside it, as in the text report.
    sk = Skeleton.from_dict({"name": "<b>bold</b>", "tasks": {
        "A": {"duration": 1, "period": "7/3"}}})
    raw = render_html(analyze(sk))
    assert "<b>" not in raw and "&lt;b&gt;bold&lt;/b&gt;" in raw
    tasks = table(parsed(raw), "tasks")
    assert tasks[0]["period"] == "7/3 ms (≈2.33333)"
    assert tasks[0]["slack"] == "4/3 ms (≈1.33333)"  # 7/3 - 1


def test_a_sensitivity_result_shows_its_factor_margins_and_formulas():
    result = sensitivity(load_skeleton(TORQUE))
    page = parsed(result._repr_html_())
    assert page.paragraphs[0].endswith(render_text(result).splitlines()[-1])
    # On its one CPU every duration may grow by 5/3 (test_on_processors derives it
    # by Lehoczky-Sha-Ding's scheduling points).
    [scaling] = table(page, "every duration")
    assert scaling["factor"] == "5/3 (≈1.66667)" and scaling["exact"] == "yes"
    margins = {m["parameter"]: m for m in table(page, "each parameter")}
    assert set(margins) == set(result.margins)
    # MOD.DYN.duration is 1.2 ms in the file; its high end is the result's own.
    dyn = result.margins["MOD.DYN.duration"]
    assert margins["MOD.DYN.duration"]["nominal"] == "1.2 ms"
    assert margins["MOD.DYN.duration"]["high"] == human(dyn.high, "ms")
    formulas = table(page, "each group")
    assert len(formulas) == len(result.formulas) == 3


def test_an_exploration_shows_its_front():
    found = explore(load_skeleton(FIG4), links=["MT1:x1 -> MT2:x1=ASYN/SYN,ASYN/ASYN"],
                    clocks=["rtc=10,20"], workers=0)
    page = parsed(found._repr_html_())
    assert page.paragraphs[0].endswith(render_text(found).splitlines()[-1])
    # Two protocols times two periods: four variants, every one judged.
    assert page.paragraphs[1].startswith("4 of 4 variants judged")
    front = table(page, "Pareto front")
    assert [int(r["variant"]) for r in front] == [r.variant for r in found.front]
    assert {r["rtc (ms)"] for r in front} <= {"10", "20"}
    assert {r["MT1:x1 -> MT2:x1"] for r in front} <= {"ASYN/SYN", "ASYN/ASYN"}


def test_a_timeline_shows_its_drawing():
    tl = simulate_timeline(load_skeleton(TORQUE))
    raw = tl._repr_html_()
    page = parsed(raw)
    assert page.paragraphs[0].endswith(render_text(tl).splitlines()[-1])
    svg = ET.fromstring(raw[raw.index("<svg"):raw.rindex("</svg>") + len("</svg>")])
    texts = " ".join(t for t in svg.itertext())
    # The title's verdict and the lane of the one processor, as text (not outlines).
    assert "schedulable (proven)" in texts and "processor default" in texts
    for task in ("OBS.JL", "MOD.DYN"):
        assert task in texts


def test_a_timeline_without_matplotlib_shows_its_text_diagram(monkeypatch):
    def unavailable():
        raise plot.PlotUnavailableError(f"needs matplotlib; install it with: {plot.INSTALL_HINT}")

    monkeypatch.setattr(plot, "_matplotlib", unavailable)
    tl = simulate_timeline(load_skeleton(TORQUE))
    raw = tl._repr_html_()
    assert "<svg" not in raw and plot.INSTALL_HINT.replace("'", "&#x27;") in raw
    assert "<pre>" in raw and "default |" in raw


def test_the_hook_names_the_report_floor_and_refuses_other_types():
    assert notebook.RENDERER == "tegraph.report.html:render_html"
    with pytest.raises(TypeError, match="no HTML rendering for a Fraction"):
        render_html(Fraction(1, 3))
