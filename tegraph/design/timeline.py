"""Timing diagram: the schedule on processors (spec §4b), drawn until its proof.

Figure 17 of the ORCCAD paper [1]_ shows the computed-torque law on one
processor under rate-monotonic priorities. :func:`simulate_timeline` gives
that diagram as data, exactly, from the one semantics of every command:
:func:`~tegraph.analysis.processors.schedule_on_processors` (§4b: jobs released
when their reads are done, preemptive fixed priorities, tokens delivered when a
job has received its duration). Nothing is simulated here; the timeline is the
engine's processor time per job, and its verdict is the engine's proof:

- by default the drawing is a window of :data:`WINDOW_PERIODS` periods of the
  fastest clock (what a reader can tell apart at a glance): around the first
  problem (the first overrun's tick, the instant a group is stuck in a deadlock,
  the first job that never ends), else from the periodic regime of the part of
  that clock; the whole proof when it fits in the window (each part's periodic
  regime reached, or the first overrun, its tick and the end of the late
  activation's computation when known). The notes say what the window shows and
  how to see more; past a part's regime the schedule is the regime again,
  shifted (that is what the proof says), so a longer drawing repeats it;
- ``horizon`` (and ``start``) only choose what is drawn, never the verdict;
- what the jobs wait for without their processor (a read, a rendezvous, a write,
  a deadlock's stuck events) comes with it (:mod:`.timeline_waits`);
- the budget is ``max_events`` (as for ``tegraph analyze``): a skeleton whose
  regime cannot be reached within it (drifting clocks, whose hyperperiod is
  huge) is undecided at once, with the reason and its hyperperiod, unless an
  overrun was found first;
- each chain (the skeleton's and those asked for) comes with its figures on
  processors (spec §4c, the one definition of :mod:`tegraph.analysis.chains`,
  read off the same schedule) and its worst data path (the largest first use:
  the sample, each write and read it passes, the output), taken in the proven
  regime; the default drawing runs on until every such path is drawn.

References
----------
.. [1] D. Simon et al., "Design and analysis of synchronization for
   real-time closed-loop control in robotics", IEEE Transactions on Control
   Systems Technology, 1998.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction

from maxplus.scalar import display_text

from ..analysis import notebook
from ..analysis.analyze import analyze_skeleton
from ..analysis.chains import ChainFigures, chain_paths, figures_on, trace_request
from ..analysis.processors import MAX_EVENTS, JobInterval, ProcessorSchedule, schedule_on_processors
from ..analysis.results import Deadlock
from ..errors import InputError
from ..model.build import activation_end, build_teg
from ..model.limits import event_budget_problem, shown
from ..model.skeleton import Skeleton
from .schedulability import hyperperiod
from .timeline_blocking import Blocking, blockings
from .timeline_waits import Stuck, Wait, stuck_problems, waits_until
from .timeline_window import WINDOW_PERIODS, default_window

__all__ = ["MAX_DRAWN", "MAX_EVENTS", "WINDOW_PERIODS", "Job", "Stuck", "Timeline",
           "TimelineChain", "Wait", "simulate_timeline"]

MAX_DRAWN = 20_000
"""Processor intervals at most added by repeating a proven regime (a long
``horizon``): the drawing stops there, and says so."""

@dataclass
class Job:
    """The processor time of one activation, as drawn."""

    task: str
    index: int
    """Activation number k (spec §4: ``x_T.compute(k)`` released it)."""
    processor: str
    segments: list[tuple[Fraction, Fraction]]
    finish: Fraction | None
    """``f_T(k)``: when it has received its duration; None if not within the drawing."""
    late: bool = False
    """Its task overruns at activation ``index + 1`` (the first overrun of that task)."""

    @property
    def preemptions(self) -> int:
        """How many times it lost its processor before the end of the drawing."""
        return max(len(self.segments) - 1, 0)


@dataclass(frozen=True)
class TimelineChain:
    """A chain on the timeline: its tasks and its figures on processors (spec §4c), whose
    ``worst`` is the data path drawn."""

    tasks: tuple[str, ...]
    figures: ChainFigures


@dataclass
class Timeline:
    """The result of :func:`simulate_timeline`: one lane per processor.

    Examples
    --------
    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 2, "period": 10}}})
    >>> tl = simulate_timeline(sk)
    >>> tl.horizon, tl.schedulable, tl.order_of_execution()
    (Fraction(10, 1), True, [('A', Fraction(0, 1), Fraction(2, 1))])
    """

    name: str
    unit: str
    schedule: ProcessorSchedule
    horizon: Fraction
    """End of the drawing (the verdict never depends on it)."""
    start: Fraction
    """Beginning of the drawing (0 unless a window is drawn)."""
    proof_end: Fraction | None
    """The instant by which every part was decided (None: some part is undecided)."""
    intervals: list[JobInterval]
    """Processor time of each job from 0 to ``horizon``, by processor then start."""
    ticks: dict[str, list[Fraction]]
    clocks: dict[str, str | None]
    """The clock of each task (None: none)."""
    ends_with_computation: dict[str, bool]
    """Whether an activation of each task ends when its job does, not with a write
    (spec §4: a task without outputs)."""
    durations: dict[str, Fraction]
    overrun_ticks: dict[str, Fraction]
    """Task -> its clock's tick ``overrun_at`` (``phase + (k - 1) * period``)."""
    deadlocks: list[Deadlock] = field(default_factory=list)
    dead_tasks: list[str] = field(default_factory=list)
    """The tasks of the groups that are not live, in file order."""
    hyperperiods: dict[str, Fraction] = field(default_factory=dict)
    """First task of each undecided part -> its clocks' hyperperiod."""
    unsimulated: list[str] = field(default_factory=list)
    """First task of each part decided by a theorem: only the start of its schedule
    (a quick look) is drawn."""
    notes: list[str] = field(default_factory=list)
    """What the drawing leaves out."""
    chains: list[TimelineChain] = field(default_factory=list)
    """The skeleton's chains, then those asked for, with their figures on processors."""
    waits: list[Wait] = field(default_factory=list)
    """What the activations wait for without their processor, up to ``horizon``."""
    stuck: list[Stuck] = field(default_factory=list)
    """Each task of a group that is not live: the event it waits at for ever, since when."""
    window: str | None = None
    """What the default window shows and how to see more (None: the whole proof, or a
    drawing asked for)."""
    blocking: list[Blocking] = field(default_factory=list)
    """On non-preemptive processors (§4d): each drawn job's wait for a less urgent job
    holding the processor (:mod:`.timeline_blocking`)."""

    def _repr_html_(self) -> str:
        """Its drawing (SVG) as a notebook shows it (:func:`tegraph.report.html.render_html`)."""
        return notebook.html(self)

    @property
    def processors(self) -> list[str]:
        """The processors, one lane each, in the platform's order."""
        return [p.name for p in self.schedule.platform.processors]

    @property
    def visible(self) -> list[JobInterval]:
        """The intervals within the window ``[start, horizon]``, cut to it."""
        a = self.start
        return [i if i.start >= a else JobInterval(i.processor, a, i.end, i.task, i.k)
                for i in self.intervals if i.end > a]

    @property
    def priorities(self) -> dict[str, int]:
        """Each task's priority on its processor (larger is more urgent)."""
        return self.schedule.platform.priority

    @property
    def tasks(self) -> list[str]:
        """By processor, most urgent first, then file order."""
        prio = self.priorities
        return [t for p in self.schedule.platform.processors
                for t in sorted(p.tasks, key=lambda t: -prio[t])]

    @property
    def schedulable(self) -> bool | None:
        """The §4b verdict (None: undecided within the budget)."""
        return self.schedule.schedulable

    @property
    def overrun_at(self) -> dict[str, int | None]:
        """Each task's first overrun on its processors (the §4 numbering), or None."""
        return {t: f.overrun_at for t, f in self.schedule.tasks.items()}

    @property
    def exit_status(self) -> int:
        """0 schedulable (proven); 1 not schedulable, or undecided within the budget."""
        return 0 if self.schedulable is True else 1

    @property
    def jobs(self) -> list[Job]:
        """The drawn jobs, by processor then first start."""
        by_job: dict[tuple[str, int], Job] = {}
        for i in self.intervals:
            job = by_job.setdefault((i.task, i.k), Job(i.task, i.k, i.processor, [], None))
            job.segments.append((i.start, i.end))
        overrun_at = self.overrun_at
        for job in by_job.values():
            if sum(b - a for a, b in job.segments) == self.durations[job.task]:
                job.finish = job.segments[-1][1]
            k = overrun_at[job.task]
            job.late = k is not None and job.index == k - 1
        return list(by_job.values())

    @property
    def late_jobs(self) -> list[Job]:
        """The jobs of an overrun's late activation."""
        return [j for j in self.jobs if j.late]

    def order_of_execution(self, processor: str | None = None
                           ) -> list[tuple[str, Fraction, Fraction]]:
        """``(task, start, end)`` of every drawn interval on ``processor`` (default: the
        first processor), by start."""
        name = processor if processor is not None else self.processors[0]
        return [(i.task, i.start, i.end) for i in self.intervals if i.processor == name]


