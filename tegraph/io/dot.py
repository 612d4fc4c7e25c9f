"""Graph views: Graphviz DOT text, and networkx graphs both ways.

DOT shows a skeleton (tasks, clocks, links, threads), its timed event graph
(events and places), or a P/T net (places and transitions). The critical
circuit (the one that sets the period) is drawn red and bold; a circuit
without token (a deadlock) orange and dashed — both found by
:func:`tegraph.cycle_time.cycle_time` on the graph's timed event graph.

:func:`to_networkx` gives a :class:`networkx.MultiDiGraph` of a timed event
graph (as :meth:`TimedEventGraph.to_networkx`) or a bipartite
:class:`networkx.DiGraph` of a P/T net (node attribute ``kind``);
:func:`from_networkx` reads either back.
"""

from __future__ import annotations

import os
from fractions import Fraction
from pathlib import Path
from typing import Any

import networkx as nx
import numpy as np

from maxplus.errors import MaxPlusError
from maxplus.scalar import exact_time

from ..errors import ModelError, TegraphError
from ..petri import PetriNet
from ..report import exact_text
from ..skeleton import Protocol, Skeleton
from ..teg import TimedEventGraph
from .formats import as_teg_like, write_bytes

__all__ = ["from_networkx", "to_dot", "to_networkx", "write_dot", "write_teg_dot"]

_CRITICAL = 'color="red", fontcolor="red", penwidth=2.5'
_DEAD = 'color="darkorange", fontcolor="darkorange", penwidth=2.5, style="dashed"'


def _q(text: Any) -> str:
    """A DOT double-quoted string (a label's line breaks become ``\\n``)."""
    s = str(text).replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")
    return f'"{s}"'


def _highlights(obj: Any) -> tuple[set[int], set[int], str]:
    """Place indices on the critical circuit, on a token-free circuit, and a caption."""
    from ..cycle_time import cycle_time

    try:
        r = cycle_time(obj, verify=False)
    except (TegraphError, MaxPlusError):  # a drawing never fails for want of figures
        return set(), set(), ""
    if not r.applicable:
        return set(), set(), r.reason or ""
    if r.token_free_circuit is not None:
        return set(), set(r.token_free_places), "deadlock: circuit without token (dashed)"
    if r.period is None:
        return set(), set(), "no circuit"
    return set(r.critical_places), set(), f"period {exact_text(r.period)} (critical circuit in red)"


def to_dot(obj: Any, view: str | None = None) -> str:
    """DOT text of a skeleton, a timed event graph (or anything that becomes one), or a net.

    Parameters
    ----------
    view : {"skeleton", "teg", "net"}, optional
        Default: ``skeleton`` for a Skeleton, ``net`` for a P/T net,
        ``teg`` otherwise. A skeleton may be drawn as its ``teg``.

    Examples
    --------
    >>> g = TimedEventGraph("ring"); _ = g.add_transition("a"); _ = g.add_transition("b")
    >>> _ = g.add_place("a", "b", 0, 2); _ = g.add_place("b", "a", 1, 3)
    >>> print(to_dot(g))  # doctest: +NORMALIZE_WHITESPACE
    digraph "ring" {
      label="ring: period 5 (critical circuit in red)"; rankdir=LR;
      node [shape=box, style=rounded];
      "a";
      "b";
      "a" -> "b" [label="a -> b\\nh=2", color="red", fontcolor="red", penwidth=2.5];
      "b" -> "a" [label="b -> a\\nh=3 m=1", color="red", fontcolor="red", penwidth=2.5];
    }
    """
    if view is None:
        view = "skeleton" if isinstance(obj, Skeleton) else "net" if isinstance(obj, PetriNet) \
            else "teg"
    if view == "skeleton":
        if not isinstance(obj, Skeleton):
            raise ModelError("only a skeleton has a skeleton view", type(obj).__name__)
        return _skeleton_dot(obj)
    if view == "net":
        return _net_dot(obj if isinstance(obj, PetriNet) else PetriNet.from_teg(_teg(obj)))
    if view == "teg":
        return _teg_dot(as_teg_like(obj))
    raise ValueError(f"view is 'skeleton', 'teg' or 'net', got {view!r}")


def _teg(obj: Any) -> TimedEventGraph:
    g = as_teg_like(obj)
    return g if isinstance(g, TimedEventGraph) else g.to_teg()


