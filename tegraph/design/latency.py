"""Sensor-to-actuator latency of a chain of tasks.

A chain ``[T1, ..., Tn]`` (spec §6 ``chains:``, or the ``chains`` argument of
:func:`tegraph.analyze`)
follows the data: each task reads an output of the one before. The latency
of the data sampled by T1 is measured from T1's reading of its sensor (its
first unlinked input; the start of its computation if it has none) to Tn's
posting of its actuator output (its first unlinked output; the end of its
computation if it has none).

The chain is cut into *segments*, runs of consecutive tasks of one
synchronized group. Inside a segment the latency is **exact**: the data read
at a task's k-th activation is the last message posted at or before that
read, so tracing an actuator output back through the steady-state daters of
the timed event graph (spec §3) gives the age of the sensor value it used (a message posted
at the very instant of the read counts only when the protocol orders the
two: the k-th write of an ASYN/SYN or SYN/SYN link comes before the k-th
read, the k-th write of a SYN/ASYN link after it; for ASYN/ASYN the worst
case, not yet posted, is taken);
the worst age over one cyclicity of the periodic regime (spec §4
``transient``) is the steady-state worst case. This is the timed event
graph's view: every task runs as soon as its places allow (no processor
contention). It needs a rate-consistent group.

Between segments (an ASYN/ASYN hop between groups) nothing relates the two
clocks, and the published bounds for register communication apply, each
segment s standing for one periodic task of period ``T_s`` (its group's
period) and response time ``R_s`` (the Joseph-Pandya response time [1]_ of
its group on its processor, :mod:`tegraph.design.schedulability`):

- **Davare et al. 2007** [2]_: ``L <= Σ_s (T_s + R_s)``;
- **Dürr et al. 2019** [3]_: the term of a segment followed, on the same
  processor, by a segment of strictly lower priority shrinks to
  ``T_s + max(R_s - T_{s+1}, 0)``.

Both bound the time from a change of the sensor value to the actuator output
that reflects it, one sampling period of T1 included. The daters inside a
segment are those of the (max,+) model of the timed event graph [4]_.

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
.. [4] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
   and Linearity*, Wiley, 1992.
"""

from __future__ import annotations

import bisect
import itertools
from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from maxplus.scalar import exact_text

from ..analysis.analyze import analyze_skeleton
from ..analysis.results import Report
from ..model.build import build_teg
from ..model.elements import LinkLabel
from ..model.skeleton import Link, Protocol, Skeleton
from ..model.skeleton.checks import KeyPath, Locator, check_chain
from .schedulability import Schedulability, schedulability

__all__ = ["Bound", "ChainLatency", "Hop", "Segment", "chain_latency", "parse_chain"]

DAVARE = "Davare et al. 2007"
DUERR = "Dürr et al. 2019"
_MAX_FIRINGS = 1 << 15


@dataclass
class Segment:
    """Consecutive tasks of the chain in one synchronized group."""

    tasks: list[str]
    group: int
    start: str
    """Event where the segment's data enters (a read, or a compute)."""
    end: str
    """Event where it leaves (a write, or the end of a computation)."""
    period: Fraction | None
    latency: Fraction | None
    """Exact worst steady-state latency from ``start`` to ``end``."""
    note: str = ""


@dataclass
class Hop:
    """An asynchronous hop between two segments."""

    writer: str
    reader: str
    links: list[LinkLabel]


@dataclass
class Bound:
    """A published bound on the end-to-end latency."""

    name: str
    value: Fraction | None
    formula: str
    note: str = ""


