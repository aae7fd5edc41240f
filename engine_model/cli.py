"""Command line: ``python -m engine_model simulate|render`` (a thin layer over the library)."""

from __future__ import annotations

import argparse
import json
import sys

from analytic.cli_shared import (EXIT_FAILED, EXIT_INVALID, EXIT_NO_THROW, EXIT_OK, OutputPathError,
                                 output_folder, positive_float, positive_int, read_command_line,
                                 units_argument)
from analytic.design import Design, DesignError
from analytic.design_file import chosen_units, default_design, load_design
from analytic.result import Shot
from analytic.units import with_units
from engine_model import DEFAULT_DT, EngineError, simulate
from engine_model.build import DEFAULT_ITERATIONS, SLINGS
from engine_model.timeline import DEFAULT_FPS, SWING_SLOW_MOTION

#: The exit code of an engine run that could not be trusted (unstable, joints apart).
EXIT_ENGINE_ERROR = EXIT_FAILED


def _design(path: str | None) -> Design:
    return default_design() if path is None else load_design(path)


def _run(args: argparse.Namespace) -> Shot | int:
    """Load the design and simulate it; returns the shot or an exit code."""
    try:
        design = _design(args.design)
    except DesignError as error:
        print(f"invalid design: {error}", file=sys.stderr)
        return EXIT_INVALID
    try:
        return simulate(design, dt=args.dt, iterations=args.iterations, sling=args.sling,
                        machine_after_release=args.command == "render")   # frames draw its swing on
    except EngineError as error:
        print(f"engine error: {error}", file=sys.stderr)
        return EXIT_ENGINE_ERROR


def _simulate(args: argparse.Namespace) -> int:
    from engine_model.report import format_shot

    shot = _run(args)
    if isinstance(shot, int):
        return shot
    units = chosen_units(args.units, args.design)
    if args.json:
        data = {**shot.to_json(), "max_joint_drift": shot.diagnostics.max_joint_drift,
                **(shot.diagnostics.support_loads or {})}
        print(json.dumps(with_units(data, units), indent=2))
    else:
        print(format_shot(shot, units))
    return EXIT_OK if shot.ok else EXIT_NO_THROW


def _render(args: argparse.Namespace) -> int:
    from engine_model.render import render_shot

    try:
        output_folder(args.out, "--out")
    except OutputPathError as error:
        print(error, file=sys.stderr)
        return EXIT_INVALID
    shot = _run(args)
    if isinstance(shot, int):
        return shot
    frames = render_shot(shot, args.out, fps=args.fps, swing_slow_motion=args.slow_motion,
                         gif=args.gif, mp4=args.mp4, progress=not args.quiet,
                         units=chosen_units(args.units, args.design))
    movies = [name for name, asked in (("shot.gif", args.gif), ("shot.mp4", args.mp4)) if asked]
    print(f"the shot drawn from the engine: {len(frames)} frames written to {args.out}"
          + (f" (and {', '.join(movies)})" if movies else ""))
    return EXIT_OK if shot.ok else EXIT_NO_THROW


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m engine_model",
                                     description="The trebuchet in the pymunk rigid-body engine.")
    commands = parser.add_subparsers(dest="command", required=True)
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("design", nargs="?", help="design TOML (default: the paper's Table III optimum)")
    common.add_argument("--dt", type=positive_float, default=None,
                        help=f"fixed step, s, kept whatever the shot costs (default {DEFAULT_DT:g}, "
                             f"lengthened where a slow machine would need more than the shot's step budget)")
    common.add_argument("--iterations", type=positive_int, default=DEFAULT_ITERATIONS,
                        help=f"solver iterations per step (default {DEFAULT_ITERATIONS})")
    common.add_argument("--sling", choices=SLINGS, default="rigid",
                        help="rigid rod (default) or rope that goes slack instead of pushing")

    sim = commands.add_parser("simulate", parents=[common], help="simulate one shot")
    sim.add_argument("--json", action="store_true",
                     help="print one JSON object (the analytic model's keys plus max_joint_drift, m)")
    units_argument(sim, "the printed table")
    sim.set_defaults(func=_simulate)

    ren = commands.add_parser("render", parents=[common], help="draw the shot as numbered PNG frames")
    ren.add_argument("--out", required=True, help="directory for frame_00000.png, ...")
    ren.add_argument("--fps", type=positive_float, default=DEFAULT_FPS,
                     help=f"frames per second of playback (default {DEFAULT_FPS:g})")
    ren.add_argument("--slow-motion", type=positive_float, default=SWING_SLOW_MOTION,
                     help=f"the swing this many times slower than real time (default {SWING_SLOW_MOTION:g};"
                          f" the flight plays in real time)")
    ren.add_argument("--gif", action="store_true", help="also write shot.gif")
    ren.add_argument("--mp4", action="store_true", help="also write shot.mp4 (H.264, ffmpeg from imageio-ffmpeg)")
    ren.add_argument("--quiet", action="store_true", help="no progress bar")
    units_argument(ren, "the frames' ground scale, landing mark and summary")
    ren.set_defaults(func=_render)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line on ``argv`` (default ``sys.argv[1:]``); returns the exit code."""
    args = read_command_line(build_parser(), argv)
    return args.func(args)
