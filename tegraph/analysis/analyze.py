"""`analyze_skeleton`: every figure of ``docs/skeleton.md`` §4 for one skeleton.

How each figure is obtained:

- **live / deadlocks**: token-free circuits of the timed event graph (Commoner
  et al. [1]_), cross-checked by the minimal p-semiflows
  (:mod:`.invariants`).
- **reorder**: the polynomial precedence-graph test of :mod:`.reorder`, whose
  answer is re-checked by rebuilding the reordered graph.
- **periods** (cycle times): the certified maximum cycle ratio of
  :func:`maxplus.max_cycle_ratio` (Howard's policy iteration [2]_); with it,
  the unbounded places (output event slower than input event) and the
  critical circuits.
- **transient, overrun_at**: exact dater simulation with a proof of the
  periodic regime (:mod:`.dynamics`).
- **slack**: longest circuits through each ``T.compute`` under the weights
  ``holding - λ·tokens``, by Dijkstra [3]_ after Johnson's reweighting [4]_
  with the Howard potentials (which are exactly the feasible potentials
  needed).

Each step is a function of the graph (``_EventGraph``, built once) and
of the results of the steps before it.

References
----------
.. [1] F. Commoner, A. W. Holt, S. Even, A. Pnueli, "Marked directed graphs",
   Journal of Computer and System Sciences 5(5), 511–523, 1971.
.. [2] J. Cochet-Terrasson, G. Cohen, S. Gaubert, M. Mc Gettrick,
   J.-P. Quadrat, "Numerical computation of spectral elements in max-plus
   algebra", IFAC Conference on System Structure and Control, 1998.
.. [3] E. W. Dijkstra, "A note on two problems in connexion with graphs",
   Numerische Mathematik 1, 269–271, 1959.
.. [4] D. B. Johnson, "Efficient algorithms for shortest paths in sparse
   networks", Journal of the ACM 24(1), 1–13, 1977.
"""

from __future__ import annotations

import dataclasses
import gc
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from maxplus import CycleRatioResult, max_cycle_ratio
from maxplus.scalar import display_text

from ..model.build import UnboundedKind, activation_end, build_teg, task_chain, unbounded_kind
from ..model.elements import flow_list
from ..model.platform import platform_of
from ..model.skeleton import Skeleton
from ..model.structure import Structure
from ..model.teg import Place, TimedEventGraph
from .chains import ChainPath, DaterTrace, chain_paths, chain_reports, trace_request
from .deadlocks import skeleton_deadlocks
from .dynamics import DaterSimulation, OverrunWatch, Regime, explore
from .invariants import semiflow_census
from .liveness import token_free_circuits
from .processors import MAX_EVENTS, schedule_on_processors
from .regime_bounds import autonomous_from
from .reorder import reorder_ports
from .repair import fix_ports
from .results import (
    Deadlock,
    GroupReport,
    InvariantCheck,
    Reorder,
    Report,
    TaskReport,
    UnboundedPlace,
)
from .slack import shortest_circuits_through

__all__ = ["analyze_skeleton", "unbounded_mask"]

_PER_GROUP_SCALE = True
"""Each group's times on its own scale (False: every group on the common scale of
all, as :meth:`~tegraph.model.teg.TimedEventGraph.arrays` gives; the tests compare both)."""




