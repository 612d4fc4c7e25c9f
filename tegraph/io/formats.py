"""Interchange formats: detection, size limit, safe XML, and :func:`read` / :func:`write`.

Every reader returns the model its format holds, most faithfully:

=============  ==============================  =========================================
format         files                           :func:`read` returns
=============  ==============================  =========================================
``skeleton``   ``.yaml``, ``.yml``, ``.json``  :class:`~tegraph.skeleton.Skeleton`
``pnml``       ``.pnml``, ``.xml``             :class:`~tegraph.petri.PetriNet`
``sdf3``       ``.sdf3``, ``.xml``             :class:`~tegraph.io.sdf3.SDFGraph`
``edges``      ``.edges``                      :class:`~tegraph.io.edges.ArcList`
``tpne-json``  ``.json`` (TimedPetriNetEditor)  :class:`~tegraph.petri.PetriNet`
``tpne-teg``   ``.teg`` (TimedPetriNetEditor)   :class:`~tegraph.teg.TimedEventGraph`
``dot``        ``.dot``, ``.gv`` (write only)   --
``teg-dot``    (write only)                     --
=============  ==============================  =========================================

:func:`write` accepts any of these models (and a :class:`TimedEventGraph`)
wherever the target can hold the content: a skeleton becomes a timed event
graph, never the other way round; a P/T net that is not a marked graph can
only go to net formats (PNML, TimedPetriNetEditor JSON, DOT).

Safety: a file larger than ``max_bytes`` (default :data:`DEFAULT_MAX_BYTES`)
is refused before it is read, and XML is parsed by expat with every document
type declaration refused, so no entity is ever expanded and no external file
is ever fetched (an entity-expansion bomb is refused at its first line).
"""

from __future__ import annotations

import json
import os
import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any
from xml.parsers import expat

from ..errors import InputError, ModelError

if TYPE_CHECKING:  # pragma: no cover
    from ..petri import PetriNet
    from ..teg import TimedEventGraph
    from .edges import ArcList

__all__ = [
    "DEFAULT_MAX_BYTES",
    "FORMATS",
    "XmlNode",
    "as_petri_net",
    "as_teg",
    "as_teg_like",
    "check_size",
    "detect_format",
    "parse_size",
    "parse_xml",
    "read",
    "read_limited",
    "write",
    "write_bytes",
]

DEFAULT_MAX_BYTES = 256 * 2**20
"""Files above this size are refused unless the caller raises the limit (256 MiB:
an arc list of 4 million places takes about 100 MB)."""

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


def parse_size(text: str | int) -> int:
    """A byte count from ``"300M"``, ``"2G"``, ``"512k"`` or a plain integer.

    >>> parse_size("300M"), parse_size("2G"), parse_size(1000)
    (314572800, 2147483648, 1000)
    """
    if isinstance(text, int):
        return text
    m = re.fullmatch(r"\s*(\d+)\s*([kKmMgG]?)[iI]?[bB]?\s*", str(text))
    if not m:
        raise InputError(f"expected a size such as 300M or 2G, got {text!r}", "--max-size")
    return int(m.group(1)) * {"": 1, "k": 2**10, "m": 2**20, "g": 2**30}[m.group(2).lower()]


def check_size(path: str | os.PathLike[str], max_bytes: int = DEFAULT_MAX_BYTES) -> None:
    """Refuse (``InputError``) a file above ``max_bytes``, or one that cannot be read."""
    file = os.fspath(path)
    try:
        size = os.stat(file).st_size
    except OSError as exc:
        raise InputError(f"cannot read the file: {exc.strerror}", file=file) from None
    if size > max_bytes:
        raise InputError(f"the file has {size} bytes, above the limit of {max_bytes}; raise "
                         "the limit to read it (--max-size on the command line, max_bytes= "
                         "in the library)", file=file)


def read_limited(path: str | os.PathLike[str], max_bytes: int = DEFAULT_MAX_BYTES) -> bytes:
    """The bytes of ``path``, refused (``InputError``) above ``max_bytes`` or when unreadable."""
    check_size(path, max_bytes)
    file = os.fspath(path)
    try:
        with open(file, "rb") as fh:
            return fh.read()
    except OSError as exc:
        raise InputError(f"cannot read the file: {exc.strerror}", file=file) from None


