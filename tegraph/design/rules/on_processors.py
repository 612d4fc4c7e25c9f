"""What an advised change does to the skeleton on its processors (spec §4b), before -> after.

The advice (:mod:`.advice`) states the periods a change gives, which assume a
processor per task (spec §4). A controller runs on a few processors under
preemptive fixed priorities (§4b), where a change can make the skeleton
schedulable or break it. :class:`ScheduleAdvice` decides that for the change
chosen for a finding:

- **where**: the groups the change touches, closed under "shares a processor
  with" (§4b's platform takes whole groups: the rate-monotonic proposal numbers
  the groups of a processor). A change re-forms groups only among the tasks it
  touches, so the same tasks are closed before and after; their schedule is
  independent of the rest (no place, no processor time shared), and the rest is
  not simulated again;
- **how**: that part alone (:meth:`~tegraph.model.skeleton.Skeleton.restricted_to`),
  before and with the change, analyzed on its processors
  (:func:`~tegraph.analysis.analyze.analyze_skeleton` with ``processors=True``,
  which decides it with :func:`~tegraph.analysis.processors.schedule_on_processors`);
- **within a budget**: :data:`CHANGE_EVENTS` event firings per simulation (two per
  change: before and after), :data:`ADVICE_EVENTS` in all, each simulation charged
  at least its fixed cost, and parts of more than :data:`PART_TASKS` tasks are not
  simulated. So a skeleton of 10,000 tasks with 10,000 findings costs a bounded
  time; once the budget is spent, the advice says so.

A clock the change adds gets the period the advisor proposed (``Change.period``,
:mod:`.periods`), else the one it assumed (a period no group has,
``Advisor.fresh``); the words say which. :meth:`ScheduleAdvice.after`
is the advisor's judge: it ranks the candidates by the schedule they lead to.

**Chains.** For each chain the change touches (a task of it in the part), the
advice states its first use on processors (spec §4c) before -> after: before, the
analysis' own figure when the caller has it; after, the part and the parts of the
chains' tasks (still independent of the rest) analyzed with the change and those
chains, within :data:`CHANGE_EVENTS` per simulation and a budget of their own
(:data:`ADVICE_EVENTS` again), so that the chains never take the schedule's clause
its budget.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from fractions import Fraction
from typing import Any

from maxplus.scalar import display_text

from ...model.budgets import MAX_EVENTS
from ...model.platform import processor_of, processor_parts
from ...model.skeleton import Skeleton
from .advice import _group_text
from .change import Change, ScheduleEffect, apply_change

__all__ = ["ADVICE_EVENTS", "CHANGE_EVENTS", "PART_TASKS", "ScheduleAdvice"]

CHANGE_EVENTS = MAX_EVENTS // 100
"""Event firings of one simulation of a changed part (10,000; twice per change:
before and after): a part the advice touches is usually a group or two, decided in
some tens to thousands of firings; past it the verdict is "undecided"."""

ADVICE_EVENTS = MAX_EVENTS // 5
"""Event firings the advice simulates in all (200,000, a fifth of what ``analyze``
spends on the whole schedule), each simulation counted at least
:data:`_MIN_COST` plus :data:`_TASK_COST` per task of its part."""

PART_TASKS = 500
"""Largest part (tasks on the processors a change touches) the advice simulates."""

_MIN_COST = 500
"""What one simulation costs at least, in firings: the fixed cost of building and
analyzing the part, counted as the firings of the simulation it takes as long as."""

_TASK_COST = 100
"""What building and analyzing a part costs per task, in firings (measured, and
counted as the firings that take as long), so that the advice's budget bounds its time."""

_SHOWN = 4
"""Groups named in a verdict's figures; more are counted."""


class _Verdict:
    """The §4b verdict of one part: schedulable (or None), and its words."""

    __slots__ = ("schedulable", "words")

    def __init__(self, schedulable: bool | None, words: str) -> None:
        self.schedulable, self.words = schedulable, words


