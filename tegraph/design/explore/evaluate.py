"""Judge variants of a design space: analyze, repair the port order, schedule, measure.

One variant is judged as ``tegraph analyze`` would judge it, on its processors
(spec v1.2 §4b). Step 1 is composed, when the variant is live, from the figures of its
groups, each analysed once per configuration of its own choices (:mod:`.incremental`,
the same result as the whole analysis):

1. :func:`~tegraph.analysis.analyze.analyze_skeleton` on the variant's skeleton
   (spec §4, every task on a processor of its own);
2. when it is not live but some port order makes it live
   (:func:`~tegraph.analysis.reorder.reorder_ports`), the reordered skeleton is
   analyzed instead and the variant is marked ``repaired`` (the orders depend
   only on the protocols, Rule A of :mod:`.prune`, so they are found
   once per protocol assignment in a batch);
3. when live and consistent, on its processors: rule C of :mod:`.prune`
   (:func:`~.prune.overloaded`: a processor whose groups with a clock need
   more than all its time; proven not schedulable, without the schedule), else the
   exact schedule (:func:`~tegraph.analysis.processors.schedule_on_processors`,
   within the space's ``max_events``): ``schedulable`` True, False (an overrun, a
   starved task or a growing place, named in the reason) or None (undecided within
   the budget: rejected as undecided, never kept). The response-time test
   (:func:`~tegraph.design.schedulability.schedulability`) decides nothing: it is
   kept as a cross-check (``rta``) and for the latency bounds;
4. the objectives:

   - ``latency:A,B,C``, ``age:A,B,C``, ``reaction:A,B,C``: the chain's first use,
     age and reaction on processors (spec §4c, :mod:`tegraph.analysis.chains`),
     exact for the declared phases, read off the very schedule that decides the
     variant (it records the chains' reads and writes). Where the figure is
     undecided (a part of the chain without a proven regime) the variant is
     rejected with that reason, never ranked by a bound (its kind, ``exact`` or
     ``undecided``, is kept beside it);
   - ``period`` (the *period ratio*, on processors): the largest, over the tasks,
     of the task's period on processors over its designed period
     (:attr:`DesignSpace.reference_periods`): the period, in the *input* skeleton,
     of the task's own clock, or for a task without a clock of the fastest clock
     of its input group. 1: every task runs at its designed rate; 1/2, twice as
     fast (a faster clock); 3, some task three times slower (a task pulled into a
     slower group, or a free-running task slowed down by its processor). Tasks
     with no reference are not counted;
   - ``load``: the busiest processor's utilization on processors, ``Σ C/T`` with
     T each task's period on processors (what the processor really gives per unit
     of time once the schedule is periodic);
   - ``utilization``: the sum of every processor's load (what a faster loop costs
     on the processors that are not the busiest).

   These three are None (undefined) where a task of the count has no period on
   processors (undecided, starved, or the schedule not run: rule C).

   Where tasks run (when processors are offered, :mod:`.allocation`):
   ``processors``, the number of processors the variant uses; ``traffic``, the
   number of links whose two tasks run on different processors (each with its
   delay of spec §4d: :meth:`~.space.DesignSpace.crossing`); ``busiest``, the
   largest, over the processors, of ``Σ duration(T)/period(T)`` over the tasks T of
   a group with a clock, ``period(T)`` the task's §4 period (a processor per task:
   its group's clock period, in a consistent variant): what the placement asks of the
   processor (rule C's load; a free-running group asks nothing, it takes the time
   left), defined once the variant is consistent, also where the schedule on
   processors is undecided.

A variant whose allocation puts a SYN/SYN link across processors with a positive
network delay is not a skeleton spec §1 accepts (a rendezvous is one event): it is
rejected without analysis (``judged="pruned"``, :data:`RENDEZVOUS`).

Besides the objectives: the number of Rule 2 findings of section 6 (SYN/SYN
links, and ASYN/ASYN links between groups of one rate: :func:`rule2_findings`),
which breaks ties between designs of equal objectives, and the constraints of
the space (:class:`~.objectives.Constraints`), which a kept design meets.

A variant is *kept* when it is live (perhaps after the repair), consistent
(spec §4: no unbounded place, no overrun), schedulable on its processors (§4b,
decided True) and meets the constraints; unless the space keeps them
(``Constraints.free_running``), a variant in which a task runs free that the input
design runs on a clock (:func:`free_running`: a link made ASYN/ASYN cut it from its
clock, and it now runs as often as its processor lets it) is not kept either.
Everything is exact: Fractions, no tolerance.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import KW_ONLY, dataclass, field, replace
from fractions import Fraction
from typing import Any

from maxplus.scalar import exact_text

from ...analysis.analyze import analyze_skeleton
from ...analysis.chains import ChainFigures, chain_paths, figures_on, trace_request
from ...analysis.processors import ProcessorSchedule, schedule_on_processors
from ...analysis.reorder import reorder_ports
from ...analysis.results import Report
from ...model.build import build_teg
from ...model.elements import link_name
from ...model.platform import crosses, processor_of
from ...model.skeleton import Protocol, Skeleton
from ...model.structure import Structure
from ..schedulability import Schedulability, schedulability
from .demand import processor_shares
from .incremental import judge_of
from .objectives import CHAIN_FIGURES, PLACEMENT_OBJECTIVES, chain_objective
from .prune import overloaded
from .space import DesignSpace

__all__ = ["FREE_RUNNING", "RENDEZVOUS", "VariantResult", "evaluate_batch", "evaluate_variant",
           "free_running", "placement_objectives", "rejection", "rule2_findings"]

ANALYZED, PRUNED, FAILED = "analyzed", "pruned", "failed"


@dataclass
class VariantResult:
    """The verdict and objectives of one variant.

    Attributes
    ----------
    variant : int
        Its number in the design space.
    judged : str
        ``"analyzed"``, ``"pruned"`` (settled by a proven rule, without
        analysis) or ``"failed"`` (the evaluation raised; ``reason`` says what).
    live : bool or None
        Live, perhaps after the port repair.
    repaired : bool
        The port orders were changed to make it live (``orders`` says how).
    consistent : bool or None
    schedulable : bool or None
        On its processors (spec §4b), once consistent: True or False, proven (by
        the exact schedule, or by rule C), or None: undecided within the space's
        ``max_events`` (the variant is not kept; its reason says why).
    objectives : dict of str to Fraction or None
        Every objective of the space (None where undefined).
    kinds : dict of str to str
        ``exact`` or ``undecided`` for each chain objective (undecided: not kept).
    reason : str
        Why it is not kept (empty when kept).
    seconds : float
        Time spent judging it.
    rule2 : int or None
        Rule 2 findings of section 6 in the judged skeleton (None when not analyzed):
        the tie-breaker of the front.
    meets : bool or None
        Meets the constraints of the space (None when not reached, or none).
    rta : bool or None
        The response-time test's verdict (a cross-check, never the verdict; None
        when not run or undecided). Not written to the results file.
    """

    variant: int
    judged: str
    # The rest by keyword only: eleven fields, most of them flags or None, cannot be read
    # in a positional call; the variant and its judgement (always given) can.
    _: KW_ONLY
    live: bool | None = None
    repaired: bool = False
    consistent: bool | None = None
    schedulable: bool | None = None
    objectives: dict[str, Fraction | None] = field(default_factory=dict)
    kinds: dict[str, str] = field(default_factory=dict)
    orders: dict[str, dict[str, list[str]]] = field(default_factory=dict)
    reason: str = ""
    seconds: float = 0.0
    rule2: int | None = None
    meets: bool | None = None
    rta: bool | None = field(default=None, compare=False)

    @property
    def kept(self) -> bool:
        """Live, consistent, schedulable on its processors (decided: an undecided
        schedule keeps nothing), every chain objective decided, and not against a
        constraint."""
        return bool(self.live and self.consistent and self.schedulable is True
                    and "undecided" not in self.kinds.values() and self.meets is not False)


RENDEZVOUS = "a rendezvous across processors"
"""How the reason of a variant whose allocation puts a delayed SYN/SYN link across
processors begins."""

REJECTIONS = ("failed to be judged", RENDEZVOUS, "dead whatever the port order",
              "an unbounded place", "an overrun", "not schedulable on processors",
              "undecided within max_events", "a chain's latency undecided",
              "a free-running task", "against a constraint")
"""Why a variant is not kept, in the order the judgement meets them (the unbounded
place and the overrun of spec §4, with a processor per task; then §4b)."""


def rejection(result: VariantResult) -> str | None:
    """Why ``result`` is not kept, as one of :data:`REJECTIONS` (None when kept).

    >>> rejection(VariantResult(3, PRUNED, live=False))
    'dead whatever the port order'
    """
    if result.judged == FAILED:
        return REJECTIONS[0]
    if result.reason.startswith(RENDEZVOUS):
        return REJECTIONS[1]
    if not result.live:
        return REJECTIONS[2]
    if not result.consistent:
        return REJECTIONS[4] if result.reason.startswith("overrun") else REJECTIONS[3]
    if result.schedulable is False:
        return REJECTIONS[5]
    if result.schedulable is None:
        return REJECTIONS[6]
    if "undecided" in result.kinds.values():
        return REJECTIONS[7]
    if result.meets is False:
        return REJECTIONS[8] if result.reason.startswith(FREE_RUNNING) else REJECTIONS[9]
    return None


FREE_RUNNING = "free-running"
"""How the reason of a design rejected for a free-running task begins."""


def free_running(space: DesignSpace, structure: Structure) -> list[str]:
    """The tasks that run free in a variant (their group has no clock) and not in the
    input design, in file order: what ``space.constraints.free_running`` keeps.

    >>> from tegraph.design.explore.space import design_space
    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "A": {"duration": 1, "period": 10, "outputs": ["x"]},
    ...     "B": {"duration": 2, "inputs": ["x"]}},
    ...     "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]})
    >>> space = design_space(sk, ["A:x -> B:x"])
    >>> free_running(space, Structure.of(space.build(0)))  # ASYN/ASYN: B has no clock
    ['B']
    """
    free = {t for tasks, clocks in zip(structure.groups, structure.clocks) if not clocks
            for t in tasks} - space.free_running_in_input
    return [t for t in space.skeleton.tasks if t in free]


def rule2_findings(skeleton: Skeleton, structure: Structure | None = None) -> int:
    """Departures from Rule 2 of section 6 in ``skeleton``, counted as
    :func:`tegraph.design.rules.check_rules` reports them: each SYN/SYN link (a
    rendezvous blocks both sides), and each ASYN/ASYN link between two groups of
    one design period (Figure 4: the data may wait a period at each hop).
    ``structure`` is ``Structure.of(skeleton)``, if known.

    >>> sk = Skeleton.from_dict({"clocks": {"rtc": {"period": 10}}, "tasks": {
    ...     "A": {"duration": 1, "clock": "rtc", "outputs": ["x"]},
    ...     "B": {"duration": 2, "inputs": ["x"]}},
    ...     "links": [{"from": "A:x", "to": "B:x", "protocol": "SYN/SYN"}]})
    >>> rule2_findings(sk)
    1
    """
    s = Structure.of(skeleton) if structure is None else structure
    group_of, periods = s.group_of, s.periods
    count = 0
    for link in skeleton.links:
        w, r = group_of[link.writer[0]], group_of[link.reader[0]]
        if link.protocol is Protocol.SYN_SYN:
            count += 1
        elif link.protocol is Protocol.ASYN_ASYN and w != r \
                and periods[w] is not None and periods[w] == periods[r]:
            count += 1
    return count


def evaluate_batch(space: DesignSpace, variants: Sequence[int]) -> list[VariantResult]:
    """Judge ``variants`` one after the other (what a worker runs).

    Variants of one protocol assignment share the port repair. An exception
    while judging one variant is recorded in its result (``judged="failed"``),
    so a batch always returns one result per variant.

    >>> from tegraph import load_skeleton
    >>> from tegraph.design.explore.space import design_space
    >>> space = design_space(load_skeleton("examples/fig4_pipeline_synchronized.yaml"),
    ...                      clocks={"rtc": [5, 10]}, chains=[["MT1", "MT2", "MT3", "MT4"]])
    >>> [(r.kept, r.objectives["load"]) for r in evaluate_batch(space, [0, 1])]
    [(False, None), (True, Fraction(3, 5))]

    At 5 the pipe-line needs 6/5 of its processor: rule C rejects it without a
    schedule, so no load on processors is measured (None).
    """
    repairs: dict[int, dict[str, dict[str, list[str]]] | None] = {}
    out = []
    for variant in variants:
        start = time.perf_counter()
        try:
            result = evaluate_variant(space, variant, repairs)
        except Exception as exc:  # a failed variant is reported in its row, never lost
            result = VariantResult(variant, FAILED, reason=f"{type(exc).__name__}: {exc}")
        result.seconds = time.perf_counter() - start
        out.append(result)
    return out


def evaluate_variant(space: DesignSpace, variant: int,
                     repairs: dict[int, Any] | None = None, *,
                     incremental: bool = True) -> VariantResult:
    """Judge one variant (see the module docstring).

    Parameters
    ----------
    space : DesignSpace
    variant : int
    repairs : dict, optional
        Port orders already found per protocol index (filled in).
    incremental : bool
        Compose the §4 verdict of a live variant (and, when it is consistent, the
        report the judgement on processors reads) from the figures of its groups,
        each group analysed once per configuration of its own choices
        (:mod:`.incremental`); False: analyse the whole variant afresh. The result
        is the same.

    Returns
    -------
    VariantResult
    """
    repairs = {} if repairs is None else repairs
    if space.allocation is not None and space.skeleton.network_delay:
        refused = _rendezvous_across(space, variant)
        if refused:
            return VariantResult(variant, PRUNED, reason=refused)
    judge = judge_of(space) if incremental else None
    composed = judge.judge(variant) if judge is not None else None
    if composed is not None:  # live: the whole analysis' verdict, from the groups'
        skeleton = composed.skeleton
        result = VariantResult(variant, ANALYZED, live=True,
                               rule2=rule2_findings(skeleton, composed.structure))
        if composed.report is None:
            result.consistent, result.reason = False, composed.reason
            return result
        report = composed.report
        result.consistent = True
    else:
        skeleton = space.build(variant)
        report = analyze_skeleton(skeleton)
        result = VariantResult(variant, ANALYZED, live=report.live,
                               rule2=rule2_findings(skeleton, report.structure))
        if not report.live:
            protocol_index = space.split(variant)[0]
            if protocol_index not in repairs:
                found = reorder_ports(skeleton)
                repairs[protocol_index] = found.orders if found.possible else None
            orders = repairs[protocol_index]
            if orders is None:
                result.reason = "dead whatever the port order (reorder: the precedence " \
                                "graph has a circuit)"
                return result
            skeleton = _reordered(skeleton, orders)
            report = analyze_skeleton(skeleton)
            if not report.live:  # pragma: no cover - reorder's theorem, re-checked by analyze
                raise AssertionError("internal error: the reordered variant is not live")
            result.live, result.repaired, result.orders = True, True, orders
        result.consistent = report.consistent
        if not report.consistent:
            result.reason = _inconsistency(report)
            return result
    sched = schedulability(skeleton, report)
    # The response-time test decides nothing on processors (docs/explore.md): it is a
    # cross-check, and the chain latency's bounds read its response times.
    result.rta = sched.schedulable
    schedule = None
    chains: dict[tuple[str, ...], ChainFigures] = {}
    too_much = overloaded(skeleton, report)
    if too_much is not None:  # rule C: proven not schedulable, no schedule needed
        result.schedulable, result.reason = False, too_much
    else:
        # A composed variant's graph is shared by the variants that only move tasks
        # (IncrementalJudge.whole_graph); a repaired or fresh one is built here.
        teg = (build_teg(skeleton) if composed is None or judge is None
               else judge.whole_graph(variant, skeleton))
        paths = chain_paths(skeleton, teg, space.chains_read) if space.chains_read else []
        schedule = schedule_on_processors(skeleton, teg, report.groups,
                                          max_events=space.max_events,
                                          platform=report.platform,
                                          trace=trace_request(paths) if paths else None)
        if paths:
            assert schedule.trace is not None  # asked for
            chains = dict(zip(space.chains_read, figures_on(
                paths, schedule.trace, report.groups, shared=True, unit=skeleton.unit,
                max_events=space.max_events)))
        result.schedulable = schedule.schedulable
        if schedule.schedulable is False:
            result.reason = _unschedulable(skeleton, schedule)
        elif schedule.schedulable is None:
            why = schedule.why_undecided or ""
            why = why.partition("): ")[2] or why  # the budget is said once, here
            result.reason = (f"undecided within max_events ({space.max_events:,} event "
                             f"firings): {why}")
    _objectives(space, skeleton, report, sched, schedule, result, chains)
    structure = composed.structure if composed is not None else report.structure
    free = [] if space.constraints.free_running else free_running(
        space, Structure.of(skeleton) if structure is None else structure)
    if free:  # not kept unless asked: a rate that nobody chose
        result.meets = False
        if not result.reason:
            result.reason = (f"{FREE_RUNNING}: {', '.join(free[:3])}"
                             + (f" and {len(free) - 3} more" if len(free) > 3 else "")
                             + " would run free (no clock in its group), where the input "
                             "design runs it on a clock (`free_running` keeps such designs)")
    if space.constraints and schedule is not None:
        broken = _broken(space, skeleton, schedule, chains)
        result.meets = not broken and not free
        if broken and not result.reason:
            result.reason = "against a constraint: " + "; ".join(broken)
    return result


def _rendezvous_across(space: DesignSpace, variant: int) -> str:
    """Why ``variant``'s skeleton would be refused by spec §1 (a SYN/SYN link with a
    positive delay: its network's, across processors), or empty; read from its
    protocols and placement, without building it."""
    sk = space.skeleton
    on = space.processors_of(variant)
    chosen = {c.index: p for c, p in zip(space.links, space.protocols(variant))}
    for i, link in enumerate(sk.links):
        if chosen.get(i, link.protocol) is not Protocol.SYN_SYN:
            continue
        w, r = on[link.writer[0]], on[link.reader[0]]
        delay = link.effective_delay(w != r, sk.network_delay)
        if delay:
            return (f"{RENDEZVOUS}: {link_name(link.writer, link.reader)} is SYN/SYN between "
                    f"{w} and {r}, with a delay of {exact_text(delay)} {sk.unit} (spec §4d)")
    return ""


def _broken(space: DesignSpace, skeleton: Skeleton, schedule: ProcessorSchedule,
            chains: dict[tuple[str, ...], ChainFigures]) -> list[str]:
    """The constraints the variant does not meet, each in words with its unit."""
    unit = skeleton.unit
    out = []
    for task, op, bound in space.constraints.periods:
        period = schedule.tasks[task].period
        if period is None:
            out.append(f"{task} has no period on processors, required {op} "
                       f"{exact_text(bound)} {unit}")
        elif not (period == bound if op == "=" else period <= bound):
            out.append(f"{task}.period on processors is {exact_text(period)} {unit}, "
                       f"required {op} {exact_text(bound)} {unit}")
    for chain, bound in space.constraints.latencies:
        figures = chains[chain]
        value = figures.first_use
        if value is None or value > bound:
            shown = (f"undecided ({figures.why_undecided})" if value is None
                     else f"{exact_text(value)} {unit}")
            out.append(f"latency {','.join(chain)} on processors is {shown}, required <= "
                       f"{exact_text(bound)} {unit}")
    return out


def _reordered(skeleton: Skeleton, orders: dict[str, dict[str, list[str]]]) -> Skeleton:
    tasks = dict(skeleton.tasks)
    for name, order in orders.items():
        tasks[name] = replace(tasks[name], inputs=tuple(order["inputs"]),
                              outputs=tuple(order["outputs"]))
    return replace(skeleton, tasks=tasks)


def _objectives(space: DesignSpace, skeleton: Skeleton, report: Report, sched: Schedulability,
                schedule: ProcessorSchedule | None, result: VariantResult,
                chains: dict[tuple[str, ...], ChainFigures]) -> None:
    wanted = set(space.objectives)
    for name in space.objectives:
        objective = chain_objective(name)
        if objective is None or schedule is None:
            continue  # without a schedule (rule C) no chain is read: not kept anyway
        figures = chains[objective[1]]
        result.objectives[name] = getattr(figures, CHAIN_FIGURES[objective[0]])
        result.kinds[name] = "exact" if figures.decided else "undecided"
        if not figures.decided and result.schedulable is True and not result.reason:
            result.reason = (f"the {objective[0]} of {','.join(objective[1])} on processors "
                             f"is undecided: {figures.why_undecided}")
    periods = {} if schedule is None else {t: f.period for t, f in schedule.tasks.items()}
    if "period" in wanted and schedule is not None:
        reference = space.reference_periods
        # Each task's period over its designed one (tasks with a designed period), when
        # every one of those periods is known (the `else`: no period was missing).
        ratios: list[Fraction] = []
        for name in skeleton.tasks:
            designed = reference.get(name)
            if designed:
                period = periods[name]
                if period is None:
                    break
                ratios.append(period / designed)
        else:
            result.objectives["period"] = max(ratios, default=None)
    if schedule is not None and wanted & {"load", "utilization"}:
        where = schedule.platform.processor_of
        known = [(where[name], task.duration, period) for name, task in skeleton.tasks.items()
                 if (period := periods[name]) is not None]
        # A task's share of its processor is not known without its period.
        loads = (processor_shares(known, every=set(where.values()))
                 if len(known) == len(skeleton.tasks) else {})
        if loads:
            result.objectives["load"] = max(loads.values())
            result.objectives["utilization"] = sum(loads.values(), Fraction(0))
    if wanted & set(PLACEMENT_OBJECTIVES):
        result.objectives.update(placement_objectives(skeleton, report))
    result.objectives = {name: result.objectives.get(name) for name in space.objectives}


def placement_objectives(skeleton: Skeleton, report: Report) -> dict[str, Fraction | None]:
    """``processors``, ``traffic`` and ``busiest`` of a consistent variant (see the module
    docstring), exact.

    Examples
    --------
    A (1 every 4) and B (2, ASYN/SYN after A: period 4) on cpu1, C (1 every 2) on cpu2:
    two processors, one link across (A -> C), cpu1 asks 1/4 + 2/4 = 3/4, cpu2 1/2. A
    task of a group without a clock would ask nothing.

    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "A": {"duration": 1, "period": 4, "outputs": ["x", "y"], "processor": "cpu1"},
    ...     "B": {"duration": 2, "inputs": ["x"], "processor": "cpu1"},
    ...     "C": {"duration": 1, "period": 2, "inputs": ["y"], "processor": "cpu2"}},
    ...     "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"},
    ...               {"from": "A:y", "to": "C:y", "protocol": "ASYN/ASYN"}]})
    >>> {k: str(v) for k, v in placement_objectives(sk, analyze_skeleton(sk)).items()}
    {'processors': '2', 'traffic': '1', 'busiest': '3/4'}
    """
    on = processor_of(skeleton)
    # A free-running group asks nothing: it takes the time the others leave.
    clocked = [name for group in report.groups if group.clocks for name in group.tasks]
    known = [(on[name], skeleton.tasks[name].duration, period) for name in clocked
             if (period := report.tasks[name].period) is not None]
    busiest = (max(processor_shares(known, every=set(on.values())).values())
               if len(known) == len(clocked) else None)
    return {"processors": Fraction(len(set(on.values()))),
            "traffic": Fraction(sum(1 for k in skeleton.links if crosses(skeleton, k))),
            "busiest": busiest}


def _inconsistency(report: Report) -> str:
    if report.unbounded_places:
        u = report.unbounded_places[0]
        more = len(report.unbounded_places) - 1
        return f"{u.kind} at {u.src} -> {u.dst}" + (f" (and {more} more)" if more else "")
    late = [t for t in report.tasks.values() if t.overrun_at is not None]
    if late:
        return f"overrun: {late[0].name} at activation {late[0].overrun_at}"
    return "not consistent"


def _unschedulable(skeleton: Skeleton, schedule: ProcessorSchedule) -> str:
    """Why the schedule on processors is not schedulable: its earliest problem (an
    overrun or a starved task, in the one order of every command), else a growing
    place (the §4b verdict's own evidence)."""
    where = schedule.platform.processor_of
    if schedule.problems:
        p = schedule.problems[0]
        if p.kind == "overrun":
            return f"overrun on processors: {p.task} at activation {p.k} (on {where[p.task]})"
        return f"starved on processors: {p.task} never gets its duration on {where[p.task]}"
    if schedule.unbounded:
        u = schedule.unbounded[0]
        more = len(schedule.unbounded) - 1
        return (f"a place grows on processors: {u.kind} at {u.src} -> {u.dst}"
                + (f" (and {more} more)" if more else ""))
    return "not schedulable on processors: a group is not live"  # pragma: no cover
