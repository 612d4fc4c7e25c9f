"""Arc lists (``.edges``): one place a line, ``src dst holding tokens``.

The format of the SDF3 reference expansions (``shared/anchors/sdf/hsdf_edges``)::

    # any comment; '#' starts a comment anywhere on a line
    # node 0 fork1_0          <- names transition 0 (optional)
    # nodes 48                <- number of transitions (optional; else max index + 1)
    0 1 1 0                   <- place 0 -> 1, holding time 1, no initial token

Indices and tokens are integers >= 0; holding times are exact (``7/3``,
``0.25`` and ``1e3`` are read exactly) and >= 0. The stated limits of
:mod:`tegraph.model.limits` apply: tokens up to 2**63 - 1, numbers of at most
4300 digits and exponents up to 1000, and at most as many transitions as the
file has bytes, plus 2**20 (a huge index or ``# nodes`` count is refused
rather than allocated).

Reading and writing are whole-array numpy operations so that 4 million lines
take about a second (``benchmarks/bench_edges.py``): the common all-integer
file is parsed by one ``numpy.fromstring`` call in C, with a marker after each
line so that a line with the wrong number of fields cannot go unnoticed;
non-integer times take a slower vectorized path; only a malformed file is
walked line by line, to name the first bad line.

An arc list holds no place names and no availability times of initial
tokens: writing a graph whose initial tokens are available later than 0 is
refused rather than silently changed.
"""

from __future__ import annotations

import math
import os
import re
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

from maxplus.errors import MaxPlusValueError
from maxplus.scalar import exact_text, exact_time, size_problem

from ..errors import InputError, ModelError
from ..model.arcs import ArcList
from ..model.convert import as_teg_like
from ..model.limits import (
    MAX_COUNT,
    count_problem,
    denominator_problem,
    node_count_problem,
    shown,
)
from ._files import DEFAULT_MAX_BYTES, read_limited, write_bytes

__all__ = ["dumps_edges", "parse_edges", "read_edges", "write_edges"]

_SAFE = 2**62  # as in tegraph.model.teg: sums of two values stay in int64
_CHUNK = 1 << 20  # rows formatted at once when writing (bounds the temporary matrix)
# Literal "#" first, so that the regex engine searches for it instead of trying
# every line start; that the "#" opens its line is checked per match.
_NODE = re.compile(rb"#[ \t]*node[ \t]+(\d+)[ \t]+([^\r\n]*)")
_NODES = re.compile(rb"#[ \t]*nodes[ \t]+(\d+)[ \t]*(?=[\r\n]|$)")
_COMMENT = re.compile(rb"#[^\n]*")
_HEADER = re.compile(rb"(?:[ \t\r]*(?:#[^\n]*)?\n)*")
_POW10 = 10 ** np.arange(19, dtype=np.int64)


# --------------------------------------------------------------------------- reading


def read_edges(path: str | os.PathLike[str], *, max_bytes: int = DEFAULT_MAX_BYTES) -> ArcList:
    """Read an ``.edges`` file (see the module docstring); the graph is named by the file stem.

    Raises
    ------
    InputError
        Naming the file, the first bad line and the field.
    """
    file = os.fspath(path)
    return parse_edges(read_limited(file, max_bytes), file, Path(file).stem)


def parse_edges(data: bytes | str, file: str | None = None, name: str = "edges") -> ArcList:
    """Parse the text of an arc list.

    Examples
    --------
    >>> g = parse_edges("# node 0 a\\n# node 1 b\\n0 1 7/3 0  # a comment\\n1 0 0.5 2\\n")
    >>> g.transition_names, [str(g.holding_time(p)) for p in range(2)], g.tokens.tolist()
    (('a', 'b'), ['7/3', '1/2'], [0, 2])
    >>> parse_edges("0 1 2\\n", "g.edges")
    Traceback (most recent call last):
    ...
    tegraph.errors.InputError: g.edges:1: expected 4 fields 'src dst holding tokens', got 3
    """
    if isinstance(data, str):
        data = data.encode("utf-8")
    names: dict[int, tuple[str, int]] = {}
    n_declared = declared_at = 0
    clean = data
    if b"#" in data:
        for m in _NODE.finditer(data):
            if _opens_line(data, m.start()):
                try:
                    label = m.group(2).decode("utf-8").strip()
                except UnicodeDecodeError:
                    raise InputError("a node name is not UTF-8 text", "node name", file,
                                     _line_of(data, m.start())) from None
                index = _declared(m.group(1), "node", data, m.start(), file)
                names[index] = (label, m.start())
        for m in _NODES.finditer(data):
            if _opens_line(data, m.start()):
                count = _declared(m.group(1), "nodes", data, m.start(), file)
                if count > n_declared:
                    n_declared, declared_at = count, m.start()
        body = _HEADER.match(data).end()  # type: ignore[union-attr]  # matches "" at least
        clean = data[body:] if b"#" not in data[body:] else _COMMENT.sub(b"", data)
    parsed = _parse_fast(clean)
    if parsed is None:
        parsed = _parse_general(clean, data, file)
    src, dst, holding, tokens, scale = parsed
    n = int(max(src.max(initial=-1), dst.max(initial=-1))) + 1
    n = max(n, n_declared, max(names, default=-1) + 1)
    why = node_count_problem(n, len(data), "transitions (the largest index + 1, or '# nodes')")
    if why is not None:
        line = (_line_of(data, declared_at) if n == n_declared else
                _line_of(data, names[n - 1][1]) if n - 1 in names else
                _line_of_index(data, n - 1, src, dst))
        raise InputError(why, "nodes", file, line)
    return ArcList(np.ascontiguousarray(src), np.ascontiguousarray(dst),
                   np.ascontiguousarray(holding), np.ascontiguousarray(tokens), scale,
                   _names(names, n, data, file), n, name)


