"""`explore` on a real Dask cluster: one `distributed.LocalCluster` of two worker processes
for the module, on 127.0.0.1 only, always closed.

- the front equals the one `analyze` finds variant by variant, as in this process;
- a worker killed in the middle of a run: the run completes, every variant once in the
  results file;
- the exploring process itself killed: `--resume` completes the table, no duplicate row;
- a scheduler that does not answer: a clear refusal within the timeout.
"""

from __future__ import annotations

import csv
import json
import logging
import math
import os
import signal
import socket
import subprocess
import sys
import time
from fractions import Fraction

import pytest

from tegraph import InputError, load_skeleton
from tegraph.api import explore
from tegraph.design.explore import explore_design
from tegraph.design.explore.space import design_space
from tests.paths import REPO
from tests.tegraph.design.explore.test_exploration import (
    CONTROL,
    EXAMPLES,
    FIG4,
    FIG4_LINKS,
    check_against_reference,
)

distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def cluster():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       host="127.0.0.1", dashboard_address="127.0.0.1:0",
                                       silence_logs=logging.CRITICAL)
    client = distributed.Client(cluster, set_as_default=False)
    try:
        client.wait_for_workers(2, timeout=60)
        yield cluster, client
    finally:
        client.close()
        cluster.close()


def test_distributed_front_is_the_one_analyze_finds(cluster):
    sk = load_skeleton(EXAMPLES / "fig4_pipeline_synchronized.yaml")
    found = check_against_reference(sk, FIG4_LINKS, {"rtc": [5, 10, 20]}, [FIG4],
                                    scheduler=cluster[0].scheduler_address)
    assert found.log.engine == "scheduler" and found.log.workers == 2
    assert found.log.batches > 2  # the work was spread
    local = explore_design(found.space, workers=0)
    assert [(r.variant, r.objectives) for r in found.front] == \
        [(r.variant, r.objectives) for r in local.front]


def rows_of(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def front_of_rows(rows, objectives):
    """The Pareto front of a results file, from its cells alone: not dominated, and
    among equal objective vectors the fewest Rule 2 findings (the `rule2` column).
    An empty cell is an undefined objective, ranked worst (on processors a kept
    design can have one: a free-running group whose latency no response time bounds)."""
    kept = {int(r["variant"]): ([Fraction(r[n]) if r[n] else math.inf for n in objectives],
                                int(r["rule2"]))
            for r in rows if r["kept"] == "true"}

    def beaten(a, b):
        (va, ra), (vb, rb) = a, b
        if va == vb:
            return rb < ra
        return all(y <= x for x, y in zip(va, vb))

    return {v for v, a in kept.items() if not any(beaten(a, b) for b in kept.values())}


def test_a_worker_killed_mid_run_loses_nothing(cluster, tmp_path):
    local_cluster, client = cluster
    sk = load_skeleton(EXAMPLES / "computed_torque.yaml")
    pids = list(client.run(os.getpid).values())
    killed = []

    def kill_one(progress):
        if not killed and progress.judged >= 8:
            os.kill(pids[0], signal.SIGKILL)
            killed.append(progress.judged)

    out = tmp_path / "runs.csv"
    links = ["TG.JS:qd -> TF.TT.JS:qd", "TF.TT.JS:e -> CO.JS:e", "MOD.DYN:M -> CO.JS:M"]
    found = explore(sk, links, chains=[CONTROL], output=out, batch_size=2,
                    scheduler=local_cluster.scheduler_address, progress=kill_one)
    size = found.space.size
    assert killed and killed[0] < size  # killed while variants were still out
    rows = rows_of(out)
    assert sorted(int(r["variant"]) for r in rows) == list(range(size))  # each once
    assert found.exhaustive
    assert {r.variant for r in found.front} == front_of_rows(rows, found.space.objectives)
    client.wait_for_workers(2, timeout=60)  # the nanny restarted it, for the next tests


def test_resume_after_the_process_is_killed_completes_the_table(cluster, tmp_path):
    local_cluster, _ = cluster
    out = tmp_path / "torque.csv"
    command = [sys.executable, "-m", "tegraph.cli", "explore",
               str(EXAMPLES / "computed_torque.yaml"), "--all-links",
               "--chain", ",".join(CONTROL), "--batch-size", "1",
               "--scheduler", local_cluster.scheduler_address, "-o", str(out), "--json"]
    run = subprocess.Popen(command, cwd=REPO, stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and run.poll() is None:
            if out.exists() and out.read_text().count("\n") > 20:
                break
            time.sleep(0.01)
        assert run.poll() is None, "the run ended before it could be killed"
        run.send_signal(signal.SIGKILL)
    finally:
        run.wait(timeout=30)
    before = rows_of(out)
    assert 20 <= len(before) < 256
    # Resumed with adaptive batches: the batch size is no part of the exploration.
    command.remove("--batch-size")
    command.remove("1")
    done = subprocess.run([*command, "--resume"], cwd=REPO, capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    rows = rows_of(out)
    variants = [int(r["variant"]) for r in rows]
    assert len(variants) == len(set(variants)) == 256
    report = json.loads(done.stdout)
    assert report["exhaustive"] is True and report["resumed"] >= len(before) - 1
    assert {f["variant"] for f in report["front"]} == front_of_rows(rows, report["objectives"])


def test_a_scheduler_that_does_not_answer_is_refused_in_time():
    with socket.socket() as s:  # a port that nothing listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    sk = load_skeleton(EXAMPLES / "fig4_pipeline_synchronized.yaml")
    start = time.monotonic()
    with pytest.raises(InputError) as err:
        explore(sk, all_links=True, scheduler=f"tcp://127.0.0.1:{port}", timeout=1)
    assert err.value.where == "scheduler" and "no Dask scheduler answers" in str(err.value)
    assert time.monotonic() - start < 15


def test_distributed_allocation_front_is_the_local_one(cluster, tmp_path):
    # Where the tasks run, on the cluster: the same variants, the same front, and a
    # results file whose `on:` cells name each task's processor.
    from tests.tegraph.design.explore.test_allocation import OBJECTIVES, three
    space = design_space(three(), offer="p,q,r", allocate="tasks", chains=[["A", "C"]],
                         objectives=OBJECTIVES)
    found = explore_design(space, scheduler=cluster[0].scheduler_address, batch_size=1)
    local = explore_design(space, workers=0)
    assert found.log.engine == "scheduler" and len(found.results) == space.size == 5
    assert [(r.variant, r.objectives) for r in found.front] == \
        [(r.variant, r.objectives) for r in local.front]
