"""The ``optimise`` command: maximise range for a problem, report beside the paper, write the design and plots.

``python -m analytic optimise [PROBLEM.toml] [--robust [SIGMA_DEG]] [--seed S] [--path fast|reference] [--out DIR]``
``python -m analytic optimise --around DESIGN.toml [PROBLEM.toml] [--factor F] [--bound NAME LOW HIGH] ...``

Without a problem file the paper's problem (``analytic/data/paper_problem.toml``). With
``--around`` the problem around that design (``analytic.optimise.around``): its variables within
bounds about its values, its machine kept, its own size as the limits unless the options (or a
problem file's ``[constraints]`` and ``[loads]``) say otherwise; the search starts from it.
Writes to ``--out``: ``report.txt`` (also printed), ``optimum.toml`` (a design
file ``python -m analytic simulate`` reads), ``convergence.png``,
``sensitivity.png``, and with ``--robust`` also ``robust-optimum.toml``.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
from pathlib import Path

from analytic.cli_shared import (EXIT_INVALID, EXIT_OK, OutputPathError, output_folder, read_command_line,
                                 units_argument)
from analytic.design import KINDS, Design, DesignError
from analytic.design_file import chosen_units, load_design, save_design
from analytic.optimise import IDEAL_NO_SCATTER, Optimisation, optimise
from analytic.optimise.around import (DEFAULT_ANGLE_WINDOW, DEFAULT_FACTOR, adopted, problem_around,
                                      start_values)
from analytic.optimise.evaluate import DEFAULT_PROCESSES, PATHS
from analytic.design_space import (ANGLE_VARIABLES, VARIABLE_NAMES, Problem, default_problem, design_at,
                                   load_problem, with_kind)
from analytic.optimise.report import format_report
from analytic.optimise.robust import DEFAULT_NODES
from analytic.optimise.search import Settings
from analytic.units import ANGLE, FORCE, LENGTH, command_line_value

#: Release-angle standard deviation of ``--robust`` given without a value, deg.
DEFAULT_ROBUST_SIGMA_DEG = 2.0


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The ``optimise`` subcommand's arguments."""
    parser.add_argument("problem", nargs="?",
                        help="problem TOML (default: the paper's problem, analytic/data/paper_problem.toml); "
                             "with --around only its [constraints] and [loads] are used")
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
    parser.add_argument("--generations", type=int, default=Settings.maxiter,
                        help="most generations of the global stage (default %(default)s)")
    around = parser.add_argument_group("around a design (--around)")
    around.add_argument("--around", metavar="DESIGN.toml",
                        help="optimise around this design instead of the paper's problem: each design "
                             "variable within bounds about its value, the design's machine, losses, frame, "
                             "projectile and release rule kept, its footprint and pivot height the limits; "
                             "the search starts from it and optimum.toml changes only the optimised fields")
    around.add_argument("--factor", type=float, default=DEFAULT_FACTOR,
                        help="lengths vary from value / F to value * F (default %(default)s)")
    around.add_argument("--angle-window", type=float, default=math.degrees(DEFAULT_ANGLE_WINDOW),
                        help="angles vary this far either side of their value, deg (default %(default)g)")
    around.add_argument("--bound", nargs=3, action="append", default=[], metavar=("NAME", "LOW", "HIGH"),
                        help=f"bounds of one variable instead ({', '.join(VARIABLE_NAMES)}; lengths in the "
                             "--units or with a unit, angles in deg); repeatable")
    around.add_argument("--max-footprint", help="footprint limit (default: the design's own)")
    around.add_argument("--max-height", help="pivot height limit (default: the design's own)")
    around.add_argument("--axle-radius", help="axle radius the counterweight clears at rest "
                                              "(default: the design's losses.axle_radius, else 0)")
    around.add_argument("--max-axle-load", help="limit on the peak axle load (force; default none)")
    units_argument(parser, "report.txt, the printed report and the plots (metric: the paper's cm)",
                   default="the units the problem file is mostly written in, else metric")


