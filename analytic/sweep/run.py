"""Running a sweep: the chunks not yet written, on an executor, each written as it arrives."""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from analytic.sweep import storage
from analytic.sweep.executors import InProcess
from analytic.sweep.spec import Sweep


@dataclass(frozen=True)
class SweepRun:
    """What one run of a sweep did.

    Attributes
    ----------
    shots, chunks : the whole sweep's designs and chunks.
    chunks_written : chunks this run wrote (the rest were there already).
    shots_run : designs in the chunks this run wrote.
    ok : designs of the whole sweep that threw (status ``ok``).
    seconds : wall-clock time of this run, from checking the folder to the last chunk written.
    executor : where the chunks ran.
    """

    shots: int
    chunks: int
    chunks_written: int
    shots_run: int
    ok: int
    seconds: float
    executor: str

    def to_json(self) -> dict:
        """The ``--json`` object: ``shots``, ``chunks``, ``chunks_written``, ``ok``, ``seconds``, then ``shots_run`` and ``executor``."""
        return {"shots": self.shots, "chunks": self.chunks, "chunks_written": self.chunks_written,
                "ok": self.ok, "seconds": self.seconds, "shots_run": self.shots_run, "executor": self.executor}


def run_sweep(sweep: Sweep, out: str | Path, executor=None, *, progress: bool = False,
              on_chunk: Callable[[int], None] | None = None) -> SweepRun:
    """Shoot every chunk of ``sweep`` not yet in ``out`` and write each as it finishes.

    Parameters
    ----------
    sweep : the sweep (``load_sweep``).
    out : the results folder: new, empty, or holding this same sweep (then its chunks are kept).
    executor : ``InProcess()`` (the default) or an ``OnDask``; the caller closes it.
    progress : a progress bar over chunks on stderr.
    on_chunk : called with each chunk's number once its file is written.

    Raises
    ------
    DesignError
        if ``out`` holds something else, before anything is written.
    """
    from analytic.cli_shared import progress_bar

    began = time.perf_counter()
    executor = executor or InProcess()
    settings = storage.settings_of(sweep)
    done = storage.check_folder(out, settings)
    storage.create(out, settings)
    ok = sum(_ok_in(storage.chunk_path(out, chunk)) for chunk in done)
    todo = [chunk for chunk in range(sweep.chunks) if chunk not in done]
    written = shots_run = 0
    with progress_bar(total=sweep.chunks, initial=len(done), unit="chunk", desc=sweep.name, disable=not progress,
              file=sys.stderr) as bar:
        for chunk, columns in executor.chunks(sweep, todo):
            storage.write_chunk(out, chunk, columns)
            written += 1
            shots_run += len(columns["index"])
            ok += int(np.count_nonzero(columns["status"] == "ok"))
            bar.update()
            if on_chunk is not None:
                on_chunk(chunk)
    return SweepRun(shots=sweep.shots, chunks=sweep.chunks, chunks_written=written, shots_run=shots_run, ok=ok,
                    seconds=time.perf_counter() - began, executor=executor.name)


def _ok_in(path: Path) -> int:
    import pyarrow.compute as pc
    import pyarrow.parquet as pq

    status = pq.read_table(path, columns=["status"])["status"]
    return int(pc.sum(pc.equal(status.cast("string"), "ok")).as_py() or 0)
