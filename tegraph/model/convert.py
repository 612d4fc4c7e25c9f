"""Conversions between the models: what becomes a timed event graph, and how.

A skeleton is built into its timed event graph (spec §2), an SDF graph is
expanded through its repetition vector, a P/T net that is a marked graph is
converted; a net that is not one is refused, naming the place or arc at
fault. networkx graphs go both ways.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp

from maxplus.scalar import exact_time

from ..errors import InputError, ModelError
from .arcs import ArcList
from .build import build_teg
from .limits import DEFAULT_MAX_FIRINGS
from .petri import PetriNet
from .sdf import SDFGraph
from .skeleton import Skeleton
from .teg import TimedEventGraph

if TYPE_CHECKING:  # networkx is slow to import; only these conversions need it
    import networkx as nx

__all__ = ["as_petri_net", "as_teg", "as_teg_like", "from_networkx", "to_networkx"]


def as_teg_like(obj: Any, max_firings: int = DEFAULT_MAX_FIRINGS) -> TimedEventGraph | ArcList:
    """A timed event graph, or an arc list for array-sized graphs, from any model.

    Skeletons are built (spec §2), SDF graphs expanded through their
    repetition vector, marked graphs converted.

    Parameters
    ----------
    obj : Skeleton, TimedEventGraph, ArcList, SDFGraph or PetriNet
    max_firings : int
        The bound on an SDF graph's expansion (:meth:`SDFGraph.to_arcs
        <tegraph.model.sdf.SDFGraph.to_arcs>`), default 10**7 firings.

    Raises
    ------
    InputError
        A P/T net that is not a marked graph (the reason names the place or arc),
        an SDF expansion above ``max_firings``, or an object of no known model.
    """
    if isinstance(obj, (TimedEventGraph, ArcList)):
        return obj
    if isinstance(obj, Skeleton):
        return build_teg(obj)
    if isinstance(obj, SDFGraph):
        return obj.to_arcs(max_firings)
    if isinstance(obj, PetriNet):
        why = obj.marked_graph_violation()
        if why is not None:
            raise InputError(f"not a marked graph: {why}", f"net {obj.name}")
        return obj.to_teg()
    raise InputError(f"expected a skeleton, timed event graph, P/T net, SDF graph or arc list, "
                     f"got {type(obj).__name__}")


def as_teg(obj: Any, max_firings: int = DEFAULT_MAX_FIRINGS) -> TimedEventGraph:
    """Like :func:`as_teg_like`, always a :class:`~tegraph.model.teg.TimedEventGraph`."""
    g = as_teg_like(obj, max_firings)
    return g if isinstance(g, TimedEventGraph) else g.to_teg()


def as_petri_net(obj: Any, max_firings: int = DEFAULT_MAX_FIRINGS) -> PetriNet:
    """A P/T net: itself, or the net of the timed event graph of ``obj``.

    An SDF graph or arc list goes to the net through its arrays, without a
    Python object per place (``max_firings`` as for :func:`as_teg_like`).
    """
    if isinstance(obj, PetriNet):
        return obj
    return PetriNet.from_teg(as_teg_like(obj, max_firings))


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
    import networkx as nx

    if not isinstance(obj, PetriNet):
        return as_teg(obj).to_networkx()
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
    pre, post = obj.pre.tocoo(), obj.post.tocoo()  # canonical: one entry per arc
    for i, j, w in zip(pre.row.tolist(), pre.col.tolist(), pre.data.tolist()):
        G.add_edge(obj.places[i], obj.transitions[j], weight=w)
    for i, j, w in zip(post.row.tolist(), post.col.tolist(), post.data.tolist()):
        G.add_edge(obj.transitions[j], obj.places[i], weight=w)
    return G


def from_networkx(G: nx.DiGraph) -> PetriNet | TimedEventGraph:
    """A P/T net when every node has ``kind`` place or transition, else a timed event graph."""
    import networkx as nx

    kinds = nx.get_node_attributes(G, "kind")
    if not G or len(kinds) != len(G) or not set(kinds.values()) <= {"place", "transition"}:
        return TimedEventGraph.from_networkx(G)
    places = [n for n in G if kinds[n] == "place"]
    transitions = [n for n in G if kinds[n] == "transition"]
    pi = {n: k for k, n in enumerate(places)}
    ti = {n: k for k, n in enumerate(transitions)}
    arcs: dict[str, tuple[list[int], list[int], list[int]]] = {
        "pre": ([], [], []), "post": ([], [], [])}
    for u, v, w in G.edges(data="weight", default=1):
        if kinds[u] == kinds[v]:
            raise ModelError("an arc joins two nodes of one kind", f"edge {u} -> {v}")
        rows, cols, weights = arcs["pre" if kinds[u] == "place" else "post"]
        p, t = (pi[u], ti[v]) if kinds[u] == "place" else (pi[v], ti[u])
        rows.append(p)
        cols.append(t)
        weights.append(int(w))
    shape = (len(places), len(transitions))
    try:
        pre, post = (sp.coo_array((np.array(w, dtype=np.int64), (np.array(r, dtype=np.int64),
                                   np.array(c, dtype=np.int64))), shape=shape)
                     for r, c, w in (arcs["pre"], arcs["post"]))
    except OverflowError:
        raise ModelError("an arc weight must be at most 2**63 - 1", "weight") from None
    timed = any("holding" in G.nodes[p] for p in places)
    hold = [exact_time(G.nodes[p].get("holding", 0), f"place {p}") for p in places] if timed else []
    init = [exact_time(G.nodes[p].get("initial", 0), f"place {p}") for p in places] if timed else []
    marking = [int(G.nodes[p].get("tokens", 0)) for p in places]  # PetriNet bounds them
    # The field is typed as the int64 array __post_init__ makes of it (refusing, with a
    # message, a count beyond int64, which np.array here would raise as OverflowError).
    return PetriNet(str(G.graph.get("name", "net")), [str(p) for p in places],
                    [str(t) for t in transitions], pre, post,
                    marking, hold, init)  # type: ignore[arg-type]
