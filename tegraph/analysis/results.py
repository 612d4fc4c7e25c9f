"""What :func:`~tegraph.analysis.analyze.analyze_skeleton` finds: the report data of spec §4.

Plain dataclasses with exact :class:`fractions.Fraction` times and ``None``
where ``docs/skeleton.md`` §5 says a figure is undefined; ``to_dict`` gives
the JSON document's data (exact numbers as strings). Rendering them as text,
JSON or tables is :mod:`tegraph.report`'s job.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import TYPE_CHECKING, Any, Protocol

from maxplus.scalar import exact_text

from ..model.build import UnboundedKind
from ..model.platform import Platform
from ..model.structure import Structure
from . import notebook
from .chains import ChainReport
from .processors.schedule import ProcessorSchedule

if TYPE_CHECKING:  # annotations only: a report loads no more modules for them
    from ..model.elements import LinkLabel

__all__ = ["Deadlock", "DesignPart", "GroupReport", "InvariantCheck", "Reorder", "Report",
           "TaskReport", "UnboundedPlace"]


@dataclass
class Deadlock:
    """A token-free circuit: its events never fire."""

    events: list[str]
    tasks: list[str]
    links: list[LinkLabel]
    advice: str


@dataclass
class UnboundedPlace:
    """A place where tokens pile up: its output event is slower than its input event."""

    src: str
    dst: str
    kind: UnboundedKind
    src_cycle_time: Fraction
    dst_cycle_time: Fraction
    group: int
    advice: str


# Keyword-only, as the other long results: several fields share a type (None, Fraction),
# so a positional call would neither read nor type-check as meant.
@dataclass(kw_only=True)
class TaskReport:
    """Figures of one task (null where spec §5 says they are undefined)."""

    name: str
    group: int
    period: Fraction | None
    overrun_at: int | None
    slack: Fraction | None
    critical: bool | None
    clock: str | None = None
    overrun_decided: bool = True
    duration_margin: Fraction | None = None
    """How much the duration may grow, its group staying consistent (``duration_margins``)."""
    duration_margin_state: str = "not computed"
    """``"exact"`` (``duration_margin``), ``"unbounded"``, ``"not consistent"`` or
    ``"not computed"`` (``tegraph.analyze`` above its ``margins_max_tasks``)."""
    duration: Fraction = Fraction(0)
    """Its duration (the skeleton's), which a job needs of its processor."""
    overrun_tick: Fraction | None = None
    """The instant of the overrun: its clock's tick ``overrun_at`` (``phase + (k - 1) *
    period``), by which the problems are listed, earliest first."""

    @property
    def overrun(self) -> str:
        """The overrun verdict in words, one for each case tables must tell apart.

        ``"at activation k"``; ``"never"`` (decided: no activation overruns);
        ``"no clock"`` (spec §4: only a clocked task can overrun); ``"not live"``
        (its group is dead: the deadlock is reported instead); ``"undecided
        (budget)"`` (the simulation budget ran out first). ``overrun_at`` alone
        is null in all but the first case.
        """
        if self.overrun_at is not None:
            return f"at activation {self.overrun_at}"
        if self.clock is None:
            return "no clock"
        if self.period is None:
            return "not live"
        return "never" if self.overrun_decided else "undecided (budget)"


# Keyword-only: see TaskReport.
@dataclass(kw_only=True)
class GroupReport:
    """One weakly connected part of the timed event graph."""

    index: int
    tasks: list[str]
    clocks: list[str]
    live: bool
    rate_consistent: bool
    period: Fraction | None
    transient: tuple[int, int] | None
    critical_circuit: list[str] = field(default_factory=list)
    cycle_times: dict[str, Fraction] = field(default_factory=dict)
    """Per task cycle time when the group is live (differs from period when not rate-consistent)."""
    critical_holdings: list[Fraction] = field(default_factory=list)
    """Holding time of each place of the critical circuit, in circuit order."""
    critical_tokens: int | None = None
    """Initial tokens on the critical circuit.

    Its ratio is ``sum(critical_holdings) / critical_tokens``."""

    @property
    def critical_holding(self) -> Fraction | None:
        """Total holding time of the critical circuit (None when there is none)."""
        return sum(self.critical_holdings, Fraction(0)) if self.critical_tokens else None


@dataclass
class Reorder:
    """Whether some port order makes a dead skeleton live (spec §4 deadlocks).

    Attributes
    ----------
    possible : bool
    orders : dict
        ``task -> {"inputs": [...], "outputs": [...]}`` for every task whose
        order changes (empty when ``possible`` is False).
    circuit : list of str or None
        When impossible: a circuit of the precedence graph, as event names, a
        deadlock whatever the port orders; None when possible.
    links : list of LinkLabel or None
        When impossible: the synchronizing links on that circuit; None when possible.
    """

    possible: bool
    orders: dict[str, dict[str, list[str]]]
    circuit: list[str] | None = None
    links: list[LinkLabel] | None = None

    def to_dict(self) -> dict[str, Any]:
        """Plain data for the JSON report (``circuit`` and ``links`` only when impossible)."""
        out: dict[str, Any] = {"possible": self.possible, "orders": self.orders}
        if not self.possible:
            out["circuit"] = self.circuit
            out["links"] = [link.document() for link in self.links or ()]
        return out


class DesignPart(Protocol):
    """What :attr:`Report.design` holds: the design section of ORCCAD §6.

    It is :class:`tegraph.design.section.DesignSection`, a floor above the
    analysis: the report carries it without importing it.
    """

    rules: list[Any]
    schedulability: Any
    latency: list[Any]
    cross_check: Any
    """Where the response-time test agrees with the exact schedule."""

    def to_dict(self) -> dict[str, Any]:
        """Plain data for the JSON report."""


@dataclass
class InvariantCheck:
    """The p-semiflow cross-check of the liveness verdict."""

    computed: bool
    count: int | None
    liveness_agrees: bool | None
    unmarked: int | None = None
    reason: str = ""


@dataclass
class Report:
    """Everything ``tegraph analyze`` reports about one skeleton.

    See Also
    --------
    tegraph.analyze : makes it.
    tegraph.report.to_json : its JSON document (``docs/skeleton.md`` §5).
    tegraph.report.render_text : its text report.

    Examples
    --------
    >>> from tegraph import Skeleton, analyze
    >>> r = analyze(Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 10}}}))
    >>> r.live, r.consistent, r.exit_status, list(r.tasks)
    (True, True, 0, ['A'])
    """

    name: str
    unit: str
    live: bool
    consistent: bool
    deadlocks: list[Deadlock]
    reorder: Reorder | None
    groups: list[GroupReport]
    tasks: dict[str, TaskReport]
    unbounded_places: list[UnboundedPlace]
    invariants: InvariantCheck
    methods: dict[str, str] = field(default_factory=dict)
    """How each verdict was obtained (theorem or algorithm, cross-check)."""
    notes: list[str] = field(default_factory=list)
    source: str | None = None
    design: DesignPart | None = None
    """Rules 1-4, schedulability and chain latencies (docs/skeleton.md §6)."""
    schedule: ProcessorSchedule | None = None
    """The skeleton on its processors (spec §4b); None: every task on a processor
    of its own (``processors=False``), where the figures of §4 decide."""
    structure: Structure | None = field(default=None, repr=False, compare=False)
    """The skeleton's groups (numbered as ``groups``), clocks, design periods and
    links by port, computed once by the analysis: what follows it (design rules,
    margins) reads these instead of finding the groups again."""
    chains: list[ChainReport] = field(default_factory=list)
    """The latency of each chain of the skeleton and of those asked for, in that order
    (spec §4c): ``report.chains[i].on_processors.first_use`` and the other figures."""
    platform: Platform | None = field(default=None, repr=False, compare=False)
    """Each task's processor and priority, each processor's kind (spec §4b, §4d),
    computed once by the analysis (:func:`~tegraph.model.platform.platform_of`): the
    schedule, the response-time cross-check and Rule 4 read this one."""

    def _repr_html_(self) -> str:
        """The result as a notebook shows it (:func:`tegraph.report.html.render_html`)."""
        return notebook.html(self)

    @property
    def schedulable(self) -> bool | None:
        """Spec §4b's verdict: live, every job ends, no unbounded place, no overrun.

        On its processors when :attr:`schedule` is set (None: undecided within the
        budget, :attr:`schedule` says why). Without it, every task has a processor
        of its own, which is §3 exactly: live and consistent, None where an
        overrun is undecided.
        """
        if self.schedule is not None:
            return self.schedule.schedulable
        if not (self.live and self.consistent):
            return False
        return None if any(not t.overrun_decided for t in self.tasks.values()) else True

    @property
    def exit_status(self) -> int:
        """0 live, consistent and schedulable; 1 otherwise (undecided included), spec §5.

        Without :attr:`schedule` (``processors=False``) the v1.1 status: 0 live and
        consistent.
        """
        if self.schedule is None:
            return 0 if self.live and self.consistent else 1
        return 0 if self.live and self.consistent and self.schedulable else 1

    def on_processors(self, task: str) -> dict[str, Any]:
        """Task ``task``'s figures on processors (spec §5 ``on_processors``), exact strings."""
        if self.schedule is not None:
            f = self.schedule.tasks[task]
            return {"period": exact_text(f.period), "overrun_at": f.overrun_at,
                    "response": exact_text(f.response),
                    "response_from_tick": exact_text(f.response_from_tick),
                    "starved": f.starved, "stopped_after": f.stopped_after,
                    "waits_for": list(f.waits_for), "decided": f.decided}
        t = self.tasks[task]  # a processor of its own: a job runs from its release
        # The time from the tick needs the daters of the regime, which the figures of
        # spec §4 do not keep: not computed here (null), the schedule on processors has it.
        return {"period": exact_text(t.period), "overrun_at": t.overrun_at,
                "response": None if t.period is None else exact_text(t.duration),
                "response_from_tick": None, "starved": False, "stopped_after": None,
                "waits_for": [], "decided": t.overrun_decided}

    def schedule_summary(self) -> dict[str, Any]:
        """The JSON report's ``schedule``: whether the verdict is exact, how it was
        obtained, why it is undecided, the places growing on processors."""
        if self.schedule is None:
            return {"exact": self.schedulable is not None,
                    "method": "every task on a processor of its own (processors=False): "
                              "spec §3, decided by the figures of §4",
                    "why_undecided": None if self.schedulable is not None
                    else "an overrun is undecided within the dater simulation's budget",
                    "unbounded_places": []}
        s = self.schedule
        return {"exact": s.exact, "method": s.method, "why_undecided": s.why_undecided,
                "unbounded_places": [{"from": u.src, "to": u.dst, "kind": u.kind,
                                      "group": u.group, "tokens_per_regime": u.per_regime}
                                     for u in s.unbounded]}

    def _processors_list(self) -> list[dict[str, Any]]:
        if self.schedule is None:
            return []
        return [{"name": p.name, "tasks": list(p.tasks), "priorities": dict(p.priorities),
                 "priority_source": p.priority_source, "preemptive": p.preemptive,
                 "replaced_priorities": dict(p.replaced)}
                for p in self.schedule.platform.processors]

    def _group_period_on_processors(self, index: int) -> str | None:
        if self.schedule is not None:
            return exact_text(self.schedule.group_periods[index])
        return exact_text(self.groups[index].period)

    def to_dict(self) -> dict[str, Any]:
        """The JSON document of ``docs/skeleton.md`` §5 as Python data.

        :func:`tegraph.report.to_json` writes it, with its ``schema_version``.
        """
        return {
            "name": self.name,
            "unit": self.unit,
            "live": self.live,
            "consistent": self.consistent,
            "deadlocks": [
                {"events": d.events, "tasks": d.tasks,
                 "links": [link.document() for link in d.links], "advice": d.advice}
                for d in self.deadlocks
            ],
            "reorder": None if self.reorder is None else self.reorder.to_dict(),
            "groups": [
                {
                    "tasks": g.tasks,
                    "clocks": g.clocks,
                    "live": g.live,
                    "rate_consistent": g.rate_consistent,
                    "period": exact_text(g.period),
                    "transient": None if g.transient is None
                    else {"k": g.transient[0], "cyclicity": g.transient[1]},
                    "critical_circuit": g.critical_circuit,
                    "critical_holding": exact_text(g.critical_holding),
                    "critical_tokens": g.critical_tokens,
                    "period_on_processors": self._group_period_on_processors(g.index),
                }
                for g in self.groups
            ],
            "tasks": {
                t.name: {
                    "group": t.group,
                    "period": exact_text(t.period),
                    "overrun_at": t.overrun_at,
                    "slack": exact_text(t.slack),
                    "critical": t.critical,
                    "overrun_decided": t.overrun_decided,
                    "duration_margin": exact_text(t.duration_margin),
                    "duration_margin_state": t.duration_margin_state,
                    "on_processors": self.on_processors(t.name),
                }
                for t in self.tasks.values()
            },
            "unbounded_places": [
                {"from": u.src, "to": u.dst, "kind": u.kind,
                 "from_cycle_time": exact_text(u.src_cycle_time),
                 "to_cycle_time": exact_text(u.dst_cycle_time), "advice": u.advice}
                for u in self.unbounded_places
            ],
            "invariants": {
                "computed": self.invariants.computed,
                "count": self.invariants.count,
                "liveness_agrees": self.invariants.liveness_agrees,
            },
            "schedulable": self.schedulable,
            "processors": self._processors_list(),
            "schedule": self.schedule_summary(),
            "chains": [c.to_dict() for c in self.chains],
            "methods": self.methods,
            "notes": self.notes,
            "design": None if self.design is None else self.design.to_dict(),
        }
