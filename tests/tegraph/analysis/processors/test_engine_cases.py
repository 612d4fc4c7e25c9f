"""The §4b engine on parts built by hand, each figure derived by hand in the comments.

Every case runs on each loop (``conftest.py``); on a compiled one the part must
run there to its end (the Python loop is refused). Last, the times each compiled
loop leaves to the next: past its bound (2**62, 2**189), Fractions, affine times,
bools, negative times.
"""

from __future__ import annotations

import dataclasses
from fractions import Fraction

import pytest

from tegraph.analysis.processors import _engine
from tegraph.analysis.processors._engine import PartData, PartResult, simulate_part
from tegraph.analysis.processors._loops import current
from tegraph.analysis.sensitivity.affine import Cut, lin
from tests.tegraph.analysis.processors.engine_loops import built, compiled_module, use_loop


def simulate(d: PartData, budget: int, keep: bool = True) -> PartResult:
    """``simulate_part`` on the loop of the run: a compiled one must take the part."""
    with use_loop(current().first, only=True):
        return simulate_part(d, budget, keep)


def part(**kw) -> PartData:
    """A part with no task, no processor, no clock; ``kw`` replaces what a case has."""
    base = PartData(n_events=0, p_src=[], p_dst=[], p_tokens=[], p_hold=[], p_init=[],
                    p_job=[], p_cap=[], compute_task=[], duration=[], priority=[],
                    file_index=[], processor=[], n_processors=0, end_event=[], watched={},
                    snapshot_place=None)
    return dataclasses.replace(base, **kw)


def preemption() -> PartData:
    # Event 0 (z) never fires: its only input, a self-loop, is empty. It holds the
    # places that release L (event 1, task 0: duration 5, priority 1) at 0 and H
    # (event 2, task 1: duration 2, priority 2) at 1, on one processor.
    return part(n_events=3, p_src=[0, 0, 0], p_dst=[0, 1, 2], p_tokens=[0, 1, 1],
                p_hold=[0, 0, 0], p_init=[0, 0, 1], p_job=[False] * 3, p_cap=[None] * 3,
                compute_task=[-1, 0, 1], duration=[5, 2], priority=[1, 2], file_index=[0, 1],
                processor=[0, 0], n_processors=1, end_event=[None, None])


def test_a_more_urgent_job_preempts_and_the_other_resumes():
    # L runs 0-1, H preempts it at 1 and runs 1-3, L resumes with 4 left: 3-7. Then
    # nothing happens again: ("stop", 7) after 2 firings.
    r = simulate(preemption(), 100)
    assert r.intervals == [(0, 0, 1, 0, 1), (0, 1, 3, 1, 1), (0, 3, 7, 0, 1)]
    assert r.jobs == [[[0, 7]], [[1, 3]]]
    assert r.regime == ("stop", 7) and r.fired == 2 and not r.budget_spent


def test_without_intervals_the_figures_are_the_same():
    r = simulate(preemption(), 100, keep=False)
    assert r.intervals == [] and r.jobs == [[[0, 7]], [[1, 3]]] and r.regime == ("stop", 7)


def test_zero_durations_end_at_their_release():
    # z (never fires) releases T0 (event 1) at 0; its job ends at once and its job
    # place releases T1 (event 2) at 0, which ends at once too: no processor time.
    d = part(n_events=3, p_src=[0, 0, 1], p_dst=[0, 1, 2], p_tokens=[0, 1, 0],
             p_hold=[0, 0, 0], p_init=[0, 0, 0], p_job=[False, False, True],
             p_cap=[None] * 3, compute_task=[-1, 0, 1], duration=[0, 0], priority=[1, 1],
             file_index=[0, 1], processor=[0, 0], n_processors=1, end_event=[None, None])
    r = simulate(d, 100)
    assert r.jobs == [[[0, 0]], [[0, 0]]] and r.intervals == []
    assert r.regime == ("stop", 0) and r.fired == 2


def clocked_overrun(cap: int | None) -> PartData:
    # A clock (event 0, self-loop hold 2) releases task T (event 1: duration 3, its
    # job self-loop lets one job run at a time) through place 1 (capped at ``cap``).
    # States are compared at the ticks; T's overruns are watched.
    return part(n_events=2, p_src=[0, 0, 1], p_dst=[0, 1, 1], p_tokens=[1, 0, 1],
                p_hold=[2, 0, 0], p_init=[0, 0, 0], p_job=[False, False, True],
                p_cap=[None, cap, None], compute_task=[-1, 0], duration=[3], priority=[1],
                file_index=[0], processor=[0], n_processors=1, end_event=[None],
                watched={0: [0]}, snapshot_place=0)


