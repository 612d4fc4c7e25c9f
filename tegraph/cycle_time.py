"""Cycle time of any timed event graph: exact period, critical circuit, certificate.

:func:`cycle_time` is what ``tegraph cycle-time FILE`` runs. It accepts every
model the project reads (a file path, a skeleton, a timed event graph, a P/T
net, an SDF graph, an arc list), turns it into arc arrays and runs the
exact maximum cycle ratio of :func:`maxplus.cycle_ratio.max_cycle_ratio`.

* The **period** ``λ`` is the largest ``Σ holding / Σ tokens`` over the
  circuits: the time between two firings of the slowest transition in the
  long run; the **throughput** is ``1/λ`` firings per time unit (for an SDF
  graph: iterations per time unit, SDF3's throughput).
* The cycle time of a transition is the largest ratio among the circuits
  upstream of it (Baccelli et al. 1992, Thm 3.112); the transitions differ
  only when the graph is not strongly connected. A transition that no
  circuit reaches (an input) has none.
* A circuit without token never fires (Commoner et al. 1971): the graph
  deadlocks, no period exists, and that circuit is reported instead.
* A P/T net that is not a marked graph has no (max,+) figures: the result
  says why (the place or arc at fault), and what still applies is run
  instead: the untimed reachability baseline
  (:func:`tegraph.reachability.reachability_graph`, under a state and a time
  budget) decides whether a dead marking is reachable, with a shortest
  firing sequence to each.

The result is data (:class:`CycleTimeResult`, :meth:`~CycleTimeResult.to_dict`
for the JSON report of ``docs/report.schema.json``); nothing is printed.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

import numpy as np

from maxplus.cycle_ratio import find_circuit, max_cycle_ratio
from maxplus.errors import MaxPlusValueError
from maxplus.scalar import exact_time

from .errors import InputError
from .reachability import Reachability, reachability_graph
from .report import exact_text, json_report

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
    certificate_verified : bool or None
        The exact certificate of the period was checked (None when not run).
    seconds : dict of str to float
        ``read``, ``analysis``, ``certificate`` wall times.
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

    @property
    def exit_status(self) -> int:
        """1 when a deadlock was found (a circuit without token, a dead marking), else 0."""
        dead = self.reachability is not None and bool(self.reachability.dead)
        return 1 if dead or self.token_free_circuit is not None else 0

    def to_dict(self) -> dict[str, Any]:
        """The JSON report (``docs/report.schema.json``, ``"report": "cycle-time"``)."""
        return json_report("cycle-time", {
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
            "cycle_times": None if self.cycle_times is None
            else {k: exact_text(v) for k, v in self.cycle_times.items()},
            "deadlock": None if self.token_free_circuit is None
            else {"token_free_circuit": self.token_free_circuit},
            "certificate_verified": self.certificate_verified,
            "reachability": None if self.reachability is None else self.reachability.to_dict(),
            "seconds": {k: round(v, 6) for k, v in self.seconds.items()},
            "notes": self.notes,
        })

    def to_json(self, indent: int | None = 2) -> str:
        """:meth:`to_dict` as JSON text."""
        return json.dumps(self.to_dict(), indent=indent, ensure_ascii=False)

    def to_text(self) -> str:
        """The human report."""
        head = f"{self.model} {self.name}" + (f" ({self.source})" if self.source else "")
        lines = [head, f"size:        {self.n_transitions} transitions, {self.n_places} places"]
        if not self.applicable:
            lines.append(f"no period:   {self.reason}")
            if self.reachability is not None:
                lines.append("instead, the deadlock verdict of its reachable markings:")
                lines.extend("  " + line
                             for line in self.reachability.render_text(limit=3).splitlines())
                if self.reachability.deadlock is None:
                    lines.append("to decide:   raise the budget (--max-states, --max-seconds)")
        elif self.token_free_circuit is not None:
            lines.append("DEADLOCK: circuit without token "
                         + " -> ".join([*self.token_free_circuit, self.token_free_circuit[0]])
                         + "; its transitions never fire (Commoner's theorem)")
        elif self.period is None:
            lines.append("period:      none (no circuit: nothing bounds the firing rate)")
        else:
            lines.append(f"period:      {_human(self.period)}")
            what = "iterations" if self.model == "SDF graph" else "firings"
            lines.append("throughput:  " + ("unbounded (period 0)" if self.throughput is None
                                            else f"{_human(self.throughput)} {what} per time unit"))
            lines.append("critical:    " + _circuit_text(self.critical_circuit, self.place_labels))
            if self.cycle_times is not None:
                lines.append("cycle times differ (the graph is not strongly connected):")
                width = max(len(k) for k in self.cycle_times)
                for k, v in self.cycle_times.items():
                    shown = "none (no circuit upstream: an input)" if v is None else _human(v)
                    lines.append(f"  {k:<{width}}  {shown}")
            check = {True: "verified exactly", False: "FAILED", None: "not run"}
            lines.append(f"certificate: {check[self.certificate_verified]}")
        lines.append("time:        " + ", ".join(f"{k} {v:.3f} s" for k, v in self.seconds.items()))
        lines.extend(f"note: {n}" for n in self.notes)
        return "\n".join(lines) + "\n"


def _human(value: Fraction) -> str:
    text = str(exact_text(value))
    return text if value.denominator == 1 else f"{text} ({float(value):.6g})"


def _circuit_text(events: list[str], places: list[str]) -> str:
    if not events:
        return "-"
    parts = []
    for e, p in zip(events, places):
        parts.append(f"{e} -[{p}]->")
    return " ".join(parts) + f" {events[0]}"


def cycle_time(source: Any, *, format: str | None = None, verify: bool = True,
               default_holding: Any = None, max_bytes: int | None = None,
               max_states: int = 1_000_000, max_seconds: float | None = None) -> CycleTimeResult:
    """Period, throughput, critical circuit and cycle times of a timed event graph.

    Parameters
    ----------
    source : path or model
        A file (read by :func:`tegraph.read`), or a Skeleton, TimedEventGraph,
        PetriNet, SDFGraph or ArcList.
    verify : bool
        Check the exact certificate of the result (default True).
    default_holding : int, Fraction or str, optional
        Holding time of every place of a net that carries no timing at all
        (a plain PNML P/T net); default 0.
    format : str, optional
        Force the format of a file (see :data:`tegraph.io.formats.FORMATS`).
    max_bytes : int, optional
        Size limit when ``source`` is a path.
    max_states, max_seconds : int, float, optional
        Budgets of the reachability exploration run on a P/T net that is not
        a marked graph (beyond them its deadlock verdict is inconclusive).

    Returns
    -------
    CycleTimeResult

    Raises
    ------
    InputError
        The file or model is refused.

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
    from .io.formats import DEFAULT_MAX_BYTES, read

    seconds: dict[str, float] = {}
    path = None
    if isinstance(source, (str, os.PathLike)):
        path = os.fspath(source)
        t0 = time.perf_counter()
        source = read(path, format, max_bytes=max_bytes or DEFAULT_MAX_BYTES)
        seconds["read"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    graph, result = _as_graph(source, default_holding)
    result.source = path
    result.seconds = seconds
    if graph is None:
        seconds["analysis"] = time.perf_counter() - t0
        t0 = time.perf_counter()
        result.reachability = reachability_graph(source, max_states=max_states,
                                                 max_seconds=max_seconds)
        seconds["reachability"] = time.perf_counter() - t0
        return result
    _solve(graph, result, verify)
    seconds["analysis"] = time.perf_counter() - t0 - seconds.get("certificate", 0.0)
    return result


def _as_graph(obj: Any, default_holding: Any) -> tuple[Any, CycleTimeResult]:
    from .io.edges import ArcList
    from .io.formats import as_teg_like
    from .io.sdf3 import SDFGraph
    from .petri import PetriNet
    from .skeleton import Skeleton
    from .teg import TimedEventGraph

    kinds = ((Skeleton, "skeleton"), (SDFGraph, "SDF graph"), (PetriNet, "P/T net"),
             (ArcList, "arc list"), (TimedEventGraph, "timed event graph"))
    model = next((k for cls, k in kinds if isinstance(obj, cls)), None)
    if model is None:
        raise InputError(f"cannot compute the cycle time of a {type(obj).__name__}")
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
            h = _holding(default_holding)
            obj = PetriNet(obj.name, obj.places, obj.transitions, obj.pre, obj.post, obj.marking,
                           [h] * len(obj.places), [], dict(obj.attrs))
            notes.append(f"the net carries no timing: every place holds {exact_text(h)}")
    graph = as_teg_like(obj)
    if model == "SDF graph":
        notes.append("transitions are the firings actor_i of one iteration (the homogeneous "
                     "expansion); the period is the time per iteration")
    res = CycleTimeResult(graph.name, model, graph.n_transitions, len(graph.arrays().src),
                          notes=notes)
    return graph, res


def _holding(value: Any) -> Fraction:
    if value is None:
        return Fraction(0)
    try:
        h = exact_time(value, "default holding")
    except MaxPlusValueError:
        raise InputError(f"expected an exact time such as 1, 0.5 or 7/3, got {value!r}",
                         "--default-holding") from None
    if h < 0:
        raise InputError(f"a holding time must be >= 0, got {h}", "--default-holding")
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
    num, den = r.cycle_time_num, r.cycle_time_den
    top = (r.ratio.numerator, r.ratio.denominator)
    uniform = bool((den > 0).all() and (num * top[1] == den * top[0]).all())
    if not uniform:
        res.cycle_times = {names(i): (None if d == 0 else Fraction(int(m), int(d) * a.scale))
                           for i, (m, d) in enumerate(zip(num.tolist(), den.tolist()))}
        inputs = [k for k, v in res.cycle_times.items() if v is None]
        if inputs:
            shown = ", ".join(inputs[:10]) + (" ..." if len(inputs) > 10 else "")
            res.notes.append(f"{len(inputs)} transition(s) have no circuit upstream (inputs "
                             f"fired from outside), so no cycle time: {shown}")


def _namer(graph: Any) -> Callable[[int], str]:
    if hasattr(graph, "name_of"):
        return graph.name_of
    names = graph.transition_names
    return lambda i: names[i]


def _place_label(graph: Any, p: int) -> str:
    if hasattr(graph, "place_label"):
        return graph.place_label(int(p))
    return graph.places[int(p)].name
