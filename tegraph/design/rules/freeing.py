"""Candidate edits, and the search for the ways a task can keep one synchronization only.

A task that must keep only one synchronization (Rule 1's footnote 6, and the
Rule 2 and Rule 3 candidates that leave a task one) gives up each other one
in turn (:mod:`.candidates` describes the ways: cut, pull, push), and each way
that moves a synchronization to a neighbour asks the neighbour to give up its
own others the same way. The ways multiply, so :mod:`.advice` examines only
the first :data:`~.candidates.CANDIDATE_LIMIT` of them, smallest first.

:class:`Freeing` walks these ways depth first, in the order of preference,
with one mutable set of edits that it undoes on the way back: a candidate at
depth d costs its own step, not d nested generators and a copy of d edits.
Its :meth:`~Freeing.first` finds the candidate the advice examines first (the
smallest, then the earliest) without making the others, because an edit is
never taken back on the way down (a candidate is at least as large as any
partial edits it extends), so a branch no smaller than the best so far is
skipped; where a skipped branch would hide where a later candidate stands in
the order, it says so and the caller makes the whole list.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Iterator, Mapping, Sequence

from ...model.skeleton import Link, Protocol
from .synchronization import READER_BLOCKS, WRITER_BLOCKS

__all__ = ["Edits", "Freeing", "Run", "Sync", "clocked_after", "waits_for"]


class Edits:
    """Candidate edits, keyed by the original links and task names (immutable).

    ``kept`` is what the task of a Rule 1 finding keeps, or the clock a group of
    Rule 3 keeps, for the advice's words. (A plain class: candidates are made by
    the thousand, and ``dataclasses.replace`` would cost more than the check.)

    Examples
    --------
    >>> from tegraph.model.skeleton import Link, Protocol
    >>> link = Link(("A", "x"), ("B", "y"), Protocol.ASYN_SYN)
    >>> edits = Edits().set(link, Protocol.SYN_ASYN).set(link, Protocol.ASYN_ASYN)
    >>> edits.get(link), edits.with_clock("A", False).size()
    (<Protocol.ASYN_ASYN: 'ASYN/ASYN'>, 2)
    """

    __slots__ = ("protocol", "drop", "add", "kept", "_by_id", "_last", "_size", "_touched")

    def __init__(self, protocol: tuple[tuple[Link, Protocol], ...] = (),
                 drop: frozenset[str] = frozenset(), add: frozenset[str] = frozenset(),
                 kept: str = "") -> None:
        self.protocol, self.drop, self.add, self.kept = protocol, drop, add, kept
        self._by_id: dict[int, Protocol] | None = None
        self._last: list[tuple[Link, Protocol]] | None = None
        self._touched: frozenset[str] | None = None
        self._size: int | None = None  # known when made by the search (it counts as it goes)

    def set(self, link: Link, protocol: Protocol) -> Edits:
        """These edits and ``link`` given ``protocol``."""
        return Edits(self.protocol + ((link, protocol),), self.drop, self.add, self.kept)

    def with_clock(self, task: str, present: bool) -> Edits:
        """``task`` keeps no clock (``present`` False) or gets one of its own."""
        if present:
            return Edits(self.protocol, self.drop, self.add | {task}, self.kept)
        return Edits(self.protocol, self.drop | {task}, self.add - {task}, self.kept)

    def saying(self, kept: str) -> Edits:
        """The same edits, keeping the synchronization ``kept``."""
        return Edits(self.protocol, self.drop, self.add, kept)

    def get(self, link: Link) -> Protocol:
        """The protocol ``link`` has under these edits."""
        for known, protocol in reversed(self.protocol):
            if known is link:
                return protocol
        return link.protocol

    def by_id(self) -> dict[int, Protocol]:
        """The last protocol given to each edited link, by the link's ``id`` (made once)."""
        if not self.protocol:
            return {}  # most candidates of a group's clocks edit no link: no map to make
        if self._by_id is None:
            self._by_id = {id(link): protocol for link, protocol in self.protocol}
        return self._by_id

    def last(self) -> list[tuple[Link, Protocol]]:
        """Each edited link once, with the last protocol given to it (made once)."""
        if self._last is None:
            if len(self.protocol) == 1:
                self._last = list(self.protocol)
            else:
                final = {id(link): (link, p) for link, p in self.protocol}
                self._last = list(final.values())
        return self._last

    def touched(self) -> frozenset[str]:
        """The tasks whose links or clock the edits touch (made once)."""
        if self._touched is None:
            self._touched = frozenset(t for link, _ in self.protocol
                                      for t in (link.writer[0], link.reader[0])
                                      ) | self.drop | self.add
        return self._touched

    def size(self) -> int:
        """How much the edits change: links edited, clocks removed and clocks added.

        The advice prefers the smallest (:class:`Freeing` counts the same as it goes).
        """
        if self._size is None:
            self._size = len({id(link) for link, _ in self.protocol}) + len(self.drop) \
                + len(self.add)
        return self._size


