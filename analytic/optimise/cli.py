"""The ``optimise`` command: maximise range for a problem, report beside the paper, write the design and plots.

``python -m analytic optimise [PROBLEM.toml] [--robust [SIGMA_DEG]] [--seed S] [--path fast|reference] [--out DIR]``

Without a problem file the paper's problem (``analytic/data/paper_problem.toml``).
Writes to ``--out``: ``report.txt`` (also printed), ``optimum.toml`` (a design
file ``python -m analytic simulate`` reads), ``convergence.png``,
``sensitivity.png``, and with ``--robust`` also ``robust-optimum.toml``.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

#: Exit codes as ``python -m analytic simulate``: done, invalid input.
EXIT_OK, EXIT_INVALID = 0, 2
#: Release-angle standard deviation of ``--robust`` given without a value, deg.
DEFAULT_ROBUST_SIGMA_DEG = 2.0
#: ``--path`` choices, the first the default: ``evaluate.PATHS``, spelled out so that
#: building the command line does not import numba (a test keeps the two equal).
PATHS = ("fast", "reference")
#: Worker processes of the reference path by default: ``evaluate.DEFAULT_PROCESSES``.
DEFAULT_PROCESSES = 2


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The ``optimise`` subcommand's arguments."""
    from analytic.optimise.robust import DEFAULT_NODES

    parser.add_argument("problem", nargs="?",
                        help="problem TOML (default: the paper's, analytic/data/paper_problem.toml)")
    parser.add_argument("--robust", metavar="SIGMA_DEG", type=float, nargs="?",
                        const=DEFAULT_ROBUST_SIGMA_DEG,
                        help="also maximise the expected range when the real release angle scatters "
                             f"normally about the set one with this standard deviation "
                             f"(deg; {DEFAULT_ROBUST_SIGMA_DEG:g} if no value is given)")
    parser.add_argument("--nodes", type=int, default=DEFAULT_NODES,
                        help="Gauss-Hermite nodes of the --robust expectation (default %(default)s)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the global stage (default %(default)s)")
    parser.add_argument("--path", choices=PATHS, default=PATHS[0],
                        help="how shots are simulated: compiled and batched on threads, or the reference "
                             "simulator in worker processes, to compare against (default %(default)s)")
    parser.add_argument("--workers", type=int, default=None,
                        help="threads (fast path; default every core) or processes (reference path; "
                             f"default {DEFAULT_PROCESSES}) simulating in parallel")
    parser.add_argument("--out", default="out/optimise", help="output folder (default %(default)s)")
    parser.add_argument("--quiet", action="store_true", help="no progress bars")


def run(args: argparse.Namespace) -> int:
    """Run the ``optimise`` subcommand; returns the exit code."""
    from analytic.design import DesignError
    from analytic.optimise.problem import default_problem, load_problem

    try:
        problem = default_problem() if args.problem is None else load_problem(args.problem)
    except DesignError as error:
        print(f"invalid problem: {error}", file=sys.stderr)
        return EXIT_INVALID
    if args.robust is not None and not (math.isfinite(args.robust) and args.robust > 0.0):
        print(f"invalid --robust {args.robust!r}: the standard deviation must be a positive angle in deg",
              file=sys.stderr)
        return EXIT_INVALID
    if args.nodes < 1 or (args.workers is not None and args.workers < 1):
        print("invalid --nodes / --workers: must be at least 1", file=sys.stderr)
        return EXIT_INVALID
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    report = optimise_and_report(problem, out, seed=args.seed, path=args.path, workers=args.workers,
                                 robust_sigma=None if args.robust is None else math.radians(args.robust),
                                 nodes=args.nodes, progress=not args.quiet)
    print(report)
    print(f"\nwritten to {out}/: report.txt, optimum.toml, convergence.png, sensitivity.png"
          + (", robust-optimum.toml" if args.robust is not None else ""))
    return EXIT_OK


