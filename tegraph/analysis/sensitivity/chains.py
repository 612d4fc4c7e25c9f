"""What using a margin costs in latency: each chain's first use at the ends of the margins.

A margin says how far a duration, a period or a delay may move; a designer who uses it
changes the schedule, and so the latency of the chains (spec §4c). For each
chain (the skeleton's and those asked for) this evaluates its first use, exactly,
at the nominal values, at the scaling factor (every varied duration times the
factor) and at each end of every reported margin (that parameter alone moved),
with :func:`~tegraph.analysis.analyze.analyze_skeleton` on the chain's parts
alone: the groups of its tasks and every group sharing a processor with them,
which nothing else can change (spec §4b). A parameter outside those parts
leaves the figure as it is at the nominal values, and is not evaluated again.
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from typing import Any

from ...model.build import link_ports
from ...model.platform import crosses, processor_of, processor_parts
from ...model.skeleton import Skeleton
from ...model.structure import Structure
from ..analyze import analyze_skeleton
from ..chains import ChainFigures
from .parameters import Parameter, skeleton_at
from .results import ChainAtMargins

__all__ = ["ChainAtMargins", "chains_at_margins"]


def chains_at_margins(skeleton: Skeleton, chains: Sequence[Sequence[str]],
                      parameters: Sequence[Parameter], scaling: Any, margins: dict[str, Any],
                      *, processors: bool, max_events: int) -> list[ChainAtMargins]:
    """Each chain's first use at the nominal values, the scaling factor and each margin's ends.

    Parameters
    ----------
    skeleton : Skeleton
    chains : sequence of task-name sequences
        Besides the skeleton's own chains.
    parameters : sequence of Parameter
        The varied parameters.
    scaling : Scaling or None
        The reported scaling factor (``factor`` read).
    margins : dict of str to Margin
        The reported margins (``low``, ``high``, ``nominal_consistent`` read).
    processors : bool
        On the skeleton's processors (§4b), else with a processor per task.
    max_events : int
        Budget of event firings of each evaluation.
    """
    all_chains = [tuple(c) for c in skeleton.chains] + [tuple(c) for c in chains]
    if not all_chains:
        return []
    structure = Structure.of(skeleton)
    part = processor_parts(structure.groups, processor_of(skeleton))
    part_of = {t: part[g] for t, g in structure.group_of.items()}
    out = []
    for chain in all_chains:
        parts = {part_of[t] for t in chain}
        tasks = [t for t in skeleton.tasks if part_of[t] in parts]
        inside = {p.name for p in parameters if _touches(skeleton, p, set(tasks))}

        def at(values: dict[str, Fraction], chain: tuple[str, ...] = chain,
               tasks: list[str] = tasks) -> ChainFigures:
            sub = _moved(skeleton, parameters, values).restricted_to(tasks)
            report = analyze_skeleton(sub, semiflow_max_places=0, processors=processors,
                                      max_events=max_events, chains=[chain])
            c = report.chains[-1]  # after the sub-skeleton's own chains: the one asked for
            return c.on_processors if processors else c.processor_per_task

        nominal = at({})
        result = ChainAtMargins(chain, processors, nominal)
        factor = None if scaling is None else scaling.factor
        if factor is not None:
            moved = {p.name: p.nominal * factor for p in parameters
                     if p.kind == "duration" and p.name in inside}
            result.at_factor = at(moved) if moved else nominal
        for name, m in margins.items():
            if name not in inside:
                result.outside.append(name)
                continue
            low = at({name: m.low}) if m.nominal_consistent and m.low is not None else None
            high = at({name: m.high}) if m.high is not None else None
            result.margins[name] = (low, high)
        out.append(result)
    return out


def _touches(sk: Skeleton, p: Parameter, tasks: set[str]) -> bool:
    """Whether parameter ``p`` is a duration or a clock of one of ``tasks``, or the delay
    of a link between two of them (its own, or the network's where it takes it: a delay
    moves which message a read sees, spec §4c, also on an ASYN/ASYN link, which has no
    place)."""
    if p.kind == "duration":
        return p.owner in tasks
    if p.kind == "period":
        return any(sk.tasks[t].clock == p.owner for t in tasks)
    inside = [x for x in sk.links if x.writer[0] in tasks and x.reader[0] in tasks]
    if p.kind == "delay":
        return any(link_ports(x) == p.owner for x in inside)
    return any(x.delay is None and crosses(sk, x) for x in inside)


def _moved(sk: Skeleton, parameters: Sequence[Parameter],
           values: dict[str, Fraction]) -> Skeleton:
    """The skeleton with these parameters (by name) at these values."""
    if not values:
        return sk
    index = {p.name: j for j, p in enumerate(parameters)}
    return skeleton_at(sk, parameters, {index[name]: v for name, v in values.items()})
