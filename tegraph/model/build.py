"""Build the timed event graph of a synchronization skeleton (spec §2).

Numbering (stable, so that tests and reports can rely on it):

* events: one ``C.tick`` per clock, in the order of ``skeleton.clocks``; then
  the chain events of every task in file order, each created when first met
  (a SYN/SYN rendezvous is created by whichever of its tasks comes first);
* places: the clock self-loops; then, task by task, the activation place
  ``C.tick -> T.activate``, the chain places in chain order and the return
  place; then the link places in link order; then the thread places.

Provenance
----------
``teg.transition_attrs[e]`` is a dict with the keys

* ``role``: ``"tick"``, ``"activate"``, ``"read"``, ``"compute"``,
  ``"write"``, or ``"rendezvous"`` (a SYN/SYN write merged with its reads);
* ``tasks``: tuple of the tasks whose chain holds the event, in file order
  (two or more for a rendezvous, none for a tick);
* ``ports``: tuple of ``(task, port)`` pairs the event stands for: the
  writer's port first, then every SYN/SYN reader's port (empty for
  tick/activate/compute);
* ``clock``: the clock of a tick or of an activation, else None.

``Place.origin`` is a dict: ``{"task": T}`` for ``chain`` and ``return``
places, ``{"clock": C}`` for ``clock``, ``{"clock": C, "task": T}`` for
``activation``, ``{"link": label, "link_index": i}`` for ``asyn-syn`` and
``syn-asyn``, ``{"thread": i, "from": Ti, "to": Tj}`` for ``thread`` and
``thread-return``.

``teg.attrs`` holds ``"chains"`` (task -> tuple of event indices, in chain
order), ``"compute"`` (task -> index of ``T.compute``), ``"clocks"`` (clock
-> index of ``C.tick``) and ``"unit"``; read them with :func:`task_chain`,
:func:`first_event`, :func:`last_event`, :func:`compute_events`.

Two typed records are the one definition of what spec §2 and §4 say about
times; read them with :func:`holding_sources` and :func:`activation_end`
(they survive :meth:`~TimedEventGraph.to_networkx` and back, like the chains):

* the :class:`HoldingSource` of every place, in place order: the parameter its
  holding time *is*: the duration of task T (every place leaving ``T.compute``),
  the period of clock C (the self-loop of ``C.tick``), the delay of a link
  (``"delay"``: the place of an ASYN/SYN or SYN/ASYN link that declares its own
  ``delay``, spec §4d), the network's delay (``"network-delay"``: the place of
  such a link that declares none, between two processors, when ``network.delay``
  is declared), or ``"none"`` (every other place holds 0: a delay is a parameter of
  a place where the file declares it, so a skeleton without the keys builds the
  graph it always did). Each holding is computed from its source
  (:meth:`HoldingSource.value`), so the two cannot disagree;
* the :class:`ActivationEnd` of every task (spec §4, ``overrun_at``): the event
  whose k-th firing ends its k-th activation, its last write, and, for a task
  without outputs, whether the duration is added after it: the activation then
  ends at ``x_T.compute(k) + duration(T)``.

A task of duration 3 with an output on a clock c of period 2: the clock's
self-loop holds 2 (period of c), the place leaving ``T.compute`` holds 3
(duration of T), the others 0; an activation ends with its write:

>>> from fractions import Fraction as F
>>> from tegraph.model.skeleton import Clock, Task
>>> sk = Skeleton("s", {"T": Task("T", F(3), clock="c", outputs=("o",))},
...               {"c": Clock("c", F(2))})
>>> g = build_teg(sk)
>>> [(p.name, str(p.holding), s.kind, s.owner) for p, s in zip(g.places, holding_sources(g))]
... # doctest: +NORMALIZE_WHITESPACE
[('c.tick -> c.tick', '2', 'period', 'c'), ('c.tick -> T.activate', '0', 'none', ''),
 ('T.activate -> T.compute', '0', 'none', ''),
 ('T.compute -> T.write:o', '3', 'duration', 'T'),
 ('T.write:o -> T.activate', '0', 'none', '')]
>>> end = activation_end(g, "T")
>>> g.transition_names[end.event], end.adds_duration, end.offset
('T.write:o', False, Fraction(0, 1))

Without the output, the activation ends 3 after ``T.compute``:

>>> sk = Skeleton("s", {"T": Task("T", F(3), clock="c")}, {"c": Clock("c", F(2))})
>>> g = build_teg(sk)
>>> end = activation_end(g, "T")
>>> g.transition_names[end.event], end.adds_duration, end.offset
('T.compute', True, Fraction(3, 1))
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Literal, NamedTuple, TypeAlias

import numpy as np

from ..errors import ModelError
from .elements import link_name
from .platform import crosses, link_delay
from .skeleton import Link, Protocol, Skeleton
from .teg import TimeCodes, TimedEventGraph

__all__ = [
    "PLACE_KINDS",
    "ActivationEnd",
    "UnboundedKind",
    "HoldingSource",
    "activation_end",
    "build_teg",
    "compute_events",
    "delay_source",
    "first_event",
    "holding_sources",
    "last_event",
    "link_ports",
    "task_chain",
    "unbounded_kind",
]

PLACE_KINDS = ("chain", "return", "clock", "activation", "asyn-syn", "syn-asyn",
               "thread", "thread-return")
"""Every ``Place.kind`` that :func:`build_teg` produces."""

UnboundedKind: TypeAlias = Literal["clock-overrun", "messages-overwritten",
                                  "requests-overwritten", "thread", "chain"]
"""What an unbounded place is, as reports name it (spec §4)."""

_UNBOUNDED: dict[str, UnboundedKind] = {
    "activation": "clock-overrun", "asyn-syn": "messages-overwritten",
    "syn-asyn": "requests-overwritten", "thread": "thread", "thread-return": "thread"}


def unbounded_kind(place_kind: str) -> UnboundedKind:
    """What an unbounded place of this :data:`PLACE_KINDS` kind is, as reports name it.

    >>> unbounded_kind("activation"), unbounded_kind("return")
    ('clock-overrun', 'chain')
    """
    return _UNBOUNDED.get(place_kind, "chain")


@dataclass(frozen=True)
class HoldingSource:
    """The parameter a place's holding time is (spec §2).

    Attributes
    ----------
    kind : {"duration", "period", "delay", "network-delay", "none"}
        The duration of a task, the period of a clock, the declared delay of a link,
        the network's delay (§4d), or none: the place holds 0.
    owner : str
        The task (``"duration"``), the clock (``"period"``), the link's ports
        ``"W:p -> R:q"`` (``"delay"``: an input port has one writer, so they name one
        link, whatever its protocol); ``""`` otherwise.
    """

    kind: Literal["duration", "period", "delay", "network-delay", "none"]
    owner: str = ""

    def value(self, skeleton: Skeleton) -> Fraction:
        """The holding time it gives in ``skeleton``.

        >>> from tegraph.model.skeleton import Task
        >>> sk = Skeleton("s", {"T": Task("T", Fraction(3))})
        >>> HoldingSource("duration", "T").value(sk), HoldingSource("none").value(sk)
        (Fraction(3, 1), Fraction(0, 1))
        """
        if self.kind == "duration":
            return skeleton.tasks[self.owner].duration
        if self.kind == "period":
            return skeleton.clocks[self.owner].period
        if self.kind == "delay":
            link = next(x for x in skeleton.links if link_ports(x) == self.owner)
            return link.delay if link.delay is not None else _ZERO
        if self.kind == "network-delay":
            return skeleton.network_delay if skeleton.network_delay is not None else _ZERO
        return _ZERO


def link_ports(link: Link) -> str:
    """``"W:p -> R:q"``: the owner of a link's delay (:class:`HoldingSource`).

    >>> link_ports(Link(("A", "x"), ("B", "y"), Protocol.ASYN_SYN))
    'A:x -> B:y'
    """
    return link_name(link.writer, link.reader)


def delay_source(skeleton: Skeleton, link: Link) -> HoldingSource:
    """The parameter a link's place holds (§4d): its own delay where it declares one,
    else the network's between two processors where ``network.delay`` is declared,
    else none (the place holds 0). Its value is
    :func:`~tegraph.model.platform.link_delay`."""
    if link.delay is not None:
        return HoldingSource("delay", link_ports(link))
    if skeleton.network_delay is not None and crosses(skeleton, link):
        return _NETWORK
    return _NO_PARAMETER


_ZERO = Fraction(0)  # one object for every place that holds 0 (most of them)
_NO_PARAMETER = HoldingSource("none")
_NETWORK = HoldingSource("network-delay")


@dataclass(frozen=True)
class ActivationEnd:
    """When the k-th activation of a task ends (spec §4, ``overrun_at``).

    At ``x_event(k) + offset``.

    Attributes
    ----------
    event : int
        The task's last event: its last write, or ``T.compute`` without outputs.
    adds_duration : bool
        True for a task without outputs: the activation ends when its
        computation does, ``duration(T)`` after ``T.compute`` fires.
    offset : Fraction
        ``duration(T)`` if ``adds_duration``, else 0.
    """

    event: int
    adds_duration: bool
    offset: Fraction


def build_teg(skeleton: Skeleton) -> TimedEventGraph:
    """The timed event graph of a skeleton, exactly per spec §2.

    Parameters
    ----------
    skeleton : Skeleton
        Assumed valid (:meth:`Skeleton.validate`); a dangling reference
        (unknown task, clock or port) still raises :class:`ModelError`.

    Returns
    -------
    TimedEventGraph
        With the provenance described in the module docstring.

    Raises
    ------
    ModelError
        A dangling reference: an unknown task, clock or port.

    See Also
    --------
    tegraph.model.skeleton.Skeleton.validate : the rules assumed here.
    tegraph.cycle_time : the period of the graph built.
    tegraph.analyze : the full analysis of the skeleton.

    Notes
    -----
    The Petri net model of periodic module tasks and their synchronizations
    is that of section 3 of the ORCCAD paper [1]_; every place has one input
    and one output transition, so the net is a timed event graph, linear in
    the (max,+) algebra [2]_.

    References
    ----------
    .. [1] D. Simon et al., "Design and analysis of synchronization for
       real-time closed-loop control in robotics", IEEE Transactions on Control
       Systems Technology, 1998.
    .. [2] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992.

    Examples
    --------
    A task of duration 3 activated by a clock of period 4 and phase 1:

    >>> from fractions import Fraction as F
    >>> from tegraph.model.skeleton import Clock, Task
    >>> sk = Skeleton("s", {"T": Task("T", F(3), clock="c")}, {"c": Clock("c", F(4), F(1))})
    >>> g = build_teg(sk)
    >>> g.transition_names
    ('c.tick', 'T.activate', 'T.compute')
    >>> [(g.transition_names[p.src], p.tokens, str(p.holding), p.kind) for p in g.places]
    ... # doctest: +NORMALIZE_WHITESPACE
    [('c.tick', 1, '4', 'clock'), ('c.tick', 0, '0', 'activation'),
     ('T.activate', 0, '0', 'chain'), ('T.compute', 1, '3', 'return')]
    >>> [str(t) for t in g.simulate(3)["T.compute"]]
    ['1', '5', '9']
    """
    _check_references(skeleton)
    teg = TimedEventGraph(skeleton.name)
    teg.attrs["unit"] = skeleton.unit
    events = _Events(skeleton)
    teg.add_transitions(events.names, events.attrs)
    places = _Places(skeleton, events)
    teg.add_place_columns(places.src, places.dst, places.tokens,
                          TimeCodes(places.holding_times, places.holding),
                          TimeCodes(places.initial_times, places.initial), places.kind,
                          places.origin)
    tasks = skeleton.tasks
    chains = events.chains
    teg.attrs["chains"] = chains
    teg.attrs["compute"] = events.compute
    teg.attrs["clocks"] = {c: i for i, c in enumerate(skeleton.clocks)}
    teg.attrs["holding_source"] = tuple(places.sources)
    # The activation ends with the last event of the chain: the last write, or
    # T.compute without outputs, and then only when the computation ends (spec §4).
    teg.attrs["activation_end"] = {
        t: ActivationEnd(chain[-1], not tasks[t].outputs,
                         _ZERO if tasks[t].outputs else tasks[t].duration)
        for t, chain in chains.items()}
    return teg


class _Events:
    """The events of the graph, numbered as the module docstring says, and their provenance.

    Attributes
    ----------
    names : list of str
    attrs : list of dict
        ``teg.transition_attrs``, in event order.
    chains : dict
        Task -> tuple of its chain's event indices.
    compute : dict
        Task -> index of ``T.compute``.
    """

    def __init__(self, skeleton: Skeleton) -> None:
        # A SYN/SYN read is the writer's event: one event on both chains (a rendezvous).
        merged = {link.reader: f"{link.writer[0]}.write:{link.writer[1]}"
                  for link in skeleton.links if link.protocol is Protocol.SYN_SYN}
        writer = {merged[link.reader]: link.writer for link in skeleton.links
                  if link.protocol is Protocol.SYN_SYN}
        self.names = [f"{c}.tick" for c in skeleton.clocks]
        self.attrs: list[dict[str, Any]] = [
            {"role": "tick", "tasks": (), "ports": (), "clock": c} for c in skeleton.clocks]
        self.index = {name: i for i, name in enumerate(self.names)}
        self._ticks = len(self.names)
        # A rendezvous' owners (file order) and ports (the writer's, then the readers'
        # in file and port order), completed once every chain is known.
        self._owners: dict[int, list[str]] = {}
        self._ports: dict[int, list[tuple[str, str]]] = {}
        self.chains: dict[str, tuple[int, ...]] = {}
        self.compute: dict[str, int] = {}
        for name, task in skeleton.tasks.items():
            own = (name,)
            chain = []
            if task.clock is not None:
                chain.append(self._new(f"{name}.activate", "activate", own, (), task.clock))
            for q in task.inputs:
                ev = merged.get((name, q))
                chain.append(self._new(f"{name}.read:{q}", "read", own, ((name, q),), None)
                             if ev is None else self._shared(ev, "read", name, (name, q)))
            compute = self.compute[name] = self._new(f"{name}.compute", "compute", own, (), None)
            chain.append(compute)
            for p in task.outputs:
                ev = f"{name}.write:{p}"
                chain.append(self._shared(ev, "write", name, None) if ev in writer
                             else self._new(ev, "write", own, ((name, p),), None))
            self.chains[name] = tuple(chain)
        for e, owners in self._owners.items():
            ports = (writer[self.names[e]], *self._ports[e])
            attrs = self.attrs[e]
            attrs["tasks"], attrs["ports"] = tuple(owners), ports
            if len(ports) > 1:
                attrs["role"] = "rendezvous"

    def _new(self, name: str, role: str, tasks: tuple[str, ...],
             ports: tuple[tuple[str, str], ...], clock: str | None) -> int:
        """A new event of one task's chain."""
        e = self.index.setdefault(name, len(self.names))
        if e < len(self.names):
            self._met_again(name, e)
            return e
        self.names.append(name)
        self.attrs.append({"role": role, "tasks": tasks, "ports": ports, "clock": clock})
        return e

    def _shared(self, name: str, role: str, task: str, port: tuple[str, str] | None) -> int:
        """The event of a SYN/SYN link, made by the first task that meets it."""
        e = self.index.get(name)
        if e is None:
            e = self._new(name, role, (), (), None)
            self._owners[e], self._ports[e] = [], []
        owners = self._owners[e]
        if task not in owners:
            owners.append(task)
        if port is not None:
            self._ports[e].append(port)
        return e

    def _met_again(self, name: str, e: int) -> None:
        """An event name made twice: a clock's tick is refused as a duplicate event; a
        task's event is that one event (names with ':', which validation refuses, can
        name two events alike: the first one's attributes stay)."""
        if e < self._ticks:
            raise ModelError("duplicate event name", name)


