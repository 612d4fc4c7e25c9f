"""Arc lists: a timed event graph as arc arrays, for graphs of millions of places.

What an ``.edges`` file holds (:mod:`tegraph.io.edges` reads and writes it):
no Python object per place, only numpy arrays of the place endpoints, exact
holding times scaled to integers, and tokens.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from ..errors import ModelError
from .teg import TEGArrays, TimedEventGraph

__all__ = ["ArcList"]


@dataclass(eq=False)
class ArcList:
    """A timed event graph as arc arrays: what an ``.edges`` file holds.

    Graphs of millions of places are handled here without a Python object
    per place; :meth:`to_teg` gives a :class:`~tegraph.model.teg.TimedEventGraph`
    when one is wanted.

    Attributes
    ----------
    src, dst : numpy.ndarray of int64
        Input and output transition of each place.
    holding : numpy.ndarray
        Holding times multiplied by ``scale``: int64, or object (Python ints)
        for values from 2**62.
    tokens : numpy.ndarray of int64
    scale : int
    names : list of str or None
        Transition names; None means ``"0", "1", ...``.
    n_transitions : int
    name : str

    Examples
    --------
    >>> g = ArcList.from_teg(TimedEventGraph.from_networkx(__import__("networkx").DiGraph(
    ...     [("a", "b", {"holding": "1/2"}), ("b", "a", {"tokens": 1})])))
    >>> g.holding.tolist(), g.scale, g.transition_names
    ([1, 0], 2, ('a', 'b'))
    """

    src: np.ndarray
    dst: np.ndarray
    holding: np.ndarray
    tokens: np.ndarray
    scale: int = 1
    names: list[str] | None = None
    n_transitions: int = 0
    name: str = "edges"

    @property
    def n_places(self) -> int:
        """Number of places (lines)."""
        return len(self.src)

    @property
    def transition_names(self) -> tuple[str, ...]:
        """Transition names, in index order."""
        if self.names is not None:
            return tuple(self.names)
        return tuple(map(str, range(self.n_transitions)))

    def name_of(self, transition: int) -> str:
        """Name of one transition (cheap even for millions of transitions)."""
        return self.names[transition] if self.names is not None else str(transition)

    def place_label(self, place: int) -> str:
        """``"SRC -> DST"``, the label of a place (arc lists have no place names)."""
        return f"{self.name_of(int(self.src[place]))} -> {self.name_of(int(self.dst[place]))}"

    def holding_time(self, place: int) -> Fraction:
        """Exact holding time of one place."""
        return Fraction(int(self.holding[place]), self.scale)

    def arrays(self) -> TEGArrays:
        """The same arrays as :meth:`TimedEventGraph.arrays` (availability times all 0)."""
        return TEGArrays(self.src, self.dst, self.tokens, self.holding,
                         np.zeros(len(self.src), dtype=np.int64), self.scale, self.n_transitions)

    def to_teg(self) -> TimedEventGraph:
        """The :class:`~tegraph.model.teg.TimedEventGraph` (one Python object per place)."""
        teg = TimedEventGraph(self.name)
        for name in self.transition_names:
            teg.add_transition(name)
        for s, d, h, t in zip(self.src.tolist(), self.dst.tolist(), self.holding.tolist(),
                              self.tokens.tolist()):
            teg.add_place(s, d, t, Fraction(int(h), self.scale))
        return teg

    @classmethod
    def from_teg(cls, teg: TimedEventGraph) -> ArcList:
        """The arc list of a timed event graph.

        Raises
        ------
        ModelError
            A place's initial tokens are available after time 0: an arc list
            cannot hold that (the cycle time would not change, the daters would).
        """
        a = teg.arrays()
        late = np.flatnonzero(np.asarray(a.initial) != 0)
        if len(late):
            p = teg.places[int(late[0])]
            raise ModelError(f"its initial tokens are available at {p.initial}, not 0; an arc "
                             "list cannot hold availability times (PNML can)", f"place {p.name}")
        names = list(teg.transition_names)
        default = names == [str(i) for i in range(len(names))]
        return cls(a.src, a.dst, a.holding, a.tokens, a.scale, None if default else names,
                   teg.n_transitions, teg.name)
