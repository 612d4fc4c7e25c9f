"""The latency of a chain, exactly (spec §4c): which message each read sees, and when
the data an output is computed from was sampled.

A chain ``[T1, ..., Tn]`` is followed backwards from each output of ``Tn``: the
read of its job saw the newest message of the link from ``Tn-1`` visible at the
read's instant, that message was written by one job of ``Tn-1``, whose read saw
one of ``Tn-2``, and so on down to a job of ``T1`` and the instant it sampled its
sensor. The instants are those of a schedule (spec §4b, on the skeleton's
processors; or with a processor per task, where it is §3's daters) that the
engine recorded while it proved its periodic regime
(:class:`~.processors.trace.ScheduleTrace`): every read, write, start and end
is then periodic, and so is the whole data path. The figures are a maximum or
minimum over one period of the regime the chain's parts share (the least
common multiple of their regimes' lengths), with every sequence extended
backwards periodically as far as a data path reaches; ``docs/analysis.md``
(*The latency of a chain*) proves that this is the maximum over the whole
regime. Where a part of the chain has no proven regime, the figures are null
and say why.

- ``first_use``: the largest time from a sample to the first output computed from it;
- ``age`` (``age_min``): the largest (smallest) time from the sample an output is
  computed from to the output;
- ``reaction``: the largest time from a sample to the first output computed from a
  later one (a change just after a sample waits for the next).

References
----------
.. [1] D. Simon, B. Espiau, K. Kapellos, R. Pissard-Gibollet, "Orccad: software
   engineering for real-time robotics", 1998: the latency between a measurement
   and its use in the output (Figure 4).
.. [2] M. Günzel, K.-H. Chen, N. Ueter, G. von der Brüggen, M. Dürr, J.-J. Chen,
   "Compositional timing analysis of asynchronized distributed cause-effect
   chains", ACM Transactions on Embedded Computing Systems 22(4), 2023; and
   "On the equivalence of maximum reaction time and maximum data age for
   cause-effect chains", ECRTS 2023.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np

from maxplus.scalar import display_text, exact_text

from ..model.build import task_chain
from ..model.platform import link_delay, processor_per_task
from ..model.skeleton import Link, Protocol, Skeleton
from ..model.skeleton.checks import Locator, check_chain
from ..model.teg import TimedEventGraph
from .processors.schedule import MAX_EVENTS, trace_schedule
from .processors.trace import Instants, ScheduleTrace, TraceRequest

__all__ = ["ChainFigures", "ChainPath", "ChainReport", "DataStep", "DaterTrace", "Hop",
           "Instant", "chain_paths", "chain_reports", "figures_on", "trace_request"]

_BLOCKING = (Protocol.ASYN_SYN, Protocol.SYN_SYN)
"""Protocols whose reader waits (§4c: a blocking read happens at its event)."""


@dataclass(frozen=True)
class Instant:
    """Where an instant of a task's activations is read in a schedule: the firings of
    an event (``event`` >= 0), or each job's ``"start"`` or ``"end"``."""

    task: str
    kind: str
    """``"event"``, ``"start"`` or ``"end"``."""
    name: str
    """What it is, in words: ``MT1.read:q``, ``the start of MT1``."""
    event: int = -1


@dataclass(frozen=True)
class Hop:
    """The link a chain follows from ``writer`` to ``reader``, and how it is read (§4c)."""

    writer: str
    reader: str
    link: Link
    write: Instant
    read: Instant
    blocking: bool
    """The read waits for the message (ASYN/SYN, SYN/SYN): it sees a message visible at
    its very instant; a non-blocking read sees one only from a writer on its processor."""
    delay: Fraction = Fraction(0)
    """The message is visible from its write plus ``delay`` on (spec §4d): the link's
    :func:`~tegraph.model.platform.link_delay`."""


@dataclass(frozen=True)
class ChainPath:
    """A chain resolved into the instants its data passes (spec §4c, *A chain's data*)."""

    tasks: tuple[str, ...]
    sample: Instant
    """When ``T1`` samples its sensor: its first unlinked input's read, or its job's start."""
    hops: tuple[Hop, ...]
    output: Instant
    """When ``Tn`` posts its output: its first unlinked output's write, or its job's end."""

    @property
    def instants(self) -> list[Instant]:
        """The sample, each hop's write and read, and the output, in the data's order."""
        return [self.sample, *(x for h in self.hops for x in (h.write, h.read)), self.output]


