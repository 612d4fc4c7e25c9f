"""Port orders that make a skeleton live, decided in polynomial time.

Within one activation a task reads all its inputs before it computes and
writes all its outputs after; only the order *among* its reads and among its
writes is free. Take the *precedence graph* of those obligations: each task's
``activate -> read -> compute -> write`` edges, the 0-token places of the links
(ASYN/SYN ``write -> read``, SYN/ASYN ``read -> write``, SYN/SYN one merged
event), the clocks' ``tick -> activate`` places, and for a thread
``[T1, ..., Tn]`` the obligation that all of ``Ti`` precedes all of ``Ti+1``
(0-token thread places). Every port order yields a 0-token graph that contains
these edges (up to transitivity), so a circuit here is a deadlock for every
order; conversely, if the graph is acyclic, ordering every task's ports along
one topological order gives 0-token places that all point forward in it: no
token-free circuit, the skeleton is live (Commoner et al. [1]_, [2]_).

The topological order is chosen by Kahn's algorithm [3]_ with the declared
port positions as priorities, so declared orders that are already fine stay.
The example is Figure 7b of the ORCCAD paper [4]_.

References
----------
.. [1] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed
   graphs", Journal of Computer and System Sciences 5(5), 511–523, 1971.
.. [2] T. Murata, "Petri nets: properties, analysis and applications",
   Proceedings of the IEEE 77(4), 541–580, 1989.
.. [3] A. B. Kahn, "Topological sorting of large networks", Communications
   of the ACM 5(11), 558–562, 1962.
.. [4] D. Simon et al., "Design and analysis of synchronization for
   real-time closed-loop control in robotics", IEEE Transactions on Control
   Systems Technology, 1998.
"""

from __future__ import annotations

import heapq
from dataclasses import dataclass, field, replace

from ..model.build import build_teg
from ..model.elements import LinkLabel, flow_list
from ..model.skeleton import Protocol, Skeleton, Task
from .liveness import token_free_circuits

__all__ = ["PrecedenceGraph", "ReorderResult", "ThreadRepair", "reorder_ports",
           "reorder_threads", "thread_advice"]


@dataclass
class ReorderResult:
    """Whether some port order makes the skeleton live, and one such order.

    Attributes
    ----------
    possible : bool
    orders : dict
        ``task -> {"inputs": [...], "outputs": [...]}`` for every task whose
        order changes (empty when ``possible`` is False).
    skeleton : Skeleton or None
        The reordered skeleton when possible.
    circuit : list of str
        When impossible: a circuit of the precedence graph, as event names;
        it is a deadlock whatever the port orders.
    links : list of LinkLabel
        When impossible: the synchronizing links on that circuit (turning one
        of them asynchronous, or adding a clock or thread token, breaks it).
    """

    possible: bool
    orders: dict[str, dict[str, list[str]]] = field(default_factory=dict)
    skeleton: Skeleton | None = None
    circuit: list[str] = field(default_factory=list)
    links: list[LinkLabel] = field(default_factory=list)


@dataclass
class ThreadRepair:
    """Thread orders that make a skeleton live when no port order does.

    Attributes
    ----------
    threads : dict
        ``index -> new order`` of each thread that changes (its index in the
        file's ``threads``).
    orders : dict
        Port orders that must change as well, as ``ReorderResult.orders``.
    skeleton : Skeleton
        The skeleton with those threads and ports reordered (live).
    """

    threads: dict[int, tuple[str, ...]]
    orders: dict[str, dict[str, list[str]]]
    skeleton: Skeleton


