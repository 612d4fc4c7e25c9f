"""The latency of a chain (spec §4c) against a deliberately plain computation.

The plain one shares nothing with ``tegraph.analysis.chains`` or the engine
but the skeleton and its timed event graph: the schedule is fired tick by tick
(integer times, one unit of processor time at a time, as the oracle of
``processors/test_schedule_oracle.py``), for many regime periods; the data is
carried forwards, activation by activation: each job of a chain's task takes
the sample index of the newest message its read sees (§4c's rules, written out
on the lists of instants), and the figures are read off outputs and samples in
two late windows of one period each (the analysis's period only says how long
a window is), where every part has long repeated. No periodic extension, no
index arithmetic, no regime proof: if the analysis's proof, its window or its
lookups were wrong, the two would differ.
"""

from __future__ import annotations

from collections import deque

from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from tegraph.analysis.processors import platform_of
from tegraph.api import analyze
from tegraph.model.build import build_teg
from tegraph.model.skeleton import Skeleton

PROTOCOLS = ["ASYN/ASYN", "ASYN/ASYN", "ASYN/SYN", "ASYN/SYN", "SYN/ASYN", "SYN/SYN"]


@st.composite
def chained_skeletons(draw):
    """2 to 4 tasks T0 -> T1 -> ... linked in a line, the chain through all of them: some
    with a clock (phases too), a sensor, an actuator, a second input read before or after
    the chain's, on one or two processors, priorities declared or rate-monotonic, links
    with a delay of their own or the network's."""
    n = draw(st.integers(2, 4))
    tasks = {}
    declared = draw(st.booleans())
    for i in range(n):
        spec = {"duration": draw(st.sampled_from([0, 1, 1, 2, 3])), "inputs": [],
                "outputs": []}
        if i == 0 or draw(st.booleans()):
            spec["period"] = draw(st.sampled_from([2, 3, 4, 6, 12]))
            spec["phase"] = draw(st.sampled_from([0, 0, 1, 3]))
        elif spec["duration"] == 0:
            spec["duration"] = 1  # no time upstream: infinitely many firings at 0
        spec["processor"] = draw(st.sampled_from(["cpu0", "cpu0", "cpu1"]))
        if declared:
            spec["priority"] = draw(st.integers(1, 3))
        tasks[f"T{i}"] = spec
    if draw(st.booleans()):
        tasks["T0"]["inputs"].append("sensor")
    links = []
    for j in range(1, n):
        tasks[f"T{j - 1}"]["outputs"].append(f"o{j}")
        tasks[f"T{j}"]["inputs"].append(f"i{j}")
        links.append({"from": f"T{j - 1}:o{j}", "to": f"T{j}:i{j}",
                      "protocol": draw(st.sampled_from(PROTOCOLS))})
    if n >= 3 and draw(st.booleans()):  # a side input of the last task, before or after
        tasks["T0"]["outputs"].append("side")
        inputs = tasks[f"T{n - 1}"]["inputs"]
        inputs.insert(draw(st.integers(0, len(inputs))), "side")
        links.append({"from": "T0:side", "to": f"T{n - 1}:side",
                      "protocol": draw(st.sampled_from(["ASYN/ASYN", "ASYN/SYN"]))})
    if draw(st.booleans()):
        tasks[f"T{n - 1}"]["outputs"].append("act")
    # Communication delays (spec §4d): some ASYN/ASYN links declare one (0 too), and a
    # network delay may apply to those between processors; the other protocols then
    # declare 0. A delay on a place (ASYN/SYN, SYN/ASYN) is left out: where messages
    # pile up or a task starves, the schedule engine's memory then grows without bound
    # (its limitation, not the read rule's); a rendezvous refuses a positive delay.
    network = draw(st.sampled_from([None, None, 1, 3]))
    for link in links:
        if link["protocol"] != "ASYN/ASYN":
            if network is not None:
                link["delay"] = 0
        elif (d := draw(st.sampled_from([None, None, 0, 1, 2, 5]))) is not None:
            link["delay"] = d
    out = {"tasks": tasks, "links": links, "chains": [[f"T{i}" for i in range(n)]]}
    if network is not None:
        out["network"] = {"delay": network}
    # A SYN/SYN write joined by two readers is a library limitation; T0 has two outputs.
    return out


