"""Draw a sensitivity result: period against one parameter, or the map of two.

matplotlib is optional (the ``[plot]`` extra), as for
:mod:`tegraph.report.plot`. Every figure drawn comes exact from the result:
the period curves are the maxima of the formula's terms (evaluated exactly
at every breakpoint, then drawn as straight segments between them), the
regions are polygons whose vertices come from the exact double description;
only the drawing coordinates are floats.

- One parameter: each group's period (cycle time) against the parameter, the
  values where the group is consistent shaded, the nominal value marked.
- Two parameters: for each group that depends on them, the cells of its
  period formula (which circuit is critical where), where it keeps pace with
  every clock (pale yellow, each clock's boundary outlined), inside it where
  it is consistent, with no overrun either (green, exact:
  :mod:`tegraph.analysis.sensitivity.region`), the edges beyond which an
  overrun begins, and the nominal point with its verdict.
"""

from __future__ import annotations

import os
from fractions import Fraction
from pathlib import Path

from maxplus.scalar import display_text

from ..analysis.sensitivity.polyhedra import Polyhedron
from ..analysis.sensitivity.region import ConsistentRegion, consistent_region
from ..analysis.sensitivity.results import GroupFormulaReport, SensitivityResult
from ..errors import InputError
from .plot import matplotlib_available, plot_unavailable, save_figure

__all__ = ["draw_sensitivity", "plot_parameters", "sensitivity_figure"]

_FORMATS = (".svg", ".png")
_SHADE, _CURVE, _PACE = "#c7e9c0", "#4878a8", "#d62728"
_PACE_ONLY = "#fdf1b8"
"""Keeps pace with every clock but overruns: pale yellow, under the consistent green."""
_NOT_CONSISTENT, _CONSISTENT_POINT, _OVERRUN = "#7f0000", "#006d2c", "black"
_CONSISTENT_LINE = "#41ab5d"
_CLOCK_COLOURS = ["#d62728", "#1f77b4", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2"]
"""One colour per clock's boundary (two clocks never share one)."""
_CELL_GREYS = ["#f2f2f2", "#e0e0e0", "#cccccc", "#ebebeb", "#d6d6d6", "#c2c2c2"]
"""The cells of the period formula in greys: colour is kept for what the legend names."""


def plot_parameters(result: SensitivityResult) -> int:
    """How many parameters a drawing would show (1 or 2 can be drawn)."""
    return len(result.parameters)


def _window(result: SensitivityResult, k: int) -> tuple[Fraction, Fraction]:
    p = result.parameters[k]
    if p.high is not None:
        return p.low, p.high
    ends = [b for m in result.margins.values() for _, b in m.intervals if b is not None]
    ends += [a for m in result.margins.values() for a, _ in m.intervals]
    top = max([2 * p.nominal, Fraction(1), *(Fraction(3, 2) * e for e in ends)])
    return p.low, top


def _value(formula: GroupFormulaReport, point: dict[str, Fraction]) -> Fraction:
    return max((t.constant + sum((c * point[n] for n, c in t.coefficients.items()),
                                 Fraction(0))) / t.tokens for t in formula.terms)


def draw_sensitivity(result: SensitivityResult, path: str | os.PathLike[str],
                     overwrite: bool = False) -> Path:
    """Draw the result for one or two parameters into an SVG or PNG file.

    Raises
    ------
    InputError
        Not ``.svg``/``.png``, or not one or two parameters (``where``: ``plot``).
    FileExistsError
        The file exists and ``overwrite`` is False.
    PlotUnavailableError
        matplotlib is not installed.
    """
    target = Path(os.fspath(path))
    suffix = target.suffix.lower()
    if suffix not in _FORMATS:
        raise InputError(f"cannot draw to {target.name!r}; expected a file name ending in "
                         ".svg or .png", where="plot")
    n = plot_parameters(result)
    if n not in (1, 2):
        raise InputError(f"a drawing shows one or two parameters; {n} are varied (name one "
                         "or two with `vary`)", where="plot")
    if result.formulas is None:
        raise InputError("a drawing needs the period formulas (formulas=True)", where="plot")
    if not matplotlib_available():
        raise plot_unavailable("drawing the sensitivity", "the text report needs nothing")
    return save_figure(sensitivity_figure(result), target, overwrite)


def sensitivity_figure(result: SensitivityResult):
    """The matplotlib Figure that :func:`draw_sensitivity` saves (one or two parameters).

    Parameters
    ----------
    result : SensitivityResult
        With one or two parameters and its formulas (else :class:`InputError`).

    Returns
    -------
    matplotlib.figure.Figure
        Its artists carry the labels of the legend: a test (or a notebook) can
        read what is drawn without pixels.
    """
    n = plot_parameters(result)
    if n not in (1, 2) or result.formulas is None:
        raise InputError("a drawing needs one or two parameters and their formulas",
                         where="plot")
    if not matplotlib_available():
        raise plot_unavailable("drawing the sensitivity", "the text report needs nothing")
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 5.0), layout="constrained")
    if n == 1:
        _one(fig, result)
    else:
        _two(fig, result)
    return fig


