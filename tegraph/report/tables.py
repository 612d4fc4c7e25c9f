"""CSV tables of an analysis: one row per task, one per group."""

from __future__ import annotations

import csv
import errno
from pathlib import Path

from ..analysis.results import Report

__all__ = ["write_csv"]


def write_csv(report: Report, directory: str | Path, overwrite: bool = False) -> list[Path]:
    """Write ``tasks.csv`` and ``groups.csv`` into ``directory``.

    Raises
    ------
    FileExistsError
        When a file exists and ``overwrite`` is False (nothing is written).
    """
    out = Path(directory)
    targets = [out / "tasks.csv", out / "groups.csv"]
    if not overwrite:
        for path in targets:
            if path.exists():
                raise FileExistsError(errno.EEXIST, "the file exists already; pass "
                                      "overwrite=True to replace it", str(path))
    out.mkdir(parents=True, exist_ok=True)
    data = report.to_dict()
    with open(targets[0], "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["task", "group", "period", "overrun_at", "slack", "critical"])
        for name, t in data["tasks"].items():
            writer.writerow([name, t["group"], t["period"], t["overrun_at"], t["slack"], t["critical"]])
    with open(targets[1], "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["group", "tasks", "clocks", "live", "rate_consistent", "period",
                         "transient_k", "cyclicity"])
        for k, g in enumerate(data["groups"]):
            tr = g["transient"] or {}
            writer.writerow([k, " ".join(g["tasks"]), " ".join(g["clocks"]), g["live"],
                             g["rate_consistent"], g["period"], tr.get("k"), tr.get("cyclicity")])
    return targets