def _declared(digits: bytes, what: str, data: bytes, pos: int, file: str | None) -> int:
    """The number of a ``# node`` / ``# nodes`` line, refused before a huge one is converted."""
    if len(digits) > 19:  # above any count the node limit lets through
        raise InputError(f"{shown(digits.decode())} is above any number of transitions this "
                         f"file can hold ({len(data)} bytes + 2**20)", what, file,
                         _line_of(data, pos))
    return int(digits)


def _line_of_index(data: bytes, index: int, src: np.ndarray, dst: np.ndarray) -> int | None:
    """The line of the first place naming transition ``index`` (None: a header named it)."""
    hits = np.flatnonzero((src == index) | (dst == index))
    if not len(hits):
        return None
    # Type: _HEADER matches the empty string: match() never gives None.
    body = _HEADER.match(data).end()  # type: ignore[union-attr]
    count = int(hits[0])
    for number, raw in enumerate(data[body:].split(b"\n"), start=data.count(b"\n", 0, body) + 1):
        if raw.split(b"#", 1)[0].strip():
            if count == 0:
                return number
            count -= 1
    return None  # pragma: no cover - every place has a line


def _opens_line(data: bytes, pos: int) -> bool:
    """True when only blanks stand between the previous newline and ``pos``."""
    return not data[data.rfind(b"\n", 0, pos) + 1:pos].strip()


def _line_of(data: bytes, pos: int) -> int:
    return data.count(b"\n", 0, pos) + 1


_Parsed = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, int]


