"""Command line: ``python -m benchmarks`` (also ``python -m analytic bench``), a thin layer over ``suite.run``."""

from __future__ import annotations

import argparse
import json
import sys

import benchmarks
from analytic.cli_shared import (EXIT_FAILED, EXIT_INVALID, EXIT_OK, OutputPathError, negative_numbers_as_values,
                                 output_file)
from analytic.design import DesignError
from analytic.design_file import load_design
from benchmarks import suite
from benchmarks.baseline import BaselineError, with_baseline
from benchmarks.plot import save_bench_figure
from benchmarks.report import format_bench, performance_page

#: The command as the performance page prints it.
COMMAND = "python -m benchmarks"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("design", nargs="?", help="design TOML for the models part (default: the paper's optimum)")
    parser.add_argument("--json", action="store_true", help="print the figures as one JSON object")
    parser.add_argument("--designs", type=int, default=200,
                        help="designs sampled over Table II besides the paper's optimum (default %(default)s)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the sample (default %(default)s)")
    parser.add_argument("--repeat", type=int, default=5,
                        help="runs per timing, the best counts (default %(default)s)")
    parser.add_argument("--cold", action="store_true",
                        help="also compile the fast path in a fresh process with an empty cache "
                             "(tens of seconds of CPU)")
    parser.add_argument("--plot", metavar="FILE.png", help="plot the time per shot and the agreement per design")
    parser.add_argument("--sweep-shots", type=int, default=40_960,
                        help="designs in the sweep-throughput part (in this process and on a 2-worker "
                             "LocalCluster; 0 skips it; default %(default)s)")
    parser.add_argument("--sweep-chunk", type=int, default=None,
                        help="chunk size of that sweep (default: the sweep files' default)")
    parser.add_argument("--baseline", metavar="REV",
                        help="also time commit REV of this repository (its sources in a temporary folder, run with "
                             "this interpreter) beside this checkout, the two interleaved shot by shot on one "
                             "CPU, and give each headline figure as a ratio to it; needs the checkout's git "
                             "history (a clone holding REV, not a source archive)")
    parser.add_argument("--markdown", metavar="FILE.md",
                        help="write the documentation's performance page from these figures")
    parser.add_argument("--quiet", action="store_true", help="no progress bars")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog=COMMAND, description=benchmarks.__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    add_arguments(parser)
    return parser


def _check(args: argparse.Namespace) -> tuple:
    """The design, the plot's path and the page's path ``args`` name (``None`` where not given);
    DesignError, OutputPathError or ValueError for one that cannot be used."""
    if args.designs < 0 or args.repeat < 1 or args.sweep_shots < 0 or (args.sweep_chunk or 1) < 1:
        raise ValueError(f"--designs = {args.designs}, --repeat = {args.repeat}, --sweep-shots = "
                         f"{args.sweep_shots}, --sweep-chunk = {args.sweep_chunk}: need designs >= 0, "
                         f"repeat >= 1, sweep shots >= 0 and sweep chunk >= 1")
    plot = None if args.plot is None else output_file(args.plot, "--plot")
    markdown = None if args.markdown is None else output_file(args.markdown, "--markdown", formats=(".md",))
    design = None if args.design is None else load_design(args.design)
    return design, plot, markdown


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark on ``argv`` (default: the process's); 0, 1 if the paths end differently on
    any design (``suite.MISMATCH_KEYS``) or the sweep's two tables differ, 2 for a refused input."""
    argv = negative_numbers_as_values(sys.argv[1:] if argv is None else list(argv))
    args = build_parser().parse_args(argv)
    try:
        design, plot, markdown = _check(args)
    except DesignError as error:
        print(f"invalid design: {error}", file=sys.stderr)
        return EXIT_INVALID
    except (OutputPathError, ValueError) as error:
        print(error, file=sys.stderr)
        return EXIT_INVALID

    def measure() -> dict:
        return suite.run(design, count=args.designs, seed=args.seed, repeat=args.repeat, cold=args.cold,
                         progress=not args.quiet, sweep_shots=args.sweep_shots, sweep_chunk=args.sweep_chunk)

    try:
        figures = (measure() if args.baseline is None else
                   with_baseline(measure, args.baseline, args.designs, args.seed, not args.quiet,
                                 cold_rounds=2 if args.cold else 0))
    except BaselineError as error:
        print(error, file=sys.stderr)
        return EXIT_INVALID
    if markdown is not None:
        markdown.write_text(performance_page(figures, " ".join([COMMAND, *argv])))
    if plot is not None:
        save_bench_figure(figures, plot)
    figures.pop("per_design")
    print(json.dumps(figures, indent=2) if args.json else format_bench(figures))
    if plot is not None and not args.json:
        print(f"plot written to {plot}")
    agree = not any(figures[key] for key in suite.MISMATCH_KEYS)
    return EXIT_OK if agree and figures.get("sweep_tables_identical", True) else EXIT_FAILED
