"""Drive a search over an engine: batches out, verdicts in, the front kept exact.

The driver asks the search for variants, sends them in batches to an engine
(this process, or Dask workers: :mod:`.dask_engine`), and as each batch
comes back records its verdicts (the caller's ``record`` appends them to the
results file at once), updates the Pareto front and feeds the search.
Verdicts already known (read back from a results file) are fed without being
judged again.

**Batch size.** A batch should take long enough that the per-task cost of
Dask (about a millisecond of scheduling and a round trip) is negligible, and
be short enough that the workers stay balanced and a killed worker loses
little. Unless told, the driver starts with batches of one variant, measures
the time a variant takes, then sizes batches to about
:data:`TARGET_BATCH_SECONDS` of work, never more than the remaining work spread
over twice the workers, and keeps two batches per worker in flight.

**The local engine.** Without a scheduler address or a number of workers, the
driver judges in this process and stays there until the measured work pays for a
cluster. The rule, checked after each batch: on a machine of at least
:data:`MIN_CLUSTER_CORES` cores, once the cost of a variant is measured
(:data:`MEASURED_VARIANTS` variants judged after the first, or a quarter of
:data:`LOCAL_CLUSTER_WORTH_SECONDS` of work), when the work left (the median cost
of those variants, the first one left out, times the variants the search may still
send) exceeds :data:`LOCAL_CLUSTER_WORTH_SECONDS`, a local Dask cluster of one
worker process per core takes over; otherwise everything is judged here. The
first variant is left out because it also fills the caches of the incremental
judge: it may cost many times a later one, and judged alone it made a cluster look
worth its start where judging in process is faster.

Why these bounds (``benchmarks/bench_explore.py --crossover``, results in
``benchmarks/results/explore.md``): a worker judges slower than this process (it
fills its own caches, and its batches pass through the scheduler), and the driver,
the scheduler and the workers share the cores; on two cores a local cluster of two
was never faster than this process, whatever the work measured, so no crossover
exists there and the default never starts one. From :data:`MIN_CLUSTER_CORES` cores
the workers' number outweighs their cost; the threshold keeps the cluster's start,
and the workers' cold caches, a small part of the work.
"""

from __future__ import annotations

import math
import os
import statistics
import time
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Protocol

from .evaluate import ANALYZED, PRUNED, VariantResult, evaluate_batch
from .prune import DEAD_REASON
from .search import ExhaustiveSearch, ParetoFront, ParetoLocalSearch
from .space import DesignSpace

__all__ = ["LOCAL_CLUSTER_WORTH_SECONDS", "MEASURED_VARIANTS", "MIN_CLUSTER_CORES",
           "TARGET_BATCH_SECONDS",
           "Progress", "RunLog", "max_local_workers", "run_search"]

TARGET_BATCH_SECONDS = 0.5
"""Seconds of work a batch of variants aims at (see the module's account)."""
LOCAL_CLUSTER_WORTH_SECONDS = 60.0
"""Seconds of work left (measured in this process) above which a local cluster of one
worker per core is started, on :data:`MIN_CLUSTER_CORES` cores or more (module
docstring)."""
MIN_CLUSTER_CORES = 4
"""Cores a machine needs for the default to start a local cluster (module docstring)."""
MEASURED_VARIANTS = 8
"""Variants judged in this process, after the first, before their cost decides the engine."""
MAX_BATCH = 512


@dataclass
class Progress:
    """What a progress display shows."""

    judged: int
    """Variants with a verdict (resumed ones included)."""
    total: int
    """Variants the search will judge at most."""
    front: int
    seconds: float
    rate: float
    """Variants judged per second in this run."""


@dataclass
class RunLog:
    """How the work was done."""

    engine: str = "in-process"
    workers: int = 1
    address: str | None = None
    batches: int = 0
    batch_sizes: list[int] = field(default_factory=list)
    seconds_per_variant: float | None = None


