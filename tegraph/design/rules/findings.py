"""What a finding of the design rules is: its kind, its key, its words, its change.

A finding is recognised by its :class:`FindingKind` (which rule, which departure,
how severe) and its ``key`` (what it is about: a task, a link, a group, the
tasks of a priority conflict), never by its message: the message and the advice
are words for people, and rewording them changes no decision of the advisor
(:mod:`.advice`). Two findings of two checks, on two versions of a skeleton, are
the same one when their :attr:`RuleFinding.identity` is.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Any

from ...model.elements import LinkLabel
from ...model.skeleton import Protocol
from .change import Change, ScheduleEffect

__all__ = ["FindingKey", "FindingKind", "RuleFinding", "link_key"]


class FindingKind(enum.Enum):
    """Which departure from which rule a finding reports, and how severe it is.

    The value is ``(rule, severity, name)``; :attr:`rule` and :attr:`severity`
    read it. The key of a finding of each kind (:attr:`RuleFinding.key`):

    - Rule 1: the task (``str``);
    - Rule 2: the link as ``((writer task, port), (reader task, port))``; the
      kind says its protocol (SYN/SYN or ASYN/ASYN);
    - Rule 3: the group (its tasks in file order);
    - Rule 4: the tasks concerned, in the order the finding names them.
    """

    RULE1_SEVERAL_SYNCS = (1, "error", "several synchronizations")
    """A task waits for two things or more: its clock, inputs, outputs (Figures 7b, 12)."""
    RULE1_NO_SYNC = (1, "warning", "no synchronization")
    """A task outside any thread waits for nothing: it runs freely."""
    RULE2_RENDEZVOUS = (2, "warning", "rendezvous")
    """A SYN/SYN link: both sides block."""
    RULE2_UNSYNCHRONIZED = (2, "warning", "unsynchronized")
    """An ASYN/ASYN link between two groups of one design period (Figure 4)."""
    RULE3_NO_CLOCK = (3, "error", "no clock")
    """A synchronized group without a clock (Figure 7a)."""
    RULE3_SEVERAL_CLOCKS = (3, "error", "several clocks")
    """A synchronized group bound to two clocks or more (Figure 12)."""
    RULE4_NONE_DECLARED = (4, "info", "no priority declared")
    """No task declares a priority: the rate-monotonic proposal."""
    RULE4_PARTIAL = (4, "error", "partial declaration")
    """Some tasks of one processor declare a priority, these do not: all or none (spec
    §4b), so the declared ones are replaced; its change completes the declaration."""
    RULE4_MISSING = (4, "warning", "priority missing")
    """Some tasks declare a priority, these do not (on a processor where none does)."""
    RULE4_GROUP_PRIORITIES = (4, "error", "one group, several priorities")
    """The tasks of one group on one processor have different priorities."""
    RULE4_SHARED_PRIORITY = (4, "error", "two groups, one priority")
    """Two groups on one processor share a priority."""
    RULE4_NOT_RATE_MONOTONIC = (4, "warning", "not rate-monotonic")
    """A slower group has a higher priority than a faster one."""
    RULE4_AUTOMATON_BELOW = (4, "error", "automaton not highest")
    """The Robot-task automaton is not above every control task of its processor."""

    rule: int
    """1 to 4."""
    severity: str
    """``"error"``, ``"warning"`` or ``"info"``."""

    def __init__(self, rule: int, severity: str, _words: str) -> None:
        # Plain attributes, set once per member: an enum property reads ``value``
        # through enum's descriptor, which cost more than the rest of sorting
        # 10,000 findings by rule and severity.
        self.rule, self.severity = rule, severity


FindingKey = tuple[FindingKind, Any]
"""What identifies a finding: its kind and its key (:attr:`RuleFinding.identity`)."""

# The protocol that each kind of Rule 2 finding is about (its key names the ports).
RULE2_PROTOCOL = {FindingKind.RULE2_RENDEZVOUS: Protocol.SYN_SYN,
                  FindingKind.RULE2_UNSYNCHRONIZED: Protocol.ASYN_ASYN}


def link_key(writer: tuple[str, str], reader: tuple[str, str]) -> tuple[tuple[str, ...], ...]:
    """The key of a Rule 2 finding: the link's two ports, ``(task, port)`` each."""
    return (tuple(writer), tuple(reader))


