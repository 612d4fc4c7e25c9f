"""The design rules of section 6 of the ORCCAD paper, checked on a skeleton.

The ORCCAD paper [1]_ gives four *sufficient* (not necessary) conditions for
a deadlock-free, temporally consistent, low-latency set of module tasks:

1. one and only one synchronization per task: a clock, or one synchronizing
   port (an input read ASYN/SYN or SYN/SYN, an output posted SYN/ASYN or
   SYN/SYN);
2. cooperating tasks are synchronized with ASYN/SYN and SYN/ASYN links (a
   SYN/SYN rendezvous blocks both sides; tasks of one rate left ASYN/ASYN run
   in whatever order the scheduler picks, Figure 4);
3. one and only one clock per synchronized group;
4. one priority per group, different priorities for different groups on one
   processor, rate-monotonic order [2]_, the Robot-task automaton highest.

A synchronized group is a weakly connected part of the timed event graph
(spec §4 ``groups``): tasks joined by a synchronizing link, a thread or a
shared clock. Each finding names the tasks, ports and links concerned and
what to change: for Rules 1-3 a machine-applicable :class:`~.advice.Change`,
chosen so that it brings no other finding of Rules 1-3 (:mod:`.advice`), so
that following the advice never goes round in a circle. The automaton is
recognized by its name (spec §6): ``RTA``, ``automaton``, or a name ending in
``.RTA`` / ``.automaton``, any case.

References
----------
.. [1] D. Simon et al., "Design and analysis of synchronization for
   real-time closed-loop control in robotics", IEEE Transactions on Control
   Systems Technology, 1998.
.. [2] C. L. Liu, J. W. Layland, "Scheduling algorithms for
   multiprogramming in a hard-real-time environment", Journal of the ACM
   20(1), 46–61, 1973.
"""

from __future__ import annotations

import dataclasses
import re
from dataclasses import dataclass
from typing import Any

from maxplus.scalar import display_text

from ..model.skeleton import Protocol, Skeleton
from .advice import CANDIDATE_LIMIT, SPLIT, Advisor
from .change import Change
from .synchronization import (
    Synchronization,
    group_period,
    link_index,
    synchronizations,
    synchronized_groups,
)

__all__ = [
    "RuleFinding",
    "Synchronization",
    "check_rules",
    "group_period",
    "is_automaton",
    "proposed_priorities",
    "synchronizations",
    "synchronized_groups",
]

_AUTOMATON = re.compile(r"(?:^|\.)(?:rta|automaton)$", re.IGNORECASE)
_ORDER = {"error": 0, "warning": 1, "info": 2}


@dataclass(frozen=True)
class RuleFinding:
    """One departure from a rule of section 6 (or, as ``info``, a proposal).

    Attributes
    ----------
    rule : int
        1 to 4.
    severity : str
        ``"error"`` (deadlock, overrun or priority inversion risk),
        ``"warning"`` (a rule is not followed) or ``"info"`` (a proposal).
    tasks, ports, links : tuple of str
        The tasks, ``TASK:PORT`` ports and link labels concerned.
    message : str
        What is wrong.
    advice : str
        What to change, in words.
    change : Change or None
        The same as an edit of the skeleton (Rules 1-3; None for Rule 4, and
        when no change removes the finding without bringing another one).

    See Also
    --------
    check_rules : makes them.
    """

    rule: int
    severity: str
    tasks: tuple[str, ...]
    ports: tuple[str, ...]
    links: tuple[str, ...]
    message: str
    advice: str
    change: Change | None = None

    def to_dict(self) -> dict[str, Any]:
        """Plain data for the JSON report."""
        return {"rule": self.rule, "severity": self.severity, "tasks": list(self.tasks),
                "ports": list(self.ports), "links": [link.document() for link in self.links],
                "message": self.message, "advice": self.advice,
                "change": None if self.change is None else self.change.to_dict()}


def is_automaton(name: str) -> bool:
    """Whether ``name`` names the Robot-task automaton (spec §6).

    >>> is_automaton("RTA"), is_automaton("arm.rta"), is_automaton("PARTA")
    (True, True, False)
    """
    return bool(_AUTOMATON.search(name))