Sync = tuple[str, Link | None]
"""``("clock", None)``, ``("input", link)`` or ``("output", link)``."""

Run = tuple[Edits, str, Sync, frozenset[str], str]
"""One search of :class:`Freeing`: from these edits, this task keeps this
synchronization and nothing else; the tasks already seen (never pulled into
again); what the candidates say they keep (:attr:`Edits.kept`)."""



def clocked_after(task: str, own_clock: bool, drop: Collection[str], add: Collection[str]
                  ) -> bool:
    """Whether ``task`` has a clock once the clocks in ``drop`` go and those in ``add`` come.

    Its own clock (``own_clock``) stays unless dropped; an added one counts either way.

    Examples
    --------
    >>> clocked_after("A", True, {"A"}, ()), clocked_after("A", False, (), {"A"})
    (False, True)
    """
    return own_clock and task not in drop or task in add


def waits_for(has_clock: bool, inputs: list[Link], outputs: list[Link],
              edited: Mapping[int, Protocol]) -> list[Sync]:
    """A task's synchronizations, in chain order: its clock, the inputs it reads
    blocking, the outputs it posts blocking (``edited``: the protocol of each edited
    link, by its ``id``; the others keep theirs).

    A map, not a function of the link: this runs for every step of every search
    of :class:`Freeing`, and a call per link cost more than the rest of it.

    Examples
    --------
    >>> from tegraph.model.skeleton import Link, Protocol
    >>> link = Link(("A", "x"), ("B", "y"), Protocol.ASYN_SYN)
    >>> [kind for kind, _ in waits_for(True, [link], [], {})]
    ['clock', 'input']
    >>> [kind for kind, _ in waits_for(True, [link], [], {id(link): Protocol.ASYN_ASYN})]
    ['clock']
    """
    out: list[Sync] = [("clock", None)] if has_clock else []
    if edited:
        get = edited.get
        out += [("input", link) for link in inputs
                if get(id(link), link.protocol) in READER_BLOCKS]
        out += [("output", link) for link in outputs
                if get(id(link), link.protocol) in WRITER_BLOCKS]
    else:
        out += [("input", link) for link in inputs if link.protocol in READER_BLOCKS]
        out += [("output", link) for link in outputs if link.protocol in WRITER_BLOCKS]
    return out


_FREE, _REMOVE = 0, 1  # the two kinds of goal: free a task, remove one of its syncs
_MISSING = object()