def _parse_fast(clean: bytes) -> _Parsed | None:
    """One ``numpy.fromstring`` call in C; None sends the text to the general path.

    Every newline becomes the marker ``-1`` (no field is negative), so the
    fields of each line are counted. A holding time ``a/b`` is rewritten
    ``a -2 b`` and ``a.b`` as ``a -3 1b`` (the leading 1 keeps the count of
    decimals of ``b``): a line then has 4 values, or 6 with its marker third.
    """
    body = clean.lstrip()  # the blank lines left by a header of comments
    if body and not body.endswith(b"\n"):
        body += b"\n"
    slash, dot = body.count(b"/"), body.count(b".")
    if slash and dot:
        return None
    if dot:
        body = body.replace(b".", b" -3 1")
    elif slash:
        body = body.replace(b"/", b" -2 ")
    try:
        vals = np.fromstring(body.replace(b"\n", b" -1\n"), dtype=np.int64, sep=" ")
    except ValueError:  # a field that is no integer (1e3, x, ...)
        return None
    n_lines = body.count(b"\n")
    if not slash + dot and len(vals) == 5 * n_lines:
        rows = vals.reshape(n_lines, 5)  # the common file: integers, no blank line
        if (rows[:, 4] == -1).all() and (len(rows) == 0 or (
                rows[:, :4].min() >= 0 and rows[:, :4].max() < _SAFE)):
            return rows[:, 0], rows[:, 1], rows[:, 2], rows[:, 3], 1
    ends = np.flatnonzero(vals == -1)
    if len(ends) != n_lines or (len(vals) and ends[-1] != len(vals) - 1):
        return None
    counts = np.diff(ends, prepend=-1) - 1
    lines = np.flatnonzero(counts)
    c = counts[lines]
    first = ends[lines] - c
    split = c == 6
    if not ((c == 4) | split).all() or int(split.sum()) != slash + dot:
        return None
    if split.any() and not (vals[first[split] + 3] == (-2 if slash else -3)).all():
        return None
    src, dst, num, tokens = vals[first], vals[first + 1], vals[first + 2], vals[first + c - 1]
    low = np.zeros(len(first), dtype=np.int64)
    low[split] = vals[first[split] + 4]
    cols = (src, dst, num, tokens, low)
    # fromstring saturates on overflow, and a stray "-1" would be taken for a marker
    if len(first) and (min(int(x.min()) for x in cols) < 0 or max(int(x.max()) for x in cols)
                       >= 10**18):
        return None
    den = np.ones(len(first), dtype=np.int64)
    if slash:
        den[split] = low[split]
        if (den == 0).any():
            return None
    elif dot:
        digits = np.searchsorted(_POW10, low[split], side="right") - 1
        if (digits < 0).any():
            return None
        den[split] = _POW10[digits]
        num = num.copy()
        if (num[split] >= 10**18 // den[split]).any():
            return None
        num[split] = num[split] * den[split] + (low[split] - den[split])
    if split.any():
        g = np.gcd(num, den)
        num, den = num // g, den // g
        scale = math.lcm(*np.unique(den).tolist())
        if scale >= _SAFE:
            return None
        factor = scale // den
        if (num >= _SAFE // factor).any():  # the product would leave int64: general path
            return None
        num = num * factor
    else:
        scale = 1
    return src, dst, num, tokens, int(scale)


def _parse_general(clean: bytes, data: bytes, file: str | None) -> _Parsed:
    """Vectorized path for exact non-integer times; a malformed file is diagnosed."""
    body = clean if clean.endswith(b"\n") else clean + b"\n"
    fields = np.array(body.replace(b"\n", b" ;\n").split(), dtype="S")
    ends = np.flatnonzero(fields == b";")  # one marker per line, as in _parse_fast
    counts = np.diff(ends, prepend=-1) - 1
    lines = np.flatnonzero(counts)
    if (counts[lines] != 4).any():
        _diagnose(data, file)
    cols = fields[(ends[lines] - 4)[:, None] + np.arange(4)]
    try:
        src, dst, tokens = (cols[:, k].astype(np.int64) for k in (0, 1, 3))
    except (ValueError, OverflowError):
        _diagnose(data, file)
    if len(src) and min(src.min(), dst.min(), tokens.min()) < 0:
        _diagnose(data, file)
    texts, inverse = np.unique(cols[:, 2], return_inverse=True)
    try:
        decoded = [t.decode("ascii") for t in texts.tolist()]
    except UnicodeDecodeError:
        _diagnose(data, file)
    if any(size_problem(t) for t in decoded):  # 1e999999999 would take hours
        _diagnose(data, file)
    try:
        values = [exact_time(t, "holding") for t in decoded]
    except MaxPlusValueError:
        _diagnose(data, file)
    if any(v < 0 for v in values):
        _diagnose(data, file)
    why = denominator_problem(v.denominator for v in values)
    if why is not None:
        raise InputError(why, "holding", file)
    scale = math.lcm(1, *(v.denominator for v in values))
    ints = [int(v * scale) for v in values]
    table = np.array(ints, dtype=np.int64 if all(v < _SAFE for v in ints) else object)
    return src, dst, table[inverse.ravel()], tokens, scale


def _diagnose(data: bytes, file: str | None) -> None:
    """Walk the lines and raise for the first malformed one (only on refusal)."""
    for number, raw in enumerate(data.split(b"\n"), start=1):
        line = raw.split(b"#", 1)[0].strip()
        if not line:
            continue
        parts = line.split()
        if len(parts) != 4:
            raise InputError(f"expected 4 fields 'src dst holding tokens', got {len(parts)}",
                             "", file, number)
        for field, text in zip(("src", "dst", "holding", "tokens"), parts):
            written = text.decode("utf-8", "replace")
            why = size_problem(written)
            if why is not None:
                raise InputError(f"expected a number within the limits: {why}", field, file,
                                 number)
            if field == "holding":
                try:
                    value = exact_time(written, field)
                except MaxPlusValueError:
                    raise InputError(f"expected an exact time such as 3, 0.25 or 7/3, got "
                                     f"{shown(written)}", field, file, number) from None
                if value < 0:
                    raise InputError(f"a holding time must be >= 0, got {shown(written)}", field,
                                     file, number)
            elif not re.fullmatch(rb"\+?[0-9]+", text):
                what = "a transition index" if field != "tokens" else "a token count"
                raise InputError(f"expected {what} (an integer >= 0), got {shown(written)}",
                                 field, file, number)
            elif int(text) > MAX_COUNT:
                what = "a token count" if field == "tokens" else "a transition index"
                raise InputError(count_problem(int(text), what) or "", field, file, number)
    raise InputError("malformed arc list", "", file)  # pragma: no cover - defensive


def _names(given: dict[int, tuple[str, int]], n: int, data: bytes, file: str | None
           ) -> list[str] | None:
    if not given:
        return None
    names = [str(i) for i in range(n)]
    seen: dict[str, int] = {}
    for i, (label, _) in given.items():
        names[i] = label
    for i, label in enumerate(names):
        if not label:
            raise InputError("a node name must not be empty", "node name", file,
                             _line_of(data, given[i][1]))
        if label in seen:
            pos = given.get(i, given.get(seen[label], ("", None)))[1]
            raise InputError(f"transitions {seen[label]} and {i} are both named {label!r}",
                             "node name", file, None if pos is None else _line_of(data, pos))
        seen[label] = i
    return names


# --------------------------------------------------------------------------- writing


def write_edges(obj: Any, path: str | os.PathLike[str], overwrite: bool = False) -> Path:
    """Write any timed event graph (or what becomes one) as an ``.edges`` file.

    Raises
    ------
    FileExistsError
        ``path`` exists and ``overwrite`` is False.
    ModelError
        Initial tokens available after 0 (an arc list cannot hold that).
    """
    return write_bytes(path, dumps_edges(obj), overwrite)


def dumps_edges(obj: Any) -> bytes:
    """The text of the ``.edges`` file of ``obj``, as bytes.

    Examples
    --------
    >>> g = parse_edges("0 1 7/3 0\\n1 0 2 1\\n")
    >>> print(dumps_edges(g).decode(), end="")
    # tegraph arc list: one place a line, 'src dst holding tokens'
    # nodes 2
    0 1 7/3 0
    1 0 2 1
    """
    g = as_teg_like(obj)
    arcs = g if isinstance(g, ArcList) else ArcList.from_teg(g)
    head = ["# tegraph arc list: one place a line, 'src dst holding tokens'",
            f"# nodes {arcs.n_transitions}"]
    if arcs.names is not None:
        for i, label in enumerate(arcs.names):
            if "\n" in label or "\r" in label or label != label.strip():
                raise ModelError("a name written to an arc list must be one line without "
                                 "leading or trailing blanks", f"transition {label!r}")
            head.append(f"# node {i} {label}")
    parts = ["\n".join(head).encode("utf-8") + b"\n"]
    hold_table = None
    if arcs.scale != 1 or arcs.holding.dtype == object:
        hold_table, hold_index = _text_table(arcs.holding, arcs.scale)
    for lo in range(0, arcs.n_places, _CHUNK):
        sl = slice(lo, lo + _CHUNK)
        hold = _digits(arcs.holding[sl]) if hold_table is None else hold_table[hold_index[sl]]
        cols = [_digits(arcs.src[sl]), _sep(b" ", len(hold)), _digits(arcs.dst[sl]),
                _sep(b" ", len(hold)), hold, _sep(b" ", len(hold)), _digits(arcs.tokens[sl]),
                _sep(b"\n", len(hold))]
        mat = np.concatenate(cols, axis=1)
        parts.append(mat[mat != 0].tobytes())  # NUL pads fixed-width fields: drop them
    return b"".join(parts)


def _digits(values: np.ndarray) -> np.ndarray:
    """Decimal digits of non-negative int64 values, right-aligned, NUL-padded: (m, width) uint8."""
    v = np.asarray(values, dtype=np.int64)
    width = max(1, len(str(int(v.max())))) if len(v) else 1
    out = np.zeros((len(v), width), dtype=np.uint8)
    rest = v.copy()
    for k in range(width - 1, -1, -1):
        digit = (rest % 10).astype(np.uint8) + 48
        # a leading position stays NUL once the number is exhausted (but "0" keeps one digit)
        out[:, k] = np.where((rest > 0) | (k == width - 1), digit, 0)
        rest //= 10
    return out


def _sep(char: bytes, m: int) -> np.ndarray:
    return np.full((m, 1), char[0], dtype=np.uint8)


def _text_table(holding: np.ndarray, scale: int) -> tuple[np.ndarray, np.ndarray]:
    """Fixed-width text of each distinct exact holding time, and each place's row in it."""

    uniq, inverse = np.unique(holding, return_inverse=True)
    texts = [str(exact_text(Fraction(int(u), scale))) for u in uniq.tolist()]
    table = np.array([t.encode("ascii") for t in texts], dtype="S")
    width = table.dtype.itemsize
    return table.view(np.uint8).reshape(len(texts), width), inverse.ravel()