def proposed_priorities(sk: Skeleton) -> dict[str, int]:
    """Rate-monotonic priorities (Rule 4): larger is more urgent.

    On each processor, the automaton first, then the groups by increasing
    design period (:func:`group_period`; groups without a clock last, as
    background work), ties in file order; every task of a group gets its
    group's priority, distinct groups distinct priorities, numbered from 1
    (lowest) up.

    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "SLOW": {"duration": 1, "period": 6}, "FAST": {"duration": 1, "period": 1},
    ...     "RTA": {"duration": 0}}})
    >>> proposed_priorities(sk)
    {'SLOW': 1, 'FAST': 2, 'RTA': 3}
    """
    index = {t: i for i, t in enumerate(sk.tasks)}
    units: dict[str | None, list[tuple[tuple, list[str]]]] = {}
    for group in synchronized_groups(sk):
        period = group_period(sk, group)
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


def check_rules(skeleton: Skeleton) -> list[RuleFinding]:
    """Check Rules 1-4 of section 6 of the ORCCAD paper [1]_.

    Parameters
    ----------
    skeleton : Skeleton
        The design to check (file order decides the order of findings).

    Returns
    -------
    list of RuleFinding
        By rule, then errors before warnings before proposals, then file order.
        No ``error`` or ``warning``: the design follows the rules (which
        suffice for a live, consistent skeleton, spec §4).

    See Also
    --------
    tegraph.fix_ports : repairs a dead skeleton by reordering ports.
    tegraph.design.schedulability.schedulability : the Rule 4 priorities checked
        by response times.
    tegraph.analyze : the report that carries these findings.

    References
    ----------
    .. [1] D. Simon et al., "Design and analysis of synchronization for
       real-time closed-loop control in robotics", IEEE Transactions on Control
       Systems Technology, 1998.
    .. [2] C. L. Liu, J. W. Layland, "Scheduling algorithms for
       multiprogramming in a hard-real-time environment", Journal of the ACM
       20(1), 46–61, 1973.

    Examples
    --------
    Figure 7a: three tasks wait for each other, no clock anywhere (Rule 3).

    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "MT1": {"duration": 1, "inputs": ["b"], "outputs": ["a"]},
    ...     "MT2": {"duration": 1, "inputs": ["c"], "outputs": ["b"]},
    ...     "MT3": {"duration": 1, "inputs": ["a"], "outputs": ["c"]}},
    ...   "links": [{"from": "MT2:b", "to": "MT1:b", "protocol": "ASYN/SYN"},
    ...             {"from": "MT3:c", "to": "MT2:c", "protocol": "ASYN/SYN"},
    ...             {"from": "MT1:a", "to": "MT3:a", "protocol": "ASYN/SYN"}]})
    >>> [(f.rule, f.severity, f.tasks) for f in check_rules(sk) if f.severity != "info"]
    [(3, 'error', ('MT1', 'MT2', 'MT3'))]
    """
    groups = synchronized_groups(skeleton)
    structural = _structural(skeleton, groups)
    advisor = Advisor(skeleton, structural, groups)
    findings = [_advised(f, advisor) for f in structural]
    findings += _rule4(skeleton, groups)
    index = {t: i for i, t in enumerate(skeleton.tasks)}
    findings.sort(key=lambda f: (f.rule, _ORDER[f.severity],
                                 min((index[t] for t in f.tasks), default=0)))
    return findings


def _structural(skeleton: Skeleton, groups: list[tuple[str, ...]]) -> list[RuleFinding]:
    """The findings of Rules 1-3, their advice still to be chosen."""
    group_of = {t: g for g, tasks in enumerate(groups) for t in tasks}
    index = link_index(skeleton)
    return (_rule1(skeleton, index) + _rule2(skeleton, groups, group_of)
            + _rule3(skeleton, groups))


def _advised(finding: RuleFinding, advisor: Advisor) -> RuleFinding:
    """The finding with the best change that brings no other finding, in words."""
    choice = advisor.choose(finding)
    change, said = choice.change, choice.kept
    if change is None:
        # Only a bounded set of candidate changes is examined: say so, claim no more.
        if said:
            advice = (f"none of the changes examined (the smallest of their kind, at most "
                      f"{CANDIDATE_LIMIT}) removes this without another finding of Rules 1-3: "
                      f"{said} would bring "
                      + "; ".join(_key_text(k) for k in sorted(choice.brought))
                      + f" [{choice.periods}]")
        else:
            advice = (f"none of the changes examined (the smallest of their kind, at most "
                      f"{CANDIDATE_LIMIT}) removes this")
        return dataclasses.replace(finding, advice=advice)
    words = advisor.describe(change)
    if finding.rule == 1 and finding.severity == "error":
        words = (f"keep only its {said}" + (" (footnote 6: the synchronizing port is best the "
                 "first input read, or the last output posted)" if said != "clock" else "")
                 + f": {words}")
    elif finding.rule == 3 and said == SPLIT:
        words = f"split the group, each clocked task keeping its clock: {words}"
    elif finding.rule == 3 and said:
        words = f"keep one clock ({said}): {words}"
    elif finding.rule == 3:
        words += " (one clock for the whole group)"
    words += f" [{choice.periods}]"
    if choice.live is False:
        # Under a deadlock, advice that leaves it is said to leave it (spec §4 deadlocks).
        words += (" This alone leaves the skeleton dead: none of the changes examined for this "
                  "finding makes it live (see the deadlock's own advice).")
    elif choice.live:
        words += " This also makes the skeleton live."
    return dataclasses.replace(finding, advice=words, change=change)


