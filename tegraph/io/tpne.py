"""TimedPetriNetEditor files: JSON nets (revision 4) and ``.teg`` event graphs.

**JSON** holds a net: places (``id``, ``caption``, ``tokens``), transitions
(``id``, ``caption``) and arcs between the keys ``P<id>`` and ``T<id>``; a
``duration`` on a transition -> place arc is the holding time of that place.
Arcs are read as written (the token flow of the drawing). Nodes are named by
their caption when captions are unique, else by their key.

**.teg** holds a timed event graph::

    TimedEventGraph <transitions> <lines>
    <i> <j>: <duration> <tokens>

This reader takes a line in the (max,+) *matrix* orientation: transition
``i`` waits ``duration`` for the firing of transition ``j`` that is
``tokens`` firings back, i.e. a place ``j -> i`` (the ``A[i][j]`` convention
of :mod:`maxplus`). The cycle times published with these files (the
editor's Howard tests) hold in that orientation. The editor's own importer
draws the arc ``i -> j`` instead, the transposed graph: the maximum cycle
ratio is the same, but the per-transition cycle times of a graph that is
not strongly connected are not; pass ``orientation="from-to"`` to read a
file the editor exported from a drawing. Transitions are named ``T0``,
``T1``... as in the editor.

Both formats store durations as decimal numbers: writing a time with no
finite decimal form (``7/3``) is refused rather than rounded.
"""

from __future__ import annotations

import json
import math
import os
import re
from decimal import Decimal
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

from maxplus.errors import MaxPlusValueError
from maxplus.scalar import exact_time, size_problem

from ..errors import InputError, ModelError
from ..model.convert import as_petri_net, as_teg
from ..model.limits import (
    count_problem,
    node_count_problem,
    shown,
    text_problem,
    written,
)
from ..model.petri import PetriNet
from ..model.teg import TimedEventGraph
from ._files import DEFAULT_MAX_BYTES, read_limited, write_bytes

__all__ = ["dumps_tpne_json", "dumps_tpne_teg", "parse_tpne_json", "parse_tpne_teg",
           "read_tpne_json", "read_tpne_teg", "write_tpne_json", "write_tpne_teg"]

_LINE = re.compile(r"\s*(\S+)\s+(\S+?)\s*:\s*(\S+)\s+(\S+)\s*")
_DIGITS = re.compile(r"[0-9]+")  # str.isdigit() takes "²", which int() refuses


# --------------------------------------------------------------------------- JSON


def read_tpne_json(path: str | os.PathLike[str], *, max_bytes: int = DEFAULT_MAX_BYTES
                   ) -> PetriNet:
    """Read a TimedPetriNetEditor JSON file (see the module docstring)."""
    file = os.fspath(path)
    return parse_tpne_json(read_limited(file, max_bytes), file)