def _place_text(holding: Fraction, tokens: int) -> str:
    return f"h={exact_text(holding)}" + (f" m={tokens}" if tokens else "")


def _teg_dot(g: Any) -> str:
    crit, dead, caption = _highlights(g)
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


def _net_dot(net: PetriNet) -> str:
    crit, dead, caption = _highlights(net)
    label = net.name + (f": {caption}" if caption else "")
    out = [f"digraph {_q(net.name)} {{", f"  label={_q(label)}; rankdir=LR;"]
    for k, p in enumerate(net.places):
        extra = f"\nh={exact_text(net.holding[k])}" if net.holding else ""
        style = _CRITICAL if k in crit else _DEAD if k in dead else ""
        out.append(f"  {_q('p:' + p)} [shape=circle, label={_q(f'{p}{extra}')}, "
                   f"xlabel={_q('●' * int(net.marking[k]) if net.marking[k] <= 5 else net.marking[k])}"
                   + (f", {style}" if style else "") + "];")
    for t in net.transitions:
        out.append(f"  {_q('t:' + t)} [shape=box, label={_q(t)}];")
    for mat, forward in ((net.pre, True), (net.post, False)):
        for i, j in np.argwhere(mat > 0).tolist():
            ends = (f"p:{net.places[i]}", f"t:{net.transitions[j]}")
            s, d = ends if forward else ends[::-1]
            w = int(mat[i, j])
            out.append(f"  {_q(s)} -> {_q(d)}" + (f" [label={_q(w)}]" if w != 1 else "") + ";")
    return "\n".join(out + ["}"]) + "\n"


def _skeleton_dot(sk: Skeleton) -> str:
    from ..build import build_teg

    g = build_teg(sk)
    crit, dead, caption = _highlights(g)
    on = {"crit": crit, "dead": dead}
    tasks_on: dict[str, set[str]] = {"crit": set(), "dead": set()}
    links_on: dict[str, set[int]] = {"crit": set(), "dead": set()}
    clocks_on: dict[str, set[str]] = {"crit": set(), "dead": set()}
    ports_on: dict[str, set[Any]] = {"crit": set(), "dead": set()}
    for key, places in on.items():
        for p in places:
            place = g.places[p]
            for e in (place.src, place.dst):
                attrs = g.transition_attrs[e]
                tasks_on[key].update(attrs.get("tasks", ()))
                if attrs.get("role") == "tick" and place.kind == "clock":
                    clocks_on[key].add(attrs["clock"])
                if attrs.get("role") == "rendezvous":
                    ports_on[key].update(attrs.get("ports", ()))
            if isinstance(place.origin, dict) and "link_index" in place.origin:
                links_on[key].add(place.origin["link_index"])
    for key in on:
        for i, link in enumerate(sk.links):
            if link.protocol is Protocol.SYN_SYN and {link.writer, link.reader} <= ports_on[key]:
                links_on[key].add(i)

    def style(key_sets: dict[str, set[Any]], item: Any) -> str:
        return (", " + _CRITICAL) if item in key_sets["crit"] else \
            (", " + _DEAD) if item in key_sets["dead"] else ""

    label = sk.name + (f": {caption}" if caption else "")
    out = [f"digraph {_q(sk.name)} {{", f"  label={_q(label)}; rankdir=LR;"]
    for c in sk.clocks.values():
        text = f"{c.name}\nperiod {exact_text(c.period)} {sk.unit}" + (
            f", phase {exact_text(c.phase)}" if c.phase else "")
        out.append(f"  {_q('clock:' + c.name)} [shape=ellipse, label={_q(text)}"
                   + style(clocks_on, c.name) + "];")
    for t in sk.tasks.values():
        text = f"{t.name}\n{exact_text(t.duration)} {sk.unit}"
        out.append(f"  {_q('task:' + t.name)} [shape=box, label={_q(text)}"
                   + style(tasks_on, t.name) + "];")
        if t.clock is not None:
            out.append(f"  {_q('clock:' + t.clock)} -> {_q('task:' + t.name)} [style=dotted];")
    for i, link in enumerate(sk.links):
        text = f"{link.writer[1]} -> {link.reader[1]}\n{link.protocol.value}"
        out.append(f"  {_q('task:' + link.writer[0])} -> {_q('task:' + link.reader[0])} "
                   f"[label={_q(text)}" + style(links_on, i) + "];")
    for thread in sk.threads:
        for a, b in zip(thread, thread[1:] + thread[:1]):
            out.append(f"  {_q('task:' + a)} -> {_q('task:' + b)} [style=dashed, color=gray, "
                       'label="thread"];')
    return "\n".join(out + ["}"]) + "\n"


