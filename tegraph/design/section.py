"""The design section of a report (ORCCAD §6): rules, schedulability, chain latencies."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ..analysis.results import Report
from ..model.skeleton import Skeleton
from .latency import chain_latency
from .rules import check_rules
from .schedulability import schedulability

__all__ = ["design_section"]


def design_section(skeleton: Skeleton, report: Report,
                   chains: Sequence[Sequence[str]] = ()) -> dict[str, Any]:
    """Rules 1-4, schedulability and the latency of each chain, for one analyzed skeleton.

    Parameters
    ----------
    skeleton : Skeleton
    report : Report
        Its analysis (:func:`tegraph.analysis.analyze.analyze_skeleton`): the
        periods come from there.
    chains : sequence of task-name sequences
        Chains to report besides the skeleton's own ``chains`` (key path
        ``chains[i][j]`` for those, ``chain[i][j]`` for these in error messages).

    Returns
    -------
    dict
        ``rules`` (list of RuleFinding), ``schedulability`` (Schedulability),
        ``latency`` (list of ChainLatency): the ``design`` of a :class:`Report`.

    Raises
    ------
    SkeletonError
        A chain names an unknown task, a task twice, or two unlinked tasks.
    """
    sched = schedulability(skeleton, report)
    named = [(tuple(c), ("chains", i)) for i, c in enumerate(skeleton.chains)]
    named += [(tuple(c), ("chain", i)) for i, c in enumerate(chains)]
    return {
        "rules": check_rules(skeleton),
        "schedulability": sched,
        "latency": [chain_latency(skeleton, c, report, sched, path) for c, path in named],
    }
