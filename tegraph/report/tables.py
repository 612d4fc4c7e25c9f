"""CSV tables of an analysis: one row per task, one per group, and one per chain and
platform when the analysis has chains (spec §4c).

Every time is given twice: exact (``7/3``) and as a decimal (``2.33333333333333``,
15 significant digits, for spreadsheets), each column headed with its unit.
"""

from __future__ import annotations

import csv
import errno
from decimal import Context, Decimal
from fractions import Fraction
from pathlib import Path

from maxplus.scalar import exact_text

from ..analysis.results import Report
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
    """Write ``tasks.csv`` and ``groups.csv`` into an existing ``directory``, and
    ``chains.csv`` when the report has chains.

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
        The files written.

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
    targets = [out / "tasks.csv", out / "groups.csv"]
    if report.chains:
        targets.append(out / "chains.csv")
    if not overwrite:
        for path in targets:
            if path.exists():
                raise FileExistsError(errno.EEXIST, "the file exists already; pass "
                                      "overwrite=True to replace it", str(path))
    u = report.unit
    with open(targets[0], "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(["task", "group", f"period ({u})", f"period ({u}, decimal)",
                         "overrun", "overrun_at (activation)", f"slack ({u})",
                         f"slack ({u}, decimal)", "critical"])
        for t in report.tasks.values():
            # `overrun` tells apart what an empty overrun_at cell cannot: never, no
            # clock, not live, undecided.
            writer.writerow([t.name, t.group, exact_text(t.period), _decimal(t.period),
                             t.overrun, t.overrun_at, exact_text(t.slack), _decimal(t.slack),
                             t.critical])
    with open(targets[1], "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(["group", "tasks", "clocks", "live", "rate_consistent", f"period ({u})",
                         f"period ({u}, decimal)", "transient_k (activation)", "cyclicity",
                         f"critical_holding ({u})", "critical_tokens"])
        for g in report.groups:
            k, c = g.transient if g.transient is not None else (None, None)
            writer.writerow([g.index, " ".join(g.tasks), " ".join(g.clocks), g.live,
                             g.rate_consistent, exact_text(g.period), _decimal(g.period), k, c,
                             exact_text(g.critical_holding), g.critical_tokens])
    if report.chains:
        _chains_csv(report, targets[2])
    return targets


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
