"""Rules 1-3 on a skeleton, each finding with its advice; :func:`check_rules`, all four rules.

Rules 1-3 state what is wrong (:func:`rule1`, :func:`rule2`, :func:`rule3`);
what to change is chosen by the advisor (:mod:`.advice`) and said here in
words (:func:`advised`). Rule 4 is :mod:`.priorities`.

References
----------
.. [1] D. Simon et al., "Design and analysis of synchronization for
   real-time closed-loop control in robotics", IEEE Transactions on Control
   Systems Technology, 1998.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from maxplus.scalar import display_text

from ...model.platform import Platform
from ...model.skeleton import Protocol, Skeleton
from ...model.structure import Structure
from .advice import CANDIDATE_LIMIT, SPLIT, Advisor, PeriodProposal
from .change import Change, ScheduleEffect
from .findings import FindingKind, RuleFinding, key_text, link_key, naming_order
from .on_processors import ScheduleAdvice
from .priorities import rule4
from .synchronization import synchronizations

__all__ = ["check_rules"]

_ORDER = {"error": 0, "warning": 1, "info": 2}


def check_rules(skeleton: Skeleton, structure: Structure | None = None, *,
                processors: bool = True, live: bool | None = None,
                chains: Mapping[tuple[str, ...], Any] | Sequence[Sequence[str]] = (),
                platform: Platform | None = None) -> list[RuleFinding]:
    """Check Rules 1-4 of section 6 of the ORCCAD paper [1]_.

    Parameters
    ----------
    skeleton : Skeleton
        The design to check (file order decides the order of findings).
    structure : Structure, optional
        ``Structure.of(skeleton)``, if known (its groups are the synchronized groups).
    processors : bool
        Also say what each advised change does to the skeleton on its processors
        (spec §4b, :mod:`tegraph.design.rules.on_processors`: ``RuleFinding.schedule``
        and a clause of
        the advice); False: every task has a processor of its own, where the
        periods the advice states say it.
    live : bool, optional
        Whether the skeleton is live (``Report.live`` of its analysis), if known:
        the advice then need not look for token-free circuits itself.
    chains : mapping or sequence of task-name sequences
        With ``processors``: chains (checked) whose first use on processors each
        advised change states before -> after, where it touches them (spec §4c); a
        mapping gives their figures on processors as they are (``report.chains``).
    platform : Platform, optional
        ``report.platform``, if known (Rule 4 reads its priorities and processors).

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
    >>> [(f.kind.name, f.key) for f in check_rules(sk) if f.severity != "info"]
    [('RULE3_NO_CLOCK', ('MT1', 'MT2', 'MT3'))]
    """
    structure = Structure.of(skeleton) if structure is None else structure
    structural = structural_findings(skeleton, structure)
    advisor = Advisor(skeleton, structural, structure, live)
    on = (ScheduleAdvice(skeleton, structure.groups, structure.group_of, advisor.fresh, chains)
          if processors else None)
    findings = [advised(f, advisor, on) for f in structural]
    findings += rule4(skeleton, structure, platform)
    index = {t: i for i, t in enumerate(skeleton.tasks)}
    findings.sort(key=lambda f: (f.rule, _ORDER[f.severity],
                                 # Most findings name one task: no generator for it.
                                 index[f.tasks[0]] if len(f.tasks) == 1
                                 else min((index[t] for t in f.tasks), default=0)))
    return findings


def structural_findings(skeleton: Skeleton, structure: Structure) -> list[RuleFinding]:
    """The findings of Rules 1-3, their advice still to be chosen."""
    return (rule1(skeleton, structure) + rule2(skeleton, structure)
            + rule3(skeleton, structure.groups))


def advised(finding: RuleFinding, advisor: Advisor, on: ScheduleAdvice | None = None
            ) -> RuleFinding:
    """The finding with the best change that brings no other finding, in words; with
    ``on``, what the change does to the skeleton on its processors too."""
    choice = advisor.choose(finding, on)
    change, said = choice.change, choice.kept
    if change is None:
        # Only a bounded set of candidate changes is examined: say so, claim no more.
        advice = (f"none of the changes examined (the smallest of their kind, at most "
                  f"{CANDIDATE_LIMIT}) removes this")
        if said:
            advice += (f" without another finding of Rules 1-3: {said} would bring "
                       + "; ".join(key_text(k) for k in sorted(choice.brought, key=naming_order))
                       + f" [{choice.periods}]")
        return _with_advice(finding, advice, finding.change, finding.schedule)
    words = advisor.describe(change)
    if finding.kind is FindingKind.RULE1_SEVERAL_SYNCS:
        words = (f"keep only its {said}" + (" (footnote 6: the synchronizing port is best the "
                 "first input read, or the last output posted)" if said != "clock" else "")
                 + f": {words}")
    elif finding.rule == 3 and said == SPLIT:
        words = f"split the group, each clocked task keeping its clock: {words}"
    elif finding.rule == 3 and said:
        words = f"keep one clock ({said}): {words}"
    notes = ["one clock for the whole group"] if finding.rule == 3 and not said else []
    if choice.proposal is not None:
        notes.append(_proposal_words(choice.proposal, advisor.sk.unit))
    if notes:
        words += f" ({'; '.join(notes)})"
    effect = None if on is None else on.effect(change)
    words += f" [{choice.periods}" + ("" if effect is None else f"; {effect.text}") + "]"
    if choice.live is False:
        # Under a deadlock, advice that leaves it is said to leave it (spec §4 deadlocks).
        words += (" This alone leaves the skeleton dead: none of the changes examined for this "
                  "finding makes it live (see the deadlock's own advice).")
    elif choice.live:
        words += " This also makes the skeleton live."
    return _with_advice(finding, words, change, effect)


def _proposal_words(proposal: PeriodProposal, unit: str) -> str:
    """Why the period of a new clock is the one proposed (:mod:`.periods`)."""
    if proposal.source == "assumed":
        return "no period is known around the group: the one the check assumed"
    hyper = f"{display_text(proposal.hyperperiod)} {unit}"
    if proposal.source in ("cycle time", "duration"):
        what = ("the group's cycle time" if proposal.source == "cycle time"
                else "its longest duration")
        why = f"a multiple of {what} (no clock around it)"
    else:
        whose = ("the groups it is linked to" if proposal.source == "linked"
                 else "the groups on its processors")
        why = (f"from the periods of {whose}: it divides {hyper}, their hyperperiod, which "
               "stays" if proposal.divides else
               f"from the periods of {whose}: their hyperperiod becomes {hyper}")
    if proposal.tried == 0:
        return why
    tried = (f"the first of {proposal.tried} periods tried" if proposal.tried > 1
             else "the first period tried")
    verdict = {True: f"{tried} that is schedulable on its processors",
               False: f"none of the {proposal.tried} periods tried is schedulable on its "
                      "processors",
               None: "not decided on its processors"}[proposal.schedulable]
    return f"{why}; {verdict}"


def _with_advice(finding: RuleFinding, advice: str, change: Change | None,
                 schedule: ScheduleEffect | None) -> RuleFinding:
    """``finding`` with its advice (its own fields, named here rather than copied by
    ``dataclasses.replace``, which inspects the class's fields at each call: a tenth of
    the advice's own time over 10,000 findings)."""
    # Its own class, as dataclasses.replace would (not the name RuleFinding read again).
    return type(finding)(finding.kind, finding.key, finding.tasks, finding.ports,
                         finding.links, finding.message, advice, change, schedule)


def rule1(sk: Skeleton, structure: Structure) -> list[RuleFinding]:
    """Rule 1: tasks with several synchronizations, and tasks outside threads with none."""
    threaded = {t for thread in sk.threads for t in thread}
    out = []
    for name in sk.tasks:
        syncs = synchronizations(sk, name, structure)
        if len(syncs) > 1:
            out.append(RuleFinding(
                FindingKind.RULE1_SEVERAL_SYNCS, name, (name,),
                tuple(s.port for s in syncs if s.port),
                tuple(s.link.label for s in syncs if s.link),
                f"{name} has {len(syncs)} synchronizations ({'; '.join(s.label for s in syncs)}): "
                "its activations are bound to two rates, which can overrun or deadlock "
                "(Figures 7b, 12)", ""))
        elif not syncs and name not in threaded:
            out.append(RuleFinding(
                FindingKind.RULE1_NO_SYNC, name, (name,), (), (),
                f"{name} has no synchronization (no clock, no input read ASYN/SYN or SYN/SYN, "
                "no output posted SYN/ASYN or SYN/SYN): it runs freely, as often as the "
                "processor lets it", ""))
    return out


def rule2(sk: Skeleton, structure: Structure) -> list[RuleFinding]:
    """Rule 2: rendezvous, and ASYN/ASYN links between two groups of one design period."""
    periods, group_of = structure.periods, structure.group_of
    out = []
    for link in sk.links:
        (w, p), (r, q) = link.writer, link.reader
        key = link_key(link.writer, link.reader)
        if link.protocol is Protocol.SYN_SYN:
            out.append(RuleFinding(
                FindingKind.RULE2_RENDEZVOUS, key, (w, r), (f"{w}:{p}", f"{r}:{q}"),
                (link.label,),
                f"{link.label} is a rendezvous: {w} and {r} both block on it, which the paper "
                "advises to avoid (it adds circuits to the skeleton)", ""))
        elif link.protocol is Protocol.ASYN_ASYN and group_of[w] != group_of[r]:
            pw, pr = periods[group_of[w]], periods[group_of[r]]
            if pw is not None and pw == pr:
                out.append(RuleFinding(
                    FindingKind.RULE2_UNSYNCHRONIZED, key, (w, r), (f"{w}:{p}", f"{r}:{q}"),
                    (link.label,),
                    f"{w} and {r} cooperate at one rate (period {display_text(pw)} {sk.unit}) "
                    f"but {link.label} does not synchronize them: the scheduler may run {r} "
                    f"before {w}, and the data then waits a period at each hop (Figure 4)", ""))
    return out


def rule3(sk: Skeleton, groups: tuple[tuple[str, ...], ...]) -> list[RuleFinding]:
    """Rule 3: groups without a clock, and groups with several."""
    out = []
    for tasks in groups:
        clocks: dict[str, list[str]] = {}
        for t in tasks:
            if clock := sk.tasks[t].clock:
                clocks.setdefault(clock, []).append(t)
        if not clocks:
            out.append(RuleFinding(
                FindingKind.RULE3_NO_CLOCK, tasks, tasks, (), (),
                f"the group {{{', '.join(tasks)}}} has no clock: nothing sets its rate (it "
                "runs as fast as its tasks allow), and nothing breaks a circular wait such as "
                "Figure 7a", ""))
        elif len(clocks) > 1:
            out.append(RuleFinding(
                FindingKind.RULE3_SEVERAL_CLOCKS, tasks, tasks, (), (),
                f"the group {{{', '.join(tasks)}}} has {len(clocks)} clocks ("
                + ", ".join(f"{c} on {', '.join(ts)}" for c, ts in clocks.items())
                + "): its tasks are bound to several rates, which can overrun (Figure 12)", ""))
    return out