def write_bytes(path: str | os.PathLike[str], data: bytes | str, overwrite: bool = False) -> Path:
    """Write ``data`` to ``path``; an existing file is replaced only when ``overwrite``.

    Raises
    ------
    FileExistsError
        ``path`` exists and ``overwrite`` is False (the file is not touched).
    """
    target = Path(os.fspath(path))
    payload = data.encode("utf-8") if isinstance(data, str) else data
    # "x" mode creates atomically: no window between an exists() check and the write.
    with open(target, "wb" if overwrite else "xb") as fh:
        fh.write(payload)
    return target


# --------------------------------------------------------------------------- XML


@dataclass
class XmlNode:
    """An XML element with namespace prefixes and URIs dropped, and its line.

    Attributes
    ----------
    tag : str
        Local name (``place`` for ``<pnml:place>`` or ``{uri}place``).
    attrs : dict of str to str
        Attributes by local name (``xmlns`` declarations left out).
    line : int
        1-based line of the start tag.
    children : list of XmlNode
    text : str
        Character data directly inside the element, as written (names keep
        their blanks; numbers are stripped where they are read).
    """

    tag: str
    attrs: dict[str, str]
    line: int
    children: list[XmlNode] = field(default_factory=list)
    text: str = ""

    def child(self, tag: str) -> XmlNode | None:
        """The first child called ``tag``, or None."""
        return next((c for c in self.children if c.tag == tag), None)

    def all(self, tag: str) -> list[XmlNode]:
        """The children called ``tag``."""
        return [c for c in self.children if c.tag == tag]

    def iter(self, tag: str) -> Iterator[XmlNode]:
        """Every descendant called ``tag``, depth first, in document order."""
        stack = list(reversed(self.children))
        while stack:
            node = stack.pop()
            if node.tag == tag:
                yield node
            stack.extend(reversed(node.children))

    def text_of(self, *path: str) -> str | None:
        """Text of the descendant reached through ``path`` (``"name", "text"``), or None."""
        node: XmlNode | None = self
        for tag in path:
            node = node.child(tag) if node is not None else None
        return None if node is None else node.text


class _Refused(Exception):
    pass


def _local(name: str) -> str:
    return name.rsplit(":", 1)[-1]


def parse_xml(data: bytes, file: str | None = None) -> XmlNode:
    """Parse an XML document safely into :class:`XmlNode` (the root element).

    A document type declaration is refused before anything in it is read:
    that is where entities are declared, so an entity-expansion bomb or an
    external entity never gets expanded.

    Raises
    ------
    InputError
        DOCTYPE present, or malformed XML (the line, and the innermost open
        element, are named).

    Examples
    --------
    >>> root = parse_xml(b'<a xmlns="urn:x"><b id="1">hi</b></a>')
    >>> root.tag, root.child("b").attrs, root.child("b").text
    ('a', {'id': '1'}, 'hi')
    >>> parse_xml(b'<!DOCTYPE a [<!ENTITY e "x">]><a>&e;</a>')
    Traceback (most recent call last):
    ...
    tegraph.errors.InputError: DOCTYPE: XML document type declarations are refused (they can expand entities or fetch external files); remove the DOCTYPE
    """
    parser = expat.ParserCreate()
    parser.buffer_text = True
    parser.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)
    stack: list[XmlNode] = []
    texts: list[list[str]] = []
    root: list[XmlNode] = []

    def refuse(*_: Any) -> None:
        raise _Refused

    def start(tag: str, attrs: dict[str, str]) -> None:
        node = XmlNode(_local(tag), {_local(k): v for k, v in attrs.items()
                                     if k != "xmlns" and not k.startswith("xmlns:")},
                       parser.CurrentLineNumber)
        if stack:
            stack[-1].children.append(node)
        else:
            root.append(node)
        stack.append(node)
        texts.append([])

    def end(_tag: str) -> None:
        stack.pop().text = "".join(texts.pop())

    def chars(text: str) -> None:
        texts[-1].append(text)

    parser.StartDoctypeDeclHandler = refuse  # type: ignore[assignment]
    parser.EntityDeclHandler = refuse  # type: ignore[assignment]
    parser.ExternalEntityRefHandler = refuse  # type: ignore[assignment]
    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.CharacterDataHandler = chars
    try:
        parser.Parse(data, True)
    except _Refused:
        raise InputError("XML document type declarations are refused (they can expand "
                         "entities or fetch external files); remove the DOCTYPE", "DOCTYPE",
                         file, parser.CurrentLineNumber) from None
    except expat.ExpatError as exc:
        where = "/".join(_describe(n) for n in stack)
        raise InputError(f"malformed XML: {expat.ErrorString(exc.code)} (column {exc.offset + 1})"
                         + (" inside this element, which is never closed" if stack else ""),
                         where, file, exc.lineno) from None
    if not root:
        raise InputError("the document has no element", "", file)
    return root[0]


