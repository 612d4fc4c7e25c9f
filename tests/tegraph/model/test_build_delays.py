"""Communication delays in the timed event graph (spec §4d).

A link's delay is the holding of its place: ASYN/SYN ``W.write -> R.read``,
SYN/ASYN ``R.read -> W.write``. The independent reference is a relay: a task M
of duration d, alone on its own processor, that reads the message ASYN/SYN and
writes it on ASYN/SYN to the reader. Its chain ``M.read -> M.compute -> M.write``
adds d between the writer's write and the reader's read, as the delay does; it is
one server where the delay is infinitely many, so the two agree while the writes
are at least d apart: here d never exceeds the writer's duration, and two writes
of one writer are at least its duration apart (its chain's return place, one token).
"""

from __future__ import annotations

from fractions import Fraction as F

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from tegraph import analyze
from tegraph.model.build import build_teg, holding_sources
from tegraph.model.skeleton import Skeleton

N = 12  # firings compared


def daters(sk: Skeleton, n: int = N) -> dict[str, list[F]]:
    d = build_teg(sk).simulate(n)
    return {name: [F(int(v), d.scale) for v in d.times[:, e]] for e, name in enumerate(d.names)}


def pair(protocol: str, delay: F | None, w_duration: F, w_period: F, r_duration: F,
         relay: bool = False, **extra) -> Skeleton:
    """W (clocked) -> R over ``protocol``; with ``relay``, W -> M -> R over ASYN/SYN with M of
    duration ``delay`` on a processor of its own instead of the delay."""
    tasks = {"W": {"duration": w_duration, "period": w_period, "outputs": ["a"]},
             "R": {"duration": r_duration, "inputs": ["a"], "outputs": ["o"]}}
    if relay:
        tasks["M"] = {"duration": delay, "inputs": ["a"], "outputs": ["b"], "processor": "wire"}
        tasks["R"]["inputs"] = ["b"]
        links = [{"from": "W:a", "to": "M:a", "protocol": "ASYN/SYN"},
                 {"from": "M:b", "to": "R:b", "protocol": "ASYN/SYN"}]
    else:
        link = {"from": "W:a", "to": "R:a", "protocol": protocol}
        if delay is not None:
            link["delay"] = delay
        links = [link]
    return Skeleton.from_dict({"tasks": tasks, "links": links, **extra})


times = st.fractions(min_value=0, max_value=20, max_denominator=6)


@settings(max_examples=60, deadline=None)
@given(w=times.filter(lambda t: t > 0), r=times, p=times.filter(lambda t: t > 0),
       share=st.fractions(min_value=0, max_value=1, max_denominator=5))
def test_a_delay_is_a_relay_task_on_its_own_processor(w, r, p, share):
    d = w * share  # at most the writer's duration (module docstring)
    delayed = daters(pair("ASYN/SYN", d, w, p, r))
    relayed = daters(pair("ASYN/SYN", d, w, p, r, relay=True))
    for name in delayed:  # every event of W, of R and the clock, by name
        mine = name.replace("R.read:a", "R.read:b")
        assert delayed[name] == relayed[mine], name
    assert all(r >= w + d for r, w in zip(delayed["R.read:a"], delayed["W.write:a"]))


def test_the_relay_agrees_on_processors_too():
    # W (1 every 4) and R (2) share the default processor; d = 1: W runs 0-1 and writes
    # at 1, R reads at 2 and runs 2-4 (response 2, period 4); with the relay M alone on
    # "wire" (1-2) R reads at 2 as well.
    a = analyze(pair("ASYN/SYN", F(1), F(1), F(4), F(2)), design=False)
    b = analyze(pair("ASYN/SYN", F(1), F(1), F(4), F(2), relay=True), design=False)
    for t in ("W", "R"):
        assert a.on_processors(t) == b.on_processors(t), t
        assert (a.tasks[t].period, a.tasks[t].overrun_at) == (
            b.tasks[t].period, b.tasks[t].overrun_at)
    assert a.on_processors("R")["response"] == "2" and a.on_processors("R")["period"] == "4"
    assert a.schedulable is b.schedulable is True


def test_an_asyn_syn_delay_by_hand():
    # W: period 10, duration 2, writes at 2 + 10(k-1); the delay 3: R reads at 5, ends at 6.
    x = daters(pair("ASYN/SYN", F(3), F(2), F(10), F(1)), 3)
    assert x["W.write:a"] == [2, 12, 22]
    assert x["R.read:a"] == [5, 15, 25] and x["R.write:o"] == [6, 16, 26]