class _Places:
    """The places of the graph as columns, in the order of the module docstring, with
    each one's holding source (:class:`HoldingSource`).

    Times are indices in ``holding_times`` (0, each clock's period, each task's
    duration) and ``initial_times`` (0, each clock's phase). The tasks' places (most
    of them: a chain place per event) are laid out by array arithmetic over all
    chains at once, not one by one.
    """

    def __init__(self, skeleton: Skeleton, events: _Events) -> None:
        clocks, tasks = skeleton.clocks, skeleton.tasks
        n_clocks = len(clocks)
        self.holding_times: list[Fraction] = [_ZERO, *(c.period for c in clocks.values()),
                                              *(t.duration for t in tasks.values())]
        self.initial_times: list[Fraction] = [_ZERO, *(c.phase for c in clocks.values())]
        # The clocks' self-loops, one token each, available at the phase.
        first_clock = np.arange(1, n_clocks + 1)
        parts = [_Section(np.arange(n_clocks), np.arange(n_clocks), np.ones(n_clocks, np.int64),
                          first_clock, first_clock, ["clock"] * n_clocks,
                          [{"clock": c} for c in clocks],
                          [HoldingSource("period", c) for c in clocks]),
                 self._tasks(skeleton, events, n_clocks + 1),
                 self._links(skeleton, events.index, self.holding_times),
                 self._threads(skeleton, events)]
        self.src, self.dst, self.tokens, self.holding, self.initial = (
            np.concatenate([getattr(part, f) for part in parts]).astype(np.int64)
            for f in ("src", "dst", "tokens", "holding", "initial"))
        self.kind = [k for part in parts for k in part.kind]
        self.origin = [o for part in parts for o in part.origin]
        self.sources = [h for part in parts for h in part.sources]

    @staticmethod
    def _tasks(skeleton: Skeleton, events: _Events, first_duration: int) -> _Section:
        """Task by task: the activation place (clocked tasks), the chain places in
        chain order, the return place (the last event back to the first, one token);
        the place leaving ``T.compute`` holds ``duration(T)``."""
        tasks = list(skeleton.tasks.values())
        chains = list(events.chains.values())
        n = len(tasks)
        length = np.fromiter(map(len, chains), dtype=np.int64, count=n)
        flat = np.fromiter(itertools.chain.from_iterable(chains), dtype=np.int64,
                           count=int(length.sum()))
        clocked = np.fromiter((t.clock is not None for t in tasks), dtype=bool, count=n)
        reads = np.fromiter((len(t.inputs) for t in tasks), dtype=np.int64, count=n)
        size = length + clocked  # places of each task
        start = np.cumsum(size) - size  # its first place
        first = np.cumsum(length) - length  # its first event in flat
        total = int(size.sum())
        src, dst = np.empty(total, np.int64), np.empty(total, np.int64)
        kind = np.ones(total, np.int64)  # _TASK_KINDS
        activation = start[clocked]
        # Chain place j of a task leaves its j-th event for the next one, the last
        # (the return place) for the first: every place but the activations, in order.
        chain = np.ones(total, dtype=bool)
        chain[activation] = False
        chain_at = np.flatnonzero(chain)
        following = np.arange(1, len(flat) + 1)
        following[first + length - 1] = first
        src[chain_at], dst[chain_at] = flat, flat[following]
        returns = start + clocked + length - 1
        tokens = np.zeros(total, np.int64)
        tokens[returns], kind[returns] = 1, 2
        tick = {c: i for i, c in enumerate(skeleton.clocks)}
        src[activation] = np.fromiter((tick[t.clock] for t in tasks if t.clock is not None),
                                      dtype=np.int64, count=len(activation))
        dst[activation], kind[activation] = flat[first[clocked]], 0
        # T.compute comes after the activation and the reads: the place leaving it.
        leaving = start + clocked + clocked + reads
        holding = np.zeros(total, np.int64)
        holding[leaving] = first_duration + np.arange(n)
        sources = np.full(total, _NO_PARAMETER, dtype=object)
        sources[leaving] = _objects([HoldingSource("duration", t.name) for t in tasks])
        # One origin for a task's chain and return places: origins are read-only
        # (Place.origin), and a dict a place would hold tens of megabytes at 100,000 tasks.
        origin = np.empty(total, dtype=object)
        origin[chain_at] = np.repeat(_objects([{"task": t.name} for t in tasks]), length)
        origin[activation] = _objects([{"clock": t.clock, "task": t.name}
                                       for t in tasks if t.clock is not None])
        return _Section(src, dst, tokens, holding, np.zeros(total, np.int64),
                        _TASK_KINDS[kind].tolist(), origin.tolist(), sources.tolist())

    @staticmethod
    def _links(skeleton: Skeleton, index: dict[str, int], holding_times: list[Fraction]
               ) -> _Section:
        """The place of each ASYN/SYN and SYN/ASYN link (spec §2), holding the link's
        delay (§4d: the message, or the request, travels), a new entry of
        ``holding_times`` for each delay that is not 0."""
        src, dst, kind, origin = [], [], [], []
        holding: list[int] = []
        sources: list[HoldingSource] = []
        for i, link in enumerate(skeleton.links):
            w = f"{link.writer[0]}.write:{link.writer[1]}"
            r = f"{link.reader[0]}.read:{link.reader[1]}"
            if link.protocol is Protocol.ASYN_SYN:
                src.append(_event(index, w, r, w))
                dst.append(_event(index, w, r, r))
                kind.append("asyn-syn")
            elif link.protocol is Protocol.SYN_ASYN:
                src.append(_event(index, r, w, r))
                dst.append(_event(index, r, w, w))
                kind.append("syn-asyn")
            else:  # ASYN/ASYN: no place; SYN/SYN: already one event on both chains.
                continue
            origin.append({"link": link.label, "link_index": i})
            source = delay_source(skeleton, link)
            sources.append(source)
            delay = _ZERO if source is _NO_PARAMETER else link_delay(skeleton, link)
            if delay:
                holding_times.append(delay)
                holding.append(len(holding_times) - 1)
            else:
                holding.append(0)
        n = len(src)
        zeros = np.zeros(n, np.int64)
        return _Section(np.array(src, np.int64), np.array(dst, np.int64), zeros,
                        np.array(holding, np.int64), zeros, kind, origin, sources)

    @staticmethod
    def _threads(skeleton: Skeleton, events: _Events) -> _Section:
        """Each thread's places: one task's last event to the next one's first, the
        return to the first task holding the token."""
        chains, compute = events.chains, events.compute
        first_duration = len(skeleton.clocks) + 1  # _Places.holding_times
        duration = ({t: first_duration + k for k, t in enumerate(skeleton.tasks)}
                    if skeleton.threads else {})
        rows = []
        for i, thread in enumerate(skeleton.threads):
            for j, name in enumerate(thread):
                nxt, last = thread[(j + 1) % len(thread)], j == len(thread) - 1
                end = chains[name][-1]
                leaves_compute = end == compute[name]
                rows.append((end, chains[nxt][0], 1 if last else 0,
                             duration[name] if leaves_compute else 0,
                             "thread-return" if last else "thread",
                             {"thread": i, "from": name, "to": nxt},
                             HoldingSource("duration", name) if leaves_compute
                             else _NO_PARAMETER))
        src, dst, tokens, holding, kind, origin, sources = (
            [list(column) for column in zip(*rows)] if rows else [[] for _ in range(7)])
        return _Section(np.array(src, np.int64), np.array(dst, np.int64),
                        np.array(tokens, np.int64), np.array(holding, np.int64),
                        np.zeros(len(rows), np.int64), kind, origin, sources)


