"""One design through every model and path, each as a multiple of one reference shot of it."""

from __future__ import annotations

import engine_model
from analytic.fast import simulate_fast
from analytic.reference import DEFAULT_ATOL, DEFAULT_RTOL, simulate
from benchmarks.measure import best_time


def models(design, repeat: int) -> list[dict]:
    """One design through every model and path: ``{"label", "seconds", "ratio"}``, the baseline first."""
    dt = engine_model.DEFAULT_DT
    entries = [
        ("analytic reference, default tolerance (baseline)", lambda: simulate(design)),
        ("analytic reference, 100x tighter tolerance",
         lambda: simulate(design, rtol=DEFAULT_RTOL / 100, atol=DEFAULT_ATOL / 100)),
        ("analytic reference, summary only", lambda: simulate(design, histories=False)),
        ("analytic fast path", lambda: simulate_fast(design)),
        (f"engine, default step {dt:g} s", lambda: engine_model.simulate(design, dt=dt)),
        (f"engine, step {2 * dt:g} s", lambda: engine_model.simulate(design, dt=2 * dt)),
    ]
    timed = []
    for label, run in entries:
        run()   # warm-up: imports, caches
        timed.append((label, best_time(run, repeat)[0]))
    baseline = timed[0][1]
    return [{"label": label, "seconds": seconds, "ratio": seconds / baseline} for label, seconds in timed]