def parse_tpne_json(data: bytes | str, file: str | None = None) -> PetriNet:
    """Parse TimedPetriNetEditor JSON into a :class:`~tegraph.model.petri.PetriNet`.

    Raises
    ------
    InputError
        Malformed JSON, no net, a node without integer id, a negative or
        non-integer token count, an arc to an unknown node or between two
        nodes of one kind, a negative or malformed duration; the message
        gives the key path (``nets[0].arcs[3].to``).

    Examples
    --------
    >>> net = parse_tpne_json('''{"revision": 4, "type": "Timed event graph", "nets": [{
    ...   "name": "loop", "places": [{"id": 0, "caption": "P0", "tokens": 1}],
    ...   "transitions": [{"id": 0, "caption": "T0"}],
    ...   "arcs": [{"from": "T0", "to": "P0", "duration": 2.5}, {"from": "P0", "to": "T0"}]}]}''')
    >>> net.places, net.transitions, net.holding, net.marking.tolist()
    (['P0'], ['T0'], [Fraction(5, 2)], [1])
    """
    if isinstance(data, str):
        data = data.encode("utf-8")
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"not UTF-8 text (byte {exc.start})", file=file) from None
    try:
        doc = json.loads(text, parse_float=_json_decimal, parse_int=_json_int)
    except _NumberRefused as exc:
        raise InputError(f"expected a number within the limits: {exc.why}", "", file,
                         _line_of(text, exc.text)) from None
    except json.JSONDecodeError as exc:
        raise InputError(f"malformed JSON: {exc.msg} (column {exc.colno})", file=file,
                         line=exc.lineno) from None
    except RecursionError:  # 3,000 nested brackets: json's C scanner gives up
        raise InputError("malformed JSON: nested too deeply; expected a TimedPetriNetEditor "
                         "net (objects and lists a few levels deep)", file=file) from None
    except ValueError as exc:  # an integer of more digits than Python converts
        raise InputError(f"malformed JSON: {exc}", file=file) from None
    nets = doc.get("nets") if isinstance(doc, dict) else None
    if not isinstance(nets, list) or not nets or not isinstance(nets[0], dict):
        raise InputError("expected an object with a non-empty list 'nets'", "nets", file)
    net = nets[0]
    name = _text(net.get("name"), "nets[0].name", file) or Path(file or "net").stem
    keys: dict[str, tuple[str, int]] = {}
    captions: dict[str, list[str]] = {"place": [], "transition": []}
    tokens: list[int] = []
    positions: dict[str, list[tuple[Any, Any]]] = {"places": [], "transitions": []}
    for kind, letter in (("place", "P"), ("transition", "T")):
        items = net.get(kind + "s", [])
        if not isinstance(items, list):
            raise InputError(f"expected a list of {kind}s", f"nets[0].{kind}s", file)
        for k, item in enumerate(items):
            where = f"nets[0].{kind}s[{k}]"
            if not isinstance(item, dict) or type(item.get("id")) is not int or item["id"] < 0:
                raise InputError("expected an object with an integer id >= 0", f"{where}.id",
                                 file)
            key = f"{letter}{item['id']}"
            if key in keys:
                raise InputError(f"duplicate id {item['id']}", f"{where}.id", file)
            keys[key] = (kind, len(captions[kind]))
            captions[kind].append(_text(item.get("caption"), f"{where}.caption", file) or key)
            positions[kind + "s"].append((item.get("x"), item.get("y")))
            if kind == "place":
                t = item.get("tokens", 0)
                if type(t) is not int or t < 0:
                    raise InputError(f"tokens must be an integer >= 0, got {shown(t)}",
                                     f"{where}.tokens", file)
                why = count_problem(t, "tokens")
                if why is not None:
                    raise InputError(why, f"{where}.tokens", file)
                tokens.append(t)
    n_p, n_t = len(captions["place"]), len(captions["transition"])
    pre_arcs: list[tuple[int, int]] = []
    post_arcs: list[tuple[int, int]] = []
    holding = [Fraction(0)] * n_p
    kind_text = doc.get("type", "")
    timed = isinstance(kind_text, str) and "timed" in kind_text.lower()
    arcs = net.get("arcs", [])
    if not isinstance(arcs, list):
        raise InputError("expected a list of arcs", "nets[0].arcs", file)
    for k, arc in enumerate(arcs):
        where = f"nets[0].arcs[{k}]"
        if not isinstance(arc, dict):
            raise InputError("expected an object", where, file)
        ends = []
        for end in ("from", "to"):
            ref = arc.get(end)
            if not isinstance(ref, str) or ref not in keys:
                raise InputError(f"{shown(ref)} is not the key (P<id> or T<id>) of a node of "
                                 "the net", f"{where}.{end}", file)
            ends.append(keys[ref])
        (k_from, i_from), (k_to, i_to) = ends
        if k_from == k_to:
            raise InputError(f"the arc joins two {k_from}s; an arc joins a place and a "
                             "transition", where, file)
        if k_from == "place":
            pre_arcs.append((i_from, i_to))
        else:
            post_arcs.append((i_to, i_from))
            if "duration" in arc:
                timed = True
                holding[i_to] = _duration(arc["duration"], f"{where}.duration", file)
    result = PetriNet(name, _unique(captions["place"], "P"), _unique(captions["transition"], "T"),
                      _weights(pre_arcs, n_p, n_t), _weights(post_arcs, n_p, n_t),
                      np.array(tokens, dtype=np.int64), holding if timed else [],
                      [] if not timed else [Fraction(0)] * n_p)
    result.attrs["tpne_positions"] = positions
    return result