def reorder_threads(skeleton: Skeleton) -> ThreadRepair | None:
    """Orders of the threads (and then of ports) that make ``skeleton`` live, if found.

    A thread runs its tasks one after the other, so a thread ``[EST, IMU]`` in
    which EST waits for IMU's message deadlocks whatever the port orders; written
    ``[IMU, EST]`` it does not. Take the precedence graph without the threads
    (:class:`PrecedenceGraph`): task A must come before task B in a thread when
    some event of A reaches some event of B there. The threads are ordered one
    at a time (in the order of their sorted task names, so that the file's order
    does not matter), each by Kahn's algorithm on that relation, declared
    positions first, and its obligations are added before the next; the ports
    are then ordered as :func:`reorder_ports` does.

    Parameters
    ----------
    skeleton : Skeleton

    Returns
    -------
    ThreadRepair or None
        None when the skeleton has no thread, when no thread changes, or when
        this search (greedy, one thread at a time: a search over every
        combination of thread orders could find one where it does not) finds
        no live order.

    Examples
    --------
    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "IMU": {"duration": 1, "period": 10, "outputs": ["m"]},
    ...     "EST": {"duration": 2, "inputs": ["m"]}},
    ...   "links": [{"from": "IMU:m", "to": "EST:m", "protocol": "ASYN/SYN"}],
    ...   "threads": [["EST", "IMU"]]})
    >>> reorder_threads(sk).threads
    {0: ('IMU', 'EST')}
    """
    if not skeleton.threads:
        return None
    graph = PrecedenceGraph(replace(skeleton, threads=[]))
    threads = list(skeleton.threads)
    for k in sorted(range(len(threads)), key=lambda i: sorted(threads[i])):
        order = _thread_order(graph, threads[k])
        if order is None:
            return None
        graph.add_thread(k, order)
        threads[k] = order
    if graph.topological_order() is None:
        return None
    changed = {k: tuple(t) for k, t in enumerate(threads) if tuple(t) != skeleton.threads[k]}
    if not changed:
        return None
    ports = reorder_ports(replace(skeleton, threads=[tuple(t) for t in threads]))
    if not ports.possible or ports.skeleton is None:  # pragma: no cover - the graph is acyclic
        return None
    return ThreadRepair(changed, ports.orders, ports.skeleton)


def thread_advice(skeleton: Skeleton) -> str | None:
    """The words of :func:`reorder_threads`' repair, or None when it finds none.

    The repair is re-checked: the timed event graph of the reordered skeleton is
    rebuilt and has no token-free circuit.
    """
    repair = reorder_threads(skeleton)
    if repair is None:
        return None
    rebuilt = build_teg(repair.skeleton).arrays()
    if token_free_circuits(rebuilt.src, rebuilt.dst, rebuilt.tokens,
                           int(max(rebuilt.src.max(), rebuilt.dst.max())) + 1):
        raise AssertionError("internal error: the reordered threads are not live")
    words = "; ".join(f"write threads[{k}] as {flow_list(list(order))}"
                      for k, order in repair.threads.items())
    if repair.orders:
        words += "; then reorder ports: " + "; ".join(
            f"{t} inputs {flow_list(o['inputs'])} outputs {flow_list(o['outputs'])}"
            for t, o in repair.orders.items())
    return (f"no port order helps, a thread order does: {words} (a thread runs its tasks one "
            "after the other: as declared, a task waits for one that runs after it)")


def _thread_order(graph: PrecedenceGraph, thread: tuple[str, ...]) -> tuple[str, ...] | None:
    """The tasks of ``thread`` in an order the obligations allow, declared order first."""
    reach = {t: graph.reached(graph.events_of[t]) for t in thread}
    events = {t: set(graph.events_of[t]) for t in thread}
    before = {b: {a for a in thread if a != b and reach[a] & events[b]} for b in thread}
    position = {t: i for i, t in enumerate(thread)}
    heap = [position[t] for t in thread if not before[t]]
    heapq.heapify(heap)
    order: list[str] = []
    while heap:
        t = thread[heapq.heappop(heap)]
        order.append(t)
        for b in thread:
            if t in before[b]:
                before[b].discard(t)
                if not before[b]:
                    heapq.heappush(heap, position[b])
    return tuple(order) if len(order) == len(thread) else None


