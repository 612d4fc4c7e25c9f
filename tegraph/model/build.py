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
"""

from __future__ import annotations

import itertools

from ..errors import ModelError
from .skeleton import Protocol, Skeleton, Task
from .teg import TimedEventGraph

__all__ = [
    "PLACE_KINDS",
    "build_teg",
    "compute_events",
    "first_event",
    "last_event",
    "task_chain",
]

PLACE_KINDS = ("chain", "return", "clock", "activation", "asyn-syn", "syn-asyn",
               "thread", "thread-return")
"""Every ``Place.kind`` that :func:`build_teg` produces."""


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
    for c, clock in clocks.items():
        teg.add_place(f"{c}.tick", f"{c}.tick", 1, clock.period, clock.phase, "clock",
                      origin={"clock": c})
    for name, chain in chains.items():
        _add_chain(teg, tasks[name], [ev for ev, _ in chain])
    _add_links(teg, skeleton)
    _add_threads(teg, skeleton, chains)
    idx = teg.index
    teg.attrs["chains"] = {t: tuple(idx(ev) for ev, _ in chain) for t, chain in chains.items()}
    teg.attrs["compute"] = {t: idx(f"{t}.compute") for t in tasks}
    teg.attrs["clocks"] = {c: idx(f"{c}.tick") for c in clocks}
    return teg


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


def _add_links(teg: TimedEventGraph, skeleton: Skeleton) -> None:
    """The place of each ASYN/SYN and SYN/ASYN link (spec §2)."""
    for i, link in enumerate(skeleton.links):
        w = f"{link.writer[0]}.write:{link.writer[1]}"
        r = f"{link.reader[0]}.read:{link.reader[1]}"
        origin = {"link": link.label, "link_index": i}
        if link.protocol is Protocol.ASYN_SYN:
            teg.add_place(w, r, kind="asyn-syn", origin=origin)
        elif link.protocol is Protocol.SYN_ASYN:
            teg.add_place(r, w, kind="syn-asyn", origin=origin)
        # ASYN/ASYN: no place; SYN/SYN: already one event on both chains.


def _add_threads(teg: TimedEventGraph, skeleton: Skeleton,
                 chains: dict[str, list[tuple[str, str]]]) -> None:
    """Each thread's places: one task's last event to the next one's first, the
    return to the first task holding the token."""
    tasks = skeleton.tasks
    ends = {name: (chain[0][0], chain[-1][0]) for name, chain in chains.items()}
    for i, thread in enumerate(skeleton.threads):
        for j, name in enumerate(thread):
            nxt, last = thread[(j + 1) % len(thread)], j == len(thread) - 1
            # "The place that leaves T.compute holds duration(T)" (spec §2): a
            # thread place leaves it when T has no outputs.
            holding = tasks[name].duration if ends[name][1] == f"{name}.compute" else 0
            teg.add_place(ends[name][1], ends[nxt][0], tokens=1 if last else 0, holding=holding,
                          kind="thread-return" if last else "thread",
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


def _add_chain(teg: TimedEventGraph, task: Task, chain: list[str]) -> None:
    """Activation place, chain places, return place; duration on the place leaving compute."""
    t = task.name
    if task.clock is not None:
        teg.add_place(f"{task.clock}.tick", chain[0], kind="activation",
                      origin={"clock": task.clock, "task": t})
    compute = f"{t}.compute"
    for a, b in itertools.pairwise(chain):
        teg.add_place(a, b, holding=task.duration if a == compute else 0, kind="chain",
                      origin={"task": t})
    # The return place (a self-loop on T.compute when the chain is that one event).
    teg.add_place(chain[-1], chain[0], tokens=1,
                  holding=task.duration if chain[-1] == compute else 0, kind="return",
                  origin={"task": t})


# ------------------------------------------------------------- chain helpers
def _chains(teg: TimedEventGraph) -> dict[str, tuple[int, ...]]:
    if "chains" not in teg.attrs:
        raise ModelError("not built from a skeleton (no 'chains' in attrs)", teg.name)
    return teg.attrs["chains"]


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