def main(argv: list[str] | None = None) -> int:
    """``python -m analytic optimise`` on its own: parse ``argv`` and run."""
    parser = argparse.ArgumentParser(prog="python -m analytic optimise",
                                     description="Maximise range over the paper's design variables.")
    add_arguments(parser)
    return run(parser.parse_args(argv))


def optimise_and_report(problem, out: Path, *, seed: int, robust_sigma: float | None, nodes: int,
                        progress: bool, path: str = PATHS[0], workers: int | None = None) -> str:
    """Optimise ``problem`` (and its robust variant if ``robust_sigma``, rad), write outputs to ``out``.

    ``path`` and ``workers`` choose how shots are simulated (``evaluate.Evaluator``).

    Returns
    -------
    The report's text (also written to ``out/report.txt``).
    """
    from analytic.design_file import default_design, save_design
    from analytic.optimise.evaluate import Evaluator
    from analytic.optimise.plot import (
        convergence_figure,
        save_figure,
        sensitivity_figure,
    )
    from analytic.optimise.robust import release_scatter
    from analytic.optimise.search import Settings, maximise
    from analytic.optimise.sensitivity import scan
    from analytic.optimise.problem import design_at, variables_of

    began = time.perf_counter()
    settings = Settings(seed=seed)
    scatter = None if robust_sigma is None else release_scatter(robust_sigma, nodes)
    paper = variables_of(default_design().machine)
    with Evaluator(problem, path=path, workers=workers) as evaluator:
        optima = {"optimum": maximise(problem, evaluator, settings, progress=progress)}
        if scatter is not None:
            optima["robust optimum"] = maximise(problem, evaluator, settings, scatter=scatter,
                                                start=optima["optimum"].values, progress=progress)
        designs = {"paper, ours": paper} | {label: o.values for label, o in optima.items()}
        ranges = dict(zip(designs, evaluator.scores(list(designs.values()), settings.final_tolerance), strict=True))
        node_ranges = None if scatter is None else dict(zip(designs, evaluator.node_ranges(
            list(designs.values()), settings.final_tolerance, scatter), strict=True))
        sensitivity = scan(evaluator, problem, optima["optimum"].values, optima["optimum"].score,
                           settings.search_tolerance)

    report = _report(problem, paper, optima, ranges, scatter, node_ranges)
    report += f"\n\nTotal wall time {time.perf_counter() - began:.1f} s ({path} path)"
    (out / "report.txt").write_text(report + "\n")
    save_figure(convergence_figure(optima), out / "convergence.png")
    save_figure(sensitivity_figure(problem, sensitivity, f"range through the optimum ({problem.name})"),
                out / "sensitivity.png")
    for optimum in optima.values():
        prefix = "robust-" if optimum.scatter.sigma > 0 else ""
        save_design(design_at(problem, optimum.values, name=f"{problem.name}-{prefix}optimum"),
                    out / f"{prefix}optimum.toml")
    return report


def _report(problem, paper, optima, ranges, scatter, node_ranges) -> str:
    from analytic.optimise.report import (
        PAPER_RANGE,
        format_constraints,
        format_first_order,
        format_scatter,
        format_search,
        format_tables,
    )

    columns = [("paper", paper, PAPER_RANGE), ("paper, ours", paper, ranges["paper, ours"])]
    columns += [(label, optimum.values, ranges[label]) for label, optimum in optima.items()]
    sections = [f"Problem {problem.name!r}: maximise range"
                + ("" if scatter is None else f"; robust variant: maximise the expected range when the "
                   f"release angle scatters, sigma {math.degrees(scatter.sigma):g} deg (local stage "
                   f"from the optimum)"),
                "Columns: the paper's published Table III optimum; the same design under this problem "
                "and our model; " + "; ".join(f"our {label}" for label in optima),
                format_tables(problem, columns), format_constraints(problem, columns)]
    for label, optimum in optima.items():
        sections += [format_search(label, optimum), format_first_order(optimum)]
    if scatter is not None:
        sections.append(format_scatter(scatter, [(label, ranges[label], node_ranges[label])
                                                 for label in ranges]))
    return "\n\n".join(sections)
