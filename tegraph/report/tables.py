"""CSV tables of an analysis: one row per task, one per group, its verdict, and one per
chain and platform when the analysis has chains (spec §4c).

Every time is given twice: exact (``7/3``) and as a decimal (``2.33333333333333``,
15 significant digits, for spreadsheets), each column headed with its unit. The
figures with a processor per task (spec §4) come first, then those on the
processors (§4b), headed "on processors"; ``verdict.csv`` holds the one row of the
verdict (spec §5) and how it was obtained.
"""

from __future__ import annotations

import csv
import errno
from decimal import Context, Decimal
from fractions import Fraction
from pathlib import Path

from maxplus.scalar import exact_text

from ..analysis.processors import TaskOnProcessors
from ..analysis.results import Report, TaskReport
from ..errors import InputError

__all__ = ["write_csv"]


def _decimal(value: Fraction | None) -> str | None:
    """15 significant digits, exact for any size.

    >>> _decimal(Fraction(7, 3)), _decimal(Fraction(5)), _decimal(None)
    ('2.33333333333333', '5', None)
    """
    if value is None:
        return None
    d = Context(prec=15).divide(Decimal(value.numerator), Decimal(value.denominator))
    return format(d.normalize(), "f") if abs(d.adjusted()) < 15 else format(d, "e")


def write_csv(report: Report, directory: str | Path, overwrite: bool = False) -> list[Path]:
    """Write ``tasks.csv``, ``groups.csv`` and ``verdict.csv`` into an existing ``directory``,
    and ``chains.csv`` when the report has chains.

    Parameters
    ----------
    report : Report
    directory : str or path-like
        An existing directory (none is created).
    overwrite : bool
        Replace existing files; without it nothing is written when one exists.

    Returns
    -------
    list of pathlib.Path
        The files written (three, four with chains).

    Raises
    ------
    InputError
        ``directory`` does not exist or is not a directory.
    FileExistsError
        When a file exists and ``overwrite`` is False (nothing is written).
    """
    out = Path(directory)
    if not out.is_dir():
        what = "is not a directory" if out.exists() else "no such directory"
        raise InputError(f"{what}; expected an existing directory for the CSV files",
                         "directory", str(out))
    targets = [out / "tasks.csv", out / "groups.csv", out / "verdict.csv"]
    if report.chains:
        targets.append(out / "chains.csv")
    if not overwrite:
        for path in targets:
            if path.exists():
                raise FileExistsError(errno.EEXIST, "the file exists already; pass "
                                      "overwrite=True to replace it", str(path))
    u = report.unit
    s = report.schedule
    with open(targets[0], "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(["task", "group", f"period ({u})", f"period ({u}, decimal)",
                         "overrun", "overrun_at (activation)", f"slack ({u})",
                         f"slack ({u}, decimal)", "critical", "processor", "priority",
                         f"period on processors ({u})", f"period on processors ({u}, decimal)",
                         "overrun on processors", "overrun_at on processors (activation)",
                         f"response from release ({u})", f"response from release ({u}, decimal)",
                         f"response from tick ({u})", f"response from tick ({u}, decimal)"])
        for t in report.tasks.values():
            # `overrun` tells apart what an empty overrun_at cell cannot: never, no
            # clock, not live, undecided.
            row = [t.name, t.group, exact_text(t.period), _decimal(t.period),
                   t.overrun, t.overrun_at, exact_text(t.slack), _decimal(t.slack), t.critical]
            if s is None:  # a processor per task: nothing more than the figures above
                row += [None] * 10
            else:
                f = s.tasks[t.name]
                row += [s.platform.processor_of[t.name], s.platform.priority[t.name],
                        exact_text(f.period), _decimal(f.period), _on_processors(t, f),
                        f.overrun_at, exact_text(f.response), _decimal(f.response),
                        exact_text(f.response_from_tick), _decimal(f.response_from_tick)]
            writer.writerow(row)
    with open(targets[1], "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(["group", "tasks", "clocks", "live", "rate_consistent", f"period ({u})",
                         f"period ({u}, decimal)", "transient_k (activation)", "cyclicity",
                         f"critical_holding ({u})", "critical_tokens",
                         f"period on processors ({u})", f"period on processors ({u}, decimal)"])
        for g in report.groups:
            k, c = g.transient if g.transient is not None else (None, None)
            on = None if s is None else s.group_periods[g.index]
            writer.writerow([g.index, " ".join(g.tasks), " ".join(g.clocks), g.live,
                             g.rate_consistent, exact_text(g.period), _decimal(g.period), k, c,
                             exact_text(g.critical_holding), g.critical_tokens,
                             exact_text(on), _decimal(on)])
    with open(targets[2], "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(["name", "live", "consistent", "on processors", "schedulable",
                         "exit status", "method", "why undecided"])
        doc = report.schedule_summary()
        writer.writerow([report.name, report.live, report.consistent, s is not None,
                         report.schedulable, report.exit_status, doc["method"],
                         doc["why_undecided"]])
    if report.chains:
        _chains_csv(report, targets[3])
    return targets


def _on_processors(t: TaskReport, f: TaskOnProcessors) -> str:
    """The overrun verdict on processors in words, as ``TaskReport.overrun`` with a
    processor per task: one word for each case an empty ``overrun_at`` cannot tell.

    >>> from tegraph.analysis.processors import TaskOnProcessors
    >>> _on_processors(TaskReport(name="A", group=0, period=None, overrun_at=None,
    ...                           slack=None, critical=None, clock=None),
    ...                TaskOnProcessors(starved=True, decided=True))
    'starved'
    """
    if f.starved:
        return "starved"
    if f.overrun_at is not None:
        return f"at activation {f.overrun_at}"
    if f.stopped_after is not None:
        return "stopped"
    if t.clock is None:
        return "no clock"
    if t.period is None:
        return "not live"
    return "never" if f.decided else "undecided (budget)"


def _chains_csv(report: Report, path: Path) -> None:
    """One row per chain and platform: on its processors (when analyzed there), then with a
    processor per task; each figure exact and decimal, ``why_undecided`` where null."""
    u = report.unit
    figures = ("first_use", "age", "age_min", "reaction")
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(["chain", "platform"]
                        + [c for f in figures for c in (f"{f} ({u})", f"{f} ({u}, decimal)")]
                        + ["why_undecided"])
        for c in report.chains:
            platforms = ([("on its processors", c.on_processors)] if report.schedule else [])
            platforms.append(("processor per task", c.processor_per_task))
            for where, f in platforms:
                values = [getattr(f, name) for name in figures]
                writer.writerow([" ".join(c.tasks), where]
                                + [x for v in values for x in (exact_text(v), _decimal(v))]
                                + [f.why_undecided])
