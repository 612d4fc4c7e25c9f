"""What to change for a finding of design rules 1-3, so that following the advice converges.

Each finding of Rules 1 to 3 (:func:`~.check.check_rules`) gets a
:class:`~.change.Change`, a machine-applicable edit of the skeleton (links that
get another protocol, clocks removed, clocks added), and its advice is that
change in words. The change is the smallest of a short list of candidates
(fewest links and clocks edited; among equals, the order below, which is the
ORCCAD paper's preference [1]_) that *brings no new finding*: applied to the
skeleton, the finding is gone and every finding of Rules 1-3 left was there
before. So, following the advice one finding at a time, the findings of Rules
1-3 only ever shrink: none comes back, and the loop ends. When no candidate
qualifies, the finding has no change and its advice says what the first
candidate would bring.

The candidates are :mod:`.candidates`. A candidate is checked where it can
change the rules (:meth:`Advisor.brings`): Rule 1 for the tasks it touches,
Rule 3 for the groups their tasks form afterwards, Rule 2 for its links and
the ASYN/ASYN links of those groups (but those of a group that stays as it
was, whose findings are as before). So a check costs the size of the groups
touched, not of the skeleton. Findings are compared by their identity (kind
and key, :attr:`~.findings.RuleFinding.identity`), never by their words.

References
----------
.. [1] D. Simon et al., "Design and analysis of synchronization for
   real-time closed-loop control in robotics", IEEE Transactions on Control
   Systems Technology, 1998.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Mapping, Sequence
from fractions import Fraction
from typing import Any, Literal
from typing import Protocol as _Protocol

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from maxplus.scalar import display_text

from ...analysis.reorder import PrecedenceGraph
from ...model.skeleton import Link, Protocol, Skeleton
from ...model.structure import Structure
from .candidates import CANDIDATE_LIMIT, SPLIT, Candidates, Edits
from .change import Change, apply_change
from .findings import FindingKey, FindingKind, RuleFinding, link_key
from .periods import TRIES, candidate_periods
from .periods import lcm as lcm_of
from .rates import DEAD, Rates, task_rates, token_free
from .regroup import Regrouping

__all__ = ["CANDIDATE_LIMIT", "JUDGED", "PERIODS_BUDGET", "SPLIT", "Advisor", "Choice", "Judge",
           "PeriodProposal"]

PERIODS_BUDGET = 10_000
"""Tasks the advice may rebuild and solve, in all, to state real periods (each
solve counts at least ``_SOLVE_COST``): a change to a group of n tasks rebuilds
and solves those n tasks, so one finding per task of a 10,000-task chain would
cost 10^8 (hours); 10,000 is about a second of solving. A change is solved only
while the periods before it fit too (they are worded side by side). Past it, the
advice states no period before -> after and says so; the choice then falls back
to the smallest change bringing no finding."""

_SOLVE_COST = 30
"""What one solve costs at least, in tasks: the fixed cost of a build and a solve."""

_NO_CHANGE = Change()


class _Roots:
    """The root task of each task of some groups, as a read-only mapping (built on demand)."""

    __slots__ = ("groups", "group_of", "chosen")

    def __init__(self, groups: Sequence[tuple[str, ...]], group_of: Mapping[str, int],
                 chosen: set[int]) -> None:
        self.groups, self.group_of, self.chosen = groups, group_of, chosen

    def __contains__(self, task: object) -> bool:
        return isinstance(task, str) and self.group_of.get(task) in self.chosen

    def __getitem__(self, task: str) -> str:
        return self.groups[self.group_of[task]][0]


class Judge(_Protocol):
    """The exact §4b verdict of the skeleton once a change is made, on the part the change
    touches (:class:`~.on_processors.ScheduleAdvice` is one)."""

    def after(self, change: Change) -> bool | None:
        """Schedulable with ``change`` made; None: not decided."""

    def can_decide(self, change: Change) -> bool:
        """Whether a verdict may still come for ``change`` (its part is not too large,
        the budget is not spent)."""

_SCHEDULE_RANK = {True: 0, None: 1, False: 2}
"""A candidate's rank by the exact schedule it leads to: schedulable first."""

JUDGED = 4
"""Candidates of one finding judged by the exact schedule, at most (the first that bring
no finding); the later ones rank as undecided."""


class PeriodProposal:
    """The period proposed for the clocks a change adds (:mod:`.periods`).

    Attributes
    ----------
    period : Fraction
    hyperperiod : Fraction
        Of the periods around the new group with it.
    schedulable : bool or None
        The exact verdict with it (None: not decided, or not judged).
    tried : int
        Candidate periods judged by the exact schedule (0: none judged).
    divides : bool
        It divides the hyperperiod of the periods around the group (which stays).
    source : str
        Where the candidates came from: ``"linked"`` (the groups the new group is
        linked to), ``"processor"`` (those on its processors), ``"cycle time"`` (its
        own, without any clock around it), ``"duration"`` (its longest task duration,
        the same for a dead group) or ``"assumed"`` (nothing known: the period the check
        assumed).
    """

    __slots__ = ("period", "hyperperiod", "schedulable", "tried", "divides", "source")

    def __init__(self, period: Fraction, hyperperiod: Fraction, schedulable: bool | None,
                 tried: int, divides: bool, source: str) -> None:
        self.period, self.hyperperiod, self.schedulable = period, hyperperiod, schedulable
        self.tried, self.divides, self.source = tried, divides, source