def _one(fig, result: SensitivityResult) -> None:
    p = result.parameters[0]
    low, high = _window(result, 0)
    ax = fig.add_subplot()
    margin = result.margins[p.name]
    for a, b in margin.intervals:
        right = high if b is None else min(b, high)
        if a == right:
            ax.axvline(float(a), color=_SHADE, linewidth=3, zorder=0)
        else:
            ax.axvspan(float(a), float(right), color=_SHADE, zorder=0)
    for f in result.formulas or ():
        if p.name not in f.parameters:
            continue
        breaks = {low, high}
        for t in f.terms:  # where two terms cross, the maximum may bend
            for u in f.terms:
                # Exact slopes: ``int / int`` would make the crossings floats.
                cu = Fraction(t.coefficients.get(p.name, 0), t.tokens)
                cv = Fraction(u.coefficients.get(p.name, 0), u.tokens)
                if cu != cv:
                    x = (_at_zero(u, p.name, result) - _at_zero(t, p.name, result)) / (cu - cv)
                    if low < x < high:
                        breaks.add(x)
        xs = sorted(breaks)
        ys = [_value(f, {**_nominal(result), p.name: x}) for x in xs]
        ax.plot([float(x) for x in xs], [float(y) for y in ys], color=_CURVE, linewidth=1.5,
                label=f"group {f.group} ({', '.join(f.tasks)})")
    ax.axvline(float(p.nominal), color="black", linestyle=":", linewidth=1, label="nominal")
    ax.set_xlim(float(low), float(high))
    ax.set_ylim(bottom=0)
    ax.set_xlabel(f"{p.name} ({result.unit})")
    ax.set_ylabel(f"period / cycle time ({result.unit})")
    ax.set_title(f"{result.name}: period against {p.name}; consistent values shaded")
    ax.grid(linestyle=":", linewidth=0.5)
    ax.legend(fontsize="small")


def _nominal(result: SensitivityResult) -> dict[str, Fraction]:
    return {p.name: p.nominal for p in result.parameters}


def _at_zero(term, name: str, result: SensitivityResult) -> Fraction:
    point = {**_nominal(result), name: Fraction(0)}
    return (term.constant + sum((c * point[n] for n, c in term.coefficients.items()),
                                Fraction(0))) / term.tokens


def _two(fig, result: SensitivityResult) -> None:
    """Per group: the formula's cells (greys, each annotated with its critical term),
    the region where the group keeps pace with every clock shaded and labelled, and
    each clock's own boundary in a colour of its own."""
    px, py = result.parameters
    window = (*_window(result, 0), *_window(result, 1))
    groups = [f for f in result.formulas or () if px.name in f.parameters
              or py.name in f.parameters]
    nominal = _nominal(result)
    for k, f in enumerate(groups[:4]):
        ax = fig.add_subplot(1, min(len(groups), 4), k + 1)
        _draw_cells(ax, f, px.name, py.name, window, nominal)
        found = _draw_pace(ax, result, f, window, nominal) if f.pace else None
        if found is not None:
            _draw_consistent(ax, found)
        _draw_clock_boundaries(ax, f, px.name, py.name, window, nominal)
        _draw_nominal(ax, result, found)
        _frame(ax, result, f, window)


def _draw_cells(ax, f: GroupFormulaReport, x: str, y: str, window, nominal) -> None:
    """The cell where each term of the formula is the largest, in greys, annotated."""
    for i, t in enumerate(f.terms):
        cell = _cell(f, i, x, y, window, nominal)
        if cell:
            ax.fill([float(a) for a, _ in cell], [float(b) for _, b in cell],
                    facecolor=_CELL_GREYS[i % len(_CELL_GREYS)], edgecolor="grey",
                    linewidth=0.5, zorder=0)
            cx = sum(float(a) for a, _ in cell) / len(cell)
            cy = sum(float(b) for _, b in cell) / len(cell)
            ax.annotate(_term_text(t), (cx, cy), ha="center", fontsize="x-small")


