"""A machine-applicable edit of a skeleton: what a design-rule finding says to change.

:class:`Change` is the structured form of a finding's advice (links that get
another protocol, clocks removed, clocks added, priorities declared); :func:`apply_change`
makes it. (What identifies a
finding is its kind and key: :attr:`~.findings.RuleFinding.identity`.)
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from maxplus.scalar import exact_text

from ...errors import InputError
from ...model.skeleton import Clock, Protocol, Skeleton

__all__ = ["Change", "ScheduleEffect", "apply_change"]


@dataclass(frozen=True)
class Change:
    """A machine-applicable edit of a skeleton: what a finding's advice says to do.

    Attributes
    ----------
    protocols : tuple of (str, str, str)
        ``(writer "TASK:PORT", reader "TASK:PORT", protocol)``: links to give
        another protocol, in the order of the skeleton's links.
    drop_clock : tuple of str
        Tasks whose clock is removed (a ``period:`` shorthand included).
    add_clock : tuple of str
        Tasks that get a clock of their own; its period is the designer's choice
        (the check assumes one equal to no other period of the skeleton).
    priorities : tuple of (str, int)
        ``(task, priority)``: priorities to declare (Rule 4, completing a partial
        declaration), in file order.
    period : Fraction or None
        The period proposed for the clocks ``add_clock`` adds (None: none proposed;
        :func:`apply_change` then needs one).
    """

    protocols: tuple[tuple[str, str, str], ...] = ()
    drop_clock: tuple[str, ...] = ()
    add_clock: tuple[str, ...] = ()
    priorities: tuple[tuple[str, int], ...] = ()
    period: Fraction | None = None

    def to_dict(self) -> dict[str, Any]:
        """Plain data for the JSON report."""
        return {"protocols": [{"from": w, "to": r, "protocol": p} for w, r, p in self.protocols],
                "drop_clock": list(self.drop_clock), "add_clock": list(self.add_clock),
                "priorities": [{"task": t, "priority": p} for t, p in self.priorities],
                "period": None if self.period is None else exact_text(self.period)}


@dataclass(frozen=True)
class ScheduleEffect:
    """What a change does to the skeleton on its processors (spec §4b), before -> after.

    Decided on the part the change touches
    (:mod:`tegraph.design.rules.on_processors`): the groups it
    touches and every group sharing a processor with them.

    Attributes
    ----------
    tasks : tuple of str
        The tasks of that part, in file order (the rest is not simulated again).
    processors : tuple of str
        Their processors.
    before, after : bool or None
        Schedulable on processors without and with the change; None: not decided
        (``why_undecided``).
    why_undecided : str or None
        Why ``before`` or ``after`` is None (a budget); None when both are decided.
    text : str
        The same in words (the advice's clause).
    """

    tasks: tuple[str, ...]
    processors: tuple[str, ...]
    before: bool | None
    after: bool | None
    why_undecided: str | None
    text: str

    def to_dict(self, part: int) -> dict[str, Any]:
        """Plain data for the JSON report (the words are in the finding's advice); the
        tasks and processors are ``part``, an index into the design section's
        ``schedule_parts``: written once, not once per finding (one part of 10,000 tasks
        touched by 4,000 findings made a JSON report of 1.2 GB)."""
        return {"part": part, "schedulable_before": self.before,
                "schedulable_after": self.after, "why_undecided": self.why_undecided}


def apply_change(skeleton: Skeleton, change: Change, period: Fraction | int | None = None
                 ) -> Skeleton:
    """The skeleton with ``change`` applied (the input is not modified).

    Parameters
    ----------
    skeleton : Skeleton
    change : Change
    period : Fraction, optional
        Period of each clock that ``change.add_clock`` adds (a private clock
        ``T.clock``, phase 0); needed only when it adds one; default
        ``change.period``.

    Returns
    -------
    Skeleton

    Raises
    ------
    InputError
        ``change`` names a link or task the skeleton does not have, or adds a
        clock without ``period``.

    Examples
    --------
    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "A": {"duration": 1, "period": 4, "outputs": ["x"]},
    ...     "B": {"duration": 1, "period": 4, "inputs": ["x"]}},
    ...   "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/ASYN"}]})
    >>> out = apply_change(sk, Change((("A:x", "B:x", "ASYN/SYN"),), drop_clock=("B",)))
    >>> out.links[0].protocol.value, out.tasks["B"].clock, sorted(out.clocks)
    ('ASYN/SYN', None, ['A.clock'])
    """
    wanted = {(w, r): Protocol(p) for w, r, p in change.protocols}
    links = []
    for link in skeleton.links:
        key = (":".join(link.writer), ":".join(link.reader))
        links.append(dataclasses.replace(link, protocol=wanted.pop(key)) if key in wanted
                     else link)
    if wanted:
        raise InputError(f"no link {' -> '.join(next(iter(wanted)))} in the skeleton", "change")
    tasks, clocks = dict(skeleton.tasks), dict(skeleton.clocks)
    for name in (*change.drop_clock, *change.add_clock, *(t for t, _ in change.priorities)):
        if name not in tasks:
            raise InputError(f"no task {name!r} in the skeleton", "change")
    for name, priority in change.priorities:
        tasks[name] = dataclasses.replace(tasks[name], priority=int(priority))
    for name in change.drop_clock:
        tasks[name] = dataclasses.replace(tasks[name], clock=None)
    if period is None:
        period = change.period
    if change.add_clock and period is None:
        raise InputError("a clock is added: give its period", "period")
    for name in change.add_clock:
        clock = f"{name}.clock"
        while clock in clocks:
            clock += "'"
        # Type: period is given whenever a clock is added (refused above otherwise).
        clocks[clock] = Clock(clock, Fraction(period), private=True)  # type: ignore[arg-type]
        tasks[name] = dataclasses.replace(tasks[name], clock=clock)
    used = {t.clock for t in tasks.values()}
    # A private clock belongs to its task's `period:`: it goes with it.
    clocks = {c: k for c, k in clocks.items() if c in used or not k.private}
    return dataclasses.replace(skeleton, tasks=tasks, clocks=clocks, links=links)