class Engine(Protocol):
    """What :func:`run_search` asks of an engine (in process, or Dask)."""

    # Read only: run_search never sets them (DaskEngine counts its workers live).
    @property
    def kind(self) -> str:
        """The engine's name, as the report states it."""

    @property
    def address(self) -> str | None:
        """The scheduler's address (None in process)."""

    @property
    def workers(self) -> int:
        """The workers that judge variants."""

    @property
    def in_flight(self) -> int:
        """Batches submitted and not yet returned."""

    @property
    def capacity(self) -> int:
        """Batches worth keeping in flight at once."""

    def submit(self, variants: list[int]) -> None:
        """Start judging one batch of variants."""

    def wait(self) -> list[VariantResult]:
        """The verdicts of the next batch that finishes."""

    def close(self) -> None:
        """Release what the engine holds."""


class InProcessEngine:
    """Judge batches here, one after the other."""

    kind = "in-process"
    address = None
    workers = 1

    def __init__(self, space: DesignSpace) -> None:
        self.space = space
        self._queue: deque[list[int]] = deque()

    @property
    def in_flight(self) -> int:
        """Batches submitted and not yet judged."""
        return len(self._queue)

    @property
    def capacity(self) -> int:
        """Batches to hold: one (it is judged when waited for)."""
        return 1

    def submit(self, variants: list[int]) -> None:
        """Queue one batch of variants."""
        self._queue.append(variants)

    def wait(self) -> list[VariantResult]:
        """Judge the oldest queued batch, here, and return its verdicts."""
        return evaluate_batch(self.space, self._queue.popleft())

    def close(self) -> None:
        """Drop the batches not yet judged."""
        self._queue.clear()


def run_search(space: DesignSpace, search: ExhaustiveSearch | ParetoLocalSearch,
               front: ParetoFront, *, scheduler: str | None = None, workers: int | None = None,
               known: dict[int, VariantResult] | None = None,
               record: Callable[[Sequence[VariantResult]], None] | None = None,
               progress: Callable[[Progress], None] | None = None,
               batch_size: int | None = None, timeout: float = 10.0
               ) -> tuple[dict[int, VariantResult], RunLog]:
    """Run ``search`` to its end; return every verdict (known ones included) and the log.

    Parameters
    ----------
    space : DesignSpace
    search : ExhaustiveSearch or ParetoLocalSearch
    front : ParetoFront
        Updated as verdicts arrive.
    scheduler : str, optional
        Address of a running Dask scheduler.
    workers : int, optional
        0: this process; N: a local Dask cluster of N worker processes; None: decide
        from the measured cost (module docstring).
    known : dict, optional
        Verdicts from an earlier run (not judged again, not recorded again).
    record : callable, optional
        Called with each list of new verdicts as they arrive.
    progress : callable, optional
        Called with a :class:`Progress` after each batch.
    batch_size : int, optional
        Variants per batch; default adaptive.
    timeout : float
        Seconds to wait for a scheduler (and its first worker).
    """
    run = _Run(space, search, front, dict(known or {}), record, batch_size)
    engine = _engine(space, scheduler, workers, timeout)
    automatic = scheduler is None and workers is None
    log = RunLog()
    try:
        while True:
            run.fill(engine, log)
            if engine.in_flight == 0:
                break
            run.receive(engine.wait(), progress)
            if automatic and run.worth_a_local_cluster(engine):
                engine.close()
                engine = _engine(space, None, max_local_workers(), timeout)
        log.engine, log.address = engine.kind, engine.address
        log.workers = engine.workers
        log.seconds_per_variant = statistics.median(run.costs) if run.costs else None
    finally:
        engine.close()
    return run.judged, log