def _draw_pace(ax, result: SensitivityResult, f: GroupFormulaReport, window,
               nominal) -> ConsistentRegion | None:
    """Where the group keeps pace with all its clocks at once (pale yellow); returns
    where, inside it, it is consistent (no overrun either), computed exactly by the
    oracle."""
    from matplotlib.lines import Line2D

    px, py = result.parameters
    every = _pace_polygon(f.pace, px.name, py.name, window, nominal)
    clocks = ", ".join(r.clock for r in f.pace)
    if len(every) >= 3:
        ax.fill([float(a) for a, _ in every], [float(b) for _, b in every],
                facecolor=_PACE_ONLY, edgecolor="none", zorder=1,
                label=f"keeps pace with every clock ({clocks})")
    elif every:  # periods equal only on a line: a segment (or a point)
        ax.plot([float(a) for a, _ in every], [float(b) for _, b in every],
                color=_PACE_ONLY, linewidth=9, solid_capstyle="butt", zorder=1,
                label=f"keeps pace with every clock ({clocks}) only on this "
                      f"{'segment' if len(every) == 2 else 'point'}")
    else:
        ax.add_line(Line2D([], [], color=_PACE_ONLY, linewidth=6,
                           label=f"nowhere here keeps pace with every clock "
                                 f"({clocks})"))
    return _consistent(result, f, px.name, py.name, window, nominal)


def _draw_clock_boundaries(ax, f: GroupFormulaReport, x: str, y: str, window,
                           nominal) -> None:
    """Each clock's own boundary of keeping pace, in a colour and line style of its own."""
    from matplotlib.lines import Line2D

    for c, region in enumerate(f.pace):
        colour = _CLOCK_COLOURS[c % len(_CLOCK_COLOURS)]
        shape = _pace_polygon([region], x, y, window, nominal)
        if shape:
            xs = [float(a) for a, _ in shape] + [float(shape[0][0])]
            ys = [float(b) for _, b in shape] + [float(shape[0][1])]
            ax.plot(xs, ys, color=colour, linewidth=1.5, zorder=2,
                    linestyle=("-", "--", "-.", ":")[c % 4],
                    label=f"boundary of keeping pace with {region.clock}")
        else:
            ax.add_line(Line2D([], [], color=colour, linestyle=":",
                               label=f"{region.clock}: not kept pace with anywhere here"))


def _draw_nominal(ax, result: SensitivityResult, found: ConsistentRegion | None) -> None:
    """The nominal point, with its verdict when the consistent region was computed."""
    px, py = result.parameters
    verdict = ("" if found is None or found.why_not is not None else
               ": consistent" if found.nominal_consistent else ": NOT CONSISTENT")
    ax.plot([float(px.nominal)], [float(py.nominal)],
            marker="x" if verdict == ": NOT CONSISTENT" else "o", markersize=8,
            color=_NOT_CONSISTENT if verdict == ": NOT CONSISTENT" else (
                _CONSISTENT_POINT if verdict else "black"),
            linestyle="none", zorder=4,
            label=f"nominal ({display_text(px.nominal)}, {display_text(py.nominal)})"
                  f"{verdict}")


def _frame(ax, result: SensitivityResult, f: GroupFormulaReport, window) -> None:
    px, py = result.parameters
    x0, x1, y0, y1 = window
    ax.set_xlim(float(x0), float(x1))
    ax.set_ylim(float(y0), float(y1))
    ax.set_xlabel(f"{px.name} ({result.unit})")
    ax.set_ylabel(f"{py.name} ({result.unit})")
    ax.set_title(f"group {f.group}: where it is consistent; critical circuit by region "
                 "(greys)", fontsize="small")
    ax.legend(fontsize="x-small")


def _consistent(result: SensitivityResult, f: GroupFormulaReport, x: str, y: str, window,
                nominal) -> ConsistentRegion | None:
    """Where group ``f`` is consistent in the window (None: the result holds no model)."""
    model = result.models.get(f.group)
    if model is None:
        return None
    index = {p.name: i for i, p in enumerate(result.parameters)}
    pace = []
    for coefficients, bound, _ in (q for r in f.pace for q in r.inequalities):
        rest = sum((c * nominal[n] for n, c in coefficients.items() if n not in (x, y)),
                   Fraction(0))
        pace.append((coefficients.get(x, Fraction(0)), coefficients.get(y, Fraction(0)),
                     bound - rest))
    if any(r.empty for r in f.pace):
        pace.append((Fraction(0), Fraction(0), Fraction(-1)))  # 0 <= -1: nowhere
    values = [p.nominal for p in result.parameters]
    return consistent_region(model, index[x], index[y], window, pace, values)


