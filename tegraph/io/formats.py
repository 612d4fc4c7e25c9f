"""The formats tegraph reads and writes: one record each, read by every part that needs one.

:data:`FORMATS` is the one table of formats: what a file of each holds (for
messages), the extensions that select it, the extensions it shares with another
format and how its first bytes tell it apart, its reader and its writer. The
detection of a file's format (:func:`detect_format`), :func:`read`, :func:`write`,
the skeleton reader's refusal of another format's file and the command line's help
all read it, so that a new format is one record here and one module of its own.

Readers and writers are named ``"module:function"`` and imported when a file of
theirs is read or written: a skeleton's analysis needs none of the other formats'
modules (nor the nets and SDF graphs they hold), and the command line builds its
help from this table without importing any of them.

>>> [f.name for f in FORMATS.values() if f.reader is None]
['dot', 'teg-dot']
>>> detect_format("net.pnml"), FORMATS["edges"].suffixes
('pnml', ('.edges',))
"""

from __future__ import annotations

import importlib
import os
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import InputError, ModelError
from ._files import DEFAULT_MAX_BYTES

__all__ = ["FORMATS", "FileFormat", "detect_format", "format_for_writing", "read",
           "readable", "sniff_format", "writable", "write"]

_XML_ROOT = re.compile(rb"<\s*(?:[\w.-]+:)?(pnml|sdf3)\b")
_EDGES = re.compile(rb"(\s*(#[^\n]*)?\n)*\s*\d+\s+\d+\s+\S+\s+\d+\s*(#|\n|$)")
_TPNE_KEYS = re.compile(rb'"(nets|revision)"\s*:')
_DOT = re.compile(rb"(strict\s+)?(di)?graph\b", re.IGNORECASE)


def _xml_root(name: bytes) -> Callable[[bytes], bool]:
    def sniff(text: bytes) -> bool:
        if not text.startswith(b"<"):
            return False
        m = _XML_ROOT.search(text)
        return m is not None and m.group(1) == name
    return sniff


@dataclass(frozen=True)
class FileFormat:
    """One format: how files of it are named and recognised, and who reads and writes them.

    Attributes
    ----------
    name : str
        The format's name (``--format``, ``--to``, ``format=``).
    holds : str
        What a file of the format holds, as messages name it (``"a PNML net"``).
    suffixes : tuple of str
        Extensions that select this format alone.
    shared : tuple of str
        Extensions this format shares with another one: a file is told apart by
        :attr:`sniff` when read, by :attr:`model` when written.
    sniff : callable, optional
        Whether the first bytes of a file (a byte order mark and leading white space
        removed) show this format beyond doubt. None: never told from its content.
    reader : str, optional
        ``"module:function"`` reading a path (keyword ``max_bytes``); None: not read.
    writer : str, optional
        ``"module:function"`` writing ``(model, path, overwrite=...)``; None: not written.
    model : str, optional
        The dotted name of the class a file of this format holds, when a shared
        extension is written: the format whose model the object is (or subclasses);
        None for the format a shared extension falls back to.
    draws : bool
        The writer takes ``highlights`` (a drawing that colours circuits).
    """

    name: str
    holds: str
    suffixes: tuple[str, ...] = ()
    shared: tuple[str, ...] = ()
    sniff: Callable[[bytes], bool] | None = None
    reader: str | None = None
    writer: str | None = None
    model: str | None = None
    draws: bool = False

    def extensions(self) -> tuple[str, ...]:
        """Every extension that may name a file of this format.

        >>> FORMATS["skeleton"].extensions()
        ('.yaml', '.yml', '.json')
        """
        return self.suffixes + self.shared


