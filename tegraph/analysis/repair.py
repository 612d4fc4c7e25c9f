"""Repair a dead skeleton by reordering ports, keeping what is already fine.

:func:`tegraph.analysis.reorder.reorder_ports` decides in polynomial time whether some
port order makes a skeleton live: the *precedence graph* (each task's
``activate -> reads -> compute -> writes``, the 0-token link, clock and thread
places) must be acyclic, and then any topological order of it gives live port
orders. :func:`fix_ports` builds on it and chooses *which* order:

1. **Keep every declared order that is fine.** A side of a task (its inputs
   or its outputs) whose declared order puts no edge on a circuit of the
   precedence graph plus all declared orders — that is, on no token-free
   circuit of the timed event graph — keeps its order. Those sides together
   never close a circuit (a circuit among them would lie in one strongly
   connected part, whose declared edges all belong to the other sides), so
   they are added to the graph as hard edges.
2. **Prefer short latency on the sides on a token-free circuit** (footnote 6
   of the ORCCAD paper [1]_: "the synchronizing port will be either the first
   reading or the last posting one so that the MT computes with the last
   available data"). On such a side the synchronizing inputs (read ASYN/SYN
   or SYN/SYN) are placed before the other inputs, and the blocking outputs
   (posted SYN/ASYN or SYN/SYN) after the others, as far as these preference
   edges close no circuit. Then each such side keeps its declared order when
   that still closes no circuit. Footnote 6 comes first so that a side
   declared as it advises is not the one sacrificed: a task posting its
   blocking output first is reordered, not its reader that reads its
   synchronizing input first.
3. One topological order of the result (Kahn's algorithm [2]_, declared
   positions as priorities, ties by event name) gives every port order; the
   reordered skeleton is rebuilt and checked for token-free circuits before
   it is returned.

The sides are taken by task name and the ties broken by event name, never by
the position of a task or link in the file: the same skeleton in any file
order gets the same repair. When no port order helps, the threads may be
reordered (:func:`tegraph.analysis.reorder.reorder_threads`) and the ports then
repaired as above.

Nothing here prints or writes files: the command line does.

References
----------
.. [1] D. Simon et al., "Design and analysis of synchronization for
   real-time closed-loop control in robotics", IEEE Transactions on Control
   Systems Technology, 1998.
.. [2] A. B. Kahn, "Topological sorting of large networks", Communications
   of the ACM 5(11), 558–562, 1962.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from ..model.build import build_teg
from ..model.elements import LinkLabel
from ..model.skeleton import Protocol, Skeleton
from .liveness import token_free_circuits

# The precedence graph is reorder.py's; this module only adds edges to it.
from .reorder import PrecedenceGraph, reorder_ports, reorder_threads

__all__ = ["FixResult", "PortChange", "ThreadChange", "fix_ports"]

_READER_BLOCKS = (Protocol.ASYN_SYN, Protocol.SYN_SYN)
_WRITER_BLOCKS = (Protocol.SYN_ASYN, Protocol.SYN_SYN)


@dataclass(frozen=True)
class PortChange:
    """A side of a task whose port order changed."""

    task: str
    side: str
    """``"inputs"`` or ``"outputs"``."""
    before: tuple[str, ...]
    after: tuple[str, ...]
    reason: str


@dataclass(frozen=True)
class ThreadChange:
    """A thread whose order changed (when no port order alone helps)."""

    index: int
    """Its position in the file's ``threads``."""
    before: tuple[str, ...]
    after: tuple[str, ...]
    reason: str


