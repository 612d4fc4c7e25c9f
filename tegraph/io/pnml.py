"""PNML (ISO/IEC 15909-2) place/transition nets, read and written.

Reading is namespace-agnostic and accepts the net types ``ptnet`` and
``pnmlcoremodel`` (any URI ending so); places, transitions and arcs are
collected from every page, nested pages and reference nodes included.
``initialMarking`` and ``inscription`` (the arc weight, default 1) are read
from their ``<text>``; unknown ``toolspecific`` elements are ignored.

Timing, read from two places and added up:

* this project's element, inside a place::

      <toolspecific tool="tegraph" version="1">
        <holding>7/3</holding>     <!-- holding time, exact, >= 0 -->
        <initial>0</initial>       <!-- availability of the initial tokens -->
      </toolspecific>

* TINA's ``<delay>`` on a transition (a MathML interval ``[a, b]``): the
  firing takes ``a`` (the earliest behaviour) and each output place of the
  transition holds it, as an SDF actor's execution time does. TINA's
  single-server rule (a transition is newly enabled after each firing) is
  not added; the cycle ratio of every circuit is the same either way unless
  a transition fires faster than its own delay.

A net with neither has no timing (``PetriNet.holding`` empty).

Writing uses the 2009 namespace, type ``ptnet``, one page, and keeps every
name; timing goes only into the ``toolspecific`` element above, never into
``inscription``, which is the arc weight. A net read back from what was
written is equal and gives the same figures.
"""

from __future__ import annotations

import os
import re
from collections import Counter
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

from maxplus.errors import MaxPlusValueError
from maxplus.scalar import exact_text, exact_time, size_problem

from ..errors import InputError
from ..model.convert import as_petri_net
from ..model.limits import (
    MAX_COUNT,
    count_problem,
    denominator_problem,
    shown,
)
from ..model.petri import PetriNet
from ._files import DEFAULT_MAX_BYTES, read_limited, write_bytes
from ._xml import XmlNode, parse_xml

__all__ = ["PNML_NAMESPACE", "PTNET_TYPE", "TOOL", "TOOL_VERSION", "dumps_pnml", "parse_pnml",
           "read_pnml", "write_pnml"]

PNML_NAMESPACE = "http://www.pnml.org/version-2009/grammar/pnml"
PTNET_TYPE = "http://www.pnml.org/version-2009/grammar/ptnet"
TOOL = "tegraph"
TOOL_VERSION = "1"
_NCNAME = re.compile(r"[A-Za-z_][\w.\-]*\Z")


def read_pnml(path: str | os.PathLike[str], *, max_bytes: int = DEFAULT_MAX_BYTES) -> PetriNet:
    """Read a PNML file; see the module docstring."""
    file = os.fspath(path)
    return parse_pnml(read_limited(file, max_bytes), file)