class _Section(NamedTuple):
    """Consecutive places as columns (:class:`_Places`)."""

    src: np.ndarray
    dst: np.ndarray
    tokens: np.ndarray
    holding: np.ndarray
    initial: np.ndarray
    kind: list[str]
    origin: list[Any]
    sources: list[HoldingSource]


_TASK_KINDS = np.array(["activation", "chain", "return"], dtype=object)


def _objects(values: list[Any]) -> np.ndarray:
    """An object array of ``values`` (dicts and dataclasses kept as objects)."""
    out = np.empty(len(values), dtype=object)
    out[:] = values
    return out


def _event(index: dict[str, int], src: str, dst: str, name: str) -> int:
    """The event called ``name``, an end of the place ``src -> dst``."""
    if name not in index:
        raise ModelError(f"unknown event {name!r}", f"place {src} -> {dst}")
    return index[name]


def _check_references(skeleton: Skeleton) -> None:
    """Refuse dangling names, which would otherwise create stray events."""
    tasks = skeleton.tasks
    for t in tasks.values():
        if t.clock is not None and t.clock not in skeleton.clocks:
            raise ModelError(f"unknown clock {t.clock!r}", f"task {t.name}")
    for i, link in enumerate(skeleton.links):
        (w, p), (r, q) = link.writer, link.reader
        if w not in tasks or p not in tasks[w].outputs:
            raise ModelError(f"unknown output port {w}:{p}", f"links[{i}]")
        if r not in tasks or q not in tasks[r].inputs:
            raise ModelError(f"unknown input port {r}:{q}", f"links[{i}]")
    for i, thread in enumerate(skeleton.threads):
        for name in thread:
            if name not in tasks:
                raise ModelError(f"unknown task {name!r}", f"threads[{i}]")