def around_problem(args: argparse.Namespace, design: Design, units: str) -> Problem:
    """The problem ``--around`` and its options ask for (``analytic.optimise.around.problem_around``);
    a problem file's ``[constraints]`` and ``[loads]`` apply, the options over them."""
    limits: dict = {}
    if args.problem is not None:
        given = load_problem(args.problem)
        limits = dict(max_footprint=given.max_footprint, max_height=given.max_height,
                      axle_radius=given.axle_radius, load_limits=given.load_limits, minimise=given.minimise,
                      min_range=given.min_range)
    for option in ("max_footprint", "max_height", "axle_radius"):
        text = getattr(args, option)
        if text is not None:
            limits[option] = command_line_value(f"--{option.replace('_', '-')}", text, LENGTH, units)
    if args.max_axle_load is not None:
        load = command_line_value("--max-axle-load", args.max_axle_load, FORCE, units)
        limits["load_limits"] = tuple(pair for pair in limits.get("load_limits", ()) if pair[0] != "axle_load") + (
            ("axle_load", load),)
    bounds = {}
    for name, low, high in args.bound:
        if name not in VARIABLE_NAMES:
            raise DesignError("--bound", name, f"not a design variable; expected one of {', '.join(VARIABLE_NAMES)}")
        kind = ANGLE if name in ANGLE_VARIABLES else LENGTH
        ends = [command_line_value(f"--bound {name}", text, kind, units) for text in (low, high)]
        bounds[name] = tuple(math.radians(end) for end in ends) if kind is ANGLE else tuple(ends)
    return problem_around(design, bounds, factor=args.factor, angle_window=math.radians(args.angle_window),
                          **limits)


def run(args: argparse.Namespace) -> int:
    """Run the ``optimise`` subcommand; returns the exit code."""
    design = None
    try:
        if args.around is not None:
            design = load_design(args.around)
            if args.kind is not None and args.kind != design.machine.kind:
                raise DesignError("--kind", args.kind, f"--around keeps the design's kind "
                                                       f"({design.machine.kind}): change it in the design file")
            problem = around_problem(args, design, chosen_units(args.units, args.around))
        else:
            problem = default_problem() if args.problem is None else load_problem(args.problem)
            if args.kind is not None:
                problem = with_kind(problem, args.kind)
    except DesignError as error:
        print(f"invalid {'design or bounds' if args.around else 'problem'}: {error}", file=sys.stderr)
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
    if args.nodes < 1 or (args.workers is not None and args.workers < 1) or args.generations < 1:
        print("invalid --nodes / --workers / --generations: must be at least 1", file=sys.stderr)
        return EXIT_INVALID
    try:
        out = output_folder(args.out, "--out")
    except OutputPathError as error:
        print(error, file=sys.stderr)
        return EXIT_INVALID
    result = optimise(problem, seed=args.seed, path=args.path, workers=args.workers,
                      robust_sigma=None if args.robust is None else math.radians(args.robust),
                      nodes=args.nodes, progress=not args.quiet,
                      start=None if design is None else start_values(design),
                      settings=Settings(seed=args.seed, maxiter=args.generations))
    print(write_outputs(result, out, chosen_units(args.units, args.around or args.problem), design))
    print(f"\nwritten to {out}/: report.txt, optimum.toml, convergence.png, sensitivity.png"
          + (", robust-optimum.toml" if args.robust is not None else ""))
    return EXIT_OK


def main(argv: list[str] | None = None) -> int:
    """``python -m analytic optimise`` on its own: parse ``argv`` and run."""
    parser = argparse.ArgumentParser(prog="python -m analytic optimise",
                                     description="Maximise range over the paper's design variables.")
    add_arguments(parser)
    return run(read_command_line(parser, argv))


def write_outputs(result: Optimisation, out: Path, system: str = "metric", around: Design | None = None) -> str:
    """Write the report (in ``system``'s units, ``metric`` or ``imperial``), the figures and each optimum
    as a design file to the folder ``out``; with ``around`` (the design optimised around) each optimum
    is that design with only the optimised fields changed (``analytic.optimise.around.adopted``).

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
        name = f"{problem.name}-{prefix}optimum"
        save_design(design_at(problem, optimum.values, name=name) if around is None else
                    dataclasses.replace(adopted(around, problem, optimum.values), name=name),
                    out / f"{prefix}optimum.toml")
    return report