def test_an_overrun_with_a_capped_place_reaches_a_regime():
    # Jobs [0, 3], [3, 6], [6, 9], [9, 12]: one per 3 while the clock ticks every 2.
    # Ticks: at 0 k=1, slack 0; at 2 k=2, none ended: -1 (the overrun, at 3 firings:
    # tick, T, tick; the search goes on to 3 + max(3, 100 // 10) = 13 firings); at 4
    # k=3, slack 1 - 2 = -1; at 6 k=4, 2 - 3 (the job ending at 6 counts after the
    # instant); at 8 and 10, -2 and -2 (3 - 5 at 10: the job of 9 ended).
    # States at the ticks: at 6 place 1 holds the token of 4, T's job ends now
    # (pending 0); at 12 it holds those of 8 and 10, pending 0 again: above the cap 1
    # the counts are one key, and place 1 only gained a token, never taken the
    # instant it came since 0 (it is not tight): the regime (6, 12), place 1 growing
    # by 1, after 10 firings. The run stops there, before the job of 9 ends at 12.
    r = simulate(clocked_overrun(1), 100)
    assert r.regime[:2] == (6, 12) and r.regime[4] == {1: 1}
    assert r.fired == 10 and not r.budget_spent and r.after_overrun is None
    assert r.overrun_at == {0: 2}
    assert r.tick_log[0] == [(0, 1, 0), (2, 2, -1), (4, 3, -1), (6, 4, -1), (8, 5, -2),
                             (10, 6, -2)]
    assert r.jobs[0] == [[0, 3], [3, 6], [6, 9], [9, None]]
    assert r.regime[2].pending == (0,) and r.regime[3].pending == (0,)


def test_an_overrun_cuts_the_search_for_a_regime():
    # Place 1 uncapped: its count grows at every comparison, no state repeats. The
    # overrun at 3 firings limits the run to 13 (above): the 13th firing is the
    # tick at 14, and at 15 T's job ends and T could fire again: the budget is spent
    # there, after the overrun.
    r = simulate(clocked_overrun(None), 100)
    assert r.regime is None and r.budget_spent and r.after_overrun == 3 and r.fired == 13
    assert r.jobs[0][-1] == [12, 15] and r.overrun_at == {0: 2}


def test_the_budget_cuts_before_any_overrun():
    # 4 firings: tick and T at 0, tick at 2 (the overrun there, at 3 firings: the
    # limit is min(4, 3 + max(3, 4 // 10)), the budget), T at 3: the budget is spent
    # at 4, where the clock could tick.
    r = simulate(clocked_overrun(None), 4)
    assert r.budget_spent and r.fired == 4 and r.after_overrun is None
    assert r.overrun_at == {0: 2} and r.jobs[0] == [[0, 3], [3, None]]
    assert r.tick_log[0] == [(0, 1, 0), (2, 2, -1)]


def two_clocks() -> PartData:
    # Clock A (event 0, period 1) fills place 2, clock B (event 1, period 2) place 3;
    # event 2 (no task) takes one token of each. States at B's ticks.
    return part(n_events=3, p_src=[0, 1, 0, 1], p_dst=[0, 1, 2, 2], p_tokens=[1, 1, 0, 0],
                p_hold=[1, 2, 0, 0], p_init=[0, 0, 0, 0], p_job=[False] * 4,
                p_cap=[None, None, 0, None], compute_task=[-1] * 3, snapshot_place=1)


def test_a_place_off_every_circuit_grows_once_it_is_not_tight():
    # At 0 all three fire, event 2 taking the tokens of 0 the instant they came (place
    # 2 tight at 0); at 1 A fires; at 2 A, B and event 2, which takes A's token of 1.
    # Place 2 (cap 0: every count one key) holds 0, 1, 2 tokens at 0, 2, 4: at 2 the
    # state does not repeat the one at 0 (place 2 was tight then), at 4 it repeats the
    # one at 2, place 2 growing by 1: the regime (2, 4), after 3 + 1 + 3 + 1 firings.
    r = simulate(two_clocks(), 100)
    assert r.regime[:2] == (2, 4) and r.regime[4] == {2: 1} and r.fired == 8


def test_a_queue_grows_past_its_room(engine_loop):
    # The same with place 2 exact: no state repeats. Each period of 2 has 4 firings
    # (A, B, event 2 at its start, A in its middle): the budget of 1000 is spent at
    # 500, after 250 periods: A put 500 tokens in place 2, event 2 took 250 of them.
    d = dataclasses.replace(two_clocks(), p_cap=[None] * 4)
    r = simulate(d, 1000)
    assert r.budget_spent and r.fired == 1000 and r.regime is None
    state = (_engine._Part(d) if engine_loop == "python"
             else _engine._CompiledPart(compiled_module(engine_loop), d, True))
    assert state.run(1000) == 500 and state.lengths() == [1, 1, 250, 0]