# ------------------------------------------------------------- chain helpers
def _record(teg: TimedEventGraph, key: str) -> Any:
    if key not in teg.attrs:
        raise ModelError(f"not built from a skeleton (no {key!r} in attrs)", teg.name)
    return teg.attrs[key]


def _chains(teg: TimedEventGraph) -> dict[str, tuple[int, ...]]:
    chains: dict[str, tuple[int, ...]] = _record(teg, "chains")
    return chains


def task_chain(teg: TimedEventGraph, task: str) -> list[int]:
    """Event indices of the chain of ``task``, in chain order.

    Examples
    --------
    >>> from fractions import Fraction as F
    >>> from tegraph.model.skeleton import Task
    >>> g = build_teg(Skeleton("s", {"A": Task("A", F(1), inputs=("i",), outputs=("o",))}))
    >>> [g.transition_names[e] for e in task_chain(g, "A")]
    ['A.read:i', 'A.compute', 'A.write:o']
    >>> first_event(g, "A"), last_event(g, "A"), compute_events(g)
    (0, 2, {'A': 1})
    """
    chains = _chains(teg)
    if task not in chains:
        raise ModelError("unknown task", task)
    return list(chains[task])


def first_event(teg: TimedEventGraph, task: str) -> int:
    """Index of the first event of the chain of ``task``."""
    return task_chain(teg, task)[0]


def last_event(teg: TimedEventGraph, task: str) -> int:
    """Index of the last event of the chain of ``task``."""
    return task_chain(teg, task)[-1]


def compute_events(teg: TimedEventGraph) -> dict[str, int]:
    """Task -> index of its ``T.compute`` event, in file order."""
    _chains(teg)
    return dict(teg.attrs["compute"])


def holding_sources(teg: TimedEventGraph) -> tuple[HoldingSource, ...]:
    """The parameter each place's holding time is, in place order (module docstring).

    Raises
    ------
    ModelError
        ``teg`` was not built by :func:`build_teg`.
    """
    sources: tuple[HoldingSource, ...] = _record(teg, "holding_source")
    return sources


def activation_end(teg: TimedEventGraph, task: str) -> ActivationEnd:
    """When each activation of ``task`` ends (module docstring).

    Raises
    ------
    ModelError
        An unknown task, or ``teg`` was not built by :func:`build_teg`.
    """
    ends: dict[str, ActivationEnd] = _record(teg, "activation_end")
    if task not in ends:
        raise ModelError("unknown task", task)
    return ends[task]

