"""The engine's rule for trying an event again at the same instant, on parts built by hand.

After a firing, an event whose input place was emptied is not tried again at once
(nothing but its own firing could refill it, and a place it refills puts it back on
the list of events to try); an event with a self-loop is tried again at once, as
before the rule, so the order of the firings is unchanged. No skeleton makes a
self-loop without holding time (its event would fire without end at time 0, and the
schedule leaves such events out): these parts check the counts where it matters.
"""

from tegraph.analysis.processors._engine import PartData, simulate_part


def _loop_part(tokens: int, hold: int) -> PartData:
    # One event, one self-loop place: with hold 0 it can fire for ever at time 0.
    return PartData(n_events=1, p_src=[0], p_dst=[0], p_tokens=[tokens], p_hold=[hold],
                    p_init=[0], p_job=[False], p_cap=[None], compute_task=[-1], duration=[],
                    priority=[], file_index=[], processor=[], n_processors=0, end_event=[],
                    watched={}, snapshot_place=None)


def test_a_self_loop_without_holding_fires_until_the_budget():
    # By hand: each firing takes the token and puts it back at once, so the event
    # stays enabled at time 0 and the 50 firings of the budget are all spent there.
    r = simulate_part(_loop_part(1, 0), 50)
    assert r.budget_spent and r.fired == 50 and r.regime is None


def test_a_self_loop_with_holding_fires_once_per_hold():
    # By hand: hold 3, one token: firings at 0, 3, 6, ...; the state repeats at the
    # instant 3 (one token, available now), a regime of length 3 after one firing.
    r = simulate_part(_loop_part(1, 3), 50)
    assert not r.budget_spent and r.regime[:2] == (0, 3) and r.fired == 1


def test_a_circuit_empties_its_places_and_waits():
    # a -> b -> c -> a, holds 0, 0, 5, one token in a -> b. By hand: at 0, b fires then
    # c (its token comes back to a at 5); at 5, a, b and c fire once each; the state at
    # 10 repeats the one at 5: a regime (5, 10) after 2 + 3 firings, none tried twice.
    d = PartData(n_events=3, p_src=[0, 1, 2], p_dst=[1, 2, 0], p_tokens=[1, 0, 0],
                 p_hold=[0, 0, 5], p_init=[0, 0, 0], p_job=[False] * 3, p_cap=[None] * 3,
                 compute_task=[-1, -1, -1], duration=[], priority=[], file_index=[],
                 processor=[], n_processors=0, end_event=[], watched={}, snapshot_place=None)
    r = simulate_part(d, 50)
    assert r.fired == 5 and r.regime[:2] == (5, 10)
