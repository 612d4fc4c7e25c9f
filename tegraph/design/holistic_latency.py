"""A chain's latency over any phases on a distributed design, by holistic analysis.

The windows of :func:`tegraph.design.holistic.holistic_analysis` (Tindell and Clark
[1]_: every periodic task's release window and response bound, its release jitter
inherited along the links) bound a chain's latency for any phases of its groups'
clocks relative to one another, as Davare et al.'s ``Σ (T + R)`` [2]_ does with a
response ``R`` per task.

**A chain's latency over any phases** (:func:`holistic_latency`). Cut the chain
``[T1, ..., Tn]`` where a task reads the one before without blocking
(ASYN/ASYN, or SYN/ASYN on the reader's side): runs joined by blocking reads are
*segments* of one group. A change of the sensor value just after T1's sample of job
j is first sampled by job j + 1, and job j + 1 of each later task of the segment
reads a message of its writer's job j + 1 or later; the message leaving the segment
is written by ``jλ + off(exit)`` while the sample was taken at ``(j-1)λ + a(entry)``
or later. After a hop of delay ``d`` the first reading job ``m`` of the next segment
reads after the message is visible, while job ``m - 1`` read at or before it. So the
``reaction`` of spec §4c, and the ``age`` and ``first_use`` it bounds, are at most

    Σ_segments (λ_s + off(exit_s) - a(entry_s)) + Σ_hops d_hop,

with ``entry`` the sample (T1's sensor read, or the start of its job) or the read of
the hop, ``exit`` the write to the next segment or the output (the last task's
first unlinked output, or its end). Every term is a difference within one group, so
the bound holds for any phases of the groups relative to one another.

References
----------
.. [1] K. Tindell, J. Clark, "Holistic schedulability analysis for distributed
   hard real-time systems", Microprocessing and Microprogramming 40, 117–134, 1994.
.. [2] A. Davare, Q. Zhu, M. Di Natale, C. Pinello, S. Kanajan,
   A. Sangiovanni-Vincentelli, "Period optimization for hard real-time distributed
   automotive systems", Design Automation Conference (DAC), 2007.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from maxplus.scalar import display_text, exact_text

from ..analysis.analyze import analyze_skeleton
from ..analysis.results import Report
from ..model.platform import link_delay
from ..model.skeleton import Link, Protocol, Skeleton
from ..model.skeleton.checks import KeyPath, Locator, check_chain
from .holistic import (
    HOLISTIC,
    HOLISTIC_ROUNDS,
    GroupWindows,
    Holistic,
    TaskWindow,
    holistic_analysis,
    not_periodic,
)

__all__ = ["FORMULA", "HolisticLatency", "holistic_latency"]

_BLOCKING_READ = (Protocol.ASYN_SYN, Protocol.SYN_SYN)


@dataclass
class HolisticLatency:
    """A chain's latency bound over any phases, by the holistic analysis.

    ``name``, ``value``, ``formula`` and ``note`` are those of a published bound
    (:class:`tegraph.design.latency.Bound`); ``value`` bounds the chain's
    ``reaction`` on processors (spec §4c), and so its ``age`` and ``first_use``.

    Attributes
    ----------
    name : str
    value : Fraction or None
        None where the analysis does not apply or has no fixed point (``note`` says
        why).
    formula, note : str
    segments : list of dict
        Each segment's tasks, period, entry and exit events and term.
    windows : dict of str to TaskWindow
        The chain's tasks' windows and responses.
    """

    name: str
    value: Fraction | None
    formula: str
    note: str
    segments: list[dict[str, Any]] = field(default_factory=list)
    windows: dict[str, TaskWindow] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """Exact strings, as the JSON report holds a bound."""
        return {"name": self.name, "value": exact_text(self.value), "formula": self.formula,
                "note": self.note,
                "segments": [{**s, "period": exact_text(s["period"]),
                              "term": exact_text(s["term"])} for s in self.segments],
                "tasks": [w.to_dict() for w in self.windows.values()]}


FORMULA = ("sum over the segments (runs joined by blocking reads) of (T + latest exit - "
           "earliest entry), plus the delays of the non-blocking hops between them")


def holistic_latency(skeleton: Skeleton, chain: Sequence[str], report: Report | None = None,
                     *, path: KeyPath = ("chain",), budget: int | None = None,
                     rounds: int = HOLISTIC_ROUNDS, analysis: Holistic | None = None
                     ) -> HolisticLatency:
    """A bound on a chain's latency on processors that holds for any phases of its groups.

    Parameters
    ----------
    skeleton : Skeleton
    chain : sequence of str
        Task names, sensor first; each reads an output of the one before (the
        first link in the file from one to the next is followed, spec §4c).
    report : Report, optional
        ``analyze_skeleton(skeleton)`` (computed when not given).
    path : KeyPath
        Where the chain came from, for the message of a refused chain
        (``("chains", i)`` for the file's, ``("chain", i)`` for one given).
    budget, rounds : int
        As for :func:`holistic_analysis`.
    analysis : Holistic, optional
        :func:`holistic_analysis` of the skeleton (or of the chain's parts), when
        known: several chains share it.

    Returns
    -------
    HolisticLatency
        ``value`` bounds the chain's ``reaction`` on processors (spec §4c), hence
        its ``age`` and ``first_use``, over the periodic regime, for any phases of
        the groups' clocks relative to one another; None with the reason in
        ``note`` where a task of the chain is not in a live, rate-consistent,
        clocked group, or the analysis has no fixed point.

    Raises
    ------
    SkeletonError
        The chain names an unknown task, a task twice, or two unlinked tasks.

    See Also
    --------
    tegraph.design.holistic.holistic_analysis : the windows the bound is made of.
    tegraph.design.latency.chain_latency : the exact figures it is reported beside.

    Notes
    -----
    The reasoning is in the module's docstring. With every task alone on its
    processor it is Davare et al.'s ``Σ (T + R)`` [1]_ with each ``R`` a latest end
    in its group's daters; with sharing, the responses carry the jitter the chain's
    own predecessors hand on.

    References
    ----------
    .. [1] A. Davare, Q. Zhu, M. Di Natale, C. Pinello, S. Kanajan,
       A. Sangiovanni-Vincentelli, "Period optimization for hard real-time
       distributed automotive systems", Design Automation Conference (DAC), 2007.
    .. [2] K. Tindell, J. Clark, "Holistic schedulability analysis for distributed
       hard real-time systems", Microprocessing and Microprogramming 40, 117–134,
       1994.

    Examples
    --------
    The design of :func:`holistic_analysis`'s example, from S's sample (its start,
    at the tick or later) to A's end: one segment of period 10, the next sample
    at most 10 later, A's end at most 7 after its tick: 17 ms.

    >>> sk = Skeleton.from_dict({"tasks": {
    ...   "S": {"duration": 1, "period": 10, "outputs": ["x"], "processor": "cpu1"},
    ...   "M": {"duration": 2, "inputs": ["x"], "outputs": ["y"], "processor": "can",
    ...         "priority": 2},
    ...   "N": {"duration": 3, "period": 10, "processor": "can", "priority": 1},
    ...   "A": {"duration": 1, "inputs": ["y"], "processor": "cpu2"}},
    ...   "processors": {"can": {"preemptive": False}},
    ...   "links": [{"from": "S:x", "to": "M:x", "protocol": "ASYN/SYN"},
    ...             {"from": "M:y", "to": "A:y", "protocol": "ASYN/SYN"}]})
    >>> b = holistic_latency(sk, ["S", "M", "A"])
    >>> b.name, b.value
    ('holistic analysis (Tindell and Clark 1994)', Fraction(17, 1))
    """
    in_file = skeleton.source if path[:1] == ("chains",) else None
    chain = list(check_chain(skeleton, list(chain), path, Locator(file=in_file)))
    if report is None:
        report = analyze_skeleton(skeleton)
    for t in chain:
        why = not_periodic(report.groups[report.tasks[t].group])
        if why is not None:
            return HolisticLatency(HOLISTIC, None, FORMULA, f"{t}: {why}")
    if analysis is None:
        analysis = holistic_analysis(skeleton, report, tasks=chain, budget=budget,
                                     rounds=rounds)
    if analysis.why is not None:
        return HolisticLatency(HOLISTIC, None, FORMULA, analysis.why)
    windows = analysis.windows
    links = [_first_link(skeleton, a, b) for a, b in zip(chain, chain[1:], strict=False)]
    cuts = [i + 1 for i, link in enumerate(links) if link.protocol not in _BLOCKING_READ]
    starts = [0, *cuts]
    ends = [*cuts, len(chain)]
    total = Fraction(0)
    segments = []
    for s, (lo, hi) in enumerate(zip(starts, ends, strict=True)):
        tasks = chain[lo:hi]
        grp = analysis.groups[report.tasks[tasks[0]].group]
        if s == 0:
            entry_name, entry = _sample(skeleton, grp, tasks[0], _sensor(skeleton, tasks[0]))
        else:
            entry_name, entry = _sample(skeleton, grp, tasks[0], links[lo - 1].reader[1])
        if hi < len(chain):
            port = links[hi - 1].writer
            exit_e = grp.port_event[port]
            exit_name, exit_off = grp.names[exit_e], grp.latest_of(windows)[exit_e]
        else:
            out = _output(skeleton, tasks[-1])
            if out is None:
                w = windows[tasks[-1]]
                exit_name, exit_off = f"end of {tasks[-1]}", w.earliest + w.response
            else:
                exit_e = grp.port_event[tasks[-1], out]
                exit_name, exit_off = grp.names[exit_e], grp.latest_of(windows)[exit_e]
        term = grp.period + exit_off - entry
        total += term
        segments.append({"tasks": tasks, "group": grp.index, "period": grp.period,
                         "from": entry_name, "to": exit_name, "term": term})
    delays = [link_delay(skeleton, links[i - 1]) for i in cuts]
    total += sum(delays, Fraction(0))
    unit = skeleton.unit
    note = (f"bounds the reaction (and the age and first use) over any phases; "
            f"{len(segments)} segment(s)"
            + (f", hop delays {' + '.join(display_text(d) for d in delays)} {unit}"
               if any(delays) else "")
            + "; T: the segment's group period; offsets from the holistic windows")
    return HolisticLatency(HOLISTIC, total, FORMULA, note, segments,
                           {t: windows[t] for t in chain})


def _first_link(sk: Skeleton, writer: str, reader: str) -> Link:
    return next(x for x in sk.links if x.writer[0] == writer and x.reader[0] == reader)


def _sensor(sk: Skeleton, task: str) -> str | None:
    linked = {x.reader for x in sk.links}
    return next((p for p in sk.tasks[task].inputs if (task, p) not in linked), None)


def _output(sk: Skeleton, task: str) -> str | None:
    linked = {x.writer for x in sk.links}
    return next((p for p in sk.tasks[task].outputs if (task, p) not in linked), None)


def _sample(sk: Skeleton, grp: GroupWindows, task: str, port: str | None) -> tuple[str, Fraction]:
    """The event a non-blocking read (or the sample of a task without a sensor) happens
    at, by spec §4c, and its earliest offset: the job's start (no earlier than its
    release) when the read comes after every blocking read, else its own event."""
    inputs = list(sk.tasks[task].inputs)
    blocking = {x.reader[1] for x in sk.links
                if x.reader[0] == task and x.protocol in _BLOCKING_READ}
    if port is None or not any(q in blocking for q in inputs[inputs.index(port) + 1:]):
        return f"start of {task}", grp.lower[grp.compute[task]]
    e = grp.port_event[task, port]
    return grp.names[e], grp.lower[e]
