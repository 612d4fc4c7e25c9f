"""Draw a timing diagram like Figure 17 of the ORCCAD paper, to SVG or PNG.

matplotlib is optional (the ``[plot]`` extra): it is imported only when a
picture is drawn, and its absence is reported by
:class:`PlotUnavailableError`, whose message says how to install it. The
figures themselves are exact in the :class:`~tegraph.design.timeline.Timeline`;
only the drawing coordinates are floats.

One lane per processor, its jobs' processor time as bars in their task's
colour (a preempted job shows as several bars), under it a strip per task that
waits (a read, a rendezvous, a write; a deadlock's stuck event), one row per clock
with its ticks, the late activation of an overrun in red (no task is red), each
chain's worst data path over the jobs (spec §4c). The drawing is a list of layers
(:data:`LAYERS`) over one :class:`Frame`: an overlay is one more layer.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from maxplus.scalar import display_text

from ..design.timeline import Timeline
from ..errors import InputError, TegraphError

__all__ = [
    "INSTALL_HINT", "LAYERS", "Frame", "PlotUnavailableError", "draw_timeline",
    "matplotlib_available", "plot_unavailable", "save_figure", "timeline_figure", "timeline_svg",
]

INSTALL_HINT = "pip install '.[plot]'"
"""How to install matplotlib with tegraph: its ``plot`` extra, from the source directory
(where ``pip install .`` installed tegraph)."""
_FORMATS = (".svg", ".png")
_REPRODUCIBLE: dict[Any, Any] = {"svg.fonttype": "none", "svg.hashsalt": "tegraph"}
"""SVG text stays text, and the same figure gives the same bytes."""
_LATE, _WAIT, _STUCK = "#d62728", "#9a9a9a", "#3a3a3a"


class PlotUnavailableError(TegraphError):
    """Drawing needs matplotlib, which is not installed."""


def plot_unavailable(drawing: str, without: str) -> PlotUnavailableError:
    """The one message of a drawing that needs matplotlib where it is not installed:
    what needs it, the extra that installs it, and what works without it.

    >>> print(plot_unavailable("drawing a timing diagram", "leave out -o"))
    drawing a timing diagram needs matplotlib, which is not installed; install tegraph's \
plot extra: pip install '.[plot]' in tegraph's source directory (or: pip install \
matplotlib); leave out -o
    """
    return PlotUnavailableError(
        f"{drawing} needs matplotlib, which is not installed; install tegraph's plot extra: "
        f"{INSTALL_HINT} in tegraph's source directory (or: pip install matplotlib); {without}")


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
        raise plot_unavailable("drawing a timing diagram",
                               "the text diagram needs nothing: leave out -o") from None
    return Figure


def draw_timeline(timeline: Timeline, path: str | os.PathLike[str], overwrite: bool = False,
                  layers: Sequence[Layer] | None = None) -> Path:
    """Draw ``timeline`` into an SVG or PNG file: one lane per processor.

    Each job's processor time is a bar in its task's colour, labelled ``T#k``
    where it fits (a preempted job shows as several bars); the late activation
    of the first overrun is hatched and edged in red (the one colour no task
    takes); below each lane, a strip per task that waits shows when its
    activation waits without the processor (to start: a read, a rendezvous, its
    thread; to end: a write for its reader) and, in a deadlock, the event it is
    stuck at for ever; one row per clock marks its ticks (red: a tick at which a
    task overruns); dotted lines bound each proven regime. The legend lists only
    what is drawn; a note under the axis says what a default window shows and how
    to see more.

    Parameters
    ----------
    timeline : Timeline
    path : str or path-like
        Ends in ``.svg`` or ``.png`` (the format).
    overwrite : bool
        Replace an existing file; without it an existing file is never touched.
    layers : sequence of callables, optional
        What is drawn, in order: each takes the :class:`Frame` and returns the
        legend entries of what it drew (default :data:`LAYERS`; an overlay, such as
        a chain's data path, is one more layer: ``[*LAYERS, overlay]``).

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
    return save_figure(timeline_figure(timeline, layers), target, overwrite)


def timeline_svg(timeline: Timeline) -> str:
    """The drawing of :func:`draw_timeline` as SVG text, for a notebook or a page.

    Raises
    ------
    PlotUnavailableError
        matplotlib is not installed (the message says how to install it).

    Examples
    --------
    >>> from tegraph.model.skeleton import Skeleton
    >>> from tegraph.design.timeline import simulate_timeline
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2}}})
    >>> try:
    ...     svg = timeline_svg(simulate_timeline(sk))
    ... except PlotUnavailableError:
    ...     svg = "<svg>"  # no matplotlib
    >>> "<svg" in svg
    True
    """
    import io

    import matplotlib

    fig = timeline_figure(timeline)
    out = io.StringIO()
    with matplotlib.rc_context(_REPRODUCIBLE):
        fig.savefig(out, format="svg", metadata={"Date": None})
    return out.getvalue()


def timeline_figure(timeline: Timeline, layers: Sequence[Layer] | None = None) -> Any:
    """The matplotlib Figure that :func:`draw_timeline` saves (its artists carry the
    legend's labels: a test or a notebook reads what is drawn without pixels)."""
    Figure = _matplotlib()
    tl = timeline
    rows = _rows(tl)
    height = sum(h for _, _, h in rows)
    fig = Figure(figsize=(10.0, 1.9 + 0.5 * height), layout="constrained")
    ax = fig.add_subplot()
    frame = Frame(ax, tl, rows, _task_colours(tl))
    handles: list[Any] = []
    for layer in (LAYERS if layers is None else layers):
        handles += layer(frame)
    ax.set_yticks([frame.y[kind, name] for kind, name, _ in rows])
    lazy = frozenset(p.name for p in tl.schedule.platform.processors if not p.preemptive)
    ax.set_yticklabels([_row_label(kind, name, lazy) for kind, name, _ in rows])
    for label, (kind, _, _) in zip(ax.get_yticklabels(), rows):
        if kind == "wait":
            label.set_fontsize("small")
    ax.set_ylim(-0.6, height - 0.4)
    # A margin of 1 % each side: a mark at either end (an overrun's tick at the end of
    # the drawing) is drawn whole, inside the frame.
    pad = float(tl.horizon - tl.start) / 100
    ax.set_xlim(float(tl.start) - pad, float(tl.horizon) + pad)
    xlabel = f"time ({tl.unit})"
    if tl.window:  # what the default window shows, and how to see more
        import textwrap

        xlabel += "\n" + "\n".join(textwrap.wrap(tl.window.replace("`", ""), 140))
    ax.set_xlabel(xlabel, fontsize="small" if tl.window else None)
    ax.grid(axis="x", linestyle=":", linewidth=0.5)
    ax.set_title(_title(tl))
    fig.legend(handles=handles, loc="outside lower center", ncol=4, fontsize="small",
               frameon=False)
    return fig


@dataclass
class Frame:
    """What every layer draws on: the axes, the timeline, the rows and the colours.

    ``y[kind, name]`` is the height of a row: ``("lane", processor)`` a processor's
    jobs, ``("wait", task)`` the strip of a task's waits under its processor's lane,
    ``("clock", clock)`` a clock's ticks.
    """

    ax: Any
    timeline: Timeline
    rows: list[tuple[str, str, float]]
    colour: dict[str, Any]
    y: dict[tuple[str, str], float] = field(init=False)

    def __post_init__(self) -> None:
        top = sum(h for _, _, h in self.rows)
        self.y = {}
        for kind, name, h in self.rows:
            top -= h
            self.y[kind, name] = top + h / 2 - 0.5

    def fits(self, width: float, label: str) -> bool:
        """Whether ``label`` fits in a bar ``width`` time units wide (some 4.2 points a
        character at size 7, on an axis some 9 inches wide)."""
        points = 9.0 * 72 / float(self.timeline.horizon - self.timeline.start)
        return width * points >= 4.2 * len(label) + 2


Layer = Callable[[Frame], list[Any]]


def _rows(tl: Timeline) -> list[tuple[str, str, float]]:
    """The rows, top down: each processor's lane and its tasks' wait strips, then the
    clocks; with their heights."""
    waiting = ({w.task for w in tl.waits if w.end > tl.start} | {st.task for st in tl.stuck}
               | {b.task for b in tl.blocking if b.end > tl.start})
    rows: list[tuple[str, str, float]] = []
    for p in tl.schedule.platform.processors:
        rows.append(("lane", p.name, 1.0))
        prio = tl.priorities
        rows += [("wait", t, 0.4) for t in sorted(p.tasks, key=lambda t: -prio[t])
                 if t in waiting]
    rows += [("clock", c, 0.8) for c in tl.ticks if any(tl.clocks[t] == c for t in tl.tasks)]
    return rows


def _row_label(kind: str, name: str, lazy: frozenset[str] = frozenset()) -> str:
    """A row's label; a non-preemptive processor's lane (§4d) says so."""
    if kind == "lane" and name in lazy:
        return f"{name} (non-preemptive)"
    return {"lane": f"processor {name}", "wait": f"{name} waits",
            "clock": f"clock {name}"}[kind]


def _target(path: str | os.PathLike[str]) -> Path:
    """The file to draw into: refused unless its suffix names a format drawn here."""
    target = Path(os.fspath(path))
    if target.suffix.lower() not in _FORMATS:
        raise InputError(f"cannot draw to {target.name!r}; expected a file name ending in "
                         ".svg or .png", where="path")
    return target


# tab20 without its reds (the late activation's and the overrun tick's colour) and its
# greys (the waits' and the regimes'): no task is ever painted in a colour that means
# something else.
_PALETTE = tuple(i for i in range(20) if i not in (6, 7, 14, 15))


def _task_colours(tl: Timeline) -> dict[str, Any]:
    """Each task's colour, from a 16-colour palette (a task keeps its colour in every
    lane): no red, no grey."""
    from matplotlib import colormaps

    palette = colormaps["tab20"]
    return {t: palette(_PALETTE[i % len(_PALETTE)]) for i, t in enumerate(tl.tasks)}


def _draw_jobs(frame: Frame) -> list[Any]:
    """A bar per interval of processor time, in its lane; the late job's bars hatched red."""
    from matplotlib.patches import Patch

    ax, tl, colour = frame.ax, frame.timeline, frame.colour
    late = {(j.task, j.index) for j in tl.late_jobs}
    drawn_late = False
    shown: dict[str, None] = {}
    for i in tl.visible:
        y, a, w = frame.y["lane", i.processor], float(i.start), float(i.end - i.start)
        bad = (i.task, i.k) in late
        drawn_late = drawn_late or bad
        shown[i.task] = None
        ax.broken_barh([(a, w)], (y - 0.35, 0.7), facecolors=colour[i.task],
                       edgecolors=_LATE if bad else "black", linewidth=1.2 if bad else 0.5,
                       hatch="//" if bad else None, zorder=2)
        label = f"{i.task}#{i.k}"
        if frame.fits(w, label):
            ax.text(a + w / 2, y, label, ha="center", va="center", fontsize=7, zorder=3)
    keyed = [t for t in tl.tasks if t in shown or t in {w.task for w in tl.waits}
             or t in {st.task for st in tl.stuck}]
    handles: list[Any] = [Patch(facecolor=colour[t], edgecolor="black",
                                label=f"{t} (prio {tl.priorities[t]})") for t in keyed[:_KEYED]]
    if drawn_late:
        handles.append(Patch(facecolor="white", edgecolor=_LATE, hatch="//",
                             label="late activation"))
    return handles


def _draw_waits(frame: Frame) -> list[Any]:
    """In each task's strip, when its activation waits without its processor."""
    from matplotlib.patches import Patch

    ax, tl = frame.ax, frame.timeline
    kinds: set[str] = set()
    for w in tl.waits:
        if w.end <= tl.start or ("wait", w.task) not in frame.y:
            continue
        a = max(w.start, tl.start)
        kinds.add(w.kind)
        # The task's colour, darkened: the hatch of a light colour would not show.
        edge = tuple(0.6 * c for c in frame.colour[w.task][:3])
        ax.broken_barh([(float(a), float(w.end - a))], (frame.y["wait", w.task] - 0.12, 0.24),
                       facecolors="white", edgecolors=edge, linewidth=0.8,
                       hatch=_WAIT_HATCH[w.kind], zorder=2)
    return [Patch(facecolor="white", edgecolor="#555555", hatch=_WAIT_HATCH[k],
                  label=_WAIT_LABEL[k]) for k in ("start", "end") if k in kinds]


_WAIT_HATCH = {"start": "....", "end": "\\\\"}
_WAIT_LABEL = {"start": "waits to start (a read, a rendezvous, its thread)",
               "end": "done, waits to end (a write for its reader)"}


def _draw_blocking(frame: Frame) -> list[Any]:
    """In each task's strip, when its job waits for a less urgent one holding a
    non-preemptive processor (§4d), with the blocker's name where it fits."""
    from matplotlib.patches import Patch

    ax, tl = frame.ax, frame.timeline
    drawn = False
    for b in tl.blocking:
        if b.end <= tl.start or ("wait", b.task) not in frame.y:
            continue
        a, y = max(b.start, tl.start), frame.y["wait", b.task]
        w = float(b.end - a)
        ax.broken_barh([(float(a), w)], (y - 0.12, 0.24), facecolors="white",
                       edgecolors=_BLOCKED, linewidth=0.8, hatch="xxxx", zorder=2)
        label = f"by {b.by}#{b.by_k}"
        if frame.fits(w, label):
            ax.text(float(a) + w / 2, y + 0.2, label, ha="center", va="bottom", fontsize=6,
                    color=_BLOCKED, zorder=3)
        drawn = True
    return [Patch(facecolor="white", edgecolor=_BLOCKED, hatch="xxxx",
                  label="blocked by a less urgent job (non-preemptive)")] if drawn else []


_BLOCKED = "#7a4f00"


def _draw_stuck(frame: Frame) -> list[Any]:
    """A deadlock: from when each task is stuck, to the end, with the event it waits at."""
    from matplotlib.patches import Patch

    ax, tl = frame.ax, frame.timeline
    if not tl.stuck:
        return []
    for st in tl.stuck:
        a = max(st.since, tl.start)
        y = frame.y["wait", st.task]
        ax.broken_barh([(float(a), float(tl.horizon - a))], (y - 0.12, 0.24),
                       facecolors=_STUCK, edgecolors="black", linewidth=0.8, hatch="xx",
                       zorder=2)
        ax.text(float(a) + float(tl.horizon - tl.start) / 200, y, f"stuck at {st.event}",
                ha="left", va="center", fontsize=7, color="white", zorder=3,
                bbox={"facecolor": _STUCK, "edgecolor": "none", "pad": 0.5})
    return [Patch(facecolor=_STUCK, edgecolor="black", hatch="xx",
                  label="stuck for ever (a deadlock)")]


def _overrun_ticks(tl: Timeline) -> dict[str | None, set[Any]]:
    """Per clock, the ticks at which one of its tasks overruns (drawn red; an
    overrunning task has a clock)."""
    overrun: dict[str | None, set[Any]] = {}
    for t, k in tl.overrun_at.items():
        if k is not None:
            overrun.setdefault(tl.clocks[t], set()).add(tl.overrun_ticks[t])
    return overrun


def _draw_ticks(frame: Frame) -> list[Any]:
    """A row per clock: its ticks as black triangles, an overrun's tick as a larger red
    one (drawn whole at the ends of the window)."""
    from matplotlib.lines import Line2D

    ax, tl = frame.ax, frame.timeline
    overrun = _overrun_ticks(tl)
    any_tick = any_red = False
    for kind, c, _ in frame.rows:
        if kind != "clock":
            continue
        y = frame.y[kind, c]
        xs = [float(x) for x in tl.ticks[c]
              if tl.start <= x <= tl.horizon and x not in overrun.get(c, ())]
        red = [float(x) for x in overrun.get(c, ()) if tl.start <= x <= tl.horizon]
        any_tick, any_red = any_tick or bool(xs), any_red or bool(red)
        ax.plot(xs, [y] * len(xs), linestyle="none", marker="^", markersize=6,
                color="black", zorder=3, clip_on=False)
        ax.plot(red, [y] * len(red), linestyle="none", marker="^", markersize=8,
                color=_LATE, zorder=3, clip_on=False)
    return ([Line2D([], [], color="black", marker="^", linestyle="none", label="clock tick")]
            * any_tick + [Line2D([], [], color=_LATE, marker="^", linestyle="none",
                                 label="overrun tick")] * any_red)


def _draw_regimes(frame: Frame) -> list[Any]:
    """Dotted lines at the start and end of each proven regime within the drawing (none
    for a part that holds a deadlock)."""
    from matplotlib.lines import Line2D

    ax, tl = frame.ax, frame.timeline
    drawn = False
    dead = set(tl.dead_tasks)
    for r in tl.schedule.regimes:
        # A part holding a deadlock repeats only its clocks' ticks piling up: no line.
        if r["start"] is not None and r["length"] and r["tasks"][0] not in tl.unsimulated \
                and not dead.intersection(r["tasks"]):
            for x in (r["start"], r["start"] + r["length"]):
                if tl.start < x <= tl.horizon:
                    ax.axvline(float(x), color=_WAIT, linestyle=":", linewidth=1, zorder=1)
                    drawn = True
    return [Line2D([], [], color=_WAIT, linestyle=":", label="proven regime")] * drawn


_PATH = "#1f4e9a"
"""The colour of a chain's worst data path."""


def _draw_data_paths(frame: Frame) -> list[Any]:
    """Each chain's worst data path over the jobs: a line through its instants, each on
    its task's lane, from the sample (a circle) through each write and read to the
    output (a star), the figures beside it."""
    from matplotlib.lines import Line2D

    ax, tl = frame.ax, frame.timeline
    processor_of = tl.schedule.platform.processor_of
    drawn = False
    for n, c in enumerate(tl.chains, 1):
        steps = [s for s in c.figures.worst if tl.start <= s.at <= tl.horizon]
        if not steps:
            continue
        drawn = True
        xs = [float(s.at) for s in steps]
        ys = [frame.y["lane", processor_of[s.task]] + 0.42 for s in steps]
        ax.plot(xs, ys, color=_PATH, linewidth=1.2, marker=".", zorder=4)
        ax.plot(xs[:1], ys[:1], color=_PATH, marker="o", linestyle="none", zorder=5)
        ax.plot(xs[-1:], ys[-1:], color=_PATH, marker="*", markersize=10, linestyle="none",
                zorder=5)
        f = c.figures
        ax.annotate(f"chain {n}: first use {display_text(f.first_use)} {tl.unit}",
                    (xs[-1], ys[-1]), textcoords="offset points", xytext=(4, 4),
                    fontsize=7, color=_PATH, zorder=5)
    return [Line2D([], [], color=_PATH, marker="*",
                   label="worst data path (sample o, output *)")] * drawn


LAYERS: tuple[Layer, ...] = (_draw_jobs, _draw_waits, _draw_blocking, _draw_stuck, _draw_ticks,
                              _draw_regimes, _draw_data_paths)
"""What :func:`draw_timeline` draws, in order (an overlay is one more layer)."""


def _title(tl: Timeline) -> str:
    """The title: what is drawn, over which span, and the verdict it shows."""
    verdict = {True: "schedulable (proven)", False: "NOT schedulable",
               None: "undecided within the budget"}[tl.schedulable]
    if tl.stuck:
        verdict += " (deadlock)"
    kind = ("preemptive fixed priorities"
            if all(p.preemptive for p in tl.schedule.platform.processors)
            else "fixed priorities, some processors non-preemptive")
    return (f"{tl.name} on its processors ({kind}), "
            f"{display_text(tl.start)}-{display_text(tl.horizon)} {tl.unit}: {verdict}")


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
        with matplotlib.rc_context(_REPRODUCIBLE), \
                open(target, "wb" if overwrite else "xb") as out:
            fig.savefig(out, format=suffix[1:], metadata=metadata)
    except FileExistsError:
        raise FileExistsError(f"{target}: the file exists already; pass overwrite=True "
                              "to replace it") from None
    return target
