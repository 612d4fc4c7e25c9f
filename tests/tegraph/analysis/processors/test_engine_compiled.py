"""The compiled loops of the §4b engine against the Python loop, on random parts.

Each loop must give the same :class:`PartResult` (compared by ``repr``, so an int
is not a bool or a Fraction) and compare the same states at the same instants
(every call of ``_compare`` recorded: the instant, the key and the snapshot).
The random parts are built directly (any graph, holds, caps, clocks, watched
ticks, processors, durations 0), and from random skeletons through the whole
schedule. This module picks the loops itself (``engine_loops``): ``EVERY_LOOP``
tells ``conftest.py`` to run it once rather than once per loop.
"""

from __future__ import annotations

import random

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tegraph.analysis.analyze import analyze_skeleton
from tegraph.analysis.processors import _engine, schedule_on_processors
from tegraph.analysis.processors._engine import PartData, simulate_part
from tegraph.analysis.processors.trace import TraceRequest
from tegraph.model.build import build_teg
from tegraph.model.skeleton import Skeleton
from tests.tegraph.analysis.processors.engine_loops import (
    LOOPS,
    built,
    compiled_module,
    use_loop,
)
from tests.tegraph.skeleton_corpus import random_skeleton

pytestmark = pytest.mark.skipif(not all(map(built, LOOPS)),
                                reason="the compiled loops are not built")
COMPILED = [loop for loop in LOOPS if loop != "python"]

PROPS = settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])


EVERY_LOOP = True
"""This module picks the loops itself: ``conftest.py`` runs it once, on no loop of its own."""


def run_on(loop: str, d: PartData, budget: int, keep: bool):
    """The result of ``simulate_part`` on one loop, and every state it compared.

    On a compiled loop, the part must run there to its end: the Python loop (and
    the loops after this one) are refused.
    """
    states = []
    original = _engine._compare

    def spy(part, seen, now):
        pending, lengths = part.pending(now), part.lengths()
        states.append((now, part.key(now, pending, lengths),
                       part.snapshot(now, pending, lengths)))
        return original(part, seen, now)

    with pytest.MonkeyPatch.context() as mp, use_loop(loop, only=True):
        mp.setattr(_engine, "_compare", spy)
        if loop != "python":
            assert compiled_module(loop).covers(d)
        result = simulate_part(d, budget, keep)
    return result, states


def assert_same(d: PartData, budget: int, keep: bool, loops=COMPILED) -> None:
    python = run_on("python", d, budget, keep)
    for loop in loops:
        compiled = run_on(loop, d, budget, keep)
        assert repr(compiled[0]) == repr(python[0]), loop
        assert compiled[0] == python[0], loop
        assert repr(compiled[1]) == repr(python[1]), loop


