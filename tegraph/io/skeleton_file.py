"""Read and write skeleton files (spec §1): YAML or JSON, every refusal located.

The YAML document is composed into nodes and built here rather than by
PyYAML's constructor, for three reasons: duplicate keys are refused (YAML
would silently keep the last one), every key and list item gets its 1-based
line for the messages, and names and numbers are taken from the text the
user wrote (YAML 1.1 reads the port ``on`` as true, ``010`` as eight and ``0x1A``
as 26; a plain scalar YAML reads as a number outside the number grammar stays text).
The checks themselves live in the model (:mod:`tegraph.model.skeleton.schema`
and :mod:`tegraph.model.skeleton.checks`), shared with skeletons built in code.
"""

from __future__ import annotations

import json
import os
import re
from decimal import Decimal
from pathlib import Path
from typing import Any

import yaml
from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from maxplus.errors import MaxPlusValueError
from maxplus.scalar import exact, size_problem

from ..errors import SkeletonError
from ..model.limits import text_problem
from ..model.skeleton import Skeleton
from ..model.skeleton.checks import KeyPath, Locator
from ._detect import FORMAT_NAMES, sniff_format

__all__ = ["SKELETON_EXTENSIONS", "dump_skeleton", "load_skeleton"]

SKELETON_EXTENSIONS = (".yaml", ".yml", ".json")
"""The extensions of skeleton files: ``.json`` is JSON, the others YAML."""

_MAP_TAG = "tag:yaml.org,2002:map"
_SEQ_TAG = "tag:yaml.org,2002:seq"
_MERGE_TAG = "tag:yaml.org,2002:merge"
# Aliases can expand a small file exponentially ("billion laughs"): stop early.
# Only what aliases add is counted (a node built a second time, and every time
# after): a large file without aliases is never refused, however many nodes it has.
_MAX_ELEMENTS = 1_000_000


class _Builder:
    """Build Python data from composed YAML nodes, recording lines and source texts."""

    def __init__(self, loader: yaml.SafeLoader, loc: Locator) -> None:
        self.loader = loader
        self.loc = loc
        self.budget = _MAX_ELEMENTS
        self.built: set[int] = set()  # nodes built once: building one again is an alias
        self.open: set[int] = set()  # nodes being built: an alias to one is recursive
        self.flattened: set[int] = set()

    def build(self, node: Node, path: KeyPath) -> Any:
        if id(node) in self.built:
            self.budget -= 1
            if self.budget < 0:
                raise self.loc.error(
                    f"aliases add more than {_MAX_ELEMENTS} elements to the document; "
                    "expected a skeleton of ordinary size",
                    path,
                )
        else:
            self.built.add(id(node))
        if isinstance(node, ScalarNode):
            return self.scalar(node, path)
        if id(node) in self.open:
            raise self.loc.error("a recursive alias; expected a tree of mappings and lists", path)
        self.open.add(id(node))
        try:
            if isinstance(node, SequenceNode) and node.tag == _SEQ_TAG:
                items = []
                for i, item in enumerate(node.value):
                    self.loc.lines[(*path, i)] = item.start_mark.line + 1
                    items.append(self.build(item, (*path, i)))
                return items
            if isinstance(node, MappingNode) and node.tag == _MAP_TAG:
                return self.mapping(node, path)
            raise self.loc.error(
                f"unsupported YAML tag {node.tag!r}; expected plain mappings and lists", path
            )
        finally:
            self.open.discard(id(node))

    def key(self, node: Node, path: KeyPath) -> str:
        if not isinstance(node, ScalarNode):
            self.loc.lines[path] = node.start_mark.line + 1
            raise self.loc.error("a key that is a mapping or a list; expected a name", path)
        return str(node.value)  # the text as written: `1:` and `on:` are names too

    def mapping(self, node: MappingNode, path: KeyPath) -> dict[str, Any]:
        if id(node) not in self.flattened:
            # Look for duplicates before merging `<<` keys: a merged key that the
            # mapping overrides is YAML's intended use, not a duplicate.
            first: dict[str, int] = {}
            for key_node, _ in node.value:
                if key_node.tag == _MERGE_TAG:
                    continue
                key = self.key(key_node, path)
                line = key_node.start_mark.line + 1
                if key in first:
                    self.loc.lines[(*path, key)] = line
                    raise self.loc.error(
                        f"duplicate key {key!r} (first at line {first[key]}); expected each "
                        "key once: a reader would silently keep only the last value",
                        (*path, key),
                    )
                first[key] = line
            self.loader.flatten_mapping(node)
            self.flattened.add(id(node))
        out: dict[str, Any] = {}
        for key_node, value_node in node.value:
            key = self.key(key_node, path)
            self.loc.lines[(*path, key)] = key_node.start_mark.line + 1
            out[key] = self.build(value_node, (*path, key))
        return out

    def scalar(self, node: ScalarNode, path: KeyPath) -> Any:
        if not node.style and node.tag in _NUMBER_TAGS and _outside_grammar(node.value):
            # YAML 1.1 reads 0x1A as 26, 0b11 as 3, 1:30 as 90, 1__0 as 10 and .inf as
            # infinity; the number grammar (docs/skeleton.md) has none of them. The text
            # as written goes on, so a time or a priority is refused at its key path
            # ("got the text '0x1A'") and a name such as a port `0x1A` stays that name.
            return node.value
        try:
            value = self.loader.construct_object(node)
        except ValueError as err:  # e.g. an int of more digits than Python converts
            too_big = size_problem(node.value.replace("_", ""))  # the one bound
            if too_big is not None:
                raise self.loc.error(too_big, path) from None
            raise self.loc.error(f"cannot read this value ({err}); expected a number "
                                 "or a name", path) from None
        if not node.style and not isinstance(value, str):  # plain scalar (None or "" by parser)
            self.loc.raw[path] = node.value
        return value