class _NumberRefused(ValueError):
    def __init__(self, text: str, why: str) -> None:
        super().__init__(why)
        self.text, self.why = text, why


def _json_decimal(text: str) -> Decimal:
    """A JSON number with a fraction or exponent, exactly; refused beyond the stated limits."""
    why = size_problem(text)
    if why is not None:
        raise _NumberRefused(text, why)
    return Decimal(text)


def _json_int(text: str) -> int:
    """A JSON integer; refused beyond the stated limits before it is converted."""
    why = size_problem(text)
    if why is not None:
        raise _NumberRefused(text, why)
    return int(text)


def _line_of(text: str, needle: str) -> int | None:
    pos = text.find(needle)
    return None if pos < 0 else text.count("\n", 0, pos) + 1


def _text(value: Any, where: str, file: str | None) -> str:
    """A caption or name: a text that can be written back (empty when absent)."""
    if value is None:
        return ""
    if isinstance(value, bool) or not isinstance(value, (str, int)):
        raise InputError(f"expected a text, got {type(value).__name__}", where, file)
    value = str(value)
    why = text_problem(value)
    if why is not None:
        raise InputError(why, where, file)
    return value


def _weights(arcs: list[tuple[int, int]], n_p: int, n_t: int) -> sp.csr_array:
    """Arc weights, places x transitions: how many arcs join each pair."""
    rows = np.array([p for p, _ in arcs], dtype=np.int64)
    cols = np.array([t for _, t in arcs], dtype=np.int64)
    return sp.csr_array((np.ones(len(arcs), dtype=np.int64), (rows, cols)), shape=(n_p, n_t))


def _duration(value: Any, where: str, file: str | None) -> Fraction:
    if isinstance(value, bool) or not isinstance(value, (int, Decimal)):
        raise InputError(f"a duration is a number >= 0, got {shown(value)}", where, file)
    t = Fraction(value)
    if t < 0:
        raise InputError(f"a duration must be >= 0, got {written(t)}", where, file)
    return t


def _unique(captions: list[str], letter: str) -> list[str]:
    if len(set(captions)) == len(captions):
        return captions
    return [f"{letter}{k}" for k in range(len(captions))]


def write_tpne_json(obj: Any, path: str | os.PathLike[str], overwrite: bool = False) -> Path:
    """Write a net (or the net of any timed event graph) as TimedPetriNetEditor JSON."""
    return write_bytes(path, dumps_tpne_json(obj), overwrite)


def dumps_tpne_json(obj: Any) -> str:
    """TimedPetriNetEditor JSON text (revision 4); positions kept when read from such a file.

    Raises
    ------
    ModelError
        An arc weight above 1, a holding time with no finite decimal form, or
        initial tokens available after 0: the editor cannot hold them.

    Examples
    --------
    >>> net = parse_tpne_json(dumps_tpne_json(parse_tpne_json(
    ...     '{"nets": [{"places": [{"id": 0, "tokens": 2}], "transitions": [{"id": 0}],'
    ...     ' "arcs": [{"from": "T0", "to": "P0", "duration": 0.5},'
    ...     ' {"from": "P0", "to": "T0"}]}]}')))
    >>> net.holding, net.marking.tolist()
    ([Fraction(1, 2)], [2])
    """
    net = as_petri_net(obj)
    for weights in (net.pre, net.post):
        heavy = [(p, t) for p, t, w in _arcs(weights) if w > 1]
        if heavy:
            p, t = heavy[0]
            raise ModelError("TimedPetriNetEditor arcs have weight 1",
                             f"arc between {net.places[p]} and {net.transitions[t]}")
    if net.initial and any(net.initial):
        k = next(i for i, v in enumerate(net.initial) if v)
        raise ModelError("TimedPetriNetEditor cannot hold availability times of initial tokens",
                         f"place {net.places[k]}")
    pos = net.attrs.get("tpne_positions") or {}
    t_pos = _layout(pos.get("transitions"), len(net.transitions), 250)
    p_pos = _layout(pos.get("places"), len(net.places), 150)
    marked = net.marked_graph_violation() is None
    places = [{"id": k, "caption": name, "tokens": int(net.marking[k]), "x": x, "y": y}
              for k, (name, (x, y)) in enumerate(zip(net.places, p_pos))]
    transitions = [{"id": k, "caption": name, "x": x, "y": y}
                   for k, (name, (x, y)) in enumerate(zip(net.transitions, t_pos))]
    arcs = []
    for t, p, _ in _arcs(net.post.T):
        arc = f'{{"from": "T{t}", "to": "P{p}"'
        if net.holding:
            arc += f', "duration": {_decimal(net.holding[p], net.places[p])}'
        arcs.append(arc + "}")
    for p, t, _ in _arcs(net.pre):
        arcs.append(f'{{"from": "P{p}", "to": "T{t}"}}')
    kind = ("Timed event graph" if marked else "Timed Petri net") if net.holding else "Petri net"
    lines = ["{", '  "revision": 4,', f'  "type": "{kind}",', '  "nets": [', "    {",
             f'      "name": {json.dumps(net.name)},',
             '      "places": [' + ",".join("\n        " + json.dumps(p) for p in places)
             + "\n      ],",
             '      "transitions": [' + ",".join("\n        " + json.dumps(t)
                                              for t in transitions) + "\n      ],",
             '      "arcs": [' + ",".join("\n        " + a for a in arcs) + "\n      ],",
             '      "actions": []', "    }", "  ],", '  "inputs": []', "}", ""]
    return "\n".join(lines)


