"""What :func:`~tegraph.analysis.analyze.analyze_skeleton` finds: the report data of spec §4.

Plain dataclasses with exact :class:`fractions.Fraction` times and ``None``
where ``docs/skeleton.md`` §5 says a figure is undefined; ``to_dict`` gives
the JSON document's data (exact numbers as strings). Rendering them as text,
JSON or tables is :mod:`tegraph.report`'s job.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, Protocol

from maxplus.scalar import exact_text

__all__ = ["Deadlock", "DesignPart", "GroupReport", "InvariantCheck", "Reorder", "Report",
           "TaskReport", "UnboundedPlace"]


@dataclass
class Deadlock:
    """A token-free circuit: its events never fire."""

    events: list[str]
    tasks: list[str]
    links: list[str]
    advice: str


@dataclass
class UnboundedPlace:
    """A place where tokens pile up: its output event is slower than its input event."""

    src: str
    dst: str
    kind: str
    src_cycle_time: Fraction
    dst_cycle_time: Fraction
    group: int
    advice: str


@dataclass
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


@dataclass
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
    links: list[Any] | None = None

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

    @property
    def exit_status(self) -> int:
        """0 live and consistent; 1 a deadlock, an unbounded place or an overrun."""
        return 0 if self.live and self.consistent else 1

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
            "methods": self.methods,
            "notes": self.notes,
            "design": None if self.design is None else self.design.to_dict(),
        }
