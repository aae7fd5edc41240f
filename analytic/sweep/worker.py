"""What runs on a Dask worker: the per-worker kernel loader and the task that computes one chunk.

Kept apart from ``executors`` because it imports ``distributed`` at import
time (the plugin must subclass its ``WorkerPlugin``), which an in-process
sweep never needs.
"""

from __future__ import annotations

import asyncio

import numpy as np
from distributed import WorkerPlugin

from analytic.sweep.evaluate import chunk_table
from analytic.sweep.spec import Sweep


def shoot_chunk(sweep: Sweep, chunk: int, threads: int) -> dict[str, np.ndarray]:
    """Chunk ``chunk`` of ``sweep`` (``evaluate.chunk_table``), its batch on ``threads`` cores.

    numba's thread count is a setting of the calling thread, so it is set
    here, in the worker thread that runs the task.
    """
    import numba

    numba.set_num_threads(max(1, min(threads, numba.config.NUMBA_NUM_THREADS)))
    return chunk_table(sweep, chunk)


class LoadKernel(WorkerPlugin):
    """Load (or compile) the fast path's kernel once per worker process, as it starts."""

    name = "analytic-load-kernel"
    idempotent = True

    async def setup(self, worker) -> None:
        from analytic import fast

        # Off the worker's event loop: a cold compile takes a minute, and the
        # loop must keep answering the scheduler meanwhile.
        await asyncio.get_running_loop().run_in_executor(None, fast.compile)