class _Run:
    """The state of one :func:`run_search`: the verdicts, the recent costs, the counts."""

    def __init__(self, space: DesignSpace, search: ExhaustiveSearch | ParetoLocalSearch,
                 front: ParetoFront, known: dict[int, VariantResult],
                 record: Callable[[Sequence[VariantResult]], None] | None,
                 batch_size: int | None) -> None:
        self.search, self.front, self.known = search, front, known
        self.record, self.batch_size = record, batch_size
        self.judged: dict[int, VariantResult] = {}
        self.costs: deque[float] = deque(maxlen=64)
        self.steady: deque[float] = deque(maxlen=64)
        """The costs of the variants judged after the first one (warm caches)."""
        self.measured = 0.0
        """Seconds of judging measured in this run."""
        self.analyzed = 0
        self.fresh = 0
        self.start = time.perf_counter()
        self.total = space.size if isinstance(search, ExhaustiveSearch) \
            else min(space.size, search.budget)

    def settle(self, results: Sequence[VariantResult], fresh: bool) -> None:
        """Verdicts into the front and the search; the fresh ones recorded."""
        for r in results:
            self.analyzed += r.judged == ANALYZED and r.variant not in self.judged
            self.judged[r.variant] = r
            self.front.add(r)
            self.search.feed(r)
        if fresh and self.record is not None and results:
            self.record(results)

    def size(self, workers: int) -> int:
        """The next batch's size: about TARGET_BATCH_SECONDS of work at the median cost,
        spread over the workers while few variants are left."""
        if self.batch_size:
            return self.batch_size
        if not self.costs:
            return 1
        per = max(statistics.median(self.costs), 1e-6)
        left = _left(self.search, self.analyzed)
        spread = math.ceil(left / (2 * workers)) if left else 1
        return max(1, min(int(TARGET_BATCH_SECONDS / per), MAX_BATCH, spread))

    def fill(self, engine: Engine, log: RunLog) -> None:
        """Proposals until the engine is full or the search has none: the pruned and the
        known settled at once, the others submitted."""
        known = self.known
        while engine.in_flight < engine.capacity:
            analyze, pruned = self.search.propose(self.size(engine.workers))
            if not analyze and not pruned:
                return
            self.settle([known[v] for v in pruned if v in known], fresh=False)
            self.settle([VariantResult(v, PRUNED, live=False, reason=DEAD_REASON)
                         for v in pruned if v not in known], fresh=True)
            self.settle([known[v] for v in analyze if v in known], fresh=False)
            to_judge = [v for v in analyze if v not in known]
            if to_judge:
                engine.submit(to_judge)
                log.batches += 1
                log.batch_sizes.append(len(to_judge))

    def receive(self, results: list[VariantResult],
                progress: Callable[[Progress], None] | None) -> None:
        """A batch's verdicts settled, their costs kept, the progress told."""
        costs = [r.seconds for r in results if r.judged == ANALYZED]
        self.steady.extend(costs[1:] if not self.costs else costs)
        self.costs.extend(costs)
        self.measured += sum(costs)
        self.fresh += len(results)
        self.settle(results, fresh=True)
        seconds = time.perf_counter() - self.start
        if progress is not None:
            progress(Progress(len(self.judged), self.total, len(self.front.members), seconds,
                              self.fresh / seconds if seconds > 0 else 0.0))

    def worth_a_local_cluster(self, engine: Engine) -> bool:
        """In process, idle, on a machine of MIN_CLUSTER_CORES cores or more, the cost of
        a variant measured, and more work left than LOCAL_CLUSTER_WORTH_SECONDS at that
        cost: a local cluster pays (the rule of the module docstring)."""
        if engine.kind != "in-process" or engine.in_flight or \
                max_local_workers() < MIN_CLUSTER_CORES:
            return False
        if len(self.steady) < MEASURED_VARIANTS and \
                self.measured < LOCAL_CLUSTER_WORTH_SECONDS / 4:
            return False  # not measured yet: the first variants cost more than the rest
        per = statistics.median(self.steady or self.costs)
        return per * _left(self.search, self.analyzed, ahead=True) > LOCAL_CLUSTER_WORTH_SECONDS


def max_local_workers() -> int:
    """The most local worker processes ``explore`` starts: one per core of this machine
    (a process more than the cores only shares them, and each holds a copy of the
    design space and its caches).

    >>> max_local_workers() >= 1
    True
    """
    return os.cpu_count() or 1


def _left(search: ExhaustiveSearch | ParetoLocalSearch, done: int, ahead: bool = False) -> int:
    """Variants the search may still send for analysis: all of them for the exhaustive
    search; for the local search, those of the current generation, or with ``ahead``
    the rest of its budget."""
    if isinstance(search, ExhaustiveSearch):
        return max(search.to_analyze - done, 0)
    left = max(search.budget - search.analyzed, 0)
    return left if ahead else min(left, search.pending)


def _engine(space: DesignSpace, scheduler: str | None, workers: int | None, timeout: float
            ) -> Engine:
    if scheduler is None and not workers:
        return InProcessEngine(space)
    from .dask_engine import DaskEngine  # distributed is imported only when used

    return DaskEngine(space, scheduler, workers or 1, timeout)