@dataclass(frozen=True)
class DataStep:
    """One instant of a data path: activation ``k`` of ``task`` at ``at`` (``what``)."""

    task: str
    k: int
    what: str
    at: Fraction


@dataclass(frozen=True)
class ChainFigures:
    """The §4c figures of one chain on one platform (times in the skeleton's unit).

    ``first_use``, ``age``, ``age_min`` and ``reaction`` are None together, and
    ``why_undecided`` says why; ``worst`` is the data path of the largest first
    use (its sample, each write and read it passes, its output), taken in the
    schedule's periodic regime, and ``period`` the length after which every figure
    repeats (the least common multiple of the chain's parts' regimes).
    """

    first_use: Fraction | None = None
    age: Fraction | None = None
    age_min: Fraction | None = None
    reaction: Fraction | None = None
    why_undecided: str | None = None
    worst: tuple[DataStep, ...] = ()
    period: Fraction | None = None

    @property
    def decided(self) -> bool:
        """Whether the figures are proven (:attr:`why_undecided` is None)."""
        return self.why_undecided is None

    def to_dict(self) -> dict[str, Any]:
        """The figures of spec §5's ``chains`` (exact strings)."""
        return {"first_use": exact_text(self.first_use), "age": exact_text(self.age),
                "age_min": exact_text(self.age_min), "reaction": exact_text(self.reaction),
                "why_undecided": self.why_undecided}


@dataclass(frozen=True)
class ChainReport:
    """One chain's latency, with a processor per task (§3) and on its processors (§4c).

    Examples
    --------
    Figure 4 run in the designer's order on one processor, against a processor
    per task, where each hop waits a period:

    >>> from tegraph import analyze
    >>> r = analyze("examples/fig4_pipeline_unsynchronized.yaml",
    ...             chains=[["MT1", "MT2", "MT3", "MT4"]])
    >>> c = r.chains[0]
    >>> [str(x) for x in (c.on_processors.first_use, c.on_processors.reaction)]
    ['6', '16']
    >>> [str(x) for x in (c.first_use, c.age, c.age_min, c.reaction)]
    ['31', '31', '31', '41']
    """

    tasks: tuple[str, ...]
    processor_per_task: ChainFigures
    """With every task on a processor of its own: §3's daters (``--no-processors``)."""
    on_processors: ChainFigures
    """On the skeleton's processors (§4b); the same as :attr:`processor_per_task` when
    the analysis gave every task a processor of its own."""

    @property
    def first_use(self) -> Fraction | None:
        """The first use with a processor per task (:attr:`processor_per_task`)."""
        return self.processor_per_task.first_use

    @property
    def age(self) -> Fraction | None:
        """The age with a processor per task (:attr:`processor_per_task`)."""
        return self.processor_per_task.age

    @property
    def age_min(self) -> Fraction | None:
        """The least age with a processor per task (:attr:`processor_per_task`)."""
        return self.processor_per_task.age_min

    @property
    def reaction(self) -> Fraction | None:
        """The reaction with a processor per task (:attr:`processor_per_task`)."""
        return self.processor_per_task.reaction

    def to_dict(self) -> dict[str, Any]:
        """The entry of spec §5's ``chains``."""
        return {"tasks": list(self.tasks), **self.processor_per_task.to_dict(),
                "on_processors": self.on_processors.to_dict()}


# ---------------------------------------------------------------------- the paths


