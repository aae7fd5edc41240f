"""Speed of both models, as ratios to a baseline timed in the same run.

``python -m crosscheck.benchmark [DESIGN.toml] [--repeat N]``

The baseline is one analytic shot of the design at the default tolerance;
every other timing is reported as a multiple of it, so the numbers compare
across machines and loads. Each entry is the best of ``repeat`` runs after a
warm-up run.
"""

from __future__ import annotations

import argparse
import time
from typing import Callable

from analytic.design import Design
from analytic.design_file import default_design, load_design
from analytic.fast import simulate_fast
from analytic.reference import DEFAULT_ATOL, DEFAULT_RTOL
from analytic.reference import simulate as analytic_simulate
from engine_model import DEFAULT_DT
from engine_model import simulate as engine_simulate


def best_time(run: Callable[[], object], repeat: int) -> float:
    """Best wall-clock seconds of ``repeat`` calls of ``run`` after one warm-up call."""
    run()
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return min(times)


def benchmark(design: Design, repeat: int) -> list[tuple[str, float]]:
    """``(label, seconds)`` for the baseline first, then the variants."""
    entries = [
        ("analytic, default tolerance (baseline)", lambda: analytic_simulate(design)),
        ("analytic, 100x tighter tolerance",
         lambda: analytic_simulate(design, rtol=DEFAULT_RTOL / 100, atol=DEFAULT_ATOL / 100)),
        ("analytic, summary only (no histories)", lambda: analytic_simulate(design, histories=False)),
        ("analytic fast path (compiled)", lambda: simulate_fast(design)),
        (f"engine, default step {DEFAULT_DT:g} s", lambda: engine_simulate(design, dt=DEFAULT_DT)),
        (f"engine, step {2 * DEFAULT_DT:g} s", lambda: engine_simulate(design, dt=2 * DEFAULT_DT)),
    ]
    return [(label, best_time(run, repeat)) for label, run in entries]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m crosscheck.benchmark", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("design", nargs="?", help="design TOML (default: the paper's Table III optimum)")
    parser.add_argument("--repeat", type=int, default=5, help="timed runs per entry (best is kept)")
    args = parser.parse_args(argv)
    design = default_design() if args.design is None else load_design(args.design)
    results = benchmark(design, args.repeat)
    baseline = results[0][1]
    print(f"{design.name}: best of {args.repeat} whole shots (stages 1-3)")
    for label, seconds in results:
        print(f"  {label:<42} {seconds / baseline:8.4f} x baseline   ({seconds * 1e3:8.1f} ms)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
