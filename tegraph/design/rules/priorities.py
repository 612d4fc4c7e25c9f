"""Rule 4: one priority per group, rate-monotonic, the automaton highest.

:func:`proposed_priorities` is the rate-monotonic proposal [1]_ (which
:mod:`tegraph.design.schedulability` also uses when none is declared);
:func:`rule4` compares the declared priorities with it, one function per
thing it decides. Rule 4 findings carry no machine-applicable change: their
advice is the proposal, in words.

References
----------
.. [1] C. L. Liu, J. W. Layland, "Scheduling algorithms for
   multiprogramming in a hard-real-time environment", Journal of the ACM
   20(1), 46–61, 1973.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from fractions import Fraction

from maxplus.scalar import display_text

from ...model.skeleton import Skeleton
from ...model.structure import Structure, design_period
from .findings import FindingKind, RuleFinding

__all__ = ["is_automaton", "proposed_priorities", "rule4"]

_AUTOMATON = re.compile(r"(?:^|\.)(?:rta|automaton)$", re.IGNORECASE)

Units = list[tuple[tuple[str, ...], int]]
"""The groups of one processor (their tasks with a declared priority), with that priority."""


def is_automaton(name: str) -> bool:
    """Whether ``name`` names the Robot-task automaton (spec §6).

    >>> is_automaton("RTA"), is_automaton("arm.rta"), is_automaton("PARTA")
    (True, True, False)
    """
    return bool(_AUTOMATON.search(name))


def proposed_priorities(sk: Skeleton, structure: Structure | None = None) -> dict[str, int]:
    """Rate-monotonic priorities (Rule 4): larger is more urgent.

    On each processor, the automaton first, then the groups by increasing
    design period (``Structure.periods``; groups without a clock last, as
    background work), ties in file order; every task of a group gets its
    group's priority, distinct groups distinct priorities, numbered from 1
    (lowest) up. ``structure`` is ``Structure.of(sk)``, if known.

    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "SLOW": {"duration": 1, "period": 6}, "FAST": {"duration": 1, "period": 1},
    ...     "RTA": {"duration": 0}}})
    >>> proposed_priorities(sk)
    {'SLOW': 1, 'FAST': 2, 'RTA': 3}
    """
    index = {t: i for i, t in enumerate(sk.tasks)}
    units: dict[str | None, list[tuple[tuple, list[str]]]] = {}
    s = Structure.of(sk) if structure is None else structure
    for group, period in zip(s.groups, s.periods):
        parts: dict[tuple[str | None, bool], list[str]] = {}
        for t in group:
            parts.setdefault((sk.tasks[t].processor, is_automaton(t)), []).append(t)
        for (processor, auto), tasks in parts.items():
            key = (0 if auto else 1, 0 if period is not None else 1, period or 0,
                   index[tasks[0]])
            units.setdefault(processor, []).append((key, tasks))
    out: dict[str, int] = {}
    for parts_on in units.values():
        parts_on.sort(key=lambda u: u[0])
        for rank, (_, tasks) in enumerate(parts_on):
            for t in tasks:
                out[t] = len(parts_on) - rank
    return {t: out[t] for t in sk.tasks}


def rule4(sk: Skeleton, structure: Structure) -> list[RuleFinding]:
    """The findings of Rule 4 on ``sk`` of structure ``structure``.

    Nothing declared: the proposal alone (``info``). Else, in turn: tasks
    without a priority, groups with several, groups sharing one on a processor,
    rate-monotonic order on each processor, the automaton above the rest.
    """
    proposal = proposed_priorities(sk, structure)
    declared = {t: task.priority for t, task in sk.tasks.items() if task.priority is not None}

    def propose(tasks: Sequence[str]) -> str:
        return ", ".join(f"{t}: {proposal[t]}" for t in tasks)

    if not declared:
        return [_finding(
            FindingKind.RULE4_NONE_DECLARED, tuple(sk.tasks), "no priority is declared",
            "rate-monotonic priorities (larger is more urgent; add `priority:` to each task): "
            + propose(list(sk.tasks)))]
    out = _missing(sk, declared, propose)
    mixed, by_processor = _one_priority_per_group(sk, structure.groups, declared)
    out += mixed
    for processor, units in by_processor.items():
        on = "" if processor is None else f" on processor {processor}"
        out += _shared_priorities(units, on, propose)
        out += _not_rate_monotonic(sk, units, on, propose)
    out += _automaton_below(sk, declared)
    return out


def _finding(kind: FindingKind, tasks: tuple[str, ...], message: str, advice: str
             ) -> RuleFinding:
    """A Rule 4 finding: its key is the tasks it names, in that order."""
    return RuleFinding(kind, tasks, tasks, (), (), message, advice)


def _missing(sk: Skeleton, declared: dict[str, int], propose: Callable[[Sequence[str]], str]
             ) -> list[RuleFinding]:
    """Tasks without a priority while others have one."""
    missing = [t for t in sk.tasks if t not in declared]
    if not missing:
        return []
    return [_finding(
        FindingKind.RULE4_MISSING, tuple(missing),
        f"no priority for {', '.join(missing)} while other tasks have one",
        "declare a priority for every task; rate-monotonic proposal: " + propose(missing))]


def _one_priority_per_group(sk: Skeleton, groups: Sequence[tuple[str, ...]],
                            declared: dict[str, int]
                            ) -> tuple[list[RuleFinding], dict[str | None, Units]]:
    """Groups whose tasks on one processor have several priorities (the automaton aside);
    and, by processor, the groups that have one, with it."""
    out = []
    by_processor: dict[str | None, Units] = {}
    for tasks in groups:
        parts: dict[str | None, list[str]] = {}
        for t in tasks:
            if t in declared and not is_automaton(t):
                parts.setdefault(sk.tasks[t].processor, []).append(t)
        for processor, members in parts.items():
            values = sorted({declared[t] for t in members})
            if len(values) > 1:
                out.append(_finding(
                    FindingKind.RULE4_GROUP_PRIORITIES, tuple(members),
                    "the tasks of one synchronized group have different priorities ("
                    + ", ".join(f"{t}: {declared[t]}" for t in members)
                    + "): a higher-priority task of another group can run in the middle of it",
                    f"give them all one priority (e.g. {values[-1]})"))
            else:
                by_processor.setdefault(processor, []).append((tuple(members), values[0]))
    return out, by_processor


def _shared_priorities(units: Units, on: str, propose: Callable[[Sequence[str]], str]
                       ) -> list[RuleFinding]:
    """Each group of one processor that shares its priority with an earlier one."""
    out = []
    first_at: dict[int, tuple[str, ...]] = {}
    for a, pa in units:
        if pa in first_at:
            b = first_at[pa]
            out.append(_finding(
                FindingKind.RULE4_SHARED_PRIORITY, b + a,
                f"two synchronized groups share priority {pa}{on}: {{{', '.join(b)}}} "
                f"and {{{', '.join(a)}}}; the scheduler may interleave them",
                "give different groups different priorities, the shorter period the "
                "higher (rate-monotonic): " + propose(b + a)))
        else:
            first_at[pa] = a
    return out


def _not_rate_monotonic(sk: Skeleton, units: Units, on: str,
                        propose: Callable[[Sequence[str]], str]) -> list[RuleFinding]:
    """Each slower group above the least urgent of the strictly faster ones.

    Swept by increasing period (n log n, not all pairs); groups of one period
    are compared with the faster ones only.
    """
    out = []
    timed = sorted(((period, pa, a) for a, pa in units
                    if (period := design_period(sk, a)) is not None), key=lambda x: x[0])
    lowest: tuple[int, Fraction, tuple[str, ...]] | None = None  # of the faster groups
    i = 0
    while i < len(timed):
        j = i
        while j < len(timed) and timed[j][0] == timed[i][0]:
            j += 1
        for per_b, pb, b in timed[i:j]:
            if lowest is not None and lowest[0] < pb:
                _, per_a, a = lowest
                out.append(_finding(
                    FindingKind.RULE4_NOT_RATE_MONOTONIC, a + b,
                    f"not rate-monotonic{on}: {{{', '.join(a)}}} (period "
                    f"{display_text(per_a)} {sk.unit}) has a lower priority than "
                    f"{{{', '.join(b)}}} (period {display_text(per_b)} {sk.unit})",
                    "give the group with the shorter period the higher priority: "
                    + propose(a + b)))
        for per_b, pb, b in timed[i:j]:
            if lowest is None or pb < lowest[0]:
                lowest = (pb, per_b, b)
        i = j
    return out


def _automaton_below(sk: Skeleton, declared: dict[str, int]) -> list[RuleFinding]:
    """Each automaton not above every other task with a priority on its processor."""
    out = []
    for t, mine in declared.items():
        if not is_automaton(t):
            continue
        rivals = [u for u, theirs in declared.items() if not is_automaton(u)
                  and sk.tasks[u].processor == sk.tasks[t].processor and theirs >= mine]
        if rivals:
            out.append(_finding(
                FindingKind.RULE4_AUTOMATON_BELOW, (t, *rivals),
                f"the automaton {t} (priority {mine}) is not above "
                + ", ".join(f"{u} ({declared[u]})" for u in rivals)
                + ": the reactive behavior would wait for the control tasks",
                f"give {t} a priority above {max(declared[u] for u in rivals)}"))
    return out