_NUMBER_TAGS = ("tag:yaml.org,2002:int", "tag:yaml.org,2002:float")
_PLAIN_INT = re.compile(r"[+-]?[0-9]+")  # in the grammar for sure: the fast path


def _outside_grammar(text: str) -> bool:
    """Whether a plain YAML number is no number of the grammar (hex, base 60, .inf...).

    The grammar is that of :func:`maxplus.scalar.exact`, the project's one number
    parser; a text it refuses only by its size is a number of the grammar (refused
    later, by its size, at its key path).
    """
    if _PLAIN_INT.fullmatch(text):
        return False
    try:
        exact(text)
    except MaxPlusValueError:
        return size_problem(text) is None
    return False


# libyaml's parser is an order of magnitude faster; its nodes carry the same marks.
_Loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


def _expansion(root: Node) -> tuple[int, int]:
    """Nodes of the document as composed (each once) and as built (each alias expanded).

    Computed over the composed nodes alone, children before parents, so a
    billion-laughs document is measured in microseconds; a recursive alias
    (a cycle) is left to the builder, which names it.
    """
    size: dict[int, int] = {}
    opened: set[int] = set()  # on the current path: meeting one again is a cycle
    stack: list[tuple[Node, bool]] = [(root, False)]
    while stack:
        node, done = stack.pop()
        if id(node) in size:
            continue
        children = [] if isinstance(node, ScalarNode) else (
            [n for pair in node.value for n in pair] if isinstance(node, MappingNode)
            else list(node.value))
        if done:
            opened.discard(id(node))
            size[id(node)] = 1 + sum(size[id(c)] for c in children)
            continue
        if id(node) in opened:
            return len(size), 0  # a recursive alias: the builder names it
        opened.add(id(node))
        stack.append((node, True))
        stack.extend((c, False) for c in children if id(c) not in size)
    return len(size), size[id(root)]


def _read_yaml(text: str, loc: Locator) -> Any:
    loader = _Loader(text)
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        # An alias needs an anchor ('&'): without one no node is shared, nothing to measure.
        distinct, built = _expansion(node) if "&" in text else (0, 0)
        if built - distinct > 2 * _MAX_ELEMENTS:  # surely above: refuse before building
            raise loc.error(
                f"aliases add {built - distinct} elements to the document, more than "
                f"{_MAX_ELEMENTS}; expected a skeleton of ordinary size", ())
        return _Builder(loader, loc).build(node, ())
    except yaml.MarkedYAMLError as err:
        mark = err.problem_mark or err.context_mark
        problem = err.problem or err.context or "unreadable"
        raise SkeletonError(
            f"not valid YAML: {problem}; expected a YAML mapping as in the skeleton format",
            file=loc.file, line=mark.line + 1 if mark else None,
        ) from None
    except (yaml.YAMLError, RecursionError) as err:
        raise SkeletonError(
            f"not valid YAML: {err or 'nested too deeply'}; expected a YAML mapping as in "
            "the skeleton format", file=loc.file,
        ) from None
    finally:
        loader.dispose()


class _DuplicateKey(Exception):
    def __init__(self, key: str) -> None:
        super().__init__(key)
        self.key = key


