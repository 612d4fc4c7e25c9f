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
  the period of clock C (the self-loop of ``C.tick``), or ``"none"`` (every
  other place holds 0). Each holding is computed from its source
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

from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Literal, TypeAlias

import numpy as np

from ..errors import ModelError
from .skeleton import Protocol, Skeleton, Task
from .teg import TimeCodes, TimedEventGraph

__all__ = [
    "PLACE_KINDS",
    "ActivationEnd",
    "UnboundedKind",
    "HoldingSource",
    "activation_end",
    "build_teg",
    "compute_events",
    "first_event",
    "holding_sources",
    "last_event",
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
    kind : {"duration", "period", "none"}
        The duration of a task, the period of a clock, or none: the place holds 0.
    owner : str
        The task (``"duration"``) or the clock (``"period"``); ``""`` for none.
    """

    kind: Literal["duration", "period", "none"]
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
        return _ZERO


_ZERO = Fraction(0)  # one object for every place that holds 0 (most of them)
_NO_PARAMETER = HoldingSource("none")


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
    teg.add_place_columns(np.array(places.src, dtype=np.int64),
                          np.array(places.dst, dtype=np.int64),
                          np.array(places.tokens, dtype=np.int64),
                          TimeCodes(places.times, places.holding),
                          TimeCodes(places.times, places.initial), places.kind, places.origin)
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

    Times are indices in ``times``, the few distinct times of the skeleton (0,
    each task's duration, each clock's period and phase).
    """

    def __init__(self, skeleton: Skeleton, events: _Events) -> None:
        self.src: list[int] = []
        self.dst: list[int] = []
        self.tokens: list[int] = []
        self.holding: list[int] = []
        self.initial: list[int] = []
        self.kind: list[str] = []
        self.origin: list[Any] = []
        self.sources: list[HoldingSource] = []
        self.times: list[Fraction] = [_ZERO]
        self._time_slot: dict[int, int] = {id(_ZERO): 0}  # by object: a skeleton's times
        for i, (c, clock) in enumerate(skeleton.clocks.items()):
            self._add(i, i, 1, HoldingSource("period", c), clock.period, clock.phase, "clock",
                      {"clock": c})
        tick = {c: i for i, c in enumerate(skeleton.clocks)}
        for name, task in skeleton.tasks.items():
            chain = events.chains[name]
            if task.clock is not None:
                self._add(tick[task.clock], chain[0], 0, _NO_PARAMETER, _ZERO, _ZERO,
                          "activation", {"clock": task.clock, "task": name})
            self._chain(task, chain, events.compute[name])
        index = events.index
        for i, link in enumerate(skeleton.links):
            w = f"{link.writer[0]}.write:{link.writer[1]}"
            r = f"{link.reader[0]}.read:{link.reader[1]}"
            origin = {"link": link.label, "link_index": i}
            if link.protocol is Protocol.ASYN_SYN:
                self._add(_event(index, w, r, w), _event(index, w, r, r), 0, _NO_PARAMETER,
                          _ZERO, _ZERO, "asyn-syn", origin)
            elif link.protocol is Protocol.SYN_ASYN:
                self._add(_event(index, r, w, r), _event(index, r, w, w), 0, _NO_PARAMETER,
                          _ZERO, _ZERO, "syn-asyn", origin)
            # ASYN/ASYN: no place; SYN/SYN: already one event on both chains.
        self._threads(skeleton, events)

    def _time(self, t: Fraction) -> int:
        k = self._time_slot.get(id(t))
        if k is None:
            k = self._time_slot[id(t)] = len(self.times)
            self.times.append(t)
        return k

    def _add(self, src: int, dst: int, tokens: int, source: HoldingSource, holding: Fraction,
             initial: Fraction, kind: str, origin: Any) -> None:
        self.src.append(src)
        self.dst.append(dst)
        self.tokens.append(tokens)
        self.holding.append(self._time(holding))
        self.initial.append(self._time(initial))
        self.kind.append(kind)
        self.origin.append(origin)
        self.sources.append(source)

    def _chain(self, task: Task, chain: tuple[int, ...], compute: int) -> None:
        """The chain places in chain order, then the return place (the last event back to
        the first, one token); the places leaving ``T.compute`` hold ``duration(T)``."""
        n = len(chain)
        self.src.extend(chain)
        self.dst.extend(chain[1:])
        self.dst.append(chain[0])
        self.tokens += [0] * (n - 1)
        self.tokens.append(1)
        self.kind += ["chain"] * (n - 1)
        self.kind.append("return")
        # One origin for the task's chain and return places: origins are read-only
        # (Place.origin), and a dict a place was 80 MB at 100,000 tasks.
        self.origin += [{"task": task.name}] * n
        self.initial += [0] * n
        leaving = [e == compute for e in chain]
        duration = self._time(task.duration)
        self.holding += [duration if left else 0 for left in leaving]
        source = HoldingSource("duration", task.name)
        self.sources += [source if left else _NO_PARAMETER for left in leaving]

    def _threads(self, skeleton: Skeleton, events: _Events) -> None:
        """Each thread's places: one task's last event to the next one's first, the
        return to the first task holding the token."""
        chains, compute = events.chains, events.compute
        for i, thread in enumerate(skeleton.threads):
            for j, name in enumerate(thread):
                nxt, last = thread[(j + 1) % len(thread)], j == len(thread) - 1
                end = chains[name][-1]
                leaves_compute = end == compute[name]
                self._add(end, chains[nxt][0], 1 if last else 0,
                          HoldingSource("duration", name) if leaves_compute else _NO_PARAMETER,
                          skeleton.tasks[name].duration if leaves_compute else _ZERO, _ZERO,
                          "thread-return" if last else "thread",
                          {"thread": i, "from": name, "to": nxt})


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