def _arcs(weights: Any) -> list[tuple[int, int, int]]:
    """``(row, column, weight)`` of every nonzero entry of a sparse matrix, row by row."""
    coo = sp.coo_array(weights)
    coo.sum_duplicates()
    order = np.lexsort((coo.col, coo.row))
    return list(zip(coo.row[order].tolist(), coo.col[order].tolist(),
                    coo.data[order].tolist()))


def _layout(given: Any, n: int, radius: float) -> list[tuple[Any, Any]]:
    if isinstance(given, list) and len(given) == n and all(
            isinstance(v, (int, Decimal)) and not isinstance(v, bool) and -10**9 < v < 10**9
            for xy in given for v in xy):
        return [(int(x) if x == int(x) else float(x), int(y) if y == int(y) else float(y))
                for x, y in given]
    # the editor's own default: a circle around (350, 350)
    return [(round(350 + radius * math.cos(2 * math.pi * k / max(n, 1))),
             round(350 + radius * math.sin(2 * math.pi * k / max(n, 1)))) for k in range(n)]


def _decimal(value: Fraction, where: str) -> str:
    den = value.denominator
    while den % 2 == 0:
        den //= 2
    while den % 5 == 0:
        den //= 5
    if den != 1:
        raise ModelError(f"holding time {value} has no finite decimal form; "
                         "TimedPetriNetEditor stores decimal numbers", f"place {where}")
    if value.denominator == 1:
        return str(value.numerator)
    text = format(Decimal(value.numerator) / Decimal(value.denominator), "f")
    return text


# --------------------------------------------------------------------------- .teg


def read_tpne_teg(path: str | os.PathLike[str], *, max_bytes: int = DEFAULT_MAX_BYTES,
                  orientation: str = "matrix") -> TimedEventGraph:
    """Read a ``.teg`` file (see the module docstring for ``orientation``)."""
    file = os.fspath(path)
    return parse_tpne_teg(read_limited(file, max_bytes), file, orientation,
                          Path(file).stem)