def write_dot(obj: Any, path: str | os.PathLike[str], overwrite: bool = False) -> Path:
    """Write the default DOT view of ``obj`` (see :func:`to_dot`)."""
    return write_bytes(path, to_dot(obj), overwrite)


def write_teg_dot(obj: Any, path: str | os.PathLike[str], overwrite: bool = False) -> Path:
    """Write the DOT view of the timed event graph of ``obj`` (a skeleton's, say)."""
    return write_bytes(path, to_dot(obj, "teg"), overwrite)


# --------------------------------------------------------------------------- networkx


def to_networkx(obj: Any) -> nx.DiGraph:
    """A networkx graph: the bipartite graph of a P/T net, else the TEG's MultiDiGraph.

    Examples
    --------
    >>> net = PetriNet("n", ["p"], ["t"], np.array([[1]]), np.array([[2]]), np.array([3]))
    >>> G = to_networkx(net)
    >>> dict(G.nodes["p"]), G.edges["t", "p"]["weight"]
    ({'kind': 'place', 'tokens': 3}, 2)
    >>> back = from_networkx(G)
    >>> back.pre.tolist(), back.post.tolist(), back.marking.tolist()
    ([[1]], [[2]], [3])
    """
    if not isinstance(obj, PetriNet):
        return _teg(obj).to_networkx()
    if set(obj.places) & set(obj.transitions):
        raise ModelError("a place and a transition share a name; networkx nodes must be "
                         "distinct", f"net {obj.name}")
    G = nx.DiGraph(name=obj.name)
    for k, p in enumerate(obj.places):
        attrs: dict[str, Any] = {"kind": "place", "tokens": int(obj.marking[k])}
        if obj.holding:
            attrs["holding"] = obj.holding[k]
        if obj.initial:
            attrs["initial"] = obj.initial[k]
        G.add_node(p, **attrs)
    for t in obj.transitions:
        G.add_node(t, kind="transition")
    for i, j in np.argwhere(obj.pre > 0).tolist():
        G.add_edge(obj.places[i], obj.transitions[j], weight=int(obj.pre[i, j]))
    for i, j in np.argwhere(obj.post > 0).tolist():
        G.add_edge(obj.transitions[j], obj.places[i], weight=int(obj.post[i, j]))
    return G


def from_networkx(G: nx.DiGraph) -> PetriNet | TimedEventGraph:
    """A P/T net when every node has ``kind`` place or transition, else a timed event graph."""
    kinds = nx.get_node_attributes(G, "kind")
    if not G or len(kinds) != len(G) or not set(kinds.values()) <= {"place", "transition"}:
        return TimedEventGraph.from_networkx(G)
    places = [n for n in G if kinds[n] == "place"]
    transitions = [n for n in G if kinds[n] == "transition"]
    pi = {n: k for k, n in enumerate(places)}
    ti = {n: k for k, n in enumerate(transitions)}
    pre = np.zeros((len(places), len(transitions)), dtype=np.int64)
    post = np.zeros_like(pre)
    for u, v, w in G.edges(data="weight", default=1):
        if kinds[u] == kinds[v]:
            raise ModelError("an arc joins two nodes of one kind", f"edge {u} -> {v}")
        if kinds[u] == "place":
            pre[pi[u], ti[v]] += int(w)
        else:
            post[pi[v], ti[u]] += int(w)
    timed = any("holding" in G.nodes[p] for p in places)
    hold = [exact_time(G.nodes[p].get("holding", 0), f"place {p}") for p in places] if timed else []
    init = [exact_time(G.nodes[p].get("initial", 0), f"place {p}") for p in places] if timed else []
    marking = np.array([int(G.nodes[p].get("tokens", 0)) for p in places], dtype=np.int64)
    return PetriNet(str(G.graph.get("name", "net")), [str(p) for p in places],
                    [str(t) for t in transitions], pre, post, marking, hold, init)