@dataclass
class FixResult:
    """What :func:`fix_ports` found and did.

    Attributes
    ----------
    status : str
        ``"already live"`` (nothing to change), ``"fixed"`` (``skeleton`` is
        live), or ``"impossible"`` (no port order helps).
    skeleton : Skeleton or None
        The live skeleton (the input itself when already live).
    changes : list of PortChange
    deadlocks : list of list of str
        Token-free circuits of the input, as event names.
    circuit : list of str
        When impossible: a circuit of the precedence graph, a deadlock for
        every port order.
    links : list of LinkLabel
        When impossible: the synchronizing links on that circuit; turning one
        of them asynchronous (ASYN/ASYN), or adding a clock, breaks it.
    threads : list of ThreadChange
        Threads reordered, when no port order alone makes the skeleton live
        but a thread order does (then ``changes`` are the port orders that
        change on the reordered threads).

    See Also
    --------
    fix_ports : makes it.
    tegraph.analysis.reorder.ReorderResult : the decision it refines.
    """

    status: str
    skeleton: Skeleton | None
    changes: list[PortChange] = field(default_factory=list)
    deadlocks: list[list[str]] = field(default_factory=list)
    circuit: list[str] = field(default_factory=list)
    links: list[LinkLabel] = field(default_factory=list)
    threads: list[ThreadChange] = field(default_factory=list)

    @property
    def live(self) -> bool:
        """True when a live skeleton is available (already, or after the fix)."""
        return self.status != "impossible"

    def to_dict(self) -> dict[str, Any]:
        """Plain data for JSON."""
        return {"status": self.status, "deadlocks": self.deadlocks,
                "changes": [{"task": c.task, "side": c.side, "before": list(c.before),
                             "after": list(c.after), "reason": c.reason} for c in self.changes],
                "circuit": self.circuit, "links": [link.document() for link in self.links],
                "threads": [{"index": t.index, "before": list(t.before), "after": list(t.after),
                             "reason": t.reason} for t in self.threads]}


@dataclass
class _Side:
    task: str
    side: str
    ports: tuple[str, ...]
    nodes: list[int]
    blocking: list[bool]


def fix_ports(skeleton: Skeleton) -> FixResult:
    """Port orders that make ``skeleton`` live, changing only what must change.

    Parameters
    ----------
    skeleton : Skeleton
        The design whose port orders may change (nothing else does).

    Returns
    -------
    FixResult
        ``status`` and the ``changes`` of port order, task side by task side,
        with the reordered skeleton; or why no port order can make it live.

    Raises
    ------
    AssertionError
        Internal error: the chosen orders do not give a live timed event graph.

    See Also
    --------
    tegraph.analysis.reorder.reorder_ports : the decision it builds on.
    tegraph.check_rules : the design rules of the same paper.

    Notes
    -----
    A skeleton is live when its timed event graph has no token-free circuit
    (Commoner's theorem [1]_); the preference for the first reading or the
    last posting synchronizing port is footnote 6 of the ORCCAD paper [2]_.
    The order is one topological order found by Kahn's algorithm [3]_.

    References
    ----------
    .. [1] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed
       graphs", Journal of Computer and System Sciences 5(5), 511–523, 1971.
    .. [2] D. Simon et al., "Design and analysis of synchronization for
       real-time closed-loop control in robotics", IEEE Transactions on Control
       Systems Technology, 1998.
    .. [3] A. B. Kahn, "Topological sorting of large networks", Communications
       of the ACM 5(11), 558–562, 1962.

    Examples
    --------
    Figure 7b: MT2 reads ``c`` (from MT3) before meeting MT1 on ``a``, and MT1
    posts ``a`` (where it blocks) before ``d``: both sides lie on the circuit.
    Footnote 6 has MT1 post its blocking output last; MT2's inputs, both
    synchronizing, stay.

    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "MT1": {"duration": 2, "period": 10, "inputs": ["q"], "outputs": ["a", "d"]},
    ...     "MT2": {"duration": 1, "inputs": ["c", "a"], "outputs": ["tau"]},
    ...     "MT3": {"duration": 3, "inputs": ["d"], "outputs": ["c"]}},
    ...   "links": [{"from": "MT1:a", "to": "MT2:a", "protocol": "SYN/SYN"},
    ...             {"from": "MT1:d", "to": "MT3:d", "protocol": "ASYN/SYN"},
    ...             {"from": "MT3:c", "to": "MT2:c", "protocol": "ASYN/SYN"}]})
    >>> r = fix_ports(sk)
    >>> r.status, [(c.task, c.side, c.before, c.after) for c in r.changes]
    ('fixed', [('MT1', 'outputs', ('a', 'd'), ('d', 'a'))])
    """
    deadlocks = _deadlocks(skeleton)
    if not deadlocks:
        return FixResult("already live", skeleton)
    base = reorder_ports(skeleton)
    if not base.possible:
        return _fix_threads(skeleton, deadlocks) or FixResult(
            "impossible", None, deadlocks=deadlocks, circuit=base.circuit, links=base.links)
    graph = PrecedenceGraph(skeleton)
    # Sides by task name, not by the file's order: the same skeleton in any file
    # order gets the same repair.
    sides = sorted(_sides(skeleton, graph), key=lambda s: (s.task, s.side))
    component = _strong_components(graph, sides)
    on_circuit = [any(component[u] == component[v] for u, v in itertools.pairwise(s.nodes))
                  for s in sides]
    for side, dead in zip(sides, on_circuit):
        if not dead:
            _add(graph, list(itertools.pairwise(side.nodes)))
    dead_sides = [side for side, dead in zip(sides, on_circuit) if dead]
    # Footnote 6 first on the sides that lie on a token-free circuit, then their
    # declared orders where they still fit (the preference edges are not in the
    # graph of `component`: the checks search the whole graph).
    reasons = {(s.task, s.side): _prefer_latency(graph, s) for s in dead_sides}
    freed = [s for s in dead_sides if not _try_add(graph, list(itertools.pairwise(s.nodes)))]
    fixed, changes = _reordered(skeleton, graph, freed, reasons)
    if _deadlocks(fixed):
        raise AssertionError("internal error: the reordered skeleton is not live")
    return FixResult("fixed", fixed, changes, deadlocks)


