"""The benchmark of both models and both analytic paths, as ratios to baselines timed in the same run.

``python -m crosscheck.benchmark [DESIGN.toml] [--json] [--plot FILE.png] [--cold]``
(also ``python -m analytic bench``). Three parts:

* **paths**: the analytic model's two paths on the same designs, the paper's
  optimum (the default design) and a seeded uniform sample over the paper's
  Table II bounds, kept whether they throw or fail. Each design's time is the
  best of ``repeat`` runs; reported: the median shot of the reference
  (``simulate(histories=False)``, scipy's DOP853 stepped from Python: the same
  summary the fast path gives), of the reference with its histories (what
  ``python -m analytic simulate`` runs) and of the fast path, with and without
  the peak loads (what finding them costs, in time and in evaluations); the speed-up as
  the ratio of medians; the batch's throughput on every thread and on one;
  and the agreement of the two paths (``crosscheck.compare.compare_shots``,
  the cross-check's own comparer). Also scipy with the model compiled as its
  right-hand side, the cheaper route not taken.
* **friction**: the same designs with typical losses (``crosscheck.cases.REALISTIC_LOSSES``) on
  both paths: the time per shot and the evaluations as ratios to the ideal
  machine's in the same run, and the paths' agreement with friction.
* **rolling**: the same designs on a rolling frame (``ROLLING_FRAME``), without
  and with the typical losses: the paths' agreement (outcomes and range), untimed.
* **models**: one design through every way the project can shoot it, each as
  a multiple of one reference shot of it (the baseline): the reference at a
  tighter tolerance and without histories, the fast path, the engine at its
  default step and at twice it.
* **compile**: loading the fast path's machine code from the disk cache; with
  ``--cold``, compiling it in a fresh process with an empty cache (about
  25 s of CPU), apart from every shot time.
* **sweep throughput**: one sweep (``--sweep-shots`` designs drawn over the
  paper's problem box, chunks of ``--sweep-chunk``) end to end, Parquet
  written, in this process on every core and on a 2-worker Dask
  ``LocalCluster``: shots per second of each, their ratio (what the cluster
  loses to scheduling and moving results), the cluster's start-up apart, each
  worker's peak memory, and whether the two tables are identical.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Callable

import numpy as np

from crosscheck.cases import REALISTIC_LOSSES

#: The frame the benchmark's designs roll on: the cross-check's frame for sampled designs
#: (``crosscheck.cases.ROLLING_SAMPLE_FRAME_MASS``, 10 kg, about the 6.5 kg counterweight
#: every benchmark design carries): a wooden frame and wheels a machine of this size stands
#: on, light enough that the frame moves by centimetres during the shot.
def _rolling_frame():
    from analytic.design import Base
    from crosscheck.cases import ROLLING_SAMPLE_FRAME_MASS

    return Base("rolling", ROLLING_SAMPLE_FRAME_MASS)


ROLLING_FRAME = _rolling_frame()

#: The lists of designs on which the two paths end differently: ideal, typical losses, a rolling
#: frame, both (``--json`` keys; ``bench`` exits 1 unless all are empty).
MISMATCH_KEYS = ("status_mismatches", "friction_status_mismatches", "rolling_status_mismatches",
                 "lossy_rolling_status_mismatches")
#: Keys every ``--json`` report has (more follow them).
BENCH_KEYS = ("reference_median_shot_s", "fast_median_shot_s", "speedup", "batch_shots_per_s",
              "max_range_rel_diff", "compile_s", "cache_load_s", "models")


def best_time(run: Callable[[], object], repeat: int) -> tuple[float, object]:
    """Best wall-clock seconds of ``repeat`` calls of ``run``, and the first call's result."""
    best, first = math.inf, None
    for i in range(repeat):
        began = time.perf_counter()
        result = run()
        best = min(best, time.perf_counter() - began)
        if i == 0:
            first = result
    return best, first


def bench_designs(count: int, seed: int):
    """The paper's optimum and ``count`` designs drawn uniformly over the paper's problem box."""
    from analytic.design_file import default_design
    from analytic.optimise.problem import default_problem, sample_designs

    return [default_design(), *sample_designs(default_problem(), count, seed, lambda i: f"bench-{seed}-{i:03d}")]


def cold_compile_seconds() -> tuple[float, float]:
    """(compile, import) seconds of the fast path in a fresh process with an empty numba cache."""
    code = ("import time; t = time.perf_counter(); from analytic import fast; "
            "i = time.perf_counter() - t; print(fast.compile(), i)")
    with tempfile.TemporaryDirectory(prefix="numba-cold-") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        done = subprocess.run([sys.executable, "-c", code], env=env, check=True, capture_output=True, text=True)
    compile_s, import_s = (float(v) for v in done.stdout.split())
    return compile_s, import_s


