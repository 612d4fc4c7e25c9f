"""The table of judged variants of ``explore``: appended as verdicts arrive, read back to resume.

One row per variant, in the order verdicts arrive. Columns:

``variant`` (its number in the space), ``space`` (the fingerprint of the
skeleton, choices and objectives), ``link:W:p -> R:q`` (the protocol, one
column per chosen link), ``clock:NAME`` (the period, exact), ``judged``
(analyzed, pruned, failed), ``live``, ``repaired``, ``consistent``,
``schedulable``, ``kept`` (true, false or empty when not reached), one column
per objective (exact, such as ``7/3``; empty where undefined), ``kind:`` and
the objective for each latency (``exact`` or ``bound``), ``orders`` (the port
orders of a repair, JSON), ``reason`` (why not kept), ``seconds``.

**CSV** rows are written and flushed one batch at a time, so a killed run
loses only the batches in flight; a last line cut by the kill is dropped when
the file is resumed. **Parquet** (the ``[parquet]`` extra, pyarrow) cannot be
appended to safely: rows go to a CSV journal beside it, ``FILE.parquet.journal.csv``,
and the Parquet file is written (to a temporary name, then renamed) when the
run ends; ``resume`` reads both.
"""

from __future__ import annotations

import csv
import io
import json
import os
from collections.abc import Sequence
from fractions import Fraction
from pathlib import Path
from typing import Any

from maxplus.scalar import exact_text

from ..design.explore_eval import VariantResult
from ..design.explore_space import DesignSpace
from ..errors import InputError

__all__ = ["INSTALL_PARQUET", "ResultsTable", "columns"]

INSTALL_PARQUET = "pip install 'tegraph[parquet]'"
_SUFFIXES = (".csv", ".parquet")
_FLAGS = ("live", "repaired", "consistent", "schedulable", "kept")


def columns(space: DesignSpace) -> list[str]:
    """The header of the results table of ``space``."""
    latency = [n for n in space.objectives if n.startswith("latency:")]
    return (["variant", "space"] + [f"link:{c.label}" for c in space.links]
            + [f"clock:{c.name}" for c in space.clocks] + ["judged", *_FLAGS]
            + list(space.objectives) + [f"kind:{n}" for n in latency]
            + ["orders", "reason", "seconds"])


