"""Every part of the benchmark in one run: the figures ``--json`` prints."""

from __future__ import annotations

import sys

from analytic import fast
from analytic.design_file import default_design
from analytic.scope import EVERYTHING, SCOPES
from benchmarks.measure import cache_load_seconds, cold_compile_seconds, machine_facts
from benchmarks.models import models
from benchmarks.paths import paths
from benchmarks.sweep import throughput

#: The lists of designs on which the two paths end differently: ideal, typical losses, a rolling
#: frame, both (``--json`` keys; the command exits 1 unless all are empty).
MISMATCH_KEYS = ("status_mismatches", "friction_status_mismatches", "rolling_status_mismatches",
                 "lossy_rolling_status_mismatches")
#: Keys every ``--json`` report has (more follow them).
BENCH_KEYS = ("reference_median_shot_s", "fast_median_shot_s", "speedup", "batch_shots_per_s",
              "max_range_rel_diff", "compile_s", "cache_load_s", "models")


def run(design=None, count: int = 200, seed: int = 0, repeat: int = 5, batch_repeat: int = 20,
        cold: bool = False, progress: bool = True, sweep_shots: int = 40_960,
        sweep_chunk: int | None = None) -> dict:
    """Every part of the benchmark; returns the figures (``BENCH_KEYS`` first)."""
    compile_s = import_s = None
    scopes_s = {}
    if cold:
        if progress:
            print("compiling each of the fast path's scopes in a fresh process with an empty cache ...",
                  file=sys.stderr)
        for scope in SCOPES:
            scopes_s[scope.name], import_s = cold_compile_seconds(scope=scope.name)
        compile_s = scopes_s[EVERYTHING.name]
    fast.compile_all(progress=progress)   # compiled here first if the cache is cold
    cache_load_s = cache_load_seconds()
    figures = paths(count, seed, repeat, batch_repeat, progress)
    design = design or default_design()
    if sweep_shots:
        if progress:
            print(f"sweep throughput: {sweep_shots} shots in this process and on a 2-worker cluster ...",
                  file=sys.stderr)
        figures.update(throughput(sweep_shots, sweep_chunk))
    return {
        **{key: figures[key] for key in BENCH_KEYS[:5]},
        **machine_facts(),
        "compile_s": compile_s if compile_s is not None else cache_load_s,
        "cache_load_s": cache_load_s,
        "models": models(design, max(1, repeat // 2)),
        "models_design": design.name,
        "compile_measured_cold": compile_s is not None,
        "compile_scopes_s": scopes_s or None,
        "import_s": import_s,
        **{key: value for key, value in figures.items() if key not in BENCH_KEYS},
    }

