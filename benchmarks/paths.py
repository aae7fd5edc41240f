"""The two analytic paths on the same designs: their times, the speed-up, the batch's throughput, their agreement.

With typical losses and on a rolling frame too (see the package's docstring).
"""

from __future__ import annotations

import dataclasses
import sys
from typing import Callable

import numpy as np

from analytic import fast
from analytic.cli_shared import progress_bar
from analytic.reference import simulate
from benchmarks.designs import ROLLING_FRAME, TYPICAL_LOSSES, bench_designs
from benchmarks.measure import best_time
from benchmarks.scipy_route import scipy_with_compiled_model
from crosscheck.comparison import compare_shots


def agreement(designs: list, reference: list, fast_shots: list) -> dict:
    """How closely two lists of ``Shot`` on the same designs agree, through the cross-check's comparer."""
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
    reference = [simulate(design, histories=False)
                 for design in progress_bar(designs, desc=f"reference, {label}", unit="design", disable=not progress,
                                    leave=False, file=sys.stderr)]
    return agreement(designs, reference, [fast.simulate_fast(design) for design in designs])


def rolling(designs: list, progress: bool) -> dict:
    """The outcomes of ``designs`` on ``ROLLING_FRAME``, ideal and with ``TYPICAL_LOSSES``, on both paths."""
    figures = {"rolling_frame_mass": ROLLING_FRAME.mass}
    for prefix, losses in (("rolling", None), ("lossy_rolling", TYPICAL_LOSSES)):
        varied = [dataclasses.replace(design, base=ROLLING_FRAME, **({} if losses is None else {"losses": losses}))
                  for design in designs]
        agree = both_paths(varied, progress, prefix.replace("_", " "))
        figures.update({f"{prefix}_status_mismatches": agree["status_mismatches"],
                        f"{prefix}_max_range_rel_diff": agree["max_range_rel_diff"],
                        f"{prefix}_designs_thrown": agree["thrown"]})
    return figures


def paths(count: int, seed: int, repeat: int, batch_repeat: int, progress: bool) -> dict:
    """The two analytic paths on the same designs: times, speed-up, batch throughput, agreement."""
    designs = bench_designs(count, seed)

    def each(label: str, simulate_one: Callable, times: int, among=None):
        results, seconds = [], []
        for design in progress_bar(designs if among is None else among, desc=label, unit="design",
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

    # The cost of friction: the same designs with TYPICAL_LOSSES, on both paths, against the
    # ideal machine's times above (the same run).
    lossy = [dataclasses.replace(design, losses=TYPICAL_LOSSES) for design in designs]
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
        "friction_losses": dataclasses.asdict(TYPICAL_LOSSES),
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

