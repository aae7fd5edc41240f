"""Time whole engine shots: ``python -m engine_model.benchmark [DESIGN.toml] [--repeat N] [--dt S]``."""

from __future__ import annotations

import argparse
import statistics
import time

from analytic.design import default_design, load_design
from engine_model.simulate import DEFAULT_DT, simulate


def time_shots(design, repeat: int, dt: float) -> list[float]:
    """Wall-clock seconds of ``repeat`` whole shots (stages 1-3), after one warm-up shot."""
    simulate(design, dt=dt)
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        simulate(design, dt=dt)
        times.append(time.perf_counter() - start)
    return times


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m engine_model.benchmark", description=__doc__)
    parser.add_argument("design", nargs="?", help="design TOML (default: the paper's Table III optimum)")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--dt", type=float, default=DEFAULT_DT)
    args = parser.parse_args(argv)
    design = default_design() if args.design is None else load_design(args.design)
    shot, diagnostics = simulate(design, dt=args.dt)
    times = time_shots(design, args.repeat, args.dt)
    print(f"{design.name}: {diagnostics.machine_steps} machine steps + {diagnostics.flight_steps} flight "
          f"steps of {args.dt:g} s; whole shot best {min(times):.3f} s, median "
          f"{statistics.median(times):.3f} s over {args.repeat} runs")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
