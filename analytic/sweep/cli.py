"""The ``sweep`` command: run a sweep file into a results folder, or report on a finished one.

``python -m analytic sweep SWEEP.toml --out DIR [--workers N | --scheduler ADDRESS] [--json]``
``python -m analytic sweep --report RESULTS [--out DIR] [--reach D ...] [--json]``

Exit codes: 0 done; 2 invalid input (the sweep file, a results folder that
holds something else, an unreachable scheduler), reported before anything is
written; 1 a chunk that failed on its executor; 130 interrupted (the chunks
written are kept: the same command resumes).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

from analytic.cli_shared import EXIT_FAILED, EXIT_INTERRUPTED, EXIT_INVALID, EXIT_OK, units_argument
from analytic.design import DesignError
from analytic.units import from_display, with_units


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The ``sweep`` subcommand's arguments."""
    from analytic.sweep.executors import DEFAULT_CONNECT_TIMEOUT

    parser.add_argument("sweep", nargs="?", metavar="SWEEP.toml", help="the sweep file")
    parser.add_argument("--out", metavar="DIR",
                        help="results folder (required to run; with --report, where the report goes, "
                             "default RESULTS/_report)")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N",
                       help="run on a local Dask cluster of N worker processes (default: this process, every core)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on the Dask cluster whose scheduler is at ADDRESS (tcp://host:8786)")
    parser.add_argument("--connect-timeout", type=float, default=DEFAULT_CONNECT_TIMEOUT, metavar="S",
                        help="seconds to wait for --scheduler (default %(default)s)")
    parser.add_argument("--report", metavar="RESULTS", help="analyse a finished sweep: summary and plots")
    parser.add_argument("--reach", type=float, action="append", metavar="D",
                        help="with --report: give the probability of reaching D (repeatable)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    units_argument(parser, "--report's summary and figures and of --reach", default="metric")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def _invalid(message: str) -> int:
    print(message, file=sys.stderr)
    return EXIT_INVALID


def run(args: argparse.Namespace) -> int:
    """Run the ``sweep`` subcommand; returns the exit code."""
    if args.report is not None:
        if args.sweep is not None or args.workers is not None or args.scheduler is not None:
            return _invalid("--report RESULTS takes no sweep file, --workers or --scheduler")
        return _report(args)
    if args.sweep is None:
        return _invalid("give a sweep file (SWEEP.toml --out DIR) or --report RESULTS")
    if args.reach is not None:
        return _invalid("--reach is an option of --report RESULTS")
    if args.out is None:
        return _invalid("--out DIR is required: the folder the results go to")
    if args.workers is not None and args.workers < 1:
        return _invalid(f"--workers = {args.workers}: must be at least 1")
    if not (math.isfinite(args.connect_timeout) and args.connect_timeout > 0):
        return _invalid(f"--connect-timeout = {args.connect_timeout}: must be a positive number of seconds")
    return _run(args)


def _run(args: argparse.Namespace) -> int:
    from analytic.sweep import storage
    from analytic.sweep.executors import ExecutorError, InProcess, OnDask
    from analytic.sweep.run import run_sweep
    from analytic.sweep.sweep_file import load_sweep

    try:
        sweep = load_sweep(args.sweep)
        storage.check_folder(args.out, storage.settings_of(sweep))
    except DesignError as error:
        return _invalid(f"invalid sweep: {error}")
    try:
        if args.scheduler is not None:
            executor = OnDask.connect(args.scheduler, timeout=args.connect_timeout)
        elif args.workers is not None:
            executor = OnDask.local(args.workers)
        else:
            executor = InProcess()
    except ExecutorError as error:
        return _invalid(f"invalid executor: {error}")
    try:
        with executor:
            result = run_sweep(sweep, args.out, executor, progress=not args.quiet)
    except KeyboardInterrupt:
        written = len(storage.written_chunks(args.out)) if Path(args.out).is_dir() else 0
        print(f"\ninterrupted: {written} of {sweep.chunks} chunks written in {args.out}; "
              f"the same command resumes", file=sys.stderr)
        return EXIT_INTERRUPTED
    except DesignError as error:
        return _invalid(f"invalid sweep: {error}")
    except Exception as error:   # a chunk that failed on its executor; what was written stays
        written = len(storage.written_chunks(args.out))
        print(f"sweep failed: {type(error).__name__}: {error}\n{written} of {sweep.chunks} chunks written in "
              f"{args.out}; the same command resumes", file=sys.stderr)
        return EXIT_FAILED
    if args.json:
        print(json.dumps(result.to_json(), indent=2))
    else:
        rate = f", {result.shots_run / result.seconds:,.0f} shots/s" if result.shots_run else ""
        print(f"{sweep.name}: {result.shots:,} shots in {result.chunks} chunks of {sweep.chunk_size}; "
              f"{result.chunks_written} written now ({result.executor}, {result.seconds:.1f} s{rate}); "
              f"status ok: {result.ok:,}\nresults in {args.out}/ (pyarrow.dataset.dataset) ; "
              f"report: python -m analytic sweep --report {args.out}")
    return EXIT_OK


def _report(args: argparse.Namespace) -> int:
    from analytic.sweep.report import make_report

    try:
        system = args.units or "metric"
        distances = None if args.reach is None else [from_display(d, "m", system) for d in args.reach]
        report = make_report(args.report, args.out, distances=distances, system=system)
    except DesignError as error:
        return _invalid(f"invalid results: {error}")
    if args.json:
        print(json.dumps(with_units(report.summary, system), indent=2))
    else:
        print(report.text)
        print(f"written: {', '.join(str(path) for path in report.files)}")
    return EXIT_OK


def main(argv: list[str] | None = None) -> int:
    """``python -m analytic sweep`` on its own: parse ``argv`` and run."""
    parser = argparse.ArgumentParser(prog="python -m analytic sweep", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    add_arguments(parser)
    return run(parser.parse_args(argv))
