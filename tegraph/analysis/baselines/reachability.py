"""The untimed reachability graph: the state-space baseline for deadlocks.

The ORCCAD paper [1]_ (§4-5) checks its nets by walking their reachability graph;
:mod:`tegraph.analysis.liveness` answers the same question structurally (token-free
circuits). This module is the walk, so that the two can be compared and the
difference in cost measured (``benchmarks/bench_baseline.py``).

:func:`reachability_graph` explores any :class:`~tegraph.model.petri.PetriNet`
breadth first, a whole level of markings at a time in numpy: enabledness is one
comparison against the input arcs, successors one addition of incidence
columns, and markings are stored as the bytes of a small unsigned-integer
array (widened when a place outgrows it) in one dictionary. Parent pointers
give every dead marking a shortest firing sequence from the initial one.
A *deadlock* is a reachable marking that enables no transition (the Model
Checking Contest's ``ReachabilityDeadlock``).

A skeleton's timed event graph is never bounded without time (a clock fires
at will and piles up activations), and a clock is always enabled, so no
marking of the whole net is ever dead. :func:`skeleton_reachability`
therefore explores each group (weakly connected part) on its own, with every
place ``p`` bounded to ``m_p + 1`` tokens by a complementary place. Every
circuit through a complementary place holds a token, so the bounded group is
live exactly when the group is (Commoner's theorem [2]_, [3]_ on both marked graphs);
bounded and strongly connected, a group that is not live reaches a marking
where none of its events can fire. Its firing sequence is also a firing
sequence of the unbounded net.

References
----------
.. [1] D. Simon et al., "Design and analysis of synchronization for
   real-time closed-loop control in robotics", IEEE Transactions on Control
   Systems Technology, 1998.
.. [2] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed
   graphs", Journal of Computer and System Sciences 5(5), 511–523, 1971.
.. [3] T. Murata, "Petri nets: properties, analysis and applications",
   Proceedings of the IEEE 77(4), 541–580, 1989.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from ...errors import InputError
from ...model.budgets import DEFAULT_MAX_MEMORY, DEFAULT_MAX_STATES
from ...model.petri import PetriNet
from ...model.teg import TimedEventGraph
from .marking_search import INT64_MAX, Progress, breadth_first

__all__ = ["DEFAULT_MAX_MEMORY", "DeadMarking", "Reachability", "bounded_net",
           "reachability_graph", "skeleton_groups", "skeleton_reachability"]



@dataclass
class DeadMarking:
    """A reachable marking that enables no transition (of its group).

    Attributes
    ----------
    marking : numpy.ndarray of int64
        Tokens of every place of the explored net.
    firing_sequence : list of int
        Transition indices, a shortest sequence from the initial marking.
    group : int or None
        For :func:`skeleton_reachability`, the group that is stuck.
    """

    marking: np.ndarray
    firing_sequence: list[int]
    group: int | None = None


@dataclass
class Reachability:
    """What a reachability exploration found.

    Attributes
    ----------
    net : PetriNet
        The net explored (for a skeleton, the unbounded net of its TEG).
    states, edges : int
        Markings reached and firings examined.
    complete : bool
        False when a budget or the ``stop`` flag ended the search first.
    stopped_by : str or None
        ``"states"`` (the state budget), ``"memory"`` (the memory budget),
        ``"time"``, ``"interrupted"``, ``"tokens"`` (a place would hold more
        than 2**63 - 1 tokens) or ``"unbounded"`` (a transition has no input
        place: see ``source_transition``).
    dead : list of DeadMarking
        Every dead marking reached, in breadth-first order.
    max_states : int
        The state budget.
    seconds : float
        Wall-clock time of the exploration.
    groups : list of list of str, optional
        For a skeleton, the tasks of every group, as numbered by ``analyze``.
    bounded : bool
        Whether places were bounded to ``m_p + 1`` (skeletons).
    source_transition : str or None
        A transition without input place and with an output place, found
        before any search: it is always enabled, so it fires forever, the net
        is unbounded (its reachability graph infinite) and no reachable
        marking is dead.
    max_memory : int
        The memory budget, in bytes, of the stored markings.
    """

    net: PetriNet
    states: int
    edges: int
    complete: bool
    stopped_by: str | None
    dead: list[DeadMarking]
    max_states: int
    seconds: float
    groups: list[list[str]] | None = None
    bounded: bool = False
    source_transition: str | None = None
    max_memory: int = DEFAULT_MAX_MEMORY

    @property
    def deadlock(self) -> bool | None:
        """True when a dead marking was reached, False when none exists, None if unknown."""
        if self.dead:
            return True
        return False if self.complete or self.source_transition is not None else None

    def verdict(self) -> str:
        """One line: the deadlock verdict, or why there is none.

        >>> net = PetriNet("n", ["p"], ["t"], np.array([[1]]), np.array([[1]]), np.array([1]))
        >>> reachability_graph(net).verdict()
        'no deadlock (1 state, complete)'
        >>> reachability_graph(net, max_states=0).verdict()
        'inconclusive (budget 0 states reached)'
        """
        if self.dead:
            n = len(self.dead)
            return f"deadlock: {n} dead marking{'s' * (n != 1)} reached"
        if self.source_transition is not None:
            return (f"unbounded: transition {self.source_transition!r} has no input place, it "
                    "can fire forever; no deadlock: it is always enabled, so no reachable "
                    "marking is dead (the state space is infinite and was not explored)")
        if self.complete:
            return f"no deadlock ({_count(self.states, 'state')}, complete)"
        if self.stopped_by == "states":
            return f"inconclusive (budget {self.max_states:,} states reached)"
        if self.stopped_by == "time":
            return f"inconclusive (time budget reached after {self.states:,} states)"
        if self.stopped_by == "memory":
            return (f"inconclusive (memory budget of {_size(self.max_memory)} for stored "
                    f"markings reached after {self.states:,} states; raise `max_memory`)")
        if self.stopped_by == "tokens":
            return (f"inconclusive (after {self.states:,} states a place would hold more than "
                    f"2**63 - 1 = {INT64_MAX} tokens, the limit of 64-bit markings)")
        return f"inconclusive (interrupted after {self.states:,} states)"

    @property
    def exit_status(self) -> int:
        """1 when a dead marking was reached, else 0 (as ``tegraph analyze``); 130 when
        the search was interrupted (Ctrl-C: the command's status, its counts partial)."""
        if self.stopped_by == "interrupted":
            return 130
        return int(bool(self.dead))

    def place_names(self) -> list[str]:
        """Place names, made unique with ``#index`` where two places share one."""
        names = self.net.places
        seen: dict[str, int] = {}
        for n in names:
            seen[n] = seen.get(n, 0) + 1
        return [n if seen[n] == 1 else f"{n}#{i}" for i, n in enumerate(names)]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: ``states``, ``edges``, ``complete``, ``deadlock``, ``deadlocks``...

        Each deadlock has its ``marking`` (marked places only) and its
        ``firing_sequence`` (transition names); for a skeleton also its ``group``
        and that group's ``tasks``.
        """
        names = self.place_names()
        deadlocks = []
        for d in self.dead:
            entry: dict[str, Any] = {
                "marking": {names[p]: int(d.marking[p]) for p in np.flatnonzero(d.marking)},
                "firing_sequence": [self.net.transitions[t] for t in d.firing_sequence],
            }
            if d.group is not None and self.groups is not None:
                entry["group"] = d.group
                entry["tasks"] = list(self.groups[d.group])
            deadlocks.append(entry)
        return {
            "net": self.net.name, "mode": "untimed", "states": self.states, "edges": self.edges,
            "complete": self.complete, "stopped_by": self.stopped_by,
            "deadlock": self.deadlock, "deadlocks": deadlocks,
            "bounded": "m + 1 tokens per place, each group alone" if self.bounded else None,
            "unbounded": None if self.source_transition is None else
            f"transition {self.source_transition} has no input place, it can fire forever",
            "max_states": self.max_states, "seconds": round(self.seconds, 6),
        }


def reachability_graph(net: PetriNet, *, max_states: int = DEFAULT_MAX_STATES,
                       max_seconds: float | None = None, progress: Progress | None = None,
                       stop: Callable[[], bool] | None = None,
                       max_memory: int = DEFAULT_MAX_MEMORY) -> Reachability:
    """Breadth-first reachability graph of a P/T net, under a state and a time budget.

    A transition without input place but with an output place is looked for
    first: it is always enabled and each firing adds a token, so the net is
    unbounded and no marking is dead; that verdict is given at once, without
    a search (``stopped_by="unbounded"``).

    Parameters
    ----------
    net : PetriNet
    max_states : int
        Stop (incomplete) rather than store more markings than this.
    max_seconds : float, optional
        Stop (incomplete) after about this long.
    progress : callable, optional
        ``progress(states, edges, seconds)``, called between batches.
    stop : callable, optional
        Polled between batches; when it returns True the search ends with
        ``stopped_by="interrupted"`` (a command line sets it on Ctrl-C).
    max_memory : int
        Stop (incomplete, ``stopped_by="memory"``) rather than store markings
        taking more bytes than this (default :data:`DEFAULT_MAX_MEMORY`): a
        marking costs about twice its places in bytes, so a net of many places
        reaches this budget long before ``max_states``.

    Returns
    -------
    Reachability

    Examples
    --------
    Two tokens travel a ring of two places: 3 markings, 4 firings, no deadlock.
    Taking one transition away leaves the tokens stuck after two firings:

    >>> pre = np.array([[1, 0], [0, 1]]); post = np.array([[0, 1], [1, 0]])
    >>> r = reachability_graph(PetriNet("ring", ["a", "b"], ["ab", "ba"], pre, post,
    ...                                 np.array([2, 0])))
    >>> r.states, r.edges, r.deadlock
    (3, 4, False)
    >>> r = reachability_graph(PetriNet("line", ["a", "b"], ["ab"], pre[:, :1], post[:, :1],
    ...                                 np.array([2, 0])))
    >>> r.states, r.deadlock, r.dead[0].marking.tolist(), r.dead[0].firing_sequence
    (3, True, [0, 2], [0, 0])

    A transition that takes from no place fires forever:

    >>> r = reachability_graph(PetriNet("src", ["a"], ["make"], [[0]], [[1]], [0]))
    >>> r.deadlock, r.stopped_by, r.verdict()[:68]
    (False, 'unbounded', "unbounded: transition 'make' has no input place, it can fire forever")
    """
    start = time.perf_counter()
    if max_memory < 1:
        raise InputError(f"expected a number of bytes >= 1, got {max_memory}", "max_memory")
    # No input place: always enabled. With an output place too, each firing adds a token.
    no_input = np.diff(net.pre.T.tocsr().indptr) == 0
    sources = np.flatnonzero(no_input & (np.diff(net.post.T.tocsr().indptr) > 0))
    if len(sources):
        return Reachability(net, 1, 0, False, "unbounded", [], max_states,
                            time.perf_counter() - start,
                            source_transition=net.transitions[int(sources[0])],
                            max_memory=max_memory)
    deadline = None if max_seconds is None else start + max_seconds
    run = breadth_first(net.pre, net.post, net.marking, max_states, deadline, progress, stop,
                        start, max_memory)
    dead = [DeadMarking(m, seq) for m, seq in run.dead]
    return Reachability(net, run.states, run.edges, run.stopped_by is None, run.stopped_by,
                        dead, max_states, time.perf_counter() - start, max_memory=max_memory)


def bounded_net(net: PetriNet, extra: int = 1) -> PetriNet:
    """The net with a complementary place for every place: ``p`` holds at most ``m_p + extra``.

    The complementary place of ``p`` (named ``p~``) starts with ``extra``
    tokens, loses one when a token enters ``p`` and gains one when a token
    leaves it, so ``M(p) + M(p~) = m_p + extra`` in every reachable marking.

    Examples
    --------
    >>> net = PetriNet("n", ["p"], ["t"], np.array([[0]]), np.array([[1]]), np.array([0]))
    >>> b = bounded_net(net)
    >>> b.places, b.pre.tolist(), b.post.tolist(), b.marking.tolist()
    (['p', 'p~'], [[0], [1]], [[1], [0]], [0, 1])
    >>> reachability_graph(b).states
    2
    """
    if extra < 1:
        raise InputError(f"expected an integer >= 1, got {extra}", "extra")
    return PetriNet(net.name, list(net.places) + [f"{p}~" for p in net.places],
                    list(net.transitions), sp.vstack([net.pre, net.post], format="csr"),
                    sp.vstack([net.post, net.pre], format="csr"),
                    np.concatenate([net.marking, np.full(len(net.places), extra, np.int64)]),
                    attrs=dict(net.attrs))


def skeleton_reachability(teg: TimedEventGraph, *, max_states: int = DEFAULT_MAX_STATES,
                          max_seconds: float | None = None, progress: Progress | None = None,
                          stop: Callable[[], bool] | None = None,
                          max_memory: int = DEFAULT_MAX_MEMORY) -> Reachability:
    """Deadlocks of a skeleton's TEG by exploring each group, places bounded to ``m + 1``.

    Groups are the weakly connected parts that hold a task, numbered as
    :func:`tegraph.analyze` numbers them (by their first task in the file);
    a clock that activates no task is no group and is not explored. The
    budgets are shared: groups after the one that exhausts them stay
    unexplored. ``states`` and ``edges`` add up the groups' graphs.

    Parameters
    ----------
    teg : TimedEventGraph
        Built by :func:`tegraph.model.build.build_teg` (any TEG works; without task
        chains every weakly connected part is a group).
    max_states, max_seconds, progress, stop, max_memory
        As for :func:`reachability_graph` (the memory budget applies to each group).

    Returns
    -------
    Reachability
        ``dead[i].marking`` covers every place of the (unbounded) net: the
        group's places as reached, the others as initially marked.

    Examples
    --------
    Two tasks that each wait for the other's message before computing:

    >>> from tegraph import Skeleton, build_teg
    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "A": {"duration": 1, "inputs": ["x"], "outputs": ["y"]},
    ...     "B": {"duration": 1, "inputs": ["y"], "outputs": ["x"]}},
    ...     "links": [{"from": "A:y", "to": "B:y", "protocol": "ASYN/SYN"},
    ...               {"from": "B:x", "to": "A:x", "protocol": "ASYN/SYN"}]})
    >>> r = skeleton_reachability(build_teg(sk))
    >>> r.deadlock, r.states, r.dead[0].firing_sequence, r.groups
    (True, 1, [], [['A', 'B']])
    """
    start = time.perf_counter()
    if max_memory < 1:  # the rule of reachability_graph: no budget is no search
        raise InputError(f"expected a number of bytes >= 1, got {max_memory}", "max_memory")
    deadline = None if max_seconds is None else start + max_seconds
    net = PetriNet.from_teg(teg)
    a = teg.arrays()
    groups, members = skeleton_groups(teg)
    states = edges = 0
    stopped: str | None = None
    dead: list[DeadMarking] = []
    for g, events in enumerate(members):
        places = np.flatnonzero(np.isin(a.src, events))
        sub = bounded_net(PetriNet(net.name, [net.places[p] for p in places],
                                   [net.transitions[e] for e in events],
                                   net.pre[places][:, events], net.post[places][:, events],
                                   net.marking[places]))

        def relay(s: int, e: int, sec: float, s0: int = states, e0: int = edges) -> None:
            if progress is not None:
                progress(s0 + s, e0 + e, time.perf_counter() - start)

        run = breadth_first(sub.pre, sub.post, sub.marking, max_states - states, deadline,
                            relay, stop, start, max_memory)
        states, edges = states + run.states, edges + run.edges
        for marking, seq in run.dead:
            full = net.marking.copy()
            full[places] = marking[:len(places)]
            dead.append(DeadMarking(full, [int(events[t]) for t in seq], g))
        if run.stopped_by is not None:
            stopped = run.stopped_by
            break
    return Reachability(net, states, edges, stopped is None, stopped, dead, max_states,
                        time.perf_counter() - start, groups, bounded=True,
                        max_memory=max_memory)


def skeleton_groups(teg: TimedEventGraph) -> tuple[list[list[str]], list[np.ndarray]]:
    """Tasks and event indices of every group (weakly connected part), in ``analyze``'s order.

    Groups are numbered by their first task in the file, tasks within a group
    in file order; a part without a task (a clock that activates nothing) is
    left out. A TEG without task chains has one group per part, without tasks.

    Examples
    --------
    >>> from tegraph import Skeleton, build_teg
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2},
    ...                                    "B": {"duration": 1}}})
    >>> tasks, events = skeleton_groups(build_teg(sk))
    >>> tasks, [e.tolist() for e in events]
    ([['A'], ['B']], [[0, 1, 2], [3]])
    """
    n = teg.n_transitions
    a = teg.arrays()
    graph = sp.csr_array((np.ones(len(a.src), dtype=np.int8), (a.src, a.dst)), shape=(n, n))
    _, label = connected_components(graph, directed=True, connection="weak")
    chains = teg.attrs.get("chains")
    if not chains:
        labels = list(dict.fromkeys(label.tolist()))
        return ([[] for _ in labels],
                [np.flatnonzero(label == lab) for lab in labels])
    order: dict[int, list[str]] = {}
    for task, chain in chains.items():
        order.setdefault(int(label[chain[0]]), []).append(task)
    return list(order.values()), [np.flatnonzero(label == lab) for lab in order]


def _count(n: int, noun: str) -> str:
    return f"{n:,} {noun}{'s' * (n != 1)}"


def _size(n_bytes: int) -> str:
    """``2 GiB``, ``512 MiB``, ``1,000 bytes``: a byte count as a person reads it."""
    for unit, size in (("GiB", 2**30), ("MiB", 2**20), ("KiB", 2**10)):
        if n_bytes >= size and n_bytes % size == 0:
            return f"{n_bytes // size:,} {unit}"
    return _count(n_bytes, "byte")