def tick_by_tick(sk: Skeleton, end: int, priority: dict[str, int], processor: dict[str, str]):
    """Every event's firing instants, and each task's jobs as [release, start, end], over
    [0, end): each unit [t, t + 1) of a processor to its most urgent pending job."""
    teg = build_teg(sk)
    places = teg.places
    names = list(sk.tasks)
    compute = teg.attrs["compute"]
    task_of = {compute[t]: t for t in names}
    queues = [deque([int(p.initial)] * p.tokens) for p in places]
    into = [[i for i, p in enumerate(places) if p.dst == e] for e in range(teg.n_transitions)]
    out = [[i for i, p in enumerate(places) if p.src == e] for e in range(teg.n_transitions)]
    fired: list[list[int]] = [[] for _ in range(teg.n_transitions)]
    jobs: dict[str, list[list]] = {t: [] for t in names}
    left: dict[str, int] = {}

    def deposit(e: int, at: int) -> None:
        for i in out[e]:
            queues[i].append(at if e in task_of else at + int(places[i].holding))

    for t in range(end):
        again = True
        while again:
            again = False
            for e in range(teg.n_transitions):
                if all(queues[i] and queues[i][0] <= t for i in into[e]):
                    for i in into[e]:
                        queues[i].popleft()
                    fired[e].append(t)
                    again = True
                    task = task_of.get(e)
                    if task is None:
                        deposit(e, t)
                    elif sk.tasks[task].duration == 0:
                        jobs[task].append([t, t, t])
                        deposit(e, t)
                    else:
                        jobs[task].append([t, None, None])
                        left[task] = int(sk.tasks[task].duration)
        for proc in dict.fromkeys(processor.values()):
            ready = [x for x in left if processor[x] == proc]
            if not ready:
                continue
            top = min(ready, key=lambda x: (-priority[x], jobs[x][-1][0], names.index(x)))
            job = jobs[top][-1]
            if job[1] is None:
                job[1] = t
            left[top] -= 1
            if left[top] == 0:
                del left[top]
                job[2] = t + 1
                deposit(compute[top], t + 1)
    return teg, fired, jobs