def _key_text(key: tuple) -> str:
    """A finding named by its key (:func:`~.change.finding_key`), for an advice's words."""
    rule, severity, tasks = key[:3]
    if rule == 2:
        return f"Rule 2 {severity} on {', '.join(key[4])}"
    if rule == 3:
        return f"Rule 3 {severity} on the group {{{', '.join(tasks)}}}"
    return f"Rule {rule} {severity} on {', '.join(tasks)}"


# ----------------------------------------------------------------------- Rule 1
# Rules 1-3 state what is wrong; what to change is chosen by the advisor.

def _rule1(sk: Skeleton, index: tuple[dict, dict]) -> list[RuleFinding]:
    threaded = {t for thread in sk.threads for t in thread}
    out = []
    for name in sk.tasks:
        syncs = synchronizations(sk, name, index)
        if len(syncs) > 1:
            out.append(RuleFinding(
                1, "error", (name,), tuple(s.port for s in syncs if s.port),
                tuple(s.link.label for s in syncs if s.link),
                f"{name} has {len(syncs)} synchronizations ({'; '.join(s.label for s in syncs)}): "
                "its activations are bound to two rates, which can overrun or deadlock "
                "(Figures 7b, 12)", ""))
        elif not syncs and name not in threaded:
            out.append(RuleFinding(
                1, "warning", (name,), (), (),
                f"{name} has no synchronization (no clock, no input read ASYN/SYN or SYN/SYN, "
                "no output posted SYN/ASYN or SYN/SYN): it runs freely, as often as the "
                "processor lets it", ""))
    return out


# ----------------------------------------------------------------------- Rule 2

def _rule2(sk: Skeleton, groups: list[tuple[str, ...]], group_of: dict[str, int]
           ) -> list[RuleFinding]:
    periods = [group_period(sk, g) for g in groups]
    out = []
    for link in sk.links:
        (w, p), (r, q) = link.writer, link.reader
        if link.protocol is Protocol.SYN_SYN:
            out.append(RuleFinding(
                2, "warning", (w, r), (f"{w}:{p}", f"{r}:{q}"), (link.label,),
                f"{link.label} is a rendezvous: {w} and {r} both block on it, which the paper "
                "advises to avoid (it adds circuits to the skeleton)", ""))
        elif link.protocol is Protocol.ASYN_ASYN and group_of[w] != group_of[r]:
            pw, pr = periods[group_of[w]], periods[group_of[r]]
            if pw is not None and pw == pr:
                out.append(RuleFinding(
                    2, "warning", (w, r), (f"{w}:{p}", f"{r}:{q}"), (link.label,),
                    f"{w} and {r} cooperate at one rate (period {display_text(pw)} {sk.unit}) but "
                    f"{link.label} does not synchronize them: the scheduler may run {r} before "
                    f"{w}, and the data then waits a period at each hop (Figure 4)", ""))
    return out


# ----------------------------------------------------------------------- Rule 3

def _rule3(sk: Skeleton, groups: list[tuple[str, ...]]) -> list[RuleFinding]:
    out = []
    for tasks in groups:
        clocks: dict[str, list[str]] = {}
        for t in tasks:
            if sk.tasks[t].clock:
                clocks.setdefault(sk.tasks[t].clock, []).append(t)  # type: ignore[arg-type]
        if not clocks:
            out.append(RuleFinding(
                3, "error", tasks, (), (),
                f"the group {{{', '.join(tasks)}}} has no clock: nothing sets its rate (it "
                "runs as fast as its tasks allow), and nothing breaks a circular wait such as "
                "Figure 7a", ""))
        elif len(clocks) > 1:
            out.append(RuleFinding(
                3, "error", tasks, (), (),
                f"the group {{{', '.join(tasks)}}} has {len(clocks)} clocks ("
                + ", ".join(f"{c} on {', '.join(ts)}" for c, ts in clocks.items())
                + "): its tasks are bound to several rates, which can overrun (Figure 12)", ""))
    return out