def chain_paths(skeleton: Skeleton, teg: TimedEventGraph, chains: Sequence[Sequence[str]] = ()
                ) -> list[ChainPath]:
    """The skeleton's own chains, then ``chains``, each checked and resolved (§4c).

    Each hop's :attr:`Hop.delay` is its link's delay in ``skeleton`` (spec §4d, the
    one definition :func:`~tegraph.model.platform.link_delay`: its own when declared,
    else ``network.delay`` between two declared processors, else 0), so every caller
    reads a message as visible from its write plus that delay, with and without
    processors.

    Parameters
    ----------
    skeleton : Skeleton
    teg : TimedEventGraph
        ``build_teg(skeleton)``.
    chains : sequence of task-name sequences
        Besides ``skeleton.chains`` (key path ``chain[i][j]`` in a message).

    Raises
    ------
    SkeletonError
        A chain names an unknown task, a task twice, or two consecutive tasks with no
        link from the first to the second.

    Examples
    --------
    >>> from tegraph import load_skeleton
    >>> from tegraph.model.build import build_teg
    >>> sk = load_skeleton("examples/computed_torque.yaml")
    >>> (p,) = chain_paths(sk, build_teg(sk), [["TG.JS", "TF.TT.JS", "CO.JS"]])
    >>> p.sample.name, [(h.read.name, h.blocking) for h in p.hops], p.output.name
    ('the start of TG.JS', [('TF.TT.JS.read:qd', True), ('CO.JS.read:e', True)], 'CO.JS.write:tau')
    """
    named: list[tuple[Any, tuple[str, int], str | None]] = [
        (c, ("chains", i), skeleton.source) for i, c in enumerate(skeleton.chains)]
    named += [(c, ("chain", i), None) for i, c in enumerate(chains)]
    if not named:
        return []
    links = _Links(skeleton, teg)
    out = []
    for chain, path, where in named:
        # The one message of a refused chain is check_chain's.
        if isinstance(chain, str) or not isinstance(chain, Sequence) or not links.follows(
                tuple(chain)):
            check_chain(skeleton, chain, path, Locator(file=where))
        out.append(links.path(tuple(chain)))
    return out


def trace_request(paths: Sequence[ChainPath]) -> TraceRequest:
    """What a schedule records for these chains: their events, and their tasks' jobs."""
    events = dict.fromkeys(x.event for p in paths for x in p.instants if x.kind == "event")
    tasks = dict.fromkeys(t for p in paths for t in p.tasks)
    return TraceRequest(tuple(events), tuple(tasks))


class _Links:
    """The skeleton's links as the chains read them, indexed once for all chains."""

    def __init__(self, sk: Skeleton, teg: TimedEventGraph) -> None:
        self.sk, self.teg = sk, teg
        self.linked = {end for link in sk.links for end in (link.writer, link.reader)}
        self.blocking = {link.reader for link in sk.links if link.protocol in _BLOCKING}
        self.first: dict[tuple[str, str], Link] = {}  # the first in the file, task to task
        for link in sk.links:
            self.first.setdefault((link.writer[0], link.reader[0]), link)
        self.ports: dict[tuple[str, str], int] = {}
        self.seen: set[str] = set()

    def follows(self, chain: tuple[str, ...]) -> bool:
        """Whether ``chain`` names known tasks, each once, each reading the one before."""
        return (len(chain) > 0 and all(isinstance(t, str) and t in self.sk.tasks for t in chain)
                and len(set(chain)) == len(chain)
                and all(pair in self.first for pair in zip(chain, chain[1:])))

    def port(self, task: str, port: str) -> int:
        """The event of ``task``'s port (the rendezvous of a SYN/SYN link is its writer's)."""
        if task not in self.seen:
            self.seen.add(task)
            for e in task_chain(self.teg, task):
                for owner_port in self.teg.transition_attrs[e]["ports"]:
                    self.ports[owner_port] = e
        return self.ports[task, port]

    def reading(self, task: str, port: str) -> Instant:
        """When ``task`` reads ``port`` (§4c): a blocking read at its event; a non-blocking
        one at the job's start when it comes after every blocking read of its task, else
        at its own event (the task reads it, then waits)."""
        inputs = self.sk.tasks[task].inputs
        later = inputs[inputs.index(port) + 1:]
        if (task, port) in self.blocking or any((task, q) in self.blocking for q in later):
            return _event(self.teg, task, self.port(task, port))
        return Instant(task, "start", f"{task}.read:{port} (at its job's start)")

    def path(self, chain: tuple[str, ...]) -> ChainPath:
        sk, teg = self.sk, self.teg
        hops = []
        for a, b in zip(chain, chain[1:]):
            link = self.first[a, b]
            hops.append(Hop(a, b, link, _event(teg, a, self.port(*link.writer)),
                            self.reading(*link.reader), link.protocol in _BLOCKING,
                            link_delay(sk, link)))
        first, last = chain[0], chain[-1]
        sensors = [p for p in sk.tasks[first].inputs if (first, p) not in self.linked]
        actuators = [p for p in sk.tasks[last].outputs if (last, p) not in self.linked]
        sample = (self.reading(first, sensors[0]) if sensors
                  else Instant(first, "start", f"the start of {first}"))
        output = (_event(teg, last, self.port(last, actuators[0])) if actuators
                  else Instant(last, "end", f"the end of {last}"))
        return ChainPath(chain, sample, tuple(hops), output)


