"""Command line: ``python -m analytic simulate|aim|chart|calibrate|optimise|sweep|firing-table|bench|compile`` (a thin layer over the library)."""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

from analytic.cli_shared import (EXIT_INVALID, EXIT_NO_THROW, EXIT_OK, OutputPathError, output_file,
                                 output_folder, read_command_line, units_argument)
from analytic.design import Design, DesignError
from analytic.design_file import chosen_units, default_design, load_design
from analytic.report import format_shot
from analytic.scope import SCOPES
from analytic.units import LENGTH, NUMBER, Written, command_line_value, display, with_units


def load_or_default(path: str | None) -> Design:
    """The design in ``path``, or the built-in default (the paper's Table III optimum)."""
    return default_design() if path is None else load_design(path)


def _simulate(args: argparse.Namespace) -> int:
    from analytic.reference import simulate

    try:
        design = load_or_default(args.design)
        units = chosen_units(args.units, args.design)
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
        print(json.dumps(with_units(shot.to_json(), units), indent=2))
    else:
        print(format_shot(shot, units))
    if plot is not None:
        from analytic.plot import save_shot_figure

        save_shot_figure(shot, plot, units=units)
        if not args.json:
            print(f"plot written to {plot}")
    return EXIT_OK if shot.ok else EXIT_NO_THROW


def as_typed(error: DesignError, typed: dict[str, tuple[str | None, str]]) -> DesignError:
    """``error`` echoing its option's value as typed, with the value in file units in brackets
    (``target = "-10" (-3.048 m)``); ``typed``: option -> (the text, its file unit)."""
    text, unit = typed.get(error.field, (None, ""))
    if text is None:
        return error
    values = error.value if isinstance(error.value, (list, tuple)) else [error.value]
    if not all(isinstance(value, (int, float)) for value in values):
        return error
    inside = ", ".join(f"{value:.6g}" for value in values) + f" {unit}".rstrip()
    return DesignError(error.field, Written(text, inside, NUMBER), error.reason)


def _aim(args: argparse.Namespace) -> int:
    from analytic.aim import aim, check_inputs, default_bounds, format_aim
    from analytic.fields import field

    try:
        design = load_design(args.design)
        units = chosen_units(args.units, args.design)
        target_field = field(args.adjust)
        target_field.check(design)
        target = command_line_value("target", args.target, LENGTH, units)
        within = None if args.within is None else command_line_value("within", args.within, LENGTH, units)
        if args.bounds is None:
            bounds = default_bounds(target_field, design)
        else:
            parts = args.bounds.split(":")
            if len(parts) != 2:
                raise DesignError("bounds", args.bounds, "must be LOW:HIGH")
            bounds = tuple(command_line_value("bounds", part, target_field.kind, units) for part in parts)
        typed = {"target": (args.target, "m"), "within": (args.within, "m"),
                 "bounds": (args.bounds, target_field.unit)}
        try:
            check_inputs(target, bounds, within)
        except DesignError as error:
            raise as_typed(error, typed) from None
    except DesignError as error:
        print(f"invalid input: {error}", file=sys.stderr)
        return EXIT_INVALID
    result = aim(design, target_field.name, target, bounds=bounds, within=within)
    if args.json:
        print(json.dumps(with_units(result.to_json(), units), indent=2))
    else:
        print(format_aim(result, units))
    if not result.reached:
        if result.reachable is None:
            print("out of reach: no setting within the bounds throws", file=sys.stderr)
        else:
            (low, unit), (high, _), (shown, _) = (display(value, "m", units) for value in (*result.reachable, target))
            print(f"out of reach: the target {args.target} ({shown:.4g} {unit}) is outside the reachable span "
                  f"{low:.3f} .. {high:.3f} {unit}", file=sys.stderr)
        return EXIT_NO_THROW
    return EXIT_OK


def _chart(args: argparse.Namespace) -> int:
    from analytic.chart import chart, save_chart, vary
    from analytic.fields import field

    try:
        design = load_design(args.design)
        units = chosen_units(args.units, args.design)
        varies = []
        for spec in args.vary:
            name, equals, rest = spec.partition("=")
            parts = rest.split(":")
            if not equals or len(parts) != 3:
                raise DesignError("vary", spec, "must be FIELD=FROM:TO:STEPS")
            target_field = field(name)
            try:
                steps = int(parts[2])
            except ValueError:
                raise DesignError(f"vary {target_field.name} steps", parts[2], "must be a whole number") from None
            ends = (command_line_value(f"vary {target_field.name} {end}", part, target_field.kind, units)
                    for end, part in (("from", parts[0]), ("to", parts[1])))
            varies.append(vary(name, *ends, steps))
        if len(varies) > 2:
            raise DesignError("vary", len(varies), "give one or two fields to vary")
        if len({v.field.name for v in varies}) != len(varies):
            raise DesignError("vary", [v.field.name for v in varies], "the same field twice")
        for v in varies:
            v.field.check(design)
        out = output_folder(args.out, "--out")
    except DesignError as error:
        print(f"invalid input: {error}", file=sys.stderr)
        return EXIT_INVALID
    except OutputPathError as error:
        print(error, file=sys.stderr)
        return EXIT_INVALID
    result = chart(design, varies)
    csv_path, png_path = save_chart(result, out, units)
    thrown = int((result.status == "ok").sum())
    print(f"{len(result.status)} designs ({thrown} throw) in {result.seconds:.2f} s; "
          f"written {csv_path} and {png_path}")
    return EXIT_OK