def plain_figures(sk: Skeleton, end: int, priority, processor, shared: bool, lo: int,
                  length: int):
    """(first_use, age, age_min, reaction) of the skeleton's chain over the outputs and
    samples of [lo, lo + length), by brute force; None where the run is too short. It
    checks on the way that the largest reaction is the largest age a used sample
    reaches before an output with a newer source replaces it."""
    chain = list(sk.chains[0])
    teg, fired, jobs = tick_by_tick(sk, end, priority, processor)
    ports = {port: e for e, attrs in enumerate(teg.transition_attrs) for port in attrs["ports"]}
    linked = {x for link in sk.links for x in (link.writer, link.reader)}
    blocking = {link.reader for link in sk.links
                if link.protocol.value in ("ASYN/SYN", "SYN/SYN")}
    starts = {t: [j[1] for j in jobs[t] if j[1] is not None] for t in chain}
    declared = {t: task.processor or "default" for t, task in sk.tasks.items()}

    def reads(task: str, port: str) -> list[int]:
        inputs = sk.tasks[task].inputs
        after = inputs[inputs.index(port) + 1:]
        if (task, port) in blocking or any((task, q) in blocking for q in after):
            return fired[ports[task, port]]
        return starts[task]

    first, last = chain[0], chain[-1]
    sensors = [p for p in sk.tasks[first].inputs if (first, p) not in linked]
    sample = reads(first, sensors[0]) if sensors else starts[first]
    data: list[int | None] = list(range(len(sample)))  # the sample each job of T0 uses
    for a, b in zip(chain, chain[1:]):
        link = next(x for x in sk.links if x.writer[0] == a and x.reader[0] == b)
        writes = fired[ports[link.writer]]
        at_instant = link.reader in blocking or (shared and processor[a] == processor[b])
        # Visible from w + d (§4d): its own delay, else the network's between the two
        # tasks' declared processors (also with a processor per task), else 0.
        d = (int(link.delay) if link.delay is not None
             else int(sk.network_delay or 0) if declared[a] != declared[b] else 0)
        carried: list[int | None] = []
        for rho in reads(b, link.reader[1]):
            seen = [j for j, w in enumerate(writes)
                    if w + d < rho or (at_instant and w + d == rho)]
            j = max(seen, default=None)  # the newest visible message, "no data" before one
            carried.append(None if j is None or j >= len(data) else data[j])
        data = carried
    actuators = [p for p in sk.tasks[last].outputs if (last, p) not in linked]
    outputs = fired[ports[last, actuators[0]]] if actuators else [
        j[2] for j in jobs[last] if j[2] is not None]
    n = min(len(outputs), len(data))
    ks = [k for k in range(n) if lo <= outputs[k] < lo + length]
    if not ks or any(data[k] is None for k in ks):
        return None
    ages = [outputs[k] - sample[data[k]] for k in ks]
    uses, reactions, replaced = [], [], []
    for j in (j for j in range(len(sample)) if lo <= sample[j] < lo + length):
        first_use = next((k for k in range(n) if data[k] is not None and data[k] >= j), None)
        newer = next((k for k in range(n) if data[k] is not None and data[k] > j), None)
        if newer is None:
            return None
        if data[first_use] == j:
            uses.append(outputs[first_use] - sample[j])
            # The age this sample reaches at the output before a newer one replaces it.
            replaced.append(outputs[newer] - sample[j])
        reactions.append(outputs[newer] - sample[j])
    if not uses:
        return None
    # Günzel et al. (ECRTS 2023): the maximum reaction time is the maximum age a sample
    # reaches before it is replaced (an overwritten sample reacts no later than the
    # used one before it).
    assert max(reactions) == max(replaced)
    return max(uses), max(ages), min(ages), max(reactions)


def _compare(sk: Skeleton, figures, priority, processor, shared: bool) -> None:
    assert figures.decided, figures.why_undecided
    length = int(figures.period)
    late = 4 * length + 2 * int(figures.reaction) + 40
    end = late + 3 * length + 2 * int(figures.reaction) + 40
    mine = (figures.first_use, figures.age, figures.age_min, figures.reaction)
    for lo in (late, late + length):
        assert plain_figures(sk, end, priority, processor, shared, lo, length) == mine, lo


def plain_on_processors(sk: Skeleton, figures) -> tuple:
    """The plain computation of the skeleton's first chain on its processors, over two late
    windows of ``figures.period`` (which must agree): (first_use, age, age_min, reaction)."""
    plat = platform_of(sk, analyze(sk, design=False, processors=False).groups)
    length = int(figures.period)
    late = 4 * length + 2 * int(figures.reaction) + 40
    end = late + 3 * length + 2 * int(figures.reaction) + 40
    found = {plain_figures(sk, end, plat.priority, plat.processor_of, True, lo, length)
             for lo in (late, late + length)}
    assert len(found) == 1, found
    return found.pop()


SETTINGS = settings(max_examples=150, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])


@SETTINGS
@given(chained_skeletons())
def test_chain_figures_match_a_plain_run_on_processors_and_alone(data):
    sk = Skeleton.from_dict(data)
    r = analyze(sk, design=False)
    (c,) = r.chains
    # With a processor per task first (the figures §3's daters give).
    alone = {t: t for t in sk.tasks}
    event(f"decided alone: {c.processor_per_task.decided}, on processors: "
          f"{c.on_processors.decided}")
    if c.processor_per_task.decided:
        _compare(sk, c.processor_per_task, {t: 1 for t in sk.tasks}, alone, False)
    if c.on_processors.decided:
        plat = platform_of(sk, r.groups)
        _compare(sk, c.on_processors, plat.priority, plat.processor_of, True)