def _reordered(skeleton: Skeleton, graph: PrecedenceGraph, freed: list[_Side],
               reasons: dict[tuple[str, str], str]) -> tuple[Skeleton, list[PortChange]]:
    """The skeleton with each freed side's ports in the order of a topological order
    of ``graph``, and the changes, in the file's order of tasks."""
    order = graph.topological_order()
    if order is None:  # pragma: no cover - every added edge was checked
        raise AssertionError("internal error: the kept port orders close a circuit")
    position = {v: i for i, v in enumerate(order)}
    tasks = dict(skeleton.tasks)
    changes = []
    index = {t: i for i, t in enumerate(skeleton.tasks)}
    for side in sorted(freed, key=lambda s: (index[s.task], s.side)):  # as the file lists them
        after = tuple(p for _, p in sorted(zip((position[v] for v in side.nodes), side.ports)))
        if after != side.ports:
            changes.append(PortChange(side.task, side.side, side.ports, after,
                                      reasons[side.task, side.side]))
            ports: dict[str, Any] = {side.side: after}  # "inputs" or "outputs"
            tasks[side.task] = replace(tasks[side.task], **ports)
    return replace(skeleton, tasks=tasks), changes


def _fix_threads(skeleton: Skeleton, deadlocks: list[list[str]]) -> FixResult | None:
    """No port order helps: reorder threads (:func:`reorder_threads`), then fix the ports."""
    repair = reorder_threads(skeleton)
    if repair is None:
        return None
    threads = [repair.threads.get(k, t) for k, t in enumerate(skeleton.threads)]
    inner = fix_ports(replace(skeleton, threads=threads))
    if not inner.live:  # pragma: no cover - reorder_threads checked the precedence graph
        raise AssertionError("internal error: the reordered threads are not live")
    why = ("as declared, a task of the thread waits for one that runs after it (a token-free "
           "circuit through the thread); this order is what the links and ports allow")
    changes = [ThreadChange(k, skeleton.threads[k], order, why)
               for k, order in sorted(repair.threads.items())]
    return FixResult("fixed", inner.skeleton, inner.changes, deadlocks, threads=changes)


