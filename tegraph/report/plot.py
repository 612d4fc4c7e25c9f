"""Draw a timing diagram like Figure 17 of the ORCCAD paper, to SVG or PNG.

matplotlib is optional (the ``[plot]`` extra): it is imported only when a
picture is drawn, and its absence is reported by
:class:`PlotUnavailableError`, whose message says how to install it. The
figures themselves are exact in the :class:`~tegraph.design.timeline.Timeline`;
only the drawing coordinates are floats.

One row per task (most urgent on top), its jobs' processor time as bars (a
preempted job shows as several bars), a thin line from a job's release to
its end (waiting for the processor or for data), an arrow under the row at
each tick of the task's clock, late jobs in red.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from ..design.timeline import Timeline
from ..errors import InputError, TegraphError

__all__ = [
    "INSTALL_HINT", "PlotUnavailableError", "draw_timeline", "matplotlib_available", "save_figure",
]

INSTALL_HINT = "pip install 'tegraph[plot]'"
_FORMATS = (".svg", ".png")
_RUN, _LATE, _WAIT = "#4878a8", "#d62728", "#9a9a9a"


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
    """Draw ``timeline`` into an SVG or PNG file.

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
    target = Path(os.fspath(path))
    suffix = target.suffix.lower()
    if suffix not in _FORMATS:
        raise InputError(f"cannot draw to {target.name!r}; expected a file name ending in "
                         ".svg or .png", where="path")
    Figure = _matplotlib()
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    rows = timeline.tasks
    H = float(timeline.horizon)
    fig = Figure(figsize=(10.0, 1.6 + 0.55 * len(rows)), layout="constrained")
    ax = fig.add_subplot()
    y_of = {t: len(rows) - 1 - i for i, t in enumerate(rows)}
    for job in timeline.jobs:
        y = y_of[job.task]
        end = float(job.finish) if job.finish is not None else H
        ax.hlines(y, float(job.release), end, colors=_WAIT, linewidth=1, zorder=1)
        bars = [(float(a), float(b - a)) for a, b in job.segments]
        if bars:
            ax.broken_barh(bars, (y - 0.3, 0.6), facecolors=_LATE if job.late else _RUN,
                           edgecolors="black", linewidth=0.5, zorder=2)
    for t in rows:
        clock = timeline.clocks[t]
        ticks = [float(x) for x in timeline.ticks.get(clock, [])] if clock else []
        if ticks:
            ax.plot(ticks, [y_of[t] - 0.42] * len(ticks), linestyle="none", marker="^",
                    markersize=6, color="black", zorder=3)
    ax.set_yticks([y_of[t] for t in rows])
    ax.set_ylim(-0.8, len(rows) - 0.4)
    ax.set_xlim(0, H)
    ax.set_xlabel(f"time ({timeline.unit})")
    ax.grid(axis="x", linestyle=":", linewidth=0.5)
    title = f"{timeline.name}: preemptive fixed priorities over 0-{H:g} {timeline.unit}"
    if timeline.deadlocks:
        # The picture of a dead design must not look like a quiet one.
        on = sorted({t for d in timeline.deadlocks for t in d.tasks}, key=rows.index)
        title += f"\nDEADLOCK: a token-free circuit through {', '.join(on)}"
    ax.set_title(title)
    dead = set(timeline.dead_tasks)
    ax.set_yticklabels([f"{t}  (prio {timeline.priorities[t]})" + ("  DEADLOCK" if t in dead
                                                                    else "") for t in rows])
    fig.legend(handles=[Patch(facecolor=_RUN, edgecolor="black", label="computing"),
                        Patch(facecolor=_LATE, edgecolor="black", label="late job"),
                        Line2D([], [], color=_WAIT, label="released, waiting"),
                        Line2D([], [], color="black", marker="^", linestyle="none",
                               label="clock tick")],
               loc="outside lower center", ncol=4, fontsize="small", frameon=False)
    return save_figure(fig, target, overwrite)


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
