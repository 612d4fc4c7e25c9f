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

import itertools
from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Literal, TypeAlias

from ..errors import ModelError
from .skeleton import Protocol, Skeleton, Task
from .teg import TimedEventGraph

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
    tasks, clocks = skeleton.tasks, skeleton.clocks
    _check_references(skeleton)
    merged = {link.reader: f"{link.writer[0]}.write:{link.writer[1]}"
              for link in skeleton.links if link.protocol is Protocol.SYN_SYN}
    chains = {name: _chain(t, merged) for name, t in tasks.items()}
    teg = TimedEventGraph(skeleton.name)
    teg.attrs["unit"] = skeleton.unit
    _add_events(teg, skeleton, chains, merged)
    places = _Places(teg, skeleton)
    for c, clock in clocks.items():
        places.add(f"{c}.tick", f"{c}.tick", HoldingSource("period", c), tokens=1,
                   initial=clock.phase, kind="clock", origin={"clock": c})
    for name, chain in chains.items():
        _add_chain(places, tasks[name], [ev for ev, _ in chain])
    _add_links(places, skeleton)
    _add_threads(places, skeleton, chains)
    places.into()
    idx = teg.index
    teg.attrs["chains"] = {t: tuple(idx(ev) for ev, _ in chain) for t, chain in chains.items()}
    teg.attrs["compute"] = {t: idx(f"{t}.compute") for t in tasks}
    teg.attrs["clocks"] = {c: idx(f"{c}.tick") for c in clocks}
    teg.attrs["holding_source"] = tuple(places.sources)
    # The activation ends with the last event of the chain: the last write, or
    # T.compute without outputs, and then only when the computation ends (spec §4).
    teg.attrs["activation_end"] = {
        t: ActivationEnd(idx(chain[-1][0]), not tasks[t].outputs,
                         Fraction(0) if tasks[t].outputs else tasks[t].duration)
        for t, chain in chains.items()}
    return teg


class _Places:
    """Collects each place with the holding time its source gives, and records the source;
    :meth:`into` adds them all to the graph at once (one call, not one a place)."""

    def __init__(self, teg: TimedEventGraph, skeleton: Skeleton) -> None:
        self.teg, self.skeleton = teg, skeleton
        self.rows: list[tuple[Any, ...]] = []
        self.sources: list[HoldingSource] = []

    def add(self, src: str, dst: str, source: HoldingSource = _NO_PARAMETER, *,
            tokens: int = 0, initial: Fraction = _ZERO, kind: str,
            origin: dict) -> None:
        self.rows.append((src, dst, tokens, source.value(self.skeleton), initial, kind, origin))
        self.sources.append(source)

    def into(self) -> None:
        """Add the places collected, in order."""
        self.teg.add_places(self.rows)


def _add_events(teg: TimedEventGraph, skeleton: Skeleton,
                chains: dict[str, list[tuple[str, str]]], merged: dict[tuple[str, str], str]
                ) -> None:
    """The clocks' ticks, then each task's events in chain order, a rendezvous once
    (with the ports it stands for: the writer's first, then the SYN/SYN readers)."""
    tasks = skeleton.tasks
    ports: dict[str, list[tuple[str, str]]] = {}
    for t in tasks.values():
        for p in t.outputs:
            ports[f"{t.name}.write:{p}"] = [(t.name, p)]
    for t in tasks.values():
        for q in t.inputs:
            ports.setdefault(merged.get((t.name, q), f"{t.name}.read:{q}"), []).append((t.name, q))
    owners: dict[str, list[str]] = {}
    for name, chain in chains.items():
        for ev, _ in chain:
            if name not in owners.setdefault(ev, []):
                owners[ev].append(name)
    for c in skeleton.clocks:
        teg.add_transition(f"{c}.tick", role="tick", tasks=(), ports=(), clock=c)
    made: set[str] = set()
    for name, chain in chains.items():
        for ev, role in chain:
            if ev in made:  # a rendezvous, already made by an earlier task
                continue
            made.add(ev)
            if len(ports.get(ev, ())) > 1:
                role = "rendezvous"
            teg.add_transition(ev, role=role, tasks=tuple(owners[ev]),
                               ports=tuple(ports.get(ev, ())),
                               clock=tasks[name].clock if role == "activate" else None)


def _add_links(places: _Places, skeleton: Skeleton) -> None:
    """The place of each ASYN/SYN and SYN/ASYN link (spec §2)."""
    for i, link in enumerate(skeleton.links):
        w = f"{link.writer[0]}.write:{link.writer[1]}"
        r = f"{link.reader[0]}.read:{link.reader[1]}"
        origin = {"link": link.label, "link_index": i}
        if link.protocol is Protocol.ASYN_SYN:
            places.add(w, r, kind="asyn-syn", origin=origin)
        elif link.protocol is Protocol.SYN_ASYN:
            places.add(r, w, kind="syn-asyn", origin=origin)
        # ASYN/ASYN: no place; SYN/SYN: already one event on both chains.


def _add_threads(places: _Places, skeleton: Skeleton,
                 chains: dict[str, list[tuple[str, str]]]) -> None:
    """Each thread's places: one task's last event to the next one's first, the
    return to the first task holding the token."""
    ends = {name: (chain[0][0], chain[-1][0]) for name, chain in chains.items()}
    for i, thread in enumerate(skeleton.threads):
        for j, name in enumerate(thread):
            nxt, last = thread[(j + 1) % len(thread)], j == len(thread) - 1
            places.add(ends[name][1], ends[nxt][0], _leaving(name, ends[name][1]),
                       tokens=1 if last else 0, kind="thread-return" if last else "thread",
                       origin={"thread": i, "from": name, "to": nxt})


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


def _chain(task: Task, merged: dict[tuple[str, str], str]) -> list[tuple[str, str]]:
    """(event, role) of the chain of ``task``; a SYN/SYN read is the writer's event."""
    t = task.name
    chain = [(f"{t}.activate", "activate")] if task.clock is not None else []
    chain += [(merged.get((t, q), f"{t}.read:{q}"), "read") for q in task.inputs]
    chain.append((f"{t}.compute", "compute"))
    chain += [(f"{t}.write:{p}", "write") for p in task.outputs]
    return chain


def _leaving(task: str, event: str) -> HoldingSource:
    """The source of a place of ``task`` leaving ``event``: "the place that leaves
    T.compute holds duration(T)" (spec §2), every other place of a chain 0."""
    return HoldingSource("duration", task) if event == f"{task}.compute" else _NO_PARAMETER


def _add_chain(places: _Places, task: Task, chain: list[str]) -> None:
    """Activation place, chain places, return place; duration on the place leaving compute."""
    t = task.name
    if task.clock is not None:
        places.add(f"{task.clock}.tick", chain[0], kind="activation",
                   origin={"clock": task.clock, "task": t})
    # One origin for the task's chain and return places: origins are read-only
    # (Place.origin), and a dict a place was 80 MB at 100,000 tasks.
    origin = {"task": t}
    for a, b in itertools.pairwise(chain):
        places.add(a, b, _leaving(t, a), kind="chain", origin=origin)
    # The return place (a self-loop on T.compute when the chain is that one event).
    places.add(chain[-1], chain[0], _leaving(t, chain[-1]), tokens=1, kind="return",
               origin=origin)


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