def simulate_timeline(skeleton: Skeleton, horizon: Fraction | int | str | None = None,
                      max_events: int = MAX_EVENTS,
                      start: Fraction | int | str | None = None,
                      chains: Sequence[Sequence[str]] = ()) -> Timeline:
    """The §4b schedule of ``skeleton`` on its processors, until its proof.

    Parameters
    ----------
    skeleton : Skeleton
        Priorities as declared on each processor whose tasks all declare one,
        rate-monotonic otherwise (§4b).
    horizon : Fraction, optional
        End of the drawing. Default: a window of :data:`WINDOW_PERIODS` periods of
        the fastest clock around the first problem, or from the periodic regime
        (module docstring; ``window`` says what it shows), or the whole proof when
        it fits: the end of the last part's first periodic regime, or, when a task
        overruns, the tick of the first overrun (and the end of the late
        computation when known). It never changes the verdict.
    max_events : int
        Budget of event firings of the exact schedule (default :data:`MAX_EVENTS`).
    start : Fraction, optional
        Beginning of the drawing, with ``horizon`` (default 0).
    chains : sequence of task-name sequences
        Chains to draw besides the skeleton's own (their worst data path and figures).

    Returns
    -------
    Timeline

    Raises
    ------
    InputError
        ``horizon`` is not positive, ``start`` is negative or not before ``horizon``,
        or ``max_events`` is not an integer >= 1.
    SkeletonError
        A chain names an unknown task, a task twice, or two unlinked tasks.

    See Also
    --------
    tegraph.analysis.processors.schedule_on_processors : the schedule and its proof.

    Examples
    --------
    B (period 4) is preempted at 2 by the more urgent A (period 2). The regime
    is proven from 4 to 8 (B's first job ends at 4, in it), so the drawing ends at 8:

    >>> sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 2},
    ...                                    "B": {"duration": 2, "period": 4}}})
    >>> tl = simulate_timeline(sk)
    >>> [(t, str(a), str(b)) for t, a, b in tl.order_of_execution()][:4], tl.horizon
    ([('A', '0', '1'), ('B', '1', '2'), ('A', '2', '3'), ('B', '3', '4')], Fraction(8, 1))
    """
    horizon, begin = _checked(skeleton, horizon, max_events, start)
    report = analyze_skeleton(skeleton, semiflow_max_places=0)
    teg = build_teg(skeleton)
    paths = chain_paths(skeleton, teg, chains)
    s = schedule_on_processors(skeleton, teg, report.groups, max_events=max_events,
                               trace=trace_request(paths) if paths else None)
    drawn_chains = [] if s.trace is None else [
        TimelineChain(p.tasks, f) for p, f in zip(paths, figures_on(
            paths, s.trace, report.groups, shared=True, unit=skeleton.unit,
            max_events=max_events))]
    tasks, clocks = skeleton.tasks, skeleton.clocks
    by_part = _by_part(s)
    ends, hyper, unsimulated = _part_ends(skeleton, s, by_part)
    proof_end = None if any(r["start"] is None for r in s.regimes) else max(
        (r["start"] + (r["length"] or 0) for r in s.regimes if "by" not in r),
        default=Fraction(0))
    at = {t: _tick(skeleton, t, f.overrun_at) for t, f in s.tasks.items()
          if f.overrun_at is not None}
    dead = frozenset(t for g in report.groups if not g.live for t in g.tasks)
    zero = frozenset(t for t, f in s.tasks.items() if f.period == 0)
    window = None
    if horizon is None:
        full = _until_the_proof(skeleton, s, by_part, ends, at)
        for c in drawn_chains:  # on to the end of the chain's period holding its worst path
            f = c.figures
            if f.worst and f.period and f.worst[-1].at >= full:
                full += -((full - f.worst[-1].at) // f.period) * f.period
                if full == f.worst[-1].at:
                    full += f.period
        problems = [(x, f"the first overrun ({t} at {_time(x, skeleton.unit)})")
                    for t, x in at.items()]
        if dead or s.starved:  # when a group is stuck, when a job never ends
            problems += stuck_problems(skeleton, teg, s, s.intervals, full, dead, zero)
        begin, horizon, window = default_window(skeleton, s, full,
                                                 min(problems, default=None))
    drawn, notes = _draw(s, by_part, ends, horizon, skeleton.unit)
    waits, stuck, releases = waits_until(skeleton, teg, drawn, horizon, dead, zero)
    ticks = {name: _ticks_until(c.phase, c.period, horizon) for name, c in clocks.items()}
    if window is not None:
        notes.insert(0, window)
    return Timeline(
        skeleton.name, skeleton.unit, s, horizon, begin, proof_end, drawn, ticks,
        clocks={t: task.clock for t, task in tasks.items()},
        ends_with_computation={t: activation_end(teg, t).adds_duration for t in tasks},
        durations={t: task.duration for t, task in tasks.items()}, overrun_ticks=at,
        deadlocks=list(report.deadlocks), dead_tasks=[t for t in tasks if t in dead],
        hyperperiods=hyper, unsimulated=unsimulated, notes=notes, waits=waits, stuck=stuck,
        window=window, chains=drawn_chains,
        blocking=blockings(drawn, releases, s.platform))


def _checked(skeleton: Skeleton, horizon: Fraction | int | str | None, max_events: int,
             start: Fraction | int | str | None) -> tuple[Fraction | None, Fraction]:
    """The horizon and the start as Fractions; the parameters refused before the analysis."""
    problem = event_budget_problem(max_events)
    if problem is not None:
        raise InputError(problem, "max_events")
    begin = Fraction(0) if start is None else Fraction(start)
    if begin < 0:
        raise InputError(f"expected a time >= 0, got {shown(display_text(begin), quote=False)}"
                         f" {skeleton.unit}", "start")
    if horizon is None:
        if start is not None:
            raise InputError("a start needs an end: give `horizon` too", "start")
        return None, begin
    value = Fraction(horizon)
    if value <= 0:
        raise InputError(f"expected a time > 0, got {shown(display_text(value), quote=False)}"
                         f" {skeleton.unit}", "horizon")
    if begin >= value:
        raise InputError(f"the drawing starts at {_time(begin, skeleton.unit)}, not before "
                         f"its end {_time(value, skeleton.unit)}; expected START < END",
                         "horizon")
    return value, begin


def _ticks_until(phase: Fraction, period: Fraction, horizon: Fraction) -> list[Fraction]:
    """A clock's ticks up to ``horizon``, at most :data:`MAX_DRAWN` of them."""
    n = 0 if phase > horizon else min(int((horizon - phase) / period) + 1, MAX_DRAWN)
    return [phase + j * period for j in range(n)]


def _by_part(s: ProcessorSchedule) -> dict[str, list[JobInterval]]:
    """The simulated intervals of each part, keyed by the part's first task."""
    part_of = {t: r["tasks"][0] for r in s.regimes for t in r["tasks"]}
    by_part: dict[str, list[JobInterval]] = {}
    for i in s.intervals:
        by_part.setdefault(part_of[i.task], []).append(i)
    return by_part


def _tick(skeleton: Skeleton, task: str, k: int) -> Fraction:
    """Tick k (from 1) of the clock of ``task``."""
    # Type: called for tasks that overran: each has a clock.
    c = skeleton.clocks[skeleton.tasks[task].clock]  # type: ignore[index]
    return c.phase + (k - 1) * c.period


def _part_ends(skeleton: Skeleton, s: ProcessorSchedule, by_part: dict[str, list[JobInterval]]
               ) -> tuple[dict[str, Fraction], dict[str, Fraction], list[str]]:
    """Where each part's drawing ends by default (keyed by its first task), the
    hyperperiod of each undecided part, and the parts the critical instant decided."""
    tasks, clocks = skeleton.tasks, skeleton.clocks
    ends: dict[str, Fraction] = {}
    hyper: dict[str, Fraction] = {}
    unsimulated: list[str] = []
    for r in s.regimes:
        first = r["tasks"][0]
        if r.get("by") == "critical instant":
            # Decided by the theorem: its regime (a hyperperiod) is not simulated, only
            # a quick look at its start; four periods of its slowest clock are drawn
            # (the critical instant at 0 and what follows), or less if the look stopped.
            # Type: the critical instant decides only parts whose every task has its own clock.
            slowest = max(clocks[tasks[t].clock].period for t in r["tasks"])  # type: ignore[index]
            looked = max((i.end for i in by_part.get(first, [])), default=Fraction(0))
            ends[first] = min(looked, 4 * slowest)
            unsimulated.append(first)
        elif r["start"] is None:  # undecided: drawn as far as it was simulated
            ends[first] = max((i.end for i in by_part.get(first, [])), default=Fraction(0))
            hyper[first] = hyperperiod(clocks[c].period for c in
                                       {tasks[t].clock for t in r["tasks"]} if c)
        else:
            ends[first] = r["start"] + (r["length"] or 0)
    return ends, hyper, unsimulated


def _until_the_proof(skeleton: Skeleton, s: ProcessorSchedule,
                     by_part: dict[str, list[JobInterval]], ends: dict[str, Fraction],
                     overrun_ticks: dict[str, Fraction]) -> Fraction:
    """The default end of the drawing: the first overrun's tick (and the end of the late
    computation when it comes within one more regime; a starved one never does), else
    the end of every part's proof."""
    if overrun_ticks:
        when, late = min((x, t) for t, x in overrun_ticks.items())
        length = {t: r["length"] or 0 for r in s.regimes for t in r["tasks"]}
        k = s.tasks[late].overrun_at
        assert k is not None  # overrun_ticks holds only the tasks that overran
        job = (late, k - 1)
        drawn, _ = _draw(s, by_part, ends, when + length[late], skeleton.unit)
        return max([when] + [i.end for i in drawn if (i.task, i.k) == job])
    horizon = max(ends.values(), default=Fraction(0))
    if horizon <= 0:  # nothing ever happens: one period, or one unit of time
        horizon = max((c.phase + c.period for c in skeleton.clocks.values()),
                      default=Fraction(1))
    return horizon


def _draw(s: ProcessorSchedule, by_part: dict[str, list[JobInterval]], ends: dict[str, Fraction],
          horizon: Fraction, unit: str) -> tuple[list[JobInterval], list[str]]:
    """The intervals from 0 to ``horizon``: simulated, then each proven regime repeated."""
    notes: list[str] = []
    drawn: list[JobInterval] = []
    for r in s.regimes:
        first = r["tasks"][0]
        own = by_part.get(first, [])
        drawn += [_cut(i, horizon) for i in own if i.start < horizon]
        if r["length"] and own and ends[first] < horizon:
            more, cut = _repeat(own, r["start"], r["length"], horizon, MAX_DRAWN)
            drawn += more
            if cut is not None:
                notes.append(f"the part of {first}: its regime is repeated up to "
                             f"{_time(cut, unit)} only ({MAX_DRAWN:,} intervals)")
        elif r["start"] is None and ends[first] < horizon:
            notes.append(f"the part of {first}: simulated up to {_time(ends[first], unit)} "
                         "only (undecided within `max_events`)")
    order = {p.name: n for n, p in enumerate(s.platform.processors)}
    return sorted(_merge(drawn), key=lambda i: (order[i.processor], i.start)), notes


def _cut(i: JobInterval, end: Fraction) -> JobInterval:
    return i if i.end <= end else JobInterval(i.processor, i.start, end, i.task, i.k)


def _repeat(intervals: list[JobInterval], t1: Fraction, length: Fraction, end: Fraction,
            limit: int) -> tuple[list[JobInterval], Fraction | None]:
    """The regime [t1, t1 + length) repeated, shifted, from t1 + length up to ``end``.

    The proof says the schedule from t1 + length is the one from t1 shifted by
    ``length``, each task's activations numbered ``n_T`` more, ``n_T`` its jobs
    per regime. In the regime's window, the jobs that get processor time are
    consecutive, a..b; the job running into t1 (a, when it had time before t1)
    is, shifted, the one running into t2 (b): then ``n_T = b - a``, otherwise
    ``b + 1 = a + n_T``. Returns the intervals and where ``limit`` cut them (None).
    """
    t2 = t1 + length
    window = [JobInterval(i.processor, max(i.start, t1), min(i.end, t2), i.task, i.k)
              for i in intervals if i.end > t1 and i.start < t2]
    spans: dict[str, tuple[int, int]] = {}
    for i in window:
        a, b = spans.get(i.task, (i.k, i.k))
        spans[i.task] = (min(a, i.k), max(b, i.k))
    before = {(i.task, i.k) for i in intervals if i.start < t1}
    per = {t: b - a + (0 if (t, a) in before else 1) for t, (a, b) in spans.items()}
    out: list[JobInterval] = []
    m = 1
    while window and t1 + m * length < end:
        for i in window:
            start = i.start + m * length
            if start >= end:
                continue
            if len(out) >= limit:
                return out, start
            out.append(JobInterval(i.processor, start, min(i.end + m * length, end), i.task,
                                   i.k + m * per[i.task]))
        m += 1
    return out, None


def _merge(intervals: list[JobInterval]) -> list[JobInterval]:
    """Join the pieces of one job that meet (a regime's end and the next one's start)."""
    out: list[JobInterval] = []
    last: dict[str, int] = {}
    for i in sorted(intervals, key=lambda i: (i.processor, i.start)):
        j = last.get(i.processor)
        if j is not None and (out[j].task, out[j].k, out[j].end) == (i.task, i.k, i.start):
            out[j] = JobInterval(i.processor, out[j].start, i.end, i.task, i.k)
            continue
        last[i.processor] = len(out)
        out.append(i)
    return out


def _time(value: Fraction, unit: str) -> str:
    """A time for a message: as the input wrote it, cut with its length when too long to read.

    >>> _time(Fraction(5, 2), "ms"), _time(2 + Fraction(2, 10**400), "ms")[-24:]
    ('2.5 ms', '... (802 characters) ms')
    """
    return f"{shown(display_text(value), quote=False)} {unit}"
