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
from pathlib import Path

from analytic.cli_shared import (EXIT_INVALID, EXIT_OK, OutputPathError, output_folder, read_command_line,
                                 units_argument)
from analytic.design import KINDS, DesignError
from analytic.design_file import chosen_units, save_design
from analytic.optimise import IDEAL_NO_SCATTER, Optimisation, optimise
from analytic.optimise.evaluate import DEFAULT_PROCESSES, PATHS
from analytic.design_space import default_problem, design_at, load_problem, with_kind
from analytic.optimise.report import format_report
from analytic.optimise.robust import DEFAULT_NODES

#: Release-angle standard deviation of ``--robust`` given without a value, deg.
DEFAULT_ROBUST_SIGMA_DEG = 2.0


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The ``optimise`` subcommand's arguments."""
    parser.add_argument("problem", nargs="?",
                        help="problem TOML (default: the paper's, analytic/data/paper_problem.toml)")
    parser.add_argument("--kind", choices=KINDS, default=None,
                        help="the machine every design is, instead of the problem's [machine] kind: a "
                             "fixed or floating-arm machine's counterweight is rigid on the arm, so its "
                             "link is fixed at 0 (default: the problem's, hinged if it names none)")
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
    units_argument(parser, "report.txt, the printed report and the plots (metric: the paper's cm)",
                   default="the units the problem file is mostly written in, else metric")


def run(args: argparse.Namespace) -> int:
    """Run the ``optimise`` subcommand; returns the exit code."""
    try:
        problem = default_problem() if args.problem is None else load_problem(args.problem)
        if args.kind is not None:
            problem = with_kind(problem, args.kind)
    except DesignError as error:
        print(f"invalid problem: {error}", file=sys.stderr)
        return EXIT_INVALID
    if args.robust is not None and not (math.isfinite(args.robust) and args.robust > 0.0):
        print(f"invalid --robust {args.robust!r}: the standard deviation must be a positive angle in deg",
              file=sys.stderr)
        return EXIT_INVALID
    if args.robust is not None and problem.outcome_constraints:
        print(f"invalid --robust {args.robust!r}: a problem with [loads] is optimised for the nominal shot only",
              file=sys.stderr)
        return EXIT_INVALID
    if args.robust is not None and problem.release_rule == "ideal":
        print(f"invalid --robust {args.robust!r}: {IDEAL_NO_SCATTER}", file=sys.stderr)
        return EXIT_INVALID
    if args.nodes < 1 or (args.workers is not None and args.workers < 1):
        print("invalid --nodes / --workers: must be at least 1", file=sys.stderr)
        return EXIT_INVALID
    try:
        out = output_folder(args.out, "--out")
    except OutputPathError as error:
        print(error, file=sys.stderr)
        return EXIT_INVALID
    result = optimise(problem, seed=args.seed, path=args.path, workers=args.workers,
                      robust_sigma=None if args.robust is None else math.radians(args.robust),
                      nodes=args.nodes, progress=not args.quiet)
    print(write_outputs(result, out, chosen_units(args.units, args.problem)))
    print(f"\nwritten to {out}/: report.txt, optimum.toml, convergence.png, sensitivity.png"
          + (", robust-optimum.toml" if args.robust is not None else ""))
    return EXIT_OK


def main(argv: list[str] | None = None) -> int:
    """``python -m analytic optimise`` on its own: parse ``argv`` and run."""
    parser = argparse.ArgumentParser(prog="python -m analytic optimise",
                                     description="Maximise range over the paper's design variables.")
    add_arguments(parser)
    return run(read_command_line(parser, argv))


def write_outputs(result: Optimisation, out: Path, system: str = "metric") -> str:
    """Write the report (in ``system``'s units, ``metric`` or ``imperial``), the figures and each optimum
    as a design file to the folder ``out``.

    Returns
    -------
    The report's text (also in ``out/report.txt``).
    """
    from analytic.optimise.plot import convergence_figure, save_figure, sensitivity_figure  # matplotlib, not for every command

    problem = result.problem
    report = format_report(result, system)
    (out / "report.txt").write_text(report + "\n")
    save_figure(convergence_figure(result.optima, system), out / "convergence.png")
    save_figure(sensitivity_figure(problem, result.sensitivity, f"range through the optimum ({problem.name})",
                                   system), out / "sensitivity.png")
    for optimum in result.optima.values():
        prefix = "robust-" if optimum.scatter.sigma > 0 else ""
        save_design(design_at(problem, optimum.values, name=f"{problem.name}-{prefix}optimum"),
                    out / f"{prefix}optimum.toml")
    return report