@st.composite
def parts(draw, scale: int = 1) -> PartData:
    """Any part the schedule could hand the engine, and some it could not.

    Events, tasks on some of them (most with a job self-loop: one job at a time,
    most released by a clock), clocks on the others (a self-loop holding its
    period, one token), places
    anywhere else (job places where they leave a compute event) with tokens,
    holds and caps; an event left without input gets one (else it fires without
    end at 0). States are compared at one clock's ticks, or at every instant.
    """
    n = draw(st.integers(1, 6))
    n_tasks = draw(st.integers(0, n))
    computes = draw(st.permutations(range(n)))[:n_tasks]
    compute_task = [-1] * n
    for task, e in enumerate(computes):
        compute_task[e] = task
    times = st.sampled_from([0, 0, 1, 2, 3, 5])
    inits = st.sampled_from([0, 0, 1, 4])
    caps = st.sampled_from([None, None, 0, 1, 2])
    places = []  # (src, dst, tokens, hold, init, cap)
    clocks = []
    for e in range(n):
        if compute_task[e] >= 0 and draw(st.integers(0, 9)) < 7:
            places.append((e, e, 1, 0, draw(inits), None))
        elif compute_task[e] < 0 and draw(st.integers(0, 9)) < 6:
            clocks.append(len(places))
            places.append((e, e, 1, draw(st.integers(1, 6)), draw(inits), None))
    for e in computes:  # most tasks released by a clock
        if clocks and draw(st.integers(0, 9)) < 7:
            places.append((places[draw(st.sampled_from(clocks))][0], e, 0, 0, 0, draw(caps)))
    places += draw(st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, n - 1),
                                      st.integers(0, 2), times, inits, caps), max_size=8))
    for e in set(range(n)) - {p[1] for p in places}:
        places.append((draw(st.integers(0, n - 1)), e, draw(st.integers(0, 2)), draw(times),
                       draw(inits), draw(caps)))
    snapshot_place = draw(st.sampled_from([None, *clocks]))
    src, dst, tokens, hold, init, cap = (list(x) for x in zip(*places))
    n_procs = draw(st.sampled_from([1, 1, 2]))
    watched = draw(st.dictionaries(st.integers(0, n - 1),
                                   st.lists(st.integers(0, n_tasks - 1), max_size=2)
                                   if n_tasks else st.just([]), max_size=3))
    return PartData(
        n_events=n, p_src=src, p_dst=dst, p_tokens=tokens,
        p_hold=[h * scale for h in hold], p_init=[a * scale for a in init],
        p_job=[compute_task[s] >= 0 for s in src], p_cap=cap, compute_task=compute_task,
        duration=[draw(st.sampled_from([0, 1, 2, 3, 4])) * scale for _ in range(n_tasks)],
        priority=[draw(st.integers(1, 3)) for _ in range(n_tasks)],
        file_index=draw(st.permutations(range(n_tasks))),
        processor=[draw(st.integers(0, n_procs - 1)) for _ in range(n_tasks)],
        n_processors=n_procs,
        end_event=[draw(st.one_of(st.none(), st.integers(0, n - 1))) for _ in range(n_tasks)],
        watched=watched, snapshot_place=snapshot_place, preemptive=draw(kinds(n_procs)),
        **draw(recorded(n, n_tasks)))


def recorded(n_events: int, n_tasks: int):
    """What a chain asks the engine to record (``PartData.logged`` and ``started``): some
    events' firings and some tasks' job starts, or nothing."""
    return st.fixed_dictionaries({
        "logged": st.lists(st.integers(0, n_events - 1), unique=True, max_size=n_events),
        "started": st.lists(st.integers(0, n_tasks - 1), unique=True, max_size=n_tasks)
        if n_tasks else st.just([])})


def kinds(n_procs: int):
    """``PartData.preemptive``: empty (every processor preemptive) or a flag per processor,
    False where it never interrupts a running job (§4d)."""
    return st.one_of(st.just([]), st.lists(st.booleans(), min_size=n_procs,
                                           max_size=n_procs))


