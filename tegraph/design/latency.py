"""A chain's latency in the design tools: the exact figures, and the published bounds
over any phases beside them.

A chain ``[T1, ..., Tn]`` (spec §1 ``chains:``, or the ``chains`` argument of
:func:`tegraph.analyze`) follows the data: each task reads an output of the
one before. Its latency is the analysis' (spec §4c,
:mod:`tegraph.analysis.chains`): ``first_use``, ``age``, ``age_min`` and
``reaction``, exact for the declared phases of the clocks, on the skeleton's
processors and with a processor per task. This module presents them, and
keeps beside them, named "over any phases", the bounds of the literature,
which hold whatever the clocks' phases and never stand in for the exact
figure.

The chain is cut into *segments*, runs of consecutive tasks of one
synchronized group; between segments (an ASYN/ASYN hop between groups) the
published bounds for register communication apply, each segment s standing
for one periodic task of period ``T_s`` (its group's period) and response
time ``R_s`` (the Joseph-Pandya response time [1]_ of its group on its
processor, :mod:`tegraph.design.schedulability`):

- **Davare et al. 2007** [2]_: ``L <= Σ_s (T_s + R_s)``;
- **Dürr et al. 2019** [3]_: the term of a segment followed, on the same
  processor, by a segment of strictly lower priority shrinks to
  ``T_s + max(R_s - T_{s+1}, 0)``;
- **holistic analysis (Tindell and Clark 1994)** [4]_, for a chain whose tasks
  run on more than one (declared) processor: release windows with the jitter
  inherited along the links, each segment's period plus its latest exit less
  its earliest entry, plus the delays of the hops between segments
  (:func:`tegraph.design.holistic_latency.holistic_latency`).

Each bounds the time from a change of the sensor value to the actuator output
that reflects it, one sampling period of T1 included: the exact ``reaction``
on processors (and so its ``age`` and ``first_use``) is at most them where
their assumptions hold. A bound is reported beside the exact figures, never in
their place, and decides nothing.

References
----------
.. [1] M. Joseph, P. Pandya, "Finding response times in a real-time
   system", The Computer Journal 29(5), 390–395, 1986.
.. [2] A. Davare, Q. Zhu, M. Di Natale, C. Pinello, S. Kanajan,
   A. Sangiovanni-Vincentelli, "Period optimization for hard real-time
   distributed automotive systems", Design Automation Conference (DAC),
   2007.
.. [3] M. Dürr, G. von der Brüggen, K.-H. Chen, J.-J. Chen, "End-to-end
   timing analysis of sporadic cause-effect chains in distributed systems",
   ACM Transactions on Embedded Computing Systems 18(5s) (CASES), 2019.
.. [4] K. Tindell, J. Clark, "Holistic schedulability analysis for distributed
   hard real-time systems", Microprocessing and Microprogramming 40, 117–134,
   1994.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from maxplus.scalar import display_text, exact_text

from ..analysis.analyze import analyze_skeleton
from ..analysis.chains import ChainFigures, ChainReport
from ..analysis.results import Report
from ..model.elements import LinkLabel
from ..model.platform import link_delay
from ..model.skeleton import Link, Skeleton
from ..model.skeleton.checks import KeyPath, Locator, check_chain
from .holistic_latency import holistic_latency
from .schedulability import Schedulability, schedulability

__all__ = ["OVER_ANY_PHASES", "Bound", "ChainLatency", "Hop", "Segment", "chain_latencies",
           "chain_latency", "parse_chain"]

DAVARE = "Davare et al. 2007"
DUERR = "Dürr et al. 2019"
OVER_ANY_PHASES = "over any phases"
_HOLISTIC_ROUNDS = 16
# Rounds of the holistic iteration beside the exact figures: where the responses keep
# growing each round costs more (longer busy periods), and a bound is not worth
# every command's time; past them the bound is reported as not applicable, with why.
"""What the published bounds hold for (the exact figures are for the declared phases)."""


@dataclass
class Segment:
    """Consecutive tasks of the chain in one synchronized group."""

    tasks: list[str]
    group: int
    start: str
    """Event where the segment's data enters (a read, or the sensor's)."""
    end: str
    """Event where it leaves (a write, or the output)."""
    period: Fraction | None


@dataclass
class Hop:
    """An asynchronous hop between two segments."""

    writer: str
    reader: str
    links: list[LinkLabel]


@dataclass
class Bound:
    """A published bound on the end-to-end latency, over any phases of the clocks."""

    name: str
    value: Fraction | None
    formula: str
    note: str = ""


@dataclass
class ChainLatency:
    """One chain's latency: the exact figures (spec §4c), and the published bounds over
    any phases beside them (never in their place)."""

    chain: list[str]
    figures: ChainReport
    """The exact figures, on the processors and with a processor per task."""
    segments: list[Segment]
    hops: list[Hop]
    bounds: list[Bound] = field(default_factory=list)

    @property
    def exact(self) -> ChainFigures:
        """The figures on the skeleton's processors (those with a processor per task when
        the analysis gave every task a processor of its own)."""
        return self.figures.on_processors

    @property
    def value(self) -> Fraction | None:
        """The exact first use on processors (spec §4c, the paper's latency); None where
        undecided (:attr:`why_undecided`)."""
        return self.exact.first_use

    @property
    def why_undecided(self) -> str | None:
        """Why the exact figures are null (None where they are decided)."""
        return self.exact.why_undecided

    @property
    def kind(self) -> str:
        """``"exact"``, or ``"undecided"`` where the chain's schedule is not decided."""
        return "exact" if self.exact.decided else "undecided"

    @property
    def in_periods(self) -> Fraction | None:
        """:attr:`value` over the sampling period (the period of T1's group)."""
        period = self.segments[0].period
        return None if self.value is None or not period else self.value / period

    def to_dict(self) -> dict[str, Any]:
        """The chain's latency as the JSON report holds it."""
        return {
            "chain": self.chain, "latency": exact_text(self.value), "kind": self.kind,
            "periods": exact_text(self.in_periods), "why_undecided": self.why_undecided,
            "figures": self.figures.to_dict(),
            "segments": [{"tasks": s.tasks, "group": s.group, "from": s.start, "to": s.end,
                          "period": exact_text(s.period)} for s in self.segments],
            "hops": [{"from": h.writer, "to": h.reader,
                      "links": [link.document() for link in h.links]} for h in self.hops],
            "bounds": [{"name": b.name, "scope": OVER_ANY_PHASES, "value": exact_text(b.value),
                        "formula": b.formula, "note": b.note} for b in self.bounds],
        }


def parse_chain(text: str) -> tuple[str, ...]:
    """``"A,B,C"`` -> ``("A", "B", "C")`` (task names may hold dots, never commas).

    Parameters
    ----------
    text : str
        Comma-separated task names; spaces around a name are dropped.

    Returns
    -------
    tuple of str
        The task names, in order.

    See Also
    --------
    chain_latency : the latency of the parsed chain.

    Examples
    --------
    >>> parse_chain("TG.JS, TF.TT.JS,CO.JS")
    ('TG.JS', 'TF.TT.JS', 'CO.JS')
    """
    return tuple(part.strip() for part in text.split(","))


def chain_latency(skeleton: Skeleton, chain: Sequence[str], report: Report | None = None,
                  sched: Schedulability | None = None, path: KeyPath = ("chain",),
                  figures: ChainReport | None = None) -> ChainLatency:
    """The latency of ``chain``: its exact figures, and the published bounds over any phases.

    Parameters
    ----------
    skeleton : Skeleton
        The tasks, links, clocks and threads of the controller.
    chain : sequence of str
        Task names, sensor first; each reads an output of the one before.
    report : Report, optional
        ``analyze_skeleton(skeleton, ...)``; its ``chains`` give the exact figures
        (computed, on the skeleton's processors, when the report has no such chain).
    sched : Schedulability, optional
        ``schedulability(skeleton, report)`` for the bounds (computed when needed).
    path : KeyPath
        Where the chain came from, for the message of a refused chain.
    figures : ChainReport, optional
        The chain's exact figures, when the caller has them.

    Returns
    -------
    ChainLatency
        The exact figures (:mod:`tegraph.analysis.chains`), the groups the chain
        crosses (segments), the hops between them and, when there is more than one
        segment, the Davare [2]_ and Dürr [3]_ bounds over any phases.

    Raises
    ------
    SkeletonError
        The chain names an unknown task, a task twice, or two consecutive
        tasks with no link between them.

    See Also
    --------
    parse_chain : a chain from ``"A,B,C"``.
    tegraph.analysis.chains.chain_reports : the exact figures.
    tegraph.design.schedulability.schedulability : the response times ``R_s``.

    Notes
    -----
    Across an ASYN/ASYN hop each segment stands for one periodic task of period
    ``T_s`` and Joseph-Pandya response time ``R_s`` [1]_.

    References
    ----------
    .. [1] M. Joseph, P. Pandya, "Finding response times in a real-time
       system", The Computer Journal 29(5), 390–395, 1986.
    .. [2] A. Davare, Q. Zhu, M. Di Natale, C. Pinello, S. Kanajan,
       A. Sangiovanni-Vincentelli, "Period optimization for hard real-time
       distributed automotive systems", Design Automation Conference (DAC),
       2007.
    .. [3] M. Dürr, G. von der Brüggen, K.-H. Chen, J.-J. Chen, "End-to-end
       timing analysis of sporadic cause-effect chains in distributed systems",
       ACM Transactions on Embedded Computing Systems 18(5s) (CASES), 2019.

    Examples
    --------
    The unsynchronized pipeline of Figure 4 on its one processor: 6 ms, exactly, where
    the bounds over any phases say at most 46 and 55 ms.

    >>> from tegraph import load_skeleton
    >>> sk = load_skeleton("examples/fig4_pipeline_unsynchronized.yaml")
    >>> r = chain_latency(sk, ["MT1", "MT2", "MT3", "MT4"])
    >>> r.kind, r.value, r.in_periods, [str(b.value) for b in r.bounds]
    ('exact', Fraction(6, 1), Fraction(3, 5), ['55', '46'])
    """
    return chain_latencies(skeleton, [(tuple(chain), path, figures)], report, sched)[0]


def chain_latencies(skeleton: Skeleton,
                    chains: Sequence[tuple[Sequence[str], KeyPath, ChainReport | None]],
                    report: Report | None = None, sched: Schedulability | None = None
                    ) -> list[ChainLatency]:
    """:func:`chain_latency` of each ``(chain, path, figures)``, the links indexed once."""
    links = _LinkIndex(skeleton)
    return [_chain_latency(skeleton, list(c), path, f, report, sched, links)
            for c, path, f in chains]


class _LinkIndex:
    """The links between each two tasks (file order), and the ports linked."""

    def __init__(self, sk: Skeleton) -> None:
        self.by_pair: dict[tuple[str, str], list[Link]] = {}
        for link in sk.links:
            self.by_pair.setdefault((link.writer[0], link.reader[0]), []).append(link)
        self.linked = {end for link in sk.links for end in (link.writer, link.reader)}


def _chain_latency(skeleton: Skeleton, chain: list[str], path: KeyPath,
                   figures: ChainReport | None, report: Report | None,
                   sched: Schedulability | None, links: _LinkIndex) -> ChainLatency:
    if figures is None or list(figures.tasks) != chain:
        # A chain of the file is located in it; one given as a parameter is not (a chain
        # with its figures was checked by the analysis that made them).
        in_file = skeleton.source if path[:1] == ("chains",) else None
        chain = list(check_chain(skeleton, chain, path, Locator(file=in_file)))
        figures = None
    if figures is None and report is not None:
        figures = next((c for c in report.chains if list(c.tasks) == chain), None)
    if figures is None or report is None:
        # The figures where the report has none: its analysis on the processors, with
        # this chain (the budget of every command's, max_events).
        report = analyze_skeleton(skeleton, processors=True, chains=[chain],
                                  structure=None if report is None else report.structure)
        figures = report.chains[-1]
    by_pair, linked = links.by_pair, links.linked
    pieces: list[list[str]] = []
    for t in chain:
        if pieces and report.tasks[t].group == report.tasks[pieces[-1][-1]].group:
            pieces[-1].append(t)
        else:
            pieces.append([t])
    hops = [Hop(a[-1], b[0], [link.label for link in by_pair[a[-1], b[0]]])
            for a, b in itertools.pairwise(pieces)]
    segments = []
    for s, tasks in enumerate(pieces):
        g = report.groups[report.tasks[tasks[0]].group]
        start = _sensor(skeleton, tasks[0], linked) if s == 0 else \
            f"{tasks[0]}.read:{by_pair[pieces[s - 1][-1], tasks[0]][0].reader[1]}"
        end = _actuator(skeleton, tasks[-1], linked) if s == len(pieces) - 1 else \
            f"{tasks[-1]}.write:{by_pair[tasks[-1], pieces[s + 1][0]][0].writer[1]}"
        segments.append(Segment(tasks, g.index, start, end, g.period))
    result = ChainLatency(chain, figures, segments, hops)
    if len(segments) > 1:
        if sched is None:
            sched = schedulability(skeleton, report)
        # A message is visible its link's delay after its write (§4d): each delay along
        # the chain adds to the bounds, which count processor time only.
        delays = sum((link_delay(skeleton, by_pair[a, b][0])
                      for a, b in itertools.pairwise(chain)), Fraction(0))
        result.bounds = _bounds(segments, sched, skeleton.unit, delays)
    if len({skeleton.tasks[t].runs_on for t in chain}) > 1:
        # Across processors: the holistic bound (its release windows hold for any phases
        # of the groups' clocks relative to one another), a bound like the others; on
        # the chain's parts of the schedule alone, so that another part's overload
        # leaves it standing.
        h = holistic_latency(skeleton, chain, report, path=path, rounds=_HOLISTIC_ROUNDS)
        result.bounds.append(Bound(h.name, h.value, h.formula, f"on its processors; {h.note}"))
    return result


def _sensor(sk: Skeleton, task: str, linked: set[tuple[str, str]]) -> str:
    free = [p for p in sk.tasks[task].inputs if (task, p) not in linked]
    return f"{task}.read:{free[0]}" if free else f"the start of {task}"


def _actuator(sk: Skeleton, task: str, linked: set[tuple[str, str]]) -> str:
    free = [p for p in sk.tasks[task].outputs if (task, p) not in linked]
    return f"{task}.write:{free[0]}" if free else f"the end of {task}"


def _bounds(segments: list[Segment], sched: Schedulability, unit: str,
            delays: Fraction = Fraction(0)) -> list[Bound]:
    # (T, R, (processor, priority)) of each segment; used only when every one is known
    # (else `why` says which is not).
    terms: list[tuple[Fraction, Fraction, tuple[str | None, int]]] = []
    why = []
    for s in segments:
        units = {id(u): u for t in s.tasks if (u := sched.unit_of(t)) is not None}
        u = next(iter(units.values())) if len(units) == 1 else None
        if s.period is None:
            why.append(f"group {s.group} has no steady period")
        if u is None:
            why.append(f"the tasks {', '.join(s.tasks)} are not one scheduling unit")
        elif not u.schedulable or u.response_time is None:
            why.append(f"group {s.group} does not meet its period" if u.bounds is None
                       else f"group {s.group}'s response time is only bounded (budget)")
        elif s.period is not None:
            terms.append((s.period, u.response_time, (u.processor, u.priority)))
    formula_davare = "sum over segments of (T + R)"
    formula_duerr = ("sum over segments of (T + R), or T + max(R - T_next, 0) when the next "
                     "segment runs on the same processor at a lower priority")
    note = "T: period of the segment's group; R: its response time (Joseph-Pandya)"
    if delays:
        formula_davare += ", plus the links' delays (§4d)"
        formula_duerr += ", plus the links' delays (§4d)"
        note += f"; the links' delays along the chain: {display_text(delays)} {unit}"
    if why:
        reason = "; ".join(dict.fromkeys(why))
        return [Bound(DAVARE, None, formula_davare, reason),
                Bound(DUERR, None, formula_duerr, reason)]
    davare = sum((T + R for T, R, _ in terms), delays)
    duerr = delays
    for i, (T, R, (proc, prio)) in enumerate(terms):
        if i + 1 < len(terms) and terms[i + 1][2][0] == proc and terms[i + 1][2][1] < prio:
            duerr += T + max(R - terms[i + 1][0], Fraction(0))
        else:
            duerr += T + R
    return [Bound(DAVARE, davare, formula_davare, note), Bound(DUERR, duerr, formula_duerr, note)]


