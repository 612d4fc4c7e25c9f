"""The design section of a report (ORCCAD §6): rules, schedulability, chain latencies.

It stands beside the :mod:`.rules` sub-package, not in it: it also reads the
schedulability (:mod:`.schedulability`), which itself reads the rate-monotonic
proposal of Rule 4.

Its verdict on schedulability is the analysis's, exactly (spec §4b, the schedule on
processors: :attr:`DesignSection.schedulable`); the response-time test of ORCCAD §6 is
a cross-check beside it (:mod:`.cross_check`), never the verdict.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from ..analysis.processors.overlap import NeverTogether
from ..analysis.results import Report
from ..model.skeleton import Skeleton
from .cross_check import CrossCheck, cross_check
from .latency import ChainLatency, chain_latencies
from .rules import RuleFinding, check_rules
from .schedulability import Schedulability, schedulability

__all__ = ["DesignSection", "design_section"]


@dataclass
class DesignSection:
    """Rules 1-4, schedulability and chain latencies of one skeleton.

    It is the ``design`` of a :class:`~tegraph.analysis.results.Report`, and
    the whole result of ``tegraph rules`` (:func:`tegraph.api.rules`).

    Attributes
    ----------
    name, unit : str
        The skeleton's name and time unit.
    rules : list of RuleFinding
    schedulability : Schedulability
        The response-time test and the paper's utilization condition: a cross-check.
    latency : list of ChainLatency
        The skeleton's own chains, then those asked for.
    cross_check : CrossCheck
        Where the test agrees with the exact schedule.
    analysis : Report
        The analysis the section was made from: its verdict is the section's.
    never_together : NeverTogether or None
        The tasks on different processors that never execute at once in the proven
        schedule (:mod:`.placement`; ``tegraph rules`` computes them), or None.
    """

    name: str
    unit: str
    rules: list[RuleFinding]
    schedulability: Schedulability
    latency: list[ChainLatency]
    cross_check: CrossCheck
    analysis: Report = field(repr=False, compare=False)
    never_together: NeverTogether | None = field(default=None, compare=False)

    @property
    def schedulable(self) -> bool | None:
        """The exact verdict of spec §4b, as ``tegraph analyze`` gives it
        (:attr:`Report.schedulable`; with a processor per task when the analysis was
        not made on processors)."""
        return self.analysis.schedulable

    @property
    def exit_status(self) -> int:
        """Of ``tegraph rules``: 1 when a rule is not followed (an error or a warning) or
        the analysis's exit status is 1 (a deadlock, an overrun, a growing place, not
        schedulable on its processors, or undecided: no proof), else 0. The
        response-time test decides nothing."""
        violated = (any(f.severity != "info" for f in self.rules)
                    or self.analysis.exit_status != 0)
        return 1 if violated else 0

    def to_dict(self) -> dict[str, Any]:
        """The ``design`` of the JSON report (``rules``, ``schedule_parts``,
        ``schedulability``, ``latency``).

        The parts an advised change was decided on (its tasks and processors) are
        listed once, in order of first use, and each finding's ``schedule`` names its
        part by index: many findings share one part.
        """
        parts: dict[int, int] = {}  # id of a part's task tuple -> its index
        shown: list[dict[str, Any]] = []
        rules = []
        for f in self.rules:
            part = None
            if f.schedule is not None:
                # The advice shares one tuple per part, so its identity finds it without
                # hashing thousands of names per finding; equal copies only repeat a row.
                part = parts.get(id(f.schedule.tasks))
                if part is None:
                    part = parts[id(f.schedule.tasks)] = len(shown)
                    shown.append({"tasks": list(f.schedule.tasks),
                                  "processors": list(f.schedule.processors)})
            rules.append(f.to_dict(part))
        return {
            "rules": rules,
            "schedule_parts": shown,
            "schedulability": {**self.schedulability.to_dict(),
                               "cross_check": self.cross_check.to_dict()},
            "latency": [c.to_dict() for c in self.latency],
        } | ({} if self.never_together is None
             else {"never_together": _never_together_dict(self.never_together)})


def _never_together_dict(n: NeverTogether) -> dict[str, Any]:
    return {"pairs": None if n.pairs is None else [list(p) for p in n.pairs],
            "examined": n.examined, "why": n.why, "left_out": n.left_out}


def design_section(skeleton: Skeleton, report: Report,
                   chains: Sequence[Sequence[str]] = (), *,
                   processors: bool | None = None) -> DesignSection:
    """Rules 1-4, schedulability and the latency of each chain, for one analyzed skeleton.

    Parameters
    ----------
    skeleton : Skeleton
    report : Report
        Its analysis (:func:`tegraph.analysis.analyze.analyze_skeleton`): the
        periods come from there, and the chains' exact figures (``report.chains``,
        when it was analyzed with the skeleton's chains and ``chains``).
    chains : sequence of task-name sequences
        Chains to report besides the skeleton's own ``chains`` (key path
        ``chains[i][j]`` for those, ``chain[i][j]`` for these in error messages).
    processors : bool, optional
        Whether the advice says what each change does on the skeleton's processors
        (spec §4b); default: where ``report`` was decided on them (``report.schedule``).

    Returns
    -------
    DesignSection
        The ``design`` of a :class:`Report`.

    Raises
    ------
    SkeletonError
        A chain names an unknown task, a task twice, or two unlinked tasks.
    """
    sched = schedulability(skeleton, report)
    named = [(tuple(c), ("chains", i)) for i, c in enumerate(skeleton.chains)]
    named += [(tuple(c), ("chain", i)) for i, c in enumerate(chains)]
    # The report's chains are these, in this order, when it was analyzed with them.
    figures = (list(report.chains) if [c.tasks for c in report.chains] == [c for c, _ in named]
               else [None] * len(named))
    on_processors = report.schedule is not None if processors is None else processors
    return DesignSection(
        name=skeleton.name, unit=skeleton.unit,
        rules=check_rules(skeleton, report.structure, processors=on_processors,
                          live=report.live, chains={
                              c: None if f is None or report.schedule is None
                              else f.on_processors
                              for (c, _), f in zip(named, figures)} if on_processors else {},
                          platform=report.platform),
        schedulability=sched,
        latency=chain_latencies(skeleton, [(c, path, f) for (c, path), f in zip(named, figures)],
                                report, sched),
        cross_check=cross_check(sched, report), analysis=report)
