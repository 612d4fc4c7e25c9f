"""The analysis report: data, JSON (``docs/skeleton.md`` §5) and tables.

Everything here is data or returns strings; nothing prints. The command line
decides where the strings go.
"""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

from tabulate import tabulate

__all__ = [
    "SCHEMA_VERSION",
    "Deadlock",
    "GroupReport",
    "TaskReport",
    "UnboundedPlace",
    "InvariantCheck",
    "Report",
    "exact_text",
    "json_report",
    "render_text",
    "write_csv",
]

SCHEMA_VERSION = 1


def json_report(command: str, body: dict[str, Any]) -> dict[str, Any]:
    """A command's JSON document: ``schema_version`` and ``report`` first, then ``body``.

    ``docs/report.schema.json`` describes each command's document.

    >>> json_report("reach", {"states": 3})
    {'schema_version': 1, 'report': 'reach', 'states': 3}
    """
    return {"schema_version": SCHEMA_VERSION, "report": command, **body}


def exact_text(value: Fraction | int | None) -> str | None:
    """An exact number as the report writes it: ``"7/3"``, ``"2"``; None stays None.

    >>> exact_text(Fraction(7, 3)), exact_text(Fraction(4, 2)), exact_text(None)
    ('7/3', '2', None)
    """
    if value is None:
        return None
    value = Fraction(value)
    return str(value.numerator) if value.denominator == 1 else f"{value.numerator}/{value.denominator}"


def _human(value: Fraction | None, unit: str) -> str:
    """``7/3 ms (2.333)``: exact, with a decimal beside it when not an integer."""
    if value is None:
        return "-"
    text = str(exact_text(value))
    if value.denominator != 1:
        text += f" {unit} ({float(value):.4g})"
    else:
        text += f" {unit}"
    return text


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
    """Everything ``tegraph analyze`` reports about one skeleton."""

    name: str
    unit: str
    live: bool
    consistent: bool
    deadlocks: list[Deadlock]
    reorder: dict[str, Any] | None
    groups: list[GroupReport]
    tasks: dict[str, TaskReport]
    unbounded_places: list[UnboundedPlace]
    invariants: InvariantCheck
    methods: dict[str, str] = field(default_factory=dict)
    """How each verdict was obtained (theorem or algorithm, cross-check)."""
    notes: list[str] = field(default_factory=list)
    source: str | None = None
    design: dict[str, Any] | None = None
    """Rules 1-4, schedulability and chain latencies (docs/skeleton.md §6)."""

    @property
    def exit_status(self) -> int:
        """0 live and consistent; 1 a deadlock, an unbounded place or an overrun."""
        return 0 if self.live and self.consistent else 1

    def to_dict(self) -> dict[str, Any]:
        """The JSON document of ``docs/skeleton.md`` §5 as Python data."""
        return {
            "schema_version": SCHEMA_VERSION,
            "name": self.name,
            "unit": self.unit,
            "live": self.live,
            "consistent": self.consistent,
            "deadlocks": [
                {"events": d.events, "tasks": d.tasks, "links": d.links, "advice": d.advice}
                for d in self.deadlocks
            ],
            "reorder": self.reorder,
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
            "design": None if self.design is None else {
                "rules": [f.to_dict() for f in self.design["rules"]],
                "schedulability": self.design["schedulability"].to_dict(),
                "latency": [c.to_dict() for c in self.design["latency"]],
            },
        }

    def to_json(self, indent: int | None = 2) -> str:
        """The JSON report (exact numbers as strings such as ``"7/3"``)."""
        return json.dumps(self.to_dict(), indent=indent, ensure_ascii=False)


