"""Text and JSON of an exploration (``tegraph explore``): the space, the search, the front.

The text ends with the verdict; the JSON document is ``report: "explore"``
(``docs/report.schema.json``, ``$defs/explore``).
"""

from __future__ import annotations

from typing import Any

from tabulate import tabulate

from maxplus.scalar import display_text

from ..design.explore import PRUNING_RULES, Exploration
from ..design.explore.evaluate import ANALYZED, FAILED, PRUNED, rejection
from ..design.explore.objectives import Constraints

__all__ = ["FRONT_ROWS_SHOWN", "column_name", "render_exploration"]

FRONT_ROWS_SHOWN = 40


def column_name(name: str, unit: str) -> str:
    """What an objective's column holds, with its unit: the text report's header.

    Every objective is read on processors (spec §4b, §4c): each name says so.

    >>> column_name("latency:A,B", "ms"), column_name("period", "ms")
    ('latency A,B (ms, on processors)', 'period ratio on processors')
    """
    key, _, chain = name.partition(":")
    if chain:
        return f"{key} {chain} ({unit}, on processors)"
    return _COLUMNS[name]


_CHAIN_MEANING = {"latency": "first use (from a sample to the first output computed from it)",
                  "age": "age (how old the sample an output uses is when it is posted)",
                  "reaction": "reaction (from a sensor change to the first output that "
                              "reflects it)"}
_COLUMNS = {"period": "period ratio on processors", "load": "busiest load on processors",
            "utilization": "utilization on processors", "processors": "processors used",
            "traffic": "links across processors", "busiest": "busiest demand (§4 periods)"}
_MEANING = {
    "period": "largest task period on processors over the task's designed period (its own "
              "clock's, or its input group's fastest): 1 designed rate, 2 twice slower",
    "load": "the busiest processor's utilization, sum of C/T with T each task's period on "
            "processors",
    "utilization": "sum of C/T over all processors, T on processors (what a faster loop "
                   "costs anywhere)",
    "processors": "how many processors the design uses",
    "traffic": "how many links join tasks on different processors (each listed below the "
               "front with its delay, spec §4d)",
    "busiest": "the busiest processor's demand, sum of C/T with T each task's period of "
               "spec §4 (what the placement asks; defined also where the schedule is "
               "undecided)",
}


def render_exploration(result: Exploration, all_ties: bool = False) -> str:
    """The exploration as text, ending with its verdict.

    Parameters
    ----------
    result : Exploration
    all_ties : bool
        List every design of the front. By default the front shows one row per
        distinct objective vector (its first design by variant number) with the number
        of designs that share it (``ties``); the JSON report and the results file
        hold every design.

    Returns
    -------
    str
    """
    space = result.space
    sk = space.skeleton
    lines = [f"explore {sk.name}: {result.space.size:,} variant(s) "
             f"({len(space.links)} link(s), {len(space.clocks)} clock(s) chosen"
             + ("" if (a := space.allocation) is None else
                f"; {len(a.free)} {a.mode[:-1]}(s) placed on {', '.join(a.offered)}, "
                f"{space.n_allocation_variants:,} allocation(s) up to renaming of "
                f"interchangeable processors")
             + ")"]
    for c in space.links:
        lines.append(f"  link {c.label}: {', '.join(p.value for p in c.protocols)}"
                     + (" (narrowed by `links`; `all_links` gives the other links every "
                        "protocol not forbidden)" if c.narrowed else "")
                     + (f" (not SYN/SYN: its delay of {display_text(c.delay)} {sk.unit}, "
                        "spec §4d)" if c.delay else ""))
    for k in space.clocks:
        # Decimals as the user wrote them (5.43, 2.715), a fraction only when one does not
        # terminate; the JSON report keeps its exact strings.
        lines.append(f"  clock {k.name}: " + ", ".join(f"{display_text(t)}" for t in k.periods)
                     + f" {sk.unit}")
    lines.append("objectives, all minimized (ties broken by fewer Rule 2 findings):")
    for n in space.objectives:
        key, _, chain = n.partition(":")
        meaning = (f"the chain's {_CHAIN_MEANING[key]} in {sk.unit} on processors, exact for "
                   "the declared phases (spec §4c; a variant where it is undecided is "
                   "rejected, never ranked by a bound)" if chain else _MEANING[n])
        lines.append(f"  {column_name(n, sk.unit)}: {meaning}")
    constraints = _constraint_texts(space.constraints, sk.unit)
    if constraints:
        lines.append("constraints: " + "; ".join(constraints))
    d = result.to_dict()
    optimum = ("" if result.local_optimum_at is None else
               f"; first Pareto local optimum after {result.local_optimum_at:,} analyses")
    lines.append(f"search: {d['search']['description']}; stopped: {result.stopped}{optimum}")
    lines.append(f"judged {len(result.results):,} of {space.size:,}: "
                 f"{result.count(ANALYZED):,} analyzed "
                 f"(analyze, port repair, rule C or the schedule on processors within "
                 f"`max_events` = {space.max_events:,} event firings), "
                 f"{result.count(PRUNED):,} pruned by rules A and B, "
                 f"{result.count(FAILED):,} failed; {result.consistent:,} live and consistent "
                 f"with a processor per task, {result.kept:,} also schedulable on processors"
                 + (" and meeting the constraints" if space.constraints else "") + " (kept)")
    rejected = result.rejected
    if rejected:
        examples = _examples(result)
        lines.append(f"rejected: {sum(rejected.values()):,} variant(s), by the first reason "
                     "met (every variant's own reason is in the -o file):")
        lines.extend(f"  {n:,} {why}" + (f", e.g. variant {examples[why]}" if why in examples
                                          else "") for why, n in rejected.items())
    per = result.log.seconds_per_variant
    lines.append(f"engine: {result.log.engine}"
                 + (f" at {result.log.address}" if result.log.address else "")
                 + f", {result.log.workers} worker(s), {result.log.batches} batch(es)"
                 + (f", {per * 1000:.1f} ms per variant" if per else "")
                 + f"; {result.seconds:.1f} s in all")
    if result.output:
        lines.append(f"results: {result.output}"
                     + (f" ({result.resumed:,} verdict(s) resumed from it)" if result.resumed
                        else ""))
    lines.append("")
    lines.extend(_front(result, all_ties))
    lines.append("")
    lines.append("pruning rules (proofs in tegraph/design/explore/prune.py and "
                 "docs/explore.md):")
    lines.extend(f"  {rule}" for rule in PRUNING_RULES)
    lines.extend(f"note: {n}" for n in result.notes)
    lines.append(f"verdict: {result.verdict}")
    return "\n".join(lines) + "\n"