def test_a_syn_asyn_delay_is_the_request_travelling():
    # SYN/ASYN: W's k-th write waits for R's k-th read (its request) plus the delay 3.
    # R (no clock, duration 1) runs freely and reads at k - 1; W (period 10, duration 2)
    # writes at max(compute + 2, read + 3): max(2, 3) = 3, then max(12, 4) = 12, 22.
    x = daters(pair("SYN/ASYN", F(3), F(2), F(10), F(1)), 3)
    assert x["R.read:a"] == [0, 1, 2] and x["W.write:a"] == [3, 12, 22]
    plain = daters(pair("SYN/ASYN", None, F(2), F(10), F(1)), 3)
    assert plain["W.write:a"] == [2, 12, 22]


def test_own_delay_wins_and_the_network_needs_two_processors():
    def built(link_delay, processors):
        sk = pair("ASYN/SYN", link_delay, F(2), F(10), F(1), network={"delay": 5})
        tasks = sk.to_dict()["tasks"]
        tasks["W"]["processor"], tasks["R"]["processor"] = processors
        data = {**sk.to_dict(), "tasks": tasks}
        return Skeleton.from_dict(data)

    def hold(sk):
        g = build_teg(sk)
        (p,) = [p for p in g.places if p.kind == "asyn-syn"]
        (s,) = [s for p, s in zip(g.places, holding_sources(g)) if p.kind == "asyn-syn"]
        return p.holding, s.kind

    assert hold(built(None, ("p", "q"))) == (5, "network-delay")  # across: the network's
    assert hold(built(None, ("p", "p"))) == (0, "none")  # one processor: none
    assert hold(built(F(0), ("p", "q"))) == (0, "delay")  # its own 0 wins
    assert hold(built(F(1), ("p", "q"))) == (1, "delay")
    # --no-processors keeps the declared processors' delays: the §3 figures move.
    far = analyze(built(None, ("p", "q")), processors=False, design=False)
    near = analyze(built(None, ("p", "p")), processors=False, design=False)
    assert far.tasks["R"].period == near.tasks["R"].period == 10
    assert far.groups[0].transient == near.groups[0].transient
    far_x, near_x = daters(built(None, ("p", "q")), 2), daters(built(None, ("p", "p")), 2)
    assert far_x["R.read:a"] == [7, 17] and near_x["R.read:a"] == [2, 12]


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.sampled_from(["ASYN/SYN", "SYN/ASYN", "ASYN/ASYN"]),
                          st.none() | times, st.booleans()), min_size=1, max_size=4),
       st.none() | times)
def test_every_place_holds_what_its_source_names(links, network):
    # A chain of tasks T0 -> T1 -> ...; T_i on processor p0 or p1 by the flag.
    n = len(links) + 1
    tasks = {f"T{i}": {"duration": 1, "inputs": [] if i == 0 else ["i"],
                       "outputs": [] if i == n - 1 else ["o"]} for i in range(n)}
    tasks["T0"]["period"] = 5
    for i, (_, _, flag) in enumerate(links):
        tasks[f"T{i + 1}"]["processor"] = "p1" if flag else "p0"
    data = {"tasks": tasks, "links": [
        {"from": f"T{i}:o", "to": f"T{i + 1}:i", "protocol": proto,
         **({} if d is None else {"delay": d})} for i, (proto, d, _) in enumerate(links)]}
    if network is not None:
        data["network"] = {"delay": network}
    sk = Skeleton.from_dict(data)
    g = build_teg(sk)
    assert [p.holding for p in g.places] == [s.value(sk) for s in holding_sources(g)]
    # Removing the keys gives the graph of today: the same places, delays aside.
    bare = Skeleton.from_dict({"tasks": tasks, "links": [
        {k: v for k, v in x.items() if k != "delay"} for x in data["links"]]})
    h = build_teg(bare)
    assert [(p.src, p.dst, p.tokens, p.kind) for p in g.places] == [
        (p.src, p.dst, p.tokens, p.kind) for p in h.places]
    assert g.transition_names == h.transition_names
    assert np.all(np.array([p.holding for p in g.places]) >= [p.holding for p in h.places])