def _event(teg: TimedEventGraph, task: str, e: int) -> Instant:
    return Instant(task, "event", teg.transition_names[e], e)


# ---------------------------------------------------------------------- the daters


@dataclass(frozen=True)
class DaterTrace:
    """The (max,+) daters of §3 the analysis recorded for the chains (with a processor
    per task, the schedule is these daters: every job starts at its release
    ``x_T.compute(k)`` and ends ``duration(T)`` later).

    Attributes
    ----------
    events : numpy.ndarray
        The recorded events (global indices, increasing).
    rows : list of numpy.ndarray
        ``rows[k - 1][i]`` is ``x_e(k)`` of ``events[i]``, on its group's scale.
    scales : list of int
        Each group's scale (the analysis' ``_EventGraph.scales``).
    group_of_event : numpy.ndarray
        Each event's group.
    groups : sequence of GroupReport
        Their ``transient`` (K, c) and ``period``, where the dater simulation proved
        the regime ``x(k + c) = x(k) + c·period`` for every ``k >= K``.
    durations, compute : dict
        Each chain task's duration and compute event.
    """

    events: np.ndarray
    rows: list[np.ndarray]
    scales: list[int]
    group_of_event: np.ndarray
    groups: Sequence[Any]
    durations: dict[str, Fraction]
    compute: dict[str, int]

    def trace(self, scale: int, tasks: Sequence[str]) -> ScheduleTrace:
        """The schedule trace of ``tasks`` with a processor per task, on ``scale`` (the
        graph's common one, a multiple of every group's): one cyclicity of each regime
        the daters proved; a task of another group is not in it."""
        out = ScheduleTrace(scale, {t: t for t in tasks}, frozenset(tasks))
        where = {int(e): i for i, e in enumerate(self.events.tolist())}
        for e, i in where.items():
            g = self.groups[int(self.group_of_event[e])]
            if g.transient is None or not g.rate_consistent or not g.period:
                continue  # (period 0: it runs infinitely often at 0; the engine says so)
            K, c = g.transient
            if len(self.rows) < K + c - 1:
                continue  # not simulated that far (the budget): left to the engine
            factor = scale // self.scales[g.index]
            values = tuple(int(self.rows[k - 1][i]) * factor for k in range(K, K + c))
            length = c * g.period * scale  # x(K + c) - x(K), an integer on the scale
            assert length.denominator == 1, length
            out.events[e] = Instants(K - 1, values, int(length))
        for t in tasks:
            starts = out.events.get(self.compute[t])
            if starts is None:
                continue
            d = int(self.durations[t] * scale)
            out.starts[t] = starts
            out.ends[t] = Instants(starts.first, tuple(v + d for v in starts.values),
                                   starts.length)
            out.regime_start[t] = starts.values[0]
        return out


# ---------------------------------------------------------------------- the figures


def chain_reports(skeleton: Skeleton, teg: TimedEventGraph, groups: Sequence[Any],
                  paths: Sequence[ChainPath], on_processors: ScheduleTrace | None, *,
                  max_events: int = MAX_EVENTS,
                  daters: DaterTrace | None = None) -> list[ChainReport]:
    """Each chain's figures with a processor per task and on the skeleton's processors.

    Parameters
    ----------
    skeleton, teg : Skeleton, TimedEventGraph
    groups : sequence of GroupReport
        ``analyze_skeleton(skeleton).groups`` (``tasks``, ``live`` and the
        ``cycle_times`` of §4, those of a processor per task, are read).
    paths : sequence of ChainPath
        :func:`chain_paths`.
    on_processors : ScheduleTrace or None
        What the schedule on the skeleton's processors recorded of
        :func:`trace_request` (``schedule.trace``); None: the analysis gave every
        task a processor of its own, whose figures are then repeated.
    max_events : int
        Budget of event firings of the schedule with a processor per task (on the
        parts of the chains alone), and of the outputs one period of a chain's
        figures may hold.
    daters : DaterTrace, optional
        §3's daters of the chains' events in the groups whose regime the analysis
        proved: there the figures with a processor per task are read off them, and
        the schedule with a processor per task runs on the other parts alone (the
        same instants: with a processor per task §4b is §3).

    Returns
    -------
    list of ChainReport
    """
    if not paths:
        return []
    request = trace_request(paths)
    own = None if daters is None else daters.trace(teg.arrays().scale, request.tasks)
    left = request.tasks if own is None else tuple(t for t in request.tasks
                                                   if t not in own.starts)
    if own is None or left:
        cycle_times = {t: c for g in groups for t, c in g.cycle_times.items()}
        engine = trace_schedule(skeleton, teg, groups, processor_per_task(skeleton),
                                TraceRequest(request.events, left), max_events=max_events,
                                cycle_times=cycle_times)
        own = engine if own is None else _merged(own, engine)
    unit = skeleton.unit
    alone = figures_on(paths, own, groups, shared=False, unit=unit, max_events=max_events)
    there = alone if on_processors is None else figures_on(
        paths, on_processors, groups, shared=True, unit=unit, max_events=max_events)
    return [ChainReport(p.tasks, a, b) for p, a, b in zip(paths, alone, there)]


