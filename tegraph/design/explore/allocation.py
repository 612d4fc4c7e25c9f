"""Where tasks run: the allocation digits of ``explore``'s design space.

An *allocation* puts each *unit* on one of the offered processors: a unit is a whole
group of spec §4 (the groups of the input skeleton,
:attr:`~tegraph.model.structure.Structure.groups`: tasks joined by synchronizing links,
threads and shared clocks move together) or a single task. A pinned unit stays
on its processor; the others are *free*. A task the file puts on a processor that is
not offered (a frame on its bus) is in no unit: it stays there, with its whole group
under ``groups``; a task that names no processor is free.

Two offered processors are *interchangeable* when they have the same declared
properties (``processors:``, spec §4d) and no unit is pinned to them: renaming one into
the other changes no figure (priorities are the tasks', the network delay is one for
every crossing link), so an allocation and its renamings are one variant. Only the
*canonical* allocation of each class of renamings is numbered: within each class of
interchangeable processors (in the order offered), the free units, in order, use the
class's processors in order of first use (a restricted-growth string per class).

The canonical allocations are numbered in lexicographic order of the free units'
processors (in the order offered) without being listed: the number of completions of a
prefix depends only on how many processors of each class it has used
(:meth:`Allocation.count`), so a number is turned into an allocation, and back, in
time linear in the units (times the processors).

With ``n`` free units, ``m`` processors not interchangeable with any other and one
class of ``k`` interchangeable ones, there are ``Σ_j C(n, j) m^(n-j) Σ_{i<=k} S(j, i)``
canonical allocations (``S`` the Stirling numbers of the second kind); all ``k``
alone: the Bell-like ``Σ_{i<=k} S(n, i)``, against ``k^n`` allocations with the
renamings.

Examples
--------
Three free tasks on two interchangeable processors: 4 canonical allocations of the
8 (``aaa aab aba abb``: each with its renaming ``bbb bba bab baa``).

>>> a = Allocation(("p", "q"), (("A",), ("B",), ("C",)), {}, (("p", "q"),))
>>> a.size, [a.processors_of(i) for i in range(a.size)]
(4, [('p', 'p', 'p'), ('p', 'p', 'q'), ('p', 'q', 'p'), ('p', 'q', 'q')])
>>> a.index_of(("q", "p", "p"))  # the renaming of p q q
3
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any

from ...errors import InputError
from ...model.elements import Processor
from ...model.skeleton import Skeleton
from ...model.structure import Structure

__all__ = ["ALLOCATE", "Allocation", "allocation_of"]

ALLOCATE = ("groups", "tasks")
"""What moves: whole groups of spec §4 (the default) or single tasks."""


@dataclass(frozen=True)
class Allocation:
    """The allocation digits of a design space (see the module docstring).

    Attributes
    ----------
    offered : tuple of str
        The processors offered, in the order given.
    units : tuple of tuple of str
        Each unit's tasks (file order), units in the order of their first task.
    pinned : dict of int to str
        Unit index -> the processor it stays on.
    classes : tuple of tuple of str
        The classes of interchangeable processors (two or more each, in offered order).
    mode : str
        ``groups`` or ``tasks`` (:data:`ALLOCATE`).
    """

    offered: tuple[str, ...]
    units: tuple[tuple[str, ...], ...]
    pinned: Mapping[int, str] = field(default_factory=dict)
    classes: tuple[tuple[str, ...], ...] = ()
    mode: str = "groups"

    @cached_property
    def free(self) -> tuple[int, ...]:
        """The units that move, in order."""
        return tuple(u for u in range(len(self.units)) if u not in self.pinned)

    @cached_property
    def _class_of(self) -> dict[str, tuple[int, int]]:
        """Processor -> (its class, its rank in the class)."""
        return {p: (c, j) for c, members in enumerate(self.classes)
                for j, p in enumerate(members)}

    def _options(self, used: tuple[int, ...]) -> list[tuple[str, tuple[int, ...]]]:
        """The processors a free unit may take after a prefix that used ``used[c]``
        processors of class c, with the counts after it (in offered order)."""
        out = []
        for p in self.offered:
            where = self._class_of.get(p)
            if where is None:
                out.append((p, used))
                continue
            c, j = where
            if j < used[c]:
                out.append((p, used))
            elif j == used[c]:
                out.append((p, (*used[:c], used[c] + 1, *used[c + 1:])))
        return out

    def count(self, position: int, used: tuple[int, ...]) -> int:
        """Canonical completions of a prefix of ``position`` free units that used
        ``used[c]`` processors of each class c."""
        return self._table[position][used]

    @cached_property
    def _table(self) -> list[dict[tuple[int, ...], int]]:
        """Completions by position and counts used, filled from the last unit back (no
        recursion: a skeleton may have thousands of units): ``Π (len(class) + 1)``
        states per position."""
        states = list(itertools.product(*(range(len(c) + 1) for c in self.classes)))
        table: list[dict[tuple[int, ...], int]] = [{} for _ in range(len(self.free) + 1)]
        table[-1] = dict.fromkeys(states, 1)
        for position in range(len(self.free) - 1, -1, -1):
            after = table[position + 1]
            table[position] = {used: sum(after[nxt] for _, nxt in self._options(used))
                               for used in states}
        return table

    @property
    def size(self) -> int:
        """The number of canonical allocations (1 with no free unit)."""
        return self.count(0, (0,) * len(self.classes))

    def processors_of(self, index: int) -> tuple[str, ...]:
        """The processor of each free unit in allocation number ``index``."""
        used = (0,) * len(self.classes)
        out = []
        for position in range(len(self.free)):
            for p, after in self._options(used):
                n = self.count(position + 1, after)
                if index < n:
                    out.append(p)
                    used = after
                    break
                index -= n
            else:  # pragma: no cover - index < size
                raise IndexError("allocation index out of range")
        return tuple(out)

    def canonical(self, processors: Sequence[str]) -> tuple[str, ...]:
        """The canonical renaming of an allocation of the free units (each class's
        processors renamed in order of first use)."""
        rename: dict[str, str] = {}
        used = [0] * len(self.classes)
        out = []
        for p in processors:
            where = self._class_of.get(p)
            if where is not None and p not in rename:
                c = where[0]
                rename[p] = self.classes[c][used[c]]
                used[c] += 1
            out.append(rename.get(p, p))
        return tuple(out)

    def index_of(self, processors: Sequence[str]) -> int:
        """The number of the allocation of the free units ``processors`` (renamed to its
        canonical form first)."""
        used = (0,) * len(self.classes)
        index = 0
        for position, wanted in enumerate(self.canonical(processors)):
            for p, after in self._options(used):
                if p == wanted:
                    used = after
                    break
                index += self.count(position + 1, after)
            else:
                raise ValueError(f"processor {wanted!r} is not offered")
        return index

    def task_processors(self, index: int) -> dict[str, str]:
        """Task -> processor, for every task of a unit, in allocation number ``index``."""
        on = dict(zip(self.free, self.processors_of(index)))
        on.update(self.pinned)
        return {t: on[u] for u, tasks in enumerate(self.units) for t in tasks}

    def unit_label(self, unit: int) -> str:
        """A unit as reports name it: its tasks joined by ``+``."""
        return "+".join(self.units[unit])

    def to_dict(self) -> dict[str, Any]:
        """Plain data for the fingerprint and the report."""
        return {"offered": list(self.offered), "mode": self.mode,
                "units": [list(u) for u in self.units],
                "pinned": {self.unit_label(u): p for u, p in sorted(self.pinned.items())},
                "interchangeable": [list(c) for c in self.classes]}


def _processor(skeleton: Skeleton, name: str) -> Processor:
    return skeleton.processors.get(name) or Processor(name)


def allocation_of(skeleton: Skeleton, offer: Sequence[str] | str | None,
                  allocate: str = "groups", pin: Sequence[Any] = ()) -> Allocation | None:
    """The allocation digits offered by ``offer``, ``allocate`` and ``pin``, checked.

    Parameters
    ----------
    skeleton : Skeleton
    offer : sequence of str, or a comma-separated str, or None
        The processors the search may put units on (None or empty: no allocation).
    allocate : str
        ``groups`` (whole groups of spec §4 move together) or ``tasks``.
    pin : sequence
        ``"TASK=PROCESSOR"`` texts or ``(task, processor)`` pairs: the task (its group,
        under ``groups``) stays on that processor, one of ``offer``.

    Returns
    -------
    Allocation or None

    Raises
    ------
    InputError
        A processor named twice or with an empty or ``:``-holding name; ``allocate``
        not one of :data:`ALLOCATE`; a pin that cannot be read, names an unknown
        task or a processor not offered, or pins a unit twice on two processors.

    Examples
    --------
    >>> sk = Skeleton.from_dict({"processors": {"bus": {"preemptive": False}}, "tasks": {
    ...     "A": {"duration": 1, "period": 4, "processor": "bus"},
    ...     "B": {"duration": 1, "period": 4}, "C": {"duration": 1, "period": 4}}})
    >>> a = allocation_of(sk, "p,q,bus", "tasks", ["A=bus"])
    >>> a.free, a.classes, a.size  # B and C: p p, p q, p bus, bus p, bus bus
    ((1, 2), (('p', 'q'),), 5)
    """
    if offer is None or (not isinstance(offer, str) and not offer):
        if pin:
            raise InputError("a task is pinned but no processor is offered; expected "
                             "`offer` with the processors to search", "pin")
        if str(allocate).strip().lower() != "groups":
            raise InputError(f"`allocate` {allocate!r} without processors to offer; expected "
                             "`offer` with the processors to search", "allocate")
        return None
    names = ([n.strip() for n in offer.split(",")] if isinstance(offer, str)
             else [str(n).strip() for n in offer])
    seen: set[str] = set()
    for k, name in enumerate(names):
        if not name or ":" in name or any(c.isspace() for c in name):
            raise InputError(f"processor name {name!r} cannot be read; expected names "
                             "without ':' or spaces, comma-separated, such as cpu1,cpu2",
                             f"offer[{k}]")
        if name in seen:
            raise InputError(f"the processor {name!r} is offered twice; expected each "
                             "processor once", f"offer[{k}]")
        seen.add(name)
    if not names:
        raise InputError("no processor offered; expected at least one name, such as "
                         "cpu1,cpu2", "offer")
    mode = str(allocate).strip().lower()
    if mode not in ALLOCATE:
        raise InputError(f"cannot allocate {allocate!r}; expected one of "
                         f"{', '.join(ALLOCATE)}", "allocate")
    every: tuple[tuple[str, ...], ...] = (
        tuple(tuple(g) for g in Structure.of(skeleton).groups) if mode == "groups"
        else tuple((t,) for t in skeleton.tasks))
    # A task the file puts on a processor that is not offered (a frame on its bus)
    # stays there, and so does its unit; a task without `processor:` is free.
    tasks_of = skeleton.tasks
    stays = {t: tasks_of[t].processor for t in tasks_of
             if tasks_of[t].processor is not None and tasks_of[t].processor not in seen}
    units = tuple(u for u in every if not any(t in stays for t in u))
    unit_of = {t: u for u, tasks in enumerate(units) for t in tasks}
    pinned: dict[int, str] = {}
    for k, item in enumerate(pin):
        where = f"pin[{k}]"
        if isinstance(item, str):
            task, equals, proc = item.partition("=")
            task, proc = task.strip(), proc.strip()
            if not equals or not task or not proc:
                raise InputError(f"cannot read {item!r}; expected TASK=PROCESSOR, such as "
                                 f"CTRL={names[0]}", where)
        else:
            task, proc = str(item[0]), str(item[1])
        if task not in skeleton.tasks:
            known = ", ".join(list(skeleton.tasks)[:8]) + (
                ", ..." if len(skeleton.tasks) > 8 else "")
            raise InputError(f"no task {task!r} in the skeleton; expected TASK=PROCESSOR "
                             f"with one of its tasks ({known})", where)
        if proc not in seen:
            raise InputError(f"unknown processor {proc!r}; expected one of the processors "
                             f"offered ({', '.join(names)})", where)
        if task not in unit_of:
            holder = next(t for u in every if task in u for t in u if t in stays)
            raise InputError(f"{task!r} stays where the file puts it ({holder!r} runs on "
                             f"{stays[holder]!r}, which is not offered); expected a task that "
                             "runs on an offered processor or on none", where)
        u = unit_of[task]
        if pinned.get(u, proc) != proc:
            whose = (f"the group of {task!r} ({'+'.join(units[u])})" if mode == "groups"
                     else repr(task))
            raise InputError(f"{whose} is pinned to both {pinned[u]!r} and {proc!r}; "
                             "expected one processor", where)
        pinned[u] = proc
    classes: dict[Processor, list[str]] = {}
    held = set(pinned.values())
    for name in names:
        if name not in held:
            kind = _processor(skeleton, name)
            # Alike: the same declared properties, whatever the name.
            classes.setdefault(replace(kind, name=""), []).append(name)
    return Allocation(tuple(names), units, pinned,
                      tuple(tuple(c) for c in classes.values() if len(c) > 1), mode)