class ResultsTable:
    """A results file: checked at opening, appended to, read back for ``resume``.

    Parameters
    ----------
    path : str or path-like
        Ends in ``.csv`` or ``.parquet``; its directory must exist.
    space : DesignSpace
    resume : bool
        Read the verdicts already in the file and append to it.
    overwrite : bool
        Start the file anew when it exists.

    Raises
    ------
    InputError
        (``where="output"``) another suffix, a directory that does not exist, a
        file that exists without ``resume`` or ``overwrite``, a file of another
        exploration, or Parquet without pyarrow.
    """

    def __init__(self, path: str | os.PathLike[str], space: DesignSpace, resume: bool = False,
                 overwrite: bool = False) -> None:
        self.path = Path(os.fspath(path))
        self.space = space
        self.columns = columns(space)
        self.parquet = self.path.suffix.lower() == ".parquet"
        if self.path.suffix.lower() not in _SUFFIXES:
            raise InputError(f"cannot write results to {self.path.name!r}; expected a file "
                             "name ending in .csv or .parquet", "output")
        parent = self.path.parent
        if not parent.is_dir():
            raise InputError(f"the directory {str(parent)!r} does not exist; expected an "
                             "existing directory (none is created)", "output")
        if self.parquet:
            _pyarrow()
        self.journal = self.path.with_name(self.path.name + ".journal.csv") if self.parquet \
            else self.path
        existing = [p for p in {self.path, self.journal} if p.exists()]
        if existing and not resume and not overwrite:
            raise InputError(f"{existing[0]} exists already; expected `resume` to continue it "
                             "or `overwrite` to start it anew", "output")
        self.known: dict[int, VariantResult] = {}
        if existing and resume:
            if self.parquet and self.path.exists():
                names, rows = _read_parquet(self.path)
                if names != self.columns:
                    raise InputError(f"{self.path} holds the results of another exploration "
                                     "(other links, clocks or objectives); expected a file "
                                     "written by this one, or `overwrite`", "output")
                self._load(rows, self.path)
            if self.journal.exists():
                self._load(self._read_csv(self.journal), self.journal)
        elif existing and overwrite:
            for p in existing:
                p.unlink()
        fresh = not self.journal.exists() or self.journal.stat().st_size == 0
        self._file = open(self.journal, "a", newline="", encoding="utf-8")
        self._writer = csv.writer(self._file)
        if fresh:
            self._writer.writerow(self.columns)
            self._file.flush()

    def append(self, results: Sequence[VariantResult]) -> None:
        """Write ``results`` and flush them to the disk."""
        for r in results:
            self._writer.writerow(self.row(r))
        self._file.flush()
        os.fsync(self._file.fileno())

    def close(self, rows: dict[int, VariantResult] | None = None) -> None:
        """Close the file; for Parquet, write every row (``rows``, else those known and
        appended are read back from the journal) and remove the journal."""
        self._file.close()
        if not self.parquet:
            return
        table = self._read_csv(self.journal)
        done = {int(row["variant"]) for row in table}
        previous = [self.row(r) for v, r in sorted(self.known.items()) if v not in done]
        records = [[row[c] for c in self.columns] for row in table] + previous
        _write_parquet(self.path, self.columns, records)
        self.journal.unlink()

    def row(self, r: VariantResult) -> list[str]:
        """One result as the cells of its row."""
        links, clocks = self.space.describe(r.variant)
        flags = [r.live, r.repaired, r.consistent, r.schedulable, r.kept]
        latency = [n for n in self.space.objectives if n.startswith("latency:")]
        return ([str(r.variant), self.space.fingerprint] + list(links.values())
                + list(clocks.values()) + [r.judged]
                + ["" if f is None else str(bool(f)).lower() for f in flags]
                + [exact_text(r.objectives.get(n)) or "" for n in self.space.objectives]
                + [r.kinds.get(n, "") for n in latency]
                + [json.dumps(r.orders) if r.orders else "", r.reason, f"{r.seconds:.6f}"])

    def _read_csv(self, path: Path) -> list[dict[str, str]]:
        text = path.read_text(encoding="utf-8")
        if text and not text.endswith("\n"):
            # The last row was cut by a kill: drop it (its variant is judged again).
            text = text[:text.rfind("\n") + 1]
            with open(path, "r+", encoding="utf-8") as f:
                f.truncate(len(text.encode("utf-8")))
        reader = csv.DictReader(io.StringIO(text))
        if not text:
            return []
        if reader.fieldnames != self.columns:
            raise InputError(f"{path} holds the results of another exploration (other links, "
                             "clocks or objectives); expected a file written by this one, or "
                             "`overwrite`", "output")
        return list(reader)

    def _load(self, rows: list[dict[str, str]], path: Path) -> None:
        for row in rows:
            if row["space"] != self.space.fingerprint:
                raise InputError(f"{path} holds the results of another exploration (another "
                                 "skeleton, choices or objectives); expected a file written "
                                 "by this one, or `overwrite`", "output")
            r = self.parse(row)
            self.known.setdefault(r.variant, r)

    def parse(self, row: dict[str, str]) -> VariantResult:
        """A row read back as a :class:`VariantResult`."""
        def flag(text: str) -> bool | None:
            return None if text == "" else text == "true"

        variant = int(row["variant"])
        objectives: dict[str, Fraction | None] = {
            n: Fraction(row[n]) if row[n] else None for n in self.space.objectives}
        kinds = {n[len("kind:"):]: row[n] for n in self.columns
                 if n.startswith("kind:") and row[n]}
        return VariantResult(variant, row["judged"], flag(row["live"]),
                             bool(flag(row["repaired"])), flag(row["consistent"]),
                             flag(row["schedulable"]), objectives, kinds,
                             json.loads(row["orders"]) if row["orders"] else {},
                             row["reason"], float(row["seconds"] or 0))


def _pyarrow() -> Any:
    try:
        import pyarrow
        import pyarrow.parquet  # noqa: F401
    except ImportError:
        raise InputError("writing .parquet needs pyarrow, which is not installed; install it "
                         f"with: {INSTALL_PARQUET} (or pip install pyarrow), or write .csv",
                         "output") from None
    return pyarrow


def _write_parquet(path: Path, names: list[str], records: list[list[str]]) -> None:
    pa = _pyarrow()
    import pyarrow.parquet as pq

    # Every column is text: exact numbers stay exact ("7/3"), as in the CSV.
    table = pa.table({name: [r[i] for r in records] for i, name in enumerate(names)})
    temporary = path.with_name(path.name + ".tmp")
    pq.write_table(table, temporary)
    os.replace(temporary, path)


def _read_parquet(path: Path) -> tuple[list[str], list[dict[str, str]]]:
    _pyarrow()
    import pyarrow.parquet as pq

    table = pq.read_table(path)
    return list(table.column_names), table.to_pylist()