# ----------------------------------------------------------------------- Rule 4

def _rule4(sk: Skeleton, groups: list[tuple[str, ...]]) -> list[RuleFinding]:
    proposal = proposed_priorities(sk)
    declared = {t: task.priority for t, task in sk.tasks.items() if task.priority is not None}

    def propose(tasks: list[str] | tuple[str, ...]) -> str:
        return ", ".join(f"{t}: {proposal[t]}" for t in tasks)

    if not declared:
        return [RuleFinding(
            4, "info", tuple(sk.tasks), (), (),
            "no priority is declared",
            "rate-monotonic priorities (larger is more urgent; add `priority:` to each task): "
            + propose(list(sk.tasks)))]
    out = []
    missing = [t for t in sk.tasks if t not in declared]
    if missing:
        out.append(RuleFinding(
            4, "warning", tuple(missing), (), (),
            f"no priority for {', '.join(missing)} while other tasks have one",
            "declare a priority for every task; rate-monotonic proposal: " + propose(missing)))
    by_processor: dict[str | None, list[tuple[tuple[str, ...], int]]] = {}
    for tasks in groups:
        parts: dict[str | None, list[str]] = {}
        for t in tasks:
            if t in declared and not is_automaton(t):
                parts.setdefault(sk.tasks[t].processor, []).append(t)
        for processor, members in parts.items():
            values = sorted({declared[t] for t in members})
            if len(values) > 1:
                out.append(RuleFinding(
                    4, "error", tuple(members), (), (),
                    "the tasks of one synchronized group have different priorities ("
                    + ", ".join(f"{t}: {declared[t]}" for t in members)
                    + "): a higher-priority task of another group can run in the middle of it",
                    f"give them all one priority (e.g. {values[-1]})"))
            else:
                by_processor.setdefault(processor, []).append((tuple(members), values[0]))
    for processor, units in by_processor.items():
        on = "" if processor is None else f" on processor {processor}"
        first_at: dict[int, tuple[str, ...]] = {}
        for a, pa in units:  # each group sharing a priority with an earlier one
            if pa in first_at:
                b = first_at[pa]
                out.append(RuleFinding(
                    4, "error", b + a, (), (),
                    f"two synchronized groups share priority {pa}{on}: {{{', '.join(b)}}} "
                    f"and {{{', '.join(a)}}}; the scheduler may interleave them",
                    "give different groups different priorities, the shorter period the "
                    "higher (rate-monotonic): " + propose(b + a)))
            else:
                first_at[pa] = a
        # Rate-monotonic order, swept by increasing period (n log n, not all pairs):
        # each slower group above the least urgent of the strictly faster ones is reported.
        timed = sorted(((group_period(sk, a), pa, a) for a, pa in units
                        if group_period(sk, a) is not None), key=lambda x: x[0])
        lowest: tuple | None = None  # (priority, period, tasks) of the faster groups
        i = 0
        while i < len(timed):
            j = i
            while j < len(timed) and timed[j][0] == timed[i][0]:
                j += 1
            for per_b, pb, b in timed[i:j]:
                if lowest is not None and lowest[0] < pb:
                    _, per_a, a = lowest
                    out.append(RuleFinding(
                        4, "warning", a + b, (), (),
                        f"not rate-monotonic{on}: {{{', '.join(a)}}} (period "
                        f"{display_text(per_a)} {sk.unit}) has a lower priority than "
                        f"{{{', '.join(b)}}} (period {display_text(per_b)} {sk.unit})",
                        "give the group with the shorter period the higher priority: "
                        + propose(a + b)))
            for per_b, pb, b in timed[i:j]:
                if lowest is None or pb < lowest[0]:
                    lowest = (pb, per_b, b)
            i = j
    for t, mine in declared.items():
        if not is_automaton(t):
            continue
        rivals = [u for u, theirs in declared.items() if not is_automaton(u)
                  and sk.tasks[u].processor == sk.tasks[t].processor and theirs >= mine]
        if rivals:
            out.append(RuleFinding(
                4, "error", (t, *rivals), (), (),
                f"the automaton {t} (priority {mine}) is not above "
                + ", ".join(f"{u} ({declared[u]})" for u in rivals)
                + ": the reactive behavior would wait for the control tasks",
                f"give {t} a priority above {max(declared[u] for u in rivals)}"))
    return out