def reorder_ports(skeleton: Skeleton) -> ReorderResult:
    """Find port orders that make ``skeleton`` live, or prove that none does.

    Parameters
    ----------
    skeleton : Skeleton
        Tasks, ports, links, clocks and threads; the declared port positions
        are kept wherever they already work.

    Returns
    -------
    ReorderResult
        ``possible`` True with the changed ``orders`` (per task, its inputs
        and outputs in the new order) and the reordered skeleton; or
        ``possible`` False with the ``circuit`` of events and the ``links``
        on it that deadlock every port order.

    See Also
    --------
    PrecedenceGraph : the obligations the order must respect.
    tegraph.analysis.cycle_time.cycle_time : period of the reordered skeleton.

    Notes
    -----
    Linear in the size of the skeleton (plus a log factor for the priority
    queue of Kahn's algorithm [3]_). The argument is in the module docstring:
    an acyclic precedence graph leaves no token-free circuit, so the skeleton
    is live by Commoner's theorem [1]_, [2]_. The result is re-checked by the
    analysis, which rebuilds the timed event graph of the reordered skeleton
    and tests it for token-free circuits.

    References
    ----------
    .. [1] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed
       graphs", Journal of Computer and System Sciences 5(5), 511–523, 1971.
    .. [2] T. Murata, "Petri nets: properties, analysis and applications",
       Proceedings of the IEEE 77(4), 541–580, 1989.
    .. [3] A. B. Kahn, "Topological sorting of large networks", Communications
       of the ACM 5(11), 558–562, 1962.
    .. [4] D. Simon et al., "Design and analysis of synchronization for
       real-time closed-loop control in robotics", IEEE Transactions on Control
       Systems Technology, 1998.

    Examples
    --------
    Figure 7b of the ORCCAD paper [4]_: MT2 waits to read ``c`` from MT3 before it
    reads ``a``, so MT1 stays blocked writing ``a`` (SYN/ASYN) and never writes
    ``d``, for which MT3 waits:

    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "MT1": {"duration": 1, "period": 10, "outputs": ["a", "d"]},
    ...     "MT2": {"duration": 1, "inputs": ["c", "a"]},
    ...     "MT3": {"duration": 1, "inputs": ["d"], "outputs": ["c"]}},
    ...   "links": [{"from": "MT1:a", "to": "MT2:a", "protocol": "SYN/ASYN"},
    ...             {"from": "MT1:d", "to": "MT3:d", "protocol": "ASYN/SYN"},
    ...             {"from": "MT3:c", "to": "MT2:c", "protocol": "ASYN/SYN"}]})
    >>> r = reorder_ports(sk)
    >>> r.possible, r.orders
    (True, {'MT2': {'inputs': ['a', 'c'], 'outputs': []}})
    """
    graph = PrecedenceGraph(skeleton)
    order = graph.topological_order()
    if order is None:
        circuit = graph.find_circuit()
        names = [graph.names[v] for v in circuit]
        on = set(circuit)
        links = [label for (a, b), labels in graph.link_edges.items() if a in on and b in on
                 for label in labels]
        return ReorderResult(False, circuit=names, links=links)
    position = {v: i for i, v in enumerate(order)}
    orders: dict[str, dict[str, list[str]]] = {}
    tasks = dict(skeleton.tasks)
    for name, task in skeleton.tasks.items():
        inputs = sorted(task.inputs, key=lambda p: position[graph.read[name, p]])
        outputs = sorted(task.outputs, key=lambda p: position[graph.write[name, p]])
        if tuple(inputs) != task.inputs or tuple(outputs) != task.outputs:
            orders[name] = {"inputs": inputs, "outputs": outputs}
            tasks[name] = replace(task, inputs=tuple(inputs), outputs=tuple(outputs))
    reordered = replace(skeleton, tasks=tasks)
    return ReorderResult(True, orders, reordered)


