"""Draw a timing diagram like Figure 17 of the ORCCAD paper, to SVG or PNG.

matplotlib is optional (the ``[plot]`` extra): it is imported only when a
picture is drawn, and its absence is reported by
:class:`PlotUnavailableError`, whose message says how to install it. The
figures themselves are exact in the :class:`~tegraph.design.timeline.Timeline`;
only the drawing coordinates are floats.

One lane per processor, its jobs' processor time as bars in their task's
colour (a preempted job shows as several bars), one row per clock with its
ticks, the late activation of an overrun in red.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from maxplus.scalar import display_text

from ..design.timeline import Timeline
from ..errors import InputError, TegraphError

__all__ = [
    "INSTALL_HINT", "PlotUnavailableError", "draw_timeline", "matplotlib_available", "save_figure",
]

INSTALL_HINT = "pip install 'tegraph[plot]'"
_FORMATS = (".svg", ".png")
_LATE, _WAIT = "#d62728", "#9a9a9a"


class PlotUnavailableError(TegraphError):
    """Drawing needs matplotlib, which is not installed."""


def matplotlib_available() -> bool:
    """Whether matplotlib can be imported.

    >>> isinstance(matplotlib_available(), bool)
    True
    """
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return False
    return True


def _matplotlib() -> Any:
    try:
        import matplotlib  # noqa: F401  (first: a missing package fails here)
        from matplotlib.figure import Figure
    except ImportError:
        raise PlotUnavailableError(
            f"drawing a timing diagram needs matplotlib, which is not installed; install it "
            f"with: {INSTALL_HINT}  (or: pip install matplotlib); the text diagram needs "
            "nothing: leave out -o") from None
    return Figure


def draw_timeline(timeline: Timeline, path: str | os.PathLike[str], overwrite: bool = False
                  ) -> Path:
    """Draw ``timeline`` into an SVG or PNG file: one lane per processor.

    Each job's processor time is a bar in its task's colour, labelled ``T#k``
    where it fits (a preempted job shows as several bars); the late activation
    of the first overrun is hatched in red; one row per clock marks its ticks
    (red: a tick at which a task overruns); dotted lines bound each proven regime.

    Parameters
    ----------
    timeline : Timeline
    path : str or path-like
        Ends in ``.svg`` or ``.png`` (the format).
    overwrite : bool
        Replace an existing file; without it an existing file is never touched.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InputError
        The name does not end in ``.svg`` or ``.png``.
    FileExistsError
        The file exists and ``overwrite`` is False.
    PlotUnavailableError
        matplotlib is not installed (the message says how to install it).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from tegraph.model.skeleton import Skeleton
    >>> from tegraph.design.timeline import simulate_timeline
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2}}})
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "a.svg"
    >>> try:
    ...     written = draw_timeline(simulate_timeline(sk), out)
    ... except PlotUnavailableError as err:
    ...     written = INSTALL_HINT in str(err) and out  # no matplotlib: the message says how
    >>> written == out
    True
    """
    target = _target(path)
    Figure = _matplotlib()
    tl = timeline
    lanes = tl.processors
    clocks = [c for c in tl.ticks if any(tl.clocks[t] == c for t in tl.tasks)]
    rows = len(lanes) + len(clocks)
    fig = Figure(figsize=(10.0, 1.8 + 0.5 * rows), layout="constrained")
    ax = fig.add_subplot()
    y_lane = {p: rows - 1 - i for i, p in enumerate(lanes)}
    y_clock = {c: len(clocks) - 1 - i for i, c in enumerate(clocks)}
    colour = _task_colours(tl)
    _draw_jobs(ax, tl, y_lane, colour)
    _draw_ticks(ax, tl, y_clock)
    _draw_regimes(ax, tl)
    _draw_data_paths(ax, tl, y_lane)
    ax.set_yticks([y_lane[p] for p in lanes] + [y_clock[c] for c in clocks])
    ax.set_yticklabels([f"processor {p}" for p in lanes] + [f"clock {c}" for c in clocks])
    ax.set_ylim(-0.8, rows - 0.4)
    ax.set_xlim(0, float(tl.horizon))
    ax.set_xlabel(f"time ({tl.unit})")
    ax.grid(axis="x", linestyle=":", linewidth=0.5)
    ax.set_title(_title(tl))
    fig.legend(handles=_legend_handles(tl, colour), loc="outside lower center", ncol=4,
               fontsize="small", frameon=False)
    return save_figure(fig, target, overwrite)


def _target(path: str | os.PathLike[str]) -> Path:
    """The file to draw into: refused unless its suffix names a format drawn here."""
    target = Path(os.fspath(path))
    if target.suffix.lower() not in _FORMATS:
        raise InputError(f"cannot draw to {target.name!r}; expected a file name ending in "
                         ".svg or .png", where="path")
    return target


def _task_colours(tl: Timeline) -> dict[str, Any]:
    """Each task's colour, from a 20-colour palette (a task keeps its colour in every lane)."""
    from matplotlib import colormaps

    palette = colormaps["tab20"]
    return {t: palette(i % 20) for i, t in enumerate(tl.tasks)}