def _front(result: Exploration, all_ties: bool) -> list[str]:
    space = result.space
    if not result.front:
        return ["Pareto front: empty (no variant is live, consistent and schedulable on its "
                "processors)"]
    names = {c.label: f"L{i + 1}" for i, c in enumerate(space.links)}
    groups = result.distinct_front
    tied = len(result.front) - len(groups)
    if not tied:
        head = ""
    elif all_ties:
        head = (f" in {len(groups)} distinct objective vector(s): designs of equal objectives "
                "are all listed (ties: how many share the row's)")
    else:
        head = (f" in {len(groups)} distinct objective vector(s): one row each, its first "
                f"design by variant number; ties: how many designs share its objectives "
                f"({tied} not listed: --all-ties lists them)")
    lines = [f"Pareto front: {len(result.front)} design(s){head}"]
    lines.extend(f"  L{i + 1} = {c.label}" for i, c in enumerate(space.links))
    shown = [(r, len(g)) for g in groups for r in (g if all_ties else g[:1])]
    rows = []
    for r, ties in shown[:FRONT_ROWS_SHOWN]:
        e = result.entry(r)
        # The clocks and objectives from their exact values, not the entry's JSON texts.
        cells: list[Any] = [r.variant, *e["links"].values(),
                            *(display_text(t) for t in space.periods(r.variant)),
                            *e.get("processors", {}).values()]
        for n in space.objectives:
            value = display_text(r.objectives.get(n)) or "-"
            if n in e["kinds"]:
                value += f" {e['kinds'][n]}"
            cells.append(value)
        cells.append("" if r.rule2 is None else r.rule2)
        cells.append("yes" if r.repaired else "")
        if tied:
            cells.append(ties)
        rows.append(cells)
    headers = ["variant", *names.values(), *(f"{c.name} ({space.skeleton.unit})"
                                             for c in space.clocks),
               *(f"on {unit}" for unit in space.placement(0)),
               *(column_name(n, space.skeleton.unit) for n in space.objectives),
               "Rule 2", "repaired", *(["ties"] if tied else [])]
    # No number parsing: tabulate would print 1038412611.331 as a rounded float (1.03841e+09).
    lines.extend("  " + row for row in tabulate(rows, headers=headers,
                                                disable_numparse=True).splitlines())
    if len(shown) > FRONT_ROWS_SHOWN:
        lines.append(f"  ... and {len(shown) - FRONT_ROWS_SHOWN} more rows (the JSON "
                     "report and the results file hold every design)")
    if space.allocation is not None:  # the traffic of each row: which links, what delay
        unit = space.skeleton.unit
        for r, _ in shown[:FRONT_ROWS_SHOWN]:
            across = result.entry(r)["crossing"]
            lines.append(f"  variant {r.variant}: across processors: " + (", ".join(
                f"{c['link']} (delay {c['delay']} {unit})" for c in across) or "no link"))
    return lines


def _constraint_texts(constraints: Constraints, unit: str) -> list[str]:
    """Each constraint in words, its numbers as the user wrote them (``<= 9.2 ms``)."""
    return ([f"{t}.period {op} {display_text(v)} {unit}" for t, op, v in constraints.periods]
            + [f"latency {','.join(c)} on processors <= {display_text(v)} {unit}"
               for c, v in constraints.latencies]
            + [f"no {p.value} link" for p in constraints.forbidden])


def _examples(result: Exploration) -> dict[str, str]:
    """For each reason of rejection, the first variant rejected for it and its reason."""
    out: dict[str, str] = {}
    for v in sorted(result.results):
        r = result.results[v]
        why = rejection(r)
        if why is not None and why not in out:
            out[why] = f"{v}: {r.reason}" if r.reason else str(v)
    return out