# ---------------------------------------------------------------- the Python loop's cases

@pytest.mark.parametrize("times", [
    pytest.param(lambda x: x * 2 ** 60, id="past-2**62"),
    pytest.param(lambda x: Fraction(x, 3), id="fraction"),
    pytest.param(lambda x: x * 10 ** 30, id="huge"),
    pytest.param(lambda x: x * 2 ** 187, id="past-2**189")])
def test_scaled_times_give_the_scaled_figures(times):
    # The overrun case with every time scaled: the same figures, scaled, whichever
    # loop takes the part (or takes it over from another).
    d = clocked_overrun(1)
    d = dataclasses.replace(d, p_hold=[times(h) for h in d.p_hold], duration=[times(3)])
    r = simulate_part(d, 100)
    assert r.regime[:2] == (times(6), times(12)) and r.fired == 10
    assert r.jobs[0] == [[times(a), b if b is None else times(b)] for a, b in
                         [(0, 3), (3, 6), (6, 9), (9, None)]]
    assert [t for t, _, _ in r.tick_log[0]] == [times(t) for t in range(0, 12, 2)]


BOUND = {"int64": 2 ** 62, "wide": 2 ** 189}


@pytest.mark.parametrize("loop", list(BOUND))
def test_a_time_past_the_bound_stops_the_compiled_loop(loop):
    # Times of bound / 4: the first ones fit the loop's bound, the tick at 6 / 4 of
    # it does not: the compiled loop stops and says so (the next loop runs the part).
    if not built(loop):
        pytest.skip(f"the {loop} loop is not built")
    unit = BOUND[loop] // 4
    d = dataclasses.replace(clocked_overrun(1), p_hold=[2 * unit, 0, 0], duration=[3 * unit])
    assert compiled_module(loop).covers(d)
    assert _engine._CompiledPart(compiled_module(loop), d, True).run(100) is None
    assert simulate_part(d, 100).regime[:2] == (6 * unit, 12 * unit)


@pytest.mark.parametrize("loop", list(BOUND))
@pytest.mark.parametrize("change", [
    pytest.param(lambda bound: dict(p_hold=[True, 0, 0]), id="bool"),
    pytest.param(lambda bound: dict(p_init=[-1, 0, 0]), id="negative"),
    pytest.param(lambda bound: dict(p_hold=[bound + 1, 0, 0]), id="past-the-bound"),
    pytest.param(lambda bound: dict(duration=[lin(3, 1, Cut(Fraction(0), 0))]), id="affine"),
    pytest.param(lambda bound: dict(duration=[Fraction(3)]), id="fraction"),
    pytest.param(lambda bound: dict(priority=[2 ** 63]), id="priority"),
    pytest.param(lambda bound: dict(compute_task=[-1, 1]), id="no-such-task")])
def test_what_a_compiled_loop_does_not_cover(loop, change):
    if not built(loop):
        pytest.skip(f"the {loop} loop is not built")
    module = compiled_module(loop)
    assert module.covers(clocked_overrun(1))
    assert module.covers(dataclasses.replace(clocked_overrun(1), p_hold=[BOUND[loop], 0, 0]))
    assert not module.covers(dataclasses.replace(clocked_overrun(1), **change(BOUND[loop])))


@pytest.mark.parametrize("loop", list(BOUND))
def test_one_loop_alone_refuses_what_it_cannot_run(loop):
    # The switch's `only`: a part the loop does not cover, or whose times pass its
    # bound (the case above), raises instead of running on the next loop.
    if not built(loop):
        pytest.skip(f"the {loop} loop is not built")
    unit = BOUND[loop] // 4
    past = dataclasses.replace(clocked_overrun(1), p_hold=[2 * unit, 0, 0], duration=[3 * unit])
    with use_loop(loop, only=True), pytest.raises(RuntimeError, match="to its end"):
        simulate_part(past, 100)
    fraction = dataclasses.replace(clocked_overrun(1), duration=[Fraction(3)])
    with use_loop(loop, only=True), pytest.raises(RuntimeError, match="does not cover"):
        simulate_part(fraction, 100)
    with use_loop(loop):  # the next loops take both over
        assert simulate_part(past, 100).regime[:2] == (6 * unit, 12 * unit)
        assert simulate_part(fraction, 100).regime[:2] == (6, 12)


def test_an_unknown_loop_is_refused():
    with pytest.raises(ValueError, match="unknown loop 'fast'"), use_loop("fast"):
        pass