def analyze_skeleton(skeleton: Skeleton, max_steps: int = 100_000, semiflow_budget: int = 2000,
                     semiflow_max_places: int = 2_000_000, *, processors: bool = False,
                     max_events: int = MAX_EVENTS, structure: Structure | None = None,
                     chains: Sequence[Sequence[str]] = ()) -> Report:
    """Analyze a synchronization skeleton: deadlocks, periods, overruns, slack (spec §4).

    Parameters
    ----------
    skeleton : Skeleton
        From :func:`tegraph.load_skeleton` or built in code.
    max_steps : int
        Budget on the firing index of the dater simulation; only reached for
        overruns that cannot be decided otherwise (the report says so).
    semiflow_budget : int
        Largest number of candidate rows of one p-semiflow enumeration (a batch
        of strongly connected components of a few hundred places).
    semiflow_max_places : int
        Above this many places in all, the semiflow cross-check is skipped
        (the report says so).
    processors : bool
        Also decide the skeleton on its processors (spec §4b,
        :func:`~tegraph.analysis.processors.schedule_on_processors`), in
        ``report.schedule``; False: every task on a processor of its own (§3).
    max_events : int
        Budget of event firings of the schedule on processors.
    structure : Structure, optional
        ``Structure.of(skeleton)``, if known; the report carries it (``report.structure``).
    chains : sequence of task-name sequences
        Chains whose latency to report (spec §4c, ``report.chains``), besides the
        skeleton's own ``chains``.

    Returns
    -------
    Report
        Without its design section (:func:`tegraph.analyze` adds it).

    Raises
    ------
    SkeletonError
        A chain names an unknown task, a task twice, or two consecutive tasks with
        no link from the first to the second.

    See Also
    --------
    tegraph.analyze : this analysis and the design section of ORCCAD §6.

    Examples
    --------
    A task of duration 2 on a clock of period 10:

    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 10}}})
    >>> r = analyze_skeleton(sk)
    >>> r.live, r.consistent, r.tasks["A"].period, r.tasks["A"].slack
    (True, True, Fraction(10, 1), Fraction(8, 1))
    """
    with _cyclic_gc_paused():
        structure = Structure.of(skeleton) if structure is None else structure
        graph = _EventGraph.of(skeleton, structure)
        deadlocks, dead_groups = _deadlocks(graph)
        live = not deadlocks
        reorder = None if live else _reorder(skeleton, deadlocks, graph)
        periods = _cycle_times(graph, dead_groups)
        unbounded = _unbounded_places(graph, periods)
        groups = _group_reports(graph, periods, dead_groups, unbounded)
        tasks = _task_reports(graph, groups)
        _slack(graph, periods, groups, tasks)
        paths = chain_paths(skeleton, graph.teg, chains)
        recorded = _daters_recorded(graph, groups, paths)
        steps, notes = _dynamics(graph, periods, groups, tasks, max_steps, recorded)
        invariants = _invariants(graph, live, semiflow_budget, semiflow_max_places)
        overrun = any(t.overrun_at is not None for t in tasks.values())
        consistent = live and not unbounded and not overrun
        methods = _methods(deadlocks, groups, periods, invariants, tasks, steps)
        # The platform once, for the schedule, its cross-checks and the rules (report.platform).
        platform = platform_of(skeleton, structure)
        schedule = None
        if processors:  # on the groups and the event graph computed above, not again
            schedule = schedule_on_processors(
                skeleton, graph.teg, groups, platform=platform, max_events=max_events,
                intervals=False,  # the timeline draws its own
                trace=trace_request(paths) if paths else None)
            methods["schedule"] = schedule.method
        chain_figures = chain_reports(
            skeleton, graph.teg, groups, paths, None if schedule is None else schedule.trace,
            max_events=max_events,
            daters=None if recorded is None else _dater_trace(graph, groups, paths, recorded))
        if chain_figures:
            methods["chains"] = _chains_method(schedule is not None)
        return Report(
            name=skeleton.name, unit=skeleton.unit, live=live, consistent=consistent,
            deadlocks=deadlocks, reorder=reorder, groups=groups, tasks=tasks,
            unbounded_places=unbounded, invariants=invariants, methods=methods,
            notes=notes, source=skeleton.source, schedule=schedule, structure=structure,
            chains=chain_figures,
            platform=platform,
        )


@contextmanager
def _cyclic_gc_paused() -> Iterator[None]:
    """Pause Python's cyclic garbage collector for the analysis (reference counting
    still frees every object as soon as it is unused).

    The analysis makes hundreds of thousands of long-lived containers (events,
    places, Fractions, small arrays) and no reference cycles to speak of, and
    each pass of the collector walks them again, a large share of the time on
    large skeletons, for the same peak memory. The collector is left as it was
    found (nested calls too).
    """
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


@dataclass(frozen=True)
class _EventGraph:
    """The timed event graph of a skeleton as arrays, and its groups (spec §4)."""

    sk: Skeleton
    teg: TimedEventGraph
    src: np.ndarray
    dst: np.ndarray
    tokens: np.ndarray
    holding: np.ndarray
    """Each place's holding time on its group's scale."""
    initial: np.ndarray
    scales: list[int]
    """Each group's scale: its times' least common denominator (spec §2 builds no place
    between two groups, so each group's times need only their own); then that of
    the ticks of clocks in no group."""
    n: int
    names: tuple[str, ...]
    group_tasks: list[list[str]]
    group_of_event: np.ndarray
    task_group: dict[str, int]
    events_of_group: list[np.ndarray]
    places_of_group: list[np.ndarray]
    position: np.ndarray
    """Each event's index in ``events_of_group`` of its group."""
    structure: Structure

    @classmethod
    def of(cls, skeleton: Skeleton, structure: Structure) -> _EventGraph:
        teg = build_teg(skeleton)
        a = teg.arrays()
        # Each event is in its task's (its clock's) group: spec §2 builds no place
        # between two groups (tests/tegraph/model/test_structure.py checks it).
        group_of_event = structure.group_of_event(teg)
        # Events and places of each group, split once (groups can be thousands).
        n_groups = len(structure.groups)
        events_of_group = _split_by(group_of_event, n_groups)
        # The times of each group on its own scale (the ticks of clocks in no group
        # on one more): int64 where the common scale of all groups would not fit.
        part = group_of_event[a.src]
        holding, initial, scales = teg.scaled_by_part(
            np.where(part < 0, n_groups, part) if _PER_GROUP_SCALE else np.zeros_like(part),
            n_groups + 1)
        if not _PER_GROUP_SCALE:
            scales = [scales[0]] * (n_groups + 1)
        position = np.zeros(teg.n_transitions, dtype=np.int64)
        if events_of_group:
            position[np.concatenate(events_of_group)] = np.concatenate(
                [np.arange(len(e)) for e in events_of_group])
        return cls(skeleton, teg, a.src, a.dst, a.tokens, holding, initial, scales,
                   teg.n_transitions, teg.transition_names,
                   [list(g) for g in structure.groups], group_of_event, dict(structure.group_of),
                   events_of_group, _split_by(group_of_event[a.src], n_groups), position,
                   structure)

    @property
    def places(self) -> tuple[Place, ...]:
        """The places as objects, made only when read (only for an unbounded place)."""
        return self.teg.places

    def compute(self, task: str) -> int:
        return self.teg.attrs["compute"][task]

    def scale_of_event(self) -> list[int]:
        """Each event's scale: its group's (:attr:`scales`)."""
        return [self.scales[k] for k in self.group_of_event.tolist()]  # -1: the last one

    def event_tasks(self, event: int) -> tuple[str, ...]:
        return self.teg.transition_attrs[event].get("tasks", ())