def parse_tpne_teg(data: bytes | str, file: str | None = None, orientation: str = "matrix",
                   name: str = "teg") -> TimedEventGraph:
    """Parse ``.teg`` text into a :class:`~tegraph.model.teg.TimedEventGraph`.

    Parameters
    ----------
    orientation : {"matrix", "from-to"}
        ``"matrix"``: line ``i j: d t`` is a place ``j -> i``; ``"from-to"``:
        a place ``i -> j`` (how the editor draws it).

    Examples
    --------
    >>> g = parse_tpne_teg("TimedEventGraph 2 2\\n0 1: 3 1\\n1 0: 0.5 0\\n")
    >>> [(g.transition_names[p.src], g.transition_names[p.dst], str(p.holding), p.tokens)
    ...  for p in g.places]
    [('T1', 'T0', '3', 1), ('T0', 'T1', '1/2', 0)]
    """
    if orientation not in ("matrix", "from-to"):
        raise InputError(f"expected 'matrix' or 'from-to', got {orientation!r}", "orientation")
    size = len(data.encode("utf-8") if isinstance(data, str) else data)
    text = data.decode("utf-8", "replace") if isinstance(data, bytes) else data
    lines = text.splitlines()
    header = lines[0].split() if lines else []
    if (len(header) != 3 or header[0] != "TimedEventGraph" or not _DIGITS.fullmatch(header[1])
            or not _DIGITS.fullmatch(header[2])):
        raise InputError("expected the header 'TimedEventGraph <transitions> <lines>'",
                         "header", file, 1)
    # a count of more than 19 digits is above any limit: not converted (4300-digit texts
    # are refused by int() itself)
    too_long = len(header[1]) > 19
    n = 2**64 if too_long else int(header[1])
    why = node_count_problem(n, size, "transitions")
    if why is not None:
        raise InputError(why.replace(str(2**64), shown(header[1], quote=False)) if too_long
                         else why, "header", file, 1)
    body = [(k, line) for k, line in enumerate(lines[1:], start=2) if line.strip()]
    if len(header[2]) > 19 or len(body) != int(header[2]):
        raise InputError(f"the header announces {shown(header[2], quote=False)} lines, the file "
                         f"has {len(body)}", "header", file, 1)
    teg = TimedEventGraph(name)
    for k in range(n):
        teg.add_transition(f"T{k}")
    for number, line in body:
        match = _LINE.fullmatch(line)
        if not match:
            raise InputError("expected '<i> <j>: <duration> <tokens>'", "", file, number)
        i, j, d, t = match.groups()
        for field, value in (("i", i), ("j", j)):
            if not _DIGITS.fullmatch(value) or len(value) > 19 or int(value) >= n:
                raise InputError(f"expected a transition index 0..{n - 1}, got {shown(value)}",
                                 field, file, number)
        if not _DIGITS.fullmatch(t):
            raise InputError(f"expected a token count (an integer >= 0), got {shown(t)}",
                             "tokens", file, number)
        why = size_problem(t) or count_problem(int(t), "a token count")
        if why is not None:
            raise InputError(why, "tokens", file, number)
        why = size_problem(d)
        if why is not None:
            raise InputError(f"expected a duration within the limits: {why}", "duration", file,
                             number)
        try:
            duration = exact_time(d, "duration")
        except MaxPlusValueError:
            raise InputError(f"expected a duration such as 3 or 0.5, got {shown(d)}",
                             "duration", file, number) from None
        if duration < 0:
            raise InputError(f"a duration must be >= 0, got {shown(d)}", "duration", file,
                             number)
        src, dst = (int(j), int(i)) if orientation == "matrix" else (int(i), int(j))
        teg.add_place(src, dst, int(t), duration)
    return teg


def write_tpne_teg(obj: Any, path: str | os.PathLike[str], overwrite: bool = False) -> Path:
    """Write any timed event graph as a ``.teg`` file (matrix orientation; names are lost)."""
    return write_bytes(path, dumps_tpne_teg(obj), overwrite)


def dumps_tpne_teg(obj: Any) -> str:
    """``.teg`` text, in the orientation :func:`parse_tpne_teg` reads by default.

    Examples
    --------
    >>> print(dumps_tpne_teg(parse_tpne_teg("TimedEventGraph 2 1\\n0 1: 2.5 1\\n")), end="")
    TimedEventGraph 2 1
    <BLANKLINE>
    0 1: 2.5 1
    """
    g = as_teg(obj)
    out = [f"TimedEventGraph {g.n_transitions} {g.n_places}", ""]
    for p in g.places:
        if p.initial != 0:
            raise ModelError("a .teg file cannot hold availability times of initial tokens",
                             f"place {p.name}")
        out.append(f"{p.dst} {p.src}: {_decimal(p.holding, p.name)} {p.tokens}")
    return "\n".join(out) + "\n"