def render_text(report: Report) -> str:
    """The human report: verdicts with how they were obtained, then tables.

    Returns
    -------
    str
    """
    u = report.unit
    lines = [f"skeleton {report.name}" + (f" ({report.source})" if report.source else "")]
    verdict = "live" if report.live else "NOT LIVE (deadlock)"
    lines.append(f"liveness:    {verdict} — {report.methods.get('liveness', '')}")
    consistent = "consistent" if report.consistent else "NOT CONSISTENT"
    lines.append(f"timing:      {consistent} — {report.methods.get('timing', '')}")
    lines.append(f"periods:     {report.methods.get('periods', '')}")
    for d in report.deadlocks:
        lines.append("")
        lines.append("deadlock: token-free circuit " + " -> ".join([*d.events, d.events[0]]))
        lines.append(f"  tasks on it: {', '.join(d.tasks)}")
        if d.links:
            lines.append(f"  links on it: {'; '.join(d.links)}")
        lines.append(f"  what to change: {d.advice}")
    if report.reorder is not None:
        lines.append("")
        if report.reorder["possible"]:
            lines.append("reorder: a port order makes the skeleton live:")
            for task, order in report.reorder["orders"].items():
                lines.append(f"  {task}: inputs {order['inputs']}, outputs {order['outputs']}")
        else:
            lines.append("reorder: no port order makes the skeleton live "
                         "(the precedence graph of reads, computes and writes has a circuit)")
    rows = []
    for g in report.groups:
        transient = "-" if g.transient is None else f"k={g.transient[0]}, cyclicity {g.transient[1]}"
        state = "dead" if not g.live else ("rate-consistent" if g.rate_consistent else "unbounded")
        rows.append([g.index, ", ".join(g.tasks), ", ".join(g.clocks) or "-", state,
                     _human(g.period, u), transient])
    lines.append("")
    lines.append(tabulate(rows, headers=["group", "tasks", "clocks", "state", "period", "transient"]))
    rows = []
    for t in report.tasks.values():
        if t.clock is None or t.period is None:
            overrun = "-"
        else:
            overrun = "never" if t.overrun_at is None else f"at activation {t.overrun_at}"
        if not t.overrun_decided:
            overrun = "undecided (budget)"
        rows.append([t.name, t.group, _human(t.period, u), overrun, _human(t.slack, u),
                     "-" if t.critical is None else ("yes" if t.critical else "no")])
    lines.append("")
    lines.append(tabulate(rows, headers=["task", "group", "period", "overrun", "slack", "critical"]))
    for g in report.groups:
        if g.critical_circuit:
            lines.append(f"critical circuit of group {g.index}: "
                         + " -> ".join([*g.critical_circuit, g.critical_circuit[0]]))
    if report.unbounded_places:
        lines.append("")
        lines.append("unbounded places (tokens pile up):")
        for p in report.unbounded_places:
            lines.append(f"  {p.src} -> {p.dst} [{p.kind}]: {p.advice}")
    inv = report.invariants
    lines.append("")
    if inv.computed:
        agree = "agrees" if inv.liveness_agrees else "DISAGREES"
        lines.append(f"invariants: {inv.count} minimal p-semiflows, {inv.unmarked} without token; "
                     f"the semiflow verdict {agree} with the circuit verdict")
    else:
        lines.append(f"invariants: not computed ({inv.reason})")
    if report.design is not None:
        # Imported here: these modules import this one.
        from .latency import render_latency
        from .rules import render_rules
        from .schedulability import render_schedulability

        lines += ["", render_rules(report.design["rules"]).rstrip("\n"),
                  render_schedulability(report.design["schedulability"], u).rstrip("\n")]
        lines += [render_latency(c, u).rstrip("\n") for c in report.design["latency"]]
    for note in report.notes:
        lines.append(f"note: {note}")
    return "\n".join(lines) + "\n"


def write_csv(report: Report, directory: str | Path, overwrite: bool = False) -> list[Path]:
    """Write ``tasks.csv`` and ``groups.csv`` into ``directory``.

    Raises
    ------
    FileExistsError
        When a file exists and ``overwrite`` is False (nothing is written).
    """
    out = Path(directory)
    targets = [out / "tasks.csv", out / "groups.csv"]
    if not overwrite:
        for path in targets:
            if path.exists():
                raise FileExistsError(f"{path} exists; not overwriting it (use --force)")
    out.mkdir(parents=True, exist_ok=True)
    data = report.to_dict()
    with open(targets[0], "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["task", "group", "period", "overrun_at", "slack", "critical"])
        for name, t in data["tasks"].items():
            writer.writerow([name, t["group"], t["period"], t["overrun_at"], t["slack"], t["critical"]])
    with open(targets[1], "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["group", "tasks", "clocks", "live", "rate_consistent", "period",
                         "transient_k", "cyclicity"])
        for k, g in enumerate(data["groups"]):
            tr = g["transient"] or {}
            writer.writerow([k, " ".join(g["tasks"]), " ".join(g["clocks"]), g["live"],
                             g["rate_consistent"], g["period"], tr.get("k"), tr.get("cyclicity")])
    return targets
