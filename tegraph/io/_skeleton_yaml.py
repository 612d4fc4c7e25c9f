"""YAML skeleton files: the document built from PyYAML's nodes, and the writer's style.

The YAML document is composed into nodes and built here rather than by
PyYAML's constructor, for three reasons: duplicate keys are refused (YAML
would silently keep the last one), every key and list item gets its 1-based
line for the messages, and names and numbers are taken from the text the
user wrote (YAML 1.1 reads the port ``on`` as true, ``010`` as eight and ``0x1A``
as 26; a plain scalar YAML reads as a number outside the number grammar stays text).
:mod:`tegraph.io.skeleton_file` imports this module for YAML text only.
"""

from __future__ import annotations

import re
from typing import Any

import yaml
from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from maxplus.errors import MaxPlusValueError
from maxplus.scalar import exact, size_problem

from ..errors import SkeletonError
from ..model.skeleton.checks import KeyPath, Locator

__all__ = ["dump_yaml", "read_yaml"]

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


def read_yaml(text: str, loc: Locator) -> Any:
    """The data of a YAML skeleton text, its lines and source texts recorded in ``loc``.

    Raises
    ------
    SkeletonError
        Not valid YAML, a duplicate key, an unsupported tag, aliases that expand
        too far: each located.
    """
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


class _Dumper(yaml.SafeDumper):
    """Block mappings, but lists of names on one line: ``inputs: [a, b]``."""

    def ignore_aliases(self, data: Any) -> bool:
        return True

    def represent_list(self, data: Any) -> yaml.Node:
        flow = all(isinstance(item, (str, int)) for item in data)
        return self.represent_sequence(_SEQ_TAG, data, flow_style=flow)


_Dumper.add_representer(list, _Dumper.represent_list)


def dump_yaml(data: Any) -> str:
    """The text of a skeleton's dictionary form as a YAML file holds it (block style)."""
    return yaml.dump(data, Dumper=_Dumper, sort_keys=False, allow_unicode=True,
                     default_flow_style=False)