def _draw_jobs(ax: Any, tl: Timeline, y_lane: dict[str, int], colour: dict[str, Any]) -> None:
    """A bar per interval of processor time, in its lane; the late job's bars hatched red."""
    late = {(j.task, j.index) for j in tl.late_jobs}
    fits = 9.0 * 72 / float(tl.horizon)  # points per time unit, for an axis some 9 inches wide
    for i in tl.intervals:
        y, a, w = y_lane[i.processor], float(i.start), float(i.end - i.start)
        bad = (i.task, i.k) in late
        ax.broken_barh([(a, w)], (y - 0.35, 0.7), facecolors=colour[i.task],
                       edgecolors=_LATE if bad else "black", linewidth=1.2 if bad else 0.5,
                       hatch="//" if bad else None, zorder=2)
        label = f"{i.task}#{i.k}"
        if w * fits >= 4.2 * len(label) + 2:  # some 4.2 points a character at size 7
            ax.text(a + w / 2, y, label, ha="center", va="center", fontsize=7, zorder=3)


def _overrun_ticks(tl: Timeline) -> dict[str | None, set[Any]]:
    """Per clock, the ticks at which one of its tasks overruns (drawn red; an
    overrunning task has a clock)."""
    overrun: dict[str | None, set[Any]] = {}
    for t, k in tl.overrun_at.items():
        if k is not None:
            overrun.setdefault(tl.clocks[t], set()).add(tl.overrun_ticks[t])
    return overrun


def _draw_ticks(ax: Any, tl: Timeline, y_clock: dict[str, int]) -> None:
    """A row per clock: its ticks as black triangles, an overrun's tick as a larger red one."""
    overrun = _overrun_ticks(tl)
    for c in y_clock:
        xs = [x for x in tl.ticks[c] if x not in overrun.get(c, ())]
        ax.plot([float(x) for x in xs], [y_clock[c]] * len(xs), linestyle="none", marker="^",
                markersize=6, color="black", zorder=3)
        red = [float(x) for x in overrun.get(c, ()) if x <= tl.horizon]
        ax.plot(red, [y_clock[c]] * len(red), linestyle="none", marker="^", markersize=8,
                color=_LATE, zorder=3)


def _draw_regimes(ax: Any, tl: Timeline) -> None:
    """Dotted lines at the start and end of each proven regime within the drawing."""
    for r in tl.schedule.regimes:
        if r["start"] is not None and r["length"] and r["tasks"][0] not in tl.unsimulated:
            for x in (r["start"], r["start"] + r["length"]):
                if 0 < x <= tl.horizon:
                    ax.axvline(float(x), color=_WAIT, linestyle=":", linewidth=1, zorder=1)


