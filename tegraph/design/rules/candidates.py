"""The candidate edits for a finding of design rules 1-3, best first (unchecked).

The candidates move synchronizations along links rather than only cutting
them. A task that must lose an input it reads ASYN/SYN can cut the link
(ASYN/ASYN), or *pull*: the link becomes SYN/ASYN, the writer now waits for the
task's request, and the writer gives up its own other synchronizations the
same way (its clock goes). A task that must lose its clock and has nothing else
*pushes*: it posts an output SYN/ASYN, whose reader, having lost its
synchronization, does the same. Per kind of finding (:class:`~.findings.FindingKind`):

- Rule 1, two or more synchronizations: keep one (the first input read, else
  the clock, else the last output posted: the paper's footnote 6 [1]_; then the
  others); the clock goes; an input read ASYN/SYN is cut or pulled; an output
  posted SYN/ASYN is cut or pushed (ASYN/SYN); a rendezvous keeps its other
  side blocking, or is cut;
- Rule 1, none: read a linked input ASYN/SYN, or get a clock of its own, or
  post a linked output SYN/ASYN;
- Rule 2, a rendezvous: ASYN/SYN or SYN/ASYN;
- Rule 2, ASYN/ASYN between groups of one rate: ASYN/SYN with the reader
  keeping only that synchronization, or SYN/ASYN with the writer keeping only
  that one;
- Rule 3, several clocks: split the group (cut links between tasks on
  different clocks), or keep one clock; every other clocked task loses its
  clock, and pushes if that was all it had;
- Rule 3, no clock: a clock to one task (first those that read no
  synchronizing input), which keeps only that synchronization.

Which of them to advise is :mod:`.advice`'s choice.

References
----------
.. [1] D. Simon et al., "Design and analysis of synchronization for
   real-time closed-loop control in robotics", IEEE Transactions on Control
   Systems Technology, 1998.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterator

from ...model.skeleton import Link, Protocol, Skeleton, Task
from ...model.structure import Structure
from .findings import FindingKind, RuleFinding
from .freeing import Edits, Freeing, Run, Sync, clocked_after, waits_for
from .synchronization import READER_BLOCKS, WRITER_BLOCKS

__all__ = ["CANDIDATE_LIMIT", "SPLIT", "Candidates", "Edits", "Sync", "sync_label"]

CANDIDATE_LIMIT = 64
"""Candidates examined per finding (the smallest of them first)."""

SPLIT = "split"
"""What a Rule 3 change keeps when it splits the group rather than drop clocks."""

_SPLIT_LIMIT = 8
"""Links cut one at a time to split a group of several clocks (Rule 3)."""


# ------------------------------------------------------------------ candidates

class Candidates:
    """The candidate edits for each finding of Rules 1-3 on one skeleton.

    Parameters
    ----------
    skeleton : Skeleton
    structure : Structure, optional
        ``Structure.of(skeleton)``, if known (its groups, links by port).
    """

    def __init__(self, skeleton: Skeleton, structure: Structure | None = None) -> None:
        self.sk = skeleton
        self.structure = Structure.of(skeleton) if structure is None else structure
        self.groups = self.structure.groups
        self.group_of = self.structure.group_of
        self.by_reader, self.by_writer = self.structure.by_reader, self.structure.by_writer
        self.threaded = {t for thread in skeleton.threads for t in thread}
        self._inputs: dict[str, list[Link]] = {}
        self._outputs: dict[str, list[Link]] = {}
        # Each task's blocking links as they are, whether it has a clock, and the task.
        self._blocking: dict[str, tuple[int, bool, Task]] = {}
        # One search for every :meth:`ranked`'s first, not one made per finding: a
        # walk may stop half-way (a run that cannot beat the best is skipped), and
        # the next finding's walk starts by resetting the search's state.
        self._first_search = self._freeing()

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

    def syncs(self, task: str, edits: Edits) -> list[Sync]:
        """What ``task`` waits for once ``edits`` are made, in chain order."""
        has_clock = clocked_after(task, self.sk.tasks[task].clock is not None, edits.drop,
                                  edits.add)
        return waits_for(has_clock, self.inputs(task), self.outputs(task), edits.by_id())

    def sync_count(self, task: str, edits: Edits) -> int:
        """How many synchronizations ``task`` has once ``edits`` are made (as many as
        :meth:`syncs` lists).

        Its links' count as they are is kept per task; only the edited links that
        touch it are read again (a candidate edits a few links, and this is asked
        for each task it touches, of each candidate of each finding).
        """
        known = self._blocking.get(task)
        if known is None:
            spec = self.sk.tasks[task]
            known = self._blocking[task] = (
                len(waits_for(False, self.inputs(task), self.outputs(task), {})),
                spec.clock is not None, spec)
        n_links, own_clock, spec = known
        n = n_links + clocked_after(task, own_clock, edits.drop, edits.add)
        if edits.protocol:
            for link, now in edits.last():
                was = link.protocol
                if now is was:
                    continue
                # A link is listed among the task's inputs once per port it reads by
                # that name (once: ports are distinct), and among its outputs alike.
                if link.reader[0] == task:
                    n += spec.inputs.count(link.reader[1]) * (
                        (now in READER_BLOCKS) - (was in READER_BLOCKS))
                if link.writer[0] == task:
                    n += spec.outputs.count(link.writer[1]) * (
                        (now in WRITER_BLOCKS) - (was in WRITER_BLOCKS))
        return n

    def needs_one(self, task: str, edits: Edits) -> bool:
        """Rule 1 would warn: no synchronization and no thread."""
        return task not in self.threaded and not self.sync_count(task, edits)

    def _gain(self, task: str, seen: frozenset[str], edits: Edits, inputs: bool = True,
              outputs: bool = True) -> Iterator[Edits]:
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

    def _handed_over(self, other: str, seen: frozenset[str], edits: Edits) -> Iterator[Edits]:
        """``other`` may have lost its one synchronization to the task: it takes another."""
        if not self.needs_one(other, edits):
            yield edits
        elif other not in seen:
            yield from self._gain(other, seen | {other}, edits)

    def candidates(self, finding: RuleFinding) -> Iterator[Edits]:
        """The changes that would remove ``finding`` (of Rules 1-3), best first (unchecked)."""
        runs = self._runs(finding)
        if runs is not None:
            yield from self._freeing().candidates(runs)
        else:
            yield from self._by_kind[finding.kind](self, finding.key)

    def ranked(self, finding: RuleFinding) -> Iterator[Edits]:
        """The first :data:`CANDIDATE_LIMIT` :meth:`candidates`, smallest first (by
        :meth:`Edits.size`; among equals, in the order of preference).

        Made one at a time: the advice mostly takes the first. Where the candidates
        are searched (:class:`~.freeing.Freeing`), the first is found without
        making the others; elsewhere a first candidate of size 1 is the smallest
        (every candidate edits something), and the earliest such. The others are
        made if it is not taken.
        """
        made = self.candidates(finding)
        first = (self._first_kept(finding.key)
                 if finding.kind is FindingKind.RULE1_SEVERAL_SYNCS else None)
        runs = None if first is not None else self._runs(finding)
        if first is not None:
            known: list[Edits] = []
        elif runs is not None:
            first = self._first_search.first(runs, CANDIDATE_LIMIT)
            known = []
        else:
            known = list(itertools.islice(made, 1))
            first = known[0] if known and known[0].size() <= 1 else None
        if first is not None:
            yield first
        ranked = sorted(known + list(itertools.islice(made, CANDIDATE_LIMIT - len(known))),
                        key=Edits.size)
        # The sort is stable, so its first is the one already given.
        yield from ranked[1:] if first is not None else ranked

    def _freeing(self) -> Freeing:
        return Freeing(self.inputs, self.outputs, lambda task: self.sk.tasks[task].clock)

    def _runs(self, finding: RuleFinding) -> list[Run] | None:
        """The searches of :class:`~.freeing.Freeing` whose candidates are
        ``finding``'s, one after the other (None: its candidates are not searched)."""
        runs = self._runs_by_kind.get(finding.kind)
        return None if runs is None else runs(self, finding.key)

    def _several_syncs(self, task: str) -> list[Run]:
        """Rule 1, several synchronizations: keep one, each in turn, footnote 6's first."""
        empty = Edits()
        syncs = waits_for(self.sk.tasks[task].clock is not None, self.inputs(task),
                          self.outputs(task), {})
        first = _preferred(syncs)
        seen = frozenset({task})
        return [(empty, task, keep, seen, sync_label(keep))
                for keep in first + [s for s in syncs if s not in first]]

    def _first_kept(self, task: str) -> Edits | None:
        """The first candidate of :meth:`_several_syncs`' runs, as :meth:`.Freeing.first`
        finds it, told at once; None where it cannot be (then the search is made).

        When the task's synchronizations are distinct (no link twice, no two equal
        links), every candidate of the first run edits each link it gives up, and
        drops its clock if it gives that up: the first way of each (cut the link, or
        a rendezvous's other side keeps blocking; no neighbour pulled in) is the
        smallest, and no other run can be smaller (each gives up as many). This is
        the walk's first candidate, made without the walk (a task with a clock and an
        input, 10,000 of them on a chain with a clock per task, is the common case).
        """
        syncs = waits_for(self.sk.tasks[task].clock is not None, self.inputs(task),
                          self.outputs(task), {})
        links = [id(link) for _, link in syncs if link is not None]
        if len(set(links)) != len(links) or any(
                a == b for i, a in enumerate(syncs) for b in syncs[i + 1:]):
            return None
        keep = _preferred(syncs)[0]
        sets: list[tuple[Link, Protocol]] = []
        drop: frozenset[str] = frozenset()
        for sync in syncs:
            if sync == keep:
                continue
            kind, link = sync
            if link is None:
                drop = frozenset((task,))
            elif link.protocol is Protocol.SYN_SYN:
                sets.append((link, Protocol.SYN_ASYN if kind == "input" else Protocol.ASYN_SYN))
            else:
                sets.append((link, Protocol.ASYN_ASYN))
        edits = Edits(tuple(sets), drop, frozenset(), sync_label(keep))
        edits._size = len(sets) + len(drop)
        return edits

    def _no_sync(self, task: str) -> Iterator[Edits]:
        """Rule 1, no synchronization: read an input, get a clock, or post an output."""
        empty, seen = Edits(), frozenset({task})
        yield from self._gain(task, seen, empty, outputs=False)
        yield empty.with_clock(task, True)
        yield from self._gain(task, seen, empty, inputs=False)

    def _rendezvous(self, key: tuple[tuple[str, str], tuple[str, str]]) -> Iterator[Edits]:
        """Rule 2, SYN/SYN: one side stops blocking; if that was all it had, it takes another."""
        link = self._link(*key)
        w, r = link.writer[0], link.reader[0]
        for side, other, protocol in ((w, r, Protocol.ASYN_SYN), (r, w, Protocol.SYN_ASYN)):
            yield from self._handed_over(side, frozenset({other}), Edits().set(link, protocol))

    def _unsynchronized(self, key: tuple[tuple[str, str], tuple[str, str]]) -> list[Run]:
        """Rule 2, ASYN/ASYN at one rate: the reader, or the writer, waits on it and only on it."""
        link = self._link(*key)
        w, r = link.writer[0], link.reader[0]
        return [(Edits().set(link, Protocol.ASYN_SYN), r, ("input", link), frozenset({w, r}), ""),
                (Edits().set(link, Protocol.SYN_ASYN), w, ("output", link), frozenset({w, r}), "")]

    def _no_clock(self, tasks: tuple[str, ...]) -> list[Run]:
        """Rule 3, no clock: a clock to one task, which keeps only that synchronization."""
        empty = Edits()
        quiet = [t for t in tasks if not any(k == "input" for k, _ in self.syncs(t, empty))]
        return [(empty.with_clock(t, True), t, ("clock", None), frozenset({t}), "")
                for t in quiet + [t for t in tasks if t not in quiet]]

    def _several_clocks(self, tasks: tuple[str, ...]) -> Iterator[Edits]:
        """Rule 3, several clocks: split the group, or keep one clock."""
        clocks: dict[str, list[str]] = {}
        for t in tasks:
            clock = self.sk.tasks[t].clock
            if clock:
                clocks.setdefault(clock, []).append(t)
        yield from self._split(tasks)
        clocked = frozenset(t for users in clocks.values() for t in users)
        # A task's links do not change when other tasks lose their clocks: whether it
        # is left without a synchronization when its clock goes is told once, not once
        # per clock kept (a group bound by n clocks would cost n^2).
        bare = [t for users in clocks.values() for t in users
                if t not in self.threaded  # needs_one without its clock, no Edits made
                and not waits_for(False, self.inputs(t), self.outputs(t), {})]
        for keep in clocks:
            # One task at a time, breadth first: a group bound by thousands of clocks
            # would nest a generator per task (Python's recursion limit). Only the first
            # CANDIDATE_LIMIT variants (in the order of the choices) are ever examined, and the
            # first CANDIDATE_LIMIT complete ones extend the first CANDIDATE_LIMIT partial ones.
            others = clocked.difference(clocks[keep])
            # When no task is left without a synchronization, the one candidate is every
            # drop at once (what the loop below gives, without a copy of the drops per task).
            needy = [t for t in bare if self.sk.tasks[t].clock != keep]
            if not needy:
                yield Edits(drop=others, kept=keep)
                continue
            # The others are dropped at once; those left without a synchronization
            # gain one, one task at a time, breadth first.
            variants = [Edits(drop=others.difference(needy), kept=keep)]
            for t in needy:
                variants = list(itertools.islice(self._unclock(variants, t), CANDIDATE_LIMIT))
            yield from variants

    def _split(self, tasks: tuple[str, ...]) -> Iterator[Edits]:
        """Rule 3, several clocks: cut links between tasks on different clocks.

        Each clocked task keeps its clock, and so its sampling period (a 2 ms loop
        that reads 5 ms gains ASYN/SYN reads them ASYN/ASYN); each cut alone, then
        all of them at once. Only links whose both ends keep a clock are cut, so no
        task is left without a synchronization.
        """
        empty = Edits()
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

    def _unclock(self, variants: list[Edits], task: str) -> Iterator[Edits]:
        for edits in variants:
            dropped = edits.with_clock(task, False)
            if self.needs_one(task, dropped):
                yield from self._gain(task, frozenset({task}), dropped)
            else:
                yield dropped

    def _link(self, writer: tuple[str, str], reader: tuple[str, str]) -> Link:
        # A Rule 2 finding's key is its link's two ports: no text is parsed.
        return next(link for link in self.by_writer[writer] if link.reader == reader)

    # Each function takes the key of its own kind of finding (a task, a link's ports...).
    _by_kind: dict[FindingKind, Callable[..., Iterator[Edits]]] = {
        FindingKind.RULE1_NO_SYNC: _no_sync,
        FindingKind.RULE2_RENDEZVOUS: _rendezvous,
        FindingKind.RULE3_SEVERAL_CLOCKS: _several_clocks,
    }
    """The candidates of each kind of finding of Rules 1-3 that is not searched, from its key."""

    _runs_by_kind: dict[FindingKind, Callable[..., list[Run]]] = {
        FindingKind.RULE1_SEVERAL_SYNCS: _several_syncs,
        FindingKind.RULE2_UNSYNCHRONIZED: _unsynchronized,
        FindingKind.RULE3_NO_CLOCK: _no_clock,
    }
    """The searches of each other kind of finding, from its key."""


def _preferred(syncs: list[Sync]) -> list[Sync]:
    """The synchronizations a task best keeps, best first (footnote 6): its first
    input read, its clock, its last output posted."""
    inputs = [s for s in syncs if s[0] == "input"]
    outputs = [s for s in syncs if s[0] == "output"]
    return (([inputs[0]] if inputs else []) + [s for s in syncs if s[0] == "clock"]
            + ([outputs[-1]] if outputs else []))


def sync_label(sync: Sync) -> str:
    """How a message names a synchronization: ``clock``, or its kind and port."""
    kind, link = sync
    if kind == "clock" or link is None:
        return "clock"
    port = link.reader if kind == "input" else link.writer
    return f"{kind} {port[0]}:{port[1]}"