@dataclass(frozen=True)
class _Periods:
    """The certified cycle times of the live groups' events."""

    mcr: CycleRatioResult
    verified: bool
    cycle_times: list[Fraction | None]
    rank: np.ndarray
    """Each event's cycle time as its rank among the distinct ones, -1 for None."""
    live_event: np.ndarray
    live_places: np.ndarray


# ---------------------------------------------------------------------- structure


def _deadlocks(g: _EventGraph) -> tuple[list[Deadlock], set[int]]:
    out = skeleton_deadlocks(g.teg)
    dead_groups = {int(g.group_of_event[g.teg.index(d.events[0])]) for d in out}
    return out, dead_groups


def _reorder(skeleton: Skeleton, deadlocks: list[Deadlock], g: _EventGraph) -> Reorder:
    """Spec §4's reorder of the whole skeleton, and each deadlock's own advice.

    The reorder is spec §4's decision with one live order; a deadlock's advice is
    the repair :func:`~tegraph.analysis.repair.fix_ports` makes (fewest changes,
    footnote 6 preferred), the one ``tegraph fix`` writes, found on the deadlock's
    own group: with two dead groups, one repairable by a port order and one not,
    each is told what repairs it.
    """
    result = reorder_ports(skeleton)
    if result.possible and result.skeleton is not None:
        # The argument of reorder.py is re-checked on the rebuilt graph.
        rebuilt = build_teg(result.skeleton).arrays()
        left = token_free_circuits(rebuilt.src, rebuilt.dst, rebuilt.tokens,
                                   int(max(rebuilt.src.max(), rebuilt.dst.max())) + 1)
        if left:
            raise AssertionError("internal error: the reordered skeleton is not live")
    group_of = {id(d): int(g.group_of_event[g.teg.index(d.events[0])]) for d in deadlocks}
    advice = {k: _repair_advice(skeleton, g.group_tasks[k]) for k in sorted(set(group_of.values()))}
    for d in deadlocks:
        d.advice = advice[group_of[id(d)]]
    if result.possible:
        return Reorder(True, result.orders)
    return Reorder(False, result.orders, result.circuit, result.links)


def _repair_advice(skeleton: Skeleton, tasks: list[str]) -> str:
    """What to change in the group of ``tasks``: a port order, else a thread order, else links."""
    part = set(tasks)
    # The group cut out with its links, clocks and threads (a thread lies in one group:
    # its places join its tasks); threads keep their index in the file.
    numbers = [k for k, th in enumerate(skeleton.threads) if th[0] in part]
    repair = fix_ports(dataclasses.replace(
        skeleton, tasks={t: v for t, v in skeleton.tasks.items() if t in part},
        links=[x for x in skeleton.links if x.writer[0] in part and x.reader[0] in part],
        threads=[skeleton.threads[k] for k in numbers], chains=[]))
    ports = "; ".join(f"{c.task} {c.side} {flow_list(list(c.before))} -> {flow_list(list(c.after))}"
                      for c in repair.changes)
    if repair.threads:
        words = "; ".join(f"write threads[{numbers[t.index]}] as {flow_list(list(t.after))}"
                          for t in repair.threads)
        return (f"no port order helps, a thread order does: {words}"
                + (f"; then reorder ports: {ports}" if ports else "")
                + " (a thread runs its tasks one after the other: as declared, a task waits "
                "for one that runs after it)")
    if repair.live:
        return f"reorder ports (as tegraph fix does): {ports}"
    return ("no port order helps: make one of these links asynchronous "
            "(ASYN/ASYN), or break the circular wait with a clock: "
            + "; ".join(repair.links or ["(the circuit passes only through threads)"]))


# ---------------------------------------------------------------------- periods


