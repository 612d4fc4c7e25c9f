"""Run batches of variants on Dask ``distributed``: a local cluster or the user's scheduler.

The design space (the parsed skeleton and the choices) goes to each worker
once, as a worker plugin: the scheduler hands it to every worker that joins,
including one restarted after a crash, and the batches then carry only
variant numbers. A batch whose worker dies is rescheduled by Dask on another
worker; one that has killed workers ``distributed.scheduler.allowed-failures``
times comes back as :class:`distributed.KilledWorker` and is split into single
variants, each tried once more before it is recorded as failed.

Local clusters (and the tests' clusters) listen on 127.0.0.1 only, their HTTP
endpoint on a free loopback port (never 8787, which a user's dashboard may hold).
"""

from __future__ import annotations

import logging
import signal
import time
import uuid
from collections.abc import Sequence
from typing import Any, cast

from distributed import Client, LocalCluster, WorkerPlugin, as_completed, get_worker
from distributed.scheduler import KilledWorker

from ...errors import InputError, TegraphError
from .evaluate import FAILED, VariantResult, evaluate_batch
from .space import DesignSpace

__all__ = ["DaskEngine", "judge_on_worker", "local_cluster"]


class _SpacePlugin(WorkerPlugin):
    """Holds the design space on a worker (shipped once per worker)."""

    def __init__(self, space: DesignSpace) -> None:
        self.space = space


def judge_on_worker(plugin: str, variants: Sequence[int]) -> list[VariantResult]:
    """The task a worker runs: judge ``variants`` of the space its plugin holds."""
    # The plugin registered under this name by DaskEngine (distributed types it as any plugin).
    space = cast(_SpacePlugin, get_worker().plugins[plugin]).space
    return evaluate_batch(space, variants)


def local_cluster(workers: int) -> LocalCluster:
    """A cluster of ``workers`` single-threaded worker processes on this machine
    (loopback only, quiet).

    A Ctrl-C while the workers start would leave a half-built cluster that
    fails noisily at exit: it is held until the cluster is up, which is then
    closed and the interrupt raised.
    """
    interrupted: list[int] = []
    try:
        previous = signal.signal(signal.SIGINT, lambda *_: interrupted.append(1))
    except ValueError:  # not the main thread: Ctrl-C cannot reach here anyway
        previous = None
    try:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               host="127.0.0.1", dashboard_address="127.0.0.1:0",
                               silence_logs=logging.CRITICAL)
    finally:
        if previous is not None:
            signal.signal(signal.SIGINT, previous)
    if interrupted:
        cluster.close()
        raise KeyboardInterrupt
    return cluster


class DaskEngine:
    """Batches of variants in flight on a Dask cluster, answered as they complete.

    Parameters
    ----------
    space : DesignSpace
    address : str, optional
        A running scheduler (``tcp://HOST:8786``); None starts a local cluster.
    workers : int
        Worker processes of the local cluster.
    timeout : float
        Seconds to wait for the scheduler to answer and for a first worker.
    """

    def __init__(self, space: DesignSpace, address: str | None = None, workers: int = 2,
                 timeout: float = 10.0) -> None:
        self.cluster = None
        self._pending: dict[Any, list[int]] = {}
        self._retried: set[int] = set()
        self._asked, self._workers = -1e9, 1
        self.kind = "scheduler" if address else "local-cluster"
        self.address = address
        try:
            if address is None:
                self.cluster = local_cluster(workers)
                self.client = Client(self.cluster, set_as_default=False)
            else:
                self.client = Client(address, timeout=f"{timeout}s", set_as_default=False)
        except (OSError, TimeoutError, ValueError) as exc:
            self._close_cluster()
            if address is None:
                raise TegraphError(f"cannot start a local Dask cluster: {exc}") from None
            raise InputError(f"no Dask scheduler answers at {address!r} within {timeout:g} s "
                             f"({type(exc).__name__}); expected the address of a running "
                             "`dask scheduler`, such as tcp://HOST:8786", "scheduler") from None
        try:
            self.client.wait_for_workers(1, timeout=timeout)
        except (OSError, TimeoutError) as exc:
            self.close()
            raise InputError(f"the Dask scheduler at {address!r} has no worker after "
                             f"{timeout:g} s ({type(exc).__name__}); start some with "
                             f"`dask worker {address}`", "scheduler") from None
        # One name per run: two runs of one space on one cluster must not share it.
        self.plugin = f"tegraph-explore-{space.fingerprint}-{uuid.uuid4().hex[:8]}"
        self.client.register_plugin(_SpacePlugin(space), name=self.plugin)
        self._done = as_completed(loop=self.client.loop)

    @property
    def workers(self) -> int:
        """Workers connected (asked of the scheduler at most once a second)."""
        now = time.monotonic()
        if now - self._asked > 1.0:
            self._asked = now
            self._workers = len(self.client.scheduler_info(n_workers=-1)["workers"]) or 1
        return self._workers

    @property
    def in_flight(self) -> int:
        """Batches submitted and not yet returned."""
        return len(self._pending)

    @property
    def capacity(self) -> int:
        """Batches to keep in flight: two per worker, so none waits for the next."""
        return 2 * self.workers

    def submit(self, variants: list[int]) -> None:
        """Send one batch of variants to the cluster."""
        future = self.client.submit(judge_on_worker, self.plugin, variants, pure=False)
        self._pending[future] = variants
        self._done.add(future)

    def wait(self) -> list[VariantResult]:
        """Results of the next batch that completes (empty when it was resubmitted)."""
        future = next(self._done)
        variants = self._pending.pop(future)
        try:
            return future.result()
        except KilledWorker:
            out = []
            for v in variants:
                if len(variants) > 1 or v not in self._retried:
                    self._retried.add(v)
                    self.submit([v])
                else:
                    out.append(VariantResult(v, FAILED, reason=(
                        "its evaluation killed its Dask worker repeatedly (KilledWorker)")))
            return out
        except ModuleNotFoundError as exc:
            raise TegraphError(f"the Dask workers cannot import {exc.name!r}: install tegraph "
                               "on every worker (pip install tegraph)") from None
        except OSError as exc:
            raise TegraphError(f"lost the Dask scheduler ({exc}); the results so far are "
                               "kept: run again with `resume`") from None
        except Exception as exc:  # the batch failed on its worker: say so in its rows
            return [VariantResult(v, FAILED, reason=f"{type(exc).__name__}: {exc}")
                    for v in variants]

    def close(self) -> None:
        """Cancel what is pending, unregister the plugin, close the client and its cluster."""
        try:
            for future in self._pending:
                future.cancel()
            if hasattr(self, "plugin"):
                self.client.unregister_worker_plugin(self.plugin)
        except Exception:  # closing is best effort: the cluster may be gone already
            pass
        finally:
            self.client.close()
            self._close_cluster()

    def _close_cluster(self) -> None:
        if self.cluster is not None:
            self.cluster.close()
            self.cluster = None