def _deadlocks(sk: Skeleton) -> list[list[str]]:
    teg = build_teg(sk)
    a = teg.arrays()
    names = teg.transition_names
    return [[names[int(a.src[p])] for p in c]
            for c in token_free_circuits(a.src, a.dst, a.tokens, teg.n_transitions)]


def _sides(sk: Skeleton, g: PrecedenceGraph) -> list[_Side]:
    """Every side with at least two ports, in file order."""
    out = []
    for name, task in sk.tasks.items():
        if len(task.inputs) > 1:
            blocking = [any(link.reader == (name, p) and link.protocol in _READER_BLOCKS
                            for link in sk.links) for p in task.inputs]
            out.append(_Side(name, "inputs", task.inputs,
                             [g.read[name, p] for p in task.inputs], blocking))
        if len(task.outputs) > 1:
            blocking = [any(link.writer == (name, p) and link.protocol in _WRITER_BLOCKS
                            for link in sk.links) for p in task.outputs]
            out.append(_Side(name, "outputs", task.outputs,
                             [g.write[name, p] for p in task.outputs], blocking))
    return out


def _strong_components(g: PrecedenceGraph, sides: list[_Side]) -> np.ndarray:
    """Strong components of the precedence graph plus every declared order."""
    n = len(g.names)
    edges = [(u, v) for u, outs in enumerate(g.succ) for v in outs]
    edges += [e for s in sides for e in itertools.pairwise(s.nodes)]
    rows, cols = (np.array(x, dtype=np.int64) for x in zip(*edges)) if edges else ([], [])
    matrix = sp.csr_matrix((np.ones(len(edges), dtype=np.int8), (rows, cols)), shape=(n, n))
    return connected_components(matrix, directed=True, connection="strong")[1]


def _add(g: PrecedenceGraph, edges: list[tuple[int, int]]) -> None:
    for u, v in edges:
        g.succ[u].append(v)


def _try_add(g: PrecedenceGraph, edges: list[tuple[int, int]],
             component: np.ndarray | None = None) -> bool:
    """Add ``edges`` unless one of them closes a circuit; report which happened.

    With ``component`` (strong components of a graph that contains every
    edge tried), a circuit through ``u -> v`` can only lie in the component
    of ``u``: the search stays there, and is skipped when ``v`` is elsewhere.
    """
    _add(g, edges)
    for u, v in edges:
        if component is not None and component[u] != component[v]:
            continue
        if _reaches(g, v, u, None if component is None else component[u], component):
            for a, _ in reversed(edges):
                g.succ[a].pop()  # the edges were appended last: undo in reverse
            return False
    return True


def _reaches(g: PrecedenceGraph, source: int, target: int, label: int | None,
             component: np.ndarray | None) -> bool:
    seen = {source}
    stack = [source]
    while stack:
        v = stack.pop()
        if v == target:
            return True
        for w in g.succ[v]:
            # Type: component is given whenever label is.
            if w not in seen and (label is None or component[w] == label):  # type: ignore[index]
                seen.add(w)
                stack.append(w)
    return False


def _prefer_latency(g: PrecedenceGraph, side: _Side) -> str:
    """Footnote 6 on a side that must change: synchronizing reads first, blocking writes last."""
    first = [v for v, b in zip(side.nodes, side.blocking) if b == (side.side == "inputs")]
    last = [v for v, b in zip(side.nodes, side.blocking) if b != (side.side == "inputs")]
    why = "its declared order lies on a token-free circuit"
    if not first or not last:
        return why
    what = ("synchronizing inputs read first" if side.side == "inputs"
            else "blocking outputs posted last")
    # The whole preferred order if it fits; else each preference edge that fits.
    if _try_add(g, list(itertools.pairwise(first + last))):
        return f"{why}; {what} (footnote 6)"
    kept = sum(_try_add(g, [(a, b)]) for a in first for b in last)
    if kept == len(first) * len(last):
        return f"{why}; {what} (footnote 6)"
    return f"{why}; {what} where the circuit allows it (footnote 6)" if kept else why