@dataclass(frozen=True)
class RuleFinding:
    """One departure from a rule of section 6 (or, as ``info``, a proposal).

    Attributes
    ----------
    kind : FindingKind
        Which rule, which departure, how severe.
    key
        What it is about (see :class:`FindingKind`): with ``kind``, what
        identifies the finding.
    tasks, ports, links : tuple of str
        The tasks, ``TASK:PORT`` ports and link labels concerned.
    message : str
        What is wrong, in words (nothing reads it but people).
    advice : str
        What to change, in words.
    change : Change or None
        The same as an edit of the skeleton (Rules 1-3, and a partial declaration of
        priorities; None for the other Rule 4 findings, and when no change removes
        the finding without bringing another one).
    schedule : ScheduleEffect or None
        What ``change`` does to the skeleton on its processors (spec §4b), before
        -> after; None without a change, or when every task has a processor of
        its own (``processors=False``), where the periods say it.

    See Also
    --------
    tegraph.design.rules.check.check_rules : makes them.

    Examples
    --------
    >>> f = RuleFinding(FindingKind.RULE1_NO_SYNC, "T", ("T",), (), (), "T runs freely", "")
    >>> f.rule, f.severity, f.identity
    (1, 'warning', (<FindingKind.RULE1_NO_SYNC: (1, 'warning', 'no synchronization')>, 'T'))
    """

    kind: FindingKind
    key: Any
    tasks: tuple[str, ...]
    ports: tuple[str, ...]
    links: tuple[LinkLabel, ...]
    message: str
    advice: str
    change: Change | None = None
    schedule: ScheduleEffect | None = None

    @property
    def rule(self) -> int:
        """1 to 4."""
        return self.kind.rule

    @property
    def severity(self) -> str:
        """``"error"`` (deadlock, overrun or priority inversion risk), ``"warning"``
        (a rule is not followed) or ``"info"`` (a proposal)."""
        return self.kind.severity

    @property
    def identity(self) -> FindingKey:
        """``(kind, key)``: the same finding in two checks of two versions of a skeleton."""
        return (self.kind, self.key)

    def to_dict(self, part: int | None = None) -> dict[str, Any]:
        """Plain data for the JSON report; ``part``: the index of ``schedule``'s part in
        the section's ``schedule_parts`` (:meth:`DesignSection.to_dict
        <tegraph.design.section.DesignSection.to_dict>` numbers them)."""
        schedule = None
        if self.schedule is not None:
            if part is None:
                raise ValueError("a finding with a schedule needs its part's index")
            schedule = self.schedule.to_dict(part)
        return {"rule": self.rule, "severity": self.severity, "tasks": list(self.tasks),
                "ports": list(self.ports), "links": [link.document() for link in self.links],
                "message": self.message, "advice": self.advice,
                "change": None if self.change is None else self.change.to_dict(),
                "schedule": schedule}


def key_text(identity: FindingKey) -> str:
    """A finding named by its identity, for an advice's words.

    >>> key_text((FindingKind.RULE3_NO_CLOCK, ("A", "B")))
    'Rule 3 error on the group {A, B}'
    """
    kind, key = identity
    if kind.rule == 2:
        (w, p), (r, q) = key
        return f"Rule 2 {kind.severity} on {w}:{p} -> {r}:{q} ({RULE2_PROTOCOL[kind].value})"
    if kind.rule == 3:
        return f"Rule 3 {kind.severity} on the group {{{', '.join(key)}}}"
    return f"Rule {kind.rule} {kind.severity} on {key if kind.rule == 1 else ', '.join(key)}"


def naming_order(identity: FindingKey) -> tuple:
    """The order in which an advice names findings: by rule, errors first, tasks, then
    for Rule 2 the ports and protocol, for Rule 3 several clocks before none."""
    kind, key = identity
    if kind.rule == 1:
        return (1, kind.severity, (key,))
    if kind.rule == 2:
        (w, p), (r, q) = key
        return (2, kind.severity, (w, r), (f"{w}:{p}", f"{r}:{q}"),
                (f"{w}:{p} -> {r}:{q} ({RULE2_PROTOCOL[kind].value})",))
    if kind.rule == 3:
        return (3, kind.severity, tuple(key), kind is FindingKind.RULE3_NO_CLOCK)
    return (kind.rule, kind.severity, tuple(key))