@dataclass
class ChainLatency:
    """Latency of one chain: exact inside groups, bounded across asynchronous hops."""

    chain: list[str]
    segments: list[Segment]
    hops: list[Hop]
    bounds: list[Bound] = field(default_factory=list)

    @property
    def exact(self) -> Fraction | None:
        """The exact latency when the whole chain is one synchronized segment."""
        return self.segments[0].latency if len(self.segments) == 1 else None

    @property
    def value(self) -> Fraction | None:
        """The exact latency, else the smallest bound (None when none applies)."""
        if len(self.segments) == 1:
            return self.exact
        values = [b.value for b in self.bounds if b.value is not None]
        return min(values) if values else None

    @property
    def kind(self) -> str:
        """``"exact"`` or ``"bound"``."""
        return "exact" if len(self.segments) == 1 else "bound"

    @property
    def in_periods(self) -> Fraction | None:
        """:attr:`value` over the sampling period (the period of T1's group)."""
        period = self.segments[0].period
        return None if self.value is None or not period else self.value / period

    def to_dict(self) -> dict[str, Any]:
        """The chain's latency as the JSON report holds it."""
        return {
            "chain": self.chain, "latency": exact_text(self.value), "kind": self.kind,
            "periods": exact_text(self.in_periods),
            "segments": [{"tasks": s.tasks, "group": s.group, "from": s.start, "to": s.end,
                          "period": exact_text(s.period), "latency": exact_text(s.latency),
                          "note": s.note} for s in self.segments],
            "hops": [{"from": h.writer, "to": h.reader,
                      "links": [link.document() for link in h.links]} for h in self.hops],
            "bounds": [{"name": b.name, "value": exact_text(b.value), "formula": b.formula,
                        "note": b.note} for b in self.bounds],
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
                  sched: Schedulability | None = None, path: KeyPath = ("chain",)
                  ) -> ChainLatency:
    """Latency of ``chain``: exact inside synchronized groups, bounded across hops.

    Parameters
    ----------
    skeleton : Skeleton
        The tasks, links, clocks and threads of the controller.
    chain : sequence of str
        Task names, sensor first; each reads an output of the one before.
    report : Report, optional
        ``analyze_skeleton(skeleton)`` (computed when not given).
    sched : Schedulability, optional
        ``schedulability(skeleton, report)`` for the bounds (computed when needed).
    path : KeyPath
        Where the chain came from, for the message of a refused chain.

    Returns
    -------
    ChainLatency
        The segments (one per synchronized group crossed, each with its exact
        steady-state worst latency), the hops between them and, when there is
        more than one segment, the Davare [2]_ and Dürr [3]_ bounds.

    Raises
    ------
    SkeletonError
        The chain names an unknown task, a task twice, or two consecutive
        tasks with no link between them.

    See Also
    --------
    parse_chain : a chain from ``"A,B,C"``.
    tegraph.design.schedulability.schedulability : the response times ``R_s``.
    tegraph.analysis.analyze.analyze_skeleton : the report the segments use.

    Notes
    -----
    Inside a segment the latency is exact: the steady-state daters of the
    timed event graph [4]_ are traced back over one cyclicity. Across an
    ASYN/ASYN hop each segment stands for one periodic task of period
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
    .. [4] F. Baccelli, G. Cohen, G. J. Olsder, J.-P. Quadrat, *Synchronization
       and Linearity*, Wiley, 1992.

    Examples
    --------
    The synchronized pipeline of Figure 4 (durations 1, 2, 2, 1; period 10):
    q is read at 0 and u posted at 6, within one period.

    >>> from tegraph import load_skeleton
    >>> sk = load_skeleton("examples/fig4_pipeline_synchronized.yaml")
    >>> r = chain_latency(sk, ["MT1", "MT2", "MT3", "MT4"])
    >>> r.kind, r.value, r.in_periods
    ('exact', Fraction(6, 1), Fraction(3, 5))
    """
    # A chain of the file is located in it; one given as a parameter is not.
    in_file = skeleton.source if path[:1] == ("chains",) else None
    chain = list(check_chain(skeleton, list(chain), path, Locator(file=in_file)))
    if report is None:
        report = analyze_skeleton(skeleton)
    pieces: list[list[str]] = []
    for t in chain:
        if pieces and report.tasks[t].group == report.tasks[pieces[-1][-1]].group:
            pieces[-1].append(t)
        else:
            pieces.append([t])
    hops = [Hop(a[-1], b[0], [link.label for link in _links(skeleton, a[-1], b[0])])
            for a, b in itertools.pairwise(pieces)]
    segments = []
    for s, tasks in enumerate(pieces):
        start = _sensor(skeleton, tasks[0]) if s == 0 else \
            ("read", tasks[0], _links(skeleton, pieces[s - 1][-1], tasks[0])[0].reader[1])
        end = _actuator(skeleton, tasks[-1]) if s == len(pieces) - 1 else \
            ("write", tasks[-1], _links(skeleton, tasks[-1], pieces[s + 1][0])[0].writer[1])
        segments.append(_segment(skeleton, report, tasks, start, end))
    result = ChainLatency(chain, segments, hops)
    if len(segments) > 1:
        if sched is None:
            sched = schedulability(skeleton, report)
        result.bounds = _bounds(segments, sched, skeleton.unit)
    return result


def _links(sk: Skeleton, writer: str, reader: str) -> list[Link]:
    return [link for link in sk.links if link.writer[0] == writer and link.reader[0] == reader]


def _linked(sk: Skeleton, task: str, port: str) -> bool:
    return any((task, port) in (link.writer, link.reader) for link in sk.links)


def _sensor(sk: Skeleton, task: str) -> tuple[str, str, str]:
    free = [p for p in sk.tasks[task].inputs if not _linked(sk, task, p)]
    return ("read", task, free[0]) if free else ("compute", task, "")


def _actuator(sk: Skeleton, task: str) -> tuple[str, str, str]:
    free = [p for p in sk.tasks[task].outputs if not _linked(sk, task, p)]
    return ("write", task, free[0]) if free else ("end", task, "")


def _event_name(ref: tuple[str, str, str]) -> str:
    kind, task, port = ref
    return {"read": f"{task}.read:{port}", "write": f"{task}.write:{port}",
            "compute": f"{task}.compute", "end": f"{task}.compute + duration"}[kind]


