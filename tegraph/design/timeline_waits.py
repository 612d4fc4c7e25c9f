"""What the jobs of a timeline wait for: reads, rendezvous, writes, and a deadlock's stuck events.

A timing diagram on processors (:mod:`.timeline`) shows processor time; a job also
spends time *waiting*, which takes no processor and which the ORCCAD paper's
synchronizations are about. Given the end ``f_T(k)`` of every drawn job (the
processor time the schedule gave it), the daters of every event follow from the
§4b dynamics: as §3, with each place leaving ``T.compute`` available at ``f_T(k)``
(``docs/skeleton.md`` §4b). :func:`replay_daters` computes them, exactly, up to a
time; from them, for activation k of task T:

- **waiting to start** ``[due, r_T(k))``: its activation is due (its clock has
  ticked, ``x_C.tick(k)``, and its previous activation has ended, ``end_T(k-1)``)
  but its job is not released: a read waits for its writer (ASYN/SYN), a rendezvous
  for its partner (SYN/SYN), or the task for its thread;
- **waiting to end** ``[f_T(k), end_T(k))``: its job is done but its activation is
  not: a write waits for its reader (SYN/ASYN, SYN/SYN);
- **stuck** (a group that is not live): the first event of its chain that never
  fires again, and since when (the firing of the event before it, or the end of its
  last activation): a deadlock drawn where it happens.

Nothing here decides anything: the verdict and the processor time are the
engine's (:func:`~tegraph.analysis.processors.schedule_on_processors`); this
only reads the events between.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from fractions import Fraction

from maxplus.scalar import display_text

from ..analysis.processors import JobInterval, ProcessorSchedule
from ..model.build import activation_end, task_chain
from ..model.limits import shown
from ..model.skeleton import Skeleton
from ..model.teg import TimedEventGraph

__all__ = ["MAX_REPLAYED", "Stuck", "Wait", "replay_daters", "stuck_problems",
           "waits_and_stuck", "waits_until"]

MAX_REPLAYED = 200_000
"""Event firings at most replayed for one drawing (the waits stop there, and say so)."""


@dataclass(frozen=True)
class Wait:
    """A stretch of time activation ``k`` of ``task`` waits, without its processor."""

    task: str
    k: int
    start: Fraction
    end: Fraction
    kind: str
    """``"start"``: due, its job not released (a read, a rendezvous, its thread);
    ``"end"``: its job done, a write waits for its reader."""


@dataclass(frozen=True)
class Stuck:
    """A task of a group that is not live: it waits at ``event`` for ever, from ``since``."""

    task: str
    event: str
    since: Fraction


def replay_daters(teg: TimedEventGraph, finish: Mapping[str, Mapping[int, Fraction]],
                  durations: Mapping[str, Fraction], until: Fraction,
                  skip: frozenset[int] = frozenset(), limit: int = MAX_REPLAYED
                  ) -> tuple[list[list[Fraction]], bool]:
    """The firing times of every event on processors, up to ``until``, from the jobs' ends.

    Parameters
    ----------
    teg : TimedEventGraph
        ``build_teg(skeleton)``.
    finish : mapping
        Task -> activation k -> ``f_T(k)``, for the jobs whose end is known (a task of
        duration 0 needs none: its job ends at its release).
    durations : mapping
        Task -> duration.
    until : Fraction
        No firing after it is computed.
    skip : frozenset of int
        Events left out (they fire infinitely often at time 0: their places into the
        rest are available at once).
    limit : int
        Firings at most.

    Returns
    -------
    (list of list of Fraction, bool)
        Each event's firing times, in order; whether ``limit`` cut them.

    Examples
    --------
    A (duration 1, period 4) writes x, which B (duration 2, no clock) reads ASYN/SYN.
    B's job k ends at 3 + 4(k - 1) (here given): B.read:x fires with A's write, at
    1 + 4(k - 1), and A's write waits for nothing.

    >>> from tegraph.model.build import build_teg
    >>> sk = Skeleton.from_dict({"tasks": {
    ...     "A": {"duration": 1, "period": 4, "outputs": ["x"]},
    ...     "B": {"duration": 2, "inputs": ["x"]}},
    ...     "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]})
    >>> teg = build_teg(sk)
    >>> x, cut = replay_daters(teg, {"A": {1: Fraction(1), 2: Fraction(5)},
    ...                               "B": {1: Fraction(3), 2: Fraction(7)}},
    ...                        {"A": Fraction(1), "B": Fraction(2)}, Fraction(6))
    >>> [str(t) for t in x[teg.transition_names.index("B.read:x")]], cut
    (['1', '5'], False)
    """
    compute = teg.attrs["compute"]
    task_of_compute = {e: t for t, e in compute.items()}
    n = teg.n_transitions
    into: list[list[tuple[int, int, Fraction, Fraction, str | None]]] = [[] for _ in range(n)]
    zero_edges: dict[int, set[int]] = {e: set() for e in range(n) if e not in skip}
    for p in teg.places:
        if p.dst in skip:
            continue
        job = task_of_compute.get(p.src)
        into[p.dst].append((p.src, p.tokens, p.holding, p.initial, job))
        if p.tokens == 0 and p.src not in skip:
            zero_edges[p.dst].add(p.src)
    order = _fireable_order(zero_edges)
    x: list[list[Fraction]] = [[] for _ in range(n)]
    fireable = set(order)
    done = [e not in fireable for e in range(n)]  # never fire: a token-free circuit, skipped
    fired = 0
    progress = True
    while progress:
        progress = False
        for e in order:
            if done[e]:
                continue
            k = len(x[e]) + 1
            when = _next_firing(into[e], k, x, skip, finish, durations, task_of_compute)
            if when is None or when > until:
                if when is not None or _never(into[e], k, done, x):
                    done[e] = True
                continue
            if fired >= limit:
                return x, True
            x[e].append(when)
            fired += 1
            progress = True
    return x, False


def _fireable_order(zero_edges: dict[int, set[int]]) -> list[int]:
    """A topological order of the events off every circuit of token-free places (those
    on one never fire: they are left out)."""
    pending = {e: set(srcs) for e, srcs in zero_edges.items()}
    order: list[int] = []
    ready = [e for e, srcs in pending.items() if not srcs]
    users: dict[int, list[int]] = {}
    for e, srcs in pending.items():
        for s in srcs:
            users.setdefault(s, []).append(e)
    while ready:
        e = ready.pop()
        order.append(e)
        for u in users.get(e, ()):
            pending[u].discard(e)
            if not pending[u]:
                ready.append(u)
    return order


def _next_firing(places, k: int, x: list[list[Fraction]], skip: frozenset[int],
                 finish: Mapping[str, Mapping[int, Fraction]],
                 durations: Mapping[str, Fraction],
                 task_of_compute: Mapping[int, str]) -> Fraction | None:
    """``x_e(k)`` from its input places, or None while an input is not known yet."""
    best = Fraction(0)
    for src, tokens, holding, initial, job in places:
        if k <= tokens:
            t = initial
        elif src in skip:  # fires infinitely often at time 0
            t = holding
        else:
            j = k - tokens
            if len(x[src]) < j:
                return None
            if job is not None:
                if durations[job] == 0:
                    t = x[src][j - 1]
                else:
                    end = finish.get(job, {}).get(j)
                    if end is None:
                        return None
                    t = end
            else:
                t = x[src][j - 1] + holding
        if t > best:
            best = t
    return best


def _never(places, k: int, done: list[bool], x: list[list[Fraction]]) -> bool:
    """Whether firing k can never be computed: an input's source is done with fewer
    firings than it needs."""
    return any(k > tokens and done[src] and len(x[src]) < k - tokens
               for src, tokens, _, _, _ in places)


def waits_and_stuck(skeleton: Skeleton, teg: TimedEventGraph, x: list[list[Fraction]],
                    finish: Mapping[str, Mapping[int, Fraction]], dead: frozenset[str],
                    skip_tasks: frozenset[str]) -> tuple[list[Wait], list[Stuck]]:
    """The waits of every replayed activation, and where each task of a dead group is
    stuck (module docstring); times in the skeleton's unit.

    ``x`` is :func:`replay_daters`'s; ``dead`` the tasks of the groups that are not
    live; ``skip_tasks`` those whose events fire infinitely often at 0 (no waits).
    """
    names = teg.transition_names
    clocks = teg.attrs.get("clocks", {})
    waits: list[Wait] = []
    stuck: list[Stuck] = []
    for t, task in skeleton.tasks.items():
        if t in skip_tasks:
            continue
        chain = task_chain(teg, t)
        compute = teg.attrs["compute"][t]
        end = activation_end(teg, t)
        releases = x[compute]
        ticks = x[clocks[task.clock]] if task.clock is not None else []
        last = x[end.event]
        # end_T(k) of each released activation: its last write, or its job's end
        # without outputs (None: not within the replay).
        ends = [_finish(finish, t, k, releases, task.duration) if end.adds_duration
                else (last[k - 1] if len(last) >= k else None)
                for k in range(1, len(releases) + 1)]
        for k, release in enumerate(releases, start=1):
            due = Fraction(0) if k == 1 else ends[k - 2]
            if due is None:  # pragma: no cover - a release follows its previous end
                break
            if len(ticks) >= k:
                due = max(due, ticks[k - 1])
            if release > due:
                waits.append(Wait(t, k, due, release, "start"))
            f, e = _finish(finish, t, k, releases, task.duration), ends[k - 1]
            if not end.adds_duration and f is not None and e is not None and e > f:
                waits.append(Wait(t, k, f, e, "end"))
        if t in dead:
            known = [e for e in ends if e is not None]
            job_end = {compute: finish.get(t, {}) if task.duration else
                       dict(enumerate(releases, start=1))}
            stuck.append(_stuck_at(t, chain, x, names, known[-1] if known else None, job_end))
    return waits, stuck


def _finish(finish: Mapping[str, Mapping[int, Fraction]], task: str, k: int,
            releases: list[Fraction], duration: Fraction) -> Fraction | None:
    if duration == 0:
        return releases[k - 1] if len(releases) >= k else None
    return finish.get(task, {}).get(k)


def _stuck_at(task: str, chain: list[int], x: list[list[Fraction]], names: tuple[str, ...],
              last_end: Fraction | None, job_end: Mapping[int, Mapping[int, Fraction]]
              ) -> Stuck:
    """The first event of the chain that never fires again, and since when: the firing
    of the event before it (after ``T.compute``, the end of its job: ``job_end``), or
    for the first event the end of the last activation."""
    counts = [len(x[e]) for e in chain]
    for i in range(1, len(chain)):
        if counts[i] < counts[i - 1]:
            before, n = chain[i - 1], counts[i - 1]
            since = job_end[before].get(n) if before in job_end else x[before][n - 1]
            return Stuck(task, names[chain[i]], x[before][n - 1] if since is None else since)
    return Stuck(task, names[chain[0]], last_end or Fraction(0))


def _finishes(intervals: list[JobInterval], durations: dict[str, Fraction]
              ) -> dict[str, dict[int, Fraction]]:
    """``f_T(k)`` of every job whose whole duration is among ``intervals``."""
    got: dict[tuple[str, int], Fraction] = {}
    last: dict[tuple[str, int], Fraction] = {}
    for i in intervals:
        key = (i.task, i.k)
        got[key] = got.get(key, Fraction(0)) + (i.end - i.start)
        last[key] = max(last.get(key, i.end), i.end)
    out: dict[str, dict[int, Fraction]] = {}
    for (t, k), work in got.items():
        if work == durations[t]:
            out.setdefault(t, {})[k] = last[t, k]
    return out


def _replayed(skeleton: Skeleton, teg: TimedEventGraph, intervals: list[JobInterval],
              until: Fraction, dead: frozenset[str], zero: frozenset[str]
              ) -> tuple[list[Wait], list[Stuck], list[list[Fraction]], dict, bool]:
    """The daters replayed from the jobs' ends in ``intervals`` (:mod:`.timeline_waits`)."""
    durations = {t: task.duration for t, task in skeleton.tasks.items()}
    finish = _finishes(intervals, durations)
    skip = frozenset(e for t in zero for e in task_chain(teg, t))
    x, cut = replay_daters(teg, finish, durations, until, skip)
    waits, stuck = waits_and_stuck(skeleton, teg, x, finish, dead, zero)
    return waits, stuck, x, finish, cut


def waits_until(skeleton: Skeleton, teg: TimedEventGraph, drawn: list[JobInterval],
           horizon: Fraction, dead: frozenset[str], zero: frozenset[str]
           ) -> tuple[list[Wait], list[Stuck], dict[tuple[str, int], Fraction]]:
    """What the drawn activations wait for, up to ``horizon`` (cut to it), and the
    release ``r_T(k)`` of each drawn job (from the replayed daters)."""
    waits, stuck, x, _, _ = _replayed(skeleton, teg, drawn, horizon, dead, zero)
    compute = teg.attrs["compute"]
    releases = {}
    for i in drawn:
        fired = x[compute[i.task]]
        if i.k <= len(fired):
            releases[i.task, i.k] = fired[i.k - 1]
    return [w if w.end <= horizon else Wait(w.task, w.k, w.start, horizon, w.kind)
            for w in waits if w.start < horizon], stuck, releases


def stuck_problems(skeleton: Skeleton, teg: TimedEventGraph, s: ProcessorSchedule,
                    intervals: list[JobInterval], until: Fraction, dead: frozenset[str],
                    zero: frozenset[str]) -> list[tuple[Fraction, str]]:
    """When a group that is not live is stuck for good (its last task stuck), and when
    the first job that never ends is released, from the simulated schedule."""
    _, stuck, x, finish, _ = _replayed(skeleton, teg, intervals, until, dead, zero)
    unit = skeleton.unit
    out = []
    if stuck:
        last = max(stuck, key=lambda st: st.since)
        out.append((last.since, f"the deadlock ({', '.join(st.task for st in stuck[:3])}"
                                f"{' ...' if len(stuck) > 3 else ''} stuck from "
                                f"{_at(last.since, unit)})"))
    for t in s.starved:
        releases = x[teg.attrs["compute"][t]]
        ended = finish.get(t, {})
        never = [r for k, r in enumerate(releases, start=1) if k not in ended]
        if never:
            out.append((never[0], f"the job of {t} that never ends (released at "
                                  f"{_at(never[0], unit)})"))
    return out


def _at(value: Fraction, unit: str) -> str:
    return f"{shown(display_text(value), quote=False)} {unit}"
