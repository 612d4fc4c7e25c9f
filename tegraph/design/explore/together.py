"""Moves of the allocation digits: one unit to another processor, and the pairs tried first.

The neighbours of an allocation (:func:`moves`) move one free unit to another
offered processor, each renamed to its canonical form (:mod:`.allocation`). The local
search starts, besides the input design, from the allocations that put on one
processor a pair of tasks that never run at once in the starting design
(:func:`together_first`): ORCCAD's §2.4 candidates to share a processor
(:func:`tegraph.design.placement.shared_processor_candidates`), found once, on the
schedule of the starting design alone.
"""

from __future__ import annotations

from ...analysis.analyze import analyze_skeleton
from ...errors import TegraphError
from ..placement import shared_processor_candidates
from .space import DesignSpace

__all__ = ["moves", "together_first"]


def moves(space: DesignSpace, allocation: int) -> list[int]:
    """The allocations one unit's move away from number ``allocation`` (canonical, each
    once, in the order of the units and the processors offered; itself left out).

    >>> from tegraph import Skeleton
    >>> from tegraph.design.explore.space import design_space
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 4},
    ...                                    "B": {"duration": 1, "period": 4}}})
    >>> space = design_space(sk, offer="p,q", allocate="tasks")
    >>> [space.allocation.processors_of(a) for a in moves(space, 0)]  # from p p
    [('p', 'q')]
    """
    a = space.allocation
    if a is None:
        return []
    here = list(a.processors_of(allocation))
    out: dict[int, None] = {}
    for position in range(len(here)):
        for p in a.offered:
            if p != here[position]:
                out[a.index_of([*here[:position], p, *here[position + 1:]])] = None
    out.pop(allocation, None)
    return list(out)


def together_first(space: DesignSpace) -> list[int]:
    """The allocations that put a pair of tasks that never run at once, in the starting
    design, on one processor (one per pair: the second task's unit moved to the
    first's processor, or the first's when the second is pinned), in the order of the
    pairs; empty when processors are not offered, the starting design is not proven
    schedulable, or no pair is found. Each search calls it once, on its space.

    >>> from tegraph import Skeleton
    >>> from tegraph.design.explore.space import design_space
    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "A": {"duration": 1, "period": 4, "processor": "p"},
    ...     "B": {"duration": 1, "period": 4, "phase": 2, "processor": "q"}}})
    >>> space = design_space(sk, offer="p,q", allocate="tasks")
    >>> [space.allocation.processors_of(a) for a in together_first(space)]
    [('p', 'p')]
    """
    a = space.allocation
    if a is None:
        return []
    start = space.starting_variant()
    index = space.allocation_index(start)
    skeleton = space.build(start, validate=False)
    out: dict[int, None] = {}
    try:
        report = analyze_skeleton(skeleton, processors=True, max_events=space.max_events)
        found = shared_processor_candidates(skeleton, report, space.max_events)
    except TegraphError:  # a starting design the analysis refuses: no hint, the search
        found = None      # judges every variant anyway
    if found is not None and found.pairs:
        unit_of = {t: u for u, tasks in enumerate(a.units) for t in tasks}
        position = {u: k for k, u in enumerate(a.free)}
        here = list(a.processors_of(index))
        on = skeleton.tasks
        for first, second in found.pairs:
            for fixed, moved in ((first, second), (second, first)):
                u = unit_of.get(moved)  # None: it stays on a processor not offered
                if u is not None and u in position and unit_of.get(fixed) != u:
                    k = position[u]
                    target = on[fixed].runs_on
                    if target in a.offered:
                        out[a.index_of([*here[:k], target, *here[k + 1:]])] = None
                    break
    out.pop(index, None)
    return list(out)