def _cycle_times(g: _EventGraph, dead_groups: set[int]) -> _Periods:
    live_event = ~np.isin(g.group_of_event, sorted(dead_groups))
    lp = np.flatnonzero(live_event[g.src] & live_event[g.dst])
    mcr = max_cycle_ratio(g.src[lp], g.dst[lp], g.holding[lp], g.tokens[lp], n_nodes=g.n)
    verified = mcr.verify()
    # One Fraction per distinct cycle time (a group's events share a few): 30,000
    # divisions, each with its gcd, cost more than the analysis around them.
    # Each event's cycle time is on its group's scale.
    distinct: dict[tuple[int, int, int], int] = {}
    values: list[Fraction] = []
    slot = np.full(g.n, -1, dtype=np.int64)  # each event's value in `values`, -1 for None
    for e, key in enumerate(zip(mcr.cycle_time_num.tolist(), mcr.cycle_time_den.tolist(),
                                g.scale_of_event())):
        if key[1] == 0:  # no circuit reaches the event
            continue
        k = distinct.get(key)
        if k is None:
            k = distinct[key] = len(values)
            values.append(Fraction(key[0], key[1] * key[2]))
        slot[e] = k
    cycle_times = [None if k < 0 else values[k] for k in slot.tolist()]
    # The rank of each event's cycle time among the distinct ones (-1 for None):
    # a group's slowest event by one argmax, not by comparing Fractions.
    # Equal values rank alike (two groups' scales give one value two slots).
    order = sorted(range(len(values)), key=values.__getitem__)
    rank_of_slot = np.empty(len(values), dtype=np.int64)
    rank_of_slot[order] = np.cumsum([0] + [values[a] != values[b]
                                           for a, b in zip(order, order[1:])])[:len(order)]
    rank = np.full(g.n, -1, dtype=np.int64)
    rank[slot >= 0] = rank_of_slot[slot[slot >= 0]]
    return _Periods(mcr, verified, cycle_times, rank, live_event, lp)


def unbounded_mask(num: np.ndarray, den: np.ndarray, src: np.ndarray, dst: np.ndarray
                   ) -> np.ndarray:
    """Which places fill up without bound: their output event's cycle time
    ``num/den`` exceeds their input event's (chi_out > chi_in), compared exactly
    by cross-multiplication.

    Events of cycle times 3 and 5/2; place 0 goes 3 -> 5/2 (its reader is faster),
    place 1 goes 5/2 -> 3 (its reader is slower: it fills):

    >>> unbounded_mask(np.array([3, 5]), np.array([1, 2]), np.array([0, 1]),
    ...                np.array([1, 0])).tolist()
    [False, True]
    """
    return num[dst] * den[src] > num[src] * den[dst]


def _unbounded_places(g: _EventGraph, periods: _Periods) -> list[UnboundedPlace]:
    lp = periods.live_places
    slower = unbounded_mask(periods.mcr.cycle_time_num, periods.mcr.cycle_time_den,
                            g.src[lp], g.dst[lp])
    ct = periods.cycle_times
    # The text of each distinct cycle time once (10,000 clocked tasks slower than
    # their clocks share a few); the values are shared objects, told apart by id.
    texts: dict[int, str] = {}

    def text(value: Fraction) -> str:
        found = texts.get(id(value))
        if found is None:
            found = texts[id(value)] = display_text(value)
        return found

    out = []
    places = lp[slower].tolist()
    for k, a, b in zip(places, g.src[places].tolist(), g.dst[places].tolist()):
        kind = unbounded_kind(g.teg.place_kind(k))
        fast, slow = ct[a], ct[b]
        # The ends of a live place lie downstream of a circuit: their cycle times are set.
        assert fast is not None and slow is not None
        out.append(UnboundedPlace(g.names[a], g.names[b], kind, fast, slow,
                                  int(g.group_of_event[a]),
                                  _unbounded_advice(g, text(fast), text(slow), kind, a, b)))
    return out


def _unbounded_advice(g: _EventGraph, fast: str, slow: str, kind: UnboundedKind, a: int,
                      b: int) -> str:
    """What to do about an unbounded place ``a -> b``; ``fast`` and ``slow`` are the texts
    of the cycle times of ``a`` and of ``b``."""
    u = g.sk.unit
    writer = ", ".join(g.event_tasks(a))
    reader = ", ".join(g.event_tasks(b))
    if kind == "clock-overrun":
        return (f"{reader} needs {slow} {u} per activation but its clock ticks every {fast} {u}: "
                "its ticks queue up without bound (none is lost: each activation starts "
                f"further behind its tick). Lengthen the clock period to at least {slow} {u}, "
                "or drop one of the task's two synchronizations (Rule 1).")
    if kind == "messages-overwritten":
        return (f"{writer} posts every {fast} {u} but {reader} reads every {slow} {u}: "
                "messages are overwritten. Make the link ASYN/ASYN, or run both at one rate.")
    if kind == "requests-overwritten":
        return (f"{writer} requests every {fast} {u} but {reader} answers every {slow} {u}: "
                "requests pile up. Make the link ASYN/ASYN, or run both at one rate.")
    return (f"{g.names[b]} fires every {slow} {u}, {g.names[a]} every {fast} {u}: "
            "tokens pile up between them; give both one rate.")