def _segment(sk: Skeleton, report: Report, tasks: list[str], start: tuple[str, str, str],
             end: tuple[str, str, str]) -> Segment:
    g = report.groups[report.tasks[tasks[0]].group]
    seg = Segment(tasks, g.index, _event_name(start), _event_name(end), g.period, None)
    if not g.rate_consistent or g.transient is None:
        seg.note = ("the group is not live" if not g.live else
                    "the group is not rate-consistent: no steady state to measure"
                    if not g.rate_consistent else
                    "the analysis did not reach the periodic regime (raise `max_steps`)")
        return seg
    seg.latency = _steady_latency(sk, g.tasks, tasks, start, end, g.transient, g.period)
    if seg.latency is None:  # pragma: no cover - the firing budget is far above any example
        seg.note = f"the trace did not settle within {_MAX_FIRINGS} activations"
    return seg


def _steady_latency(sk: Skeleton, group: list[str], tasks: list[str], start, end,
                    transient: tuple[int, int], period) -> Fraction | None:
    """Worst data age over one cyclicity of the regime, from the group's daters."""
    teg = build_teg(sk.restricted_to(group))
    port_event = {pt: e for e, attrs in enumerate(teg.transition_attrs)
                  for pt in attrs.get("ports", ())}
    compute = teg.attrs["compute"]

    def event(ref) -> tuple[int, Fraction]:
        kind, task, port = ref
        if kind in ("read", "write"):
            return port_event[task, port], Fraction(0)
        return compute[task], Fraction(0) if kind == "compute" else sk.tasks[task].duration

    causal = (Protocol.ASYN_SYN, Protocol.SYN_SYN)  # write k happens before read k
    hops = [[(port_event[link.writer], port_event[link.reader], link.protocol in causal)
             for link in _links(sk, a, b)] for a, b in itertools.pairwise(tasks)]
    (start_e, start_d), (end_e, end_d) = event(start), event(end)
    K, c = transient
    n = 2 * (K + c) + 4 * len(tasks) + 8
    while n <= _MAX_FIRINGS:
        daters = teg.simulate(n)
        col = {e: daters.times[:, e].tolist() for e in
               {start_e, end_e, *(x for hop in hops for w, r, _ in hop for x in (w, r))}}
        worst = _worst_age(col, hops, len(tasks), (start_e, start_d), (end_e, end_d),
                           transient, n, daters.scale)
        if worst is not None:
            return worst
        n *= 2
    return None  # pragma: no cover


def _worst_age(col, hops, n_tasks: int, start: tuple[int, Fraction], end: tuple[int, Fraction],
               transient: tuple[int, int], n: int, scale: int) -> Fraction | None:
    """The worst data age over one cyclicity in the middle of ``n`` simulated firings;
    None when the trace leaves the simulated steady state (or no sample reaches the end)."""
    (start_e, start_d), (end_e, end_d) = start, end
    K, c = transient
    worst = None
    for m in range(n // 2, n // 2 + c):
        oldest = _oldest(col, hops, n_tasks - 1, m, start_e, K, n)
        if oldest is False:
            return None
        if oldest is None:
            continue
        age = Fraction(col[end_e][m - 1], scale) + end_d - Fraction(oldest, scale) - start_d
        worst = age if worst is None else max(worst, age)
    return worst


def _oldest(col, hops, i: int, k: int, start_e: int, K: int, n: int):
    """Earliest start time (scaled) of the data used by activation k of task i.

    None when the data is the initial value of a port (no sample); False when
    the trace leaves the simulated steady state (simulate further).
    """
    if k < K or k > n:
        return False
    if i == 0:
        return col[start_e][k - 1]
    best = None
    for w, r, causal in hops[i - 1]:
        read = col[r][k - 1]
        # Daters are non-decreasing: j writes come strictly before the read...
        j = bisect.bisect_left(col[w], read)
        if j >= n:
            return False
        # ...and the k-th one also when the protocol puts it first at a tie.
        if causal and col[w][k - 1] <= read:
            j = max(j, k)
        if j == 0:
            continue
        found = _oldest(col, hops, i - 1, j, start_e, K, n)
        if found is False:
            return False
        if found is not None:
            best = found if best is None else min(best, found)
    return best


def _bounds(segments: list[Segment], sched: Schedulability, unit: str) -> list[Bound]:
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
    if why:
        reason = "; ".join(dict.fromkeys(why))
        return [Bound(DAVARE, None, formula_davare, reason),
                Bound(DUERR, None, formula_duerr, reason)]
    davare = sum((T + R for T, R, _ in terms), Fraction(0))
    duerr = Fraction(0)
    for i, (T, R, (proc, prio)) in enumerate(terms):
        if i + 1 < len(terms) and terms[i + 1][2][0] == proc and terms[i + 1][2][1] < prio:
            duerr += T + max(R - terms[i + 1][0], Fraction(0))
        else:
            duerr += T + R
    return [Bound(DAVARE, davare, formula_davare, note), Bound(DUERR, duerr, formula_duerr, note)]


