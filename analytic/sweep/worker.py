"""What runs on a Dask worker: the per-worker kernel loader and the task that computes one chunk.

Kept apart from ``executors`` because it imports ``distributed`` at import
time (the plugin must subclass its ``WorkerPlugin``), which an in-process
sweep never needs.
"""

from __future__ import annotations

import asyncio

import numpy as np
from distributed import WorkerPlugin

from analytic.sweep.evaluate import chunk_table, model_identity
from analytic.sweep.spec import Sweep


def shoot_chunk(sweep: Sweep, chunk: int, threads: int, model: dict) -> dict[str, np.ndarray]:
    """Chunk ``chunk`` of ``sweep`` (``evaluate.chunk_table``), its batch on ``threads`` cores.

    ``model``: the client's ``evaluate.model_identity``; a worker whose own
    differs (another checkout on a cluster's machine) refuses, rather than
    mix another model's numbers into the results.
    """
    own = _model_identity(sweep.base.kind, sweep.base.name)
    if own != model:
        raise RuntimeError(f"this worker runs another version of the model than the client "
                           f"(worker {own}, client {model}): install the same checkout on every machine")
    return chunk_table(sweep, chunk, threads)


_identities: dict = {}


def _model_identity(kind: str, name: str) -> dict:
    """``evaluate.model_identity`` of this process, computed once per base kind (it hashes source files)."""
    if (kind, name) not in _identities:
        from analytic.sweep.spec import Base, Sweep

        base = Base(kind, name, {}, {}, {})
        _identities[kind, name] = model_identity(Sweep(name, base, (), None, 1))
    return _identities[kind, name]


class LoadKernel(WorkerPlugin):
    """Load (or compile) the fast path's kernels, every scope, once per worker process, as it starts."""

    name = "analytic-load-kernel"
    idempotent = True

    async def setup(self, worker) -> None:
        from analytic import fast

        # Off the worker's event loop: a cold compile takes a minute, and the
        # loop must keep answering the scheduler meanwhile.
        await asyncio.get_running_loop().run_in_executor(None, fast.compile_all)