def _group_reports(g: _EventGraph, periods: _Periods, dead_groups: set[int],
                   unbounded: list[UnboundedPlace]) -> list[GroupReport]:
    bad = {u.group for u in unbounded}
    ct = periods.cycle_times
    out = []
    for index, tasks in enumerate(g.group_tasks):
        clocks = list(g.structure.clocks[index])
        live = index not in dead_groups
        consistent = live and index not in bad
        period = None
        circuit: list[str] = []
        cycle_times = {}
        holdings: list[Fraction] = []
        tokens = None
        if live:
            events = g.events_of_group[index]
            cycle_times = {t: ct[g.compute(t)] for t in tasks}
            slowest = int(events[np.argmax(periods.rank[events])])  # the first of the slowest
            mcr = periods.mcr
            arcs = mcr.policy_circuit(slowest)
            circuit = [g.names[int(mcr.src[a])] for a in arcs.tolist()]
            holdings = [Fraction(int(w), g.scales[index]) for w in mcr.weight[arcs].tolist()]
            tokens = int(sum(int(t) for t in mcr.tokens[arcs].tolist()))
            if consistent:
                period = ct[slowest]
        out.append(GroupReport(index=index, tasks=list(tasks), clocks=clocks, live=live,
                               rate_consistent=consistent, period=period, transient=None,
                               critical_circuit=circuit,
                               # Type: the events of a live group have their cycle times.
                               cycle_times=cycle_times,  # type: ignore[arg-type]
                               critical_holdings=holdings, critical_tokens=tokens))
    return out


def _task_reports(g: _EventGraph, groups: list[GroupReport]) -> dict[str, TaskReport]:
    out = {}
    for name, task in g.sk.tasks.items():
        index = g.task_group[name]
        period = groups[index].cycle_times.get(name) if groups[index].live else None
        out[name] = TaskReport(name=name, group=index, period=period, overrun_at=None,
                               slack=None, critical=None, clock=task.clock,
                               duration=task.duration)
    return out


# ---------------------------------------------------------------------- slack


def _slack(g: _EventGraph, periods: _Periods, groups: list[GroupReport],
           tasks: dict[str, TaskReport]) -> None:
    cert = periods.mcr.certificate
    for group in groups:
        if not group.rate_consistent:
            continue
        events = g.events_of_group[group.index]
        places = g.places_of_group[group.index]
        W = int(cert.ratio_num[events[0]])
        T = int(cert.ratio_den[events[0]])
        s, d = g.src[places], g.dst[places]
        chains = [task_chain(g.teg, t) for t in group.tasks]
        arcs = (s, d, g.holding[places], g.tokens[places], cert.potential)
        weights = None
        if len(places) >= _SLACK_ARRAYS:
            weights = _circuit_weights_int64(*arcs, W, T, chains)
        reduced, upper = weights or _circuit_weights_exact(*arcs, W, T, chains)
        sources = [g.compute(t) for t in group.tasks]
        # A group's tasks share a few slacks: one Fraction (and its gcd) for each.
        slack_of: dict[int, Fraction] = {}
        for t, shortest in zip(group.tasks, shortest_circuits_through(
                events, s, d, reduced, sources, upper)):
            assert shortest is not None  # on its own chain circuit (above): a minimum exists
            slack = slack_of.get(shortest)
            if slack is None:
                slack = slack_of[shortest] = Fraction(shortest, T * g.scales[group.index])
            tasks[t].slack = slack
            tasks[t].critical = shortest == 0  # T * scale > 0: the slack is 0 exactly then


_SLACK_ARRAYS = 128
"""Places from which a group's circuit weights are computed as arrays: below, the
fixed cost of the numpy calls exceeds the Python loops (measured on random groups:
``benchmarks/results/constants.md``)."""


def _circuit_weights_exact(s: np.ndarray, d: np.ndarray, holding: np.ndarray,
                           tokens: np.ndarray, X: np.ndarray, W: int, T: int,
                           chains: list[list[int]]) -> tuple[list[int], list[int | None]]:
    """Johnson's reduced weight of each place and a circuit bound for each chain.

    Parameters
    ----------
    s, d : numpy.ndarray of int
        Input and output event of each place of a group.
    holding, tokens : numpy.ndarray of int
        Holding time (on the group's scale) and initial tokens of each place.
    X : numpy.ndarray of int
        Every event's potential (scaled by the group's ``T``).
    W, T : int
        The group's cycle time ``W / T`` (on its scale).
    chains : list of list of int
        The events of each task's chain, in order.

    Returns
    -------
    reduced : list of int
        ``-(holding*T - W*tokens + X[s] - X[d])`` per place: non-negative, 0 on
        the critical circuits.
    upper : list of int or None
        Per chain, the weight of its circuit by the lightest place of each hop
        (None when a hop has no place).
    """
    w_prime = [int(h) * T - W * int(m) for h, m in zip(holding.tolist(), tokens.tolist())]
    reduced = [-(wp + int(X[a]) - int(X[b]))
               for wp, a, b in zip(w_prime, s.tolist(), d.tolist())]
    # Every task lies on its own chain circuit, so each minimum exists,
    # and that circuit's length bounds how far each search must go.
    lightest: dict[tuple[int, int], int] = {}
    for a, b, r in zip(s.tolist(), d.tolist(), reduced):
        lightest[a, b] = min(r, lightest.get((a, b), r))
    upper: list[int | None] = []
    for chain in chains:
        hops = [lightest.get(hop) for hop in zip(chain, chain[1:] + chain[:1])]
        known = [h for h in hops if h is not None]
        upper.append(sum(known) if len(known) == len(hops) else None)
    return reduced, upper


