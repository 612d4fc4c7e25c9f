"""What to change for a finding of design rules 1-3, so that following the advice converges.

Each finding of Rules 1 to 3 (:func:`tegraph.design.rules.check_rules`) gets a
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

The candidates move synchronizations along links rather than only cutting
them. A task that must lose an input it reads ASYN/SYN can cut the link
(ASYN/ASYN), or *pull*: the link becomes SYN/ASYN, the writer now waits for the
task's request, and the writer gives up its own other synchronizations the
same way (its clock goes). A task that must lose its clock and has nothing else
*pushes*: it posts an output SYN/ASYN, whose reader, having lost its
synchronization, does the same. Per finding:

- Rule 1, two or more synchronizations: keep one (the first input read, else
  the clock, else the last output posted: the paper's footnote 6; then the
  others); the clock goes; an input read ASYN/SYN is cut or pulled; an output
  posted SYN/ASYN is cut or pushed (ASYN/SYN); a rendezvous keeps its other
  side blocking, or is cut;
- Rule 1, none: read a linked input ASYN/SYN, or get a clock of its own, or
  post a linked output SYN/ASYN;
- Rule 2, a rendezvous: ASYN/SYN or SYN/ASYN;
- Rule 2, ASYN/ASYN between groups of one rate: ASYN/SYN with the reader
  keeping only that synchronization, or SYN/ASYN with the writer keeping only
  that one;
- Rule 3, several clocks: keep one; every other clocked task loses its clock,
  and pushes if that was all it had;
- Rule 3, no clock: a clock to one task (first those that read no
  synchronizing input), which keeps only that synchronization.

A candidate is checked where it can change the rules (:meth:`Advisor.brings`):
Rule 1 for the tasks it touches, Rule 3 for the groups their tasks form
afterwards, Rule 2 for its links and the ASYN/ASYN links of those groups. So a
check costs the size of the groups touched, not of the skeleton.

References
----------
.. [1] D. Simon et al., "Design and analysis of synchronization for
   real-time closed-loop control in robotics", IEEE Transactions on Control
   Systems Technology, 1998.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Iterator
from fractions import Fraction
from typing import Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from maxplus.scalar import display_text

from ..analysis.liveness import token_free_circuits
from ..analysis.reorder import PrecedenceGraph
from ..model.build import build_teg
from ..model.elements import LinkLabel
from ..model.skeleton import Link, Protocol, Skeleton
from .change import Change, Key, apply_change, finding_key
from .synchronization import (
    READER_BLOCKS,
    WRITER_BLOCKS,
    group_period,
    link_index,
    synchronized_groups,
)

__all__ = ["CANDIDATE_LIMIT", "SPLIT", "Advisor", "Choice"]

CANDIDATE_LIMIT = 64
"""Candidates examined per finding (the smallest of them first)."""

SPLIT = "split"
"""What a Rule 3 change keeps when it splits the group rather than drop clocks."""

_SPLIT_LIMIT = 8
"""Links cut one at a time to split a group of several clocks (Rule 3)."""


# ------------------------------------------------------------------ candidates

class _Edits:
    """Candidate edits, keyed by the original links and task names (immutable).

    ``kept`` is what the task of a Rule 1 finding keeps, or the clock a group of
    Rule 3 keeps, for the advice's words. (A plain class: candidates are made by
    the thousand, and ``dataclasses.replace`` would cost more than the check.)
    """

    __slots__ = ("protocol", "drop", "add", "kept")

    def __init__(self, protocol: tuple[tuple[Link, Protocol], ...] = (),
                 drop: frozenset[str] = frozenset(), add: frozenset[str] = frozenset(),
                 kept: str = "") -> None:
        self.protocol, self.drop, self.add, self.kept = protocol, drop, add, kept

    def set(self, link: Link, protocol: Protocol) -> _Edits:
        return _Edits(self.protocol + ((link, protocol),), self.drop, self.add, self.kept)

    def with_clock(self, task: str, present: bool) -> _Edits:
        """``task`` keeps no clock (``present`` False) or gets one of its own."""
        if present:
            return _Edits(self.protocol, self.drop, self.add | {task}, self.kept)
        return _Edits(self.protocol, self.drop | {task}, self.add - {task}, self.kept)

    def saying(self, kept: str) -> _Edits:
        return _Edits(self.protocol, self.drop, self.add, kept)

    def get(self, link: Link) -> Protocol:
        for known, protocol in reversed(self.protocol):
            if known is link:
                return protocol
        return link.protocol


Sync = tuple[str, Link | None]
"""``("clock", None)``, ``("input", link)`` or ``("output", link)``."""


class _Roots:
    """The root task of each task of some groups, as a read-only mapping (built on demand)."""

    __slots__ = ("groups", "group_of", "chosen")

    def __init__(self, groups: list[tuple[str, ...]], group_of: dict[str, int],
                 chosen: set[int]) -> None:
        self.groups, self.group_of, self.chosen = groups, group_of, chosen

    def __contains__(self, task: object) -> bool:
        return self.group_of.get(task) in self.chosen  # type: ignore[arg-type]

    def __getitem__(self, task: str) -> str:
        return self.groups[self.group_of[task]][0]


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
    """

    __slots__ = ("change", "kept", "brought", "live", "periods")

    def __init__(self, change: Change | None, kept: str, brought: set[Key],
                 live: bool | None = None, periods: str = "") -> None:
        self.change, self.kept, self.brought = change, kept, brought
        self.live, self.periods = live, periods