def _unique_pairs(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    # dict() builds the object in C; a duplicate shows as a shorter dict (some 20,000
    # objects in a 10,000-task file: 31 ms of parse before, 22 ms after).
    out = dict(pairs)
    if len(out) < len(pairs):
        seen: set[str] = set()
        for key, _ in pairs:  # the first key met twice, as the message names it
            if key in seen:
                raise _DuplicateKey(key)
            seen.add(key)
    return out


def _read_json(text: str, loc: Locator) -> Any:
    try:
        # Decimal keeps "0.1" exact and never overflows to inf.
        return json.loads(text, object_pairs_hook=_unique_pairs, parse_float=Decimal)
    except _DuplicateKey as dup:
        # Composing the text as YAML (most JSON is YAML) finds the line of the
        # duplicate; when it cannot, the message goes without a line.
        try:
            _read_yaml(text, Locator(file=loc.file))
        except SkeletonError as err:
            if err.reason.startswith("duplicate key"):
                raise err from None
        raise SkeletonError(f"duplicate key {dup.key!r}; expected each key once",
                            file=loc.file) from None
    except json.JSONDecodeError as err:
        raise SkeletonError(f"not valid JSON: {err.msg} (column {err.colno}); expected a "
                            "JSON object as in the skeleton format",
                            file=loc.file, line=err.lineno) from None
    except (ValueError, RecursionError) as err:
        raise SkeletonError(f"not valid JSON: {err or 'nested too deeply'}; expected a JSON "
                            "object as in the skeleton format", file=loc.file) from None


def _json_lines(text: str, loc: Locator) -> None:
    """Fill ``loc`` with the line of every key path, by composing the JSON as YAML."""
    probe = Locator(file=loc.file)
    try:
        _read_yaml(text, probe)
    except SkeletonError:
        return
    loc.lines.update(probe.lines)


def load_skeleton(path: str | os.PathLike[str]) -> Skeleton:
    """Read a skeleton file and check every rule of spec §1.

    Parameters
    ----------
    path : str or path-like
        A ``.json`` file is read as JSON, anything else (``.yaml``, ``.yml``)
        as YAML.

    Returns
    -------
    Skeleton
        Named by the file's ``name`` key, else by the file's stem; ``source``
        is ``path`` as given.

    Raises
    ------
    SkeletonError
        The file does not exist, is empty, is not valid YAML/JSON, or breaks a
        rule of the format; the message names the file, the key path, the line
        when known, and what is expected.

    See Also
    --------
    dump_skeleton : the converse.
    tegraph.io.read : any supported file.
    tegraph.model.skeleton.Skeleton.from_dict : a skeleton from a mapping.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "demo.yaml"
    >>> _ = f.write_text("tasks:\\n  A: {duration: 0.1, period: '7/3'}\\n")
    >>> sk = load_skeleton(f)
    >>> sk.name, sk.tasks["A"].duration, sk.clocks["A.clock"].period
    ('demo', Fraction(1, 10), Fraction(7, 3))
    """
    file = os.fspath(path)
    where = Path(file)
    loc = Locator(file=file)
    try:
        raw = where.read_bytes()
    except FileNotFoundError:
        raise SkeletonError("no such file; expected an existing skeleton file "
                            "(.yaml, .yml or .json)", file=file) from None
    except IsADirectoryError:
        raise SkeletonError("is a directory; expected a skeleton file", file=file) from None
    except OSError as err:
        raise SkeletonError(f"cannot be read ({err.strerror}); expected a readable "
                            "skeleton file", file=file) from None
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        raise SkeletonError(f"not UTF-8 text (byte 0x{raw[err.start]:02x} at offset "
                            f"{err.start}); expected a YAML or JSON text file", file=file,
                            line=raw[:err.start].count(b"\n") + 1) from None
    data = None
    as_json = where.suffix.lower() == ".json"
    if text.strip():
        try:
            if not as_json and text.lstrip().startswith("{"):
                # JSON is YAML, and JSON's parser is some twenty times faster than YAML's
                # on a large file (a generated skeleton of 100,000 tasks): try it first.
                try:
                    data, as_json = _read_json(text, loc), True
                except SkeletonError:
                    data = _read_yaml(text, loc)
            else:
                data = _read_json(text, loc) if as_json else _read_yaml(text, loc)
        except SkeletonError:
            _other_format(raw, file)  # an XML net read as YAML fails: say what it is
            raise
    if not isinstance(data, dict) or "tasks" not in data:
        _other_format(raw, file, data)
    if data is None:  # nothing but blanks or comments
        raise SkeletonError("the file is empty; expected a skeleton with at least 'tasks'",
                            file=file)
    if _SURROGATE_ESCAPE.search(text):
        _refuse_surrogates(data, loc)
    if not as_json:
        return Skeleton.from_dict(data, where.stem, file, locator=loc)
    try:
        return Skeleton.from_dict(data, where.stem, file, locator=loc)
    except SkeletonError:
        # Lines of a JSON file are looked up only when there is an error to place.
        _json_lines(text, loc)
        return Skeleton.from_dict(data, where.stem, file, locator=loc)


def _other_format(raw: bytes, file: str, data: Any = None) -> None:
    """Refuse a file of another format that tegraph reads, saying which commands read it.

    Called only when the file is no skeleton anyway (it does not parse, or
    holds no ``tasks`` mapping), so a skeleton is never refused for how it looks.
    """
    fmt = sniff_format(raw[:4096])
    if fmt is None and isinstance(data, dict) and isinstance(data.get("nets"), list):
        fmt = "tpne-json"
    if fmt is None:
        return
    readers = ("tegraph writes DOT drawings but reads none" if fmt == "dot" else
               "`tegraph cycle-time` and `tegraph reach` read it (tegraph.io.read in Python)")
    raise SkeletonError(f"this is {FORMAT_NAMES[fmt]}, not a skeleton file; {readers}",
                        file=file)


# JSON's "\ud800" and YAML's "\ud800" or "\U0000d800": a surrogate written as an escape
_SURROGATE_ESCAPE = re.compile(r"\\(u|U0000)[dD][89a-fA-F]")


def _refuse_surrogates(data: Any, loc: Locator) -> None:
    """Refuse the first key or text holding a lone surrogate, at its key path.

    Such a name is read without complaint and fails only when a report or a
    file is written (UnicodeEncodeError); it is refused where it is read.
    """
    stack: list[tuple[KeyPath, Any]] = [((), data)]
    while stack:
        path, value = stack.pop()
        if isinstance(value, str):
            why = text_problem(value)
            if why is not None:
                raise loc.error(why, path)
        elif isinstance(value, dict):
            for key, item in reversed(list(value.items())):
                why = text_problem(key)
                if why is not None:  # the key path shows the surrogate escaped
                    raise loc.error(f"the key {why}",
                                    (*path, key.encode("utf-8", "backslashreplace").decode()))
                stack.append(((*path, key), item))
        elif isinstance(value, list):
            stack.extend(((*path, i), item) for i, item in reversed(list(enumerate(value))))


class _Dumper(yaml.SafeDumper):
    """Block mappings, but lists of names on one line: ``inputs: [a, b]``."""

    def ignore_aliases(self, data: Any) -> bool:
        return True

    def represent_list(self, data: Any) -> yaml.Node:
        flow = all(isinstance(item, (str, int)) for item in data)
        return self.represent_sequence(_SEQ_TAG, data, flow_style=flow)


_Dumper.add_representer(list, _Dumper.represent_list)


def dump_skeleton(sk: Skeleton, path: str | os.PathLike[str], overwrite: bool = False) -> Path:
    """Write a skeleton file that :func:`load_skeleton` reads back equal.

    Parameters
    ----------
    sk : Skeleton
        The skeleton to write.
    path : str or path-like
        ``.json`` writes JSON, ``.yaml`` and ``.yml`` YAML; any other
        extension is refused (nothing is written).
    overwrite : bool
        Replace an existing file; without it an existing file is never touched.

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    FileExistsError
        ``path`` exists and ``overwrite`` is False.
    SkeletonError
        ``sk`` breaks a rule of spec §1, or ``path`` has no skeleton extension
        (nothing is written).

    See Also
    --------
    load_skeleton : the converse.
    tegraph.write : any model to any format.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": "7/3", "period": 4}}}, "s")
    >>> f = dump_skeleton(sk, pathlib.Path(tempfile.mkdtemp()) / "s.yaml")
    >>> print(f.read_text(), end="")
    name: s
    unit: ms
    tasks:
      A:
        duration: 7/3
        period: 4
    >>> load_skeleton(f) == sk
    True
    """
    target = Path(os.fspath(path))
    if target.suffix.lower() not in SKELETON_EXTENSIONS:
        raise SkeletonError(f"a skeleton file is .yaml, .yml or .json, not "
                            f"{target.suffix or 'a name without extension'!r}; name the file "
                            "accordingly (other formats take a timed event graph: "
                            "tegraph.io.write)", file=str(target))
    data = sk.to_dict()
    if target.suffix.lower() == ".json":
        text = json.dumps(data, indent=2, ensure_ascii=False) + "\n"
    else:
        text = yaml.dump(data, Dumper=_Dumper, sort_keys=False, allow_unicode=True,
                         default_flow_style=False)
    try:
        # Mode "x" refuses an existing file atomically (no check-then-write race).
        with open(target, "w" if overwrite else "x", encoding="utf-8") as out:
            out.write(text)
    except FileExistsError:
        raise FileExistsError(f"{target}: the file exists already; pass overwrite=True "
                              "to replace it") from None
    return target