# --------------------------------------------------------------------------- #
# The parts
# --------------------------------------------------------------------------- #

def agreement(designs: list, reference: list, fast_shots: list) -> dict:
    """How closely two lists of ``Shot`` on the same designs agree, through the cross-check's comparer."""
    from crosscheck.compare import compare_shots

    range_diffs, time_diff, mismatches, thrown = [], 0.0, [], 0
    for design, r, f in zip(designs, reference, fast_shots, strict=True):
        rows = {row.quantity: row for row in compare_shots(r, f)}
        if not rows["outcome"].ok:
            mismatches.append(f"{design.name}: reference {r.status.value}, fast {f.status.value}")
            continue
        for name in ("liftoff_time", "release_time"):
            if name in rows:
                time_diff = max(time_diff, abs(rows[name].difference))
        if r.ok:
            thrown += 1
            range_diffs.append(abs(rows["range"].difference / r.range))
    return {"max_range_rel_diff": max(range_diffs, default=0.0), "max_event_time_diff_s": time_diff,
            "status_mismatches": mismatches, "thrown": thrown, "range_rel_diffs": range_diffs}


def both_paths(designs: list, progress: bool, label: str) -> dict:
    """Both analytic paths on ``designs``, one shot each, untimed: their ``agreement``."""
    from tqdm import tqdm

    from analytic.fast import simulate_fast
    from analytic.reference import simulate

    reference = [simulate(design, histories=False)
                 for design in tqdm(designs, desc=f"reference, {label}", unit="design", disable=not progress,
                                    leave=False, file=sys.stderr)]
    return agreement(designs, reference, [simulate_fast(design) for design in designs])


def rolling(designs: list, progress: bool) -> dict:
    """The outcomes of ``designs`` on ``ROLLING_FRAME``, ideal and with ``REALISTIC_LOSSES``, on both paths."""
    figures = {"rolling_frame_mass": ROLLING_FRAME.mass}
    for prefix, losses in (("rolling", None), ("lossy_rolling", REALISTIC_LOSSES)):
        varied = [dataclasses.replace(design, base=ROLLING_FRAME, **({} if losses is None else {"losses": losses}))
                  for design in designs]
        agree = both_paths(varied, progress, prefix.replace("_", " "))
        figures.update({f"{prefix}_status_mismatches": agree["status_mismatches"],
                        f"{prefix}_max_range_rel_diff": agree["max_range_rel_diff"],
                        f"{prefix}_designs_thrown": agree["thrown"]})
    return figures


