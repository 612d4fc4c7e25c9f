"""Rule 4: one priority per group, rate-monotonic, the automaton highest; all or none.

The priorities a task runs at, the rate-monotonic proposal and the automaton are the
platform's (:mod:`tegraph.model.platform`): :func:`proposed_priorities` is its
proposal [1]_, the one the exact schedule and the response-time cross-check run;
:func:`rule4` compares the declared priorities with it, one function per thing it
decides. A processor where some tasks declare a priority and others do not breaks the
contract (all or none, spec §4b: the declared ones are replaced by the proposal): an
error, whose machine-applicable change completes the declaration (:func:`completion`).
The other Rule 4 findings carry no change: their advice is the proposal, in words.

Rate-monotonic order is optimal among fixed priorities under preemption only [1]_: on
a processor declared ``preemptive: false`` (spec §4d) no finding says a departure from
it is a fault.

References
----------
.. [1] C. L. Liu, J. W. Layland, "Scheduling algorithms for
   multiprogramming in a hard-real-time environment", Journal of the ACM
   20(1), 46–61, 1973.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from fractions import Fraction

from maxplus.scalar import display_text

from ...model.platform import (
    DEFAULT_PROCESSOR,
    Platform,
    ProcessorInfo,
    is_automaton,
    platform_of,
    rate_monotonic,
)
from ...model.skeleton import Skeleton
from ...model.structure import Structure, design_period
from .change import Change
from .findings import FindingKind, RuleFinding

__all__ = ["completion", "is_automaton", "proposed_priorities", "rule4"]

Units = list[tuple[tuple[str, ...], int]]
"""The groups of one processor (their tasks with a declared priority), with that priority."""


def proposed_priorities(sk: Skeleton, structure: Structure | None = None) -> dict[str, int]:
    """Rate-monotonic priorities (Rule 4, spec §4b): larger is more urgent.

    :func:`tegraph.model.platform.rate_monotonic`, the one proposal: on each
    processor the groups by increasing design period (``Structure.periods``; groups
    without a clock last, as background work), ties in file order, numbered from 1
    (lowest) up, every task of a group at its group's number, and the automaton one
    above the rest. ``structure`` is ``Structure.of(sk)``, if known.

    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "SLOW": {"duration": 1, "period": 6}, "FAST": {"duration": 1, "period": 1},
    ...     "RTA": {"duration": 0}}})
    >>> proposed_priorities(sk)
    {'SLOW': 2, 'FAST': 3, 'RTA': 4}
    """
    return rate_monotonic(sk, structure)


def rule4(sk: Skeleton, structure: Structure, platform: Platform | None = None
          ) -> list[RuleFinding]:
    """The findings of Rule 4 on ``sk`` of structure ``structure``.

    Nothing declared: the proposal alone (``info``). Else, in turn: processors whose
    declaration is partial (an error, with the change that completes it), tasks
    without a priority on a processor where none is declared while others are, groups
    with several, groups sharing one on a processor, rate-monotonic order on each
    preemptive processor, the automaton above the rest. ``platform`` is
    ``report.platform``, if known.
    """
    platform = platform_of(sk, structure) if platform is None else platform
    proposal = proposed_priorities(sk, structure)
    declared = {t: task.priority for t, task in sk.tasks.items() if task.priority is not None}

    def propose(tasks: Sequence[str]) -> str:
        return ", ".join(f"{t}: {proposal[t]}" for t in tasks)

    if not declared:
        advice = ("rate-monotonic priorities (larger is more urgent; add `priority:` to each "
                  "task): " + propose(list(sk.tasks)))
        lazy = [p.name for p in platform.processors if not p.preemptive]
        if lazy:
            advice += (f"; on the non-preemptive processor {', '.join(lazy)} no fixed order is "
                       "optimal for every task set (a long job of a less urgent task blocks a "
                       "more urgent one): the schedule on processors says whether these fit")
        return [_finding(FindingKind.RULE4_NONE_DECLARED, tuple(sk.tasks),
                         "no priority is declared", advice)]
    out = [_partial(sk, structure, info, proposal) for info in platform.replaced]
    out += _missing(sk, declared, propose, platform)
    mixed, by_processor = _one_priority_per_group(sk, structure.groups, declared)
    out += mixed
    for processor, units in by_processor.items():
        on = "" if processor == DEFAULT_PROCESSOR else f" on processor {processor}"
        out += _shared_priorities(units, on, propose)
        if platform.preemptive(processor):  # rate-monotonic is optimal there only
            out += _not_rate_monotonic(sk, units, on, propose)
    out += _automaton_below(sk, declared)
    return out


def completion(sk: Skeleton, structure: Structure, tasks: Sequence[str],
               proposal: dict[str, int]) -> tuple[dict[str, int], bool]:
    """The priorities that complete a partial declaration on one processor.

    Parameters
    ----------
    sk : Skeleton
    structure : Structure
    tasks : sequence of str
        The tasks of the processor, in file order.
    proposal : dict of str to int
        The rate-monotonic proposal (:func:`proposed_priorities`).

    Returns
    -------
    (dict, bool)
        Task -> priority for each task whose priority changes, and whether every
        declared priority is kept. Kept where it can be: each task without one gets
        its group's declared priority when its group declares one on this processor
        (Rule 4: one priority per group); the groups that declare none are placed in
        rate-monotonic order among the declared ones, on integers between theirs
        (above the most urgent, below the least); an automaton above every other
        task. Where no integer lies between two declared priorities for the groups
        that come between them (or the declared ones are not in rate-monotonic order
        around them), every task of the processor gets the proposal (False).

    Examples
    --------
    A (period 5) and C (period 20) declare 10 and 5; B (period 10) and D (no clock)
    declare none: B between them, D below.

    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "A": {"duration": 1, "period": 5, "priority": 10},
    ...     "B": {"duration": 1, "period": 10},
    ...     "C": {"duration": 1, "period": 20, "priority": 5},
    ...     "D": {"duration": 1}}})
    >>> completion(sk, Structure.of(sk), list(sk.tasks), proposed_priorities(sk))
    ({'B': 9, 'D': 4}, True)
    """
    declared = {t: p for t in tasks if (p := sk.tasks[t].priority) is not None}
    control = [t for t in tasks if not is_automaton(t)]
    # The groups on this processor, most urgent first (the proposal's order).
    order = sorted(dict.fromkeys(structure.group_of[t] for t in control),
                   key=lambda g: -max(proposal[t] for t in control
                                      if structure.group_of[t] == g))
    members = {g: [t for t in control if structure.group_of[t] == g] for g in order}
    value: dict[int, int | None] = {
        g: max((declared[t] for t in ts if t in declared), default=None)
        for g, ts in members.items()}
    automata = [t for t in tasks if is_automaton(t)]
    ceiling = min((declared[t] for t in automata if t in declared), default=None)
    kept = _fill(order, value, ceiling)
    if kept is None:
        return {t: proposal[t] for t in tasks if declared.get(t) != proposal[t]}, False
    out = {t: kept[g] for g, ts in members.items() for t in ts if t not in declared}
    top = max(kept.values(), default=0) + 1
    out.update({t: max(top, max((declared[a] for a in automata if a in declared),
                                default=top))
                for t in automata if t not in declared})
    return {t: out[t] for t in tasks if t in out}, True


def _fill(order: list[int], value: dict[int, int | None], ceiling: int | None
          ) -> dict[int, int] | None:
    """Integers for the groups without a declared value (None), decreasing along
    ``order`` (most urgent first) between the declared ones and below ``ceiling``
    (a declared automaton); None when some run of them has no room."""
    out: dict[int, int] = {}
    i = 0
    above = ceiling
    while i < len(order):
        if value[order[i]] is not None:
            out[order[i]] = value[order[i]]  # type: ignore[assignment]
            above = value[order[i]]
            i += 1
            continue
        j = i
        while j < len(order) and value[order[j]] is None:
            j += 1
        run = order[i:j]
        below = value[order[j]] if j < len(order) else None
        if above is None and below is None:
            start = len(run)
        elif above is None:
            start = below + len(run)  # type: ignore[operator]
        else:
            start = above - 1
            if below is not None and start - len(run) + 1 <= below:
                return None
        for k, g in enumerate(run):
            out[g] = start - k
        i = j
    return out


def _finding(kind: FindingKind, tasks: tuple[str, ...], message: str, advice: str
             ) -> RuleFinding:
    """A Rule 4 finding: its key is the tasks it names, in that order."""
    return RuleFinding(kind, tasks, tasks, (), (), message, advice)


def _partial(sk: Skeleton, structure: Structure, info: ProcessorInfo,
             proposal: dict[str, int]) -> RuleFinding:
    """A processor where some tasks declare a priority and others do not: the contract
    is all or none (§4b), so the declared ones were replaced by the proposal. An error,
    with the change that completes the declaration (:func:`completion`)."""
    tasks = info.tasks
    missing = tuple(t for t in tasks if t not in info.replaced)
    on = ("the default processor" if info.name == DEFAULT_PROCESSOR
          else f"processor {info.name}")
    changed = [f"{t} {p} -> {info.priorities[t]}" for t, p in info.replaced.items()
               if p != info.priorities[t]]
    message = (f"{len(info.replaced)} of the {len(tasks)} tasks on {on} declare a priority "
               f"({', '.join(missing)} do not): the priorities of a processor are all "
               "declared or none (spec §4b), so every task there runs at the rate-monotonic "
               "proposal and the declared priorities are replaced"
               + (f" ({', '.join(changed)})" if changed else " (each by the same number)"))
    values, kept = completion(sk, structure, tasks, proposal)
    shown = ", ".join(f"{t}: {p}" for t, p in values.items())
    if kept:
        advice = ("complete the declaration, keeping every declared priority (the groups "
                  f"without one in rate-monotonic order among them): {shown}")
    else:
        advice = ("no integers between the declared priorities keep them in rate-monotonic "
                  "order around the groups without one: declare the proposal for the "
                  f"whole processor: {shown}")
    change = Change(priorities=tuple(values.items()))
    return RuleFinding(FindingKind.RULE4_PARTIAL, missing, missing, (), (), message, advice,
                       change)


def _missing(sk: Skeleton, declared: dict[str, int], propose: Callable[[Sequence[str]], str],
             platform: Platform) -> list[RuleFinding]:
    """Tasks without a priority, on processors where none is declared, while others have
    one (a partial processor is :func:`_partial`'s)."""
    partial = {t for p in platform.replaced for t in p.tasks}
    missing = [t for t in sk.tasks if t not in declared and t not in partial]
    if not missing:
        return []
    return [_finding(
        FindingKind.RULE4_MISSING, tuple(missing),
        f"no priority for {', '.join(missing)} while other tasks have one",
        "declare a priority for every task; rate-monotonic proposal: " + propose(missing))]


def _one_priority_per_group(sk: Skeleton, groups: Sequence[tuple[str, ...]],
                            declared: dict[str, int]
                            ) -> tuple[list[RuleFinding], dict[str, Units]]:
    """Groups whose tasks on one processor have several priorities (the automaton aside);
    and, by processor, the groups that have one, with it."""
    out = []
    by_processor: dict[str, Units] = {}
    for tasks in groups:
        parts: dict[str, list[str]] = {}
        for t in tasks:
            if t in declared and not is_automaton(t):
                parts.setdefault(sk.tasks[t].runs_on, []).append(t)
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
                  and sk.tasks[u].runs_on == sk.tasks[t].runs_on and theirs >= mine]
        if rivals:
            out.append(_finding(
                FindingKind.RULE4_AUTOMATON_BELOW, (t, *rivals),
                f"the automaton {t} (priority {mine}) is not above "
                + ", ".join(f"{u} ({declared[u]})" for u in rivals)
                + ": the reactive behavior would wait for the control tasks",
                f"give {t} a priority above {max(declared[u] for u in rivals)}"))
    return out