def _draw_consistent(ax, region: ConsistentRegion) -> None:
    """The consistent polygon (green), where an overrun begins (its edges), or why not."""
    from matplotlib.lines import Line2D

    if region.why_not is not None:
        ax.add_line(Line2D([], [], color="grey", linestyle="none", marker="",
                           label=region.why_not))
        return
    label = "consistent: keeps pace with every clock and no overrun (exact)"
    shape = region.vertices
    if len(shape) >= 3:
        ax.fill([float(a) for a, _ in shape], [float(b) for _, b in shape],
                facecolor=_SHADE, edgecolor="none", zorder=1.5, label=label)
    elif shape:  # a point or a segment: drawn darker, it has no area to show
        ax.plot([float(a) for a, _ in shape], [float(b) for _, b in shape],
                color=_CONSISTENT_LINE, linewidth=4, marker="|", markersize=12, zorder=1.5,
                label=label + f" only on this {'segment' if len(shape) == 2 else 'point'}")
    else:
        ax.add_line(Line2D([], [], color=_SHADE, linewidth=6,
                           label="consistent nowhere here (exact)"))
    tasks = sorted({task for _, _, task in region.overrun_edges})
    for k, (u, v, _) in enumerate(region.overrun_edges):
        ax.plot([float(u[0]), float(v[0])], [float(u[1]), float(v[1])],
                color=_OVERRUN, linewidth=2.5, zorder=2.5,
                label=f"an overrun begins beyond ({', '.join(tasks)})" if k == 0 else None)


def _term_text(term) -> str:
    parts = [str(term.constant)] if term.constant else []
    parts += [f"{c}·{n}" if c != 1 else n for n, c in term.coefficients.items()]
    body = " + ".join(parts) or "0"
    return body if term.tokens == 1 else f"({body})/{term.tokens}"


def _affine_2d(term, x: str, y: str, nominal) -> tuple[Fraction, Fraction, Fraction]:
    """``term`` over the plane (x, y), the other parameters nominal: c + a·x + b·y."""
    c = term.constant
    a = b = Fraction(0)
    for n, k in term.coefficients.items():
        if n == x:
            a += k
        elif n == y:
            b += k
        else:
            c += k * nominal[n]
    return c / term.tokens, a / term.tokens, b / term.tokens


def _box(window) -> Polyhedron:
    x0, x1, y0, y1 = window
    P = Polyhedron(2)
    for row in (((Fraction(-1), Fraction(0)), -x0), ((Fraction(1), Fraction(0)), x1),
                ((Fraction(0), Fraction(-1)), -y0), ((Fraction(0), Fraction(1)), y1)):
        P.add(row)
    return P


def _ordered(points) -> list[tuple[Fraction, Fraction]]:
    import math

    if len(points) < 3:
        return sorted(points)  # a point or a segment (a period equal to another clock's)
    cx = sum(float(a) for a, _ in points) / len(points)
    cy = sum(float(b) for _, b in points) / len(points)
    return sorted(points, key=lambda q: math.atan2(float(q[1]) - cy, float(q[0]) - cx))


def _cell(f: GroupFormulaReport, i: int, x: str, y: str, window, nominal):
    P = _box(window)
    ci, ai, bi = _affine_2d(f.terms[i], x, y, nominal)
    for k, t in enumerate(f.terms):
        if k != i:  # t_k <= t_i
            ck, ak, bk = _affine_2d(t, x, y, nominal)
            P.add(((ak - ai, bk - bi), ci - ck))
    cell = _ordered(P.vertices())
    return cell if len(cell) >= 3 else []  # a cell of no area is not drawn


def _pace_polygon(regions, x: str, y: str, window, nominal):
    """The window's part where every region of ``regions`` holds (vertices in order)."""
    if any(region.empty for region in regions):
        return []
    P = _box(window)
    for coefficients, bound, _ in (q for region in regions for q in region.inequalities):
        a = coefficients.get(x, Fraction(0))
        b = coefficients.get(y, Fraction(0))
        rest = sum((c * nominal[n] for n, c in coefficients.items() if n not in (x, y)),
                   Fraction(0))
        P.add(((a, b), bound - rest))
    return _ordered(P.vertices())