def parse_pnml(data: bytes | str, file: str | None = None) -> PetriNet:
    """Parse PNML text into a :class:`~tegraph.model.petri.PetriNet`.

    Places and transitions are named by their ``<name>`` when it is given and
    unique, else by their id; ``net.attrs["pnml_ids"]`` keeps the ids so that
    writing the net back reuses them.

    Raises
    ------
    InputError
        Malformed XML, a DOCTYPE, no net or several, an unsupported net type,
        a node without id, a duplicate id, an arc to an unknown node or
        between two places or two transitions, a marking or weight that is
        not an integer, a negative or malformed time. The message names the
        element and its line.

    Examples
    --------
    >>> net = parse_pnml('''<pnml><net id="n" type="http://www.pnml.org/version-2009/grammar/ptnet">
    ... <page id="g"><place id="p"><initialMarking><text>1</text></initialMarking></place>
    ... <transition id="t"/><arc id="a1" source="p" target="t"/><arc id="a2" source="t" target="p">
    ... <inscription><text>2</text></inscription></arc></page></net></pnml>''')
    >>> net.places, net.transitions, net.pre.tolist(), net.post.tolist(), net.marking.tolist()
    (['p'], ['t'], [[1]], [[2]], [1])
    """
    if isinstance(data, str):
        data = data.encode("utf-8")
    root = parse_xml(data, file)
    if root.tag != "pnml":
        raise InputError(f"the root element is <{root.tag}>, expected <pnml>", root.tag, file,
                         root.line)
    nets = root.all("net")
    if len(nets) != 1:
        raise InputError(f"the document holds {len(nets)} nets; tegraph reads exactly one",
                         "pnml", file, root.line)
    net = nets[0]
    net_id = net.attrs.get("id") or Path(file or "net").stem
    net_name = net.text_of("name", "text")
    net_name = net_name if net_name and net_name.strip() else net_id
    kind = net.attrs.get("type", "")
    if not kind.rstrip("/").endswith(("ptnet", "pnmlcoremodel")):
        raise InputError(f"net type {kind!r} is not supported; expected a P/T net (ptnet or "
                         "pnmlcoremodel)", f"net[{net_id}]", file, net.line)
    nodes: dict[str, tuple[str, XmlNode]] = {}
    arcs: list[XmlNode] = []
    refs: dict[str, tuple[str, XmlNode]] = {}
    _collect(net, nodes, arcs, refs, set(), file)
    places = [i for i, (k, _) in nodes.items() if k == "place"]
    transitions = [i for i, (k, _) in nodes.items() if k == "transition"]
    p_index = {i: k for k, i in enumerate(places)}
    t_index = {i: k for k, i in enumerate(transitions)}
    # (kind, place, transition) -> weight; parallel arcs add up, in Python ints
    weights: dict[tuple[str, int, int], int] = {}
    for arc in arcs:
        aid = arc.attrs["id"]
        where = f"arc[{aid}]"
        ends = []
        for end in ("source", "target"):
            ref = arc.attrs.get(end)
            if not ref:
                raise InputError(f"the arc has no {end} attribute", where, file, arc.line)
            ends.append(_resolve(ref, nodes, refs, where, end, file, arc.line))
        weight = _count(arc.text_of("inscription", "text"), "inscription", where, file, arc.line,
                        default=1)
        if weight < 1:
            raise InputError(f"an arc weight must be >= 1, got {weight}", where, file, arc.line)
        (s_kind, s), (d_kind, d) = ends
        if s_kind == d_kind:
            raise InputError(f"the arc joins two {s_kind}s ({s!r} and {d!r}); a P/T net arc "
                             "joins a place and a transition", where, file, arc.line)
        key = ("pre", p_index[s], t_index[d]) if s_kind == "place" else \
            ("post", p_index[d], t_index[s])
        weights[key] = weights.get(key, 0) + weight
        if weights[key] > MAX_COUNT:
            raise InputError(f"the arcs between {s!r} and {d!r} weigh {weights[key]} together, "
                             f"above 2**63 - 1 = {MAX_COUNT}", where, file, arc.line)
    shape = (len(places), len(transitions))
    pre, post = (sp.csr_array(
        (np.array([w for k, w in weights.items() if k[0] == kind], dtype=np.int64),
         (np.array([k[1] for k in weights if k[0] == kind], dtype=np.int64),
          np.array([k[2] for k in weights if k[0] == kind], dtype=np.int64))), shape=shape)
        for kind in ("pre", "post"))
    marking = np.array([_count(nodes[p][1].text_of("initialMarking", "text"), "initialMarking",
                               f"place[{p}]", file, nodes[p][1].line, default=0)
                        for p in places], dtype=np.int64)
    holding, initial, timed = _timing(places, transitions, nodes, post, file)
    why = denominator_problem(t.denominator for t in holding + initial)
    if why is not None:  # 1/2, 1/3, 1/5...: every time scaled by one huge denominator
        raise InputError(why, f"net[{net_id}]", file, net.line)
    result = PetriNet(net_name, _names(places, nodes), _names(transitions, nodes), pre, post,
                      marking, holding if timed else [], initial if timed else [])
    result.attrs["pnml_ids"] = {"places": places, "transitions": transitions}
    return result


def _collect(elem: XmlNode, nodes: dict[str, tuple[str, XmlNode]], arcs: list[XmlNode],
             refs: dict[str, tuple[str, XmlNode]], ids: set[str], file: str | None) -> None:
    """Places, transitions, arcs and reference nodes of every page, recursively."""
    for child in elem.children:
        kind = child.tag
        if kind in ("place", "transition", "arc", "referencePlace", "referenceTransition"):
            cid = child.attrs.get("id")
            if not cid:
                raise InputError(f"<{kind}> has no id attribute", kind, file, child.line)
            if cid in ids:
                raise InputError(f"duplicate id {cid!r}", f"{kind}[{cid}]", file, child.line)
            ids.add(cid)
            if kind == "arc":
                arcs.append(child)
            elif kind.startswith("reference"):
                refs[cid] = (kind[len("reference"):].lower(), child)
            else:
                nodes[cid] = (kind, child)
        elif kind == "page":
            _collect(child, nodes, arcs, refs, ids, file)