def _circuit_weights_int64(s: np.ndarray, d: np.ndarray, holding: np.ndarray,
                           tokens: np.ndarray, X: np.ndarray, W: int, T: int,
                           chains: list[list[int]]
                           ) -> tuple[np.ndarray, list[int | None]] | None:
    """:func:`_circuit_weights_exact` in int64 arrays, None when a value may not fit.

    Exact: every weight is an integer on the group's scale, and the bound
    below caps each reduced weight and each chain's sum of them (at most one
    place per event of the chain) under 2**63.
    """
    if not len(s) or not chains or max(abs(W), abs(T)) >= 2**63:
        return None
    ends = np.concatenate((s, d))
    # Python ints: the bound itself must not overflow.
    largest = (max(abs(int(holding.max())), abs(int(holding.min()))) * abs(T)
               + abs(W) * max(abs(int(tokens.max())), abs(int(tokens.min())))
               + int(X[ends].max()) - int(X[ends].min()))
    lengths = np.fromiter((len(c) for c in chains), dtype=np.int64, count=len(chains))
    flat = np.fromiter((e for c in chains for e in c), dtype=np.int64, count=int(lengths.sum()))
    n = max(int(ends.max()), int(flat.max(initial=0))) + 1
    if largest * max(int(lengths.max()), 1) >= 2**63 or n >= 2**31:  # n * n < 2**63
        return None
    if max(abs(int(tokens.max())), abs(int(tokens.min()))) >= 2**63:
        return None  # with W = 0 the bound above holds, but the tokens are read as int64
    s64, d64 = s.astype(np.int64), d.astype(np.int64)
    # Only differences of potentials matter: shifted by the least, they fit in
    # int64 by the bound above even when the potentials themselves do not (a
    # downstream group's may lie past 2**63, close together).
    x = (X[ends] - X[ends].min()).astype(np.int64)
    reduced = -(holding.astype(np.int64) * T - W * tokens.astype(np.int64)
                + x[:len(s)] - x[len(s):])
    # The lightest place of each (input, output) pair, keyed by one int64 each.
    key = s64 * n + d64
    order = np.lexsort((reduced, key))
    first = np.r_[True, key[order][1:] != key[order][:-1]]
    pair_key, pair_weight = key[order][first], reduced[order][first]
    # Each chain's hops e[i] -> e[i+1], the last back to the first.
    start = np.cumsum(lengths) - lengths
    following = np.arange(1, len(flat) + 1)
    following[start + lengths - 1] = start
    hop = flat * n + flat[following]
    at = np.minimum(np.searchsorted(pair_key, hop), len(pair_key) - 1)
    found = pair_key[at] == hop
    total = np.add.reduceat(np.where(found, pair_weight[at], 0), start)
    complete = np.logical_and.reduceat(found, start)
    upper = [int(v) if ok else None for v, ok in zip(total.tolist(), complete.tolist())]
    return reduced, upper


# ---------------------------------------------------------------------- dynamics


