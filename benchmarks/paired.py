"""A paired comparison with a baseline commit: both sides' shots interleaved within milliseconds.

The host this project is benchmarked on is shared: the same shot takes 1.6x longer from one
minute to the next, so a baseline run before and after this checkout's (``benchmarks.baseline``)
brackets the drift but does not cancel it. Here one worker process per side
(``benchmarks.paired_worker``, each importing its own sources) is pinned to the same CPU, and
the driver alternates them over small blocks of designs in the order A B B A, several passes
over the designs: each design's time is its best over the passes, so both sides of every design
are measured under the same conditions. The batch, on every CPU, alternates whole batches. The
figures are the medians over the designs (the best batch), as in the full benchmark, and each
ratio is this checkout's figure over the baseline's.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from benchmarks.measure import cold_compile_seconds

WORKER = Path(__file__).resolve().with_name("paired_worker.py")

#: Per key: the worker's timed call, the designs per block, passes over the designs, shots per
#: design per pass.
SHOT_KEYS = {"fast_median_shot_s": ("fast", 10, 3, 3),
             "fast_no_loads_median_shot_s": ("fast_no_loads", 10, 3, 3),
             "reference_median_shot_s": ("reference", 4, 2, 1)}
#: Batches per side, alternated A B B A.
BATCH_ROUNDS = 8


class Worker:
    """A ``paired_worker`` process importing the sources in ``folder``."""

    def __init__(self, folder: Path, env: dict):
        self.process = subprocess.Popen([sys.executable, str(WORKER)], cwd=folder, env=env, text=True,
                                        stdin=subprocess.PIPE, stdout=subprocess.PIPE)

    def ask(self, **request) -> dict:
        self.process.stdin.write(json.dumps(request) + "\n")
        self.process.stdin.flush()
        line = self.process.stdout.readline()
        if not line:
            raise RuntimeError(f"the paired benchmark's worker stopped (exit {self.process.wait()})")
        return json.loads(line)

    def close(self) -> None:
        self.process.stdin.close()
        self.process.wait()
        self.process.stdout.close()


def _orders(blocks: int) -> list:
    """A B, then B A, alternately: each side goes first as often as the other."""
    return [(0, 1) if b % 2 == 0 else (1, 0) for b in range(blocks)]


def paired(here: Path, baseline: Path, env_here: dict, env_baseline: dict, count: int, seed: int,
           batch_repeat: int = 20, cold_rounds: int = 0, progress: bool = False) -> dict:
    """This checkout's and the baseline's figures, interleaved (the module's docstring); per key
    ``{"this": ..., "baseline": ..., "ratio": ...}`` plus the method's facts. With ``cold_rounds``,
    also ``compile_s``: each side's fastest of that many cold compiles (a fresh process and an
    empty cache each), alternated A B B A, before the shots."""
    figures = {}
    if cold_rounds:
        if progress:
            print(f"  paired: {2 * cold_rounds} cold compiles ...", file=sys.stderr, flush=True)
        best = [math.inf, math.inf]
        for order in _orders(cold_rounds):
            for side in order:
                folder, env = (here, env_here) if side == 0 else (baseline, env_baseline)
                best[side] = min(best[side], cold_compile_seconds(folder, env)[0])
        figures["compile_s"] = {"this": best[0], "baseline": best[1], "ratio": best[0] / best[1]}
    workers = [Worker(here, env_here), Worker(baseline, env_baseline)]
    try:
        setups = [w.ask(op="setup", count=count, seed=seed, batch_repeat=batch_repeat) for w in workers]
        ranges = [np.array([np.nan if r is None else r for r in s["ranges"]]) for s in setups]
        both = np.isfinite(ranges[0]) & np.isfinite(ranges[1])
        same = (np.array_equal(np.isfinite(ranges[0]), np.isfinite(ranges[1]))
                and bool(np.all(np.abs(ranges[0][both] - ranges[1][both]) <= 1e-6 * np.abs(ranges[1][both]))))
        cpu = setups[0]["cpus"][-1]
        for w in workers:
            w.ask(op="pin", cpu=cpu)
        designs = setups[0]["designs"]
        for key, (what, block, passes, repeat) in SHOT_KEYS.items():
            if progress:
                print(f"  paired: {what} ...", file=sys.stderr, flush=True)
            best = np.full((2, designs), np.inf)
            chunks = [list(range(i, min(i + block, designs))) for i in range(0, designs, block)]
            for _ in range(passes):
                for chunk, order in zip(chunks, _orders(len(chunks)), strict=True):
                    for side in order:
                        seconds = workers[side].ask(op="time", what=what, indices=chunk, repeat=repeat)["seconds"]
                        best[side, chunk] = np.minimum(best[side, chunk], seconds)
            this, base = (float(np.median(best[side])) for side in (0, 1))
            figures[key] = {"this": this, "baseline": base, "ratio": this / base}
        if progress:
            print("  paired: batch ...", file=sys.stderr, flush=True)
        for key, op in (("batch_shots_per_s", "batch"), ("batch_one_thread_shots_per_s", "batch_one")):
            batch, shots = np.full(2, np.inf), 0
            for order in _orders(BATCH_ROUNDS):
                for side in order:
                    answer = workers[side].ask(op=op)
                    batch[side], shots = min(batch[side], answer["seconds"]), answer["shots"]
            this, base = (float(shots / batch[side]) for side in (0, 1))
            figures[key] = {"this": this, "baseline": base, "ratio": this / base}
    finally:
        for w in workers:
            w.close()
    return {"figures": figures, "cpu": cpu, "designs": designs, "same_designs": same,
            "max_range_rel_diff": float(np.max(np.abs(ranges[0][both] - ranges[1][both]) / np.abs(ranges[1][both]))),
            "method": "interleaved A B B A on one CPU; best per design over the passes; medians"}


def paired_env(folder: Path) -> dict:
    """The environment of a worker importing the sources in ``folder`` (its own numba cache there)."""
    return dict(os.environ, PYTHONPATH=str(folder), PYTHONDONTWRITEBYTECODE="1")