def _merged(daters: ScheduleTrace, engine: ScheduleTrace) -> ScheduleTrace:
    """The daters' trace completed by the engine's for the tasks it lacks (one scale)."""
    assert daters.scale == engine.scale
    out = ScheduleTrace(engine.scale, {**engine.processor_of, **daters.processor_of},
                        daters.requested | engine.requested)
    for name in ("events", "starts", "ends", "regime_start", "undecided"):
        getattr(out, name).update(getattr(engine, name))
        getattr(out, name).update(getattr(daters, name))
    return out


def figures_on(paths: Sequence[ChainPath], trace: ScheduleTrace, groups: Sequence[Any], *,
               shared: bool, unit: str, max_events: int = MAX_EVENTS) -> list[ChainFigures]:
    """Each chain's figures in one schedule's trace (what :func:`chain_reports` gives for
    each platform).

    Parameters
    ----------
    paths : sequence of ChainPath
    trace : ScheduleTrace
        What the schedule recorded of ``trace_request(paths)``.
    groups : sequence of GroupReport
        ``tasks`` and ``live`` are read (a chain through a dead group has no figure).
    shared : bool
        The tasks share processors (§4b: a non-blocking read then sees a message
        posted at its very instant by a writer on its processor); False: a
        processor per task (§3).
    unit : str
        The skeleton's, for the words of a reason.
    max_events : int
        Outputs and samples one period of a chain's figures may hold.
    """
    dead = {t: g for g in groups if not g.live for t in g.tasks}
    return [_figures(p, trace, dead, shared, unit, max_events) for p in paths]


def _figures(path: ChainPath, trace: ScheduleTrace, dead: dict[str, Any], shared: bool,
             unit: str, budget: int) -> ChainFigures:
    """The figures of ``path`` in ``trace``; ``shared``: processors are shared (a
    non-blocking read then sees a message posted at its instant on its own processor)."""
    for t in path.tasks:
        if t in dead:
            return ChainFigures(why_undecided=f"the group of {t} is not live (a deadlock)")
        if t in trace.undecided:
            return ChainFigures(why_undecided=trace.undecided[t])
    sequences = [_sequence(trace, x) for x in path.instants]
    missing = [x.name for x, s in zip(path.instants, sequences) if s is None]
    if missing:
        return ChainFigures(why_undecided=f"{missing[0]} never happens in the periodic regime")
    return _Window(path, trace, shared, [s for s in sequences if s is not None],
                   unit, budget).figures()


def _sequence(trace: ScheduleTrace, x: Instant) -> Instants | None:
    if x.kind == "event":
        return trace.events.get(x.event)
    return (trace.starts if x.kind == "start" else trace.ends).get(x.task)


