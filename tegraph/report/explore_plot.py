"""Draw the Pareto front of an exploration, to SVG or PNG (matplotlib, the ``[plot]`` extra).

One panel per pair of objectives (a strip for a single objective): every
live and consistent variant in grey, the kept ones (also schedulable on their
processors) in blue,
the front in red. Values are exact in the result; only the drawing
coordinates are floats. A missing matplotlib is reported by
:class:`~tegraph.report.plot.PlotUnavailableError`, whose message says how to
install it.
"""

from __future__ import annotations

import itertools
import os
from pathlib import Path
from typing import Any

from ..design.explore import Exploration
from ..design.explore.evaluate import VariantResult
from ..errors import InputError
from .plot import plot_unavailable, save_figure

__all__ = ["draw_front"]

_FORMATS = (".svg", ".png")
_OTHER, _KEPT, _FRONT = "#bdbdbd", "#4878a8", "#d62728"


def draw_front(result: Exploration, path: str | os.PathLike[str], overwrite: bool = False
               ) -> Path:
    """Draw the objectives of the judged variants and the Pareto front.

    Parameters
    ----------
    result : Exploration
    path : str or path-like
        Ends in ``.svg`` or ``.png``.
    overwrite : bool
        Replace an existing file; without it an existing file is never touched.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InputError
        The name does not end in ``.svg`` or ``.png`` (``where="plot"``).
    FileExistsError
        The file exists and ``overwrite`` is False.
    PlotUnavailableError
        matplotlib is not installed.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from tegraph import load_skeleton
    >>> from tegraph.design.explore import explore_design
    >>> from tegraph.design.explore.space import design_space
    >>> from tegraph.report.plot import INSTALL_HINT, PlotUnavailableError
    >>> space = design_space(load_skeleton("examples/fig4_pipeline_synchronized.yaml"),
    ...                      clocks={"rtc": [5, 10, 20]}, objectives=["period", "load"])
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "front.svg"
    >>> try:
    ...     written = draw_front(explore_design(space, workers=0), out)
    ... except PlotUnavailableError as err:
    ...     written = INSTALL_HINT in str(err) and out
    >>> written == out
    True
    """
    target = _target(path)
    Figure = _figure_class()
    names = list(result.space.objectives)
    measured = [r for r in result.results.values() if r.live and r.consistent]
    front = {r.variant for r in result.front}
    pairs: list[tuple[str, str | None]] = [*itertools.combinations(names, 2)] or [(names[0], None)]
    columns = min(len(pairs), 3)
    rows = -(-len(pairs) // columns)
    fig = Figure(figsize=(4.2 * columns, 3.6 * rows + 0.6), layout="constrained")
    unit = result.space.skeleton.unit
    for k, (x_name, y_name) in enumerate(pairs):
        _draw_panel(fig.add_subplot(rows, columns, k + 1), x_name, y_name,
                    _point_sets(measured, front), unit)
    legend = _legend_entries(fig)
    if legend:
        fig.legend(list(legend.values()), list(legend), loc="outside lower center", ncol=3,
                   fontsize="small", frameon=False)
    how = "exhaustive" if result.exhaustive else f"{result.method}, not exhaustive"
    fig.suptitle(f"{result.space.skeleton.name}: {len(result.front)} design(s) on the front "
                 f"({how})", fontsize="medium")
    return save_figure(fig, target, overwrite)


def _target(path: str | os.PathLike[str]) -> Path:
    """The file to draw into: refused unless its suffix names a format drawn here."""
    target = Path(os.fspath(path))
    if target.suffix.lower() not in _FORMATS:
        raise InputError(f"cannot draw to {target.name!r}; expected a file name ending in "
                         ".svg or .png", "plot")
    return target


def _figure_class() -> Any:
    """matplotlib's Figure, or the error that says how to install matplotlib."""
    try:
        from matplotlib.figure import Figure
    except ImportError:
        raise plot_unavailable("drawing the front",
                               "the text and JSON reports need nothing") from None
    return Figure


def _point_sets(measured: list[VariantResult], front: set[Any]
                ) -> list[tuple[str, list[VariantResult], str]]:
    """The three kinds of points, drawn in this order: colour, variants, legend label."""
    return [(_OTHER, [r for r in measured if not r.kept], "live, consistent, not kept"),
            (_KEPT, [r for r in measured if r.kept and r.variant not in front], "kept"),
            (_FRONT, [r for r in measured if r.variant in front], "Pareto front")]


def _coordinates(chosen: list[VariantResult], x_name: str, y_name: str | None
                 ) -> list[tuple[float, float]]:
    """The variants' points in a panel (0 on a single objective's strip); a variant
    without a value for one of the two objectives is left out."""
    points = [(r.objectives.get(x_name), r.objectives.get(y_name) if y_name else 0)
              for r in chosen]
    return [(float(x), float(y)) for x, y in points if x is not None and y is not None]


def _draw_panel(ax: Any, x_name: str, y_name: str | None,
                sets: list[tuple[str, list[VariantResult], str]], unit: str) -> None:
    """One panel: a pair of objectives (or one on a strip), each kind of point in its colour."""
    for colour, chosen, label in sets:
        points = _coordinates(chosen, x_name, y_name)
        if points:
            xs, ys = zip(*points)
            on_front = colour == _FRONT
            ax.scatter(xs, ys, s=30 if on_front else 18, c=colour, label=label,
                       edgecolors="black" if on_front else "none", linewidths=0.5,
                       zorder=3 if on_front else 2)
    ax.set_xlabel(_label(x_name, unit))
    if y_name:
        ax.set_ylabel(_label(y_name, unit))
    else:
        ax.set_yticks([])
    ax.grid(linestyle=":", linewidth=0.5)


def _legend_entries(fig: Any) -> dict[str, object]:
    """One legend entry per kind of point, gathered from every panel (a panel may lack one)."""
    legend: dict[str, object] = {}
    for ax in fig.axes:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            legend.setdefault(label, handle)
    return legend


def _label(name: str, unit: str) -> str:
    key, _, chain = name.partition(":")
    if chain:
        what = {"latency": "first use"}.get(key, key)
        return f"{what} of {chain} ({unit}, on processors)"
    return {"period": "period ratio on processors (task period / designed period)",
            "load": "busiest processor's utilization on processors",
            "utilization": "utilization on processors, all processors"}.get(name, name)
