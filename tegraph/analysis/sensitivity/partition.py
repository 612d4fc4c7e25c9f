"""The parts of a skeleton's schedule on its processors, as the sensitivity analysis keeps them.

The §4b schedule is simulated part by part (tasks joined by a group or a
processor, :class:`~tegraph.analysis.processors.schedule._Net`). Before any
line of parameters is walked, each part is read once off the nominal graph
(:func:`nominal_parts`): its simulation data, its levels
(:func:`part_levels`), the places of its links that hold a varied delay
(:func:`delay_places`), and the places from events fired infinitely often at
time 0 that make it grow at once (:func:`zero_grows`). None of these depends
on the values of the parameters, only on which are varied.

See Also
--------
tegraph.analysis.sensitivity.parts : the parts evaluated along a line.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

from ...model.build import holding_sources
from ...model.platform import clock_hyperperiod
from ..processors._engine import PartData
from ..processors.levels import Levels, processor_levels
from ..processors.schedule import _Net
from .parameters import DELAY_KINDS, Parameter

__all__ = ["Part", "delay_places", "nominal_parts", "part_levels", "zero_grows"]


@dataclass
class Part:
    """One part of the schedule at the nominal values, and what is known of it."""

    data: PartData | None
    """None: every task of the part has events at time 0 only (none is simulated)."""
    names: list[str]
    """The tasks simulated (those whose events are not all at time 0)."""
    events: list[int]
    places: list[int]
    tasks: list[str]
    """Every task of the part, in file order."""
    levels: Levels | str = "not computed"
    """Its levels (:mod:`tegraph.analysis.processors.levels`), or why it has none."""
    open_units: list[str] = dataclasses.field(default_factory=list)
    """Why its levels left points of a line undecided (a unit without closing task
    missing its deadline), in words."""
    too_long: str | None = None
    delays: dict[int, list[int]] = dataclasses.field(default_factory=dict)
    """The local places holding each varied delay j of the part's links."""
    delay_at_zero: dict[int, str] = dataclasses.field(default_factory=dict)
    """A place of the part's links holding delay j that no simulation holds (its events
    fire at time 0 only at the nominal values), named ``W.write:p -> R.read:q``."""


def nominal_parts(net: _Net, max_events: int) -> list[Part]:
    """The parts of ``net``: those it simulates, then those whose events are all at time 0.

    A part whose clocks' hyperperiod alone needs more ticks than ``max_events``
    says so in ``too_long``.
    """
    sk = net.sk
    out: list[Part] = []
    label = net._union_parts()
    index = {t: i for i, t in enumerate(net.tasks)}
    members: dict[int, list[str]] = {}
    for t, lab in zip(net.tasks, label):
        members.setdefault(lab, []).append(t)
    for data, names, events, places in net.parts():
        hyper, ticks = clock_hyperperiod(sk, names)
        lab = label[index[names[0]]] if names else -1
        part = Part(data, names, events, places, members.pop(lab, list(names)))
        if ticks > max_events:
            part.too_long = (f"the hyperperiod of the part of {', '.join(names[:3])}"
                             f"{' ...' if len(names) > 3 else ''} is {hyper} {sk.unit} "
                             f"({ticks:,} clock ticks), more than `max_events` firings")
        out.append(part)
    for tasks in members.values():  # parts whose events are all at time 0
        out.append(Part(None, [], [], [], tasks))
    return out


def part_levels(net: _Net, parts: Sequence[Part]) -> None:
    """Each part's levels (:mod:`tegraph.analysis.processors.levels`), or why it has none."""
    group_of, groups = net.group_of, net.groups
    shapes = []
    for part in parts:
        own = list(dict.fromkeys(group_of[t] for t in part.tasks))
        shapes.append([list(groups[g].tasks) for g in own])
    found = processor_levels(net.sk, net.teg, shapes, net.platform)
    for part, shape, levels in zip(parts, shapes, found):
        live = all(groups[group_of[g[0]]].live for g in shape)
        part.levels = levels if live else "a group is not live"


def delay_places(net: _Net, params: Sequence[Parameter], parts: Sequence[Part],
                 part_of: dict[str, int]) -> dict[int, list[int]]:
    """The places (global numbers) holding each varied delay, read off the graph's
    holding sources as the parametric groups are (a link without a place,
    ASYN/ASYN, moves no event of the schedule), and each part's own."""
    param_of = {(p.kind, p.owner): j for j, p in enumerate(params)
                if p.kind in DELAY_KINDS}
    out: dict[int, list[int]] = {}
    if not param_of:
        return out
    for q, source in enumerate(holding_sources(net.teg)):
        j = param_of.get((source.kind, source.owner))
        if j is not None:
            out.setdefault(j, []).append(q)
    attrs, names = net.teg.transition_attrs, net.teg.transition_names
    local = [{int(q): i for i, q in enumerate(part.places)} for part in parts]
    for j, places in out.items():
        for q in places:
            src, dst = int(net.src[q]), int(net.dst[q])
            # A link place joins two tasks of one group: one part.
            i = part_of[attrs[src]["tasks"][0]]
            if q in local[i]:
                parts[i].delays.setdefault(j, []).append(local[i][q])
            else:
                parts[i].delay_at_zero.setdefault(j, f"{names[src]} -> {names[dst]}")
    return out


def zero_grows(net: _Net, part_of: dict[str, int]) -> tuple[dict[int, str], str | None]:
    """A place that grows at once in each part it leads into, and one of the whole (a
    task no part holds), named ``SRC -> DST``.

    Places from events that fire infinitely often at time 0 into the rest
    grow at once (schedule.py's module docstring): not schedulable, as
    ``schedule_on_processors`` says, for the part they lead into.
    """
    grows: dict[int, str] = {}
    whole: str | None = None
    teg = net.teg
    names_ = teg.transition_names
    for s, d in zip(net.src, net.dst):
        if s in net.zero and d not in net.zero:
            owner = (teg.transition_attrs[d].get("tasks")
                     or teg.transition_attrs[s].get("tasks"))
            if not net.groups[net.group_of[owner[0]]].live:
                continue
            text = f"{names_[s]} -> {names_[d]}"
            if owner[0] in part_of:
                grows.setdefault(part_of[owner[0]], text)
            elif whole is None:
                whole = text
    return grows, whole
