"""Graphviz DOT drawings of a skeleton, a timed event graph or a P/T net (write only).

DOT shows a skeleton (tasks, clocks, links, threads), its timed event graph
(events and places), or a P/T net (places and transitions). Circuits given
as :class:`Highlights` are coloured: the critical circuit (the one that sets
the period) red and bold, a circuit without token (a deadlock) orange and
dashed. This module draws what it is given; finding those circuits is the
analysis's job (:func:`tegraph.write` and :func:`tegraph.report.dot.highlights`
do both).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

from maxplus.scalar import exact_text

from ..errors import InputError, ModelError
from ..model.build import build_teg
from ..model.convert import as_teg, as_teg_like
from ..model.petri import PetriNet
from ..model.skeleton import Protocol, Skeleton
from ..model.teg import TimedEventGraph
from ._files import write_bytes

__all__ = ["Highlights", "dot_text", "write_dot", "write_teg_dot"]

_CRITICAL = 'color="red", fontcolor="red", penwidth=2.5'
_DEAD = 'color="darkorange", fontcolor="darkorange", penwidth=2.5, style="dashed"'


def _q(text: Any) -> str:
    """A DOT double-quoted string (a label's line breaks become ``\\n``)."""
    s = str(text).replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")
    return f'"{s}"'


@dataclass(frozen=True)
class Highlights:
    """What a drawing colours, by place index of the timed event graph (or of the net).

    Attributes
    ----------
    critical : frozenset of int
        Places of the critical circuit (drawn red and bold).
    token_free : frozenset of int
        Places of a circuit without token (drawn orange and dashed).
    caption : str
        Appended to the graph's name in its label (``period 5 (critical circuit in red)``).
    """

    critical: frozenset[int] = frozenset()
    token_free: frozenset[int] = frozenset()
    caption: str = ""


_NONE = Highlights()


def dot_text(obj: Any, view: str | None = None, highlights: Highlights | None = None) -> str:
    """DOT text of a skeleton, a timed event graph (or anything that becomes one), or a net.

    Parameters
    ----------
    obj : Skeleton, TimedEventGraph, PetriNet, SDFGraph or ArcList
    view : {"skeleton", "teg", "net"}, optional
        Default: ``skeleton`` for a Skeleton, ``net`` for a P/T net,
        ``teg`` otherwise. A skeleton may be drawn as its ``teg``.
    highlights : Highlights, optional
        Circuits to colour, by place index of the timed event graph of
        ``obj`` (of the net itself for a P/T net).

    Returns
    -------
    str

    Raises
    ------
    InputError
        An unknown ``view``.
    ModelError
        A skeleton view of something that is not a skeleton.

    See Also
    --------
    tegraph.report.dot.highlights : the circuits a cycle-time result names.

    Examples
    --------
    >>> g = TimedEventGraph("ring"); _ = g.add_transition("a"); _ = g.add_transition("b")
    >>> _ = g.add_place("a", "b", 0, 2); _ = g.add_place("b", "a", 1, 3)
    >>> marks = Highlights(frozenset({0, 1}), caption="period 5 (critical circuit in red)")
    >>> print(dot_text(g, highlights=marks))  # doctest: +NORMALIZE_WHITESPACE
    digraph "ring" {
      label="ring: period 5 (critical circuit in red)"; rankdir=LR;
      node [shape=box, style=rounded];
      "a";
      "b";
      "a" -> "b" [label="a -> b\\nh=2", color="red", fontcolor="red", penwidth=2.5];
      "b" -> "a" [label="b -> a\\nh=3 m=1", color="red", fontcolor="red", penwidth=2.5];
    }
    """
    marks = highlights or _NONE
    if view is None:
        view = "skeleton" if isinstance(obj, Skeleton) else "net" if isinstance(obj, PetriNet) \
            else "teg"
    if view == "skeleton":
        if not isinstance(obj, Skeleton):
            raise ModelError("only a skeleton has a skeleton view", type(obj).__name__)
        return _skeleton_dot(obj, marks)
    if view == "net":
        return _net_dot(obj if isinstance(obj, PetriNet) else PetriNet.from_teg(as_teg(obj)),
                        marks)
    if view == "teg":
        return _teg_dot(as_teg_like(obj), marks)
    raise InputError(f"expected 'skeleton', 'teg' or 'net', got {view!r}", "view")


def _place_text(holding: Fraction, tokens: int) -> str:
    return f"h={exact_text(holding)}" + (f" m={tokens}" if tokens else "")


def _teg_dot(g: Any, marks: Highlights) -> str:
    crit, dead, caption = marks.critical, marks.token_free, marks.caption
    a = g.arrays()
    names = list(g.transition_names)
    label = g.name + (f": {caption}" if caption else "")
    out = [f"digraph {_q(g.name)} {{", f"  label={_q(label)}; rankdir=LR;",
           "  node [shape=box, style=rounded];"]
    out += [f"  {_q(n)};" for n in names]
    for p, (s, d, h, t) in enumerate(zip(a.src.tolist(), a.dst.tolist(), a.holding.tolist(),
                                         a.tokens.tolist())):
        pname = g.places[p].name if isinstance(g, TimedEventGraph) else g.place_label(p)
        style = _CRITICAL if p in crit else _DEAD if p in dead else ""
        text = f"{pname}\n{_place_text(Fraction(int(h), a.scale), t)}"
        out.append(f"  {_q(names[s])} -> {_q(names[d])} [label={_q(text)}"
                   + (f", {style}" if style else "") + "];")
    return "\n".join(out + ["}"]) + "\n"


def _tokens_text(tokens: int) -> str:
    """A few tokens as dots, more as their number."""
    return "●" * tokens if tokens <= 5 else str(tokens)


def _net_dot(net: PetriNet, marks: Highlights) -> str:
    crit, dead, caption = marks.critical, marks.token_free, marks.caption
    label = net.name + (f": {caption}" if caption else "")
    out = [f"digraph {_q(net.name)} {{", f"  label={_q(label)}; rankdir=LR;"]
    for k, p in enumerate(net.places):
        extra = f"\nh={exact_text(net.holding[k])}" if net.holding else ""
        style = _CRITICAL if k in crit else _DEAD if k in dead else ""
        out.append(f"  {_q('p:' + p)} [shape=circle, label={_q(f'{p}{extra}')}, "
                   f"xlabel={_q(_tokens_text(int(net.marking[k])))}"
                   + (f", {style}" if style else "") + "];")
    for t in net.transitions:
        out.append(f"  {_q('t:' + t)} [shape=box, label={_q(t)}];")
    for mat, forward in ((net.pre, True), (net.post, False)):
        coo = mat.tocoo()  # canonical: one entry per arc
        order = np.lexsort((coo.col, coo.row))  # place by place, as the rows are
        for i, j, w in zip(coo.row[order].tolist(), coo.col[order].tolist(),
                           coo.data[order].tolist()):
            ends = (f"p:{net.places[i]}", f"t:{net.transitions[j]}")
            s, d = ends if forward else ends[::-1]
            out.append(f"  {_q(s)} -> {_q(d)}" + (f" [label={_q(w)}]" if w != 1 else "") + ";")
    return "\n".join(out + ["}"]) + "\n"


@dataclass
class _Marked:
    """The skeleton's items that a set of marked places of its TEG touch."""

    tasks: set[str]
    links: set[int]
    clocks: set[str]
    ports: set[Any]

    def has(self, kind: str, item: Any) -> bool:
        """``item`` is among the marked ``kind`` (``"tasks"``, ``"links"``, ``"clocks"``)."""
        return item in getattr(self, kind)


def _marked(sk: Skeleton, g: TimedEventGraph, places: Any) -> _Marked:
    """The tasks, clocks (through their tick's own place), rendezvous ports and links
    (a place made by a link, or a SYN/SYN link between two marked ports) of ``places``."""
    m = _Marked(set(), set(), set(), set())
    for p in places:
        place = g.places[p]
        for e in (place.src, place.dst):
            attrs = g.transition_attrs[e]
            m.tasks.update(attrs.get("tasks", ()))
            if attrs.get("role") == "tick" and place.kind == "clock":
                m.clocks.add(attrs["clock"])
            if attrs.get("role") == "rendezvous":
                m.ports.update(attrs.get("ports", ()))
        if isinstance(place.origin, dict) and "link_index" in place.origin:
            m.links.add(place.origin["link_index"])
    for i, link in enumerate(sk.links):
        if link.protocol is Protocol.SYN_SYN and {link.writer, link.reader} <= m.ports:
            m.links.add(i)
    return m


def _skeleton_dot(sk: Skeleton, marks: Highlights) -> str:
    g = build_teg(sk)
    crit, dead = _marked(sk, g, marks.critical), _marked(sk, g, marks.token_free)

    def style(kind: str, item: Any) -> str:
        return (", " + _CRITICAL) if crit.has(kind, item) else \
            (", " + _DEAD) if dead.has(kind, item) else ""

    label = sk.name + (f": {marks.caption}" if marks.caption else "")
    out = [f"digraph {_q(sk.name)} {{", f"  label={_q(label)}; rankdir=LR;"]
    for c in sk.clocks.values():
        text = f"{c.name}\nperiod {exact_text(c.period)} {sk.unit}" + (
            f", phase {exact_text(c.phase)}" if c.phase else "")
        out.append(f"  {_q('clock:' + c.name)} [shape=ellipse, label={_q(text)}"
                   + style("clocks", c.name) + "];")
    for t in sk.tasks.values():
        text = f"{t.name}\n{exact_text(t.duration)} {sk.unit}"
        out.append(f"  {_q('task:' + t.name)} [shape=box, label={_q(text)}"
                   + style("tasks", t.name) + "];")
        if t.clock is not None:
            out.append(f"  {_q('clock:' + t.clock)} -> {_q('task:' + t.name)} [style=dotted];")
    for i, link in enumerate(sk.links):
        text = f"{link.writer[1]} -> {link.reader[1]}\n{link.protocol.value}"
        out.append(f"  {_q('task:' + link.writer[0])} -> {_q('task:' + link.reader[0])} "
                   f"[label={_q(text)}" + style("links", i) + "];")
    for thread in sk.threads:
        for a, b in zip(thread, thread[1:] + thread[:1]):
            out.append(f"  {_q('task:' + a)} -> {_q('task:' + b)} [style=dashed, color=gray, "
                       'label="thread"];')
    return "\n".join(out + ["}"]) + "\n"


def write_dot(obj: Any, path: str | os.PathLike[str], overwrite: bool = False,
              highlights: Highlights | None = None) -> Path:
    """Write the default DOT view of ``obj`` (see :func:`dot_text`)."""
    return write_bytes(path, dot_text(obj, highlights=highlights), overwrite)


def write_teg_dot(obj: Any, path: str | os.PathLike[str], overwrite: bool = False,
                  highlights: Highlights | None = None) -> Path:
    """Write the DOT view of the timed event graph of ``obj`` (a skeleton's, say)."""
    return write_bytes(path, dot_text(obj, "teg", highlights), overwrite)