@st.composite
def clocked_tasks(draw, scale: int = 1) -> PartData:
    """Tasks each on its own clock (events 2i: tick, 2i + 1: compute), one job at a
    time, on one or two processors, some reading another's job end: the usual part,
    where jobs preempt each other and clocked tasks overrun."""
    n_tasks = draw(st.integers(1, 4))
    src, dst, tokens, hold, init, cap = [], [], [], [], [], []
    clocks = []  # the self-loop place of each tick

    def place(s, t, m, h, a, c=None):
        for values, x in zip((src, dst, tokens, hold, init, cap), (s, t, m, h, a, c)):
            values.append(x)

    for i in range(n_tasks):
        tick, job = 2 * i, 2 * i + 1
        clocks.append(len(src))
        place(tick, tick, 1, draw(st.integers(1, 8)) * scale, draw(st.integers(0, 2)) * scale)
        place(tick, job, 0, 0, 0, draw(st.sampled_from([None, 1])))
        place(job, job, 1, 0, 0)
        if i and draw(st.booleans()):  # it reads an earlier task's job end
            place(2 * draw(st.integers(0, i - 1)) + 1, job, draw(st.integers(0, 1)), 0, 0,
                  draw(st.sampled_from([None, 1])))
    n_procs = draw(st.sampled_from([1, 1, 2]))
    return PartData(
        n_events=2 * n_tasks, p_src=src, p_dst=dst, p_tokens=tokens, p_hold=hold,
        p_init=init, p_job=[s % 2 == 1 for s in src], p_cap=cap,
        compute_task=[e // 2 if e % 2 else -1 for e in range(2 * n_tasks)],
        duration=[draw(st.integers(0, 4)) * scale for _ in range(n_tasks)],
        priority=[draw(st.integers(1, 3)) for _ in range(n_tasks)],
        file_index=list(range(n_tasks)),
        processor=[draw(st.integers(0, n_procs - 1)) for _ in range(n_tasks)],
        n_processors=n_procs, end_event=[None] * n_tasks,
        watched={2 * i: [i] for i in range(n_tasks)},
        snapshot_place=draw(st.sampled_from([None, *clocks])),
        preemptive=draw(kinds(n_procs)), **draw(recorded(2 * n_tasks, n_tasks)))


@PROPS
@given(parts(), st.integers(1, 120), st.booleans())
def test_compiled_loop_is_the_python_loop(d, budget, keep):
    assert_same(d, budget, keep)


@PROPS
@given(clocked_tasks(), st.integers(1, 300), st.booleans())
def test_compiled_loop_is_the_python_loop_on_clocked_tasks(d, budget, keep):
    assert_same(d, budget, keep)


@settings(PROPS, max_examples=100)
@given(parts(scale=10**15), st.integers(1, 120))
def test_large_times_within_int64(d, budget):
    # Times of 10**15 and more (a thousand of them before the bound of 2**62).
    assert_same(d, budget, True)


@settings(PROPS, max_examples=100)
@given(st.one_of(parts(scale=10**40 + 7), clocked_tasks(scale=10**40 + 7)), st.integers(1, 120))
def test_times_past_int64_on_the_wide_loop(d, budget):
    # Times of some 2**133 (as the group benchmarks' scaled times), all three words
    # of a wide time used: the int64 loop takes no part with such a time, the wide
    # loop takes them all.
    assert_same(d, budget, True, loops=["wide"])


@settings(PROPS, max_examples=60)
@given(st.randoms(use_true_random=False), st.sampled_from([0, 2, 99]))
def test_random_skeletons_schedule_the_same(rng, processors):
    # On the default processor, or tasks dealt round two or each on its own.
    data = random_skeleton(rng)
    if processors:
        data.pop("threads", None)  # a thread is one OS thread: one processor
        for i, spec in enumerate(data["tasks"].values()):
            spec["processor"] = f"cpu{i % processors}"
    sk = Skeleton.from_dict(data)
    teg, groups = build_teg(sk), analyze_skeleton(sk).groups
    # Every event's firings and every task's job starts recorded (what chains read).
    trace = TraceRequest(tuple(range(teg.n_transitions)), tuple(sk.tasks))
    schedules = []
    for loop in LOOPS:
        with use_loop(loop):
            s = schedule_on_processors(sk, teg, groups, trace=trace)
            schedules.append(repr(s) + repr(s.trace))
    assert schedules[0] == schedules[1] == schedules[2]


def test_corpus_seeds_schedule_the_same():
    # The fixed corpus (seeds 0..39), as the other corpus tests, on both loops.
    for seed in range(40):
        sk = Skeleton.from_dict(random_skeleton(random.Random(seed)))
        teg, groups = build_teg(sk), analyze_skeleton(sk).groups
        compiled = repr(schedule_on_processors(sk, teg, groups))
        for loop in LOOPS[1:]:
            with use_loop(loop):
                assert repr(schedule_on_processors(sk, teg, groups)) == compiled, (seed, loop)
