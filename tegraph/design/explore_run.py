"""Drive a search over an engine: batches out, verdicts in, the front kept exact.

The driver asks the search for variants, sends them in batches to an engine
(this process, or Dask workers: :mod:`.explore_dask`), and as each batch
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
driver judges the first batch in this process; when the remaining work
(measured cost times the variants left) exceeds :data:`LOCAL_CLUSTER_WORTH_SECONDS`,
it starts a local Dask cluster with one worker process per core, otherwise it
finishes in this process (starting a cluster costs about two seconds: see
``benchmarks/results/explore.md``).
"""

from __future__ import annotations

import math
import os
import statistics
import time
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from .explore_eval import ANALYZED, PRUNED, VariantResult, evaluate_batch
from .explore_prune import DEAD_REASON
from .explore_search import ExhaustiveSearch, ParetoFront, ParetoLocalSearch
from .explore_space import DesignSpace

__all__ = ["LOCAL_CLUSTER_WORTH_SECONDS", "TARGET_BATCH_SECONDS", "Progress", "RunLog",
           "run_search"]

TARGET_BATCH_SECONDS = 0.5
LOCAL_CLUSTER_WORTH_SECONDS = 6.0
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
        return len(self._queue)

    @property
    def capacity(self) -> int:
        """Batches to hold: one (it is judged when waited for)."""
        return 1

    def submit(self, variants: list[int]) -> None:
        self._queue.append(variants)

    def wait(self) -> list[VariantResult]:
        return evaluate_batch(self.space, self._queue.popleft())

    def close(self) -> None:
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
    known = dict(known or {})
    judged: dict[int, VariantResult] = {}
    log = RunLog()
    costs: deque[float] = deque(maxlen=64)
    start = time.perf_counter()
    fresh_count = 0
    total = space.size if isinstance(search, ExhaustiveSearch) \
        else min(space.size, search.budget)
    engine = _engine(space, scheduler, workers, timeout)
    automatic = scheduler is None and workers is None

    analyzed = [0]

    def settle(results: Sequence[VariantResult], fresh: bool) -> None:
        for r in results:
            analyzed[0] += r.judged == ANALYZED and r.variant not in judged
            judged[r.variant] = r
            front.add(r)
            search.feed(r)
        if fresh and record is not None and results:
            record(results)

    def size() -> int:
        if batch_size:
            return batch_size
        if not costs:
            return 1
        per = max(statistics.median(costs), 1e-6)
        left = _left(search, analyzed[0])
        spread = math.ceil(left / (2 * engine.workers)) if left else 1
        return max(1, min(int(TARGET_BATCH_SECONDS / per), MAX_BATCH, spread))

    try:
        while True:
            while engine.in_flight < engine.capacity:
                analyze, pruned = search.propose(size())
                if not analyze and not pruned:
                    break
                settle([known[v] for v in pruned if v in known], fresh=False)
                settle([VariantResult(v, PRUNED, live=False, reason=DEAD_REASON)
                        for v in pruned if v not in known], fresh=True)
                settle([known[v] for v in analyze if v in known], fresh=False)
                todo = [v for v in analyze if v not in known]
                if todo:
                    engine.submit(todo)
                    log.batches += 1
                    log.batch_sizes.append(len(todo))
            if engine.in_flight == 0:
                break
            results = engine.wait()
            costs.extend(r.seconds for r in results if r.judged == ANALYZED)
            fresh_count += len(results)
            settle(results, fresh=True)
            seconds = time.perf_counter() - start
            if progress is not None:
                progress(Progress(len(judged), total, len(front.members), seconds,
                                  fresh_count / seconds if seconds > 0 else 0.0))
            if automatic and engine.kind == "in-process" and costs and engine.in_flight == 0 \
                    and (os.cpu_count() or 1) > 1 \
                    and statistics.median(costs) * _left(search, analyzed[0], ahead=True) \
                    > LOCAL_CLUSTER_WORTH_SECONDS:
                engine.close()
                engine = _engine(space, None, os.cpu_count() or 1, timeout)
        log.engine, log.address = engine.kind, engine.address
        log.workers = engine.workers
        log.seconds_per_variant = statistics.median(costs) if costs else None
    finally:
        engine.close()
    return judged, log


def _left(search: ExhaustiveSearch | ParetoLocalSearch, done: int, ahead: bool = False) -> int:
    """Variants the search may still send for analysis: all of them for the exhaustive
    search; for the local search, those of the current generation, or with ``ahead``
    the rest of its budget."""
    if isinstance(search, ExhaustiveSearch):
        return max(search.to_analyze - done, 0)
    left = max(search.budget - search.analyzed, 0)
    return left if ahead else min(left, search.pending)


def _engine(space: DesignSpace, scheduler: str | None, workers: int | None, timeout: float):
    if scheduler is None and not workers:
        return InProcessEngine(space)
    from .explore_dask import DaskEngine  # distributed is imported only when used

    return DaskEngine(space, scheduler, workers or 1, timeout)
