"""The periods a (cut-down, edited) skeleton's tasks run at, for the advice's words.

The advisor (:mod:`.advice`) states what a change does to the period of each
group it touches: it cuts those groups out, makes the change, and solves them
here (:func:`task_rates`) as :func:`tegraph.analysis.analyze` would: the max
cycle ratio of the timed event graph, exactly.

Before the solve, each event with a single input place (a task's chain is mostly
such events) is folded into the event before it (:func:`folded`): its firings are
those of that event, shifted, so it has the same cycle time, and each circuit
through it keeps its weight and tokens. Howard's iteration then runs on about a
third of the events (a 25-task group: 73 events, 30 after folding).
"""

from __future__ import annotations

from collections.abc import Mapping
from fractions import Fraction
from typing import Any, Final

import numpy as np

from maxplus import ZeroTokenCircuitError, max_cycle_ratio
from maxplus.scalar import int_array

from ...analysis.liveness import token_free_circuits
from ...model.build import build_teg
from ...model.skeleton import Skeleton
from ...model.structure import label_events

__all__ = ["DEAD", "Folded", "Rates", "folded", "task_rates", "token_free"]

DEAD: Final = "dead"  # the period of a task on a dead part (a token-free circuit)


class Rates:
    """The periods of a skeleton's tasks: ``period[task]`` (a Fraction, or DEAD), and
    ``mixed[task]``, for a task whose weak part runs at several rates, those rates
    (one event of each, in words: ``[(who, rate)]``)."""

    __slots__ = ("period", "mixed")

    def __init__(self, period: dict[str, Any], mixed: dict[str, list[tuple[str, Fraction]]]
                 ) -> None:
        self.period, self.mixed = period, mixed


class Folded:
    """A graph with its single-input nodes folded away (:func:`folded`).

    Attributes
    ----------
    src, dst, weight, tokens : numpy.ndarray
        The arcs left, between the nodes left numbered ``0 .. n_nodes - 1``.
    n_nodes : int
    node : numpy.ndarray
        Each node of the graph given -> the node left it was folded into.
    """

    __slots__ = ("src", "dst", "weight", "tokens", "n_nodes", "node")

    def __init__(self, src: np.ndarray, dst: np.ndarray, weight: np.ndarray,
                 tokens: np.ndarray, n_nodes: int, node: np.ndarray) -> None:
        self.src, self.dst, self.weight, self.tokens = src, dst, weight, tokens
        self.n_nodes, self.node = n_nodes, node


def folded(src: list[int], dst: list[int], weight: list[int], tokens: list[int], n: int
           ) -> Folded:
    """The graph with each node of a single in-arc ``u -> v`` (not a loop) folded into ``u``.

    ``x_v(k) = x_u(k - t) + w`` for that arc, so ``v`` has the cycle time of ``u``
    (the cycle-time vector: the largest ratio of the circuits upstream, which for
    ``v`` are those upstream of ``u``); each out-arc ``v -> z`` becomes ``u -> z`` with
    the weights and tokens added, so the circuits through ``v`` are those through
    ``u`` with the same ratios, and a token-free circuit stays token-free. Folding
    runs along chains of such nodes (a ring of them keeps one node).

    Examples
    --------
    A chain 0 -> 1 -> 2 -> 0 (node 0 has two in-arcs) and a loop on 0:

    >>> f = folded([0, 1, 2, 0], [1, 2, 0, 0], [1, 2, 3, 4], [0, 0, 1, 1], 3)
    >>> f.n_nodes, f.node.tolist(), f.src.tolist(), f.weight.tolist(), f.tokens.tolist()
    (1, [0, 0, 0], [0, 0], [6, 4], [1, 1])
    """
    count = [0] * n
    for d in dst:
        count[d] += 1
    arc_in = [-1] * n  # the single in-arc of a node folded away
    for a, d in enumerate(dst):
        if count[d] == 1 and src[a] != d:
            arc_in[d] = a
    root = [-1] * n  # -1: not seen; -2: on the walk being made
    shift_w, shift_t = [0] * n, [0] * n  # x_v = x_root shifted by these
    for v in range(n):
        if root[v] != -1:
            continue
        walk = []
        u = v
        while root[u] == -1 and arc_in[u] >= 0:
            root[u] = -2
            walk.append(u)
            u = src[arc_in[u]]
        if root[u] < 0:  # a node of its own: no single in-arc, or it closes a ring of them
            arc_in[u] = -1
            root[u] = u
        for x in reversed(walk):
            if x == u:
                continue
            a = arc_in[x]
            p = src[a]
            root[x] = root[p]
            shift_w[x] = shift_w[p] + weight[a]
            shift_t[x] = shift_t[p] + tokens[a]
    left = [v for v in range(n) if arc_in[v] < 0]
    number = [0] * n
    for i, v in enumerate(left):
        number[v] = i
    kept = [a for a, d in enumerate(dst) if arc_in[d] < 0]
    return Folded(
        np.array([number[root[src[a]]] for a in kept], dtype=np.int64),
        np.array([number[dst[a]] for a in kept], dtype=np.int64),
        int_array([weight[a] + shift_w[src[a]] for a in kept]),
        int_array([tokens[a] + shift_t[src[a]] for a in kept]),
        len(left), np.array([number[root[v]] for v in range(n)], dtype=np.int64))