class Choice:
    """What :meth:`Advisor.choose` found for one finding.

    Attributes
    ----------
    change : Change or None
        None when no candidate examined removes the finding without another one.
    kept : str
        With a change: what the task keeps (Rule 1) or the clock kept (Rule 3).
        Without: the first candidate, in words.
    brought : set of keys
        Without a change: what the first candidate would bring.
    live : bool or None
        None when the skeleton is live; else whether the change makes it live.
    periods : str
        What the change does to the period of each group it touches, in words.
    proposal : PeriodProposal or None
        The period proposed for the clocks the change adds (None: it adds none).
    """

    __slots__ = ("change", "kept", "brought", "live", "periods", "proposal")

    def __init__(self, change: Change | None, kept: str, brought: set[FindingKey],
                 live: bool | None = None, periods: str = "",
                 proposal: PeriodProposal | None = None) -> None:
        self.change, self.kept, self.brought = change, kept, brought
        self.live, self.periods, self.proposal = live, periods, proposal


class Advisor(Candidates):
    """The structure of one skeleton, the candidates for each finding, and their check.

    Parameters
    ----------
    skeleton : Skeleton
    findings : list of RuleFinding
        The findings of Rules 1-3 on ``skeleton``: a change must bring no
        finding outside them.
    structure : Structure, optional
        ``Structure.of(skeleton)``, if known.
    live : bool, optional
        Whether ``skeleton`` is live (no token-free circuit), if known: a live
        skeleton has no dead group to search for (:meth:`_dead_groups`).
    """

    def __init__(self, skeleton: Skeleton, findings: list[RuleFinding],
                 structure: Structure | None = None, live: bool | None = None) -> None:
        super().__init__(skeleton, structure)
        self.periods = self.structure.periods
        self._group_clocks: dict[int, tuple[dict[str, int], list[tuple[Fraction, str]]]] = {}
        self.order = {t: i for i, t in enumerate(skeleton.tasks)}
        self.link_order = {id(link): i for i, link in enumerate(skeleton.links)}
        self.clock_order = {c: i for i, c in enumerate(skeleton.clocks)}
        self.threads_of: dict[int, list[tuple[str, ...]]] = {}
        for thread in skeleton.threads:
            self.threads_of.setdefault(self.group_of[thread[0]], []).append(thread)
        periods = [c.period for c in skeleton.clocks.values()]
        self.fresh = max(periods, default=Fraction(0)) + 1  # a period no group has
        self.keys = {f.identity for f in findings}
        self._after: tuple[Edits, tuple[list[int], dict, Any]] | None = None
        self._change: tuple[Edits, Change] | None = None
        self._rates_after: tuple[Edits, int, Rates | None] | None = None
        # The Rule 3 finding of each group, by the group's own tuple: :meth:`brings`
        # need not hash all the tasks of a group that stays as it was to see that its
        # finding is not new (a group of 10,000 tasks, once per finding of its tasks).
        self._rule3: dict[int, FindingKind] = {}
        for kind, key in self.keys:
            if kind in (FindingKind.RULE3_NO_CLOCK, FindingKind.RULE3_SEVERAL_CLOCKS):
                members = self.groups[self.group_of[key[0]]]
                if members == key:
                    self._rule3[id(members)] = kind
        # The groups with a token-free circuit (on demand; none in a live skeleton).
        self._dead: set[int] | None = set() if live else None
        self._live: dict[Change, bool] = {}
        # Real periods by the groups solved, then by change: a group that was never
        # solved and does not fit the budget is refused before its change is formed.
        self._real: dict[tuple[int, ...], dict[Change, Rates]] = {}
        self.periods_spent = 0
        """Tasks rebuilt and solved so far for real periods (:data:`PERIODS_BUDGET`)."""
        # Each group's clocked load on each processor (:meth:`_load_beside`, on demand).
        self._group_load: list[dict[str | None, Fraction]] | None = None
        self.clock_users: dict[str, int] = {}
        for task in skeleton.tasks.values():
            if task.clock:
                self.clock_users[task.clock] = self.clock_users.get(task.clock, 0) + 1
        # Each link under its writer's group, so that cutting out a few groups costs
        # their own links, not the whole skeleton's (_within, once per candidate).
        self.links_from: list[list[Link]] = [[] for _ in self.groups]
        for link in skeleton.links:
            self.links_from[self.group_of[link.writer[0]]].append(link)
        self.regrouping = Regrouping(skeleton, self.groups, self.links_from, self.threads_of,
                                     self.order, self.fresh)
        # The ASYN/ASYN links each group has: Rule 2 re-reads them when the group changes.
        self.asyn: list[list[Link]] = [[] for _ in self.groups]
        for link in skeleton.links:
            if link.protocol is Protocol.ASYN_ASYN:
                gw, gr = self.group_of[link.writer[0]], self.group_of[link.reader[0]]
                self.asyn[gw].append(link)
                if gr != gw:
                    self.asyn[gr].append(link)

    # ------------------------------------------------------------ the check
    def choose(self, finding: RuleFinding, judge: Judge | None = None) -> Choice:
        """The best candidate that brings no new finding, with the words of its advice.

        Among the candidates that bring no new finding, the first (smallest, then
        in the order of preference) that is best by, in turn: the exact schedule on
        processors it leads to (``judge``: schedulable first, then undecided, then
        not schedulable; a change that adds a clock is judged with the period
        proposed for it, :meth:`propose_period`), making the skeleton live when it
        is dead (token-free circuits of the edited skeleton), keeping the designed
        rates: the fewest clocked tasks of the touched groups that do not run at
        their clock's period afterwards (the periods the edited groups run at,
        :meth:`real_periods`), then the fewest groups left not rate-consistent. The
        scan stops at the first candidate that is schedulable (or not judged), live,
        keeps every clock's period and leaves every touched group rate-consistent. At
        most :data:`JUDGED` candidates are judged; the later ones rank as undecided.

        Parameters
        ----------
        finding : RuleFinding
        judge : Judge, optional
            The exact verdict on processors of a change (None: not judged, every
            candidate alike, as with a processor per task).

        Returns
        -------
        Choice
        """
        key = finding.identity
        first: Edits | None = None
        best: tuple[tuple[int, int, int, int], Edits, Change, PeriodProposal | None] | None = None
        judged = 0
        # The smallest edits first; among equals, the order of preference.
        for edits in self.ranked(finding):
            if self.brings(key, edits, whole=False) is not None:
                first = first or edits
                continue
            live = 0 if self.makes_live(edits) is not False else 1
            # Past the periods budget no period is known: none moves, none is mixed
            # (what resampled and inconsistent would say, without asking them).
            rest = ((live, 0, 0) if self._periods_after(edits) is None
                    else (live, len(self.resampled(edits)), self.inconsistent(edits)))
            if best is not None and best[0][0] == 0 and rest >= best[0][1:]:
                continue  # cannot beat a schedulable one: not judged
            # Past JUDGED candidates, the others are not judged (undecided): the cost of a
            # finding stays a few simulations, whatever its candidates.
            now = judge if judged < JUDGED else None
            judged += judge is not None
            change, proposal = self.change_of(edits), None
            if change.add_clock:
                proposal = self.propose_period(edits, now)
                change = dataclasses.replace(change, period=proposal.period)
            verdict = (None if now is None else proposal.schedulable if proposal is not None
                       else now.after(change))
            rank = (0 if judge is None else _SCHEDULE_RANK[verdict], *rest)
            if best is None or rank < best[0]:
                best = (rank, edits, change, proposal)
            # Best by every criterion; or by every other one, and no verdict will come
            # (a part too large, the budget spent): the later candidates cannot do better.
            if rank == (0, 0, 0, 0) or (rest == (0, 0, 0) and verdict is None and (
                    now is None or not now.can_decide(change))):
                break
        if best is not None:
            _, edits, change, proposal = best
            return Choice(change, edits.kept, set(), self.makes_live(edits),
                          self.periods_text(edits, change), proposal)
        if first is None:
            return Choice(None, "", set())
        brought = self.brings(key, first) or set()
        return Choice(None, self.describe(self.change_of(first)), brought,
                      periods=self.periods_text(first))

    def propose_period(self, edits: Edits, judge: Judge | None = None) -> PeriodProposal:
        """The period for the clocks ``edits`` add, from the skeleton's own periods.

        The candidates of :func:`.periods.candidate_periods` (around the group the
        clocked tasks form afterwards: its neighbours by ASYN/ASYN links, the groups
        on its processors, its cycle time), judged by ``judge`` in turn, at most
        :data:`.periods.TRIES` of them: the first schedulable one, else the first.
        Without a judge, the first. Without any period to start from, the period
        the check assumed (:attr:`fresh`).
        """
        groups, part, root_of = self._groups_after(edits)
        members = {t for added in edits.add for t in part[root_of[added]][0]}
        edited = edits.by_id()
        near: set[Fraction] = set()
        for t in members:
            for link in itertools.chain(self.inputs(t), self.outputs(t)):
                other = link.reader[0] if link.writer[0] == t else link.writer[0]
                if other in members or edited.get(id(link), link.protocol) is not \
                        Protocol.ASYN_ASYN:
                    continue
                g = root_of[other] if other in root_of else self.group_of[other]
                period = part[g][2] if g in part else self.periods[g]
                if period is not None and period != self.fresh:
                    near.add(period)
        touched = set(groups)
        processors = {self.sk.tasks[t].processor for t in members}
        around: set[Fraction] = set()
        for g, period in enumerate(self.periods):
            if (period is not None and g not in touched
                    and self.sk.tasks[self.groups[g][0]].processor in processors):
                around.add(period)
        # A faster clock would overrun: at least the group's cycle time (each task's own
        # chain holds its duration, a bound when the periods budget is spent).
        lower = max(self.sk.tasks[t].duration for t in members)
        own = "duration"
        before = self.real_periods(groups, Change(), self.group_of)
        if before is not None:
            cycle = [before.period[t] for t in members if before.period.get(t) not in (None, DEAD)]
            if cycle:
                lower, own = max(cycle), "cycle time"
        found = candidate_periods(near, around, lower)
        if not found:
            return PeriodProposal(self.fresh, self.fresh, None, 0, False, "assumed")
        source = "linked" if near else "processor" if around else own
        reference = lcm_of(near | around) if near | around else lower
        chosen, verdict, tried = found[0], None, 0
        if judge is not None:
            change = self.change_of(edits)
            load, work = self._load_beside(touched, members)
            verdicts: list[tuple[tuple[Fraction, Fraction], bool | None]] = []
            for period, hyper in found[:TRIES]:
                if any(load[proc] + w / period > 1 for proc, w in work.items()):
                    # More work with a clock than its processor's time: some task falls
                    # behind its clock, proven by the load alone (no simulation).
                    tried += 1
                    verdicts.append(((period, hyper), False))
                    continue
                candidate = dataclasses.replace(change, period=period)
                if verdicts and not judge.can_decide(candidate):
                    break  # no verdict will come for the others either
                tried += 1
                v = judge.after(candidate)
                verdicts.append(((period, hyper), v))
                if v is True:
                    break
            chosen, verdict = next(((c, v) for c, v in verdicts if v is True), verdicts[0])
        return PeriodProposal(chosen[0], chosen[1], verdict, tried, chosen[1] == reference,
                              source)

    def _load_beside(self, touched: set[int], members: set[str]
                     ) -> tuple[dict[str | None, Fraction], dict[str | None, Fraction]]:
        """The load of the clocked groups not ``touched`` on each processor of
        ``members``, and the members' work per processor.

        Only groups whose clocks share one period are counted (each of their tasks runs
        once per that period wherever they keep pace): a lower bound of the processor's
        load, so that a load above 1 with the new clock proves it overloaded. Each
        group's share is computed once, over the whole skeleton.
        """
        if self._group_load is None:
            self._group_load = []
            self._total_load: dict[str | None, Fraction] = {}
            for tasks in self.groups:
                share: dict[str | None, Fraction] = {}
                periods = {self.sk.clocks[c].period for t in tasks
                           if (c := self.sk.tasks[t].clock) is not None}
                if len(periods) == 1:
                    (period,) = periods
                    for t in tasks:
                        proc = self.sk.tasks[t].processor
                        share[proc] = (share.get(proc, Fraction(0))
                                       + self.sk.tasks[t].duration / period)
                for proc, x in share.items():
                    self._total_load[proc] = self._total_load.get(proc, Fraction(0)) + x
                self._group_load.append(share)
        work: dict[str | None, Fraction] = {}
        for t in members:
            proc = self.sk.tasks[t].processor
            work[proc] = work.get(proc, Fraction(0)) + self.sk.tasks[t].duration
        load = {}
        for proc in work:
            load[proc] = self._total_load.get(proc, Fraction(0)) - sum(
                (self._group_load[g].get(proc, Fraction(0)) for g in touched), Fraction(0))
        return load, work

    # ------------------------------------------------------------ rates and liveness
    def _groups_after(self, edits: Edits) -> tuple[list[int], dict, Any]:
        """The groups the edited tasks are in, and those their tasks form after ``edits``.

        Remembered for the last edits asked about: ranking a candidate and wording
        the chosen one ask for the same edits up to five times.
        """
        if self._after is not None and self._after[0] is edits:
            return self._after[1]
        self._after = (edits, self._form_groups_after(edits))
        return self._after[1]

    def _form_groups_after(self, edits: Edits) -> tuple[list[int], dict, Any]:
        group_of = self.group_of
        groups = sorted({group_of[t] for t in edits.touched()})
        part, root_of = self._regroup(groups, edits)
        return groups, part, root_of

    def resampled(self, edits: Edits) -> list[tuple[str, Fraction, Fraction | Literal["dead"]]]:
        """The clocked tasks of the touched groups that do not run at their clock's
        period once ``edits`` are made: (task, its clock's period, its period after).

        The period after is the task's cycle time in the edited skeleton
        (:meth:`real_periods`), ``DEAD`` where its group is dead. A task that loses its
        clock counts against its clock's period too: the designed rate is the clock's.
        """
        groups, _, _ = self._groups_after(edits)
        real = self._periods_after(edits)
        if real is None:
            return []
        out = []
        for g in groups:
            for t in self.groups[g]:
                clock = self.sk.tasks[t].clock
                if clock is None:
                    continue
                own = self.sk.clocks[clock].period
                if real.period[t] != own:
                    out.append((t, own, real.period[t]))
        return out

    def inconsistent(self, edits: Edits) -> int:
        """How many groups touched by ``edits`` are not rate-consistent afterwards."""
        _, part, _ = self._groups_after(edits)
        real = self._periods_after(edits)
        if real is None:
            return 0
        return sum(members[0] in real.mixed for members, _, _ in part.values())

    def _periods_after(self, edits: Edits) -> Rates | None:
        """:meth:`real_periods` of the touched groups once ``edits`` are made.

        Remembered for the last edits asked about while nothing more is solved (the
        answer then stays the same): ranking a candidate and wording it ask up to
        three times, and each time the key of the cache would hash the change anew.
        """
        known = self._rates_after
        if known is not None and known[0] is edits and known[1] == self.periods_spent:
            return known[2]
        groups, _, root_of = self._groups_after(edits)
        if (tuple(groups) not in self._real and self.periods_spent + self._cost(groups)
                * (1 if _changes_nothing(edits) else 2) > PERIODS_BUDGET):
            # What real_periods would answer, without forming and hashing the change: a
            # group past the budget is asked about once per finding of its tasks (10,000).
            real = None
        else:
            real = self.real_periods(groups, self.change_of(edits), root_of)
        self._rates_after = (edits, self.periods_spent, real)
        return real

    def real_periods(self, groups: list[int], change: Change, roots: Mapping[str, Any]
                     ) -> Rates | None:
        """The period of each task of ``groups`` once ``change`` is made (None: dead).

        ``roots``: the group of each of their tasks once ``change`` is made (any
        label per group: :meth:`_regroup`'s root task, or ``group_of`` for no change).

        Only the touched groups are rebuilt, edited and solved: the cycle time of
        each task's compute event is the max cycle ratio of the timed event graph
        of those groups (:func:`maxplus.max_cycle_ratio`, exact), as
        :func:`tegraph.analysis.analyze` computes it; the tasks of a weak part
        with a token-free circuit have none. Cached by change. None once
        :data:`PERIODS_BUDGET` is spent.
        """
        solved = self._real.get(tuple(groups), {})
        known = solved.get(change)
        if known is None:
            cost = self._cost(groups)
            # A change's periods are worded beside those before it: solve it only
            # when the periods before can be solved too (else a group as large as
            # the budget would spend it all on periods nobody reads).
            pair = cost if change == _NO_CHANGE or _NO_CHANGE in solved else 2 * cost
            if self.periods_spent + pair > PERIODS_BUDGET:
                return None
            self.periods_spent += cost
            edited = apply_change(self._within(groups), change,
                                  self._period_of(change))
            known = solved[change] = task_rates(edited, roots)
            self._real[tuple(groups)] = solved
        return known

    def _period_of(self, change: Change) -> Fraction | None:
        """The period of the clocks ``change`` adds: proposed, else the one assumed."""
        if not change.add_clock:
            return None
        return self.fresh if change.period is None else change.period

    def _cost(self, groups: list[int]) -> int:
        """What solving ``groups`` costs against :data:`PERIODS_BUDGET`, in tasks."""
        return max(_SOLVE_COST, sum(len(self.groups[g]) for g in groups))

    def _groups_text(self, members: list[tuple[str, ...]], real: Rates) -> str:
        u = self.sk.unit
        parts = []
        for tasks in members:
            periods = {real.period[t] for t in tasks}
            if DEAD in periods:
                words = "dead"
            elif tasks[0] in real.mixed:
                words = "not rate-consistent (" + ", ".join(
                    f"{who} {self._period(r, u)}" for who, r in real.mixed[tasks[0]]) + ")"
            else:
                words = self._period(periods.pop(), u)
            parts.append(f"{_group_text(tasks)} {words}")
        return ", ".join(parts)

    def makes_live(self, edits: Edits) -> bool | None:
        """Whether the skeleton with ``edits`` made is live; None when it is live already.

        Only the groups the edits touch can change: when a token-free circuit lies
        in another group, the answer is no at once; else the touched groups alone
        are rebuilt, edited, and searched for token-free circuits.
        """
        if self._dead is None:
            self._dead = self._dead_groups()
        if not self._dead:
            return None
        groups, _, _ = self._groups_after(edits)
        if not self._dead <= set(groups):
            return False
        change = self.change_of(edits)
        if change not in self._live:
            edited = apply_change(self._within(groups), change,
                                  self._period_of(change))
            self._live[change] = not token_free(edited)
        return self._live[change]

    def _within(self, groups: list[int] | set[int]) -> Skeleton:
        """The skeleton cut down to the tasks of ``groups`` (their links, clocks, threads).

        Only the clocks of those tasks are kept: another clock would be a tick alone
        on its part, which no task's period reads, but which the timed event graph
        would build and the solver solve (a skeleton of 637 private clocks made each
        solve of a 25-task group 700 events, not 100). The names a clock added to one
        of the tasks would take (``T.clock``, then ``T.clock'``...) are kept too, so
        that :func:`.apply_change` names it as on the whole skeleton.
        """
        chosen = set(groups)
        tasks = sorted((t for g in chosen for t in self.groups[g]), key=self.order.__getitem__)
        links = sorted((x for g in chosen for x in self.links_from[g]
                        if self.group_of[x.reader[0]] in chosen),
                       key=lambda x: self.link_order[id(x)])
        threads = [th for g in sorted(chosen) for th in self.threads_of.get(g, [])]
        clocks = self.sk.clocks
        kept = set()
        for t in tasks:
            if (clock := self.sk.tasks[t].clock) is not None:
                kept.add(clock)
            name = f"{t}.clock"
            while name in clocks:
                kept.add(name)
                name += "'"
        return dataclasses.replace(
            self.sk, tasks={t: self.sk.tasks[t] for t in tasks},
            clocks={c: clocks[c] for c in sorted(kept, key=self.clock_order.__getitem__)},
            links=links, threads=threads, chains=[])

    def _dead_groups(self) -> set[int]:
        """The groups that hold a token-free circuit (spec §4 deadlocks).

        The 0-token places of the timed event graph are, up to transitivity, the
        precedence graph of :mod:`tegraph.analysis.reorder` (chains, links,
        clocks, threads) plus each task's declared read and write orders: its
        strong components with more than one event, or a self-loop, are the
        token-free circuits (as :mod:`.fix` reads them). This costs no time
        values, where building the timed event graph checks every one.
        """
        g = PrecedenceGraph(self.sk)
        for name, task in self.sk.tasks.items():
            for nodes in ([g.read[name, p] for p in task.inputs],
                          [g.write[name, p] for p in task.outputs]):
                for u, v in itertools.pairwise(nodes):
                    g.succ[u].append(v)
        n = len(g.names)
        edges = [(u, v) for u, outs in enumerate(g.succ) for v in outs]
        rows, cols = (list(x) for x in zip(*edges)) if edges else ([], [])
        matrix = sp.csr_matrix((np.ones(len(edges), dtype=np.int8), (rows, cols)), shape=(n, n))
        _, label = connected_components(matrix, directed=True, connection="strong")
        sizes = np.bincount(label, minlength=n)
        dead = {int(x) for x in np.flatnonzero(sizes[label] > 1)} | {u for u, v in edges if u == v}
        return {self.group_of[t] for t, events in g.events_of.items() if dead.intersection(events)}

    def periods_text(self, edits: Edits, change: Change | None = None) -> str:
        """What ``edits`` do to the period of each group they touch, before -> after.

        The periods are those the skeleton runs at (:meth:`real_periods`, before
        and after the change), not the design periods: a group whose tasks run at
        different rates is "not rate-consistent", a group with a token-free
        circuit "dead". Each clocked task that does not run at its clock's period
        afterwards is named. ``change``: the change of ``edits`` with the period
        proposed for the clocks it adds (default: the one the check assumed).
        """
        u = self.sk.unit
        groups, part, root_of = self._groups_after(edits)
        # The change first: it is solved only when the periods before fit the budget too.
        real = self._periods_after(edits)
        if real is not None and change is not None and change.period is not None:
            real = self.real_periods(groups, change, root_of)
        now = None if real is None else self.real_periods(groups, Change(), self.group_of)
        if now is None or real is None:
            return (f"periods before -> after not computed: the advice's budget of "
                    f"{PERIODS_BUDGET:,} tasks rebuilt is spent (tegraph analyze on the "
                    "changed file gives them)")
        before = [self.groups[g] for g in groups]
        after = [tuple(members) for members, _, _ in part.values()]
        text = "periods (max cycle ratio), before -> after: "
        if set(before) == set(after) and all(
                now.period[t] == real.period[t] and (t in now.mixed) == (t in real.mixed)
                for g in before for t in g):
            text += self._groups_text(before, now) + ", unchanged"
        else:
            text += (self._groups_text(before, now) + " -> " + self._groups_text(after, real))
        moved = self.resampled(edits)
        if moved:
            text += "; " + "; ".join(
                f"{t} runs {'every ' + self._period(a, u) if a != DEAD else 'never (dead)'}"
                f", not every {display_text(b)} {u} (its clock's period"
                + (", and its clock goes)" if t in edits.drop else ")")
                for t, b, a in moved)
        elif any(self.sk.tasks[t].clock for g in before for t in g):
            text += "; every clocked task keeps its clock's period"
        return text

    def _period(self, period: Fraction | None, unit: str) -> str:
        if period is None:
            return "no period"
        if period == self.fresh:
            return "a period of your choice"
        return f"{display_text(period)} {unit}"

    def brings(self, key: FindingKey, edits: Edits, whole: bool = True
               ) -> set[FindingKey] | None:
        """None when ``edits`` remove the finding ``key`` and bring none; else what is new.

        With ``whole`` False, what is new may be told only in part (Rule 1 first:
        most candidates that fail, fail there, and the groups need not be re-formed).

        The rules are re-read only where the edits can change them: Rule 1 for
        the tasks whose links or clock they touch; the groups of those tasks are
        re-formed (synchronizing links, threads and shared clocks among their
        tasks, after the edits) for Rule 3; Rule 2 for the edited links and the
        ASYN/ASYN links of those groups. Everything else is as it was.
        (``tests/tegraph/design/rules/test_advice.py`` compares this with a full re-check.)
        """
        after: set[FindingKey] = set()
        for t in edits.touched():  # the identities of the findings of .check
            n_syncs = self.sync_count(t, edits)
            if n_syncs > 1:
                after.add((FindingKind.RULE1_SEVERAL_SYNCS, t))
            elif not n_syncs and t not in self.threaded:
                after.add((FindingKind.RULE1_NO_SYNC, t))
        if not whole and (key in after or not after <= self.keys):
            return (after - self.keys) | ({key} & after)
        groups, part, root_of = self._groups_after(edits)
        for tasks, n_clocks, _ in part.values():
            if n_clocks != 1:
                kind = FindingKind.RULE3_SEVERAL_CLOCKS if n_clocks else FindingKind.RULE3_NO_CLOCK
                if self._rule3.get(id(tasks)) is kind and key != (kind, tasks):
                    continue  # the group as it was, with its finding: nothing new
                after.add((kind, tuple(tasks)))
        after |= self._rule2_after(edits, groups, part, root_of, key)
        new = after - self.keys
        if key in after:
            new.add(key)
        return new or None

    def _rule2_after(self, edits: Edits, groups: list[int], part: dict, root_of: Any,
                     key: FindingKey | None = None) -> set[FindingKey]:
        """The Rule 2 findings on the edited links and the ASYN/ASYN links of ``groups``,
        once ``edits`` are made (``part``, ``root_of``: the groups re-formed).

        With ``key`` (the finding judged), the ASYN/ASYN links, not edited, of a group
        that stays as it was (the same tasks, the same design period) are left out
        when their other end's group stays too: their finding, or none, is as
        before, so none is new there, and only ``key`` is read again if it is one
        of them (a group with many such links is re-read once per candidate).
        """
        after: set[FindingKey] = set()
        seen: set[int] = set()
        edited = edits.by_id()  # each link's last edit, by a lookup, not a scan per link
        if key is None:
            scanned = [self.asyn[g] for g in groups]
        else:
            kept = self._kept_groups(groups, part, root_of)
            scanned = [self.asyn[g] for g in groups if g not in kept]
            # A link between a group kept and one changed is scanned with the latter
            # (it is listed under both); one to a group not touched, which is kept, is not.
            if key[0] is FindingKind.RULE2_UNSYNCHRONIZED:
                (w, p), (r, q) = key[1]
                link = self._link((w, p), (r, q))
                if self.group_of[w] in kept or self.group_of[r] in kept:
                    scanned.append([link])
        for link in itertools.chain([link for link, _ in edits.protocol], *scanned):
            if id(link) in seen:
                continue
            seen.add(id(link))
            now = edited.get(id(link), link.protocol)
            if now is Protocol.SYN_SYN:
                after.add((FindingKind.RULE2_RENDEZVOUS, link_key(link.writer, link.reader)))
            elif now is Protocol.ASYN_ASYN:
                # Each end's group after the edits: re-formed (a root task) or as it was.
                gw, gr = (root_of[x] if x in root_of else self.group_of[x]
                          for x in (link.writer[0], link.reader[0]))
                pw, pr = (part[g][2] if g in part else self.periods[g] for g in (gw, gr))
                if gw != gr and pw is not None and pw == pr:
                    after.add((FindingKind.RULE2_UNSYNCHRONIZED,
                               link_key(link.writer, link.reader)))
        return after

    def _kept_groups(self, groups: list[int], part: dict, root_of: Any) -> set[int]:
        """Those of ``groups`` that stay as they were once re-formed (``part``,
        ``root_of``): the same tasks, the same design period."""
        kept = set()
        for g in groups:
            members = self.groups[g]
            root = root_of[members[0]]
            tasks, _, period = part[root]
            before = self.periods[g]
            # Identity first: a Fraction compared by value costs a call.
            if (period is not before and period != before) or len(tasks) != len(members):
                continue
            # The same count, and every task of the group in it: the same tasks.
            if tasks is members or all(root_of[t] == root for t in members):
                kept.add(g)
        return kept

    def _regroup(self, groups: list[int], edits: Edits
                 ) -> tuple[dict, dict[str, str] | _Roots]:
        """The groups that the tasks of ``groups`` form once ``edits`` are made.

        Returns ``{root: (tasks in file order, how many clocks, design period)}``
        and the root of each of those tasks (connected components over them only).
        """
        if (all(p.synchronizing == link.protocol.synchronizing for link, p in edits.protocol)
                # Type: a task whose clock is dropped has one.
                and all(self.clock_users[self.sk.tasks[t].clock] == 1  # type: ignore[index]
                        for t in edits.drop)):
            return self._same_groups(groups, edits)
        return self.regrouping.after(groups, edits)

    def _same_groups(self, groups: list[int], edits: Edits) -> tuple[dict, _Roots]:
        """:meth:`_regroup` when no link starts or stops synchronizing and no shared
        clock is dropped: the groups stay, only the clocks of the edited tasks change.

        Costs the edited tasks, not the groups: a group bound by thousands of clocks
        has a finding per task, and each is checked here.
        """
        part: dict[str, tuple[tuple[str, ...], int, Fraction | None]] = {}
        changed = edits.drop | edits.add
        tasks = self.sk.tasks
        for g in groups:
            members = self.groups[g]
            users, by_period = self._clocks_of_group(g)
            losing: dict[str, int] = {}
            added = 0
            for t in changed:
                if self.group_of[t] != g:
                    continue
                added += t in edits.add
                if clock := tasks[t].clock:
                    losing[clock] = losing.get(clock, 0) + 1
            gone = {c for c, n in losing.items() if n == users[c]}
            period = None
            for length, c in by_period:  # the fastest clock left
                if c not in gone:
                    period = length
                    break
            if added:
                period = self.fresh if period is None else min(period, self.fresh)
            part[members[0]] = (members, len(users) - len(gone) + added, period)
        return part, _Roots(self.groups, self.group_of, set(groups))

    def _clocks_of_group(self, g: int) -> tuple[dict[str, int], list[tuple[Fraction, str]]]:
        """The users of each clock of group ``g``, and its clocks by period (cached)."""
        known = self._group_clocks.get(g)
        if known is None:
            users: dict[str, int] = {}
            for t in self.groups[g]:
                clock = self.sk.tasks[t].clock
                if clock:
                    users[clock] = users.get(clock, 0) + 1
            # By rank (ints), not by (period, name): sorting a group of 10,000 clocks of
            # one period compared 40,000 Fractions. Only the fastest period is read.
            rank = self.regrouping.clock_rank
            by_period = [(self.sk.clocks[c].period, c) for c in sorted(users, key=rank.__getitem__)]
            known = self._group_clocks[g] = (users, by_period)
        return known

    def change_of(self, edits: Edits) -> Change:
        """The :class:`Change` of ``edits`` (links in skeleton order, tasks in file order).

        Remembered for the last edits asked about (ranking and wording a candidate ask
        for it up to five times).
        """
        if self._change is not None and self._change[0] is edits:
            return self._change[1]
        change = self._change_of(edits)
        self._change = (edits, change)
        return change

    def _change_of(self, edits: Edits) -> Change:
        final: dict[Link, Protocol] = {}
        for link, protocol in edits.protocol:
            final[link] = protocol
        protocols = tuple((":".join(link.writer), ":".join(link.reader), p.value)
                          for link, p in (sorted(final.items(),
                                                 key=lambda x: self.link_order[id(x[0])])
                                          if len(final) > 1 else final.items())
                          if p is not link.protocol)
        order = self.order.__getitem__
        return Change(protocols,
                      tuple(sorted(edits.drop, key=order)) if len(edits.drop) > 1
                      else tuple(edits.drop),
                      tuple(sorted(edits.add, key=order)) if len(edits.add) > 1
                      else tuple(edits.add))

    def describe(self, change: Change) -> str:
        """The change in words."""
        parts = []
        for w, r, p in change.protocols:
            why = {"ASYN/ASYN": "neither side waits",
                   "ASYN/SYN": f"{r.split(':')[0]} waits for {w.split(':')[0]}'s message",
                   "SYN/ASYN": f"{w.split(':')[0]} waits for {r.split(':')[0]}'s request",
                   "SYN/SYN": "both wait"}[p]
            parts.append(f"make {w} -> {r} {p} ({why})")
        for t in change.drop_clock:
            parts.append(f"remove the clock {self.sk.tasks[t].clock} of {t}")
        for t in change.add_clock:
            if change.period is not None:
                parts.append(f"give {t} a clock of its own, of period "
                             f"{display_text(change.period)} {self.sk.unit}")
                continue
            # The check assumed a period that no group has (Rule 2 compares periods).
            parts.append(f"give {t} a clock of its own (a period of your choice that no "
                         f"other group has, e.g. {display_text(self.fresh)} {self.sk.unit})")
        return "; ".join(parts)


def _changes_nothing(edits: Edits) -> bool:
    """Whether the :class:`Change` of ``edits`` is empty (each link's last edit counts)."""
    if edits.drop or edits.add:
        return False
    final = {id(link): (link, p) for link, p in edits.protocol}
    return all(p is link.protocol for link, p in final.values())


def _group_text(tasks: tuple[str, ...] | list[str]) -> str:
    """A group for the advice's words (a long group by its first tasks and its size)."""
    if len(tasks) <= 4:
        return "{" + ", ".join(tasks) + "}"
    return "{" + ", ".join(tasks[:3]) + f", ... ({len(tasks)} tasks)}}"
