"""``python -m analytic bench [--json]``: the fast path against the scipy reference, in one run.

Both paths shoot the same designs: the paper's optimum (Table III, the
default design) and a seeded uniform sample over the paper's Table II bounds
(``analytic.problem``), kept whether they throw or fail. Measured:

* the median time of one shot over the designs, for the reference
  (``simulate(histories=False)``: scipy's DOP853 stepped from Python, the same
  summary the fast path gives) and the fast path (``simulate_fast``); each
  design's time is the best of ``repeat`` runs. The reference with its
  histories (``simulate()``, what ``python -m analytic simulate`` runs) is
  timed too;
* the speed-up, as the ratio of the two medians;
* batch throughput of ``fast.shoot`` on all cores, and on one thread;
* agreement: the largest relative range difference and event-time
  difference over the designs both paths throw, and the designs whose
  status differs (there should be none);
* the compile cost, apart: a fresh process with an empty numba cache
  (``compile_s``), and loading the cached machine code (``cache_load_s``).
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile
import time
from typing import Callable

import numpy as np

#: Keys the issue asks ``--json`` for; more follow them.
BENCH_KEYS = ("reference_median_shot_s", "fast_median_shot_s", "speedup", "batch_shots_per_s",
              "max_range_rel_diff", "compile_s")


def bench_designs(count: int, seed: int):
    """The paper's optimum and ``count`` designs drawn uniformly over the paper's problem box."""
    from analytic.design import default_design
    from analytic.problem import default_problem, design_at, from_unit

    problem = default_problem()
    rng = np.random.default_rng(seed)
    designs = [default_design()]
    for i in range(count):
        unit = rng.uniform(0.0, 1.0, size=len(problem.free))
        designs.append(design_at(problem, from_unit(problem, unit), name=f"bench-{seed}-{i:03d}"))
    return designs


def _best_time(run: Callable[[], object], repeat: int) -> float:
    best = math.inf
    for _ in range(repeat):
        began = time.perf_counter()
        run()
        best = min(best, time.perf_counter() - began)
    return best


def cold_compile_seconds() -> tuple[float, float]:
    """(compile, import) seconds of the fast path in a fresh process with an empty numba cache."""
    code = ("import time; t = time.perf_counter(); from analytic import fast; "
            "i = time.perf_counter() - t; print(fast.compile(), i)")
    with tempfile.TemporaryDirectory(prefix="numba-cold-") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        done = subprocess.run([sys.executable, "-c", code], env=env, check=True, capture_output=True, text=True)
    compile_s, import_s = (float(v) for v in done.stdout.split())
    return compile_s, import_s


def run(count: int = 200, seed: int = 0, repeat: int = 5, batch_repeat: int = 20,
        cold: bool = True, progress: bool = True) -> dict:
    """Measure both paths on the same designs; returns the figures (``BENCH_KEYS`` first)."""
    import numba
    from tqdm import tqdm

    from analytic import fast
    from analytic.integrate import IntegrationError
    from analytic.simulate import simulate

    compile_s = import_s = None
    if cold:
        if progress:
            print("compiling the fast path in a fresh process with an empty cache ...", file=sys.stderr)
        compile_s, import_s = cold_compile_seconds()
    cache_load_s = fast.compile()
    designs = bench_designs(count, seed)

    def shots(path: str, simulate_one: Callable, times: int):
        results, seconds = [], []
        for design in tqdm(designs, desc=path, unit="design", disable=not progress, leave=False,
                           file=sys.stderr):
            try:
                results.append(simulate_one(design))
            except IntegrationError as error:
                results.append(error)
            seconds.append(_best_time(lambda d=design: _quiet(simulate_one, d), times))
        return results, np.array(seconds)

    reference, reference_s = shots("reference", lambda d: simulate(d, histories=False), 1)
    _, reference_full_s = shots("reference + histories", simulate, 1)
    fast_shots, fast_s = shots("fast", fast.simulate_fast, repeat)
    agreement = compare(designs, reference, fast_shots)

    rows = np.tile(fast.pack_many(designs), (batch_repeat, 1))
    batch_s = _best_time(lambda: fast.shoot(rows), 3)
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        batch_one_s = _best_time(lambda: fast.shoot(rows), 3)
    finally:
        numba.set_num_threads(threads)

    reference_median, fast_median = float(np.median(reference_s)), float(np.median(fast_s))
    return {
        "reference_median_shot_s": reference_median,
        "fast_median_shot_s": fast_median,
        "speedup": reference_median / fast_median,
        "batch_shots_per_s": len(rows) / batch_s,
        "max_range_rel_diff": agreement["max_range_rel_diff"],
        "compile_s": compile_s if compile_s is not None else cache_load_s,
        "compile_measured_cold": compile_s is not None,
        "import_s": import_s,
        "cache_load_s": cache_load_s,
        "reference_full_median_shot_s": float(np.median(reference_full_s)),
        "speedup_vs_full_reference": float(np.median(reference_full_s)) / fast_median,
        "fast_max_shot_s": float(np.max(fast_s)),
        "batch_one_thread_shots_per_s": len(rows) / batch_one_s,
        "batch_threads": threads,
        "batch_scaling": batch_one_s / batch_s,
        "max_event_time_diff_s": agreement["max_event_time_diff_s"],
        "status_mismatches": agreement["status_mismatches"],
        "designs": len(designs),
        "designs_thrown": agreement["thrown"],
        "designs_failed": len(designs) - agreement["thrown"],
        "batch_shots": len(rows),
        "seed": seed,
    }


def _quiet(simulate_one: Callable, design) -> None:
    from analytic.integrate import IntegrationError

    try:
        simulate_one(design)
    except IntegrationError:
        pass


def compare(designs: list, reference: list, fast_shots: list) -> dict:
    """Agreement of two lists of ``Shot`` (or ``IntegrationError``) on the same designs."""
    range_diff, time_diff, mismatches, thrown = 0.0, 0.0, [], 0
    for design, r, f in zip(designs, reference, fast_shots, strict=True):
        outcome_r = type(r).__name__ if isinstance(r, Exception) else r.status.value
        outcome_f = type(f).__name__ if isinstance(f, Exception) else f.status.value
        if outcome_r != outcome_f:
            mismatches.append(f"{design.name}: reference {outcome_r}, fast {outcome_f}")
            continue
        if isinstance(r, Exception):
            continue
        for name in ("liftoff_time", "release_time", "landing_time"):
            a, b = getattr(r, name), getattr(f, name)
            if (a is None) != (b is None):
                mismatches.append(f"{design.name}: {name} reference {a}, fast {b}")
            elif a is not None:
                time_diff = max(time_diff, abs(a - b))
        if r.ok:
            thrown += 1
            range_diff = max(range_diff, abs(f.range / r.range - 1.0))
    return {"max_range_rel_diff": range_diff, "max_event_time_diff_s": time_diff,
            "status_mismatches": mismatches, "thrown": thrown}


def format_bench(figures: dict) -> str:
    """The figures as a short report."""
    f = figures
    compile_note = "cold, fresh process" if f["compile_measured_cold"] else "cache load only (--no-cold)"
    lines = [
        f"designs: the paper's optimum + {f['designs'] - 1} sampled over Table II (seed {f['seed']}); "
        f"{f['designs_thrown']} throw, {f['designs_failed']} fail",
        "",
        "median time per shot",
        f"  reference (scipy DOP853, summary)   {f['reference_median_shot_s'] * 1e3:9.3f} ms",
        f"  reference with histories            {f['reference_full_median_shot_s'] * 1e3:9.3f} ms",
        f"  fast (compiled)                     {f['fast_median_shot_s'] * 1e3:9.3f} ms"
        f"   (slowest design {f['fast_max_shot_s'] * 1e3:.3f} ms)",
        f"  speed-up                            {f['speedup']:9.1f} x  "
        f"({f['speedup_vs_full_reference']:.0f} x against the reference with histories)",
        "",
        f"batch ({f['batch_shots']} shots)",
        f"  {f['batch_threads']} threads                           {f['batch_shots_per_s']:9.0f} shots/s",
        f"  1 thread                            {f['batch_one_thread_shots_per_s']:9.0f} shots/s"
        f"   (scaling {f['batch_scaling']:.2f} x)",
        "",
        "agreement (fast against reference)",
        f"  largest relative range difference   {f['max_range_rel_diff']:9.2e}",
        f"  largest event-time difference       {f['max_event_time_diff_s']:9.2e} s",
        f"  designs with a different outcome    {len(f['status_mismatches']):9d}",
        "",
        f"compile                               {f['compile_s']:9.2f} s   ({compile_note})",
        f"load from the disk cache              {f['cache_load_s']:9.2f} s",
    ]
    return "\n".join(lines)


def add_arguments(parser) -> None:
    parser.add_argument("--json", action="store_true", help="print the figures as one JSON object")
    parser.add_argument("--designs", type=int, default=200,
                        help="designs sampled over Table II besides the paper's optimum (default %(default)s)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the sample (default %(default)s)")
    parser.add_argument("--repeat", type=int, default=5,
                        help="fast-path runs per design, the best counts (default %(default)s)")
    parser.add_argument("--no-cold", action="store_true",
                        help="skip the cold compile in a fresh process (saves about a minute); "
                             "compile_s is then the cache load")
    parser.add_argument("--quiet", action="store_true", help="no progress bars")


def main(args) -> int:
    if args.designs < 0 or args.repeat < 1:
        print("invalid --designs / --repeat: need designs >= 0 and repeat >= 1", file=sys.stderr)
        return 2
    figures = run(count=args.designs, seed=args.seed, repeat=args.repeat, cold=not args.no_cold,
                  progress=not args.quiet)
    if args.json:
        print(json.dumps(figures, indent=2))
    else:
        print(format_bench(figures))
    return 0 if not figures["status_mismatches"] else 1
