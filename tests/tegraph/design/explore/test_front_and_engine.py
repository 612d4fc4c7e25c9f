"""The front of ``explore`` as a user reads it, and the engine it runs on by default.

- one row per distinct objective vector, with its count of ties (``--all-ties`` lists
  every design; the JSON report keeps them all, each with its count);
- a design where a task runs free that the input design runs on a clock is not kept,
  unless asked (``--free-running``);
- by default the designs are judged in this process until the measured work pays for a
  local cluster (the first, cold variant does not decide it);
- ``--workers`` is at most the machine's cores.

Nothing here starts a Dask cluster: the engine's decision is read from the driver.
"""

from __future__ import annotations

import json
import os
from fractions import Fraction as F

import jsonschema
import pytest
from typer.testing import CliRunner

from tegraph import InputError, Skeleton
from tegraph.api import explore
from tegraph.cli import app
from tegraph.design.explore import explore_design
from tegraph.design.explore import run as run_module
from tegraph.design.explore.evaluate import ANALYZED, VariantResult
from tegraph.design.explore.prune import DeadlockOracle
from tegraph.design.explore.run import (
    LOCAL_CLUSTER_WORTH_SECONDS,
    MIN_CLUSTER_CORES,
    InProcessEngine,
    _Run,
)
from tegraph.design.explore.search import ExhaustiveSearch, ParetoFront
from tegraph.design.explore.space import design_space
from tests.paths import REPO

FIG4 = str(REPO / "examples" / "fig4_pipeline_unsynchronized.yaml")
SCHEMA = json.loads((REPO / "docs" / "report.schema.json").read_text())


# ------------------------------------------------------------------ ties

def test_ties_are_one_row_with_their_count(tmp_path):
    # Figure 4's pipe-line, four tasks on private 10 ms clocks, every link chosen among the
    # four protocols: 64 variants, all kept, each with period ratio 1 and load
    # 1/10 + 2/10 + 2/10 + 1/10 = 3/5 (a link changes neither a task's period, its clock's,
    # nor its work). The tie-breaker, Rule 2, counts each SYN/SYN link and each ASYN/ASYN
    # link between groups of one rate (all are 10 ms): 0 only when every link is
    # ASYN/SYN or SYN/ASYN, 2^3 = 8 designs, all on the front with equal objectives.
    # The row shown is the first by number: every link ASYN/SYN, (1, 1, 1) in mixed
    # radix 4 with ASYN/ASYN = 0, ASYN/SYN = 1: 16 + 4 + 1 = 21.
    out = CliRunner().invoke(app, ["explore", FIG4, "--all-links", "--workers", "0"])
    assert out.exit_code == 0, out.output
    text = out.output
    assert "Pareto front: 8 design(s) in 1 distinct objective vector(s)" in text
    assert "(7 not listed: --all-ties lists them)" in text
    rows = [line.split() for line in text.splitlines() if line.startswith("  21 ")]
    assert len(rows) == 1 and rows[0][-1] == "8"
    table = text[text.index("Pareto front"):text.index("pruning rules")]
    assert not any(line.startswith(f"  {v} ") for v in (22, 25, 26, 37, 38, 41, 42)
                   for line in table.splitlines())

    every = CliRunner().invoke(app, ["explore", FIG4, "--all-links", "--workers", "0",
                                     "--all-ties"]).output
    listed = [int(line.split()[0]) for line in every.splitlines()
              if line.startswith("  ") and line.split()[0].isdigit()]
    assert listed == [21, 22, 25, 26, 37, 38, 41, 42]

    doc = json.loads(CliRunner().invoke(app, ["explore", FIG4, "--all-links", "--workers",
                                              "0", "--json"]).output)
    jsonschema.validate(doc, SCHEMA)
    assert [e["variant"] for e in doc["front"]] == [21, 22, 25, 26, 37, 38, 41, 42]
    assert {e["ties"] for e in doc["front"]} == {8}


