"""General place/transition nets, and the bridge to timed event graphs.

A :class:`PetriNet` is what interchange formats such as PNML hold and what the
reachability baseline explores. When every place has exactly one input and
one output transition and every arc weight is 1, the net is a *marked graph*
(an event graph) and :meth:`PetriNet.to_teg` gives the timed event graph that
the (max,+) analysis needs; otherwise :meth:`PetriNet.marked_graph_violation`
says why not.

The arc weights are sparse (:class:`ArcWeights`, a ``scipy.sparse`` CSR
array): a net of 26,000 places and 10,000 transitions has some 50,000 arcs,
where a dense matrix would take 2 GiB.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np
import scipy.sparse as sp

from ..errors import ModelError
from .arcs import ArcList
from .limits import MAX_COUNT
from .teg import TimedEventGraph

__all__ = ["ArcWeights", "PetriNet"]


class ArcWeights(sp.csr_array):
    """Arc weights of a net, places x transitions, as a ``scipy.sparse`` CSR array of int64.

    Everything a CSR array does (slicing, ``.T``, ``.toarray()``, arithmetic);
    :meth:`tolist` gives the dense rows, for small nets and examples.

    Examples
    --------
    >>> w = ArcWeights(np.array([[0, 2], [1, 0]]))
    >>> w.tolist(), w[0, 1], w.nnz
    ([[0, 2], [1, 0]], np.int64(2), 2)
    """

    def tolist(self) -> list[list[int]]:
        """The dense rows as lists of ints (size places x transitions: small nets only)."""
        return self.toarray().tolist()


def as_weights(values: Any, shape: tuple[int, int] | None = None) -> ArcWeights:
    """Arc weights from a dense array, a nested list or any ``scipy.sparse`` matrix.

    Duplicate entries are summed, explicit zeros dropped, indices sorted.

    Raises
    ------
    ModelError
        A negative weight, or a weight above 2**63 - 1.
    """
    if sp.issparse(values):
        coo = values.tocoo()
        m = sp.csr_array((_int64(coo.data, "an arc weight"), (coo.row, coo.col)),
                         shape=coo.shape)
    else:
        dense = np.asarray(values)
        if dense.ndim != 2 and dense.size == 0 and shape is not None:
            dense = dense.reshape(shape)
        if dense.ndim != 2:
            raise ModelError(f"arc weights are a matrix places x transitions, got "
                             f"{dense.ndim} dimensions", "arcs")
        m = sp.csr_array(_int64(dense, "an arc weight"))
    out = ArcWeights(m, dtype=np.int64)
    out.sum_duplicates()
    out.eliminate_zeros()
    if out.nnz and int(out.data.min()) < 0:
        raise ModelError(f"an arc weight must be >= 0, got {int(out.data.min())}", "arcs")
    return out


def _int64(values: np.ndarray, what: str) -> np.ndarray:
    """``values`` as int64, refused (ModelError) when a value does not fit."""
    if values.size == 0:
        return np.zeros(values.shape, dtype=np.int64)
    if values.dtype.kind in "iu" and values.dtype.itemsize <= 8 and not (
            values.dtype.kind == "u" and values.size and int(values.max()) > MAX_COUNT):
        return values.astype(np.int64, copy=False)
    if values.dtype.kind == "b" or values.dtype.kind not in "iuO":
        raise ModelError(f"{what} is an integer, got values of type {values.dtype}", "arcs")
    big = max((abs(int(v)) for v in values.flat), default=0)
    if big > MAX_COUNT:
        raise ModelError(f"{what} must be at most 2**63 - 1 = {MAX_COUNT}, got {big}", "arcs")
    return values.astype(np.int64)


@dataclass(eq=False)
class PetriNet:
    """A P/T net with optional exact timing.

    Attributes
    ----------
    name : str
    places, transitions : list of str
        Names (unique within each list).
    pre, post : ArcWeights, shape (n_places, n_transitions)
        ``pre[p, t]``: tokens transition t takes from place p when it fires;
        ``post[p, t]``: tokens it puts into p. Sparse (``scipy.sparse`` CSR
        arrays of int64); a dense array or nested list given is converted.
    marking : numpy.ndarray of int64, shape (n_places,)
        Initial marking.
    holding : list of Fraction, optional
        Holding time of every place (timed event graph semantics), or empty.
    initial : list of Fraction, optional
        Availability time of the initial tokens of every place, or empty.

    Raises
    ------
    ModelError
        Shapes that do not match the names, a negative weight or marking.

    See Also
    --------
    tegraph.TimedEventGraph : the marked-graph case, with (max,+) semantics.
    tegraph.analysis.baselines.reachability.reachability_graph : its reachable markings.
    tegraph.cycle_time : its period when it is a marked graph.

    References
    ----------
    .. [1] T. Murata, "Petri nets: properties, analysis and applications",
       Proceedings of the IEEE 77(4), 541–580, 1989.

    Examples
    --------
    A ring of two places and two transitions is a marked graph [1]_:

    >>> net = PetriNet("n", ["p", "q"], ["t", "u"], np.array([[1, 0], [0, 1]]),
    ...                np.array([[0, 1], [1, 0]]), np.array([1, 0]))
    >>> net.marked_graph_violation() is None, net.to_teg().transition_names
    (True, ('t', 'u'))
    """

    name: str
    places: list[str]
    transitions: list[str]
    pre: ArcWeights
    post: ArcWeights
    marking: np.ndarray
    holding: list[Fraction] = field(default_factory=list)
    initial: list[Fraction] = field(default_factory=list)
    attrs: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        shape = (len(self.places), len(self.transitions))
        self.pre = as_weights(self.pre, shape)
        self.post = as_weights(self.post, shape)
        for what, m in (("pre", self.pre), ("post", self.post)):
            if m.shape != shape:
                raise ModelError(f"{what} has shape {m.shape}, expected (places, transitions) "
                                 f"= {shape}", f"net {self.name}")
        try:
            self.marking = _int64(np.asarray(self.marking), "a marking").reshape(-1)
        except ModelError as exc:
            raise ModelError(exc.reason, f"net {self.name}") from None
        if self.marking.shape != (shape[0],):
            raise ModelError(f"the marking has {self.marking.size} entries, expected one per "
                             f"place ({shape[0]})", f"net {self.name}")
        if (self.marking < 0).any():
            raise ModelError("a marking must be >= 0", f"net {self.name}")

    @property
    def incidence(self) -> sp.csr_array:
        """``post - pre`` (places × transitions), sparse."""
        return (self.post - self.pre).tocsr()

    def marked_graph_violation(self) -> str | None:
        """Why the net is not a marked graph (None when it is).

        Examples
        --------
        >>> net = PetriNet("n", ["p"], ["a", "b"], np.array([[1, 1]]), np.array([[0, 0]]),
        ...                np.array([1]))
        >>> net.marked_graph_violation()
        "place 'p' has 0 input transitions and 2 output transitions; a marked graph has one of each"
        """
        heavy = [(int(c.row[k]), int(c.col[k])) for c in (self.pre.tocoo(), self.post.tocoo())
                 for k in np.flatnonzero(c.data > 1)[:1]]  # the first of each, row by row
        if heavy:
            p, t = min(heavy)
            weight = max(int(self.pre[p, t]), int(self.post[p, t]))
            return (f"the arc between place {self.places[p]!r} and transition "
                    f"{self.transitions[t]!r} has weight {weight}; a marked graph has weights 1")
        ins, outs = np.diff(self.post.indptr), np.diff(self.pre.indptr)
        wrong = np.flatnonzero((ins != 1) | (outs != 1))
        if len(wrong):
            p = int(wrong[0])
            return (f"place {self.places[p]!r} has {ins[p]} input transitions and "
                    f"{outs[p]} output transitions; a marked graph has one of each")
        return None

    def to_teg(self) -> TimedEventGraph:
        """The timed event graph of a marked graph (transitions become events).

        Raises
        ------
        ModelError
            The net is not a marked graph (the reason names the place or arc).
        """
        why = self.marked_graph_violation()
        if why is not None:
            raise ModelError(why, self.name)
        teg = TimedEventGraph(self.name)
        for t in self.transitions:
            teg.add_transition(t)
        # a marked graph: one entry per row of post (the input) and of pre (the output)
        src, dst = self.post.indices.tolist(), self.pre.indices.tolist()
        for p, name in enumerate(self.places):
            teg.add_place(src[p], dst[p], int(self.marking[p]),
                          self.holding[p] if self.holding else 0,
                          self.initial[p] if self.initial else 0, name=name)
        return teg

    @classmethod
    def from_teg(cls, teg: TimedEventGraph | ArcList) -> PetriNet:
        """The P/T net of a timed event graph or arc list (one place per TEG place).

        A self-loop place is both an input and an output of its event
        (``pre = post = 1``), so the incidence loses it but firing keeps it.
        Built from the graph's arrays: a graph of millions of places takes
        sparse arrays of its size, never a dense matrix.

        Examples
        --------
        >>> g = TimedEventGraph()
        >>> _ = g.add_transition("a"), g.add_transition("b")
        >>> _ = g.add_place("a", "b", 1, 2), g.add_place("b", "a", 0, 3)
        >>> net = PetriNet.from_teg(g)
        >>> net.pre.tolist(), net.post.tolist(), net.marking.tolist()
        ([[0, 1], [1, 0]], [[1, 0], [0, 1]], [1, 0])
        """
        a = teg.arrays()
        n_p, n_t = len(a.src), a.n_transitions
        rows, ones = np.arange(n_p), np.ones(n_p, dtype=np.int64)
        pre = sp.csr_array((ones, (rows, a.dst)), shape=(n_p, n_t))
        post = sp.csr_array((ones, (rows, a.src)), shape=(n_p, n_t))
        if isinstance(teg, TimedEventGraph):
            names = [p.name or f"p{k}" for k, p in enumerate(teg.places)]
            holding = [p.holding for p in teg.places]
            initial = [p.initial for p in teg.places]
        else:
            names = [teg.place_label(k) for k in range(n_p)]
            holding = [Fraction(int(h), a.scale) for h in a.holding.tolist()]
            initial = [Fraction(0)] * n_p
        return cls(teg.name, names, list(teg.transition_names), pre, post,
                   np.asarray(a.tokens, dtype=np.int64), holding, initial)