def task_rates(sk: Skeleton, roots: Mapping[str, Any]) -> Rates:
    """Each task's period in ``sk``: the cycle time of its compute event (DEAD: dead).

    ``roots``: the group of each task (a label per group), as the advisor
    re-formed them: the groups are not computed again.

    As :func:`tegraph.analysis.analyze` does: the weak parts with a token-free
    circuit are left out, the max cycle ratio of the rest is solved exactly; a
    part whose events do not all share one cycle time is not rate-consistent
    (some place between them fills up, as analyze's unbounded places).
    """
    teg = build_teg(sk)
    a = teg.arrays()
    n = teg.n_transitions
    # The changed skeleton's own groups (-1: the tick of a clock that drives no task,
    # alone on its part, which no task's period reads).
    number: dict[Any, int] = {}
    group_of = {t: number.setdefault(roots[t], len(number)) for t in sk.tasks}
    group_of_clock: dict[str, int] = {}
    for t, task in sk.tasks.items():
        if task.clock is not None:
            group_of_clock.setdefault(task.clock, group_of[t])
    label = label_events(teg, group_of, group_of_clock)
    try:  # most candidates leave the groups live: the kernel refuses a token-free circuit
        fold = folded(a.src.tolist(), a.dst.tolist(), a.holding.tolist(), a.tokens.tolist(), n)
        small = max_cycle_ratio(fold.src, fold.dst, fold.weight, fold.tokens,
                                n_nodes=fold.n_nodes)
        num_a, den_a = small.cycle_time_num[fold.node], small.cycle_time_den[fold.node]
        live = np.ones(n, dtype=bool)
    except ZeroTokenCircuitError:
        dead = {int(label[a.src[c[0]]])
                for c in token_free_circuits(a.src, a.dst, a.tokens, n)}
        live = ~np.isin(label, sorted(dead))
        lp = np.flatnonzero(live[a.src] & live[a.dst])
        mcr = max_cycle_ratio(a.src[lp], a.dst[lp], a.holding[lp], a.tokens[lp], n_nodes=n)
        num_a, den_a = mcr.cycle_time_num, mcr.cycle_time_den
    # Rates compared as the kernel's lowest-terms pairs (num, den): a Fraction is
    # made only for what is read (each task's period, the rates of a mixed group).
    num, den = num_a.tolist(), den_a.tolist()
    labels = label.tolist()
    first: dict[int, dict[tuple[int, int], int]] = {}  # group -> rate -> its first event
    for e in np.flatnonzero(live).tolist():
        # Every event of a skeleton lies on a circuit (its chain's): den > 0.
        first.setdefault(labels[e], {}).setdefault((num[e], den[e]), e)
    scale = a.scale
    compute = teg.attrs["compute"]
    rates = {g: [(_who(teg, f), Fraction(r[0], r[1] * scale)) for r, f in seen.items()]
             for g, seen in first.items() if len(seen) > 1}
    period: dict[str, Any] = {}
    mixed: dict[str, list[tuple[str, Fraction]]] = {}
    for t in sk.tasks:
        e = compute[t]
        period[t] = Fraction(num[e], den[e] * scale) if live[e] else DEAD
        if labels[e] in rates:
            mixed[t] = rates[labels[e]]
    return Rates(period, mixed)


def _who(teg: Any, e: int) -> str:
    """An event for the advice's words: its clock, or its task (a rendezvous by both)."""
    attrs = teg.transition_attrs[e]
    if attrs.get("role") == "tick":
        return f"clock {attrs['clock']}"
    return ", ".join(attrs.get("tasks", ())) or teg.transition_names[e]


def token_free(sk: Skeleton) -> list:
    """The token-free circuits of ``sk``'s timed event graph."""
    teg = build_teg(sk)
    a = teg.arrays()
    return token_free_circuits(a.src, a.dst, a.tokens, teg.n_transitions)
