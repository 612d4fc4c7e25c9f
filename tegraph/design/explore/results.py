"""The table of judged variants of ``explore``: appended as verdicts arrive, read back to resume.

One row per variant, in the order verdicts arrive. Columns:

``variant`` (its number in the space), ``space`` (the fingerprint of the
skeleton, choices and objectives), ``link:W:p -> R:q`` (the protocol, one
column per chosen link), ``clock:NAME`` (the period, exact), ``on:UNIT`` (the
processor of each unit that moves, ``A+B`` for a group, when processors are
offered), ``judged``
(analyzed, pruned, failed), ``live``, ``repaired``, ``consistent``,
``schedulable`` (on its processors, spec §4b), ``meets_constraints``, ``kept``
(true, false or empty when not reached; ``schedulable`` empty after ``consistent``
true: the schedule on processors was undecided within ``max_events``, and the
variant is not kept), one column per
objective (exact, such as ``7/3``; empty where undefined), ``kind:`` and the
objective for each chain objective (``exact``, or ``undecided``: not kept), ``rule2`` (Rule 2
findings, the tie-breaker), ``orders`` (the port orders of a repair, JSON),
``reason`` (why not kept), ``seconds``.

**CSV** rows are written and flushed one batch at a time, so a killed run
loses only the batches in flight; a last line cut by the kill is dropped when
the file is resumed, once every other row has been checked (a file that is
not this exploration's is refused and never changed). **Parquet** (the
``[parquet]`` extra, pyarrow) cannot be appended to safely: rows go to a CSV
journal beside it, ``FILE.parquet.journal.csv``, and the Parquet file is
written (to a temporary name, then renamed) when the run ends; ``resume``
reads both.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from collections.abc import Sequence
from fractions import Fraction
from pathlib import Path
from typing import Any, NoReturn

from maxplus.scalar import exact_text, exact_time

from ...errors import InputError
from .evaluate import ANALYZED, FAILED, PRUNED, VariantResult
from .objectives import CURRENT_DEFINITIONS, DEFINITIONS, OLDER_DEFINITIONS, chain_objective
from .space import DesignSpace

__all__ = ["INSTALL_PARQUET", "ResultsTable", "columns"]

INSTALL_PARQUET = "pip install 'tegraph[parquet]'"
_SUFFIXES = (".csv", ".parquet")
_FLAGS = ("live", "repaired", "consistent", "schedulable", "meets_constraints", "kept")
_JUDGED = (ANALYZED, PRUNED, FAILED)
_KINDS = ("exact", "undecided")
_NOT_OURS = ("; expected a results file written by `tegraph explore` for this skeleton and "
             "these choices (the file is left as it was: pass `overwrite` to replace it)")
# With `resume`, `overwrite` replaces nothing (resuming reads the file): say what does.
_NOT_OURS_RESUMED = ("; expected a results file written by `tegraph explore` for this "
                     "skeleton and these choices (the file is left as it was: `overwrite` "
                     "does not replace a file being resumed; write to a new `output` file, "
                     "or drop `resume` and keep `overwrite` to start this one anew)")


def columns(space: DesignSpace) -> list[str]:
    """The header of the results table of ``space``."""
    latency = [n for n in space.objectives if chain_objective(n) is not None]
    return (["variant", "space"] + [f"link:{c.label}" for c in space.links]
            + [f"clock:{c.name}" for c in space.clocks]
            + [f"on:{name}" for name in space.placement(0)] + ["judged", *_FLAGS]
            + list(space.objectives) + [f"kind:{n}" for n in latency]
            + ["rule2", "orders", "reason", "seconds"])


class ResultsTable:
    """A results file: checked at opening, appended to, read back for ``resume``.

    On ``resume`` every row is checked before anything is written: the header,
    the fingerprint of the space, each cell (the variant number, its choices as
    the number implies them, the verdicts, the exact objectives). A file that
    is not this exploration's is refused and left byte for byte as it was. Only
    then is a last row cut by a kill (no end of line, and the beginning of one
    of this exploration's rows) dropped, so that the rows appended after it
    start on a line of their own. An empty file is taken as a table with no
    row (a run killed before its header): it holds nothing to lose.

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
        file that exists without ``resume`` or ``overwrite``, or Parquet without
        pyarrow; (``file`` and ``line`` set) a file that is not a results file
        of this exploration, naming the row and the column refused.
    """

    def __init__(self, path: str | os.PathLike[str], space: DesignSpace, resume: bool = False,
                 overwrite: bool = False) -> None:
        self.path = Path(os.fspath(path))
        self.space = space
        self.overwrite = overwrite
        self.columns = columns(space)
        self.parquet = self.path.suffix.lower() == ".parquet"
        self.journal = self.path.with_name(self.path.name + ".journal.csv") if self.parquet \
            else self.path
        existing = self._existing(resume, overwrite)
        self.known: dict[int, VariantResult] = {}
        self._tail: tuple[Path, int, str] | None = None
        cut: int | None = None
        if existing and resume:
            # Everything is read and checked before the first byte is written or cut.
            if self.parquet and self.path.exists():
                self._load(_read_parquet(self.path, self.columns, overwrite), self.path)
            if self.journal.exists():
                rows, cut = self._read_csv(self.journal)
                self._load(rows, self.journal)
                if self._tail is not None:
                    self._check_tail(*self._tail)
        elif existing and overwrite:
            for p in existing:
                p.unlink()
        if cut is not None:
            # The file is this exploration's: drop the last row a kill cut (its variant
            # is judged again).
            with open(self.journal, "r+b") as f:
                f.truncate(cut)
        fresh = not self.journal.exists() or self.journal.stat().st_size == 0
        self._file = open(self.journal, "a", newline="", encoding="utf-8")
        self._writer = csv.writer(self._file)
        if fresh:
            self._writer.writerow(self.columns)
            self._file.flush()

    def _existing(self, resume: bool, overwrite: bool) -> list[Path]:
        """The results file and its journal that exist already, once the path is
        known to be writable as asked (refused otherwise, nothing written)."""
        if self.path.suffix.lower() not in _SUFFIXES:
            raise InputError(f"cannot write results to {self.path.name!r}; expected a file "
                             "name ending in .csv or .parquet", "output")
        parent = self.path.parent
        if not parent.is_dir():
            raise InputError(f"the directory {str(parent)!r} does not exist; expected an "
                             "existing directory (none is created)", "output")
        if self.parquet:
            _pyarrow()
        existing = [p for p in dict.fromkeys([self.path, self.journal]) if p.exists()]
        for p in existing:
            if not p.is_file():
                raise InputError(f"{p} is not a file; expected a results file", "output")
        if existing and not resume and not overwrite:
            raise InputError(f"{existing[0]} exists already; expected `resume` to continue it "
                             "or `overwrite` to start it anew", "output")
        return existing

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
        table, _ = self._read_csv(self.journal)
        done = {int(row["variant"]) for _, row in table}
        previous = [self.row(r) for v, r in sorted(self.known.items()) if v not in done]
        records = [[row[c] for c in self.columns] for _, row in table] + previous
        _write_parquet(self.path, self.columns, records)
        self.journal.unlink()

    def row(self, r: VariantResult) -> list[str]:
        """One result as the cells of its row."""
        links, clocks = self.space.describe(r.variant)
        flags = [r.live, r.repaired, r.consistent, r.schedulable, r.meets, r.kept]
        latency = [n for n in self.space.objectives if chain_objective(n) is not None]
        return ([str(r.variant), self.space.fingerprint] + list(links.values())
                + list(clocks.values()) + list(self.space.placement(r.variant).values())
                + [r.judged]
                + ["" if f is None else str(bool(f)).lower() for f in flags]
                + [exact_text(r.objectives.get(n)) or "" for n in self.space.objectives]
                + [r.kinds.get(n, "") for n in latency]
                + ["" if r.rule2 is None else str(r.rule2)]
                + [json.dumps(r.orders) if r.orders else "", r.reason, f"{r.seconds:.6f}"])

    def _refuse(self, path: Path, line: int | None, what: str) -> NoReturn:
        raise InputError(what + (_NOT_OURS_RESUMED if self.overwrite else _NOT_OURS), "",
                         str(path), line)

    def _read_csv(self, path: Path) -> tuple[list[tuple[int | None, dict[str, str]]], int | None]:
        """The rows of a CSV table with their line numbers, and where to cut a last row
        cut by a kill (None: nothing to cut). Refuses, writing nothing, a file whose
        bytes, header or cut tail are not this exploration's."""
        data = path.read_bytes()
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError as exc:
            line = data[:exc.start].count(b"\n") + 1
            self._refuse(path, line, f"byte {exc.start:,} ({data[exc.start:exc.start + 1]!r}) "
                         "is not UTF-8 text")
        if not text:
            return [], None
        cut = None
        if not text.endswith("\n"):
            keep = text.rfind("\n") + 1
            tail = text[keep:]
            if keep == 0:
                # No whole line: the beginning of the header, cut when it was written.
                if not _header_text(self.columns).startswith(tail):
                    self._refuse(path, 1, "the first line is not the header of this "
                                 "exploration's results")
            else:  # checked once the whole rows are (`check_tail`)
                self._tail = (path, text.count("\n") + 1, tail)
            cut = len(text[:keep].encode("utf-8"))
            text = text[:keep]
            if not text:
                return [], cut
        reader = csv.reader(io.StringIO(text, newline=""))
        try:
            header = next(reader)
            if header != self.columns:
                self._refuse(path, 1, "the header is not that of this exploration's results "
                             "(another exploration, or not a results file: expected "
                             f"{len(self.columns)} columns, from 'variant' to 'seconds', for "
                             "these links, clocks and objectives)")
            rows: list[tuple[int | None, dict[str, str]]] = []
            for k, cells in enumerate(reader, start=1):
                if len(cells) != len(self.columns):
                    self._refuse(path, reader.line_num, f"row {k} has {len(cells)} cells; "
                                 f"expected {len(self.columns)}")
                rows.append((reader.line_num, dict(zip(self.columns, cells))))
        except csv.Error as exc:
            self._refuse(path, reader.line_num, f"cannot read it as CSV ({exc})")
        return rows, cut

    def _check_tail(self, path: Path, line: int, tail: str) -> None:
        """Refuse a last line without an end of line unless it is the beginning of a row
        of this exploration (digits, then its fingerprint, or a beginning of them): the
        row a kill cut, and only that, is dropped."""
        number, comma, rest = tail.partition(",")
        fingerprint, comma2, _ = rest.partition(",")
        ours = number.isascii() and number.isdigit() and (
            not comma or (fingerprint == self.space.fingerprint if comma2
                          else self.space.fingerprint.startswith(fingerprint)))
        if not ours:
            self._refuse(path, line, "the last line has no end of line and is not the "
                         "beginning of one of this exploration's rows (a row cut by a kill)")

    def _load(self, rows: list[tuple[int | None, dict[str, str]]], path: Path) -> None:
        known: dict[int, VariantResult] = {}
        for k, (line, row) in enumerate(rows, start=1):
            r = self.parse(row, path, line, k)
            known.setdefault(r.variant, r)
        for v, r in known.items():
            self.known.setdefault(v, r)

    def parse(self, row: dict[str, str], path: Path | str = "", line: int | None = None,
              k: int = 0) -> VariantResult:
        """A row read back as a :class:`VariantResult`, every cell checked.

        Raises
        ------
        InputError
            Naming ``path``, the line, the row ``k`` and the column of the first cell
            refused.
        """
        cells = _Cells(self, row, Path(path), line, k)
        variant = cells.variant()
        judged = row["judged"]
        if judged not in _JUDGED:
            cells.refuse("judged", f"expected one of {', '.join(_JUDGED)}")
        live, repaired, consistent, schedulable, meets, kept = (cells.flag(c) for c in _FLAGS)
        # In the order of the columns: the first cell refused is the one named.
        objectives, kinds, rule2 = cells.objectives(), cells.kinds(), cells.rule2()
        orders, seconds = cells.orders(), cells.seconds()
        result = VariantResult(variant, judged, live=live, repaired=bool(repaired),
                               consistent=consistent, schedulable=schedulable,
                               objectives=objectives, kinds=kinds, orders=orders,
                               reason=row["reason"], seconds=seconds, rule2=rule2, meets=meets)
        cells.coherent(result, kept)
        return result


class _Cells:
    """The cells of one row of a results file, each read and checked; the first one
    refused raises, naming the file, the line, the row and the column."""

    def __init__(self, table: ResultsTable, row: dict[str, str], path: Path,
                 line: int | None, k: int) -> None:
        self.table, self.space, self.row = table, table.space, row
        self.path, self.line, self.k = path, line, k

    def refuse(self, column: str, what: str) -> NoReturn:
        self.table._refuse(self.path, self.line, f"row {self.k}, column {column!r}: {what}, "
                           f"got {_shown(self.row.get(column))}")

    def flag(self, column: str) -> bool | None:
        text = self.row[column]
        if text not in ("", "true", "false"):
            self.refuse(column, "expected true, false or empty")
        return None if text == "" else text == "true"

    def variant(self) -> int:
        """The variant number, once the row is known to be this exploration's, and
        its link and clock cells checked against the space's numbering."""
        space, row = self.space, self.row
        if row["space"] != space.fingerprint:
            older = [v for v in OLDER_DEFINITIONS if row["space"] == space.fingerprint_of(v)]
            if older:  # this exploration, judged by the definitions of an older version
                self.refuse("space", f"this exploration judged under version {older[0]} of "
                            f"the definitions ({OLDER_DEFINITIONS[older[0]]}); its verdicts are "
                            f"not those of version {DEFINITIONS} ({CURRENT_DEFINITIONS}), so "
                            "they are not resumed; expected "
                            f"{space.fingerprint}")
            self.refuse("space", "another exploration (another skeleton, choices, objectives, "
                        "constraints or budget `max_events` of each schedule); expected "
                        f"{space.fingerprint}")
        text = row["variant"]
        if not (text.isascii() and text.isdigit() and len(text) <= len(str(space.size))
                and int(text) < space.size):
            self.refuse("variant", f"expected a variant number from 0 to {space.size - 1:,}")
        variant = int(text)
        links, clocks = space.describe(variant)
        cells = ([(f"link:{n}", v) for n, v in links.items()]
                 + [(f"clock:{n}", v) for n, v in clocks.items()]
                 + [(f"on:{n}", v) for n, v in space.placement(variant).items()])
        for column, value in cells:
            if row[column] != value:
                self.refuse(column, f"variant {variant} has {value!r}")
        return variant

    def objectives(self) -> dict[str, Fraction | None]:
        objectives: dict[str, Fraction | None] = {}
        for n in self.space.objectives:
            objectives[n] = None
            if self.row[n]:
                try:
                    value = exact_time(self.row[n], n)
                except (ValueError, ArithmeticError) as exc:
                    self.refuse(n, f"expected an exact number such as 7/3 or empty ({exc})")
                if value < 0 or (n == "period" and value == 0):
                    self.refuse(n, f"expected a number {'> 0' if n == 'period' else '>= 0'}")
                objectives[n] = value
        return objectives

    def kinds(self) -> dict[str, str]:
        kinds = {}
        for n in self.space.objectives:
            if chain_objective(n) is not None:
                column = f"kind:{n}"
                if self.row[column] not in ("", *_KINDS):
                    self.refuse(column, "expected exact, undecided or empty")
                if self.row[column]:
                    kinds[n] = self.row[column]
        return kinds

    def rule2(self) -> int | None:
        text = self.row["rule2"]
        if not text:
            return None
        if not (text.isascii() and text.isdigit() and len(text) <= 9):
            self.refuse("rule2", "expected a number of findings (an integer >= 0) or empty")
        return int(text)

    def orders(self) -> dict[str, Any]:
        if not self.row["orders"]:
            return {}
        try:
            orders = json.loads(self.row["orders"])
        except ValueError:
            orders = None
        if not _orders_ok(orders, self.space):
            self.refuse("orders", "expected the port orders of a repair, as JSON "
                        '{"TASK": {"inputs": [...], "outputs": [...]}}, or empty')
        return orders

    def seconds(self) -> float:
        seconds = _seconds(self.row["seconds"])
        if seconds is None:
            self.refuse("seconds", "expected a number of seconds >= 0 or empty")
        return seconds

    def coherent(self, result: VariantResult, kept: bool | None) -> None:
        """The verdicts follow one another as a judgement makes them."""
        live, consistent, schedulable = result.live, result.consistent, result.schedulable
        if kept is not result.kept:
            self.refuse("kept", f"live, consistent, schedulable and the constraints say "
                        f"{str(result.kept).lower()}")
        if result.judged == PRUNED and (live is not False or consistent is not None):
            self.refuse("live", "a pruned variant is dead (live false, nothing after)")
        if result.judged == ANALYZED and live is None:
            self.refuse("live", "an analyzed variant is live or not")
        if (consistent is not None and not live) or (schedulable is not None
                                                    and not consistent):
            self.refuse("consistent" if schedulable is None else "schedulable",
                        "a verdict past one that failed")


def _header_text(names: list[str]) -> str:
    out = io.StringIO()
    csv.writer(out).writerow(names)
    return out.getvalue()


def _shown(text: Any) -> str:
    if text is None:
        return "nothing"
    text = str(text)
    if len(text) <= 40:
        return repr(text)
    return repr(text[:40])[:-1] + f"...' ({len(text):,} characters)"


def _seconds(text: str) -> float | None:
    if text == "":
        return 0.0
    if len(text) > 40:
        return None
    try:
        value = float(text)
    except ValueError:
        return None
    return value if math.isfinite(value) and value >= 0 else None


def _orders_ok(orders: Any, space: DesignSpace) -> bool:
    if not isinstance(orders, dict):
        return False
    for task, order in orders.items():
        if task not in space.skeleton.tasks or not isinstance(order, dict) \
                or set(order) != {"inputs", "outputs"}:
            return False
        if not all(isinstance(ports, list) and all(isinstance(p, str) for p in ports)
                   for ports in order.values()):
            return False
    return True


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


def _read_parquet(path: Path, names: list[str], overwrite: bool = False
                  ) -> list[tuple[int | None, dict[str, str]]]:
    """The rows of a Parquet results file; refused, untouched, when it is not one of
    this exploration's (not Parquet, other columns, cells that are not text)."""
    _pyarrow()
    import pyarrow.parquet as pq

    def refuse(what: str) -> NoReturn:
        raise InputError(what + (_NOT_OURS_RESUMED if overwrite else _NOT_OURS), "",
                         str(path))

    try:
        table = pq.read_table(path)
    except Exception as exc:  # pyarrow's errors (ArrowInvalid, OSError, ...): not ours
        refuse(f"cannot read it as Parquet ({type(exc).__name__})")
    if list(table.column_names) != names:
        refuse("its columns are not those of this exploration's results")
    rows = table.to_pylist()
    for k, row in enumerate(rows, start=1):
        for name in names:
            if not isinstance(row[name], str):
                refuse(f"row {k}, column {name!r}: expected text, got {type(row[name]).__name__}")
    return [(None, row) for row in rows]
