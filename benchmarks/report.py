"""The figures as text: the short report ``python -m benchmarks`` prints, and the documentation's performance page."""

from __future__ import annotations


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
        f"  friction ({', '.join(f'{k} {v:g}' for k, v in f['friction_losses'].items() if v is not None)}),"
        " same designs:",
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
        ("loading the compiled fast path, every scope, from its cache", f"{f['cache_load_s']:.2f} s", "cache_load_s"),
    ]
    if f.get("compile_measured_cold"):
        rows.append(("compiling it, cold (a fresh process): the scope that handles every design",
                     f"{f['compile_s']:.1f} s", "compile_s"))
        for name, seconds in (f.get("compile_scopes_s") or {}).items():
            if name != "everything":
                rows.append((f"the same, the {name} scope (`analytic.scope`: compiled on its first use)",
                             f"{seconds:.1f} s", "compile_scopes_s"))
    if "sweep_shots" in f:
        rows += [(f"a sweep of {f['sweep_shots']:,} designs, this process",
                  f"{f['sweep_in_process_shots_per_s']:,.0f} shots/s", "sweep_in_process_shots_per_s"),
                 (f"the same on a {f['sweep_cluster_workers']}-worker Dask cluster",
                  f"{f['sweep_cluster_shots_per_s']:,.0f} shots/s", "sweep_cluster_shots_per_s")]
    commit = "from sources outside git (no commit)" if f["commit"] is None else f"at commit `{f['commit']}`"
    lines = [
        "# Performance",
        "",
        "<!-- Generated by the command below from its own figures: do not edit by hand. -->",
        "",
        f"Measured on {f['date']} {commit}, on {f['cpu_count']} processors "
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
            "That commit's sources and this checkout's, each in a process of its own pinned to one CPU, "
            "timed in turns over blocks of designs (A B B A, several passes; the batches alternate "
            f"whole): {baseline['designs']} designs, shot alike by both "
            f"({'their ranges agree' if baseline['same_designs'] else 'their ranges do NOT agree'} to "
            f"{baseline['max_range_rel_diff']:.0e}). Each side's figure is the median over the "
            "designs of each design's best time; each ratio is this checkout's over the baseline's. "
            "The figures above come from this checkout's own run and differ from these by the "
            "machine's drift between the two. With `--cold`, `compile_s` is each side's faster of two cold "
            "compiles, taken in turns before the shots: of this checkout's scope that handles every "
            "design, as the baseline compiles its only kernel.",
            "",
            "| key | this checkout | baseline | ratio |",
            "|---|---|---|---|",
        ]
        for key, entry in baseline["figures"].items():
            form, unit, scale = (("{:,.0f}", " shots/s", 1.0) if key.endswith("per_s") else
                                 ("{:.1f}", " s", 1.0) if key == "compile_s" else ("{:.3f}", " ms", 1e3))
            this, base = (form.format(entry[side] * scale) for side in ("this", "baseline"))
            lines.append(f"| `{key}` | {this}{unit} | {base}{unit} | {entry['ratio']:.2f} |")
    lines += ["", "## Every model on one design", "",
              f"{f['models_design']}, each as a multiple of one reference shot (the first row), in the same run:", "",
              "| model and path | time | multiple |", "|---|---|---|",
              *(f"| {m['label']} | {m['seconds'] * 1e3:.2f} ms | {m['ratio']:.4f} |" for m in f["models"]), ""]
    return "\n".join(lines)