def _resolve(ref: str, nodes: dict[str, tuple[str, XmlNode]], refs: dict[str, tuple[str, XmlNode]],
             where: str, end: str, file: str | None, line: int) -> tuple[str, str]:
    seen = set()
    while ref in refs and ref not in seen:  # a reference node stands for the node it names
        seen.add(ref)
        ref = refs[ref][1].attrs.get("ref", "")
    if ref not in nodes:
        raise InputError(f"the arc's {end} {ref!r} is not a place or transition of the net",
                         where, file, line)
    return nodes[ref][0], ref


def _count(text: str | None, what: str, where: str, file: str | None, line: int,
           default: int) -> int:
    if text is None or not text.strip():
        return default
    if not re.fullmatch(r"\+?[0-9]+", text.strip()):
        raise InputError(f"{what} must be an integer >= 0, got {shown(text.strip())}", where,
                         file, line)
    why = size_problem(text.strip()) or count_problem(int(text), what)
    if why is not None:
        raise InputError(why, where, file, line)
    return int(text)


def _timing(places: list[str], transitions: list[str], nodes: dict[str, tuple[str, XmlNode]],
            post: sp.csr_array, file: str | None
            ) -> tuple[list[Fraction], list[Fraction], bool]:
    post_by_transition = post.T.tocsr()
    holding = [Fraction(0)] * len(places)
    initial = [Fraction(0)] * len(places)
    timed = False
    for k, p in enumerate(places):
        elem = nodes[p][1]
        for tool in elem.all("toolspecific"):
            if tool.attrs.get("tool") != TOOL:
                continue
            timed = True
            for tag, target in (("holding", holding), ("initial", initial)):
                node = tool.child(tag)
                if node is not None:
                    target[k] = _time(node.text, tag, f"place[{p}]/toolspecific", file, node.line)
    for k, t in enumerate(transitions):
        elem = nodes[t][1]
        delay = elem.child("delay")
        if delay is None:
            continue
        timed = True
        interval = delay.child("interval")
        bound = None
        if interval is not None:
            bound = next((c for c in interval.children if c.tag in ("cn", "ci")), None)
        where = f"transition[{t}]/delay"
        if bound is None or bound.tag != "cn":
            raise InputError("expected <delay><interval><cn>lower bound</cn>...", where, file,
                             delay.line)
        value = _time(bound.text, "delay", where, file, bound.line)
        for out in post_by_transition.indices[post_by_transition.indptr[k]:
                                               post_by_transition.indptr[k + 1]].tolist():
            holding[out] += value
    return holding, initial, timed


def _time(text: str, what: str, where: str, file: str | None, line: int) -> Fraction:
    why = size_problem(text.strip())
    if why is not None:
        raise InputError(f"{what} must be an exact time: {why}", where, file, line)
    try:
        value = exact_time(text.strip(), what)
    except MaxPlusValueError:
        raise InputError(f"{what} must be an exact time such as 3, 0.25 or 7/3, got "
                         f"{shown(text)}", where, file, line) from None
    if value < 0:
        raise InputError(f"{what} must be >= 0, got {text.strip()}", where, file, line)
    return value


def _names(ids: list[str], nodes: dict[str, tuple[str, XmlNode]]) -> list[str]:
    labels = [nodes[i][1].text_of("name", "text") or "" for i in ids]
    labels = [label if label.strip() else i for i, label in zip(ids, labels)]
    counts = Counter(labels)
    names = [label if counts[label] == 1 else i for i, label in zip(ids, labels)]
    if len(set(names)) != len(names):  # a label equal to another node's id: ids are unique
        return list(ids)
    return names


# --------------------------------------------------------------------------- writing


def write_pnml(obj: Any, path: str | os.PathLike[str], overwrite: bool = False) -> Path:
    """Write a P/T net (or the net of any timed event graph) as PNML."""
    return write_bytes(path, dumps_pnml(obj), overwrite)