class ScheduleAdvice:
    """The effect of advised changes on the skeleton's processors, within a budget.

    Parameters
    ----------
    skeleton : Skeleton
    groups : sequence of tuple of str
        The skeleton's groups (``Structure.of(skeleton).groups``).
    group_of : mapping
        Each task's index in ``groups``.
    fresh : Fraction
        The period of a clock a change adds (the advisor's assumption).
    chains : mapping or sequence of task-name sequences
        Chains whose first use on processors each advice states before -> after
        (spec §4c), for the changes that touch them; a mapping gives each chain's
        figures on processors as they are (``ChainReport.on_processors``), a sequence
        or a None figure leaves them to be computed.

    Examples
    --------
    Figure 12 on one processor: MT2 overruns at activation 3 (it waits for MT1's
    message every 10 ms on its 4 ms clock); with the link ASYN/ASYN, the two run
    at their own clocks (hand-derived in ``tests/tegraph/design/rules/test_on_processors.py``):

    >>> from tegraph.model.structure import Structure
    >>> sk = Skeleton.from_dict({"clocks": {"rtc": {"period": 10}}, "tasks": {
    ...     "MT1": {"duration": 1, "clock": "rtc", "outputs": ["y"]},
    ...     "MT2": {"duration": 2, "period": 4, "inputs": ["y"]}},
    ...   "links": [{"from": "MT1:y", "to": "MT2:y", "protocol": "ASYN/SYN"}]})
    >>> s = Structure.of(sk)
    >>> advice = ScheduleAdvice(sk, s.groups, s.group_of, Fraction(11))
    >>> effect = advice.effect(Change((("MT1:y", "MT2:y", "ASYN/ASYN"),)))
    >>> effect.before, effect.after, effect.tasks
    (False, True, ('MT1', 'MT2'))
    >>> effect.text[effect.text.index("NOT"):]
    'NOT SCHEDULABLE (MT2 overruns at activation 3) -> schedulable ({MT1} 10 ms, {MT2} 4 ms)'
    """

    def __init__(self, skeleton: Skeleton, groups: Sequence[tuple[str, ...]],
                 group_of: Mapping[str, int], fresh: Fraction,
                 chains: Mapping[tuple[str, ...], Any] | Sequence[Sequence[str]] = ()
                 ) -> None:
        self.sk, self.groups, self.group_of, self.fresh = skeleton, groups, group_of, fresh
        known = chains if isinstance(chains, Mapping) else {tuple(c): None for c in chains}
        self.chains = [tuple(c) for c in dict.fromkeys(tuple(c) for c in known)]
        self._as_it_is = {tuple(c): f for c, f in known.items() if f is not None}
        self._chain_known: dict[Any, Any] = {}
        self.chain_spent = 0
        """Event firings charged to the chains' clauses (their own :data:`ADVICE_EVENTS`)."""
        self.order = {t: i for i, t in enumerate(skeleton.tasks)}
        self.processor_of = processor_of(skeleton)
        self.part_of = self._parts()
        self.members: dict[int, list[str]] = {}  # each part's tasks, in file order
        for t in skeleton.tasks:
            self.members.setdefault(self.part_of[group_of[t]], []).append(t)
        self.spent = 0
        """Event firings charged so far (:data:`ADVICE_EVENTS`)."""
        self._known: dict[Any, _Verdict] = {}
        self._part_tasks: dict[tuple, tuple[tuple[str, ...], tuple[str, ...]]] = {}
        # The effect of any change on each part too large to simulate (it is the same).
        self._too_large: dict[tuple, ScheduleEffect] = {}

    def _parts(self) -> list[int]:
        """The part of each group on the processors (once, so that a change costs its
        own part, not the skeleton)."""
        return processor_parts(self.groups, self.processor_of)

    def _part(self, change: Change) -> tuple[tuple, tuple[str, ...], tuple[str, ...]]:
        """The key of the part ``change`` touches, its tasks and its processors."""
        touched = {port.split(":")[0] for w, r, _ in change.protocols for port in (w, r)}
        touched.update(change.drop_clock, change.add_clock)
        parts = {self.part_of[self.group_of[t]] for t in touched}
        key = tuple(sorted(parts))
        if key not in self._part_tasks:  # many changes touch one large part: once
            tasks = tuple(sorted((t for p in parts for t in self.members[p]),
                                 key=self.order.__getitem__))
            self._part_tasks[key] = (tasks, tuple(dict.fromkeys(
                self.processor_of[t] for t in tasks)))
        return (key, *self._part_tasks[key])

    def can_decide(self, change: Change) -> bool:
        """Whether :meth:`after` may still decide ``change``: its part is simulated (at
        most :data:`PART_TASKS` tasks) and its verdict is known or fits the budget
        :data:`ADVICE_EVENTS`, with room for the verdict before (the advice states both)."""
        key, tasks, _ = self._part(change)
        if len(tasks) > PART_TASKS:
            return False
        cost = _MIN_COST + _TASK_COST * len(tasks)
        needed = cost * sum((key, c) not in self._known for c in (Change(), change))
        return self.spent + needed <= ADVICE_EVENTS

    def after(self, change: Change) -> bool | None:
        """The §4b verdict with ``change`` made, on the part it touches (the advisor's
        :class:`~.advice.Judge`); None when not decided: undecided within
        :data:`CHANGE_EVENTS`, or not simulated (:meth:`can_decide`)."""
        key, tasks, _ = self._part(change)
        known = self._known.get((key, change))
        if known is not None:
            return known.schedulable
        if not self.can_decide(change):
            return None
        verdict = self._verdict(key, tasks, change)
        return None if verdict is None else verdict.schedulable

    def effect(self, change: Change) -> ScheduleEffect:
        """The §4b verdict before -> after ``change``, on the part it touches.

        Returns
        -------
        ScheduleEffect
            Its ``text`` is the advice's clause.
        """
        key, tasks, processors = self._part(change)
        unsimulated = self._too_large.get(key)
        if unsimulated is not None:
            return unsimulated  # one large part, a finding per task: its words once
        head = "on its processors (§4b), before -> after: "
        if len(tasks) > PART_TASKS:
            why = (f"not simulated: the processors it touches run {len(tasks):,} tasks, more "
                   f"than the advice simulates per change ({PART_TASKS:,}; tegraph analyze on "
                   "the changed file decides it)")
            effect = self._too_large[key] = ScheduleEffect(tasks, processors, None, None, why,
                                                           head + why)
            return effect
        # Both or neither: a verdict before alone would say nothing of the change.
        cost = _MIN_COST + _TASK_COST * len(tasks)
        needed = cost * sum((key, c) not in self._known for c in (Change(), change))
        if self.spent + needed > ADVICE_EVENTS:
            before = after = None
        else:
            before = self._verdict(key, tasks, Change())
            after = self._verdict(key, tasks, change)
        if before is None or after is None:
            why = (f"not decided: the advice's budget of {ADVICE_EVENTS:,} event firings in "
                   "all is spent (tegraph analyze on the changed file decides it)")
            return ScheduleEffect(tasks, processors, None, None, why, head + why)
        if before.words == after.words:
            text = head + before.words + ", unchanged"
        else:
            text = head + before.words + " -> " + after.words
        if change.add_clock and after.schedulable is not None:
            period = self.fresh if change.period is None else change.period
            text += (f" (the new clock at {display_text(period)} {self.sk.unit}, the period "
                     + ("the advice assumed)" if change.period is None else "proposed)"))
        undecided = None
        if before.schedulable is None or after.schedulable is None:
            undecided = f"undecided within {CHANGE_EVENTS:,} event firings per simulation"
        return ScheduleEffect(tasks, processors, before.schedulable, after.schedulable,
                              undecided, text + self._chains_clause(set(key), change))

    def _chains_clause(self, parts: set[int], change: Change) -> str:
        """The clause ``; first use on its processors (§4c), before -> after: ...``, the
        two figures of each chain with a task in ``parts`` (empty without one)."""
        touching = [c for c in self.chains
                    if any(self.part_of[self.group_of[t]] in parts for t in c)]
        if not touching:
            return ""
        reach = parts | {self.part_of[self.group_of[t]] for c in touching for t in c}
        tasks = tuple(t for t in self.sk.tasks if self.part_of[self.group_of[t]] in reach)
        head = "; first use on its processors (§4c), before -> after: "
        if len(tasks) > PART_TASKS:
            return (head + f"not simulated: the chains' processors run {len(tasks):,} tasks, "
                    f"more than the advice simulates per change ({PART_TASKS:,})")
        key = tuple(sorted(reach))
        cost = _MIN_COST + _TASK_COST * len(tasks)
        asked = [change] + ([] if all(c in self._as_it_is for c in touching) else [Change()])
        needed = cost * sum((key, c) not in self._chain_known for c in asked)
        if self.chain_spent + needed > ADVICE_EVENTS:
            return (head + f"not decided: the chains' budget of {ADVICE_EVENTS:,} event "
                    "firings in all is spent")
        before = [self._as_it_is[c] for c in touching] if len(asked) == 1 else \
            self._first_uses(key, tasks, Change(), touching)
        after = self._first_uses(key, tasks, change, touching)
        unit = self.sk.unit
        return head + "; ".join(
            f"{' -> '.join(c)} {_first_use(a, unit)} -> {_first_use(b, unit)}"
            for c, a, b in zip(touching, before, after))

    def _first_uses(self, key: tuple, tasks: tuple[str, ...], change: Change,
                    chains: list[tuple[str, ...]]) -> list[Any]:
        """The chains' figures on processors in the part of ``tasks`` with ``change``."""
        known = self._chain_known.get((key, change))
        if known is None:
            from ...analysis.analyze import analyze_skeleton

            sub = apply_change(self.sk.restricted_to(tasks), change,
                               self.fresh if change.add_clock else None)
            report = analyze_skeleton(sub, max_steps=CHANGE_EVENTS, semiflow_max_places=0,
                                      processors=True, max_events=CHANGE_EVENTS,
                                      chains=self.chains_in(tasks))
            assert report.schedule is not None  # processors=True
            self.chain_spent += (max(report.schedule.events, _MIN_COST)
                                 + _TASK_COST * len(tasks))
            known = self._chain_known[(key, change)] = {
                c.tasks: c.on_processors for c in report.chains}
        return [known[c] for c in chains]

    def chains_in(self, tasks: Sequence[str]) -> list[tuple[str, ...]]:
        """The chains whose tasks are all among ``tasks``."""
        inside = set(tasks)
        return [c for c in self.chains if inside.issuperset(c)]

    def _verdict(self, key: tuple, tasks: tuple[str, ...], change: Change) -> _Verdict | None:
        """The part of ``tasks`` with ``change`` made, decided on its processors (cached);
        None once :data:`ADVICE_EVENTS` is spent."""
        known = self._known.get((key, change))
        if known is not None:
            return known
        if self.spent + _MIN_COST + _TASK_COST * len(tasks) > ADVICE_EVENTS:
            return None
        from ...analysis.analyze import analyze_skeleton

        sub = apply_change(self.sk.restricted_to(tasks), change,
                           (self.fresh if change.period is None else change.period)
                           if change.add_clock else None)
        # Only the schedule is read: the semiflow cross-check is skipped, and the §4
        # dater simulation gets the same budget as the schedule.
        report = analyze_skeleton(sub, max_steps=CHANGE_EVENTS, semiflow_max_places=0,
                                  processors=True, max_events=CHANGE_EVENTS)
        schedule = report.schedule
        assert schedule is not None  # processors=True
        self.spent += max(schedule.events, _MIN_COST) + _TASK_COST * len(tasks)
        verdict = self._known[(key, change)] = _Verdict(
            schedule.schedulable, _words(sub, report))
        return verdict


