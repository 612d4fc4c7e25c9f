"""Synchronous dataflow (SDF) graphs and their homogeneous expansion.

An SDF graph has actors with an execution time and channels that carry
tokens at fixed rates: each firing of the source actor produces ``prod``
tokens, each firing of the destination consumes ``cons``; ``tokens`` are
there initially. What is read, as SDF3 [4]_ itself reads it:

* the execution time of an actor is that of the **last** ``<processor>`` of
  its ``actorProperties`` carrying a ``default`` attribute (any value), 0 if none;
* rates come from the ``rate`` of the ports named by the channel;
  ``initialTokens`` defaults to 0;
* an actor without a self-loop channel may fire concurrently with itself
  (unbounded auto-concurrency): no self-loop is added.

The repetition vector ``q`` [3]_ (the smallest positive integers with
``q[src] * prod == q[dst] * cons`` on every channel) expands the graph into
its homogeneous graph: one transition ``actor_i`` per firing
``i < q[actor]`` of an iteration, one place per dependency, holding the
execution time of the source firing (:meth:`SDFGraph.to_arcs`). Its maximum
cycle ratio is the period of the graph: the time per iteration, whose
inverse is SDF3's throughput ([1]_, ch. 3; [2]_).

References
----------
.. [1] S. Sriram, S. S. Bhattacharyya, *Embedded Multiprocessors: Scheduling
   and Synchronization*, 2nd ed., CRC Press, 2009.
.. [2] A. H. Ghamarian et al., "Throughput analysis of synchronous data flow
   graphs", International Conference on Application of Concurrency to
   System Design (ACSD), 2006.
.. [3] E. A. Lee, D. G. Messerschmitt, "Synchronous data flow", Proceedings
   of the IEEE 75(9), 1235–1245, 1987.
.. [4] S. Stuijk, M. Geilen, T. Basten, "SDF³: SDF For Free", International
   Conference on Application of Concurrency to System Design (ACSD), 2006.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np

from maxplus.scalar import int_array

from ..errors import InputError, ModelError
from .arcs import ArcList
from .limits import DEFAULT_MAX_FIRINGS, MAX_DIGITS
from .teg import TimedEventGraph

__all__ = ["SDFChannel", "SDFGraph"]

_MAX_BITS = int(MAX_DIGITS * 3.33) + 1  # a repetition entry of MAX_DIGITS decimal digits


@dataclass(frozen=True)
class SDFChannel:
    """A channel ``src -> dst``: ``prod`` tokens a source firing, ``cons`` a destination firing."""

    name: str
    src: str
    dst: str
    prod: int = 1
    cons: int = 1
    tokens: int = 0


@dataclass
class SDFGraph:
    """A timed SDF graph: actors with integer execution times, channels with rates.

    Attributes
    ----------
    name : str
    actors : dict of str to int
        Execution time of each actor, in file order.
    channels : list of SDFChannel
    source : str or None
        The file the graph was read from, named in refusals (not compared).

    See Also
    --------
    tegraph.io.sdf3.read_sdf3 : an SDF graph from an SDF3 file.
    tegraph.analysis.cycle_time.cycle_time : its period and throughput.

    Examples
    --------
    ``a`` fires twice per firing of ``b`` (rates 1 and 2); the two tokens on
    the way back let both firings of ``a`` start at once (no self-loop, so
    they run concurrently): the period is 2 + 3 = 5.

    >>> g = SDFGraph("g", {"a": 2, "b": 3}, [SDFChannel("ab", "a", "b", 1, 2, 0),
    ...                                     SDFChannel("ba", "b", "a", 2, 1, 2)])
    >>> g.repetition_vector()
    {'a': 2, 'b': 1}
    >>> from tegraph.analysis.cycle_time import cycle_time
    >>> str(cycle_time(g).period)
    '5'
    """

    name: str
    actors: dict[str, int]
    channels: list[SDFChannel] = field(default_factory=list)
    source: str | None = field(default=None, compare=False)

    def repetition_vector(self) -> dict[str, int]:
        """Smallest positive firings per iteration, per actor (connected parts separately).

        The balance equations ``q[src] * prod == q[dst] * cons`` of Lee and
        Messerschmitt [1]_, solved along a spanning tree of each connected
        part and checked on the other channels.

        Returns
        -------
        dict of str to int
            Firings of each actor in one iteration, in actor order.

        Raises
        ------
        ModelError
            Inconsistent rates: the message names a channel closing an
            inconsistent cycle (such a graph needs unbounded memory or deadlocks).

        See Also
        --------
        expansion_size : the size of the expansion it implies.

        References
        ----------
        .. [1] E. A. Lee, D. G. Messerschmitt, "Synchronous data flow",
           Proceedings of the IEEE 75(9), 1235–1245, 1987.

        Examples
        --------
        >>> g = SDFGraph("g", {"a": 1, "b": 1}, [SDFChannel("ab", "a", "b", 2, 3)])
        >>> g.repetition_vector()
        {'a': 3, 'b': 2}
        """
        adj: dict[str, list[tuple[str, Fraction, SDFChannel]]] = {a: [] for a in self.actors}
        for c in self.channels:
            adj[c.src].append((c.dst, Fraction(c.prod, c.cons), c))
            adj[c.dst].append((c.src, Fraction(c.cons, c.prod), c))
        q: dict[str, Fraction] = {}
        for start in self.actors:
            if start in q:
                continue
            part, stack = [start], [start]
            q[start] = Fraction(1)
            while stack:  # q[b] = q[a] * prod / cons along every channel a -> b
                a = stack.pop()
                for b, factor, c in adj[a]:
                    want = q[a] * factor
                    if max(want.numerator, want.denominator).bit_length() > _MAX_BITS:
                        raise ModelError(f"the repetition vector reaches an entry of more than "
                                         f"{MAX_DIGITS} digits at actor {b}; such a graph "
                                         "cannot be expanded", f"channel {c.name}")
                    if b not in q:
                        q[b] = want
                        part.append(b)
                        stack.append(b)
                    elif q[b] != want:
                        raise ModelError(f"inconsistent rates: {c.src} x{c.prod} -> {c.dst} "
                                         f"x{c.cons} contradicts the other channels between "
                                         "these actors (no repetition vector exists)",
                                         f"channel {c.name}")
            lcm = math.lcm(*(q[a].denominator for a in part))
            ints = [int(q[a] * lcm) for a in part]
            g = math.gcd(*ints)
            for a, v in zip(part, ints):
                q[a] = Fraction(v // g)
        return {a: int(q[a]) for a in self.actors}

    def expansion_size(self) -> tuple[int, int]:
        """Firings and token transfers of one iteration: the size of :meth:`to_arcs`' work.

        Firings are the sum of the repetition vector (the transitions of the
        expansion); transfers are the tokens all channels carry in one
        iteration, ``sum(q[dst] * cons)`` (the places before duplicates are
        dropped). Both are computed from the repetition vector alone.

        Returns
        -------
        (int, int)
            Firings and token transfers per iteration.

        Raises
        ------
        ModelError
            Inconsistent rates (see :meth:`repetition_vector`).

        See Also
        --------
        to_arcs : refuses an expansion above its ``max_firings``.

        Examples
        --------
        >>> g = SDFGraph("g", {"a": 1, "b": 1}, [SDFChannel("ab", "a", "b", 10**9, 10**9 + 1)])
        >>> g.expansion_size()
        (2000000001, 1000000001000000000)
        """
        q = self.repetition_vector()
        return sum(q.values()), sum(q[c.dst] * c.cons for c in self.channels)

    def to_arcs(self, max_firings: int = DEFAULT_MAX_FIRINGS) -> ArcList:
        """The homogeneous (HSDF) expansion as an arc list (transitions ``actor_i``).

        Firing ``j`` of ``dst`` in iteration ``k`` takes the tokens of absolute
        index ``N = (k q_dst + j) cons + i``, ``i < cons``; token ``N`` was made
        by firing ``f = floor((N - tokens) / prod)`` of ``src`` (initial tokens
        count as firings of earlier iterations), i.e. by ``src_(f mod q_src)``
        ``-floor(f / q_src)`` iterations before. Of the places between two
        firings only the one with fewest tokens constrains, and is kept.

        Parameters
        ----------
        max_firings : int
            Refuse an expansion of more firings, or token transfers, per
            iteration than this (default
            :data:`~tegraph.model.limits.DEFAULT_MAX_FIRINGS`, 10**7): its
            arrays take some 100 bytes each. Checked from the repetition
            vector before anything is built (:meth:`expansion_size`).

        Returns
        -------
        ArcList
            One transition ``actor_i`` per firing of an iteration, one arc per
            dependency, holding the execution time of its source firing; its
            maximum cycle ratio is the period of the graph [1]_, [2]_.

        Raises
        ------
        InputError
            The expansion is above ``max_firings`` (``where`` is ``max_firings``).
        ModelError
            Inconsistent rates.

        See Also
        --------
        to_teg : the same as a timed event graph.
        repetition_vector : the firings per iteration.

        References
        ----------
        .. [1] S. Sriram, S. S. Bhattacharyya, *Embedded Multiprocessors: Scheduling
           and Synchronization*, 2nd ed., CRC Press, 2009.
        .. [2] A. H. Ghamarian et al., "Throughput analysis of synchronous data flow
           graphs", International Conference on Application of Concurrency to
           System Design (ACSD), 2006.

        Examples
        --------
        The graph of the class example: ``a`` fires twice per iteration.

        >>> g = SDFGraph("g", {"a": 2, "b": 3}, [SDFChannel("ab", "a", "b", 1, 2, 0),
        ...                                     SDFChannel("ba", "b", "a", 2, 1, 2)])
        >>> arcs = g.to_arcs()
        >>> arcs.names, arcs.src.tolist(), arcs.dst.tolist(), arcs.tokens.tolist()
        (['a_0', 'a_1', 'b_0'], [0, 1, 2, 2], [2, 2, 0, 1], [0, 0, 1, 1])
        """
        firings, transfers = self.expansion_size()
        for count, what in ((firings, "firings (the sum of the repetition vector)"),
                            (transfers, "token transfers (the sum over channels of "
                                        "q[dst] * consumption rate)")):
            if count > max_firings:
                raise InputError(
                    f"the homogeneous expansion of SDF graph {self.name!r} has {count} {what} "
                    f"per iteration, above the limit of {max_firings}; raise `max_firings` to "
                    "expand it (tegraph has no method that avoids the expansion)",
                    "max_firings", self.source)
        q = self.repetition_vector()
        offset: dict[str, int] = {}
        names: list[str] = []
        for a in self.actors:
            offset[a] = len(names)
            names.extend(f"{a}_{i}" for i in range(q[a]))
        if len(set(names)) != len(names):
            raise ModelError("two firings get the same name actor_i; rename the actors",
                             f"graph {self.name}")
        src, dst, tok = [], [], []
        for c in self.channels:
            j = np.repeat(np.arange(q[c.dst], dtype=np.int64), c.cons)
            i = np.tile(np.arange(c.cons, dtype=np.int64), q[c.dst])
            f = (j * c.cons + i - c.tokens) // c.prod
            src.append(offset[c.src] + f % q[c.src])
            dst.append(offset[c.dst] + j)
            tok.append(-(f // q[c.src]))
        s = np.concatenate(src) if src else np.zeros(0, np.int64)
        d = np.concatenate(dst) if dst else np.zeros(0, np.int64)
        t = np.concatenate(tok) if tok else np.zeros(0, np.int64)
        order = np.lexsort((t, d, s))  # by (src, dst), fewest tokens first
        s, d, t = s[order], d[order], t[order]
        first = np.ones(len(s), dtype=bool)
        first[1:] = (s[1:] != s[:-1]) | (d[1:] != d[:-1])
        s, d, t = s[first], d[first], t[first]
        # execution times of any size stay exact (object arrays from 2**62)
        exec_time = int_array([self.actors[a] for a in self.actors for _ in range(q[a])])
        return ArcList(s, d, exec_time[s], t, 1, names, len(names), self.name)

    def to_teg(self) -> TimedEventGraph:
        """The homogeneous expansion as a :class:`~tegraph.model.teg.TimedEventGraph`.

        Returns
        -------
        TimedEventGraph
            One transition ``actor_i`` per firing of an iteration.

        Raises
        ------
        InputError
            The expansion is above the default ``max_firings`` of :meth:`to_arcs`.
        ModelError
            Inconsistent rates.

        See Also
        --------
        to_arcs : the same as arrays, with a ``max_firings`` of choice.
        from_teg : the converse, with all rates 1.

        Examples
        --------
        >>> g = SDFGraph("g", {"a": 2, "b": 3}, [SDFChannel("ab", "a", "b", 1, 2, 0),
        ...                                     SDFChannel("ba", "b", "a", 2, 1, 2)])
        >>> g.to_teg().transition_names
        ('a_0', 'a_1', 'b_0')
        """
        return self.to_arcs().to_teg()

    @classmethod
    def from_teg(cls, teg: TimedEventGraph) -> SDFGraph:
        """The homogeneous SDF graph of a timed event graph (all rates 1).

        A transition whose places all hold one time becomes an actor of that
        execution time. When its places hold different times, the actor takes
        0 and each place becomes an actor of its own, holding its time (no
        self-loop: it serves any number of tokens at once, as a place does).
        Every circuit keeps its times and tokens, so its cycle ratio.

        Parameters
        ----------
        teg : TimedEventGraph
            Integer holding times, initial tokens available at 0.

        Returns
        -------
        SDFGraph
            All rates 1: one actor per transition (and per place whose time
            differs from its siblings'), one channel per place.

        Raises
        ------
        ModelError
            A time is not an integer, or initial tokens are available after 0:
            SDF3 has neither.

        See Also
        --------
        to_teg : the converse.
        tegraph.io.sdf3.write_sdf3 : writes the result as SDF3 XML.

        Examples
        --------
        >>> g = SDFGraph("g", {"a": 2, "b": 3}, [SDFChannel("ab", "a", "b", 1, 2, 0),
        ...                                     SDFChannel("ba", "b", "a", 2, 1, 2)])
        >>> SDFGraph.from_teg(g.to_teg()).actors
        {'a_0': 2, 'a_1': 2, 'b_0': 3}
        """
        g = teg
        names = g.transition_names
        times: dict[int, set[Fraction]] = {}
        for p in g.places:
            where = f"place {p.name}"
            if p.initial != 0:
                raise ModelError("initial tokens available after 0 cannot be written to "
                                 "SDF3", where)
            if p.holding.denominator != 1:
                raise ModelError(f"SDF3 execution times are integers, got {p.holding}", where)
            times.setdefault(p.src, set()).add(p.holding)
        actors = {n: int(next(iter(times[k]))) if len(times.get(k, ())) == 1 else 0
                  for k, n in enumerate(names)}
        channels = []
        for k, p in enumerate(g.places):
            src, dst = names[p.src], names[p.dst]
            if len(times[p.src]) > 1 and p.holding:
                mid = f"place{k}"
                while mid in actors:
                    mid += "_"
                actors[mid] = int(p.holding)
                channels.append(SDFChannel(f"ch{k}a", src, mid, 1, 1, 0))
                src = mid
            channels.append(SDFChannel(f"ch{k}", src, dst, 1, 1, p.tokens))
        return cls(g.name, actors, channels)
