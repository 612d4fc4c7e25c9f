"""General place/transition nets, and the bridge to timed event graphs.

A :class:`PetriNet` is what interchange formats such as PNML hold and what the
reachability baseline explores. When every place has exactly one input and
one output transition and every arc weight is 1, the net is a *marked graph*
(an event graph) and :meth:`PetriNet.to_teg` gives the timed event graph that
the (max,+) analysis needs; otherwise :meth:`PetriNet.marked_graph_violation`
says why not.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np

from ..errors import ModelError
from .teg import TimedEventGraph

__all__ = ["PetriNet"]


@dataclass
class PetriNet:
    """A P/T net with optional exact timing.

    Attributes
    ----------
    name : str
    places, transitions : list of str
        Names (unique within each list).
    pre, post : numpy.ndarray of int64, shape (n_places, n_transitions)
        ``pre[p, t]``: tokens transition t takes from place p when it fires;
        ``post[p, t]``: tokens it puts into p.
    marking : numpy.ndarray of int64, shape (n_places,)
        Initial marking.
    holding : list of Fraction, optional
        Holding time of every place (timed event graph semantics), or empty.
    initial : list of Fraction, optional
        Availability time of the initial tokens of every place, or empty.
    """

    name: str
    places: list[str]
    transitions: list[str]
    pre: np.ndarray
    post: np.ndarray
    marking: np.ndarray
    holding: list[Fraction] = field(default_factory=list)
    initial: list[Fraction] = field(default_factory=list)
    attrs: dict[str, Any] = field(default_factory=dict)

    @property
    def incidence(self) -> np.ndarray:
        """``post - pre`` (places × transitions)."""
        return self.post - self.pre

    def marked_graph_violation(self) -> str | None:
        """Why the net is not a marked graph (None when it is).

        Examples
        --------
        >>> net = PetriNet("n", ["p"], ["a", "b"], np.array([[1, 1]]), np.array([[0, 0]]),
        ...                np.array([1]))
        >>> net.marked_graph_violation()
        "place 'p' has 0 input transitions and 2 output transitions; a marked graph has one of each"
        """
        if ((self.pre > 1) | (self.post > 1)).any():
            p, t = np.argwhere((self.pre > 1) | (self.post > 1))[0]
            return (f"the arc between place {self.places[p]!r} and transition "
                    f"{self.transitions[t]!r} has weight "
                    f"{max(self.pre[p, t], self.post[p, t])}; a marked graph has weights 1")
        ins, outs = (self.post > 0).sum(axis=1), (self.pre > 0).sum(axis=1)
        for p in range(len(self.places)):
            if ins[p] != 1 or outs[p] != 1:
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
        for p, name in enumerate(self.places):
            src = int(np.flatnonzero(self.post[p])[0])
            dst = int(np.flatnonzero(self.pre[p])[0])
            teg.add_place(src, dst, int(self.marking[p]),
                          self.holding[p] if self.holding else 0,
                          self.initial[p] if self.initial else 0, name=name)
        return teg

    @classmethod
    def from_teg(cls, teg: TimedEventGraph) -> PetriNet:
        """The P/T net of a timed event graph (one place per TEG place).

        A self-loop place is both an input and an output of its event
        (``pre = post = 1``), so the incidence loses it but firing keeps it.

        Examples
        --------
        >>> g = TimedEventGraph()
        >>> _ = g.add_transition("a"), g.add_transition("b")
        >>> _ = g.add_place("a", "b", 1, 2), g.add_place("b", "a", 0, 3)
        >>> net = PetriNet.from_teg(g)
        >>> net.pre.tolist(), net.post.tolist(), net.marking.tolist()
        ([[0, 1], [1, 0]], [[1, 0], [0, 1]], [1, 0])
        """
        n_p, n_t = teg.n_places, teg.n_transitions
        pre = np.zeros((n_p, n_t), dtype=np.int64)
        post = np.zeros((n_p, n_t), dtype=np.int64)
        for k, place in enumerate(teg.places):
            pre[k, place.dst] += 1
            post[k, place.src] += 1
        names = [p.name or f"p{k}" for k, p in enumerate(teg.places)]
        return cls(teg.name, names, list(teg.transition_names), pre, post,
                   np.array([p.tokens for p in teg.places], dtype=np.int64),
                   [p.holding for p in teg.places], [p.initial for p in teg.places])