def paths(count: int, seed: int, repeat: int, batch_repeat: int, progress: bool) -> dict:
    """The two analytic paths on the same designs: times, speed-up, batch throughput, agreement."""
    from tqdm import tqdm

    from analytic import fast
    from analytic.reference import simulate

    designs = bench_designs(count, seed)

    def each(label: str, simulate_one: Callable, times: int, among=None):
        results, seconds = [], []
        for design in tqdm(designs if among is None else among, desc=label, unit="design",
                           disable=not progress, leave=False, file=sys.stderr):
            best, result = best_time(lambda: simulate_one(design), times)
            results.append(result)
            seconds.append(best)
        return results, np.array(seconds)

    reference, reference_s = each("reference", lambda d: simulate(d, histories=False), 1)
    _, reference_full_s = each("reference + histories", simulate, 1)
    fast_shots, fast_s = each("fast", fast.simulate_fast, repeat)
    _, fast_no_loads_s = each("fast, no loads", lambda d: fast.simulate_fast(d, loads=False), repeat)
    agree = agreement(designs, reference, fast_shots)
    evaluations = fast.shoot(designs, loads=True).evaluations
    evaluations_no_loads = fast.shoot(designs, loads=False).evaluations

    rows = np.tile(fast.pack_many(designs), (batch_repeat, 1))
    threads = fast.default_threads()
    batch_s, _ = best_time(lambda: fast.shoot(rows, threads=threads), 3)
    batch_one_s, _ = best_time(lambda: fast.shoot(rows, threads=1), 3)
    reference_median, fast_median = float(np.median(reference_s)), float(np.median(fast_s))

    # The cost of friction: the same designs with REALISTIC_LOSSES, on both paths, against the
    # ideal machine's times above (the same run).
    lossy = [dataclasses.replace(design, losses=REALISTIC_LOSSES) for design in designs]
    lossy_reference, lossy_reference_s = each("reference, friction", lambda d: simulate(d, histories=False), 1,
                                              lossy)
    lossy_fast, lossy_fast_s = each("fast, friction", fast.simulate_fast, repeat, lossy)
    lossy_agree = agreement(lossy, lossy_reference, lossy_fast)
    lossy_evaluations = fast.shoot(lossy, loads=True).evaluations
    friction = {
        "friction_reference_time_ratio": float(np.median(lossy_reference_s)) / reference_median,
        "friction_fast_time_ratio": float(np.median(lossy_fast_s)) / fast_median,
        "friction_evaluation_ratio": float(np.median(lossy_evaluations / np.maximum(evaluations, 1))),
        "friction_max_range_rel_diff": lossy_agree["max_range_rel_diff"],
        "friction_status_mismatches": lossy_agree["status_mismatches"],
        "friction_designs_thrown": lossy_agree["thrown"],
        "friction_losses": dataclasses.asdict(REALISTIC_LOSSES),
    }
    return {
        **friction,
        **rolling(designs, progress),
        "reference_median_shot_s": reference_median,
        "fast_median_shot_s": fast_median,
        "speedup": reference_median / fast_median,
        "batch_shots_per_s": len(rows) / batch_s,
        "max_range_rel_diff": agree["max_range_rel_diff"],
        "reference_full_median_shot_s": float(np.median(reference_full_s)),
        "speedup_vs_full_reference": float(np.median(reference_full_s)) / fast_median,
        "fast_max_shot_s": float(np.max(fast_s)),
        "batch_one_thread_shots_per_s": len(rows) / batch_one_s,
        "batch_threads": threads,
        "batch_scaling": batch_one_s / batch_s,
        "max_event_time_diff_s": agree["max_event_time_diff_s"],
        "fast_no_loads_median_shot_s": float(np.median(fast_no_loads_s)),
        "load_tracking_time_ratio": fast_median / float(np.median(fast_no_loads_s)),
        "load_tracking_evaluation_ratio": float(np.median(evaluations / np.maximum(evaluations_no_loads, 1))),
        "status_mismatches": agree["status_mismatches"],
        "designs": len(designs),
        "designs_thrown": agree["thrown"],
        "designs_failed": len(designs) - agree["thrown"],
        "batch_shots": len(rows),
        "seed": seed,
        **scipy_with_compiled_model(designs[0]),
        "per_design": {"reference_s": reference_s.tolist(), "reference_full_s": reference_full_s.tolist(),
                       "fast_s": fast_s.tolist(), "range_rel_diff": agree["range_rel_diffs"]},
    }


