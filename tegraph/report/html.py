"""Results -> compact HTML for notebooks: what Jupyter shows for a result.

A :class:`~tegraph.analysis.results.Report`, a
:class:`~tegraph.analysis.sensitivity.results.SensitivityResult`, an
:class:`~tegraph.design.explore.exploration.Exploration` and a
:class:`~tegraph.design.timeline.Timeline` display as a few small tables (or,
for a timeline, its drawing), headed by the verdict line of their text report,
word for word: one definition of each verdict. Every figure is the exact text
of the text report (``7/3 ms (≈2.33333)``); the full report stays
:func:`~tegraph.report.render_text`'s.

The result classes live on the floors that compute them, below this one: their
``_repr_html_`` is a thin call of :func:`tegraph.analysis.notebook.html`, which
names :func:`render_html` by its dotted name and imports it when a result is
first shown (see that module for why this keeps the floors' rule).
"""

from __future__ import annotations

import html
from collections.abc import Iterable, Sequence
from typing import Any

from ._format import human
from .registry import Renderers

__all__ = ["render_html"]

_RENDERERS = Renderers("HTML rendering", {
    "tegraph.analysis.results.Report": "tegraph.report.html:_report",
    "tegraph.analysis.sensitivity.results.SensitivityResult": "tegraph.report.html:_sensitivity",
    "tegraph.design.explore.exploration.Exploration": "tegraph.report.html:_exploration",
    "tegraph.design.timeline.Timeline": "tegraph.report.html:_timeline",
})

_ROWS_SHOWN = 50
"""Rows of a table shown in a notebook; the rest are counted (the text and JSON
reports hold them all)."""


def render_html(result: Any) -> str:
    """The HTML a notebook shows for ``result``: its verdict, then its figures as tables.

    Parameters
    ----------
    result : Report, SensitivityResult, Exploration or Timeline

    Returns
    -------
    str
        One ``<div class="tegraph">`` element, self-contained (no script, no style
        sheet); a timeline holds its SVG drawing when matplotlib is installed, else
        its text diagram.

    Raises
    ------
    TypeError
        No HTML rendering for that type.

    See Also
    --------
    tegraph.report.render_text : the full text report, whose last line heads the HTML.

    Examples
    --------
    >>> from tegraph import Skeleton, analyze
    >>> r = analyze(Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 10}}}))
    >>> page = render_html(r)
    >>> page.startswith('<div class="tegraph">'), "<td>10 ms</td>" in page
    (True, True)
    >>> r._repr_html_() == page
    True
    """
    function = _RENDERERS.find(result)
    body: str = function(result)
    return f'<div class="tegraph">{body}</div>'


def _verdict(result: Any) -> str:
    from .text import render_text

    lines = render_text(result).rstrip().splitlines()
    return lines[-1] if lines else ""


def _head(name: str, verdict: str) -> str:
    return f"<p><strong>{html.escape(name)}</strong>: {html.escape(verdict)}</p>"


def _table(caption: str, headers: Sequence[str], rows: Iterable[Sequence[Any]]) -> str:
    """A small HTML table; past :data:`_ROWS_SHOWN` rows the rest are counted."""
    rows = list(rows)
    head = "".join(f"<th>{html.escape(str(h))}</th>" for h in headers)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>"
                   for row in rows[:_ROWS_SHOWN])
    more = (f"<p>... and {len(rows) - _ROWS_SHOWN} more rows (the text and JSON reports "
            "hold them all)</p>" if len(rows) > _ROWS_SHOWN else "")
    return (f"<table><caption>{html.escape(caption)}</caption><thead><tr>{head}</tr></thead>"
            f"<tbody>{body}</tbody></table>{more}")


def _plain(value: Any) -> str:
    """A number as the text report writes it, without a unit."""
    return " ".join(human(value, "").split())


def _yes(value: bool | None) -> str:
    return "-" if value is None else ("yes" if value else "no")


# --------------------------------------------------------------------------- analyze