class Advisor:
    """The structure of one skeleton, the candidates for each finding, and their check.

    Parameters
    ----------
    skeleton : Skeleton
    findings : list
        The findings of Rules 1-3 on ``skeleton`` (each with ``rule``,
        ``severity``, ``tasks``, ``ports``, ``links``): a change must bring no
        finding outside them.
    groups : list of tuple of str, optional
        :func:`~.synchronization.synchronized_groups` of ``skeleton``, if known.
    """

    def __init__(self, skeleton: Skeleton, findings: list,
                 groups: list[tuple[str, ...]] | None = None) -> None:
        self.sk = skeleton
        self.groups = synchronized_groups(skeleton) if groups is None else groups
        self.group_of = {t: g for g, ts in enumerate(self.groups) for t in ts}
        self.periods = [group_period(skeleton, g) for g in self.groups]
        self._group_clocks: dict[int, tuple[dict[str, int], list[tuple[Fraction, str]]]] = {}
        self.by_reader, self.by_writer = link_index(skeleton)
        self.order = {t: i for i, t in enumerate(skeleton.tasks)}
        self.link_order = {id(link): i for i, link in enumerate(skeleton.links)}
        self.threaded = {t for thread in skeleton.threads for t in thread}
        self.threads_of: dict[int, list[tuple[str, ...]]] = {}
        for thread in skeleton.threads:
            self.threads_of.setdefault(self.group_of[thread[0]], []).append(thread)
        periods = [c.period for c in skeleton.clocks.values()]
        self.fresh = max(periods, default=Fraction(0)) + 1  # a period no group has
        self.keys = {finding_key(f) for f in findings}
        self._dead: bool | None = None  # token-free circuits in the skeleton (on demand)
        self._live: dict[Change, bool] = {}
        self._inputs: dict[str, list[Link]] = {}
        self._outputs: dict[str, list[Link]] = {}
        self.clock_users: dict[str, int] = {}
        for task in skeleton.tasks.values():
            if task.clock:
                self.clock_users[task.clock] = self.clock_users.get(task.clock, 0) + 1
        # The ASYN/ASYN links each group has: Rule 2 re-reads them when the group changes.
        self.asyn: list[list[Link]] = [[] for _ in self.groups]
        for link in skeleton.links:
            if link.protocol is Protocol.ASYN_ASYN:
                gw, gr = self.group_of[link.writer[0]], self.group_of[link.reader[0]]
                self.asyn[gw].append(link)
                if gr != gw:
                    self.asyn[gr].append(link)

    # ------------------------------------------------------------ synchronizations
    def inputs(self, task: str) -> list[Link]:
        """The links into ``task``, in the order of its inputs."""
        if task not in self._inputs:
            self._inputs[task] = [link for q in self.sk.tasks[task].inputs
                                  for link in self.by_reader.get((task, q), ())]
        return self._inputs[task]

    def outputs(self, task: str) -> list[Link]:
        """The links out of ``task``, in the order of its outputs."""
        if task not in self._outputs:
            self._outputs[task] = [link for p in self.sk.tasks[task].outputs
                                   for link in self.by_writer.get((task, p), ())]
        return self._outputs[task]

    def syncs(self, task: str, edits: _Edits) -> list[Sync]:
        """What ``task`` waits for once ``edits`` are made, in chain order."""
        has_clock = (self.sk.tasks[task].clock is not None and task not in edits.drop
                     or task in edits.add)
        out: list[Sync] = [("clock", None)] if has_clock else []
        out += [("input", link) for link in self.inputs(task) if edits.get(link) in READER_BLOCKS]
        out += [("output", link) for link in self.outputs(task)
                if edits.get(link) in WRITER_BLOCKS]
        return out

    def needs_one(self, task: str, edits: _Edits) -> bool:
        """Rule 1 would warn: no synchronization and no thread."""
        return task not in self.threaded and not self.syncs(task, edits)

    def _free(self, task: str, keep: Sync, seen: frozenset[str], edits: _Edits
              ) -> Iterator[_Edits]:
        """Variants of ``edits`` in which ``task`` keeps ``keep`` and nothing else."""
        variants: Iterator[_Edits] = iter([edits])
        for sync in self.syncs(task, edits):
            if sync != keep:
                variants = self._each(variants, task, sync, seen)
        return variants

    def _each(self, variants: Iterator[_Edits], task: str, sync: Sync, seen: frozenset[str]
              ) -> Iterator[_Edits]:
        for edits in variants:
            yield from self._remove(task, sync, seen, edits)

    def _remove(self, task: str, sync: Sync, seen: frozenset[str], edits: _Edits
                ) -> Iterator[_Edits]:
        """Ways for ``task`` to stop waiting for ``sync``, best first."""
        kind, link = sync
        if kind == "clock":
            yield edits.with_clock(task, False)
            return
        assert link is not None
        now = edits.get(link)
        if now is Protocol.SYN_SYN:  # the other side keeps blocking, or neither does
            yield edits.set(link, Protocol.SYN_ASYN if kind == "input" else Protocol.ASYN_SYN)
            yield edits.set(link, Protocol.ASYN_ASYN)
            return
        yield edits.set(link, Protocol.ASYN_ASYN)
        other = link.writer[0] if kind == "input" else link.reader[0]
        if other in seen:
            return
        # Pull (the writer waits for the task's request) or push (the reader waits).
        turned = edits.set(link, Protocol.SYN_ASYN if kind == "input" else Protocol.ASYN_SYN)
        yield from self._free(other, ("output" if kind == "input" else "input", link),
                              seen | {other}, turned)

    def _gain(self, task: str, seen: frozenset[str], edits: _Edits, inputs: bool = True,
              outputs: bool = True) -> Iterator[_Edits]:
        """Variants of ``edits`` giving ``task`` (which waits for nothing) one synchronization:
        it reads an input ASYN/SYN, or posts an output SYN/ASYN; the other side, if it
        loses its one synchronization so, takes another the same way."""
        for link in self.inputs(task) if inputs else ():
            now = edits.get(link)
            if now is Protocol.ASYN_ASYN:
                yield edits.set(link, Protocol.ASYN_SYN)
            elif now is Protocol.SYN_ASYN:
                yield from self._handed_over(link.writer[0], seen,
                                             edits.set(link, Protocol.ASYN_SYN))
        for link in self.outputs(task) if outputs else ():
            now = edits.get(link)
            if now is Protocol.ASYN_ASYN:
                yield edits.set(link, Protocol.SYN_ASYN)
            elif now is Protocol.ASYN_SYN:
                yield from self._handed_over(link.reader[0], seen,
                                             edits.set(link, Protocol.SYN_ASYN))

    def _handed_over(self, other: str, seen: frozenset[str], edits: _Edits) -> Iterator[_Edits]:
        """``other`` may have lost its one synchronization to the task: it takes another."""
        if not self.needs_one(other, edits):
            yield edits
        elif other not in seen:
            yield from self._gain(other, seen | {other}, edits)

    def candidates(self, finding: Any) -> Iterator[_Edits]:
        """The changes that would remove ``finding``, best first (unchecked)."""
        empty = _Edits()
        if finding.rule == 1 and finding.severity == "error":
            (task,) = finding.tasks
            syncs = self.syncs(task, empty)
            inputs = [s for s in syncs if s[0] == "input"]
            outputs = [s for s in syncs if s[0] == "output"]
            first = ([inputs[0]] if inputs else []) + [s for s in syncs if s[0] == "clock"] \
                + ([outputs[-1]] if outputs else [])
            for keep in first + [s for s in syncs if s not in first]:
                label = _sync_label(keep)
                for edits in self._free(task, keep, frozenset({task}), empty):
                    yield edits.saying(label)
        elif finding.rule == 1:
            (task,) = finding.tasks
            seen = frozenset({task})
            yield from self._gain(task, seen, empty, outputs=False)
            yield empty.with_clock(task, True)
            yield from self._gain(task, seen, empty, inputs=False)
        elif finding.rule == 2:
            link = self._link(finding.links[0])
            w, r = link.writer[0], link.reader[0]
            if link.protocol is Protocol.SYN_SYN:
                # The side that stops blocking may have had nothing else: it takes another.
                for side, other, protocol in ((w, r, Protocol.ASYN_SYN), (r, w, Protocol.SYN_ASYN)):
                    yield from self._handed_over(side, frozenset({other}),
                                                 empty.set(link, protocol))
            else:
                yield from self._free(r, ("input", link), frozenset({w, r}),
                                      empty.set(link, Protocol.ASYN_SYN))
                yield from self._free(w, ("output", link), frozenset({w, r}),
                                      empty.set(link, Protocol.SYN_ASYN))
        elif finding.rule == 3:
            yield from self._rule3(finding.tasks)

    def _rule3(self, tasks: tuple[str, ...]) -> Iterator[_Edits]:
        empty = _Edits()
        clocks: dict[str, list[str]] = {}
        for t in tasks:
            clock = self.sk.tasks[t].clock
            if clock:
                clocks.setdefault(clock, []).append(t)
        if not clocks:
            quiet = [t for t in tasks if not any(k == "input" for k, _ in self.syncs(t, empty))]
            for t in quiet + [t for t in tasks if t not in quiet]:
                yield from self._free(t, ("clock", None), frozenset({t}),
                                      empty.with_clock(t, True))
            return
        yield from self._split(tasks)
        for keep in clocks:
            # One task at a time, breadth first: a group bound by thousands of clocks
            # would nest a generator per task (Python's recursion limit). Only the first
            # CANDIDATE_LIMIT variants (in the order of the choices) are ever examined, and the
            # first CANDIDATE_LIMIT complete ones extend the first CANDIDATE_LIMIT partial ones.
            others = [t for clock, users in clocks.items() if clock != keep for t in users]
            # A task's links do not change when other tasks lose their clocks: when none
            # is left without a synchronization, the one candidate is every drop at once
            # (what the loop below gives, without a copy of the drops per task).
            at_once = _Edits(drop=frozenset(others), kept=keep)
            needy = [t for t in others if self.needs_one(t, at_once)]
            if not needy:
                yield at_once
                continue
            # The others are dropped at once; those left without a synchronization
            # gain one, one task at a time, breadth first.
            variants = [_Edits(drop=frozenset(others).difference(needy), kept=keep)]
            for t in needy:
                variants = list(itertools.islice(self._unclock(variants, t), CANDIDATE_LIMIT))
            yield from variants

    def _split(self, tasks: tuple[str, ...]) -> Iterator[_Edits]:
        """Rule 3, several clocks: cut links between tasks on different clocks.

        Each clocked task keeps its clock, and so its sampling period (a 2 ms loop
        that reads 5 ms gains ASYN/SYN reads them ASYN/ASYN); each cut alone, then
        all of them at once. Only links whose both ends keep a clock are cut, so no
        task is left without a synchronization.
        """
        empty = _Edits()
        cuts = []
        for t in tasks:
            clock = self.sk.tasks[t].clock
            for link in self.outputs(t):
                other = self.sk.tasks[link.reader[0]].clock
                if link.protocol.synchronizing and clock and other and other != clock:
                    cuts.append(link)
        empty = empty.saying(SPLIT)
        for link in cuts[:_SPLIT_LIMIT]:
            yield empty.set(link, Protocol.ASYN_ASYN)
        if 1 < len(cuts) <= _SPLIT_LIMIT:
            every = empty
            for link in cuts:
                every = every.set(link, Protocol.ASYN_ASYN)
            yield every

    def _unclock(self, variants: list[_Edits], task: str) -> Iterator[_Edits]:
        for edits in variants:
            dropped = edits.with_clock(task, False)
            if self.needs_one(task, dropped):
                yield from self._gain(task, frozenset({task}), dropped)
            else:
                yield dropped

    def _link(self, label: LinkLabel) -> Link:
        # The label knows its ports: names may hold " -> ", so its text is never parsed.
        return next(link for link in self.by_writer[label.writer]
                    if link.reader == label.reader)

    # ------------------------------------------------------------ the check
    def choose(self, finding: Any) -> Choice:
        """The best candidate that brings no new finding, with the words of its advice.

        Among the candidates that bring no new finding, the first (smallest, then
        in the order of preference) that is best by, in turn: making the skeleton
        live when it is dead (token-free circuits of the edited skeleton), and
        changing the sampling period of the fewest clocked tasks (a task that loses
        its clock takes its new group's design period). The scan stops at the
        first candidate that is live and changes no sampling period.

        Returns
        -------
        Choice
        """
        key = finding_key(finding)
        first: _Edits | None = None
        best: tuple[tuple[int, int], _Edits] | None = None
        # The smallest edits first; among equals, the order of preference.
        ranked = sorted(itertools.islice(self.candidates(finding), CANDIDATE_LIMIT), key=_size)
        for edits in ranked:
            if self.brings(key, edits, whole=False) is not None:
                first = first or edits
                continue
            rank = (0 if self.makes_live(edits) is not False else 1, len(self.resampled(edits)))
            if best is None or rank < best[0]:
                best = (rank, edits)
            if rank == (0, 0):
                break
        if best is not None:
            edits = best[1]
            return Choice(self.change_of(edits), edits.kept, set(), self.makes_live(edits),
                          self.periods_text(edits))
        if first is None:
            return Choice(None, "", set())
        brought = self.brings(key, first) or set()
        return Choice(None, self.describe(self.change_of(first)), brought,
                      periods=self.periods_text(first))

    # ------------------------------------------------------------ rates and liveness
    def _groups_after(self, edits: _Edits) -> tuple[list[int], dict, Any]:
        """The groups the edited tasks are in, and those their tasks form after ``edits``."""
        touched = {t for link, _ in edits.protocol for t in (link.writer[0], link.reader[0])}
        touched |= edits.drop | edits.add
        groups = sorted({self.group_of[t] for t in touched})
        part, root_of = self._regroup(groups, edits)
        return groups, part, root_of

    def resampled(self, edits: _Edits) -> list[tuple[str, Fraction, Fraction | None]]:
        """The clocked tasks whose sampling period ``edits`` change: (task, before, after).

        A task keeps its clock's period as long as it keeps its clock; a task that
        loses it runs at the design period of the group it is in afterwards (its
        fastest clock; None: no clock is left to pace it).
        """
        if not edits.drop:
            return []
        _, part, root_of = self._groups_after(edits)
        out = []
        for t in sorted(edits.drop, key=self.order.__getitem__):
            own = self.sk.clocks[self.sk.tasks[t].clock].period  # type: ignore[index]
            after = part[root_of[t]][2]
            if after != own:
                out.append((t, own, after))
        return out

    def makes_live(self, edits: _Edits) -> bool | None:
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
                                  self.fresh if change.add_clock else None)
            self._live[change] = not _token_free(edited)
        return self._live[change]

    def _within(self, groups: list[int] | set[int]) -> Skeleton:
        """The skeleton cut down to the tasks of ``groups`` (their links, clocks, threads)."""
        part = {t for g in groups for t in self.groups[g]}
        return dataclasses.replace(
            self.sk, tasks={t: k for t, k in self.sk.tasks.items() if t in part},
            links=[x for x in self.sk.links if x.writer[0] in part and x.reader[0] in part],
            threads=[th for th in self.sk.threads if th[0] in part], chains=[])

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

    def periods_text(self, edits: _Edits) -> str:
        """What ``edits`` do to the period of each group they touch, before -> after."""
        u = self.sk.unit
        groups, part, _ = self._groups_after(edits)
        before = [(self.groups[g], self.periods[g]) for g in groups]
        after = [(tuple(members), period) for members, _, period in part.values()]
        text = "design periods (each group's fastest clock), before -> after: "
        if set(before) == set(after):
            text += ", ".join(f"{_group_text(g)} {self._period(p, u)}" for g, p in before)
            text += ", unchanged"
        else:
            text += (", ".join(f"{_group_text(g)} {self._period(p, u)}" for g, p in before)
                     + " -> " + ", ".join(f"{_group_text(g)} {self._period(p, u)}"
                                          for g, p in after))
        moved = self.resampled(edits)
        if moved:
            text += "; " + "; ".join(
                f"{t} is sampled every {self._period(a, u)} instead of {display_text(b)} {u} "
                "(its clock goes)" for t, b, a in moved)
        elif any(self.sk.tasks[t].clock for g, _ in before for t in g):
            text += "; every clocked task keeps its clock's period"
        return text

    def _period(self, period: Fraction | None, unit: str) -> str:
        if period is None:
            return "no clock"
        if period == self.fresh:
            return "a period of your choice"
        return f"{display_text(period)} {unit}"

    def brings(self, key: Key, edits: _Edits, whole: bool = True) -> set[Key] | None:
        """None when ``edits`` remove the finding ``key`` and bring none; else what is new.

        With ``whole`` False, what is new may be told only in part (Rule 1 first:
        most candidates that fail, fail there, and the groups need not be re-formed).

        The rules are re-read only where the edits can change them: Rule 1 for
        the tasks whose links or clock they touch; the groups of those tasks are
        re-formed (synchronizing links, threads and shared clocks among their
        tasks, after the edits) for Rule 3; Rule 2 for the edited links and the
        ASYN/ASYN links of those groups. Everything else is as it was.
        (``tests/tegraph/design/test_advice.py`` compares this with a full re-check.)
        """
        touched = {t for link, _ in edits.protocol for t in (link.writer[0], link.reader[0])}
        touched |= edits.drop | edits.add
        after: set[Key] = set()
        for t in touched:  # the keys of finding_key
            syncs = self.syncs(t, edits)
            if len(syncs) > 1:
                after.add((1, "error", (t,)))
            elif not syncs and t not in self.threaded:
                after.add((1, "warning", (t,)))
        if not whole and (key in after or not after <= self.keys):
            return (after - self.keys) | ({key} & after)
        groups = sorted({self.group_of[t] for t in touched})
        part, root_of = self._regroup(groups, edits)
        for tasks, n_clocks, _ in part.values():
            if n_clocks != 1:
                after.add((3, "error", tuple(tasks), not n_clocks))
        seen: set[int] = set()
        for link in [link for link, _ in edits.protocol] + [
                link for g in groups for link in self.asyn[g]]:
            if id(link) in seen:
                continue
            seen.add(id(link))
            (w, p), (r, q) = link.writer, link.reader
            now = edits.get(link)
            found = now is Protocol.SYN_SYN
            if now is Protocol.ASYN_ASYN:
                # Each end's group after the edits: re-formed (a root task) or as it was.
                gw, gr = (root_of[x] if x in root_of else self.group_of[x] for x in (w, r))
                pw, pr = (part[g][2] if g in part else self.periods[g] for g in (gw, gr))
                found = gw != gr and pw is not None and pw == pr
            if found:
                after.add((2, "warning", (w, r), (f"{w}:{p}", f"{r}:{q}"), (_label(link, now),)))
        new = after - self.keys
        if key in after:
            new.add(key)
        return new or None

    def _regroup(self, groups: list[int], edits: _Edits) -> tuple[dict, dict[str, str]]:
        """The groups that the tasks of ``groups`` form once ``edits`` are made.

        Returns ``{root: (tasks in file order, how many clocks, design period)}``
        and the root of each of those tasks (union-find over them only).
        """
        if (all(p.synchronizing == link.protocol.synchronizing for link, p in edits.protocol)
                and all(self.clock_users[self.sk.tasks[t].clock] == 1  # type: ignore[index]
                        for t in edits.drop)):
            return self._same_groups(groups, edits)
        tasks = [t for g in groups for t in self.groups[g]]
        parent = {t: t for t in tasks}

        def find(t: str) -> str:
            while parent[t] != t:
                parent[t] = parent[parent[t]]
                t = parent[t]
            return t

        first_of: dict[str, str] = {}
        clock_of: dict[str, str | None] = {}
        for t in tasks:
            clock = None if t in edits.drop else self.sk.tasks[t].clock
            if t in edits.add:
                clock = f"{t}\0new"  # a clock of its own: it joins nothing
            clock_of[t] = clock
            if clock:
                parent[find(t)] = find(first_of.setdefault(clock, t))
            for link in self.inputs(t):
                if edits.get(link).synchronizing:
                    parent[find(t)] = find(link.writer[0])
        for g in groups:
            for thread in self.threads_of.get(g, ()):
                for a, b in itertools.pairwise(thread):
                    parent[find(a)] = find(b)
        part: dict[str, tuple[list[str], set[str], Fraction | None]] = {}
        root_of = {t: find(t) for t in tasks}
        for t in sorted(tasks, key=self.order.__getitem__):
            entry = part.setdefault(root_of[t], ([], set(), None))
            entry[0].append(t)
            if clock_of[t]:
                entry[1].add(clock_of[t])  # type: ignore[arg-type]
        counted: dict[str, tuple[list[str], int, Fraction | None]] = {}
        for root, (members, clocks, _) in part.items():
            period = min((self.fresh if c.endswith("\0new") else self.sk.clocks[c].period
                          for c in clocks), default=None)
            counted[root] = (members, len(clocks), period)
        return counted, root_of

    def _same_groups(self, groups: list[int], edits: _Edits) -> tuple[dict, _Roots]:
        """:meth:`_regroup` when no link starts or stops synchronizing and no shared
        clock is dropped: the groups stay, only the clocks of the edited tasks change.

        Costs the edited tasks, not the groups: a group bound by thousands of clocks
        has a finding per task, and each is checked here.
        """
        part: dict[str, tuple[tuple[str, ...], int, Fraction | None]] = {}
        for g in groups:
            members = self.groups[g]
            users, by_period = self._clocks_of_group(g)
            edited = [t for t in edits.drop | edits.add if self.group_of[t] == g]
            losing: dict[str, int] = {}
            for t in edited:
                if clock := self.sk.tasks[t].clock:
                    losing[clock] = losing.get(clock, 0) + 1
            gone = {c for c, n in losing.items() if n == users[c]}
            added = sum(t in edits.add for t in edited)
            period = next((length for length, c in by_period if c not in gone), None)
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
            by_period = sorted((self.sk.clocks[c].period, c) for c in users)
            known = self._group_clocks[g] = (users, by_period)
        return known

    def change_of(self, edits: _Edits) -> Change:
        """The :class:`Change` of ``edits`` (links in skeleton order, tasks in file order)."""
        final: dict[Link, Protocol] = {}
        for link, protocol in edits.protocol:
            final[link] = protocol
        protocols = tuple((":".join(link.writer), ":".join(link.reader), p.value)
                          for link, p in sorted(final.items(),
                                                key=lambda x: self.link_order[id(x[0])])
                          if p is not link.protocol)
        return Change(protocols, tuple(sorted(edits.drop, key=self.order.__getitem__)),
                      tuple(sorted(edits.add, key=self.order.__getitem__)))

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
            # The check assumed a period that no group has (Rule 2 compares periods).
            parts.append(f"give {t} a clock of its own (a period of your choice that no "
                         f"other group has, e.g. {display_text(self.fresh)} {self.sk.unit})")
        return "; ".join(parts)


def _label(link: Link, protocol: Protocol) -> str:
    """The label of ``link`` once it has ``protocol`` (as :attr:`Link.label`)."""
    (w, p), (r, q) = link.writer, link.reader
    return f"{w}:{p} -> {r}:{q} ({protocol.value})"


def _size(edits: _Edits) -> int:
    return len({id(link) for link, _ in edits.protocol}) + len(edits.drop) + len(edits.add)


def _sync_label(sync: Sync) -> str:
    kind, link = sync
    if kind == "clock" or link is None:
        return "clock"
    port = link.reader if kind == "input" else link.writer
    return f"{kind} {port[0]}:{port[1]}"


def _group_text(tasks: tuple[str, ...] | list[str]) -> str:
    """A group for the advice's words (a long group by its first tasks and its size)."""
    if len(tasks) <= 4:
        return "{" + ", ".join(tasks) + "}"
    return "{" + ", ".join(tasks[:3]) + f", ... ({len(tasks)} tasks)}}"


def _token_free(sk: Skeleton) -> list:
    teg = build_teg(sk)
    a = teg.arrays()
    return token_free_circuits(a.src, a.dst, a.tokens, teg.n_transitions)