def _compile(args: argparse.Namespace) -> int:
    from analytic import fast
    from analytic.fast import compiled

    seconds = fast.compile_all([s for s in SCOPES if s.name in args.scope] if args.scope else SCOPES, progress=True)
    how = compiled.mechanism() + (f": {compiled.mechanism_reason()}" if compiled.mechanism() == "public" else "")
    print("fast path ready (" + ", ".join(f"{name} {s:.1f} s" for name, s in seconds.items())
          + f"; numba mechanism {how})")
    return EXIT_OK


def _bench(arguments: list[str]) -> int:
    """``python -m analytic bench ...``: ``python -m benchmarks ...`` in a child process.

    The benchmarks measure this package from above (they import the engine and
    the cross-check too), so this package does not import them: the older name
    hands over to the command, as a shell alias would, and returns its exit code.
    """
    return subprocess.run([sys.executable, "-m", "benchmarks", *arguments]).returncode


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m analytic",
                                     description="Hand-derived Lagrange model of the hinged-counterweight trebuchet.")
    commands = parser.add_subparsers(dest="command", required=True)
    sim = commands.add_parser("simulate", help="simulate one shot")
    sim.add_argument("design", nargs="?", help="design TOML (default: the paper's Table III optimum)")
    sim.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
    sim.add_argument("--plot", metavar="FILE.png", help="write trajectory, machine at release, energy and loads plot "
                                                        "(.png, .pdf or .svg; no extension: .png)")
    units_argument(sim, "the printed table and the plot")
    sim.set_defaults(func=_simulate)

    aim = commands.add_parser("aim", help="find the setting of one field that lands on a target distance")
    aim.add_argument("design", help="design TOML")
    aim.add_argument("--target", required=True,
                     help="distance from the pivot: a number in --units (m or ft), or with a unit (30m, 100ft)")
    aim.add_argument("--adjust", required=True, metavar="FIELD",
                     help="the field to set, dotted (machine.release_angle, projectile.mass) or a machine name")
    aim.add_argument("--bounds", metavar="LOW:HIGH",
                     help="settings to search, bare in --units or with units (30:60, 2kg:10kg; default: see README)")
    aim.add_argument("--within", metavar="D", help="also report the settings landing within D of the target")
    aim.add_argument("--json", action="store_true", help="print one JSON object (SI, angles in degrees)")
    units_argument(aim)
    aim.set_defaults(func=_aim)

    cha = commands.add_parser("chart", help="range and peak loads against one or two varied fields (CSV and PNG)")
    cha.add_argument("design", help="design TOML")
    cha.add_argument("--vary", action="append", required=True, metavar="FIELD=FROM:TO:STEPS",
                     help="a field and its settings (counterweight_mass=1kg:3kg:9); once or twice")
    cha.add_argument("--out", required=True, metavar="DIR", help="folder for chart.csv and chart.png")
    units_argument(cha, "chart.png and bare numbers in --vary (chart.csv stays SI)")
    cha.set_defaults(func=_chart)
    from analytic.calibrate import cli as calibrate_cli

    cal = commands.add_parser("calibrate", help="fit loss coefficients, a drag factor or a release-angle offset "
                                                "to measured shots (weighted least squares)")
    calibrate_cli.add_arguments(cal)
    cal.set_defaults(func=calibrate_cli.run)
    comp = commands.add_parser("compile", help="compile the fast path into its disk cache now "
                                               "(make does it on install; later runs load it)")
    comp.add_argument("--scope", action="append", choices=[s.name for s in SCOPES],
                      help="compile only this scope (repeatable; default: all of them, analytic.scope)")
    comp.set_defaults(func=_compile)
    ben = commands.add_parser("bench", add_help=False,
                              help="time both analytic paths (and the engine) on the same designs, as ratios in "
                                   "one run: python -m benchmarks, under its older name")
    ben.set_defaults(func=lambda args: _bench([]))   # main hands its options over unparsed
    from analytic.optimise import cli as optimise_cli

    opt = commands.add_parser("optimise", help="maximise range over the paper's design variables")
    optimise_cli.add_arguments(opt)
    opt.set_defaults(func=optimise_cli.run)
    from analytic.sweep import cli as sweep_cli

    swp = commands.add_parser("sweep", help="shoot a grid, sample or uncertain inputs in chunks (in-process or "
                                            "on Dask), or report on a finished sweep")
    sweep_cli.add_arguments(swp)
    swp.set_defaults(func=sweep_cli.run)
    from analytic.firing import cli as firing_cli

    fir = commands.add_parser("firing-table", help="the settings of one field that land on each target, at each "
                                                   "projectile mass (CSV, JSON and a printable card)")
    firing_cli.add_arguments(fir)
    fir.set_defaults(func=firing_cli.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command ``argv`` names (default: the process's own, ``cli_shared.read_command_line``);
    its exit code."""
    given = sys.argv[1:] if argv is None else list(argv)
    if given[:1] == ["bench"]:   # every option after it is python -m benchmarks's
        return _bench(given[1:])
    args = read_command_line(build_parser(), argv)
    return args.func(args)
