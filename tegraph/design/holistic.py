"""Holistic analysis of a distributed design: release jitter inherited along its links.

On several processors a task's jobs are not released at its clock's ticks: a task
that reads a message blocking waits for its writer, whose end moves with what
delays it on its own processor, and a message crosses a link in ``delay`` (spec
§4d). Tindell and Clark [1]_ bound such a system by iterating to a fixed point:
each task's response with the release jitter its predecessors' worst responses
give it, each task's jitter from those responses. Here the predecessors are the
places of the timed event graph (spec §2), so every protocol, thread and delay is
taken as the exact schedule takes it.

**The model.** Take each group that is live, rate-consistent and clocked, with
period ``λ`` (spec §4). Job k of task T is released (``r_T(k) = x_T.compute(k)`` on
processors, §4b) within ``[(k-1)λ + a_T, (k-1)λ + b_T]``: its *window*, of jitter
``J_T = b_T - a_T``.

- ``a_T`` is the earliest offset of the §3 daters, ``min_k x_T.compute(k) - (k-1)λ``
  over the transient and one cyclicity (after it the offsets repeat): a job on
  processors never ends sooner than its duration after its release, and the
  daters are non-decreasing in every holding time, so no release is earlier.
- On its processor T is a periodic task ``(C_T, λ, J_T)`` among the others; its
  response from ``(k-1)λ + a_T`` to its end is at most ``R_T``, the busy-period
  analysis with jitter (:func:`~tegraph.design.busy_period.busy_period_response`:
  Joseph-Pandya with jitter, Tindell's busy period, on a preemptive processor; the
  revised analysis of Davis et al. [2]_ on a non-preemptive one).
- ``b_T`` is the largest offset the graph's places allow when every token that
  leaves a compute event is available at the latest end ``(k-1)λ + a_T' + R_T'`` of
  its task T': the longest paths to each event ``e`` of
  ``off_e = max over places p into e of (off_src + h_p - m_p λ, a_p if m_p >= 1)``,
  with ``a_T' + R_T' - m_p λ`` on a place leaving ``T'.compute``. Cut at every
  compute event, a circuit left holds its §3 holding times, at most ``λ`` per
  token in a rate-consistent group: the longest paths exist. By induction on k,
  ``x_e(k) <= (k-1)λ + off_e`` for every event of the schedule on processors.

Starting from ``R_T = C_T``, the two steps alternate; both are non-decreasing,
and every value lies on the grid of the skeleton's common denominator, so the
iteration either reaches a fixed point or passes its round budget. At the fixed
point the windows and the responses hold for every job, for any phases of the
groups' clocks relative to one another (the least instant at which one of them
failed would need an earlier failure, [1]_).

**What is not periodic.** A group without a clock is free-running, never a
periodic load: a task of it at least as urgent as a periodic one, with work, may
take every instant (the periodic one gets no bound); less urgent, it only blocks on
a non-preemptive processor, by its duration. So does a task of a group that is
not live or not rate-consistent.

A chain's latency over any phases is made of these windows
(:mod:`tegraph.design.holistic_latency`).

References
----------
.. [1] K. Tindell, J. Clark, "Holistic schedulability analysis for distributed
   hard real-time systems", Microprocessing and Microprogramming 40, 117–134, 1994.
.. [2] R. I. Davis, A. Burns, R. J. Bril, J. J. Lukkien, "Controller Area Network
   (CAN) schedulability analysis: refuted, revisited and revised", Real-Time
   Systems 35(3), 239–272, 2007.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from maxplus.scalar import exact_text

from ..analysis.analyze import analyze_skeleton
from ..analysis.results import GroupReport, Report
from ..model.build import build_teg, holding_sources
from ..model.platform import Platform, platform_of, processor_parts
from ..model.skeleton import Skeleton
from .busy_period import busy_period_response

__all__ = ["HOLISTIC", "HOLISTIC_ROUNDS", "GroupWindows", "Holistic", "TaskWindow",
           "holistic_analysis", "not_periodic"]

HOLISTIC = "holistic analysis (Tindell and Clark 1994)"
HOLISTIC_ROUNDS = 1_000
"""Most rounds of the fixed-point iteration (each: every window, then every response)."""

@dataclass(frozen=True)
class TaskWindow:
    """One task's release window and response bound at the fixed point.

    Job k is released within ``[(k-1)λ + earliest, (k-1)λ + latest]`` and ends by
    ``(k-1)λ + earliest + response``.

    Attributes
    ----------
    task, processor : str
    priority : int
    period : Fraction
        ``λ``, its group's period.
    cost : Fraction
    earliest, latest : Fraction
        The release window's offsets ``a_T`` and ``b_T``.
    response : Fraction
        From the window's start to the job's end (at least ``latest - earliest +
        cost``).
    method : str
        The busy-period analysis used on its processor.
    """

    task: str
    processor: str
    priority: int
    period: Fraction
    cost: Fraction
    earliest: Fraction
    latest: Fraction
    response: Fraction
    method: str

    @property
    def jitter(self) -> Fraction:
        """``latest - earliest``."""
        return self.latest - self.earliest

    def to_dict(self) -> dict[str, Any]:
        """As the JSON report would hold it (exact strings)."""
        return {"task": self.task, "processor": self.processor, "priority": self.priority,
                "period": exact_text(self.period), "cost": exact_text(self.cost),
                "earliest": exact_text(self.earliest), "latest": exact_text(self.latest),
                "jitter": exact_text(self.jitter), "response": exact_text(self.response),
                "method": self.method}


@dataclass
class Holistic:
    """The fixed point of the holistic analysis over some parts of a skeleton.

    Attributes
    ----------
    windows : dict of str to TaskWindow
        Every task of a periodic group of the parts analyzed (empty when the
        iteration did not reach its fixed point).
    rounds : int
    why : str or None
        Why there is no fixed point (None when there is one).
    """

    windows: dict[str, TaskWindow]
    rounds: int
    why: str | None = None
    groups: dict[int, GroupWindows] = field(default_factory=dict, repr=False)
    """Each periodic group's offsets, by index (a chain's bound reads them)."""


def holistic_analysis(skeleton: Skeleton, report: Report | None = None, *,
                      tasks: Sequence[str] | None = None, budget: int | None = None,
                      rounds: int = HOLISTIC_ROUNDS) -> Holistic:
    """Release windows and response bounds of every periodic task, at the fixed point.

    Parameters
    ----------
    skeleton : Skeleton
    report : Report, optional
        ``analyze_skeleton(skeleton)`` (computed when not given): the groups, their
        periods and transients, the platform.
    tasks : sequence of str, optional
        Analyze only the parts of the schedule (groups joined by processors,
        :func:`~tegraph.model.platform.processor_parts`) that hold them; all when
        not given.
    budget : int, optional
        Terms of each busy-period analysis
        (:data:`~tegraph.design.busy_period.BUSY_PERIOD_BUDGET`); a spent budget
        gives its proven upper bound.
    rounds : int
        Most rounds of the iteration (:data:`HOLISTIC_ROUNDS`).

    Returns
    -------
    Holistic
        ``windows`` at the fixed point, or ``why`` there is none.

    See Also
    --------
    tegraph.design.holistic_latency.holistic_latency : a chain's bound from
        these windows.

    Examples
    --------
    A sensor task S (1 ms every 10 ms, on cpu1) sends to a frame M (2 ms, on a
    non-preemptive bus, triggered by S) read blocking by A (1 ms, on cpu2); a frame
    N (3 ms every 10 ms) shares the bus at a lower priority. M is released between
    1 and 1 ms after S's tick, blocked by N for up to 3 ms: it ends by 6 ms; A, released
    between 3 and 6 ms, ends by 7 ms.

    >>> sk = Skeleton.from_dict({"tasks": {
    ...   "S": {"duration": 1, "period": 10, "outputs": ["x"], "processor": "cpu1"},
    ...   "M": {"duration": 2, "inputs": ["x"], "outputs": ["y"], "processor": "can",
    ...         "priority": 2},
    ...   "N": {"duration": 3, "period": 10, "processor": "can", "priority": 1},
    ...   "A": {"duration": 1, "inputs": ["y"], "processor": "cpu2"}},
    ...   "processors": {"can": {"preemptive": False}},
    ...   "links": [{"from": "S:x", "to": "M:x", "protocol": "ASYN/SYN"},
    ...             {"from": "M:y", "to": "A:y", "protocol": "ASYN/SYN"}]})
    >>> h = holistic_analysis(sk)
    >>> [(w.task, str(w.earliest), str(w.latest), str(w.response)) for w in h.windows.values()]
    [('S', '0', '0', '1'), ('M', '1', '1', '5'), ('N', '0', '0', '5'), ('A', '3', '6', '4')]
    """
    if report is None:
        report = analyze_skeleton(skeleton)
    platform = report.platform if report.platform is not None else platform_of(
        skeleton, report.structure if report.structure is not None else report.groups)
    groups = _parts_of(report, platform, tasks)
    periodic: dict[int, GroupWindows] = {}
    irregular: dict[str, str] = {}  # task -> why it is no periodic load
    for g in groups:
        why = not_periodic(g)
        if why is None:
            periodic[g.index] = GroupWindows(skeleton, g)
        else:
            irregular.update({t: why for t in g.tasks})
    where = platform.processor_of
    on: dict[str, list[str]] = {}
    for g in groups:
        for t in g.tasks:
            on.setdefault(where[t], []).append(t)
    group_of = {t: gi for gi, grp in periodic.items() for t in grp.tasks}
    earliest = {t: grp.lower[grp.compute[t]] for grp in periodic.values() for t in grp.tasks}
    cost = {t: skeleton.tasks[t].duration for g in groups for t in g.tasks}
    response = {t: cost[t] for t in group_of}
    for n in range(1, rounds + 1):
        latest: dict[str, Fraction] = {}
        for grp in periodic.values():
            off = grp.upper({t: earliest[t] + response[t] for t in grp.tasks})
            latest.update({t: off[grp.compute[t]] for t in grp.tasks})
        new: dict[str, Fraction] = {}
        for t, gi in group_of.items():
            proc = where[t]
            result = _response(t, proc, on[proc], platform, cost, periodic[gi].period,
                               {u: (periodic[group_of[u]].period,
                                    max(latest[u] - earliest[u], Fraction(0)))
                                for u in on[proc] if u in group_of}, irregular, budget)
            if isinstance(result, str):
                return Holistic({}, n, result, periodic)
            new[t] = max(result, response[t])
        if new == response:
            windows = {t: TaskWindow(t, where[t], platform.priority[t],
                                     periodic[group_of[t]].period, cost[t], earliest[t],
                                     max(latest[t], earliest[t]), response[t],
                                     _method(platform, where[t]))
                       for t in skeleton.tasks if t in group_of}  # in file order
            return Holistic(windows, n, None, periodic)
        response = new
    return Holistic({}, rounds, f"the iteration did not reach its fixed point within "
                                f"{rounds:,} rounds (the responses keep growing)", periodic)


class GroupWindows:
    """One periodic group's timed event graph: its earliest offsets (the §3 daters)
    and the longest paths that give its latest ones."""

    def __init__(self, skeleton: Skeleton, g: GroupReport) -> None:
        assert g.period is not None and g.transient is not None  # not_periodic said so
        self.index, self.tasks, self.period = g.index, list(g.tasks), g.period
        teg = build_teg(skeleton.restricted_to(g.tasks))
        self.names = teg.transition_names
        self.compute: dict[str, int] = dict(teg.attrs["compute"])
        self.port_event = {pt: e for e, attrs in enumerate(teg.transition_attrs)
                           for pt in attrs.get("ports", ())}
        sources = holding_sources(teg)
        lam = self.period
        # (src, dst, shift: h - m·λ, initial a_p or None, task whose end it waits for)
        self.places = []
        for p, src in zip(teg.places, sources, strict=True):
            owner = src.owner if src.kind == "duration" else None
            self.places.append((p.src, p.dst, p.holding - p.tokens * lam,
                                p.initial if p.tokens else None, owner, p.tokens))
        K, c = g.transient
        n = K + c - 1  # the offsets x(k) - (k-1)λ repeat with period c from K on
        daters = teg.simulate(n)
        scale = daters.scale
        self.lower = [min(Fraction(int(daters.times[k, e]), scale) - k * lam for k in range(n))
                      for e in range(teg.n_transitions)]
        self._latest: tuple[dict[str, Fraction], list[Fraction]] | None = None

    def upper(self, ends: dict[str, Fraction]) -> list[Fraction]:
        """The latest offsets when job k of each task ends by ``(k-1)λ + ends[T]``."""
        lam = self.period
        off: list[Fraction | None] = [None] * len(self.names)
        has_input = [False] * len(self.names)
        for _, dst, *_ in self.places:
            has_input[dst] = True
        for e, inp in enumerate(has_input):
            if not inp:  # never held back: fires at 0 (spec §3)
                off[e] = Fraction(0)
        for _ in range(len(self.names) + 2):
            changed = False
            for src, dst, shift, initial, owner, tokens in self.places:
                cur = off[dst]
                if initial is not None and (cur is None or initial > cur):
                    off[dst] = cur = initial
                    changed = True
                if owner is not None:
                    value: Fraction | None = ends[owner] - tokens * lam
                else:
                    base = off[src]
                    value = None if base is None else base + shift
                if value is not None and (cur is None or value > cur):
                    off[dst], changed = value, True
            if not changed:
                # Every event of a live group is reached (by a token or a path).
                return [x if x is not None else Fraction(0) for x in off]
        raise AssertionError(  # pragma: no cover - excluded by rate-consistency (docstring)
            f"group {self.index}: a circuit that avoids every compute event holds more "
            "than its period per token")

    def latest_of(self, windows: dict[str, TaskWindow]) -> list[Fraction]:
        """The latest offsets at the fixed point (computed once per group)."""
        ends = {t: windows[t].earliest + windows[t].response for t in self.tasks}
        if self._latest is None or self._latest[0] != ends:
            self._latest = (ends, self.upper(ends))
        return self._latest[1]


def _parts_of(report: Report, platform: Platform, tasks: Sequence[str] | None
              ) -> list[GroupReport]:
    groups = list(report.groups)
    if tasks is None:
        return groups
    part = processor_parts([g.tasks for g in groups], platform.processor_of)
    wanted = {part[report.tasks[t].group] for t in tasks}
    return [g for g in groups if part[g.index] in wanted]


def not_periodic(g: GroupReport) -> str | None:
    """Why the tasks of ``g`` are no periodic load (not live, no clock, not
    rate-consistent, no periodic regime reached), or None."""
    if not g.live:
        return f"group {g.index} is not live"
    if not g.clocks:
        return f"group {g.index} has no clock (free-running)"
    if not g.rate_consistent or not g.period:
        return f"group {g.index} is not rate-consistent"
    if g.transient is None:
        return f"group {g.index}'s periodic regime was not reached (raise `max_steps`)"
    return None


def _response(t: str, proc: str, here: list[str], platform: Platform,
              cost: dict[str, Fraction], period: Fraction,
              periodic: dict[str, tuple[Fraction, Fraction]], irregular: dict[str, str],
              budget: int | None) -> Fraction | str:
    """``R_T`` on its processor with the others' current jitters, or why there is none."""
    prio = platform.priority
    preemptive = platform.preemptive(proc)
    for u in here:
        if u != t and u in irregular and prio[u] >= prio[t] and cost[u] > 0:
            return (f"{u} ({irregular[u]}) is at least as urgent as {t} on {proc}: it may "
                    "take every instant")
    interferers = [(cost[u], *periodic[u]) for u in here
                   if u != t and u in periodic and prio[u] >= prio[t]]
    blocking = Fraction(0) if preemptive else max(
        (cost[u] for u in here if prio[u] < prio[t]), default=Fraction(0))
    result = busy_period_response(cost[t], period, interferers, preemptive=preemptive,
                                  blocking=blocking, jitter=periodic[t][1], budget=budget)
    if result.status == "exact":
        assert result.value is not None
        return result.value
    if result.status in ("endless", "budget"):
        assert result.upper is not None
        return result.upper  # a proven bound on every instance
    return (f"{t} on {proc}: "
            + ("more urgent tasks may leave it no time" if result.status == "no time"
               else "its priority level needs more than the processor"))


def _method(platform: Platform, proc: str) -> str:
    return ("busy period with jitter, preemptive (Tindell 1994)" if platform.preemptive(proc)
            else "revised analysis with jitter, non-preemptive (Davis et al. 2007)")
