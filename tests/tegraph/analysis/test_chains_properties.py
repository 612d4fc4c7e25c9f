"""Properties of a chain's latency (spec §4c) on random skeletons.

- the order of the figures: ``age_min <= first_use <= age <= reaction``;
- with every task on a processor of its own, the figures on processors are those
  with ``--no-processors`` (§4b is then §3);
- inside one synchronized group, with a processor per task, ``age`` is the
  segment latency the design tools computed before §4c, from the (max,+) daters
  of the group (``teg.simulate``, over one cyclicity of the regime): that
  computation is kept here, written apart, as the reference;
- where the published bounds' assumptions hold (independent periodic tasks
  linked ASYN/ASYN, each meeting its period), ``reaction`` on processors is at
  most the Davare bound.

The brute-force computation (a plain run carrying sample indices) is in
``test_chains_oracle.py``, with the equality of the maximum reaction and the
maximum age a sample reaches before it is replaced (Günzel et al. 2023).
"""

from __future__ import annotations

import bisect
import itertools
import random
from fractions import Fraction

from hypothesis import HealthCheck, assume, event, given, settings
from hypothesis import strategies as st

from tegraph.api import analyze
from tegraph.design.latency import DAVARE, chain_latency
from tegraph.model.build import build_teg
from tegraph.model.skeleton import Protocol, Skeleton
from tests.tegraph.skeleton_corpus import random_skeleton

SETTINGS = settings(max_examples=150, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])


def random_chain(data: dict, rng: random.Random) -> list[str] | None:
    """A walk along the links of ``data``, each task once, 1 to 4 tasks (None: none)."""
    readers: dict[str, list[str]] = {}
    for link in data["links"]:
        w, r = link["from"].split(":")[0], link["to"].split(":")[0]
        if w != r:
            readers.setdefault(w, []).append(r)
    starts = sorted(data["tasks"])
    chain = [rng.choice(starts)]
    for _ in range(rng.randint(0, 3)):
        nxt = [t for t in readers.get(chain[-1], []) if t not in chain]
        if not nxt:
            break
        chain.append(rng.choice(sorted(nxt)))
    return chain


def with_chain(rng: random.Random) -> Skeleton:
    data = random_skeleton(rng)
    data["chains"] = [random_chain(data, rng)]
    return Skeleton.from_dict(data)


def ordered(f) -> bool:
    return f.age_min <= f.first_use <= f.age <= f.reaction


@SETTINGS
@given(st.randoms(use_true_random=False))
def test_the_figures_are_ordered(rng):
    (c,) = analyze(with_chain(rng), design=False).chains
    for f in (c.on_processors, c.processor_per_task):
        event(f"decided: {f.decided}")
        if f.decided:
            assert ordered(f), f
        else:
            assert (f.first_use, f.age, f.age_min, f.reaction) == (None,) * 4 and f.why_undecided


@SETTINGS
@given(st.randoms(use_true_random=False))
def test_a_processor_per_task_on_processors_is_no_processors(rng):
    data = random_skeleton(rng)
    data["chains"] = [random_chain(data, rng)]
    data.pop("threads", None)  # a thread is one OS thread: one processor
    for name, spec in data["tasks"].items():
        spec["processor"] = f"cpu.{name}"
    (c,) = analyze(Skeleton.from_dict(data), design=False).chains
    on, alone = c.on_processors, c.processor_per_task
    event(f"decided: {on.decided} {alone.decided}")
    if on.decided:  # the same schedule; the trace with a processor per task has a larger share
        assert alone.decided
        assert (on.first_use, on.age, on.age_min, on.reaction) == (
            alone.first_use, alone.age, alone.age_min, alone.reaction)


# ---------------------------------------------------------------------- the segment latency