def _first_use(figures: Any, unit: str) -> str:
    if figures.first_use is None:
        return f"undecided ({figures.why_undecided})"
    return f"{display_text(figures.first_use)} {unit}"


def _words(sk: Skeleton, report: Any) -> str:
    """A part's §4b verdict in words: why it is not schedulable (the first reason of:
    dead, first overrun, a starved task, a growing place), or its groups' periods."""
    schedule = report.schedule
    if schedule.schedulable is None:
        return f"undecided within {CHANGE_EVENTS:,} event firings"
    if schedule.schedulable:
        shown = [f"{_group_text(g.tasks)} {display_text(p)} {sk.unit}"
                 for g, p in zip(report.groups[:_SHOWN], schedule.group_periods)]
        if len(report.groups) > _SHOWN:
            shown.append(f"... ({len(report.groups)} groups)")
        return f"schedulable ({', '.join(shown)})"
    if not report.live:
        why = "dead: a token-free circuit"
    else:
        # The earliest problem, as every command names it first (ProcessorSchedule.problems).
        first = schedule.problems[0] if schedule.problems else None
        if first is not None and first.kind == "overrun":
            why = f"{first.task} overruns at activation {first.k}"
        elif first is not None:
            why = f"{first.task} never gets its processor (starved)"
        elif schedule.unbounded:
            u = schedule.unbounded[0]
            why = f"the place {u.src} -> {u.dst} grows ({u.kind})"
        else:  # schedulable False is proven by one of the above (spec §4b)
            why = "see tegraph analyze"
    return f"NOT SCHEDULABLE ({why})"