def dumps_pnml(obj: Any) -> str:
    """PNML text of a net: 2009 namespace, ``ptnet``, one page, names kept.

    Timing is written only when the net has some (``net.holding`` not empty).

    Examples
    --------
    >>> from tegraph.model.teg import TimedEventGraph
    >>> g = TimedEventGraph("ring"); _ = g.add_transition("a"); _ = g.add_transition("b")
    >>> _ = g.add_place("a", "b", 0, "7/3"); _ = g.add_place("b", "a", 1, 1)
    >>> net = parse_pnml(dumps_pnml(g))
    >>> net.places, [str(h) for h in net.holding], net.marking.tolist()
    (['a -> b', 'b -> a'], ['7/3', '1'], [0, 1])
    """
    # Here, not at the top: xml.sax.saxutils loads urllib.request, http and ssl,
    # which every command would pay for at start-up.
    from xml.sax.saxutils import escape, quoteattr

    net = as_petri_net(obj)
    ids = net.attrs.get("pnml_ids", {})
    p_ids, t_ids = _ids(net.places, ids.get("places"), "p"), _ids(net.transitions,
                                                                   ids.get("transitions"), "t")
    if set(p_ids) & set(t_ids):  # places and transitions share one id space
        p_ids, t_ids = _ids(net.places, None, "p"), _ids(net.transitions, None, "t")
        if set(p_ids) & set(t_ids):
            p_ids = [f"p{k}" for k in range(len(p_ids))]
            t_ids = [f"t{k}" for k in range(len(t_ids))]
    out = ['<?xml version="1.0" encoding="UTF-8"?>', f'<pnml xmlns="{PNML_NAMESPACE}">',
           f"  <net id={quoteattr(_ncname(net.name, 'net'))} type=\"{PTNET_TYPE}\">",
           f"    <name><text>{escape(net.name)}</text></name>", '    <page id="page0">']
    timed = bool(net.holding)
    for k, (pid, name) in enumerate(zip(p_ids, net.places)):
        out.append(f"      <place id={quoteattr(pid)}>")
        out.append(f"        <name><text>{escape(name)}</text></name>")
        if net.marking[k]:
            out.append(f"        <initialMarking><text>{int(net.marking[k])}</text>"
                       "</initialMarking>")
        if timed:
            init = net.initial[k] if net.initial else Fraction(0)
            out.append(f'        <toolspecific tool="{TOOL}" version="{TOOL_VERSION}">'
                       f"<holding>{exact_text(net.holding[k])}</holding>"
                       + (f"<initial>{exact_text(init)}</initial>" if init else "")
                       + "</toolspecific>")
        out.append("      </place>")
    for tid, name in zip(t_ids, net.transitions):
        out.append(f"      <transition id={quoteattr(tid)}><name><text>{escape(name)}</text>"
                   "</name></transition>")
    arc_prefix = "a"
    while any(re.fullmatch(re.escape(arc_prefix) + r"\d+", i) for i in p_ids + t_ids):
        arc_prefix += "_"
    n_arc = 0
    for src_m, first, second in ((net.pre, p_ids, t_ids), (net.post, t_ids, p_ids)):
        for p, t, weight in _arcs(src_m):
            s, d = (first[p], second[t]) if src_m is net.pre else (first[t], second[p])
            body = (f"<inscription><text>{weight}</text></inscription>" if weight != 1 else "")
            out.append(f"      <arc id=\"{arc_prefix}{n_arc}\" source={quoteattr(s)} "
                       f"target={quoteattr(d)}>{body}</arc>")
            n_arc += 1
    out += ["    </page>", "  </net>", "</pnml>", ""]
    return "\n".join(out)


def _arcs(weights: sp.csr_array) -> list[tuple[int, int, int]]:
    """``(place, transition, weight)`` of every arc, place by place, as the rows are."""
    coo = weights.tocoo()
    order = np.lexsort((coo.col, coo.row))
    return list(zip(coo.row[order].tolist(), coo.col[order].tolist(),
                    coo.data[order].tolist()))


def _ncname(name: str, fallback: str) -> str:
    return name if _NCNAME.match(name) else fallback


def _ids(names: list[str], given: list[str] | None, prefix: str) -> list[str]:
    """XML ids: the ones read (if still valid), else the names when they are ids, else p0, p1..."""
    for candidate in (given, names):
        if (candidate is not None and len(candidate) == len(names)
                and len(set(candidate)) == len(candidate)
                and all(_NCNAME.match(c) for c in candidate)):
            return list(candidate)
    return [f"{prefix}{k}" for k in range(len(names))]