def segment_age(sk: Skeleton, chain: list[str], transient: tuple[int, int]) -> Fraction | None:
    """The worst age of the data an output of ``chain`` uses, inside one rate-consistent
    group, from the group's daters over one cyclicity of the periodic regime: the design
    tools' computation before §4c (then in ``design/latency.py``), with v1.3's rule for a
    message written at the very instant of a read (a blocking read sees it, a
    non-blocking one does not, with a processor per task)."""
    teg = build_teg(sk)
    port_event = {pt: e for e, attrs in enumerate(teg.transition_attrs)
                  for pt in attrs.get("ports", ())}
    compute = teg.attrs["compute"]
    linked = {x for link in sk.links for x in (link.writer, link.reader)}
    first, last = chain[0], chain[-1]
    sensors = [p for p in sk.tasks[first].inputs if (first, p) not in linked]
    actuators = [p for p in sk.tasks[last].outputs if (last, p) not in linked]
    start = port_event[first, sensors[0]] if sensors else compute[first]
    end, end_d = ((port_event[last, actuators[0]], Fraction(0)) if actuators
                  else (compute[last], sk.tasks[last].duration))
    hops = []
    for a, b in itertools.pairwise(chain):
        link = next(x for x in sk.links if x.writer[0] == a and x.reader[0] == b)
        blocking = link.protocol in (Protocol.ASYN_SYN, Protocol.SYN_SYN)
        hops.append((port_event[link.writer], port_event[link.reader], blocking))
    K, c = transient
    n = 2 * (K + c) + 4 * len(chain) + 8
    while n < 1 << 14:
        daters = teg.simulate(n)
        col = {e: daters.times[:, e].tolist() for e in range(teg.n_transitions)}

        ages = []
        for m in range(n // 2, n // 2 + c):
            o = _oldest(col, hops, start, len(chain) - 1, m, K, n)
            if o is None:
                break
            ages.append(Fraction(col[end][m - 1] - o, daters.scale) + end_d)
        else:
            return max(ages)
        n *= 2
    return None


def _oldest(col, hops, start: int, i: int, k: int, K: int, n: int) -> int | None:
    """The sensor read (scaled) of the data job k of chain[i] uses; None: out of the
    simulated regime, or no data."""
    if k < K or k > n:
        return None
    if i == 0:
        return col[start][k - 1]
    w, r, blocking = hops[i - 1]
    read = col[r][k - 1]
    j = (bisect.bisect_right if blocking else bisect.bisect_left)(col[w], read)
    if j == 0 or j >= n:
        return None
    return _oldest(col, hops, start, i - 1, j, K, n)


@SETTINGS
@given(st.randoms(use_true_random=False))
def test_inside_one_group_the_age_is_the_segment_latency(rng):
    data = random_skeleton(rng)
    data.pop("threads", None)
    chain = random_chain(data, rng)
    sk = Skeleton.from_dict({**data, "chains": [chain]})
    r = analyze(sk, design=False)
    groups = {r.tasks[t].group for t in chain}
    assume(len(groups) == 1)
    g = r.groups[groups.pop()]
    assume(g.rate_consistent and g.transient is not None)
    # One link between each two consecutive tasks (the old computation took the oldest
    # of several, §4c the first).
    assume(all(sum(1 for x in sk.links if (x.writer[0], x.reader[0]) == pair) == 1
               for pair in itertools.pairwise(chain)))
    (c,) = r.chains
    expected = segment_age(sk.restricted_to(g.tasks), chain, g.transient)
    event(f"compared: {expected is not None and c.processor_per_task.decided}")
    if expected is not None and c.processor_per_task.decided:
        assert c.processor_per_task.age == expected


# ---------------------------------------------------------------------- Davare


@st.composite
def independent_tasks(draw):
    """2 to 4 periodic tasks, each its own clock, linked ASYN/ASYN in a line, on one or two
    processors: the published bounds' model."""
    n = draw(st.integers(2, 4))
    tasks = {}
    for i in range(n):
        period = draw(st.sampled_from([2, 3, 4, 5, 6, 10]))
        tasks[f"T{i}"] = {"duration": draw(st.sampled_from(["1/2", 1, 1, "3/2"])),
                          "period": period, "phase": draw(st.sampled_from([0, 0, 1])),
                          "processor": draw(st.sampled_from(["cpu0", "cpu0", "cpu1"])),
                          "inputs": [f"i{i}"] if i else ["s"],
                          "outputs": [f"o{i + 1}"] if i < n - 1 else ["u"]}
    links = [{"from": f"T{i}:o{i + 1}", "to": f"T{i + 1}:i{i + 1}", "protocol": "ASYN/ASYN"}
             for i in range(n - 1)]
    return {"tasks": tasks, "links": links, "chains": [[f"T{i}" for i in range(n)]]}


@SETTINGS
@given(independent_tasks())
def test_reaction_on_processors_is_within_the_davare_bound(data):
    sk = Skeleton.from_dict(data)
    report = analyze(sk)
    (latency,) = report.design.latency
    bound = next(b.value for b in latency.bounds if b.name == DAVARE)
    figures = latency.figures.on_processors
    event(f"bound: {bound is not None}, decided: {figures.decided}")
    if bound is not None and figures.decided:
        assert figures.reaction <= bound, (figures, bound)
    assert chain_latency(sk, data["chains"][0], report).value == figures.first_use