def scipy_with_compiled_model(design, repeat: int = 3) -> dict:
    """The cheaper route not taken, measured: scipy's DOP853 with the model compiled as its right-hand side.

    Stage 2 (lift-off to release, a fixed interval, no events) of ``design``
    through ``scipy.integrate.solve_ivp`` at the default tolerances, once with
    the Python model and once with the same model compiled, and the fast
    path's whole three-stage shot beside them. The compiled right-hand side
    alone cannot make scipy fast: its stepping is Python.
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
    history = shot.history
    first = int(np.argmax(history.stage == Stage.SWING)) - 1    # the lift-off sample
    y0 = np.concatenate([history.q[first], history.qdot[first]])
    span = (history.t[first], shot.release_time)
    p = params(design)
    compiled_rhs(0.0, y0, p)

    def swing(rhs) -> float:
        return best_time(lambda: solve_ivp(rhs, span, y0, method="DOP853", rtol=DEFAULT_RTOL,
                                           atol=DEFAULT_ATOL), repeat)[0]

    return {"scipy_swing_python_rhs_s": swing(lambda t, y: python_rhs(t, y, p)),
            "scipy_swing_compiled_rhs_s": swing(lambda t, y: compiled_rhs(t, y, p)),
            "fast_whole_shot_s": best_time(lambda: fast.simulate_fast(design), 20)[0]}


def models(design, repeat: int) -> list[dict]:
    """One design through every model and path: ``{"label", "seconds", "ratio"}``, the baseline first."""
    import engine_model
    from analytic.fast import simulate_fast
    from analytic.reference import DEFAULT_ATOL, DEFAULT_RTOL, simulate

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


def throughput_sweep(shots: int, chunk_size: int, seed: int = 0):
    """The throughput part's sweep: ``shots`` designs drawn at random over the paper's problem box."""
    from analytic.optimise.problem import VARIABLE_NAMES
    from analytic.sweep import sweep_from_dict

    return sweep_from_dict({"name": "throughput", "problem": "paper_problem", "chunk_size": chunk_size,
                            "sample": {"n": shots, "method": "random", "seed": seed,
                                       **{f"machine.{name}": {} for name in VARIABLE_NAMES}}})


def throughput(shots: int = 40_960, chunk_size: int | None = None, workers: int = 2, repeat: int = 2,
               cluster=None) -> dict:
    """One sweep end to end in this process and on a ``LocalCluster`` of ``workers``: shots/s and their ratio.

    Each executor's time is the best of ``repeat`` runs into fresh folders
    (Parquet written, as a user's sweep); the cluster's start-up is timed
    apart. ``cluster``: an ``OnDask`` to use instead of starting one.
    """
    import resource
    import shutil

    from analytic.sweep import OnDask, read_table, run_sweep
    from analytic.sweep.spec import DEFAULT_CHUNK_SIZE
    from analytic.sweep.storage import tables_identical

    sweep = throughput_sweep(shots, chunk_size or DEFAULT_CHUNK_SIZE)
    with tempfile.TemporaryDirectory(prefix="sweep-bench-") as folder:
        def best(executor, label: str) -> float:
            times = []
            for i in range(repeat):
                out = Path(folder) / f"{label}-{i}"
                times.append(run_sweep(sweep, out, executor).seconds)
                if i:
                    shutil.rmtree(out)
            return min(times)

        in_process_s = best(None, "in-process")
        began = time.perf_counter()
        owned = cluster is None
        cluster = OnDask.local(workers) if owned else cluster
        start_s = time.perf_counter() - began
        try:
            cluster_s = best(cluster, "cluster")
            peak_mb = cluster.client.run(lambda: resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
        finally:
            if owned:
                cluster.close()
        identical = tables_identical(read_table(Path(folder) / "in-process-0"), read_table(Path(folder) / "cluster-0"))
        parquet_bytes = sum(p.stat().st_size for p in (Path(folder) / "in-process-0").glob("*.parquet"))
    return {"sweep_shots": sweep.shots, "sweep_chunk_size": sweep.chunk_size, "sweep_chunks": sweep.chunks,
            "sweep_in_process_shots_per_s": sweep.shots / in_process_s,
            "sweep_cluster_shots_per_s": sweep.shots / cluster_s,
            "sweep_cluster_ratio": in_process_s / cluster_s, "sweep_cluster_workers": workers,
            "sweep_cluster_start_s": start_s if owned else None,
            "sweep_worker_peak_rss_mb": sorted(peak_mb.values()),
            "sweep_parquet_bytes_per_shot": parquet_bytes / sweep.shots,
            "sweep_tables_identical": bool(identical)}


def run(design=None, count: int = 200, seed: int = 0, repeat: int = 5, batch_repeat: int = 20,
        cold: bool = False, progress: bool = True, sweep_shots: int = 40_960,
        sweep_chunk: int | None = None) -> dict:
    """Every part of the benchmark; returns the figures (``BENCH_KEYS`` first)."""
    from analytic import fast
    from analytic.design_file import default_design

    compile_s = import_s = None
    if cold:
        if progress:
            print("compiling the fast path in a fresh process with an empty cache ...", file=sys.stderr)
        compile_s, import_s = cold_compile_seconds()
    cache_load_s = fast.compile(progress=progress)
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
        "import_s": import_s,
        **{key: value for key, value in figures.items() if key not in BENCH_KEYS},
    }


def machine_facts() -> dict:
    """When and where the figures were measured: date (UTC), processors, CPU model, versions, commit."""
    import datetime
    import platform

    import numba
    import scipy

    model = None
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=Path(__file__).parent,
                                capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        commit = None
    return {"date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "cpu_count": os.cpu_count(), "cpu_model": model, "python": platform.python_version(),
            "numba": numba.__version__, "scipy": scipy.__version__, "commit": commit}


# --------------------------------------------------------------------------- #
# A baseline: an earlier commit's benchmark, beside this one's
# --------------------------------------------------------------------------- #

#: The keys compared with a baseline, and the baseline's key each is divided by (the
#: pre-friction code has no ``fast_no_loads_median_shot_s``: its shots had no loads to find).
BASELINE_RATIOS = {"fast_median_shot_s": ("fast_median_shot_s", "fast_no_loads_median_shot_s"),
                   "fast_no_loads_median_shot_s": ("fast_no_loads_median_shot_s", "fast_median_shot_s"),
                   "batch_shots_per_s": ("batch_shots_per_s",),
                   "reference_median_shot_s": ("reference_median_shot_s",)}


class BaselineError(RuntimeError):
    """The baseline commit could not be checked out or benchmarked (the message says why)."""


def baseline_source(rev: str, folder: Path) -> str:
    """Write commit ``rev``'s tree into ``folder`` (``git archive``); returns the full commit id."""
    here = Path(__file__).resolve().parent
    try:
        top = subprocess.run(["git", "rev-parse", "--show-toplevel"], cwd=here, capture_output=True, text=True,
                             check=True).stdout.strip()
        commit = subprocess.run(["git", "rev-parse", "--verify", f"{rev}^{{commit}}"], cwd=top,
                                capture_output=True, text=True, check=True).stdout.strip()
        archive = subprocess.run(["git", "archive", commit], cwd=top, capture_output=True, check=True).stdout
    except FileNotFoundError as error:
        raise BaselineError(f"--baseline {rev}: git is not installed ({error})") from error
    except subprocess.CalledProcessError as error:
        raise BaselineError(f"--baseline {rev}: not a commit of this repository "
                            f"({error.stderr.strip() if isinstance(error.stderr, str) else error.stderr.decode().strip()})"
                            ) from error
    subprocess.run(["tar", "-x", "-C", str(folder)], input=archive, check=True)
    if not (Path(folder) / "analytic" / "__init__.py").is_file():   # else this checkout's would be imported
        raise BaselineError(f"--baseline {rev}: commit {commit[:7]} has no analytic package")
    return commit


def baseline_figures(folder: Path, designs: int, seed: int, repeat: int, progress: bool) -> dict:
    """The benchmark of the sources in ``folder`` (its own ``python -m analytic bench --json``), run
    with this interpreter and its packages; its fast path compiles there first (cached in ``folder``)."""
    options = subprocess.run([sys.executable, "-m", "analytic", "bench", "--help"], cwd=folder,
                             env=_baseline_env(folder), capture_output=True, text=True)
    if options.returncode != 0:
        raise BaselineError(f"the baseline's bench does not start: {options.stderr.strip()[-400:]}")
    command = [sys.executable, "-m", "analytic", "bench", "--json", "--quiet", "--designs", str(designs),
               "--seed", str(seed), "--repeat", str(repeat)]
    for flag, extra in (("--no-cold", ["--no-cold"]), ("--sweep-shots", ["--sweep-shots", "0"])):
        if flag in options.stdout:
            command += extra
    if progress:
        print("  the baseline's benchmark (its first shot compiles its fast path) ...", file=sys.stderr, flush=True)
    done = subprocess.run(command, cwd=folder, env=_baseline_env(folder), capture_output=True, text=True)
    try:
        return json.loads(done.stdout)
    except json.JSONDecodeError as error:
        raise BaselineError(f"the baseline's bench gave no figures (exit {done.returncode}): "
                            f"{done.stderr.strip()[-400:]}") from error


def _baseline_env(folder: Path) -> dict:
    """The environment of the baseline's processes: its own sources first, no progress bars."""
    return dict(os.environ, PYTHONPATH=str(folder), PYTHONDONTWRITEBYTECODE="1")


def with_baseline(run_figures: Callable[[], dict], rev: str, designs: int, seed: int, repeat: int,
                  progress: bool) -> dict:
    """This checkout's figures with commit ``rev``'s measured just before and just after them (B A B),
    and each key of ``BASELINE_RATIOS`` as a ratio to the mean of the two."""
    with tempfile.TemporaryDirectory(prefix="bench-baseline-") as folder:
        commit = baseline_source(rev, Path(folder))
        before = baseline_figures(Path(folder), designs, seed, repeat, progress)
        figures = run_figures()
        after = baseline_figures(Path(folder), designs, seed, repeat, progress)
    base = {}
    for key, candidates in BASELINE_RATIOS.items():
        found = next((name for name in candidates if name in before and name in after), None)
        if found is not None:
            base[key] = {"baseline_key": found, "baseline": [before[found], after[found]],
                         "ratio": figures[key] / (0.5 * (before[found] + after[found]))}
    figures["baseline"] = {"rev": rev, "commit": commit, "figures": base}
    return figures


# --------------------------------------------------------------------------- #
# Report
# --------------------------------------------------------------------------- #

def format_bench(figures: dict) -> str:
    """The figures as a short report."""
    f = figures
    compile_note = "cold, fresh process" if f["compile_measured_cold"] else "cache load only; --cold to compile"
    lines = [
        f"paths: the paper's optimum + {f['designs'] - 1} designs over Table II (seed {f['seed']}); "
        f"{f['designs_thrown']} throw, {f['designs_failed']} fail",
        f"  reference (scipy DOP853, summary)   {f['reference_median_shot_s'] * 1e3:9.3f} ms  median per shot",
        f"  reference with histories            {f['reference_full_median_shot_s'] * 1e3:9.3f} ms",
        f"  fast (compiled)                     {f['fast_median_shot_s'] * 1e3:9.3f} ms"
        f"   (slowest design {f['fast_max_shot_s'] * 1e3:.3f} ms)",
        f"  fast, without the peak loads        {f['fast_no_loads_median_shot_s'] * 1e3:9.3f} ms"
        f"   (finding them costs {f['load_tracking_time_ratio']:.2f} x the time,"
        f" {f['load_tracking_evaluation_ratio']:.2f} x the evaluations, medians)",
        f"  speed-up                            {f['speedup']:9.1f} x  "
        f"({f['speedup_vs_full_reference']:.0f} x against the reference with histories)",
        f"  batch of {f['batch_shots']}, {f['batch_threads']} threads"
        f"   {f['batch_shots_per_s']:9.0f} shots/s; 1 thread {f['batch_one_thread_shots_per_s']:.0f}"
        f" (scaling {f['batch_scaling']:.2f} x)",
        f"  agreement: range {f['max_range_rel_diff']:.2e} relative, events {f['max_event_time_diff_s']:.2e} s,"
        f" {len(f['status_mismatches'])} different outcomes",
        f"  friction ({', '.join(f'{k} {v:g}' for k, v in f['friction_losses'].items())}), same designs:",
        f"    time per shot x{f['friction_reference_time_ratio']:.2f} on the reference path,"
        f" x{f['friction_fast_time_ratio']:.2f} on the fast path,"
        f" x{f['friction_evaluation_ratio']:.2f} evaluations (medians, against the ideal machine);"
        f" agreement {f['friction_max_range_rel_diff']:.2e} in range,"
        f" {len(f['friction_status_mismatches'])} different outcomes, {f['friction_designs_thrown']} throw",
        f"  rolling frame of {f['rolling_frame_mass']:g} kg, same designs:",
        *(f"    {label}: agreement {f[f'{prefix}_max_range_rel_diff']:.2e} in range,"
          f" {len(f[f'{prefix}_status_mismatches'])} different outcomes, {f[f'{prefix}_designs_thrown']} throw"
          for label, prefix in (("ideal", "rolling"), ("with the friction above", "lossy_rolling"))),
        f"  scipy DOP853, stage 2 only: Python model {f['scipy_swing_python_rhs_s'] * 1e3:.3f} ms,"
        f" compiled model {f['scipy_swing_compiled_rhs_s'] * 1e3:.3f} ms;"
        f" fast path, all three stages {f['fast_whole_shot_s'] * 1e3:.3f} ms",
        "",
        f"models: {f['models_design']}, as multiples of one reference shot",
        *(f"  {m['label']:<50} {m['ratio']:9.4f} x   ({m['seconds'] * 1e3:8.2f} ms)" for m in f["models"]),
        "",
        f"compile {f['compile_s']:.2f} s ({compile_note}); load from the disk cache {f['cache_load_s']:.2f} s",
    ]
    if "sweep_shots" in f:
        lines += [
            "",
            f"sweep throughput: {f['sweep_shots']} designs over the problem box, {f['sweep_chunks']} chunks of "
            f"{f['sweep_chunk_size']}, end to end (Parquet written)",
            f"  in this process, every core          {f['sweep_in_process_shots_per_s']:9.0f} shots/s",
            f"  LocalCluster, {f['sweep_cluster_workers']} workers               "
            f"{f['sweep_cluster_shots_per_s']:9.0f} shots/s   ratio {f['sweep_cluster_ratio']:.2f}"
            + (f" (start-up {f['sweep_cluster_start_s']:.1f} s apart)" if f["sweep_cluster_start_s"] else ""),
            f"  peak memory per worker {', '.join(f'{m:.0f}' for m in f['sweep_worker_peak_rss_mb'])} MB; "
            f"{f['sweep_parquet_bytes_per_shot']:.0f} bytes of Parquet per shot; tables identical: "
            f"{'yes' if f['sweep_tables_identical'] else 'NO'}",
        ]
    return "\n".join(lines)


def performance_page(figures: dict, command: str) -> str:
    """The documentation's performance page (Markdown), every figure from ``figures`` (``--json``)."""
    f = figures
    ms = 1e3
    rows = [
        ("fast path, one shot with its peak loads (median)", f"{f['fast_median_shot_s'] * ms:.3f} ms",
         "fast_median_shot_s"),
        ("fast path, one shot without them (median)", f"{f['fast_no_loads_median_shot_s'] * ms:.3f} ms",
         "fast_no_loads_median_shot_s"),
        ("finding the peak loads costs", f"{f['load_tracking_time_ratio']:.2f} x the time, "
         f"{f['load_tracking_evaluation_ratio']:.2f} x the evaluations", "load_tracking_time_ratio"),
        (f"a batch (`shoot`), {f['batch_threads']} threads", f"{f['batch_shots_per_s']:,.0f} shots/s",
         "batch_shots_per_s"),
        ("a batch on one thread", f"{f['batch_one_thread_shots_per_s']:,.0f} shots/s",
         "batch_one_thread_shots_per_s"),
        ("reference path, summary with the peak loads (median)", f"{f['reference_median_shot_s'] * ms:.2f} ms",
         "reference_median_shot_s"),
        ("reference path with histories (median)", f"{f['reference_full_median_shot_s'] * ms:.2f} ms",
         "reference_full_median_shot_s"),
        ("speed-up, fast over reference", f"{f['speedup']:.0f} x", "speedup"),
        ("friction (typical losses), time per shot", f"{f['friction_fast_time_ratio']:.2f} x the ideal's (fast), "
         f"{f['friction_reference_time_ratio']:.2f} x (reference)", "friction_fast_time_ratio"),
        ("the paths' agreement", f"{f['max_range_rel_diff']:.1e} in range; "
         f"{len(f['status_mismatches']) + len(f['friction_status_mismatches'])} different outcomes",
         "max_range_rel_diff"),
        ("scipy's DOP853 on stage 2 of the paper's design, the Python model",
         f"{f['scipy_swing_python_rhs_s'] * ms:.2f} ms", "scipy_swing_python_rhs_s"),
        ("the same, the model compiled as its right-hand side", f"{f['scipy_swing_compiled_rhs_s'] * ms:.2f} ms",
         "scipy_swing_compiled_rhs_s"),
        ("the fast path's whole shot (three stages) of that design", f"{f['fast_whole_shot_s'] * ms:.3f} ms",
         "fast_whole_shot_s"),
        ("loading the compiled fast path from its cache", f"{f['cache_load_s']:.2f} s", "cache_load_s"),
    ]
    if f.get("compile_measured_cold"):
        rows.append(("compiling it, cold (a fresh process)", f"{f['compile_s']:.1f} s", "compile_s"))
    if "sweep_shots" in f:
        rows += [(f"a sweep of {f['sweep_shots']:,} designs, this process",
                  f"{f['sweep_in_process_shots_per_s']:,.0f} shots/s", "sweep_in_process_shots_per_s"),
                 (f"the same on a {f['sweep_cluster_workers']}-worker Dask cluster",
                  f"{f['sweep_cluster_shots_per_s']:,.0f} shots/s", "sweep_cluster_shots_per_s")]
    lines = [
        "# Performance",
        "",
        "<!-- Generated by the command below from its own figures: do not edit by hand. -->",
        "",
        f"Measured on {f['date']} at commit `{f['commit']}`, on {f['cpu_count']} processors "
        f"({f['cpu_model']}), Python {f['python']}, numba {f['numba']}, scipy {f['scipy']}, by",
        "",
        f"    {command}",
        "",
        f"over the paper's optimum and {f['designs'] - 1} designs drawn over the paper's Table II "
        f"(seed {f['seed']}; {f['designs_thrown']} throw). Each design's time is the best of a few runs; "
        "the figures are medians over the designs. The machine is shared: compare the ratios, "
        "which are measured in the same run.",
        "",
        "| what | figure | `--json` key |",
        "|---|---|---|",
        *(f"| {label} | {value} | `{key}` |" for label, value, key in rows),
    ]
    baseline = f.get("baseline")
    if baseline:
        lines += [
            "",
            f"## Against commit `{baseline['commit'][:7]}` (`--baseline {baseline['rev']}`)",
            "",
            "That commit's own benchmark, run with the same interpreter just before and just after this "
            "one's; each ratio is this checkout's figure over the mean of its two.",
            "",
            "| key | this checkout | baseline (before, after) | ratio |",
            "|---|---|---|---|",
        ]
        for key, entry in baseline["figures"].items():
            form, unit = ("{:,.0f}", " shots/s") if key.endswith("per_s") else ("{:.3f}", " ms")
            scale = 1.0 if key.endswith("per_s") else 1e3
            b0, b1 = (form.format(v * scale) for v in entry["baseline"])
            named = "" if entry["baseline_key"] == key else f" (its `{entry['baseline_key']}`)"
            lines.append(f"| `{key}` | {form.format(f[key] * scale)}{unit} | {b0}, {b1}{unit}{named} | "
                         f"{entry['ratio']:.2f} |")
    lines += ["", "## Every model on one design", "",
              f"{f['models_design']}, each as a multiple of one reference shot (the first row), in the same run:", "",
              "| model and path | time | multiple |", "|---|---|---|",
              *(f"| {m['label']} | {m['seconds'] * 1e3:.2f} ms | {m['ratio']:.4f} |" for m in f["models"]), ""]
    return "\n".join(lines)


def save_bench_figure(figures: dict, path) -> None:
    """Time per shot of each path (histogram, log scale) and the fast path's range difference per design."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    per = figures["per_design"]
    fig = Figure(figsize=(11, 4.2), layout="constrained")
    FigureCanvasAgg(fig)
    times, agree = fig.subplots(1, 2)
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
    agree.semilogy(diffs, ".", ms=4, label="|fast / reference - 1| in range")
    agree.axhline(1e-7, color="C3", ls="--", label="the paths' bound 1e-7")
    agree.axhline(np.finfo(float).eps, color="0.5", ls=":", label="machine epsilon")
    agree.set(xlabel="design (thrown ones, in order)", ylabel="relative range difference",
              title="agreement of the two paths", ylim=(1e-17, 1e-5))
    agree.legend(fontsize=8)
    fig.savefig(path, dpi=120)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("design", nargs="?", help="design TOML for the models part (default: the paper's optimum)")
    parser.add_argument("--json", action="store_true", help="print the figures as one JSON object")
    parser.add_argument("--designs", type=int, default=200,
                        help="designs sampled over Table II besides the paper's optimum (default %(default)s)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the sample (default %(default)s)")
    parser.add_argument("--repeat", type=int, default=5,
                        help="runs per timing, the best counts (default %(default)s)")
    parser.add_argument("--cold", action="store_true",
                        help="also compile the fast path in a fresh process with an empty cache "
                             "(about 25 s of CPU)")
    parser.add_argument("--plot", metavar="FILE.png", help="plot the time per shot and the agreement per design")
    parser.add_argument("--sweep-shots", type=int, default=40_960,
                        help="designs in the sweep-throughput part (in this process and on a 2-worker "
                             "LocalCluster; 0 skips it; default %(default)s)")
    parser.add_argument("--sweep-chunk", type=int, default=None,
                        help="chunk size of that sweep (default: the sweep files' default)")
    parser.add_argument("--baseline", metavar="REV",
                        help="also benchmark commit REV of this repository (its sources in a temporary folder, "
                             "run with this interpreter) just before and just after this one, and give each "
                             "headline figure as a ratio to it")
    parser.add_argument("--markdown", metavar="FILE.md",
                        help="write the documentation's performance page from these figures")
    parser.add_argument("--quiet", action="store_true", help="no progress bars")


def main(args: argparse.Namespace | list[str] | None = None) -> int:
    """Run the benchmark (``args``: parsed arguments or an argv list); 0, or 1 if the paths disagree on an
    outcome (``MISMATCH_KEYS``) or the sweep's two tables differ."""
    if not isinstance(args, argparse.Namespace):
        parser = argparse.ArgumentParser(prog="python -m crosscheck.benchmark", description=__doc__,
                                         formatter_class=argparse.RawDescriptionHelpFormatter)
        add_arguments(parser)
        from analytic.command_line import negative_numbers_as_values

        args = parser.parse_args(negative_numbers_as_values(sys.argv[1:] if args is None else args))
    if args.designs < 0 or args.repeat < 1 or args.sweep_shots < 0 or (args.sweep_chunk or 1) < 1:
        print(f"--designs = {args.designs}, --repeat = {args.repeat}, --sweep-shots = {args.sweep_shots}, "
              f"--sweep-chunk = {args.sweep_chunk}: need designs >= 0, repeat >= 1, sweep shots >= 0 and "
              f"sweep chunk >= 1", file=sys.stderr)
        return 2
    plot = None
    if args.plot:
        from analytic.command_line import OutputPathError, output_file

        try:
            plot = output_file(args.plot, "--plot")
        except OutputPathError as error:
            print(error, file=sys.stderr)
            return 2
    design = None
    if args.design is not None:
        from analytic.design import DesignError
        from analytic.design_file import load_design

        try:
            design = load_design(args.design)
        except DesignError as error:
            print(f"invalid design: {error}", file=sys.stderr)
            return 2
    markdown = None
    if args.markdown:
        from analytic.command_line import OutputPathError, output_file

        try:
            markdown = output_file(args.markdown, "--markdown", formats=(".md",))
        except OutputPathError as error:
            print(error, file=sys.stderr)
            return 2

    def measure() -> dict:
        return run(design, count=args.designs, seed=args.seed, repeat=args.repeat, cold=args.cold,
                   progress=not args.quiet, sweep_shots=args.sweep_shots, sweep_chunk=args.sweep_chunk)

    try:
        figures = (measure() if args.baseline is None else
                   with_baseline(measure, args.baseline, args.designs, args.seed, args.repeat, not args.quiet))
    except BaselineError as error:
        print(error, file=sys.stderr)
        return 2
    if markdown is not None:
        argv = sys.argv[1:] if isinstance(args, argparse.Namespace) else []
        command = "python -m analytic bench " + " ".join(a for a in argv if a != "bench")
        markdown.write_text(performance_page(figures, command.strip()))
    if plot is not None:
        save_bench_figure(figures, plot)
    figures.pop("per_design")
    print(json.dumps(figures, indent=2) if args.json else format_bench(figures))
    if plot is not None and not args.json:
        print(f"plot written to {plot}")
    agree = not any(figures[key] for key in MISMATCH_KEYS)
    return 0 if agree and figures.get("sweep_tables_identical", True) else 1


if __name__ == "__main__":
    raise SystemExit(main())