FORMATS: dict[str, FileFormat] = {f.name: f for f in (
    FileFormat("skeleton", "a skeleton file", (".yaml", ".yml"), (".json",),
               reader="tegraph.io.skeleton_file:read_skeleton_file",
               writer="tegraph.io.skeleton_file:write_skeleton_file",
               model="tegraph.model.skeleton.core.Skeleton"),
    FileFormat("pnml", "a PNML net", (".pnml",), (".xml",), _xml_root(b"pnml"),
               "tegraph.io.pnml:read_pnml", "tegraph.io.pnml:write_pnml"),
    FileFormat("sdf3", "an SDF3 graph", (".sdf3",), (".xml",), _xml_root(b"sdf3"),
               "tegraph.io.sdf3:read_sdf3", "tegraph.io.sdf3:write_sdf3",
               model="tegraph.model.sdf.SDFGraph"),
    FileFormat("edges", "an arc list (.edges)", (".edges",), (),
               lambda text: _EDGES.match(text) is not None,
               "tegraph.io.edges:read_edges", "tegraph.io.edges:write_edges"),
    FileFormat("tpne-json", "a TimedPetriNetEditor net (JSON)", (), (".json",),
               lambda text: text.startswith(b"{") and _TPNE_KEYS.search(text) is not None,
               "tegraph.io.tpne:read_tpne_json", "tegraph.io.tpne:write_tpne_json"),
    FileFormat("tpne-teg", "a TimedPetriNetEditor timed event graph (.teg)", (".teg",), (),
               lambda text: text.startswith(b"TimedEventGraph"),
               "tegraph.io.tpne:read_tpne_teg", "tegraph.io.tpne:write_tpne_teg"),
    FileFormat("dot", "a DOT drawing", (".dot", ".gv"), (),
               lambda text: _DOT.match(text) is not None,
               writer="tegraph.io.dot:write_dot", draws=True),
    FileFormat("teg-dot", "a DOT drawing", writer="tegraph.io.dot:write_teg_dot", draws=True),
)}
"""Format name -> its record; the order is the order in which content is sniffed."""

_OWNER = {ext: f for f in FORMATS.values() for ext in f.suffixes}
_SHARED = {ext: tuple(f for f in FORMATS.values() if ext in f.shared)
           for f in FORMATS.values() for ext in f.shared}
_HEAD = 4096  # bytes of a file read to tell its format


def readable() -> list[str]:
    """The names of the formats :func:`read` reads.

    >>> readable()
    ['skeleton', 'pnml', 'sdf3', 'edges', 'tpne-json', 'tpne-teg']
    """
    return [f.name for f in FORMATS.values() if f.reader is not None]


def writable() -> list[str]:
    """The names of the formats :func:`write` writes.

    >>> writable()[-2:]
    ['dot', 'teg-dot']
    """
    return [f.name for f in FORMATS.values() if f.writer is not None]


def _all_extensions() -> str:
    return ", ".join(dict.fromkeys(e for f in FORMATS.values() for e in f.extensions()))


def _stripped(head: bytes) -> bytes:
    return head.lstrip(b"\xef\xbb\xbf \t\r\n")


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
    text = _stripped(head)
    return next((f.name for f in FORMATS.values() if f.sniff is not None and f.sniff(text)),
                None)


def detect_format(path: str | os.PathLike[str], head: bytes | None = None) -> str:
    """The format name of a file, from its extension, else from its first bytes.

    An extension of one format selects it. An extension that formats share is
    told apart by content among those formats: ``.xml`` by its root element
    (``pnml`` or ``sdf3``), ``.json`` by its keys (TimedPetriNetEditor files have
    ``nets``; anything else is read as a skeleton). Any other file is sniffed
    against every format; JSON that no format claims is a skeleton.

    >>> detect_format("a.pnml"), detect_format("b.edges"), detect_format("c.xml", b"<sdf3>")
    ('pnml', 'edges', 'sdf3')
    >>> detect_format("d.json", b'{"tasks": {}}'), detect_format("e.txt", b"digraph g {}")
    ('skeleton', 'dot')
    """
    file = os.fspath(path)
    ext = Path(file).suffix.lower()
    if ext in _OWNER:
        return _OWNER[ext].name
    if head is None:
        try:
            with open(file, "rb") as fh:
                head = fh.read(_HEAD)
        except OSError as exc:
            raise InputError(f"cannot read the file: {exc.strerror}", file=file) from None
    text = _stripped(head)
    candidates = _SHARED.get(ext, tuple(FORMATS.values()))
    for f in candidates:
        if f.sniff is not None and f.sniff(text):
            return f.name
    if ext == ".json" or text.startswith(b"{"):
        return "skeleton"
    if text.startswith(b"<"):
        roots = " nor ".join(f"<{f.name}>" for f in _SHARED[".xml"])
        raise InputError(f"an XML file whose root element is neither {roots}", file=file)
    raise InputError(f"cannot tell the format of this file; expected one of {_all_extensions()} "
                     "(or give the format explicitly)", file=file)