class _Window:
    """One period of a chain's data paths in a trace (``docs/analysis.md``).

    Every sequence is scaled by ``m`` (a delay's denominator not on the trace's
    scale) and read over the common period ``L`` of the chain's parts: the outputs
    ``k0 - 1 .. k0 - 1 + N`` (``N`` per period) and their sources, found hop by hop
    from the last task back, in numpy arrays (int64, or Python ints where a time
    could pass 2**62).
    """

    def __init__(self, path: ChainPath, trace: ScheduleTrace, shared: bool,
                 sequences: list[Instants], unit: str, budget: int) -> None:
        self.path, self.unit, self.budget = path, unit, budget
        delays = [h.delay * trace.scale for h in path.hops]
        self.m = math.lcm(*(d.denominator for d in delays)) if delays else 1
        m = self.m
        scaled = [Instants(s.first, tuple(v * m for v in s.values), s.length * m)
                  for s in sequences]
        self.sample, self.output = scaled[0], scaled[-1]
        self.hops = [(scaled[1 + 2 * i], scaled[2 + 2 * i], int(d * m),
                      h.blocking or (shared and trace.processor_of[h.writer]
                                     == trace.processor_of[h.reader]))
                     for i, (h, d) in enumerate(zip(path.hops, delays))]
        self.length = math.lcm(*(s.length for s in scaled))
        self.per_period = {s: s.count * (self.length // s.length) for s in scaled}
        self.scale = trace.scale * m
        self.start = max(trace.regime_start[t] for t in path.tasks) * m
        big = max(abs(v) for s in scaled for v in s.values) + 8 * self.length
        self.dtype: Any = np.int64 if big < 2**62 else object

    def _time(self, v: Any) -> Fraction:
        return Fraction(int(v), self.scale)

    def sources(self, k: np.ndarray) -> list[np.ndarray]:
        """For outputs ``k``: the activation index of each task whose data they use,
        last task first (``k`` itself), down to the sample's."""
        out = [k]
        for write, read, delay, at_instant in reversed(self.hops):
            seen = read.at(out[-1])
            out.append(write.last_index(seen - delay, at_instant))
        return out

    def figures(self) -> ChainFigures:
        n_out, n_in = self.per_period[self.output], self.per_period[self.sample]
        period = self._time(self.length)
        if n_out + n_in > self.budget:
            return ChainFigures(why_undecided=(
                f"the chain's parts repeat together every {display_text(period)} {self.unit}, "
                f"{n_out + n_in:,} outputs and samples, more than `max_events`"))
        k0 = self.output.first
        k = np.arange(k0 - 1, k0 + n_out, dtype=np.int64).astype(self.dtype)
        src = self.sources(k)[-1]
        sampled = self.sample.at(src)
        posted = self.output.at(k)
        ages = posted[1:] - sampled[1:]
        # The samples after the one output k0 - 1 uses, one period of them: the first
        # output using each (or a later one), and the first using a later one.
        j = np.arange(0, n_in, dtype=np.int64).astype(self.dtype) + (src[0] + 1)
        first = np.searchsorted(src, j, side="left")
        used = src[first] == j
        first_k = k[first]
        then = np.append(first_k[1:], first_k[:1] + n_out)
        at_j = self.sample.at(j)
        uses = (self.output.at(first_k) - at_j)[used]
        reactions = self.output.at(then) - at_j
        worst = int(np.flatnonzero(used)[int(np.argmax(uses))])
        return ChainFigures(self._time(uses.max()), self._time(ages.max()),
                            self._time(ages.min()), self._time(reactions.max()), None,
                            self._worst(int(first_k[worst])), period)

    def _worst(self, k: int) -> tuple[DataStep, ...]:
        """The data path of output ``k``, shifted by whole periods into the regime the
        schedule reached (its sample at or after every part's regime start)."""
        n_out = self.per_period[self.output]
        shift = 0
        while True:
            ks = [np.array([k + shift * n_out], dtype=np.int64).astype(self.dtype)]
            index = [int(x[0]) for x in self.sources(ks[0])]
            sampled = int(self.sample.at(np.array([index[-1]], dtype=self.dtype))[0])
            if sampled >= self.start:
                break
            shift += -((sampled - self.start) // self.length)  # ceil of the gap
        p = self.path
        index.reverse()  # the sample's first, the output's last

        def step(seq: Instants, x: Instant, i: int) -> DataStep:
            at = int(seq.at(np.array([i], dtype=self.dtype))[0])
            return DataStep(x.task, i + 1, x.name, self._time(at))

        steps = [step(self.sample, p.sample, index[0])]
        for h, (write, read, _, _), i, j in zip(p.hops, self.hops, index, index[1:]):
            steps += [step(write, h.write, i), step(read, h.read, j)]
        steps.append(step(self.output, p.output, index[-1]))
        return tuple(steps)
