"""Cycle time of any timed event graph: exact period, critical circuit, certificate.

:func:`cycle_time` is what ``tegraph cycle-time FILE`` runs once the file is
read. It accepts every model the project reads (a skeleton, a timed event
graph, a P/T net, an SDF graph, an arc list), turns it into arc arrays and
runs the exact maximum cycle ratio of :func:`maxplus.max_cycle_ratio`
(Howard's policy iteration [4]_; Karp's maximum cycle mean [3]_ when every
place holds one token).

* The **period** ``λ`` is the largest ``Σ holding / Σ tokens`` over the
  circuits: the time between two firings of the slowest transition in the
  long run; the **throughput** is ``1/λ`` firings per time unit (for an SDF
  graph: iterations per time unit, SDF3's throughput).
* The cycle time of a transition is the largest ratio among the circuits
  upstream of it (Baccelli et al. [1]_, Thm 3.112); the transitions differ
  only when the graph is not strongly connected. A transition that no
  circuit reaches (an input) has none.
* A circuit without token never fires (Commoner et al. [2]_): the graph
  deadlocks, no period exists, and that circuit is reported instead.
* A P/T net that is not a marked graph has no (max,+) figures: the result
  says why (the place or arc at fault), and what still applies is run
  instead: the untimed reachability baseline
  (:func:`tegraph.analysis.baselines.reachability.reachability_graph`, under a state and a time
  budget) decides whether a dead marking is reachable, with a shortest
  firing sequence to each.

The result is data (:class:`CycleTimeResult`, :meth:`~CycleTimeResult.to_dict`
for the JSON report of ``docs/report.schema.json``); nothing is printed.

References
----------
.. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
   and Linearity*, Wiley, 1992.
.. [2] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed
   graphs", Journal of Computer and System Sciences 5(5), 511–523, 1971.
.. [3] R. M. Karp, "A characterization of the minimum cycle mean in a
   digraph", Discrete Mathematics 23(3), 309–311, 1978.
.. [4] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
   J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
   algebra", IFAC Conference on System Structure and Control, 1998.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from maxplus import max_cycle_ratio
from maxplus.cycle_ratio import argmax_ratio, find_circuit
from maxplus.errors import MaxPlusValueError
from maxplus.scalar import display_text, exact_text, exact_time

from ..errors import InputError
from ..model.arcs import ArcList
from ..model.budgets import DEFAULT_MAX_FIRINGS, DEFAULT_MAX_MEMORY, DEFAULT_MAX_STATES
from ..model.convert import as_teg_like
from ..model.limits import written
from ..model.petri import PetriNet
from ..model.sdf import SDFGraph
from ..model.skeleton import Skeleton
from ..model.teg import TimedEventGraph
from .baselines.reachability import Reachability, reachability_graph

__all__ = ["CycleTimeResult", "cycle_time"]


@dataclass
class CycleTimeResult:
    """Figures of ``tegraph cycle-time`` (null where undefined).

    Attributes
    ----------
    name, model : str
        The graph's name, and what was read (``"timed event graph"``,
        ``"P/T net"``, ``"SDF graph"``, ``"skeleton"``, ``"arc list"``).
    applicable : bool
        False for a P/T net that is not a marked graph (see ``reason``).
    reachability : Reachability or None
        For such a net, its explored reachable markings (the deadlock
        verdict); None otherwise.
    period, throughput : Fraction or None
        ``throughput = 1/period``; None without circuit, on a deadlock, and
        (throughput) for period 0.
    critical_circuit : list of str
        Transitions of one circuit attaining the period, in firing order.
    critical_places : list of int
        Its places (indices), ``critical_places[i]`` leaving ``critical_circuit[i]``.
    cycle_times : dict of str to Fraction or None, or None
        Per transition, only when they differ (None: all equal ``period``).
    token_free_circuit : list of str or None
        Transitions of a circuit without token (a deadlock), else None.
    token_free_places : list of int
    critical_holdings : list of Fraction
        Holding time of each place of the critical circuit, in order.
    critical_tokens : int or None
        Tokens on the critical circuit: ``period = sum(critical_holdings) / critical_tokens``.
    parts : list of CyclePart
        Each weakly connected part that holds a circuit, with its own period,
        when there are several (for a skeleton: its groups); empty otherwise.
    unit : str
        The time unit (a skeleton's ``unit``; other formats carry none).
    certificate_verified : bool or None
        The exact certificate of the period was checked (None when not run).
    seconds : dict of str to float
        ``read``, ``analysis``, ``certificate`` wall times.

    See Also
    --------
    cycle_time : computes it.
    tegraph.report.to_json : its JSON report.
    tegraph.report.render_text : its text report.

    Examples
    --------
    A ring of two places without token deadlocks: no period, the token-free
    circuit instead, and exit status 1.

    >>> from tegraph.io.tpne import parse_tpne_teg
    >>> r = cycle_time(parse_tpne_teg("TimedEventGraph 2 2\\n0 1: 2 0\\n1 0: 3 0\\n"))
    >>> r.period, r.token_free_circuit, r.exit_status
    (None, ['T1', 'T0'], 1)
    """

    name: str
    model: str
    n_transitions: int
    n_places: int
    applicable: bool = True
    reason: str | None = None
    period: Fraction | None = None
    throughput: Fraction | None = None
    critical_circuit: list[str] = field(default_factory=list)
    critical_places: list[int] = field(default_factory=list)
    place_labels: list[str] = field(default_factory=list)
    cycle_times: dict[str, Fraction | None] | None = None
    token_free_circuit: list[str] | None = None
    token_free_places: list[int] = field(default_factory=list)
    certificate_verified: bool | None = None
    seconds: dict[str, float] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    source: str | None = None
    reachability: Reachability | None = None
    critical_holdings: list[Fraction] = field(default_factory=list)
    critical_tokens: int | None = None
    parts: list[CyclePart] = field(default_factory=list)
    unit: str = "time units"

    @property
    def critical_holding(self) -> Fraction | None:
        """Total holding time of the critical circuit (None without one)."""
        return sum(self.critical_holdings, Fraction(0)) if self.critical_tokens else None

    @property
    def exit_status(self) -> int:
        """1 when a deadlock was found (a circuit without token, a dead marking), else 0."""
        dead = self.reachability is not None and bool(self.reachability.dead)
        return 1 if dead or self.token_free_circuit is not None else 0

    def to_dict(self) -> dict[str, Any]:
        """The JSON report's data (``docs/report.schema.json``, ``"report": "cycle-time"``)."""
        return {
            "name": self.name,
            "source": self.source,
            "model": self.model,
            "transitions": self.n_transitions,
            "places": self.n_places,
            "applicable": self.applicable,
            "reason": self.reason,
            "period": exact_text(self.period),
            "throughput": exact_text(self.throughput),
            "critical_circuit": self.critical_circuit,
            "critical_places": self.place_labels,
            "critical_holding": exact_text(self.critical_holding),
            "critical_tokens": self.critical_tokens,
            "unit": self.unit,
            "parts": [p.to_dict() for p in self.parts],
            "cycle_times": None if self.cycle_times is None
            else {k: exact_text(v) for k, v in self.cycle_times.items()},
            "deadlock": None if self.token_free_circuit is None
            else {"token_free_circuit": self.token_free_circuit},
            "certificate_verified": self.certificate_verified,
            "reachability": None if self.reachability is None else self.reachability.to_dict(),
            "seconds": {k: round(v, 6) for k, v in self.seconds.items()},
            "notes": self.notes,
        }


@dataclass
class CyclePart:
    """A weakly connected part of a timed event graph that holds a circuit.

    Attributes
    ----------
    label : str
        Its tasks for a skeleton (a group of spec §4), else its first transitions.
    n_transitions : int
    period : Fraction
        The largest cycle time in the part: its period when the part is
        strongly connected, else that of its slowest transitions.
    critical_circuit : list of str
        Transitions of a circuit attaining it.
    critical_holdings : list of Fraction
    critical_tokens : int
    critical_places : list of int
        Its places (indices in the graph), ``critical_places[i]`` leaving
        ``critical_circuit[i]``: a drawing marks each part's own critical circuit.
    """

    label: str
    n_transitions: int
    period: Fraction
    critical_circuit: list[str]
    critical_holdings: list[Fraction]
    critical_tokens: int
    critical_places: list[int] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready data (exact strings)."""
        return {"label": self.label, "transitions": self.n_transitions,
                "period": exact_text(self.period), "critical_circuit": self.critical_circuit,
                "critical_holding": exact_text(sum(self.critical_holdings, Fraction(0))),
                "critical_tokens": self.critical_tokens}


def cycle_time(model: Any, *, verify: bool = True, default_holding: Any = None,
               max_states: int = DEFAULT_MAX_STATES, max_seconds: float | None = None,
               max_memory: int = DEFAULT_MAX_MEMORY,
               max_firings: int = DEFAULT_MAX_FIRINGS) -> CycleTimeResult:
    """Period, throughput, critical circuit and cycle times of a timed event graph.

    Parameters
    ----------
    model : Skeleton, TimedEventGraph, PetriNet, SDFGraph or ArcList
        Anything :func:`tegraph.model.convert.as_teg_like` turns into a timed
        event graph (:func:`tegraph.cycle_time` also takes a file).
    verify : bool
        Check the exact certificate of the result (default True).
    default_holding : int, Fraction or str, optional
        Holding time of every place of a net that carries no timing at all
        (a plain PNML P/T net); default 0.
    max_states, max_seconds, max_memory : int, float, int, optional
        Budgets of the reachability exploration run on a P/T net that is not
        a marked graph (beyond them its deadlock verdict is inconclusive).
    max_firings : int
        Largest homogeneous expansion of an SDF graph (firings per iteration).

    Returns
    -------
    CycleTimeResult
        Period, throughput, critical circuit and per-transition cycle times,
        or the deadlocked circuit, or (for a P/T net that is not a marked
        graph) the reason and the reachability verdict.

    Raises
    ------
    InputError
        The model is refused.

    See Also
    --------
    tegraph.cycle_time : the same, reading a file first.
    maxplus.max_cycle_ratio : the kernel.
    tegraph.analysis.baselines.reachability.reachability_graph : the untimed fallback
        for a P/T net that is not a marked graph.

    Notes
    -----
    The period is the maximum cycle ratio of the graph [1]_, computed exactly
    by Howard's policy iteration [4]_ (with one token per place it is Karp's
    maximum cycle mean [3]_). A circuit without token is a deadlock by
    Commoner's theorem [2]_, and is reported instead of a period.

    References
    ----------
    .. [1] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992.
    .. [2] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed
       graphs", Journal of Computer and System Sciences 5(5), 511–523, 1971.
    .. [3] R. M. Karp, "A characterization of the minimum cycle mean in a
       digraph", Discrete Mathematics 23(3), 309–311, 1978.
    .. [4] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
       J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
       algebra", IFAC Conference on System Structure and Control, 1998.

    Examples
    --------
    The SemiNetherlands graph's critical circuit 0 -> 2 -> 3 -> 1 carries
    (58 + 86 + 81 + 61) / (1 + 2 + 1 + 2) = 286/6:

    >>> from tegraph.io.tpne import parse_tpne_teg
    >>> g = parse_tpne_teg("TimedEventGraph 4 4\\n2 0: 58 1\\n3 2: 86 2\\n1 3: 81 1\\n0 1: 61 2\\n")
    >>> r = cycle_time(g)
    >>> str(r.period), str(r.throughput), r.critical_circuit, r.certificate_verified
    ('143/3', '3/143', ['T0', 'T2', 'T3', 'T1'], True)
    """
    seconds: dict[str, float] = {}
    t0 = time.perf_counter()
    graph, result = _as_graph(model, default_holding, max_firings)
    result.seconds = seconds
    if graph is None:
        seconds["analysis"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        result.reachability = reachability_graph(model, max_states=max_states,
                                                 max_seconds=max_seconds, max_memory=max_memory)
        seconds["reachability"] = time.perf_counter() - t0
        return result
    _solve(graph, result, verify)
    seconds["analysis"] = time.perf_counter() - t0 - seconds.get("certificate", 0.0)
    return result


def _as_graph(obj: Any, default_holding: Any,
              max_firings: int = DEFAULT_MAX_FIRINGS) -> tuple[Any, CycleTimeResult]:
    kinds = ((Skeleton, "skeleton"), (SDFGraph, "SDF graph"), (PetriNet, "P/T net"),
             (ArcList, "arc list"), (TimedEventGraph, "timed event graph"))
    model = next((k for cls, k in kinds if isinstance(obj, cls)), None)
    if model is None:
        raise InputError(f"cannot compute the cycle time of a {type(obj).__name__}")
    # Checked even when no net of the file uses it: a wrong value is refused, not ignored.
    default = _holding(default_holding)
    notes = []
    if isinstance(obj, PetriNet):
        why = obj.marked_graph_violation()
        if why is not None:
            res = CycleTimeResult(obj.name, model, len(obj.transitions), len(obj.places),
                                  applicable=False,
                                  reason=f"not a marked graph: {why}; the (max,+) figures "
                                         "(period, throughput, critical circuit) hold for "
                                         "marked graphs only")
            res.notes.append("the deadlock verdict comes from the untimed reachability "
                             "baseline (breadth-first over the reachable markings, as "
                             "`tegraph reach`); no structural cross-check applies")
            return None, res
        if not obj.holding:
            h = default
            obj = PetriNet(obj.name, obj.places, obj.transitions, obj.pre, obj.post, obj.marking,
                           [h] * len(obj.places), [], dict(obj.attrs))
            notes.append(f"the net carries no timing: every place holds {display_text(h)}")
    graph = as_teg_like(obj, max_firings)
    if model == "SDF graph":
        notes.append("transitions are the firings actor_i of one iteration (the homogeneous "
                     "expansion); the period is the time per iteration")
    res = CycleTimeResult(graph.name, model, graph.n_transitions, len(graph.arrays().src),
                          notes=notes, unit=obj.unit if isinstance(obj, Skeleton) else "time units")
    return graph, res


def _holding(value: Any) -> Fraction:
    if value is None:
        return Fraction(0)
    try:  # the one number parser: refused by its size beyond 4,300 digits, never expanded
        h = exact_time(value, "default_holding")
    except MaxPlusValueError as exc:
        raise InputError(f"expected an exact time such as 1, 0.5 or 7/3; "
                         f"{str(exc).removeprefix('default_holding: ')}",
                         "default_holding") from None
    if h < 0:
        raise InputError(f"a holding time must be >= 0, got {written(h, value)}", "default_holding")
    return h


def _solve(graph: Any, res: CycleTimeResult, verify: bool) -> None:
    a = graph.arrays()
    n = a.n_transitions
    names = _namer(graph)
    zero = np.flatnonzero(a.tokens == 0)
    dead = find_circuit(a.src, a.dst, n, zero)
    if dead:
        res.token_free_places = [int(p) for p in dead]
        res.token_free_circuit = [names(int(a.src[p])) for p in dead]
        res.place_labels = [_place_label(graph, p) for p in dead]
        return
    r = max_cycle_ratio(a.src, a.dst, a.holding, a.tokens, n_nodes=n)
    if verify:
        t0 = time.perf_counter()
        res.certificate_verified = r.verify()
        res.seconds["certificate"] = time.perf_counter() - t0
    if r.ratio is None:
        res.notes.append("the graph has no circuit: every transition can fire as often as "
                         "its inputs allow, so no period exists")
        return
    res.period = r.ratio / a.scale
    res.throughput = None if res.period == 0 else 1 / res.period
    if res.period == 0:
        res.notes.append("every circuit holds 0 time: the firing rate is unbounded")
    res.critical_places = [int(p) for p in r.circuit]
    res.critical_circuit = [names(int(a.src[p])) for p in r.circuit]
    res.place_labels = [_place_label(graph, p) for p in r.circuit]
    res.critical_holdings = [Fraction(int(h), a.scale) for h in a.holding[r.circuit].tolist()]
    res.critical_tokens = int(sum(int(t) for t in a.tokens[r.circuit].tolist()))
    res.parts = _parts(graph, a, r, names)
    _cycle_times(res, r, a.scale, names)


def _cycle_times(res: CycleTimeResult, r: Any, scale: int, names: Callable[[int], str]) -> None:
    """Each transition's own cycle time, recorded only where they are not all the
    period (a graph that is not strongly connected), with the transitions that have none."""
    num, den = r.cycle_time_num, r.cycle_time_den
    top = (r.ratio.numerator, r.ratio.denominator)
    if bool((den > 0).all() and (num * top[1] == den * top[0]).all()):
        return
    res.cycle_times = {names(i): (None if d == 0 else Fraction(int(m), int(d) * scale))
                       for i, (m, d) in enumerate(zip(num.tolist(), den.tolist()))}
    inputs = [k for k, v in res.cycle_times.items() if v is None]
    if inputs:
        shown = ", ".join(inputs[:10]) + (" ..." if len(inputs) > 10 else "")
        res.notes.append(f"{len(inputs)} transition(s) have no circuit upstream (inputs "
                         f"fired from outside), so no cycle time: {shown}")


def _parts(graph: Any, a: Any, r: Any, names: Callable[[int], str]) -> list[CyclePart]:
    """Each weakly connected part with a circuit and its period, when there are several."""
    n = a.n_transitions
    adjacency = sp.csr_matrix((np.ones(len(a.src), dtype=np.int8), (a.src, a.dst)), shape=(n, n))
    _, label = connected_components(adjacency, directed=True, connection="weak")
    num, den = r.cycle_time_num, r.cycle_time_den
    with_cycle = np.flatnonzero(den > 0)
    order = with_cycle[np.argsort(label[with_cycle], kind="stable")]
    bounds = np.flatnonzero(np.diff(label[order])) + 1
    groups = np.split(order, bounds) if len(order) else []
    if len(groups) < 2:
        return []
    sizes = np.bincount(label, minlength=int(label.max()) + 1)
    tasks_of = getattr(graph, "transition_attrs", None)
    parts = []
    for nodes in groups:
        best = int(nodes[argmax_ratio(num[nodes], den[nodes])])
        arcs = r.policy_circuit(best)
        if tasks_of is not None and any("tasks" in tasks_of[int(e)] for e in nodes[:1]):
            members: list[str] = []
            for e in np.flatnonzero(label == label[best]).tolist():
                for t in tasks_of[e].get("tasks", ()):
                    if t not in members:
                        members.append(t)
            text = ", ".join(members)
        else:
            first = [names(int(e)) for e in np.flatnonzero(label == label[best])[:3].tolist()]
            text = ", ".join(first) + (" ..." if sizes[label[best]] > 3 else "")
        parts.append(CyclePart(
            text, int(sizes[label[best]]), Fraction(int(num[best]), int(den[best]) * a.scale),
            [names(int(a.src[p])) for p in arcs.tolist()],
            [Fraction(int(h), a.scale) for h in a.holding[arcs].tolist()],
            int(sum(int(t) for t in a.tokens[arcs].tolist())), arcs.tolist()))
    return parts


def _namer(graph: Any) -> Callable[[int], str]:
    if hasattr(graph, "name_of"):
        return graph.name_of
    names = graph.transition_names
    return lambda i: names[i]


def _place_label(graph: Any, p: int) -> str:
    if hasattr(graph, "place_label"):
        return graph.place_label(int(p))
    return graph.places[int(p)].name
