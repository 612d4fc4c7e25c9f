"""Timed event graphs (TEGs): events, places, and exact earliest-firing dynamics.

A timed event graph is a Petri net in which every place has exactly one input
transition and one output transition (a *marked graph*), with a number of
initial tokens ``m_p`` and a holding time ``h_p`` on every place (spec §2).
Transitions are called *events* here, as in the (max,+) literature.

:class:`TimedEventGraph` is usable on its own, from code, without a skeleton;
:func:`tegraph.model.build.build_teg` builds one from a synchronization skeleton.
Its design follows ``scipy.sparse.csgraph``: every value is validated once,
when it enters (:meth:`~TimedEventGraph.add_place`), then kernels receive plain
numpy arrays (:meth:`~TimedEventGraph.arrays`) of *scaled integers*: all times
multiplied by their least common denominator, so that integer arithmetic is
exact (no binary floating point where the input was exact).

Dynamics (spec §3), implemented by :meth:`~TimedEventGraph.simulate`:
``x_e(k)``, ``k >= 1``, the time of the k-th firing of event ``e``, is::

    x_e(k) = max over places p into e of  x_src(p)(k - m_p) + h_p   if k > m_p
                                          a_p                       otherwise

where ``a_p`` (:attr:`Place.initial`) is the time the initial tokens of ``p``
are available (0, except on a clock's self-loop where it is the phase).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from numbers import Integral, Rational
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
import scipy.sparse as sp

from maxplus.errors import MaxPlusValueError
from maxplus.scalar import EPS, INT64_SAFE, exact_time, int_array, size_problem

from ..errors import InputError, ModelError, NotLiveError
from .limits import MAX_COUNT, count_problem, written

if TYPE_CHECKING:  # networkx is slow to import; only the conversions need it
    import networkx as nx

__all__ = ["Daters", "Place", "TEGArrays", "TimeCodes", "TimedEventGraph"]


@dataclass(frozen=True)
class Place:
    """A place of a timed event graph: one input event, one output event.

    Attributes
    ----------
    src, dst : int
        Index of the event that puts tokens in the place (its input
        transition) and of the event that takes them (its output transition).
    tokens : int
        Initial tokens ``m_p >= 0``.
    holding : Fraction
        Holding time ``h_p >= 0``: a token put at time t can be taken at t + h_p.
    initial : Fraction
        ``a_p >= 0``, the time at which the initial tokens are available (spec §3).
    kind : str
        Free classification (:mod:`tegraph.model.build` uses ``"chain"``, ``"clock"``...).
    name : str
        Label for messages (default ``"SRC -> DST"``); need not be unique.
    origin : object
        Provenance (a dict for built graphs, see :mod:`tegraph.model.build`). Not part
        of the hash, so it may be a dict; treat it as read-only.
    """

    src: int
    dst: int
    tokens: int = 0
    holding: Fraction = Fraction(0)
    initial: Fraction = Fraction(0)
    kind: str = ""
    name: str = ""
    origin: Any = field(default=None, hash=False)


@dataclass(frozen=True, eq=False)
class TEGArrays:
    """The numeric content of a TEG, one entry per place, for array kernels.

    Attributes
    ----------
    src, dst : numpy.ndarray of int64
    tokens : numpy.ndarray of int64
    holding, initial : numpy.ndarray
        ``holding * scale`` and ``initial * scale`` as integers: int64, or
        object dtype (Python ints) when a value reaches 2**62.
    scale : int
        Least common denominator of every holding and initial time.
    n_transitions : int
    """

    src: np.ndarray
    dst: np.ndarray
    tokens: np.ndarray
    holding: np.ndarray
    initial: np.ndarray
    scale: int
    n_transitions: int


@dataclass(frozen=True, eq=False)
class Daters:
    """Firing times computed by :meth:`TimedEventGraph.simulate`.

    Attributes
    ----------
    times : numpy.ndarray
        Shape ``(n_firings, n_transitions)``; ``times[k-1, e] / scale`` is
        ``x_e(k)``. int64, or object dtype (Python ints) for huge values.
    scale : int
    names : tuple of str
        Event names, in index order.
    """

    times: np.ndarray
    scale: int
    names: tuple[str, ...]

    def __getitem__(self, event: str | int) -> list[Fraction]:
        """``[x_e(1), x_e(2), ...]`` for the event ``e`` (name or index)."""
        if isinstance(event, str):
            if event not in self.names:
                raise ModelError("unknown event", event)
            col = self.names.index(event)
        else:
            col = int(event)
        return [Fraction(int(v), self.scale) for v in self.times[:, col].tolist()]

    def fractions(self) -> np.ndarray:
        """All daters as an object array of Fractions, shape ``(n_firings, n_transitions)``."""
        out = np.empty(self.times.shape, dtype=object)
        for idx, v in np.ndenumerate(self.times):
            out[idx] = Fraction(int(v), self.scale)
        return out

    def to_dict(self) -> dict[str, list[Fraction]]:
        """Event name -> ``[x_e(1), ..., x_e(n_firings)]``."""
        return {name: self[i] for i, name in enumerate(self.names)}


class TimedEventGraph:
    """A timed event graph with exact (rational) times.

    Parameters
    ----------
    name : str
        A label (the skeleton's name for built graphs).

    Attributes
    ----------
    name : str
    attrs : dict
        Graph-level data (for built graphs: chains, see :mod:`tegraph.model.build`).
    transition_attrs : list of dict
        Keyword attributes given to :meth:`add_transition`, one dict per event.

    See Also
    --------
    tegraph.build_teg : the timed event graph of a skeleton.
    tegraph.cycle_time : its period and critical circuit.
    tegraph.PetriNet : the untimed net of the same places.

    Examples
    --------
    A clock of period 4 and phase 1 that activates a task of duration 3:

    >>> g = TimedEventGraph()
    >>> g.add_transition("tick"), g.add_transition("run")
    (0, 1)
    >>> g.add_place("tick", "tick", tokens=1, holding=4, initial=1)
    0
    >>> g.add_place("tick", "run"), g.add_place("run", "run", tokens=1, holding=3)
    (1, 2)
    >>> [str(t) for t in g.simulate(3)["run"]]
    ['1', '5', '9']
    """

    def __init__(self, name: str = "teg") -> None:
        self.name = name
        self.attrs: dict[str, Any] = {}
        self.transition_attrs: list[dict[str, Any]] = []
        self._names: list[str] = []
        self._index: dict[str, int] = {}
        # The places as columns, one entry a place: a Place object each is made only
        # when `places` is read (a built skeleton of 10,000 tasks has 70,000 places,
        # and array kernels need only the numbers). A label is None until a Place
        # is made ("SRC -> DST" then).
        self._src: list[int] = []
        self._dst: list[int] = []
        self._tokens: list[int] = []
        self._holding = _TimeColumn()
        self._initial = _TimeColumn()
        self._kind: list[str] = []
        self._label: list[str | None] = []
        self._origin: list[Any] = []
        self._cache: dict[str, Any] = {}

    def __repr__(self) -> str:
        return (f"<TimedEventGraph {self.name!r}: {self.n_transitions} events, "
                f"{self.n_places} places>")

    # ---------------------------------------------------------------- building
    def add_transition(self, name: str, /, **attrs: Any) -> int:
        """Add an event with a unique name; return its index.

        Raises
        ------
        ModelError
            The name is not a non-empty string or is already used.
        """
        if not isinstance(name, str) or not name:
            raise ModelError("an event name must be a non-empty string", repr(name))
        if name in self._index:
            raise ModelError("duplicate event name", name)
        index = self._index[name] = len(self._names)
        self._names.append(name)
        self.transition_attrs.append(attrs)  # a fresh dict already (keyword arguments)
        self._cache.clear()
        return index

    def add_place(self, src: str | int, dst: str | int, tokens: int = 0, holding: Any = 0,
                  initial: Any = 0, kind: str = "", name: str | None = None,
                  origin: Any = None) -> int:
        """Add a place ``src -> dst``; return its index.

        Parameters
        ----------
        src, dst : str or int
            Input and output event, by name or index.
        tokens : int
            Initial tokens, >= 0.
        holding, initial : int, Fraction, str or float
            Times >= 0, read exactly (``0.1`` is 1/10, ``"7/3"`` is 7/3).
        kind, name, origin
            See :class:`Place`.

        Raises
        ------
        ModelError
            Unknown event, negative or non-integral tokens, negative or
            malformed time; the message names the place.

        Examples
        --------
        >>> g = TimedEventGraph(); _ = g.add_transition("a")
        >>> g.add_place("a", "a", tokens=1, holding="0.5")
        0
        >>> g.add_place("a", "b")
        Traceback (most recent call last):
        ...
        tegraph.errors.ModelError: place a -> b: unknown event 'b'
        """
        label = f"{src} -> {dst}" if name is None else name
        index = self._index
        if _trusted(index, src, dst, tokens, holding, initial):
            # Type: _trusted checked that both ends are names of events.
            return self._append(index[src], index[dst],  # type: ignore[index]
                                tokens, holding, initial, str(kind or ""), label, origin)
        s = self._resolve(src, f"place {label}")
        d = self._resolve(dst, f"place {label}")
        if name is None:
            label = f"{self._names[s]} -> {self._names[d]}"
        where = f"place {label}"
        return self._append(s, d, _check_tokens(tokens, where),
                            _check_time(holding, "holding", where),
                            _check_time(initial, "initial", where), str(kind or ""), label,
                            origin)

    def add_places(self, places: Iterable[tuple[Any, ...]]) -> None:
        """Add places ``(src, dst, tokens, holding, initial, kind, origin)``, in order.

        The same as :meth:`add_place` on each (same checks, same errors), at less
        cost a place for the builder's own (events by name, exact times): a
        skeleton of 10,000 tasks has 70,000 places.

        Examples
        --------
        >>> g = TimedEventGraph(); _ = g.add_transition("a")
        >>> g.add_places([("a", "a", 1, Fraction(2), Fraction(0), "loop", None),
        ...               ("a", "a", 0, "1/2", 0, "", None)])
        >>> [(p.name, p.tokens, str(p.holding)) for p in g.places]
        [('a -> a', 1, '2'), ('a -> a', 0, '1/2')]
        """
        index = self._index
        for src, dst, tokens, holding, initial, kind, origin in places:
            if _trusted(index, src, dst, tokens, holding, initial):
                # The name "SRC -> DST" is made when the Place is (None until then).
                self._append(index[src], index[dst], tokens, holding, initial,
                             str(kind or ""), None, origin)
            else:
                self.add_place(src, dst, tokens, holding, initial, kind, origin=origin)
        self._cache.clear()

    def add_transitions(self, names: Sequence[str], attrs: Sequence[dict[str, Any]]) -> None:
        """Add events ``names[i]`` with the attributes ``attrs[i]``, in order.

        The same as ``add_transition(names[i], **attrs[i])`` on each (same checks,
        same errors), at less cost an event: a skeleton of 10,000 clocked tasks has
        50,000 events. The dicts are kept as given (not copied).

        >>> g = TimedEventGraph()
        >>> g.add_transitions(["a", "b"], [{"role": "x"}, {}])
        >>> g.transition_names, g.index("b"), g.transition_attrs[0]
        (('a', 'b'), 1, {'role': 'x'})
        """
        if len(attrs) != len(names):
            raise ModelError(f"{len(names)} event names but {len(attrs)} attribute dicts",
                             "add_transitions")
        first = len(self._names)
        index = dict(zip(names, range(first, first + len(names))))
        if (len(index) != len(names) or not index.keys().isdisjoint(self._index)
                or not set(map(type, index)) <= {str} or "" in index):
            for name, more in zip(names, attrs):  # the first bad name raises as it would
                self.add_transition(name, **more)
            return
        self._index.update(index)
        self._names.extend(names)
        self.transition_attrs.extend(attrs)
        self._cache.clear()

    def add_place_columns(self, src: Sequence[int] | np.ndarray, dst: Sequence[int] | np.ndarray,
                          tokens: Sequence[int] | np.ndarray, holding: TimeCodes,
                          initial: TimeCodes,
                          kind: Sequence[str], origin: Sequence[Any]) -> None:
        """Add places given as columns, one entry a place, in order.

        The same as :meth:`add_place` on each place ``(src[i], dst[i], tokens[i],
        holding.values[holding.codes[i]], ...)`` (same checks, same errors), at
        the cost of a few list copies, not of a call a place: what
        :func:`~tegraph.model.build.build_teg` gives (70,000 places at 10,000 tasks).

        Parameters
        ----------
        src, dst : array_like of int
            Event indices.
        tokens : array_like of int
        holding, initial : TimeCodes
            Each place's time as its index in a short table of distinct times.
        kind, origin : sequence
            As :class:`Place`'s (``origin`` objects are kept, not copied).

        Examples
        --------
        >>> g = TimedEventGraph(); _ = g.add_transition("a"); _ = g.add_transition("b")
        >>> times = TimeCodes((Fraction(0), Fraction(1, 2)), [1, 0])
        >>> g.add_place_columns([0, 1], [1, 0], [0, 1], times, TimeCodes((Fraction(0),), [0, 0]),
        ...                     ["x", "y"], [None, None])
        >>> [(p.name, p.tokens, str(p.holding), p.kind) for p in g.places]
        [('a -> b', 0, '1/2', 'x'), ('b -> a', 1, '0', 'y')]
        """
        n = len(src)
        if any(len(column) != n for column in (dst, tokens, holding.codes, initial.codes, kind,
                                               origin)):
            raise ModelError("place columns of different lengths", "add_place_columns")
        ints = [np.asarray(column) for column in (src, dst, tokens)]
        if not (all(type(t) is Fraction and t.numerator >= 0
                    for t in (*holding.values, *initial.values))
                and all(a.shape == (n,) and (n == 0 or a.dtype.kind in "iu") for a in ints)
                and _within(ints[0], 0, len(self._names) - 1)
                and _within(ints[1], 0, len(self._names) - 1)
                and _within(ints[2], 0, MAX_COUNT)):
            for i in range(n):  # add_place's checks, and the first failing one's error
                self.add_place(src[i], dst[i], tokens[i], holding.values[holding.codes[i]],
                               initial.values[initial.codes[i]], kind[i], origin=origin[i])
            return
        self._src.extend(ints[0].tolist())
        self._dst.extend(ints[1].tolist())
        self._tokens.extend(ints[2].tolist())
        self._holding.extend(holding)
        self._initial.extend(initial)
        self._kind.extend(kind)
        self._label.extend([None] * n)
        self._origin.extend(origin)
        self._cache.clear()

    def _append(self, src: int, dst: int, tokens: int, holding: Fraction, initial: Fraction,
                kind: str, label: str | None, origin: Any) -> int:
        """Append one place, already checked."""
        self._src.append(src)
        self._dst.append(dst)
        self._tokens.append(tokens)
        self._holding.append(holding)
        self._initial.append(initial)
        self._kind.append(kind)
        self._label.append(label)
        self._origin.append(origin)
        self._cache.clear()
        return len(self._src) - 1

    def _resolve(self, ref: str | int, where: str) -> int:
        if isinstance(ref, str):
            if ref not in self._index:
                raise ModelError(f"unknown event {ref!r}", where)
            return self._index[ref]
        if isinstance(ref, Integral) and not isinstance(ref, bool):
            if 0 <= int(ref) < len(self._names):
                return int(ref)
            raise ModelError(f"event index {ref} out of range 0..{len(self._names) - 1}", where)
        raise ModelError(f"an event is a name or an index, got {ref!r}", where)

    # ---------------------------------------------------------------- access
    def index(self, name: str) -> int:
        """Index of the event called ``name`` (:class:`ModelError` if unknown)."""
        found = self._index.get(name) if type(name) is str else None
        return found if found is not None else self._resolve(name, "event")

    @property
    def n_transitions(self) -> int:
        """Number of events."""
        return len(self._names)

    @property
    def n_places(self) -> int:
        """Number of places."""
        return len(self._src)

    @property
    def transition_names(self) -> tuple[str, ...]:
        """Event names, in index order."""
        # Cached until the next change: callers index it once per place or event, and a
        # fresh tuple per call made their loops quadratic.
        names = self._cache.get("names")
        if names is None:
            names = self._cache["names"] = tuple(self._names)
        return names

    @property
    def places(self) -> tuple[Place, ...]:
        """The places, in index order."""
        places = self._cache.get("places")
        if places is None:
            names = self._names
            places = self._cache["places"] = tuple(
                Place(s, d, tokens, holding, initial, kind,
                      f"{names[s]} -> {names[d]}" if name is None else name, origin)
                for s, d, tokens, holding, initial, kind, name, origin in zip(
                    self._src, self._dst, self._tokens, self._holding.objects(),
                    self._initial.objects(), self._kind, self._label, self._origin))
        return places

    def place(self, index: int) -> Place:
        """The place of this index, made alone when :attr:`places` was not read yet.

        A report names a few places (the unbounded ones, a deadlock's circuit);
        making every place object for them would cost a step per place on large graphs.

        >>> g = TimedEventGraph(); _ = g.add_transition("a"); _ = g.add_transition("b")
        >>> _ = g.add_place("a", "b", 1, "1/2")
        >>> g.place(0) == g.places[0], g.place(0).name
        (True, 'a -> b')
        """
        places = self._cache.get("places")
        if places is not None:
            return places[index]
        s, d, name = self._src[index], self._dst[index], self._label[index]
        if name is None:
            name = f"{self._names[s]} -> {self._names[d]}"
        return Place(s, d, self._tokens[index], self._holding[index], self._initial[index],
                     self._kind[index], name, self._origin[index])

    def place_kind(self, index: int) -> str:
        """The :attr:`Place.kind` of this place, without making its :class:`Place`.

        >>> g = TimedEventGraph(); _ = g.add_transition("a")
        >>> _ = g.add_place("a", "a", 1, kind="loop")
        >>> g.place_kind(0)
        'loop'
        """
        return self._kind[index]

    def arrays(self) -> TEGArrays:
        """The places as numpy arrays of scaled integers (cached until the next change).

        Examples
        --------
        >>> g = TimedEventGraph(); _ = g.add_transition("a"); _ = g.add_transition("b")
        >>> _ = g.add_place("a", "b", holding="1/2"); _ = g.add_place("b", "a", 1, "2/3")
        >>> a = g.arrays()
        >>> a.scale, a.holding.tolist(), a.tokens.tolist(), a.src.tolist()
        (6, [3, 4], [0, 1], [0, 1])
        """
        if "arrays" not in self._cache:
            holding, initial = self._holding, self._initial
            # Few distinct denominators: the lcm of the set, and each time scaled by
            # integer arithmetic (a Fraction product per place costs a gcd).
            scale = math.lcm(1, *{t.denominator for t in holding.values},
                             *{t.denominator for t in initial.values})
            self._cache["arrays"] = TEGArrays(
                src=np.array(self._src, dtype=np.int64),
                dst=np.array(self._dst, dtype=np.int64),
                tokens=np.array(self._tokens, dtype=np.int64),
                holding=holding.scaled(scale), initial=initial.scaled(scale),
                scale=scale, n_transitions=self.n_transitions)
        return self._cache["arrays"]

    def scaled_by_part(self, part: np.ndarray, n_parts: int
                       ) -> tuple[np.ndarray, np.ndarray, list[int]]:
        """Holding and initial times scaled by a scale of each part of the places.

        :meth:`arrays` scales every time by one common denominator; parts of the
        graph that no place joins (a skeleton's groups) need only their own: the
        lcm of the denominators of their places' times. Two hundred groups of
        periods with denominators up to 30 have a common scale of 39 digits, past
        int64, while each group's fits.

        Parameters
        ----------
        part : numpy.ndarray of int
            The part of each place, in ``0 .. n_parts-1``.
        n_parts : int

        Returns
        -------
        holding, initial : numpy.ndarray
            ``time * scales[part]`` of each place: int64, or object dtype (Python
            ints) when a value reaches 2**62 (as :meth:`arrays`).
        scales : list of int
            Each part's scale (1 for a part without places).

        Examples
        --------
        >>> g = TimedEventGraph(); _ = g.add_transition("a"); _ = g.add_transition("b")
        >>> _ = g.add_place("a", "a", 1, "1/2"); _ = g.add_place("b", "b", 1, "2/3", "1/5")
        >>> h, i, scales = g.scaled_by_part(np.array([0, 1]), 2)
        >>> h.tolist(), i.tolist(), scales, g.arrays().scale
        ([1, 10], [0, 3], [2, 15], 30)
        """
        part = np.asarray(part, dtype=np.int64)
        scales = [1] * n_parts
        found = []
        for column in (self._holding, self._initial):
            width = max(len(column.values), 1)
            # Each (part, distinct time) once: a few per task, not one per place.
            pairs, inverse = np.unique(part * width + np.asarray(column.codes, dtype=np.int64),
                                       return_inverse=True)
            parts, values = (pairs // width).tolist(), column.values
            times = [values[c] for c in (pairs % width).tolist()]
            # Most times are whole (durations and periods in whole units): only the
            # others change their part's scale.
            for p, t in zip(parts, times):
                if t.denominator != 1:
                    scales[p] = math.lcm(scales[p], t.denominator)
            found.append((parts, times, inverse))
        holding, initial = (_scaled(times, [scales[p] for p in parts])[inverse]
                            for parts, times, inverse in found)
        return holding, initial, scales

    def incidence_matrix(self) -> sp.csr_matrix:
        """The incidence matrix ``W`` (places x events), as the paper's ``W(p, t)``.

        ``W[p, t] = +1`` when p is an output place of t (``t -> p``), ``-1``
        when it is an input place (``p -> t``), 0 otherwise. A self-loop place
        (``t -> p -> t``) gives an all-zero row: the net is then not *pure*
        and ``W`` loses that place (the paper's footnote 4).

        Examples
        --------
        >>> g = TimedEventGraph(); _ = g.add_transition("a"); _ = g.add_transition("b")
        >>> _ = g.add_place("a", "b"); _ = g.add_place("b", "b", 1)
        >>> g.incidence_matrix().toarray().tolist()
        [[1, -1], [0, 0]]
        """
        a = self.arrays()
        n = self.n_places
        rows = np.concatenate([np.arange(n), np.arange(n)])
        data = np.concatenate([np.ones(n, np.int64), -np.ones(n, np.int64)])
        w = sp.coo_matrix((data, (rows, np.concatenate([a.src, a.dst]))),
                          shape=(n, self.n_transitions)).tocsr()  # sums duplicates
        w.eliminate_zeros()
        return w

    def state_equations(self) -> list[np.ndarray]:
        """The (max,+) implicit state equations ``[A0, A1, ..., AM]``.

        ``A_m[i][j]`` is the largest holding time over the places ``j -> i``
        with ``m`` initial tokens (``EPS`` if none), ``M`` the largest token
        count, so that for ``k > M``::

            x(k) = A0 ⊗ x(k) ⊕ A1 ⊗ x(k-1) ⊕ ... ⊕ AM ⊗ x(k-M)

        (``A[i][j]`` weighs the arc ``j -> i``, the :mod:`maxplus` convention).
        For ``k <= m_p`` the term of place ``p`` is its availability time
        ``a_p`` instead (spec §3), and an event without input place fires at
        0: :meth:`simulate` handles both, the matrices alone do not (two
        places ``j -> i`` with equal tokens but different ``a_p`` share one entry).

        Returns
        -------
        list of numpy.ndarray of dtype object
            Entries ``Fraction`` or ``EPS``, shape ``(n_transitions, n_transitions)``.

        Examples
        --------
        >>> g = TimedEventGraph(); _ = g.add_transition("a"); _ = g.add_transition("b")
        >>> _ = g.add_place("a", "b", holding=2); _ = g.add_place("b", "a", 1, 3)
        >>> [m.tolist() for m in g.state_equations()]
        [[[-inf, -inf], [Fraction(2, 1), -inf]], [[-inf, Fraction(3, 1)], [-inf, -inf]]]
        """
        n = self.n_transitions
        top = max(self._tokens, default=0)
        mats = [np.full((n, n), EPS, dtype=object) for _ in range(top + 1)]
        for p in self.places:
            mats[p.tokens][p.dst, p.src] = max(mats[p.tokens][p.dst, p.src], p.holding)
        return mats

    # ---------------------------------------------------------------- networkx
    def to_networkx(self) -> nx.MultiDiGraph:
        """A :class:`networkx.MultiDiGraph`: nodes are event names, one edge per place.

        Node attributes are :attr:`transition_attrs`; edge attributes are
        ``tokens``, ``holding``, ``initial`` (Fractions), ``kind``, ``name``,
        ``origin``; the edge key is the place index. ``G.graph`` holds
        ``name`` and :attr:`attrs`.

        Examples
        --------
        >>> g = TimedEventGraph(); _ = g.add_transition("a", role="x")
        >>> _ = g.add_place("a", "a", 1, 2)
        >>> G = g.to_networkx()
        >>> dict(G.nodes["a"]), G.edges["a", "a", 0]["holding"]
        ({'role': 'x'}, Fraction(2, 1))
        """
        import networkx as nx

        G = nx.MultiDiGraph()
        G.graph.update(copy.deepcopy(self.attrs))
        G.graph["name"] = self.name
        for name, attrs in zip(self._names, self.transition_attrs):
            G.add_node(name, **copy.deepcopy(attrs))
        for i, p in enumerate(self.places):
            G.add_edge(self._names[p.src], self._names[p.dst], key=i, tokens=p.tokens,
                       holding=p.holding, initial=p.initial, kind=p.kind, name=p.name,
                       origin=copy.deepcopy(p.origin))
        return G

    @classmethod
    def from_networkx(cls, G: nx.DiGraph) -> TimedEventGraph:
        """Build a TEG from a (Multi)DiGraph: nodes are events, edges places.

        Edge attributes ``tokens`` (default 0), ``holding`` and ``initial``
        (default 0; int, Fraction, str or float, read exactly), ``kind``,
        ``name``, ``origin`` are optional. Nodes that are not strings are
        named by ``str(node)``. When every edge key is a distinct int (as
        written by :meth:`to_networkx`), places are numbered by key.

        Examples
        --------
        >>> import networkx as nx
        >>> G = nx.DiGraph(); G.add_edge("a", "b", holding=0.1); G.add_edge("b", "a", tokens=1)
        >>> g = TimedEventGraph.from_networkx(G)
        >>> g.places[0].holding, g.places[1].tokens
        (Fraction(1, 10), 1)
        """
        teg = cls(name=str(G.graph.get("name", "teg")))
        teg.attrs = {k: copy.deepcopy(v) for k, v in G.graph.items() if k != "name"}
        index = {node: teg.add_transition(node if isinstance(node, str) else str(node),
                                          **copy.deepcopy(data))
                 for node, data in G.nodes(data=True)}
        if G.is_multigraph():
            edges = list(G.edges(keys=True, data=True))
            keys = [e[2] for e in edges]
            if all(type(k) is int for k in keys) and len(set(keys)) == len(keys):
                edges.sort(key=lambda e: e[2])
        else:
            edges = [(u, v, None, d) for u, v, d in G.edges(data=True)]
        for u, v, _, d in edges:
            teg.add_place(index[u], index[v], tokens=d.get("tokens", 0),
                          holding=d.get("holding", 0), initial=d.get("initial", 0),
                          kind=d.get("kind") or "", name=d.get("name"),
                          origin=copy.deepcopy(d.get("origin")))
        return teg

    # ---------------------------------------------------------------- dynamics
    def zero_token_order(self) -> list[np.ndarray]:
        """The 0-token places grouped by generation, for one firing index at a time.

        Generation g holds the 0-token places whose output event is at depth
        g >= 1 of the (acyclic) 0-token subgraph, so that the input events of
        the places of a generation are final once earlier ones are processed.

        Raises
        ------
        NotLiveError
            The 0-token subgraph has a circuit (named in the error): its
            events never fire.

        Examples
        --------
        >>> g = TimedEventGraph()
        >>> for e in "abc": _ = g.add_transition(e)
        >>> _ = g.add_place("b", "c"); _ = g.add_place("a", "b"); _ = g.add_place("c", "a", 1)
        >>> [gen.tolist() for gen in g.zero_token_order()]
        [[1], [0]]
        >>> _ = g.add_place("c", "b")
        >>> g.zero_token_order()
        Traceback (most recent call last):
        ...
        tegraph.errors.NotLiveError: circuit b -> c -> b carries no token: it never fires
        """
        if "order" in self._cache:
            return self._cache["order"]
        a = self.arrays()
        n = self.n_transitions
        zero = np.flatnonzero(a.tokens == 0)
        out: list[list[int]] = [[] for _ in range(n)]
        for p in zero.tolist():
            out[int(a.src[p])].append(p)
        waiting = np.bincount(a.dst[zero], minlength=n).tolist()
        depth = [0] * n
        frontier = [e for e in range(n) if waiting[e] == 0]
        done = 0
        while frontier:  # Kahn's algorithm, wave by wave: depth = longest 0-token path
            done += len(frontier)
            nxt = []
            for e in frontier:
                for p in out[e]:
                    d = int(a.dst[p])
                    depth[d] = max(depth[d], depth[e] + 1)
                    waiting[d] -= 1
                    if waiting[d] == 0:
                        nxt.append(d)
            frontier = nxt
        if done < n:
            self._raise_circuit(zero, [e for e in range(n) if waiting[e] > 0])
        gen = np.array(depth, dtype=np.int64)[a.dst[zero]]
        zero = zero[np.argsort(gen, kind="stable")]
        cuts = np.flatnonzero(np.diff(np.sort(gen))) + 1
        self._cache["order"] = [g for g in np.split(zero, cuts) if len(g)]
        return self._cache["order"]

    def _raise_circuit(self, zero: np.ndarray, stuck: list[int]) -> None:
        # Every stuck event has a stuck 0-token predecessor, so a circuit exists among them.
        import networkx as nx

        a, keep = self.arrays(), set(stuck)
        H = nx.DiGraph()
        H.add_edges_from((int(a.src[p]), int(a.dst[p])) for p in zero.tolist()
                         if int(a.src[p]) in keep and int(a.dst[p]) in keep)
        loops = sorted(nx.nodes_with_selfloops(H))
        circuit = loops[:1] or [u for u, _ in nx.find_cycle(H)]  # a self-loop is the shortest
        raise NotLiveError([self._names[u] for u in circuit])

    def simulate(self, n_firings: int) -> Daters:
        """Earliest firing times ``x_e(k)``, ``1 <= k <= n_firings`` (spec §3), exactly.

        ``x_e(k)`` is the max over the places p into e of
        ``x_src(p)(k - m_p) + h_p`` when ``k > m_p``, else ``a_p``. An event
        with no input place is never held back: it fires at 0 for every k.
        Each firing index costs O(places): places with tokens look back at
        earlier indices (one vectorized pass), 0-token places are taken in
        the generations of :meth:`zero_token_order`.

        Raises
        ------
        NotLiveError
            Some circuit of 0-token places never fires.

        Examples
        --------
        >>> g = TimedEventGraph(); _ = g.add_transition("a"); _ = g.add_transition("b")
        >>> _ = g.add_place("a", "b", holding="1/2"); _ = g.add_place("b", "a", 1, 1)
        >>> d = g.simulate(3)
        >>> [str(t) for t in d["a"]], [str(t) for t in d["b"]]
        (['0', '3/2', '3'], ['1/2', '2', '7/2'])
        """
        if isinstance(n_firings, bool) or not isinstance(n_firings, Integral) or n_firings < 0:
            raise InputError(f"expected an int >= 0, got {n_firings!r}", "n_firings")
        n_firings = int(n_firings)
        order = self.zero_token_order()
        a = self.arrays()
        n = self.n_transitions
        hold, init = a.holding, a.initial
        # Any x_e(k) is at most max a_p + k * sum h_p (each index level crosses each place once).
        bound = max((abs(int(v)) for v in init.tolist()), default=0) \
            + n_firings * sum(int(v) for v in hold.tolist())
        if bound < INT64_SAFE and hold.dtype != object and init.dtype != object:
            dtype, low = np.int64, np.iinfo(np.int64).min
        else:
            dtype, low = object, EPS
            hold, init = hold.astype(object), init.astype(object)
        times = np.zeros((n_firings, n), dtype=dtype)
        has_input = np.zeros(n, dtype=bool)
        has_input[a.dst] = True
        tp = np.flatnonzero(a.tokens > 0)
        t_src, t_dst, t_tok, t_hold, t_init = a.src[tp], a.dst[tp], a.tokens[tp], hold[tp], init[tp]
        gens = [(a.src[g], a.dst[g], hold[g]) for g in order]
        for k in range(1, n_firings + 1):
            row = np.full(n, low, dtype=dtype)
            row[~has_input] = 0
            if len(tp):
                back = k - t_tok  # the firing of src(p) whose token p hands over
                vals = t_init.copy()
                ready = np.flatnonzero(back >= 1)
                vals[ready] = times[back[ready] - 1, t_src[ready]] + t_hold[ready]
                np.maximum.at(row, t_dst, vals)
            for g_src, g_dst, g_hold in gens:
                np.maximum.at(row, g_dst, row[g_src] + g_hold)
            times[k - 1] = row
        return Daters(times, a.scale, self.transition_names)


def _trusted(index: dict[str, int], src: Any, dst: Any, tokens: Any, holding: Any,
             initial: Any) -> bool:
    """Whether a place needs none of :meth:`TimedEventGraph.add_place`'s checks, nor the
    words of their errors: the builder's own (events by name, exact times, counts in range)."""
    return (type(src) is str and type(dst) is str and src in index and dst in index
            and type(tokens) is int and 0 <= tokens <= MAX_COUNT
            and type(holding) is Fraction and holding.numerator >= 0
            and type(initial) is Fraction and initial.numerator >= 0)


def _within(values: np.ndarray, low: int, high: int) -> bool:
    """Whether every value lies in ``low..high`` (True when there is none)."""
    return not len(values) or (int(values.min()) >= low and int(values.max()) <= high)


def _scaled(times: list[Fraction], scales: list[int]) -> np.ndarray:
    """``times[i] * scales[i]`` for scales that the times' denominators divide, exactly,
    as :func:`int_array` makes it (int64 when every value is below 2**62, else objects).

    >>> _scaled([Fraction(1, 2), Fraction(3)], [4, 4]).tolist()
    [2, 12]
    >>> _scaled([Fraction(1, 2), Fraction(3)], [2**70, 2**70]).dtype
    dtype('O')
    >>> _scaled([Fraction(0)], [2**70]).tolist(), _scaled([], []).dtype
    ([0], dtype('int64'))
    """
    nums = [t.numerator for t in times]
    dens = [t.denominator for t in times]
    # The scales themselves must fit too (all times 0 under a scale past int64).
    largest = max(max(map(abs, nums), default=1), 1) * max(max(scales, default=1), 1)
    if largest < INT64_SAFE:  # every product below 2**62: int64 arithmetic is exact
        return (np.array(nums, dtype=np.int64)
                * (np.array(scales, dtype=np.int64) // np.array(dens, dtype=np.int64)))
    return int_array([n * (k // d) for n, d, k in zip(nums, dens, scales)])


class TimeCodes(NamedTuple):
    """A column of times as each entry's index in a table of distinct times.

    Attributes
    ----------
    values : sequence of Fraction
        The distinct times (a built graph's places share a few: 0, each task's
        duration, each clock's period and phase).
    codes : array_like of int
        Each entry's index in ``values``.
    """

    values: Sequence[Fraction]
    codes: Sequence[int] | np.ndarray


class _TimeColumn:
    """A column of times (Fractions) held as :class:`TimeCodes`: a table of the distinct
    values, and each place's index in it.

    Scaling each distinct value once, then indexing, costs an array lookup a place
    instead of a Fraction's numerator and denominator. Places added one by one
    share the slot of an equal value (told apart by value, not by object, so a
    copy or a pickle keeps it sound).
    """

    def __init__(self) -> None:
        self.values: list[Fraction] = []
        self.codes: list[int] = []
        self._slot: dict[Fraction, int] | None = {}  # None: not made yet (see extend)

    def append(self, t: Fraction) -> None:
        """Add one entry."""
        if self._slot is None:
            self._slot = {}
            for k, v in enumerate(self.values):
                self._slot.setdefault(v, k)
        slot = self._slot.get(t)
        if slot is None:
            slot = self._slot[t] = len(self.values)
            self.values.append(t)
        self.codes.append(slot)

    def extend(self, column: TimeCodes) -> None:
        """Add the entries of ``column``."""
        # Its table is appended as it is: a value may then have two slots, which
        # changes nothing (each slot is scaled alike), and hashing the Fractions
        # of 10,000 durations would cost more than the whole column.
        first = len(self.values)
        self.values.extend(column.values)
        codes = np.asarray(column.codes, dtype=np.int64)
        self.codes.extend((codes + first).tolist() if first else codes.tolist())
        self._slot = None

    def __getitem__(self, index: int) -> Fraction:
        return self.values[self.codes[index]]

    def objects(self) -> list[Fraction]:
        """Every entry's time, in order."""
        values = self.values
        return [values[k] for k in self.codes]

    def scaled(self, scale: int) -> np.ndarray:
        """``t * scale`` for each time of the column, as :func:`int_array` makes it.

        int64 or object as the distinct values need (as for the whole column).
        """
        return _scaled(self.values, [scale] * len(self.values))[
            np.asarray(self.codes, dtype=np.int64)]


def _check_tokens(value: Any, where: str) -> int:
    if type(value) is int and 0 <= value <= MAX_COUNT:  # the builder's own counts: no ABC checks
        return value
    if isinstance(value, bool) or not isinstance(value, (Integral, Rational, float)):
        raise ModelError(f"tokens must be an integer >= 0, got {value!r}", where)
    if isinstance(value, float) and not math.isfinite(value):
        raise ModelError(f"tokens must be an integer >= 0, got {value!r}", where)
    # numbers.Rational declares no __int__ in typeshed; Fraction and the numeric types
    # users pass (numpy, sympy) all have one.
    whole = int(value)  # type: ignore[arg-type]
    if value != whole or value < 0:
        raise ModelError(f"tokens must be an integer >= 0, got {value!r}", where)
    why = count_problem(whole, "tokens")  # held in int64 arrays (MAX_COUNT)
    if why is not None:
        raise ModelError(why, where)
    return whole


def _check_time(value: Any, what: str, where: str) -> Fraction:
    kind = type(value)
    if kind is Fraction or kind is int:  # the builder's own values: no parsing needed
        t = Fraction(value) if kind is int else value
        if t < 0:
            raise ModelError(f"{what} must be >= 0, got {written(t)}", where)
        return t
    why = size_problem(value)  # "1e999999999" would take hours to expand
    if why is not None:
        raise ModelError(f"{what} must be a time: {why}", where)
    try:
        t = exact_time(value, what)
    except MaxPlusValueError as exc:
        raise ModelError(str(exc), where) from None
    if t < 0:
        raise ModelError(f"{what} must be >= 0, got {written(t, value)}", where)
    return t
