"""Command line: ``python -m analytic simulate|optimise|bench|compile`` (a thin layer over the library)."""

from __future__ import annotations

import argparse
import json
import sys

from analytic.command_line import OutputPathError, negative_numbers_as_values, output_file
from analytic.design import Design, DesignError
from analytic.design_file import default_design, load_design
from analytic.report import format_shot

#: Exit codes: a throw, an unbuildable design, a valid design that does not throw.
EXIT_OK, EXIT_INVALID, EXIT_NO_THROW = 0, 2, 3


def load_or_default(path: str | None) -> Design:
    """The design in ``path``, or the built-in default (the paper's Table III optimum)."""
    return default_design() if path is None else load_design(path)


def _simulate(args: argparse.Namespace) -> int:
    from analytic.reference import simulate

    try:
        design = load_or_default(args.design)
    except DesignError as error:
        print(f"invalid design: {error}", file=sys.stderr)
        return EXIT_INVALID
    try:
        plot = None if args.plot is None else output_file(args.plot, "--plot")
    except OutputPathError as error:
        print(error, file=sys.stderr)
        return EXIT_INVALID
    shot = simulate(design)
    if args.json:
        print(json.dumps(shot.to_json(), indent=2))
    else:
        print(format_shot(shot))
    if plot is not None:
        from analytic.plot import save_shot_figure

        save_shot_figure(shot, plot)
        if not args.json:
            print(f"plot written to {plot}")
    return EXIT_OK if shot.ok else EXIT_NO_THROW


def _compile(args: argparse.Namespace) -> int:
    from analytic import fast

    seconds = fast.compile(progress=True)
    print(f"fast path ready ({seconds:.1f} s)")
    return EXIT_OK


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m analytic",
                                     description="Hand-derived Lagrange model of the hinged-counterweight trebuchet.")
    commands = parser.add_subparsers(dest="command", required=True)
    sim = commands.add_parser("simulate", help="simulate one shot")
    sim.add_argument("design", nargs="?", help="design TOML (default: the paper's Table III optimum)")
    sim.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
    sim.add_argument("--plot", metavar="FILE.png", help="write trajectory, machine at release and energy plot "
                                                        "(.png, .pdf or .svg; no extension: .png)")
    sim.set_defaults(func=_simulate)
    comp = commands.add_parser("compile", help="compile the fast path into its disk cache now "
                                               "(make does it on install; later runs load it)")
    comp.set_defaults(func=_compile)
    # The benchmark times both models, so it lives with the cross-check; the
    # command line, the top layer, may reach it.
    from crosscheck import benchmark

    ben = commands.add_parser("bench", help="time both analytic paths (and the engine) on the same designs, "
                                            "as ratios in one run (python -m crosscheck.benchmark)")
    benchmark.add_arguments(ben)
    ben.set_defaults(func=benchmark.main)
    from analytic.optimise import cli as optimise_cli

    opt = commands.add_parser("optimise", help="maximise range over the paper's design variables")
    optimise_cli.add_arguments(opt)
    opt.set_defaults(func=optimise_cli.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(negative_numbers_as_values(sys.argv[1:] if argv is None else argv))
    return args.func(args)