def test_distinct_vectors_each_get_a_row():
    # The synchronized pipe-line at 5, 10 or 20 ms (docs example): 10 and 20 trade period
    # for load, two vectors, no tie: nothing is said about ties.
    sk = Skeleton.from_dict({"clocks": {"rtc": {"period": 10}}, "tasks": {
        "A": {"duration": 1, "clock": "rtc", "outputs": ["x"]},
        "B": {"duration": 2, "inputs": ["x"]}},
        "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]})
    found = explore(sk, clocks={"rtc": [5, 10]}, objectives=["period", "load"], workers=0)
    # rtc 5: period ratio 5/10 = 1/2, load 3/5; rtc 10: ratio 1, load 3/10
    assert [[r.objectives["load"] for r in g] for g in found.distinct_front] == [
        [F(3, 5)], [F(3, 10)]]
    from tegraph.report.explore_text import render_exploration

    text = render_exploration(found)
    assert "Pareto front: 2 design(s)\n" in text and "ties" not in text.split("Pareto")[1]


# ------------------------------------------------------------------ free-running tasks

# A on its 10 ms clock writes x, which B (no clock) reads. ASYN/SYN: B runs after each
# A, in A's group, period 10. ASYN/ASYN: nothing ties B to a clock; it runs back to back
# in the processor's idle time (9 ms of every 10), a job every 2 ms of it: period 20/9.
CLOCKED_READER = {"tasks": {"A": {"duration": 1, "period": 10, "outputs": ["x"]},
                            "B": {"duration": 2, "inputs": ["x"]}},
                  "links": [{"from": "A:x", "to": "B:x", "protocol": "ASYN/SYN"}]}


def test_a_design_that_frees_a_task_is_not_kept_unless_asked():
    sk = Skeleton.from_dict(CLOCKED_READER)
    links = {"A:x -> B:x": ["ASYN/SYN", "ASYN/ASYN"]}
    found = explore(sk, links, workers=0)
    # before: both kept (the ASYN/ASYN design schedulable, B's period 20/9)
    assert found.kept == 1 and found.rejected == {"a free-running task": 1}
    freed = found.results[1]  # ASYN/ASYN is the second choice given
    assert freed.reason.startswith("free-running: B would run free")
    assert freed.schedulable is True and freed.meets is False
    asked = explore(sk, links, workers=0, free_running=True)
    assert asked.kept == 2
    assert asked.results[1].objectives["load"] == F(1, 10) + F(2) / F(20, 9)  # = 1


def test_a_task_free_in_the_input_design_is_kept_free():
    # The logger of the input design has no clock (by design: it runs in the idle time);
    # varying A's clock leaves it free in every variant, which is the design, not a choice.
    data = {"tasks": {"A": {"duration": 1, "period": 10, "outputs": ["x"]},
                      "logger": {"duration": 2, "inputs": ["x"]}},
            "links": [{"from": "A:x", "to": "logger:x", "protocol": "ASYN/ASYN"}]}
    found = explore(Skeleton.from_dict(data), clocks={"A.clock": [10, 20]}, workers=0)
    assert found.kept == 2 and "a free-running task" not in found.rejected


def test_free_running_on_the_command_line(tmp_path):
    path = tmp_path / "s.json"
    path.write_text(json.dumps(CLOCKED_READER))
    runner = CliRunner()
    plain = runner.invoke(app, ["explore", str(path), "--link", "A:x -> B:x=ASYN/SYN,"
                                "ASYN/ASYN", "--workers", "0", "--json"])
    asked = runner.invoke(app, ["explore", str(path), "--link", "A:x -> B:x=ASYN/SYN,"
                                "ASYN/ASYN", "--workers", "0", "--json", "--free-running"])
    plain_doc, asked_doc = json.loads(plain.output), json.loads(asked.output)
    jsonschema.validate(plain_doc, SCHEMA)
    assert plain_doc["kept"] == 1 and plain_doc["constraints"]["free_running"] is False
    assert asked_doc["kept"] == 2 and asked_doc["constraints"]["free_running"] is True


# ------------------------------------------------------------------ the engine

def _run_of(n_variants: int) -> _Run:
    """The driver's state for a space of ``n_variants`` variants (one clock's periods)."""
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 1000}}})
    space = design_space(sk, clocks={"A.clock": list(range(1000, 1000 + n_variants))})
    return _Run(space, ExhaustiveSearch(space, DeadlockOracle(space)),
                ParetoFront(space.objectives), {}, None, None)