class PrecedenceGraph:
    """Events and 0-token obligations of a skeleton, with port-order freedom."""

    def __init__(self, sk: Skeleton) -> None:
        self.names: list[str] = []
        self.priority: list[int] = []
        self.keys: list[str] = []  # names without the file's positions, for ties
        self.succ: list[list[int]] = []
        self.link_edges: dict[tuple[int, int], list[LinkLabel]] = {}
        self.read: dict[tuple[str, str], int] = {}
        self.write: dict[tuple[str, str], int] = {}
        self._ticks: dict[str, int] = {}
        for name, task in sk.tasks.items():
            for pos, port in enumerate(task.outputs):
                self.write[name, port] = self._node(f"{name}.write:{port}",
                                                    2 + len(task.inputs) + pos)
        merged = {link.reader: self.write[link.writer] for link in sk.links
                  if link.protocol is Protocol.SYN_SYN}
        self.events_of = {name: self._add_task(name, task, merged)
                          for name, task in sk.tasks.items()}
        for link in sk.links:
            w, r = self.write[link.writer], self.read[link.reader]
            if link.protocol is Protocol.ASYN_SYN:
                self._edge(w, r)
                self.link_edges.setdefault((w, r), []).append(link.label)
            elif link.protocol is Protocol.SYN_ASYN:
                self._edge(r, w)
                self.link_edges.setdefault((r, w), []).append(link.label)
            elif link.protocol is Protocol.SYN_SYN:
                self.link_edges.setdefault((w, w), []).append(link.label)
        for k, thread in enumerate(sk.threads):
            self.add_thread(k, thread)

    def _add_task(self, name: str, task: Task, merged: dict[tuple[str, str], int]) -> list[int]:
        """The events of one task (a SYN/SYN read is its writer's event) and the
        obligations of its chain; returns its events in chain order."""
        activate = self._node(f"{name}.activate", 0) if task.clock else None
        compute = self._node(f"{name}.compute", 1 + len(task.inputs))
        reads = []
        for pos, port in enumerate(task.inputs):
            node = merged.get((name, port))
            if node is None:
                node = self._node(f"{name}.read:{port}", 1 + pos)
            self.read[name, port] = node
            reads.append(node)
        writes = [self.write[name, port] for port in task.outputs]
        # Two SYN/SYN inputs on one writer port make one event appear twice
        # in the chain: the place between the copies is a 0-token self-loop,
        # a deadlock whatever the order.
        seen: set[int] = set()
        for node in reads:
            if node in seen:
                self._edge(node, node)
            seen.add(node)
        for r in reads:
            if activate is not None:
                self._edge(activate, r)
            self._edge(r, compute)
        if activate is not None:
            self._edge(activate, compute)
        for w in writes:
            self._edge(compute, w)
        if task.clock:
            assert activate is not None  # made above for every clocked task
            self._edge(self._tick(task.clock), activate)
            return [activate, *reads, compute, *writes]
        return [*reads, compute, *writes]

    def add_thread(self, k: int, thread: tuple[str, ...] | list[str]) -> None:
        """The obligations of thread ``k`` run in the order ``thread``: all of each
        task before all of the next (its 0-token thread places)."""
        for a, b in zip(thread, thread[1:]):
            end = self._node(f"thread[{k}]:{a}.end", 0, f"thread:{a}.end")
            start = self._node(f"thread[{k}]:{b}.start", 0, f"thread:{b}.start")
            for e in self.events_of[a]:
                self._edge(e, end)
            self._edge(end, start)
            for e in self.events_of[b]:
                self._edge(start, e)

    def reached(self, sources: list[int]) -> set[int]:
        """The events reachable from ``sources`` (themselves included)."""
        seen = set(sources)
        stack = list(sources)
        while stack:
            for b in self.succ[stack.pop()]:
                if b not in seen:
                    seen.add(b)
                    stack.append(b)
        return seen

    def _node(self, name: str, priority: int, key: str | None = None) -> int:
        self.names.append(name)
        self.keys.append(name if key is None else key)
        self.priority.append(priority)
        self.succ.append([])
        return len(self.names) - 1

    def _tick(self, clock: str) -> int:
        if clock not in self._ticks:
            self._ticks[clock] = self._node(f"{clock}.tick", 0)
        return self._ticks[clock]

    def _edge(self, a: int, b: int) -> None:
        self.succ[a].append(b)

    def topological_order(self) -> list[int] | None:
        """Kahn's topological order of the events, declared port positions first.

        Returns
        -------
        list of int or None
            Event indices in an order where every obligation points forward;
            None when the obligations contain a circuit (see
            :meth:`find_circuit`).
        """
        n = len(self.names)
        indegree = [0] * n
        for outs in self.succ:
            for b in outs:
                indegree[b] += 1
        # Ties by name, not by index: the order does not depend on the file's order.
        heap = [(self.priority[v], self.keys[v], v) for v in range(n) if indegree[v] == 0]
        heapq.heapify(heap)
        order = []
        while heap:
            _, _, v = heapq.heappop(heap)
            order.append(v)
            for b in self.succ[v]:
                indegree[b] -= 1
                if indegree[b] == 0:
                    heapq.heappush(heap, (self.priority[b], self.keys[b], b))
        return order if len(order) == n else None

    def find_circuit(self) -> list[int]:
        """One circuit, by iterative depth-first search (colours white/grey/black).

        Returns
        -------
        list of int
            Event indices of one circuit of obligations, in order; empty when
            the graph is acyclic.
        """
        n = len(self.names)
        colour = [0] * n
        for root in range(n):
            if colour[root]:
                continue
            stack = [(root, 0)]
            path = [root]
            colour[root] = 1
            while stack:
                v, i = stack[-1]
                if i < len(self.succ[v]):
                    stack[-1] = (v, i + 1)
                    b = self.succ[v][i]
                    if colour[b] == 1:
                        return path[path.index(b):]
                    if colour[b] == 0:
                        colour[b] = 1
                        stack.append((b, 0))
                        path.append(b)
                else:
                    colour[v] = 2
                    stack.pop()
                    path.pop()
        return []
