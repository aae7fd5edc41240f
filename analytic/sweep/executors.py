"""Where a sweep's chunks run: in this process on every core, or on Dask workers (local or a cluster).

Each executor yields ``(chunk, columns)`` as chunks finish, in any order;
the caller writes them. Workers only compute (``evaluate.chunk_table``) and
send the columns back, so the results folder lives where the command runs
and needs no file system shared with the workers.

Dask workers are separate processes (spawned: nothing of the client's state
is inherited). Each worker loads the compiled kernel once, when it starts
(``worker.LoadKernel``), not per chunk, and shoots a chunk on its share of
the machine's cores (``threads_per_chunk`` Python threads, the kernel
releasing the GIL).
"""

from __future__ import annotations

import itertools
import logging
import os
import uuid
from collections.abc import Iterable, Iterator

import numpy as np

from analytic.sweep.evaluate import chunk_table
from analytic.sweep.spec import Sweep

#: Chunks queued per worker thread beyond the one it runs: enough that a
#: worker never waits for the next, few enough that finished results (held
#: until written) stay small.
QUEUE_PER_THREAD = 2
#: Seconds to wait for a scheduler before giving up (``--scheduler``).
DEFAULT_CONNECT_TIMEOUT = 10.0


class ExecutorError(RuntimeError):
    """An executor that cannot be started or reached (a bad address, a cluster that will not start)."""


class InProcess:
    """Every chunk in this process, one after another, each on all cores (``fast.shoot``'s threads)."""

    name = "in-process"

    def chunks(self, sweep: Sweep, todo: Iterable[int]) -> Iterator[tuple[int, dict[str, np.ndarray]]]:
        for chunk in todo:
            yield chunk, chunk_table(sweep, chunk)

    def close(self) -> None:
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


class OnDask:
    """Chunks as Dask tasks on a ``distributed.Client``'s workers, results gathered as they finish.

    Use ``OnDask.local(workers)`` for a ``LocalCluster`` on this machine or
    ``OnDask.connect(address)`` for a running scheduler. A worker that dies
    costs only the chunks it held: the scheduler runs them again elsewhere.
    """

    def __init__(self, client, cluster=None, threads_per_chunk: int = 1, name: str = "dask"):
        self.client, self.cluster = client, cluster
        self.threads_per_chunk = threads_per_chunk
        self.name = name
        from analytic.sweep.worker import LoadKernel

        self.client.register_plugin(LoadKernel())

    @classmethod
    def local(cls, workers: int) -> OnDask:
        """A ``LocalCluster`` of ``workers`` single-threaded, spawned processes on loopback; each
        chunk's batch uses this machine's cores divided among them."""
        import dask
        from distributed import Client, LocalCluster

        cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
        try:
            # Dask's own bookkeeping, none of which a sweep uses: the workers'
            # profiler samples each running task's stack 100 times a second,
            # every process checks its event loop every 20 ms and its resources
            # every 0.1 to 0.5 s. On two busy cores these cost the cluster a
            # large part of its speed; at these settings it matches this
            # process's (python -m benchmarks, key sweep_cluster_ratio).
            with dask.config.set({"distributed.worker.multiprocessing-method": "spawn",
                                  "distributed.worker.profile.enabled": False,
                                  "distributed.admin.tick.interval": "1s",
                                  "distributed.admin.system-monitor.interval": "5s",
                                  "distributed.worker.memory.monitor-interval": "1s"}):
                # The scheduler serves HTTP (metrics, health) even without a dashboard, on
                # 8787 unless told otherwise: any free port, so that two clusters on one
                # machine (two sweeps, the test suite on two workers) do not collide.
                cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                       host="127.0.0.1", scheduler_port=0, dashboard_address="127.0.0.1:0",
                                       silence_logs=logging.ERROR)
        except Exception as error:   # a cluster that fails to start says why in its own terms
            raise ExecutorError(f"a local Dask cluster of {workers} workers did not start: {error}") from error
        client = Client(cluster)
        return cls(client, cluster, threads_per_chunk=max(1, cores // workers), name=f"local cluster, {workers} workers")

    @classmethod
    def connect(cls, address: str, timeout: float = DEFAULT_CONNECT_TIMEOUT) -> OnDask:
        """A running Dask scheduler at ``address``; each chunk's batch runs on one core of its worker
        (start one single-threaded worker per core: ``dask worker ADDRESS --nthreads 1``)."""
        from distributed import Client

        try:
            client = Client(address, timeout=timeout)
        except (OSError, TimeoutError, ValueError, TypeError) as error:
            raise ExecutorError(f"cannot reach a Dask scheduler at {address!r} within {timeout:g} s: {error}") \
                from None
        return cls(client, threads_per_chunk=1, name=f"scheduler {address}")

    def chunks(self, sweep: Sweep, todo: Iterable[int]) -> Iterator[tuple[int, dict[str, np.ndarray]]]:
        from distributed import as_completed

        from analytic.sweep.evaluate import model_identity
        from analytic.sweep.worker import shoot_chunk

        model = model_identity(sweep)
        pending = iter(todo)
        shared = self.client.scatter(sweep, broadcast=True, hash=False)
        tag = uuid.uuid4().hex[:8]
        chunk_of = {}

        def submit(chunk: int):
            future = self.client.submit(shoot_chunk, shared, chunk, self.threads_per_chunk, model,
                                        key=f"sweep-{tag}-chunk-{chunk:06d}")
            chunk_of[future.key] = chunk
            return future

        threads = sum(self.client.nthreads().values()) or 1
        running = as_completed([submit(chunk) for chunk in itertools.islice(pending, threads * (1 + QUEUE_PER_THREAD))])
        for future in running:
            columns = future.result()
            chunk = chunk_of.pop(future.key)
            future.release()
            following = next(pending, None)
            if following is not None:
                running.add(submit(following))
            yield chunk, columns

    def close(self) -> None:
        self.client.close()
        if self.cluster is not None:
            self.cluster.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()