class Freeing:
    """The variants of some edits in which a task keeps one synchronization only.

    Parameters
    ----------
    inputs, outputs : callable
        The links into (out of) a task, in the order of its ports.
    clock : callable
        The task's own clock, or None.

    Examples
    --------
    B reads A's message ASYN/SYN and has a clock: keeping its clock, B cuts the
    link, or pulls (A then waits for B's request, and A has nothing else to give up).

    >>> from tegraph.model.skeleton import Link, Protocol
    >>> link = Link(("A", "x"), ("B", "y"), Protocol.ASYN_SYN)
    >>> free = Freeing(lambda t: [link] if t == "B" else [],
    ...                lambda t: [link] if t == "A" else [], lambda t: "c" if t == "B" else None)
    >>> runs = [(Edits(), "B", ("clock", None), frozenset({"B"}), "clock")]
    >>> [[p.value for _, p in e.protocol] for e in free.candidates(runs)]
    [['ASYN/ASYN'], ['SYN/ASYN']]
    """

    def __init__(self, inputs: Callable[[str], list[Link]],
                 outputs: Callable[[str], list[Link]],
                 clock: Callable[[str], str | None]) -> None:
        self.inputs, self.outputs, self.clock = inputs, outputs, clock
        # The walk's bound (a branch at least this large is skipped) and cap (candidates
        # and skipped branches counted, past which nothing is within the limit).
        self._bound: int | None = None
        self._cap: int | None = None
        self._found = self._skipped = 0
        self.kept = ""
        # The synchronizations of the last run's task under its base (:meth:`_least`):
        # the runs of one finding share them.
        self._least_base: Edits | None = None
        self._least_task = ""
        self._least_syncs: list[Sync] = []

    # ------------------------------------------------------------ the walk
    def candidates(self, runs: Sequence[Run]) -> Iterator[Edits]:
        """Every candidate of ``runs``, one run after the other, in the order of preference."""
        self._bound, self._cap = None, None
        for size in self._walk(runs):
            edits = self._edits()
            edits._size = size  # what ranking sorts by, counted on the way
            yield edits

    def first(self, runs: Sequence[Run], limit: int) -> Edits | None:
        """The smallest of the first ``limit`` candidates (the earliest among equals).

        None when that cannot be told without making them all (a smaller one
        came after a branch skipped as no smaller than the best so far: how many
        candidates the branch held, and so whether the smaller one is within
        ``limit``, is unknown); there is always one candidate at least.
        """
        self._bound, self._cap = None, limit
        best = None
        for size in self._walk(runs):
            if self._skipped:
                return None
            best = self._edits()  # smaller than any before: the walk skips no smaller ones
            self._bound = size
        return best

    def _walk(self, runs: Sequence[Run]) -> Iterator[int]:
        """Depth first, the first way of each goal first: at each candidate, its size
        (the edits are then in ``self``'s state)."""
        self._found = self._skipped = 0
        for base, task, keep, seen, kept in runs:
            if self._bound is not None and self._least(base, task, keep) >= self._bound:
                # A whole run no smaller than the best so far (a Rule 1 finding's other
                # runs, once the first run's candidate is found): skipped before it is
                # set up, and counted as one branch (it holds a candidate at least).
                self._skipped += 1
                if self._cap is not None and self._found + self._skipped >= self._cap:
                    return
                continue
            self._start(base)
            self.kept = kept
            # Goals to reach, as a linked list (goal, rest): the rest is shared by the
            # ways of a goal. A choice is (undo mark, link, its other protocol, the
            # neighbour to pull then, rest): taken when the first way is done.
            goals: tuple | None = ((_FREE, task, keep, seen), None)
            choices: list[tuple] = []
            while True:
                size = len(self._proto) + len(self._drop) + len(self._add)
                if self._bound is not None and size >= self._bound:
                    self._skipped += 1  # no smaller candidate here; at least one
                    if self._cap is not None and self._found + self._skipped >= self._cap:
                        return
                elif goals is None:
                    if self._cap is not None and self._found + self._skipped >= self._cap:
                        return  # past the first ``cap``
                    self._found += 1
                    yield size
                else:
                    goals = self._step(goals, choices)
                    continue
                if not choices:
                    break
                mark, link, protocol, pull, goals = choices.pop()
                self._undo_to(mark)
                self._set(link, protocol)
                if pull is not None:
                    other, sync, seen = pull
                    goals = ((_FREE, other, sync, seen | {other}), goals)

    def _step(self, goals: tuple, choices: list[tuple]) -> tuple | None:
        """Reach the first goal (its first way), and note its other way as a choice."""
        goal, goals = goals
        if goal[0] == _FREE:  # the task gives up each synchronization but ``keep``, in turn
            _, task, keep, seen = goal
            for sync in reversed(self._syncs(task)):
                if sync != keep:
                    goals = ((_REMOVE, task, sync, seen), goals)
            return goals
        _, task, (kind, link), seen = goal
        if kind == "clock":
            self._clock_off(task)
            return goals
        now = self._proto.get(id(link), link.protocol)
        if now is Protocol.SYN_SYN:  # the other side keeps blocking, or neither does
            choices.append((len(self._undo), link, Protocol.ASYN_ASYN, None, goals))
            self._set(link, Protocol.SYN_ASYN if kind == "input" else Protocol.ASYN_SYN)
            return goals
        other = link.writer[0] if kind == "input" else link.reader[0]
        if other not in seen:
            # Then pull (the writer waits for the task's request) or push (the reader
            # waits), and the other side keeps only that.
            choices.append((len(self._undo), link,
                            Protocol.SYN_ASYN if kind == "input" else Protocol.ASYN_SYN,
                            (other, ("output" if kind == "input" else "input", link), seen),
                            goals))
        self._set(link, Protocol.ASYN_ASYN)
        return goals

    def _least(self, base: Edits, task: str, keep: Sync) -> int:
        """No candidate of the run (``base``, ``task``, ``keep``) is smaller than this.

        Each synchronization of ``task`` but ``keep`` goes, so each of their links
        gets another protocol and the clock, if one of them, is dropped; the walk
        only adds links and dropped clocks (it may only take a task out of the
        added clocks, which are not counted here): the edited links and dropped
        clocks of ``base``, with those, are a lower bound.
        """
        if base is not self._least_base or task != self._least_task:
            has_clock = clocked_after(task, self.clock(task) is not None, base.drop, base.add)
            self._least_base, self._least_task = base, task
            self._least_syncs = waits_for(has_clock, self.inputs(task), self.outputs(task),
                                          base.by_id())
        edited = base.by_id()
        links = {id(link) for kind, link in self._least_syncs
                 if kind != "clock" and (kind, link) != keep and id(link) not in edited}
        drops = len(base.drop) + (keep != ("clock", None) and task not in base.drop
                                  and any(kind == "clock" for kind, _ in self._least_syncs))
        return len(edited) + len(links) + drops

    # ------------------------------------------------------------ the edits so far
    def _start(self, base: Edits) -> None:
        self._base = base
        self._proto: dict[int, Protocol] = {id(link): p for link, p in base.protocol}
        self._sets: list[tuple[Link, Protocol]] = []
        self._drop, self._add = set(base.drop), set(base.add)
        self._undo: list[tuple] = []

    def _set(self, link: Link, protocol: Protocol) -> None:
        key = id(link)
        self._undo.append((key, self._proto.get(key, _MISSING)))
        self._proto[key] = protocol
        self._sets.append((link, protocol))

    def _clock_off(self, task: str) -> None:
        self._undo.append((task, task in self._drop, task in self._add))
        self._drop.add(task)
        self._add.discard(task)

    def _undo_to(self, mark: int) -> None:
        while len(self._undo) > mark:
            entry = self._undo.pop()
            if len(entry) == 2:
                key, before = entry
                self._sets.pop()
                if before is _MISSING:
                    del self._proto[key]
                else:
                    self._proto[key] = before
            else:
                task, dropped, added = entry
                if not dropped:
                    self._drop.discard(task)
                if added:
                    self._add.add(task)

    def _syncs(self, task: str) -> list[Sync]:
        """What ``task`` waits for with the edits so far (as :meth:`.Candidates.syncs`)."""
        has_clock = clocked_after(task, self.clock(task) is not None, self._drop, self._add)
        return waits_for(has_clock, self.inputs(task), self.outputs(task), self._proto)

    def _edits(self) -> Edits:
        return Edits(self._base.protocol + tuple(self._sets), frozenset(self._drop),
                     frozenset(self._add), self.kept)
