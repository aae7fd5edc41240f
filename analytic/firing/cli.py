"""The ``firing-table`` command: the settings that land on each target, written as CSV, JSON and a card.

``python -m analytic firing-table DESIGN.toml --targets FROM:TO:STEPS --adjust FIELD
[--projectile-mass FROM:TO:STEPS] [--calibration SHOTS.toml] --out DIR [--units imperial] [--json] [--force]``

Everything is checked before the first shot (the design, the field, the
targets and masses, the calibration file, ``--out``); a bad input is exit 2
with one line naming the option, its value as typed and the reason, and
nothing is written. Files already in ``--out`` are kept: the command refuses
to write over them unless ``--force``. A table with no entry in reach is
still written (each entry says "out of reach") and exits 3.
"""

from __future__ import annotations

import argparse
import json
import sys

from analytic.cli_shared import (EXIT_INVALID, EXIT_NO_THROW, EXIT_OK, OutputPathError, output_folder,
                                 units_argument)
from analytic.design import DesignError
from analytic.units import LENGTH, MASS, Kind, command_line_value


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The ``firing-table`` subcommand's arguments."""
    parser.add_argument("design", metavar="DESIGN.toml", help="design TOML")
    parser.add_argument("--targets", required=True, metavar="FROM:TO:STEPS",
                        help="target distances from the pivot: bare in --units or with units (20:40:5, 60ft:120ft:7)")
    parser.add_argument("--adjust", required=True, metavar="FIELD",
                        help="the field to set, dotted (machine.release_angle, machine.counterweight_mass) "
                             "or a machine name")
    parser.add_argument("--projectile-mass", metavar="FROM:TO:STEPS",
                        help="projectile masses, bare in --units or with units (default: the design's own)")
    parser.add_argument("--calibration", metavar="SHOTS.toml",
                        help="a calibration file (as for calibrate): shoot at its fitted parameters and give "
                             "each entry the band of where a shot lands")
    parser.add_argument("--out", required=True, metavar="DIR",
                        help="folder for firing-table.csv, .json and .png (created if missing)")
    parser.add_argument("--force", action="store_true", help="write over the table's files already in --out")
    parser.add_argument("--json", action="store_true", help="print the table's JSON (SI, settings in the units "
                                                            "analytic.Design holds, angles in radians)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    units_argument(parser, "the printed table, the card and bare numbers in --targets and --projectile-mass")


def parse_steps(option: str, text: str, kind: Kind, units: str):
    """``FROM:TO:STEPS`` as typed -> (steps,) values in ``kind``'s file unit; ``DesignError`` naming
    ``option`` and ``text``."""
    from analytic.firing.table import steps_of

    parts = text.split(":")
    if len(parts) != 3:
        raise DesignError(option, text, "must be FROM:TO:STEPS")
    try:
        steps = int(parts[2])
    except ValueError:
        raise DesignError(option, text, f"STEPS {parts[2]!r} is not a whole number") from None
    try:
        start, stop = (command_line_value(option, part, kind, units) for part in parts[:2])
    except DesignError as error:
        raise DesignError(option, text, error.reason) from None
    return steps_of(option, start, stop, steps, written=text)


def fresh_folder(given: str, force: bool):
    """The ``--out`` folder, checked and created; ``OutputPathError`` if it already holds a table's
    files and ``force`` is not given."""
    from analytic.firing.output import paths

    out = output_folder(given, "--out")
    existing = [str(p) for p in paths(out).values() if p.exists()]
    if existing and not force:
        raise OutputPathError(f"--out {given}: already holds {', '.join(existing)}; give another folder, or "
                              f"--force to write over them")
    return out


def run(args: argparse.Namespace) -> int:
    """Run the ``firing-table`` subcommand; returns the exit code."""
    from analytic.design_file import chosen_units, load_design
    from analytic.fields import field
    from analytic.firing.output import save_table
    from analytic.firing.table import check_choices, check_inputs

    try:
        design = load_design(args.design)
        units = chosen_units(args.units, args.design)
        target_field = field(args.adjust)
        target_field.check(design)
        targets = parse_steps("--targets", args.targets, LENGTH, units)
        masses = None if args.projectile_mass is None else parse_steps("--projectile-mass", args.projectile_mass,
                                                                         MASS, units)
        spec = None
        if args.calibration is not None:
            from analytic.calibrate.spec import load_calibration

            spec = load_calibration(args.calibration)
        check_choices(target_field, masses is not None, spec)
        check_inputs(design, target_field, [None] if masses is None else masses, None)
        out = fresh_folder(args.out, args.force)
    except DesignError as error:
        print(f"invalid input: {error}", file=sys.stderr)
        return EXIT_INVALID
    except OutputPathError as error:
        print(error, file=sys.stderr)
        return EXIT_INVALID
    return _make(args, design, target_field, targets, masses, spec, units, out, save_table)


def _make(args, design, target_field, targets, masses, spec, units, out, save_table) -> int:
    """Fit the calibration (if any), build the table, write and print it."""
    from analytic.firing.output import format_table
    from analytic.firing.table import firing_table

    calibration = None
    if spec is not None:
        from analytic.calibrate.fit import CalibrationError, calibrate

        try:
            calibration = calibrate(spec, progress=not args.quiet)
        except CalibrationError as error:
            print(f"cannot calibrate: {error}", file=sys.stderr)
            return EXIT_NO_THROW
    try:
        table = firing_table(design, target_field.name, targets, masses, calibration=calibration,
                             progress=not args.quiet)
    except DesignError as error:
        print(f"invalid input: {error}", file=sys.stderr)
        return EXIT_INVALID
    written = save_table(table, out, units)
    if args.json:
        print(json.dumps(table.to_json(units), indent=2))
    else:
        print(format_table(table, units))
        print(f"written {', '.join(str(p) for p in written.values())}")
    if calibration is not None:
        for line in calibration.warnings:
            print(f"warning: {line}", file=sys.stderr)
    return EXIT_OK if any(e.settings for e in table.entries) else EXIT_NO_THROW