def _report(report: Any) -> str:
    from .text import critical_circuit_text

    u = report.unit
    parts = [_head(report.name, _verdict(report))]
    parts.append(_table("groups (spec §4)", ["group", "tasks", "clocks", "state", "period",
                                             "why"], (
        [g.index, ", ".join(g.tasks), ", ".join(g.clocks) or "-",
         "dead" if not g.live else ("rate-consistent" if g.rate_consistent else "unbounded"),
         human(g.period, u),
         critical_circuit_text(g, u).partition(": ")[2] if g.critical_circuit else "-"]
        for g in report.groups)))
    headers = ["task", "group", "period", "overrun", "slack", "critical"]
    s = report.schedule
    if s is not None:
        headers += ["processor", "priority", "period on processors", "overrun on processors",
                    "response"]
    rows = []
    for t in report.tasks.values():
        row = [t.name, t.group, human(t.period, u), t.overrun, human(t.slack, u),
               _yes(t.critical)]
        if s is not None:
            f = s.tasks[t.name]
            overrun = ("starved" if f.starved else f"at activation {f.overrun_at}"
                       if f.overrun_at is not None else "never" if f.decided else "undecided")
            row += [s.platform.processor_of[t.name], s.platform.priority[t.name],
                    human(f.period, u), overrun, human(f.response, u)]
        rows.append(row)
    caption = ("tasks: with a processor per task (§4) and on their processors (§4b)"
               if s is not None else "tasks, each on a processor of its own (§4)")
    parts.append(_table(caption, headers, rows))
    if report.deadlocks:
        parts.append(_table("deadlocks: token-free circuits", ["tasks", "advice"],
                            ([", ".join(d.tasks), d.advice] for d in report.deadlocks)))
    latency = report.design.latency if report.design is not None else []
    if latency:
        parts.append(_table("chains (end-to-end latency)", ["chain", "latency", "kind"], (
            [" -> ".join(c.chain), human(c.value, u), c.kind] for c in latency)))
    return "".join(parts)


# --------------------------------------------------------------------------- sensitivity


def _sensitivity(result: Any) -> str:
    from .sensitivity_text import formula_text

    u = result.unit
    parts = [_head(result.name, _verdict(result))]
    s = result.scaling
    if s is not None:
        if s.not_searched:
            factor = s.not_searched
        elif not s.nominal_consistent:
            factor = "none: not consistent as it is"
        else:
            factor = "unbounded" if s.factor is None else _plain(s.factor)
        parts.append(_table("every duration scaled by one factor",
                            ["parameters", "factor", "exact", "how"],
                            [[", ".join(s.parameters), factor, _yes(s.exact), s.method]]))
    if result.margins:
        parts.append(_table("each parameter alone", ["parameter", "nominal", "low", "high",
                                                     "exact"], (
            [name, human(m.parameter.nominal, u),
             human(m.low, u) if m.nominal_consistent else "-",
             "unbounded" if m.nominal_consistent and m.high is None else human(m.high, u),
             _yes(m.exact)]
            for name, m in result.margins.items())))
    if result.formulas:
        parts.append(_table("each group's period as a formula", ["group", "tasks", "period"], (
            [f.group, ", ".join(f.tasks), formula_text(f.expression())]
            for f in result.formulas)))
    return "".join(parts)


# --------------------------------------------------------------------------- explore


def _exploration(result: Any) -> str:
    from maxplus.scalar import display_text

    space = result.space
    parts = [_head(space.skeleton.name, _verdict(result))]
    judged = (f"{len(result.results)} of {space.size} variants judged, {result.kept} kept, "
              f"{len(result.front)} on the front")
    parts.append(f"<p>{html.escape(judged)}</p>")
    headers = ["variant", *(c.label for c in space.links),
               *(f"{c.name} ({space.skeleton.unit})" for c in space.clocks),
               *(f"on {unit}" for unit in space.placement(0)), *space.objectives]
    rows = []
    for r in result.front:
        entry = result.entry(r)
        rows.append([r.variant, *entry["links"].values(),
                     *(display_text(t) for t in space.periods(r.variant)),
                     *entry.get("processors", {}).values(),
                     *(display_text(r.objectives.get(n)) or "-" for n in space.objectives)])
    parts.append(_table("Pareto front", headers, rows))
    return "".join(parts)


# --------------------------------------------------------------------------- timeline


def _timeline(timeline: Any) -> str:
    from .plot import PlotUnavailableError, timeline_svg

    head = _head(timeline.name, _verdict(timeline))
    try:
        svg = timeline_svg(timeline)
    except PlotUnavailableError as exc:  # the text diagram, and how to get the drawing
        from .timeline_text import render_timeline

        return (head + f"<p>{html.escape(str(exc))}</p>"
                f"<pre>{html.escape(render_timeline(timeline))}</pre>")
    return head + svg[svg.index("<svg"):]
