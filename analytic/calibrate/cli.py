"""The ``calibrate`` command: fit parameters to measured shots, print the result, write the report.

``python -m analytic calibrate SHOTS.toml [--predict FIELD=VALUE[,VALUE...]] [--json] [--out DIR] [--quiet]``

``--predict`` gives the range at each setting of one design field, with its
one standard deviation from the fit (``analytic.calibrate.predict``).

Everything is checked before the first shot (the calibration file, every
design, every parameter, ``--out``); a bad input is exit 2 with one line
naming the field, its value and the reason, and nothing is written. A shot
that does not throw at the starting parameters is exit 3 (nothing written).
With ``--out``: ``report.txt``, ``calibration.json``, ``calibration.png``
and ``fitted/<setting>.toml`` (each shot's design at the fitted parameters, named after its setting),
and ``tracks.png`` where a shot measured a track.
"""

from __future__ import annotations

import argparse
import json
import sys

from analytic.cli_shared import EXIT_INVALID, EXIT_NO_THROW, EXIT_OK, OutputPathError, output_folder, units_argument
from analytic.design import DesignError
from analytic.design_file import chosen_units
from analytic.units import with_units


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The ``calibrate`` subcommand's arguments."""
    parser.add_argument("shots", metavar="SHOTS.toml", help="calibration file: fit = [...] and [[shot]] tables")
    parser.add_argument("--json", action="store_true", help="print one JSON object instead of the report")
    parser.add_argument("--out", metavar="DIR", help="write report.txt, calibration.json, calibration.png, "
                                                     "fitted/*.toml (and tracks.png with a track) here (created "
                                                     "if missing)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    units_argument(parser, "the printed report, report.txt and calibration.png (calibration.json stays SI)",
                   default="the units the calibration file is mostly written in, else metric")
    parser.add_argument("--predict", metavar="FIELD=VALUE[,VALUE...]",
                        help="predicted range, with its one-sd band, at each setting of one design field of the "
                             "first shot's design (e.g. machine.counterweight_mass=5,6.5,8 or =\"12 lb,15 lb\")")


def run(args: argparse.Namespace) -> int:
    """Run the ``calibrate`` subcommand; returns the exit code."""
    from pathlib import Path

    from analytic.calibrate.fit import CalibrationError, calibrate
    from analytic.calibrate.predict import check_settings, parse_predict, predict_ranges
    from analytic.calibrate.report import format_report, to_json, write
    from analytic.calibrate.spec import load_calibration

    if args.out is not None and Path(args.out).exists() and not Path(args.out).is_dir():
        print(f"--out {args.out}: is a file, not a folder; give a folder (it is created if missing)",
              file=sys.stderr)
        return EXIT_INVALID
    try:
        spec = load_calibration(args.shots)
        settings = None if args.predict is None else parse_predict(args.predict)
        if settings is not None:
            check_settings(spec, *settings)
    except DesignError as error:
        print(f"invalid input: {error}", file=sys.stderr)
        return EXIT_INVALID
    units = chosen_units(args.units, args.shots)
    created = args.out is not None and not Path(args.out).exists()
    try:
        out = None if args.out is None else output_folder(args.out, "--out")
    except OutputPathError as error:
        print(error, file=sys.stderr)
        return EXIT_INVALID
    try:
        result = calibrate(spec, progress=not args.quiet)
    except CalibrationError as error:
        print(f"cannot calibrate: {error}", file=sys.stderr)
        if created and out is not None and not any(out.iterdir()):
            out.rmdir()   # made by the check before work, and nothing was written into it
        return EXIT_NO_THROW
    predictions = () if settings is None else predict_ranges(result, *settings)
    if args.json:
        print(json.dumps(with_units(to_json(result, predictions), units), indent=2))
    else:
        print(format_report(result, units, predictions))
    if out is not None:
        written = write(result, out, predictions, units)
        if not args.json:
            print(f"written {', '.join(str(p) for p in written)}")
    for line in result.warnings:
        print(f"warning: {line}", file=sys.stderr)
    return EXIT_OK