def _describe(node: XmlNode) -> str:
    key = next((node.attrs[k] for k in ("id", "name") if k in node.attrs), None)
    return f"{node.tag}[{key}]" if key is not None else node.tag


# --------------------------------------------------------------------------- detection

_XML_ROOT = re.compile(rb"<\s*(?:[\w.-]+:)?(pnml|sdf3)\b")


def detect_format(path: str | os.PathLike[str], head: bytes | None = None) -> str:
    """The format name of a file, from its extension, else from its first bytes.

    ``.xml`` files are told apart by their root element (``pnml`` or
    ``sdf3``), ``.json`` files by their keys (TimedPetriNetEditor files have
    ``nets``; skeletons have ``tasks``).

    >>> detect_format("a.pnml"), detect_format("b.edges"), detect_format("c.xml", b"<sdf3 type='sdf'>")
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
        return "tpne-json" if re.search(rb'"(nets|revision)"\s*:', head) else "skeleton"
    if re.match(rb"(\s*(#[^\n]*)?\n)*\s*\d+\s+\d+\s+\S+\s+\d+\s*(#|\n|$)", text):
        return "edges"
    if text.startswith(b"<"):
        raise InputError("an XML file whose root element is neither <pnml> nor <sdf3>", file=file)
    raise InputError("cannot tell the format of this file; expected one of "
                     + ", ".join(ext for exts in FORMATS.values() for ext in exts)
                     + " (or give the format explicitly)", file=file)


# --------------------------------------------------------------------------- coercions


def as_teg_like(obj: Any) -> TimedEventGraph | ArcList:
    """A timed event graph, or an arc list for array-sized graphs, from any model.

    Skeletons are built (spec §2), SDF graphs expanded through their
    repetition vector, marked graphs converted.

    Raises
    ------
    InputError
        A P/T net that is not a marked graph (the reason names the place or arc),
        or an object of no known model.
    """
    from ..build import build_teg
    from ..petri import PetriNet
    from ..skeleton import Skeleton
    from ..teg import TimedEventGraph
    from .edges import ArcList
    from .sdf3 import SDFGraph

    if isinstance(obj, (TimedEventGraph, ArcList)):
        return obj
    if isinstance(obj, Skeleton):
        return build_teg(obj)
    if isinstance(obj, SDFGraph):
        return obj.to_arcs()
    if isinstance(obj, PetriNet):
        why = obj.marked_graph_violation()
        if why is not None:
            raise InputError(f"not a marked graph: {why}", f"net {obj.name}")
        return obj.to_teg()
    raise InputError(f"expected a skeleton, timed event graph, P/T net, SDF graph or arc list, "
                     f"got {type(obj).__name__}")


def as_teg(obj: Any) -> TimedEventGraph:
    """Like :func:`as_teg_like`, always a :class:`~tegraph.teg.TimedEventGraph`."""
    from ..teg import TimedEventGraph

    g = as_teg_like(obj)
    return g if isinstance(g, TimedEventGraph) else g.to_teg()


def as_petri_net(obj: Any) -> PetriNet:
    """A P/T net: itself, or the net of the timed event graph of ``obj``."""
    from ..petri import PetriNet

    return obj if isinstance(obj, PetriNet) else PetriNet.from_teg(as_teg(obj))


# --------------------------------------------------------------------------- read / write


def _readers() -> dict[str, Callable[..., Any]]:
    from . import dot, edges, pnml, sdf3, tpne  # noqa: F401  (dot: no reader)

    return {"pnml": pnml.read_pnml, "sdf3": sdf3.read_sdf3, "edges": edges.read_edges,
            "tpne-json": tpne.read_tpne_json, "tpne-teg": tpne.read_tpne_teg,
            "skeleton": _read_skeleton}


def _writers() -> dict[str, Callable[..., Any]]:
    from . import dot, edges, pnml, sdf3, tpne

    return {"pnml": pnml.write_pnml, "sdf3": sdf3.write_sdf3, "edges": edges.write_edges,
            "tpne-json": tpne.write_tpne_json, "tpne-teg": tpne.write_tpne_teg,
            "dot": dot.write_dot, "teg-dot": dot.write_teg_dot, "skeleton": _write_skeleton}


def _read_skeleton(path: str | os.PathLike[str], *, max_bytes: int = DEFAULT_MAX_BYTES) -> Any:
    from .skeleton_file import load_skeleton

    check_size(path, max_bytes)
    return load_skeleton(path)


def _write_skeleton(obj: Any, path: str | os.PathLike[str], overwrite: bool = False) -> Path:
    from ..skeleton import Skeleton
    from .skeleton_file import dump_skeleton

    if not isinstance(obj, Skeleton):
        raise InputError(f"a skeleton file holds a skeleton; a {type(obj).__name__} cannot "
                         "become one (a skeleton becomes a timed event graph, not the other "
                         "way round)", file=os.fspath(path))
    return dump_skeleton(obj, path, overwrite=overwrite)


def read(path: str | os.PathLike[str], format: str | None = None, *,
         max_bytes: int = DEFAULT_MAX_BYTES) -> Any:
    """Read any supported file; the reader is picked from the file (see the module table).

    Parameters
    ----------
    path : str or path-like
    format : str, optional
        Force a format name of :data:`FORMATS` instead of detecting it.
    max_bytes : int
        Refuse larger files (default :data:`DEFAULT_MAX_BYTES`).

    Raises
    ------
    InputError
        Unknown format, file too large, or a malformed file (the message
        names the file, the line when known, and the element).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "ring.edges"
    >>> _ = f.write_text("0 1 2 0\\n1 0 3 1\\n")
    >>> g = read(f); g.n_transitions, g.n_places
    (2, 2)
    """
    readers = _readers()
    fmt = format or detect_format(path)
    if fmt not in readers:
        raise InputError(f"format {fmt!r} cannot be read; readable: {', '.join(sorted(readers))}",
                         file=os.fspath(path))
    return readers[fmt](path, max_bytes=max_bytes)


def write(obj: Any, path: str | os.PathLike[str], format: str | None = None,
          overwrite: bool = False) -> Path:
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
    fmt = format or _format_for_writing(obj, file)
    writers = _writers()
    if fmt not in writers:
        raise InputError(f"format {fmt!r} cannot be written; writable: "
                         f"{', '.join(sorted(writers))}", file=file)
    try:
        return writers[fmt](obj, path, overwrite=overwrite)
    except ModelError as exc:
        raise InputError(f"cannot be written as {fmt}: {exc}", file=file) from None


def _format_for_writing(obj: Any, file: str) -> str:
    from ..skeleton import Skeleton

    ext = Path(file).suffix.lower()
    if ext == ".json":
        return "skeleton" if isinstance(obj, Skeleton) else "tpne-json"
    if ext == ".xml":
        from .sdf3 import SDFGraph

        return "sdf3" if isinstance(obj, SDFGraph) else "pnml"
    for name, exts in FORMATS.items():
        if ext in exts:
            return name
    raise InputError(f"cannot tell the format from the extension {ext!r}; use one of "
                     + ", ".join(e for exts in FORMATS.values() for e in exts)
                     + ", .xml, or give the format", file=file)


def load_json_document(data: bytes, file: str) -> Any:
    """JSON text to Python data; malformed JSON becomes an InputError with its line."""
    try:
        return json.loads(data.decode("utf-8-sig"))
    except UnicodeDecodeError as exc:
        raise InputError(f"not UTF-8 text (byte {exc.start})", file=file) from None
    except json.JSONDecodeError as exc:
        raise InputError(f"malformed JSON: {exc.msg} (column {exc.colno})", file=file,
                         line=exc.lineno) from None
