"""Indented JSON text, the bytes of ``json.dumps(doc, indent=n, ensure_ascii=False)``, faster.

The standard library encodes in C only without ``indent``; with it, it runs a
pure-Python generator per value, the largest single cost of ``tegraph analyze
--json`` on large skeletons (a million values at 10,000 tasks). This encoder
appends to one list in a recursive function and keeps the exact output of
:func:`json.dumps` (same separators, same escapes, same float text). Anything
the document builders do not produce (keys that are not strings, values json
cannot encode) falls back to :func:`json.dumps` itself, so errors stay its own.
"""

from __future__ import annotations

import json
from json.encoder import encode_basestring  # ensure_ascii=False: UTF-8 kept as it is
from typing import Any

__all__ = ["dumps_indented"]


class _Unusual(Exception):
    """A key or value outside the plain JSON types: let :func:`json.dumps` handle it."""


def dumps_indented(doc: Any, indent: int) -> str:
    """``json.dumps(doc, indent=indent, ensure_ascii=False)``.

    Examples
    --------
    >>> doc = {"a": [1, 2.5, None, True], "b": {}, "c": "é", "d": [{"e": []}]}
    >>> dumps_indented(doc, 2) == json.dumps(doc, indent=2, ensure_ascii=False)
    True
    """
    out: list[str] = []
    try:
        _encode(doc, "\n", " " * indent, out)
    except (_Unusual, RecursionError):
        return json.dumps(doc, indent=indent, ensure_ascii=False)
    return "".join(out)


def _scalar(o: Any) -> str:
    # The order of json.encoder._make_iterencode: bool before int (bool is an int).
    if isinstance(o, str):
        return encode_basestring(o)
    if o is None:
        return "null"
    if o is True:
        return "true"
    if o is False:
        return "false"
    if isinstance(o, int):
        return int.__repr__(o)
    if isinstance(o, float):
        if o != o:
            return "NaN"
        if o in (float("inf"), float("-inf")):
            return "Infinity" if o > 0 else "-Infinity"
        return float.__repr__(o)
    raise _Unusual


def _encode(o: Any, newline: str, step: str, out: list[str]) -> None:
    """Append the text of ``o``; ``newline`` is the line break and indent of its level."""
    # Exact types first (the common case, one dict lookup), then json's own order.
    put = out.append
    if isinstance(o, dict):
        if not o:
            put("{}")
            return
        inner = newline + step
        sep = "," + inner
        put("{" + inner)
        first = True
        for key, value in o.items():
            if type(key) is not str:
                raise _Unusual  # json turns numbers and None into keys: leave it that
            if first:
                first = False
            else:
                put(sep)
            text = _FAST.get(type(value))
            if text is not None:
                put(encode_basestring(key) + ": " + text(value))
            elif isinstance(value, (dict, list, tuple)):
                put(encode_basestring(key) + ": ")
                _encode(value, inner, step, out)
            else:
                put(encode_basestring(key) + ": " + _scalar(value))
        put(newline + "}")
    elif isinstance(o, (list, tuple)):
        if not o:
            put("[]")
            return
        inner = newline + step
        sep = "," + inner
        put("[" + inner)
        first = True
        for value in o:
            if first:
                first = False
            else:
                put(sep)
            text = _FAST.get(type(value))
            if text is not None:
                put(text(value))
            elif isinstance(value, (dict, list, tuple)):
                _encode(value, inner, step, out)
            else:
                put(_scalar(value))
        put(newline + "]")
    else:
        put(_scalar(o))


# The exact plain types whose text needs no further check (float: NaN and
# infinities go through _scalar).
_FAST = {str: encode_basestring, int: int.__repr__, bool: _scalar, type(None): _scalar}