def _is(obj: Any, dotted: str) -> bool:
    return any(f"{c.__module__}.{c.__qualname__}" == dotted for c in type(obj).__mro__)


def format_for_writing(obj: Any, file: str) -> str:
    """The format :func:`write` gives ``file``: its extension's, and on a shared one the model's.

    >>> format_for_writing(object(), "out.xml"), format_for_writing(object(), "out.gv")
    ('pnml', 'dot')
    """
    ext = Path(file).suffix.lower()
    if ext in _OWNER:
        return _OWNER[ext].name
    if ext in _SHARED:
        sharing = _SHARED[ext]
        chosen = next((f for f in sharing if f.model is not None and _is(obj, f.model)), None)
        return (chosen or next(f for f in sharing if f.model is None)).name
    raise InputError(f"cannot tell the format from the extension {ext!r}; use one of "
                     f"{_all_extensions()}, or give the format", file=file)


def _resolve(target: str) -> Callable[..., Any]:
    module, _, name = target.partition(":")
    function: Callable[..., Any] = getattr(importlib.import_module(module), name)
    return function


def read(path: str | os.PathLike[str], format: str | None = None, *,
         max_bytes: int = DEFAULT_MAX_BYTES) -> Any:
    """Read any supported file; the reader is picked from the file (see :data:`FORMATS`).

    Parameters
    ----------
    path : str or path-like
        The file.
    format : str, optional
        Force a format name of :data:`FORMATS` instead of detecting it.
    max_bytes : int
        Refuse larger files (default :data:`~tegraph.io.DEFAULT_MAX_BYTES`).

    Returns
    -------
    Skeleton, PetriNet, SDFGraph, ArcList or TimedEventGraph
        The model the format holds (see the table of :mod:`tegraph.io`).

    Raises
    ------
    InputError
        Unknown format, file too large, or a malformed file (the message
        names the file, the line when known, and the element).

    See Also
    --------
    write : the converse.
    tegraph.io.load_skeleton : a skeleton file, checked against spec §1.
    detect_format : the format :func:`read` picks.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "ring.edges"
    >>> _ = f.write_text("0 1 2 0\\n1 0 3 1\\n")
    >>> g = read(f); g.n_transitions, g.n_places
    (2, 2)
    """
    fmt = format or detect_format(path)
    record = FORMATS.get(fmt)
    if record is None or record.reader is None:
        raise InputError(f"format {fmt!r} cannot be read; readable: "
                         f"{', '.join(sorted(readable()))}", file=os.fspath(path))
    return _resolve(record.reader)(path, max_bytes=max_bytes)


def write(obj: Any, path: str | os.PathLike[str], format: str | None = None,
          overwrite: bool = False, *, highlights: Any = None) -> Path:
    """Write ``obj`` in the format of ``path`` (or ``format``) when it can hold it.

    Parameters
    ----------
    obj : Skeleton, TimedEventGraph, PetriNet, SDFGraph or ArcList
    path : str or path-like
    format : str, optional
        A name of :data:`FORMATS`; default from the extension (``.json`` is
        TimedPetriNetEditor JSON for a net or graph, a skeleton file for a skeleton).
    overwrite : bool
        Replace an existing file; without it an existing file is never touched.
    highlights : tegraph.io.dot.Highlights, optional
        Circuits to colour in a DOT drawing (``tegraph.write`` computes them).

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InputError
        The target cannot hold the content (e.g. a timed event graph to a
        skeleton file, a non-marked-graph net to an arc list).
    FileExistsError
        ``path`` exists and ``overwrite`` is False.
    """
    file = os.fspath(path)
    fmt = format or format_for_writing(obj, file)
    record = FORMATS.get(fmt)
    if record is None or record.writer is None:
        raise InputError(f"format {fmt!r} cannot be written; writable: "
                         f"{', '.join(sorted(writable()))}", file=file)
    writer = _resolve(record.writer)
    try:
        if record.draws:
            return writer(obj, path, overwrite=overwrite, highlights=highlights)
        return writer(obj, path, overwrite=overwrite)
    except ModelError as exc:
        raise InputError(f"cannot be written as {fmt}: {exc}", file=file) from None
