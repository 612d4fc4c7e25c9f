"""The latency of each chain (spec §4c) in the text reports: a table, each figure labelled.

The figures on the skeleton's processors (§4b) and with a processor per task (§3)
are printed side by side, labelled as the task tables are, so that neither is read
for the other; a null figure says why (``why_undecided``).

See Also
--------
tegraph.analysis.chains.chain_reports : computes them.
"""

from __future__ import annotations

from collections.abc import Sequence

from tabulate import tabulate

from ..analysis.chains import ChainFigures, ChainReport
from ._format import human

__all__ = ["CHAIN_FIGURES_MEANING", "figures_text", "render_chains"]

CHAIN_FIGURES_MEANING = (
    "first use: from a sensor sample to the first output computed from it (the paper's "
    "latency); age: how old the sample an output is computed from is when it is posted "
    "(age min: the least); reaction: from a change of the sensor value, just after a "
    "sample, to the first output that reflects it (exact for the declared phases of the "
    "clocks, over the periodic regime; spec §4c)")


def figures_text(f: ChainFigures, unit: str) -> str:
    """``first use 6 ms, age 6 ms (min 6 ms), reaction 16 ms``, or why it is undecided.

    >>> from fractions import Fraction as F
    >>> figures_text(ChainFigures(F(6), F(6), F(6), F(16)), "ms")
    'first use 6 ms, age 6 ms (min 6 ms), reaction 16 ms'
    >>> figures_text(ChainFigures(why_undecided="T is starved"), "ms")
    'undecided: T is starved'
    """
    if f.first_use is None:
        return f"undecided: {f.why_undecided}"
    return (f"first use {human(f.first_use, unit)}, age {human(f.age, unit)} "
            f"(min {human(f.age_min, unit)}), reaction {human(f.reaction, unit)}")


def render_chains(chains: Sequence[ChainReport], unit: str, processors: bool) -> list[str]:
    """The chains' table: a row per chain and platform (``processors``: the skeleton's
    processors were analyzed; else every task had a processor of its own)."""
    if not chains:
        return []
    rows, why = [], []
    for c in chains:
        name = " -> ".join(c.tasks)
        platforms = [("on its processors", c.on_processors)] if processors else []
        platforms.append(("with a processor per task", c.processor_per_task))
        for i, (where, f) in enumerate(platforms):
            if f.first_use is None:
                why.append(f"{name} {where}: {f.why_undecided}")
            rows.append([name if i == 0 else "", where,
                         *(human(x, unit) if x is not None else "undecided"
                           for x in (f.first_use, f.age, f.age_min, f.reaction))])
    lines = ["", "latency of each chain (spec §4c; the published bounds over any phases are "
                 "in the design section):",
             tabulate(rows, headers=["chain", "figures", "first use", "age", "age min",
                                     "reaction"], disable_numparse=True),
             CHAIN_FIGURES_MEANING]
    lines += [f"undecided: {w}" for w in why]
    return lines