_PATH = "#1f4e9a"
"""The colour of a chain's worst data path."""


def _draw_data_paths(ax: Any, tl: Timeline, y_lane: dict[str, int]) -> None:
    """Each chain's worst data path over the jobs: a line through its instants, each on
    its task's lane, from the sample (a circle) through each write and read to the
    output (a star), the figures beside it."""
    processor_of = tl.schedule.platform.processor_of
    for n, c in enumerate(tl.chains, 1):
        steps = [s for s in c.figures.worst if s.at <= tl.horizon]
        if not steps:
            continue
        xs = [float(s.at) for s in steps]
        ys = [y_lane[processor_of[s.task]] + 0.42 for s in steps]
        ax.plot(xs, ys, color=_PATH, linewidth=1.2, marker=".", zorder=4)
        ax.plot(xs[:1], ys[:1], color=_PATH, marker="o", linestyle="none", zorder=5)
        ax.plot(xs[-1:], ys[-1:], color=_PATH, marker="*", markersize=10, linestyle="none",
                zorder=5)
        f = c.figures
        ax.annotate(f"chain {n}: first use {display_text(f.first_use)} {tl.unit}",
                    (xs[-1], ys[-1]), textcoords="offset points", xytext=(4, 4),
                    fontsize=7, color=_PATH, zorder=5)


def _title(tl: Timeline) -> str:
    """The title: what is drawn, over which span, and the verdict it shows."""
    verdict = {True: "schedulable (proven)", False: "NOT schedulable",
               None: "undecided within the budget"}[tl.schedulable]
    return (f"{tl.name} on its processors (preemptive fixed priorities), 0-{float(tl.horizon):g} "
            f"{tl.unit}: {verdict}")


def _legend_handles(tl: Timeline, colour: dict[str, Any]) -> list[Any]:
    """The legend: the first tasks with their priorities, then the marks' meanings."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles: list[Any] = [Patch(facecolor=colour[t], edgecolor="black", label=f"{t} (prio "
                     f"{tl.priorities[t]})") for t in tl.tasks[:_KEYED]]
    handles += [Patch(facecolor="white", edgecolor=_LATE, hatch="//", label="late activation"),
                Line2D([], [], color="black", marker="^", linestyle="none", label="clock tick"),
                Line2D([], [], color=_LATE, marker="^", linestyle="none", label="overrun tick"),
                Line2D([], [], color=_WAIT, linestyle=":", label="proven regime")]
    if any(c.figures.worst for c in tl.chains):
        handles.append(Line2D([], [], color=_PATH, marker="*", label="worst data path "
                                                                     "(sample o, output *)"))
    return handles


_KEYED = 20
"""Tasks given a legend entry (the bars' labels name the others)."""


def save_figure(fig: Any, target: Path, overwrite: bool = False) -> Path:
    """Write a matplotlib figure to ``target`` (.svg or .png), reproducibly.

    Fixed metadata and SVG hash salt make the same figure give the same bytes;
    SVG text stays text (searchable, accessible), not glyph outlines. The file
    is opened exclusively unless ``overwrite``: nothing is replaced by accident.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    target : Path
        Its suffix, ``.svg`` or ``.png``, chooses the format.
    overwrite : bool
        Replace an existing file.

    Returns
    -------
    Path
        ``target``.

    Raises
    ------
    FileExistsError
        ``target`` exists and ``overwrite`` is false.
    """
    import matplotlib

    suffix = target.suffix.lower()
    metadata = {"Date": None} if suffix == ".svg" else {"Software": "tegraph"}
    try:
        with matplotlib.rc_context({"svg.fonttype": "none", "svg.hashsalt": "tegraph"}), \
                open(target, "wb" if overwrite else "xb") as out:
            fig.savefig(out, format=suffix[1:], metadata=metadata)
    except FileExistsError:
        raise FileExistsError(f"{target}: the file exists already; pass overwrite=True "
                              "to replace it") from None
    return target
