"""``python -m analytic bench [--json]``: the fast path against the scipy reference, in one run.

Both paths shoot the same designs: the paper's optimum (Table III, the
default design) and a seeded uniform sample over the paper's Table II bounds
(``analytic.optimise.problem``), kept whether they throw or fail. Measured:

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
    from analytic.design_file import default_design
    from analytic.optimise.problem import default_problem, design_at, from_unit

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
    from analytic.reference import simulate

    compile_s = import_s = None
    if cold:
        if progress:
            print("compiling the fast path in a fresh process with an empty cache ...", file=sys.stderr)
        compile_s, import_s = cold_compile_seconds()
    cache_load_s = fast.compile(progress=progress)
    designs = bench_designs(count, seed)

    def shots(path: str, simulate_one: Callable, times: int):
        """Each design's result and its best time of ``times`` runs (the first run's result kept)."""
        results, seconds = [], []
        for design in tqdm(designs, desc=path, unit="design", disable=not progress, leave=False,
                           file=sys.stderr):
            best = math.inf
            for run in range(times):
                began = time.perf_counter()
                result = simulate_one(design)
                best = min(best, time.perf_counter() - began)
                if run == 0:
                    results.append(result)
            seconds.append(best)
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
    alternative = scipy_with_compiled_rhs(designs[0])
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
        **alternative,
        "per_design": {"reference_s": reference_s.tolist(), "reference_full_s": reference_full_s.tolist(),
                       "fast_s": fast_s.tolist(), "range_rel_diff": agreement["range_rel_diffs"]},
    }


def scipy_with_compiled_rhs(design, repeat: int = 3) -> dict:
    """The obvious cheaper route, measured: scipy's DOP853 with a numba-compiled right-hand side.

    Stage 2 (lift-off to release, a fixed interval, no events) of ``design``
    through ``scipy.integrate.solve_ivp`` at the default tolerances, once with
    the Python right-hand side and once with the same equations compiled, and
    the fast path's whole three-stage shot beside them. The compiled
    right-hand side alone cannot make scipy fast: its stepping is Python.
    """
    from numba import njit
    from scipy.integrate import solve_ivp

    from analytic import compiled, fast, stages
    from analytic.aero import DRAG_TABLE
    from analytic.parameters import params
    from analytic.reference import DEFAULT_ATOL, DEFAULT_RTOL, simulate
    from analytic.result import Stage

    derivative = compiled.stages_.derivative

    @njit
    def compiled_rhs(t, y, p):
        out = np.empty(6)
        derivative(stages.SWING, y, p, DRAG_TABLE, out)
        return out

    def python_rhs(t, y, p):
        out = np.empty(6)
        stages.derivative(stages.SWING, y, p, DRAG_TABLE, out)
        return out

    shot = simulate(design)
    first = int(np.argmax(shot.stage == Stage.SWING)) - 1    # the lift-off sample
    y0 = np.concatenate([shot.q[first], shot.qdot[first]])
    span = (shot.t[first], shot.release_time)
    p = params(design)
    compiled_rhs(0.0, y0, p)

    def swing(rhs) -> float:
        return _best_time(lambda: solve_ivp(rhs, span, y0, method="DOP853", rtol=DEFAULT_RTOL,
                                            atol=DEFAULT_ATOL), repeat)

    python_s = swing(lambda t, y: python_rhs(t, y, p))
    compiled_s = swing(lambda t, y: compiled_rhs(t, y, p))
    fast_s = _best_time(lambda: fast.simulate_fast(design), 20)
    return {"scipy_swing_python_rhs_s": python_s, "scipy_swing_compiled_rhs_s": compiled_s,
            "fast_whole_shot_s": fast_s}


def compare(designs: list, reference: list, fast_shots: list) -> dict:
    """Agreement of two lists of ``Shot`` on the same designs."""
    range_diffs, time_diff, mismatches, thrown = [], 0.0, [], 0
    for design, r, f in zip(designs, reference, fast_shots, strict=True):
        if r.status is not f.status:
            mismatches.append(f"{design.name}: reference {r.status.value}, fast {f.status.value}")
            continue
        for name in ("liftoff_time", "release_time", "landing_time"):
            a, b = getattr(r, name), getattr(f, name)
            if (a is None) != (b is None):
                mismatches.append(f"{design.name}: {name} reference {a}, fast {b}")
            elif a is not None:
                time_diff = max(time_diff, abs(a - b))
        if r.ok:
            thrown += 1
            range_diffs.append(abs(f.range / r.range - 1.0))
    return {"max_range_rel_diff": max(range_diffs, default=0.0), "max_event_time_diff_s": time_diff,
            "status_mismatches": mismatches, "thrown": thrown, "range_rel_diffs": range_diffs}


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
        "why compile the whole shot, not only the equations (the paper's optimum)",
        f"  scipy DOP853, stage 2 only, Python right-hand side   {f['scipy_swing_python_rhs_s'] * 1e3:8.3f} ms",
        f"  scipy DOP853, stage 2 only, compiled right-hand side {f['scipy_swing_compiled_rhs_s'] * 1e3:8.3f} ms",
        f"  fast path, all three stages                          {f['fast_whole_shot_s'] * 1e3:8.3f} ms",
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
    parser.add_argument("--plot", metavar="FILE.png", help="plot the time per shot and the agreement per design")
    parser.add_argument("--quiet", action="store_true", help="no progress bars")


def save_bench_figure(figures: dict, path) -> None:
    """Time per shot of each path (histogram, log scale) and the fast path's range difference per design."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    per = figures["per_design"]
    fig = Figure(figsize=(11, 4.2), layout="constrained")
    FigureCanvasAgg(fig)
    times, agreement = fig.subplots(1, 2)
    series = [("reference with histories", per["reference_full_s"]), ("reference (summary)", per["reference_s"]),
              ("fast path", per["fast_s"])]
    everything = np.concatenate([np.asarray(v) for _, v in series])
    bins = np.logspace(np.log10(everything.min()) - 0.05, np.log10(everything.max()) + 0.05, 60)
    for label, values in series:
        times.hist(np.asarray(values) * 1e3, bins=bins * 1e3, alpha=0.7,
                   label=f"{label}: median {np.median(values) * 1e3:.3g} ms")
    times.set(xscale="log", xlabel="time per shot (ms)", ylabel="designs",
              title=f"{figures['designs']} designs, speed-up {figures['speedup']:.0f}x")
    times.legend(fontsize=8)
    diffs = np.maximum(np.asarray(per["range_rel_diff"]), 1e-17)
    agreement.semilogy(diffs, ".", ms=4, label="|fast / reference - 1| in range")
    agreement.axhline(1e-7, color="C3", ls="--", label="target 1e-7")
    agreement.axhline(np.finfo(float).eps, color="0.5", ls=":", label="machine epsilon")
    agreement.set(xlabel="design (thrown ones, in order)", ylabel="relative range difference",
                  title="agreement of the two paths", ylim=(1e-17, 1e-5))
    agreement.legend(fontsize=8)
    fig.savefig(path, dpi=120)


def main(args) -> int:
    if args.designs < 0 or args.repeat < 1:
        print("invalid --designs / --repeat: need designs >= 0 and repeat >= 1", file=sys.stderr)
        return 2
    figures = run(count=args.designs, seed=args.seed, repeat=args.repeat, cold=not args.no_cold,
                  progress=not args.quiet)
    if args.plot:
        from pathlib import Path

        Path(args.plot).parent.mkdir(parents=True, exist_ok=True)
        save_bench_figure(figures, args.plot)
    per_design = figures.pop("per_design")
    if args.json:
        print(json.dumps(figures, indent=2))
    else:
        print(format_bench(figures))
        if args.plot:
            print(f"plot written to {args.plot}")
    return 0 if not figures["status_mismatches"] else 1
