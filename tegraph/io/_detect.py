"""Which format a file holds: from its extension, else from its first bytes.

Used by :func:`tegraph.io.read` to pick a reader, and by the skeleton reader to
say which command reads a file that is no skeleton (a PNML net given to
``analyze``).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

from ..errors import InputError

__all__ = ["FORMATS", "FORMAT_NAMES", "detect_format", "sniff_format"]

FORMATS: dict[str, tuple[str, ...]] = {
    "skeleton": (".yaml", ".yml", ".json"),
    "pnml": (".pnml",),
    "sdf3": (".sdf3",),
    "edges": (".edges",),
    "tpne-json": (),
    "tpne-teg": (".teg",),
    "dot": (".dot", ".gv"),
    "teg-dot": (),
}
"""Format name -> file extensions that select it (``.xml`` and ``.json`` are sniffed)."""

FORMAT_NAMES: dict[str, str] = {
    "skeleton": "a skeleton file",
    "pnml": "a PNML net",
    "sdf3": "an SDF3 graph",
    "edges": "an arc list (.edges)",
    "tpne-json": "a TimedPetriNetEditor net (JSON)",
    "tpne-teg": "a TimedPetriNetEditor timed event graph (.teg)",
    "dot": "a DOT drawing",
    "teg-dot": "a DOT drawing",
}
"""How messages name what a file of each format holds."""

_XML_ROOT = re.compile(rb"<\s*(?:[\w.-]+:)?(pnml|sdf3)\b")
_EDGES = re.compile(rb"(\s*(#[^\n]*)?\n)*\s*\d+\s+\d+\s+\S+\s+\d+\s*(#|\n|$)")
_TPNE_KEYS = re.compile(rb'"(nets|revision)"\s*:')
_DOT = re.compile(rb"(strict\s+)?(di)?graph\b", re.IGNORECASE)


def sniff_format(head: bytes) -> str | None:
    """The format the first bytes of a file show beyond doubt, or None.

    Only what no skeleton file looks like is named: an XML root ``<pnml>``
    or ``<sdf3>``, the ``TimedEventGraph`` header, JSON with ``nets`` or
    ``revision`` keys, lines of four numbers, a DOT ``digraph``.

    >>> sniff_format(b"<?xml version='1.0'?><pnml>"), sniff_format(b"tasks:\\n  A: {}")
    ('pnml', None)
    >>> sniff_format(b"TimedEventGraph 2 2\\n"), sniff_format(b"0 1 2 0\\n1 0 3 1\\n")
    ('tpne-teg', 'edges')
    """
    text = head.lstrip(b"\xef\xbb\xbf \t\r\n")
    if text.startswith(b"<"):
        m = _XML_ROOT.search(head)
        return m.group(1).decode() if m else None
    if text.startswith(b"TimedEventGraph"):
        return "tpne-teg"
    if text.startswith(b"{"):
        return "tpne-json" if _TPNE_KEYS.search(head) else None
    if _EDGES.match(text):
        return "edges"
    if _DOT.match(text):
        return "dot"
    return None


def detect_format(path: str | os.PathLike[str], head: bytes | None = None) -> str:
    """The format name of a file, from its extension, else from its first bytes.

    ``.xml`` files are told apart by their root element (``pnml`` or
    ``sdf3``), ``.json`` files by their keys (TimedPetriNetEditor files have
    ``nets``; skeletons have ``tasks``).

    >>> detect_format("a.pnml"), detect_format("b.edges"), detect_format("c.xml", b"<sdf3>")
    ('pnml', 'edges', 'sdf3')
    """
    file = os.fspath(path)
    ext = Path(file).suffix.lower()
    for name, exts in FORMATS.items():
        if ext in exts and ext != ".json":
            return name
    if head is None:
        try:
            with open(file, "rb") as fh:
                head = fh.read(4096)
        except OSError as exc:
            raise InputError(f"cannot read the file: {exc.strerror}", file=file) from None
    text = head.lstrip(b"\xef\xbb\xbf \t\r\n")
    m = _XML_ROOT.search(head)
    if m:
        return m.group(1).decode()
    if text.startswith(b"TimedEventGraph"):
        return "tpne-teg"
    if ext == ".json" or text.startswith(b"{"):
        return "tpne-json" if _TPNE_KEYS.search(head) else "skeleton"
    if _EDGES.match(text):
        return "edges"
    if text.startswith(b"<"):
        raise InputError("an XML file whose root element is neither <pnml> nor <sdf3>", file=file)
    raise InputError("cannot tell the format of this file; expected one of "
                     + ", ".join(ext for exts in FORMATS.values() for ext in exts)
                     + " (or give the format explicitly)", file=file)
