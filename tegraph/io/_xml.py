"""Safe XML: expat with every document type declaration refused.

No entity is ever expanded and no external file is ever fetched: an
entity-expansion bomb is refused at its first line. Elements come back as
:class:`XmlNode` trees with namespace prefixes dropped and line numbers kept.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any
from xml.parsers import expat

from ..errors import InputError

__all__ = ["XmlNode", "parse_xml"]


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
    >>> parse_xml(b'<!DOCTYPE a [<!ENTITY e "x">]><a>&e;</a>')  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    tegraph.errors.InputError: DOCTYPE: XML document type declarations are refused ...
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

    parser.StartDoctypeDeclHandler = refuse
    parser.EntityDeclHandler = refuse
    # Type: typeshed wants a handler returning int; refuse raises before returning.
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
    except LookupError as exc:  # <?xml encoding="..."?> names no codec Python has
        raise InputError(f"the XML declaration names an unknown encoding ({exc}); expected "
                         "UTF-8 or another encoding Python knows", "encoding", file,
                         1) from None
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