def _judged(first: int, seconds: list[float]) -> list[VariantResult]:
    return [VariantResult(first + i, ANALYZED, seconds=s) for i, s in enumerate(seconds)]


def test_a_cold_first_variant_does_not_start_a_cluster(monkeypatch):
    monkeypatch.setattr(os, "cpu_count", lambda: MIN_CLUSTER_CORES)
    run = _run_of(512)
    engine = InProcessEngine(None)  # an idle in-process engine (never given work here)
    # Given costs: the first variant 1.0 (caches filled, modules imported), the next
    # ones 0.001 each, so that the 512 cost about 1.5 in all. Were the first cost to
    # decide alone, 1.0 x 511 left = 511 would pass the threshold and start a cluster.
    run.receive(_judged(0, [1.0]), None)
    assert not run.worth_a_local_cluster(engine)
    run.receive(_judged(1, [0.001] * 10), None)
    assert not run.worth_a_local_cluster(engine)  # 0.001 x 501 = 0.5 left


def test_measured_work_that_pays_starts_a_cluster(monkeypatch):
    monkeypatch.setattr(os, "cpu_count", lambda: MIN_CLUSTER_CORES)
    run = _run_of(512)
    engine = InProcessEngine(None)
    per = 2 * LOCAL_CLUSTER_WORTH_SECONDS / 400  # 400 variants left would be twice it
    run.receive(_judged(0, [per] * 9), None)
    # 8 measured after the first: the cost is known
    assert run.worth_a_local_cluster(engine)  # per x 503 > the threshold
    # On fewer cores a local cluster never paid (benchmarks/results/explore.md): the
    # same measured work stays in this process.
    for cores in (1, 2, MIN_CLUSTER_CORES - 1):
        monkeypatch.setattr(os, "cpu_count", lambda cores=cores: cores)
        assert not run.worth_a_local_cluster(engine)


def test_a_slow_variant_is_measured_at_once(monkeypatch):
    # Variants of a large skeleton take seconds: a quarter of the threshold in all is
    # measurement enough, whatever the count.
    monkeypatch.setattr(os, "cpu_count", lambda: MIN_CLUSTER_CORES)
    run = _run_of(512)
    engine = InProcessEngine(None)
    slow = LOCAL_CLUSTER_WORTH_SECONDS / 6
    run.receive(_judged(0, [slow, slow]), None)
    assert run.worth_a_local_cluster(engine)


def test_the_default_judges_a_cheap_space_in_this_process():
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 1000}}})
    space = design_space(sk, clocks={"A.clock": list(range(1000, 1512))})
    found = explore_design(space)  # workers=None: the default
    assert found.log.engine == "in-process" and len(found.results) == 512


# ------------------------------------------------------------------ bounded workers

def test_workers_beyond_the_cores_are_refused(monkeypatch, tmp_path):
    monkeypatch.setattr(run_module.os, "cpu_count", lambda: 2)
    sk = Skeleton.from_dict({"tasks": {"A": {"duration": 1, "period": 10}}})
    with pytest.raises(InputError, match=r"from 0 to 2 \(this machine's cores\), got 3") as e:
        explore(sk, clocks={"A.clock": [10, 20]}, workers=3)
    assert e.value.where == "workers"
    path = tmp_path / "s.yaml"
    path.write_text("tasks:\n  A: {duration: 1, period: 10}\n")
    out = CliRunner().invoke(app, ["explore", str(path), "--clock", "A.clock=10,20",
                                   "--workers", "64"])
    assert out.exit_code == 2
    (line,) = out.output.strip().splitlines()
    assert line.startswith("tegraph: error: --workers: expected a number of local worker "
                           "processes from 0 to 2")