def _dynamics(g: _EventGraph, periods: _Periods, groups: list[GroupReport],
              tasks: dict[str, TaskReport], max_steps: int,
              record: tuple[np.ndarray, list] | None = None) -> tuple[int, list[str]]:
    """Transients and overruns; returns the number of activations simulated, and notes.

    ``record``: (events, rows), the daters of these events at each step appended to
    rows (:func:`~.dynamics.explore`)."""
    ct = periods.cycle_times
    regimes: list[Regime] = []
    group_regime: dict[int, int] = {}
    for group in groups:
        if group.rate_consistent:
            group_regime[group.index] = len(regimes)
            events = g.events_of_group[group.index]
            # Type: a rate-consistent group has its period (both lines).
            regimes.append(Regime(events, group.period.numerator  # type: ignore[union-attr]
                                  * g.scales[group.index],
                                  group.period.denominator))  # type: ignore[union-attr]
    watches: list[OverrunWatch] = []
    watched: list[str] = []
    closure_regime: dict[bytes, int | None] = {}
    local_graphs: dict[int, tuple] = {}
    # Cycle times compared by their ranks (ints), not as Fractions: 10,000 clocked tasks.
    rank = periods.rank.tolist()
    for name, t in tasks.items():
        clock = g.sk.tasks[name].clock
        if clock is None or not groups[t.group].live:
            continue
        end, tick = activation_end(g.teg, name), g.teg.attrs["clocks"][clock]
        # spec §4: a dater plus a constant, on the group's scale (a multiple of the
        # duration's denominator: the duration is the holding time of the place leaving
        # T.compute), by integer arithmetic (a Fraction product costs a gcd a task).
        last, o = end.event, end.offset
        offset = o.numerator * (g.scales[t.group] // o.denominator) if o else 0
        if t.group in group_regime:
            watches.append(OverrunWatch(last, tick, group_regime[t.group], end_offset=offset))
        else:
            period = ct[tick]
            proven = None
            if rank[last] == rank[tick]:  # both live: ranks >= 0
                upstream, found = _closure(g, ct, local_graphs, t.group, last, period, max_steps)
                key = upstream.tobytes()
                if key not in closure_regime:
                    closure_regime[key] = None if found is None else len(regimes)
                    if found is not None:
                        regimes.append(Regime(found[0], period.numerator * g.scales[t.group],
                                              period.denominator, start=found[1]))
                proven = closure_regime[key]
            # Without a proven regime, only an overrun ends the search; it
            # must come when the task is slower than its clock.
            certain = rank[last] > rank[tick]
            watches.append(OverrunWatch(last, tick, proven, certain=certain, end_offset=offset))
        watched.append(name)
    notes: list[str] = []
    if not regimes and not watches:
        return 0, notes
    sim = DaterSimulation(g.src, g.dst, g.tokens, g.holding, g.initial, g.n, periods.live_event)
    # Each regime's cycle time is given on its group's scale, as the daters are.
    steps = explore(sim, 1, regimes, watches, max_steps, record)
    for index, r in group_regime.items():
        found = regimes[r]
        if found.transient is not None and found.cyclicity is not None:
            groups[index].transient = (found.transient, found.cyclicity)
    for name, watch in zip(watched, watches):
        tasks[name].overrun_at = watch.overrun_at
        if watch.overrun_at is not None:
            # Type: a watched task has a clock (the loop above skips the others).
            ticks = g.sk.clocks[g.sk.tasks[name].clock]  # type: ignore[index]
            tasks[name].overrun_tick = ticks.phase + (watch.overrun_at - 1) * ticks.period
        tasks[name].overrun_decided = watch.decided
        if watch.method == "max-plus powers":
            notes.append(f"overrun of {name} located exactly by (max,+) matrix powers, not "
                         "simulated: it is slower than its clock (docs/analysis.md)")
        if not watch.decided:
            notes.append(
                f"overrun of {name} undecided after {steps} activations: tasks upstream "
                "of it run faster than its clock, so no state repeats; raise `max_steps`")
    return steps, notes


def _closure(g: _EventGraph, ct: list[Fraction | None], local_graphs: dict[int, tuple],
             group: int, last: int, period: Fraction, max_steps: int):
    """Upstream closure of ``last`` in its group, and the proven start of its regime.

    ``local_graphs`` caches each group's relabelled graph (its places' ends
    numbered inside the group, and each event's predecessors) across the tasks
    of one analysis.
    """
    if group not in local_graphs:
        events = g.events_of_group[group]
        places = g.places_of_group[group]
        ls, ld = g.position[g.src[places]], g.position[g.dst[places]]
        # A group is a few dozen events: a breadth-first search in Python costs
        # less than building a sparse graph for scipy's.
        before: list[list[int]] = [[] for _ in range(len(events))]
        for a, b in zip(ls.tolist(), ld.tolist()):
            before[b].append(a)
        local_graphs[group] = (events, places, ls, ld, before)
    events, places, ls, ld, before = local_graphs[group]
    start = int(g.position[last])
    seen, stack = {start}, [start]
    while stack:
        for e in before[stack.pop()]:
            if e not in seen:
                seen.add(e)
                stack.append(e)
    up_local = np.array(sorted(seen), dtype=np.int64)
    found = autonomous_from(up_local, [ct[e] for e in events.tolist()], period, ls, ld,
                            g.tokens[places], g.holding[places], g.initial[places],
                            g.scales[group], len(events), max_steps)
    upstream = events[up_local]
    if found is None:
        return upstream, None
    return upstream, (events[found[0]], found[1])


# ---------------------------------------------------------------------- invariants


def _invariants(g: _EventGraph, live: bool, budget: int, max_places: int) -> InvariantCheck:
    n_places = len(g.src)
    if n_places > max_places:
        return InvariantCheck(False, None, None, reason=(
            f"{n_places} places exceed the semiflow budget of {max_places}"))
    incidence = g.teg.incidence_matrix().tocsr()
    # In a marked graph the support of a minimal p-semiflow is an elementary
    # circuit, so it lies inside one strongly connected component: places
    # between components carry none, and components are enumerated apart,
    # a few hundred places at a time (a block-diagonal table stays small).
    graph = sp.csr_matrix((np.ones(n_places), (g.src, g.dst)), shape=(g.n, g.n))
    _, component = connected_components(graph, directed=True, connection="strong")
    inside = np.flatnonzero(component[g.src] == component[g.dst])
    order = inside[np.argsort(component[g.src[inside]], kind="stable")]
    labels = component[g.src[order]]
    starts = np.flatnonzero(np.concatenate(([True], labels[1:] != labels[:-1]))).tolist()
    batches, first = [], 0
    for k, end in enumerate(starts[1:] + [len(order)]):
        if end - first >= 256 or k == len(starts) - 1:
            batches.append(order[first:end])
            first = end
    blocks = [(places, np.unique(np.concatenate([g.src[places], g.dst[places]])))
              for places in batches]
    census = semiflow_census(incidence, blocks, g.tokens, budget)
    if census.failed is not None:
        return InvariantCheck(False, None, None, reason=(
            f"more than {budget} candidate semiflows among the circuits "
            f"through {g.names[int(blocks[census.failed][1][0])]}"))
    return InvariantCheck(True, census.count, (census.unmarked == 0) == live, census.unmarked)


def _methods(deadlocks: list[Deadlock], groups: list[GroupReport], periods: _Periods,
             inv: InvariantCheck, tasks: dict[str, TaskReport], steps: int) -> dict[str, str]:
    """How each verdict was obtained, claiming only what was computed."""
    n_dead = len(deadlocks)
    circuits = "none" if n_dead == 0 else f"{n_dead} found"
    if inv.computed:
        cross = ("semiflow cross-check agrees" if inv.liveness_agrees
                 else "semiflow cross-check DISAGREES")
        cross += f" ({inv.count} minimal p-semiflows, {inv.unmarked} without token)"
    else:
        cross = f"semiflow cross-check not run: {inv.reason}"
    live = [g for g in groups if g.live]
    dead = len(groups) - len(live)
    if not live:
        cycle = "no live group: no period computed"
    else:
        cycle = ("maximum cycle ratio by exact Howard policy iteration; certificate "
                 + ("verified" if periods.verified else "FAILED"))
        if dead:
            cycle = f"periods of the {len(live)} live group(s) only ({dead} dead): " + cycle
    return {
        "liveness": f"token-free circuits: {circuits} (Commoner's theorem); {cross}",
        "periods": cycle,
        "timing": _timing_method(groups, tasks, steps),
        "slack": ("longest circuits through each compute event (Dijkstra after Johnson "
                  "reweighting with the Howard potentials), exact"
                  if any(g.rate_consistent for g in groups)
                  else "no slack computed: no group is rate-consistent"),
    }


def _daters_recorded(g: _EventGraph, groups: list[GroupReport], paths: list[ChainPath]
                     ) -> tuple[np.ndarray, list] | None:
    """The events whose daters a chain reads with a processor per task (§3), in the
    rate-consistent groups (whose periodic regime the dater simulation proves): each
    chain event and each chain task's compute (its job's start; its end is the
    duration later); None without a chain."""
    if not paths:
        return None
    consistent = {t for gr in groups if gr.rate_consistent for t in gr.tasks}
    events = {x.event for p in paths for x in p.instants
              if x.kind == "event" and x.task in consistent}
    events |= {g.compute(t) for p in paths for t in p.tasks if t in consistent}
    return np.array(sorted(events), dtype=np.int64), []


def _dater_trace(g: _EventGraph, groups: list[GroupReport], paths: list[ChainPath],
                 recorded: tuple[np.ndarray, list]) -> DaterTrace:
    """What the chains read of the daters (§3), for the groups whose regime is proven."""
    events, rows = recorded
    return DaterTrace(events=events, rows=rows, scales=g.scales,
                      group_of_event=g.group_of_event, groups=groups,
                      durations={t: g.sk.tasks[t].duration for p in paths for t in p.tasks},
                      compute={t: g.compute(t) for p in paths for t in p.tasks})


def _chains_method(processors: bool) -> str:
    """The ``chains`` line of the methods: how the latency of each chain is obtained."""
    where = ("on the schedule on processors (§4b) and with a processor per task (§3)"
             if processors else "with a processor per task (§3)")
    return ("each chain's data traced back from each output to the sample it uses (spec §4c), "
            f"{where}: reads, writes, starts and ends recorded while the schedule proves "
            "its periodic regime, the figures exact over one period of the regime the "
            "chain's parts share (docs/analysis.md)")


def _timing_method(groups: list[GroupReport], tasks: dict[str, TaskReport], steps: int) -> str:
    """The ``timing`` line of the methods: what the dater simulation proved, if it ran."""
    if not any(g.live for g in groups):
        return "no dater simulation: every group is dead"
    consistent = [g for g in groups if g.rate_consistent]
    watched = [t for t in tasks.values() if t.clock is not None and groups[t.group].live]
    if steps == 0:
        return ("no dater simulation: no rate-consistent group (no transient to find) and "
                "no clocked task in a live group (no overrun to watch)")
    parts = [f"exact dater simulation over {steps} activations"]
    found = [g for g in consistent if g.transient is not None]
    if found:
        parts.append(f"the periodic regime of {len(found)} rate-consistent group(s) proven by a "
                     "repeated state (homogeneity of the (max,+) recurrence)")
    if len(found) < len(consistent):
        parts.append(f"{len(consistent) - len(found)} periodic regime(s) not found within "
                     "the budget")
    undecided = [t for t in watched if not t.overrun_decided]
    decided = len(watched) - len(undecided)
    if decided:
        parts.append(f"the overrun of {decided} clocked task(s) decided (the first one seen, "
                     "or none up to a proven periodic regime)")
    if undecided:
        parts.append(f"{len(undecided)} overrun(s) undecided within the budget")
    dead = sum(not g.live for g in groups)
    if dead:
        parts.append(f"{dead} dead group(s) not simulated")
    return "; ".join(parts)


def _split_by(key: np.ndarray, n_parts: int) -> list[np.ndarray]:
    """Indices i grouped by key[i] in 0..n_parts-1 (others dropped), each sorted."""
    order = np.argsort(key, kind="stable")
    bounds = np.searchsorted(key[order], np.arange(n_parts + 1))
    return [order[bounds[g]:bounds[g + 1]] for g in range(n_parts)]
