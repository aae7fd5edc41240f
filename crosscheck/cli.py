"""Command line: ``python -m crosscheck [DESIGN.toml ...]`` (a thin layer over the runner and the report)."""

from __future__ import annotations

import argparse
import json
import os
import sys

from analytic.cli_shared import (EXIT_FAILED, EXIT_INVALID, EXIT_OK, OutputPathError, output_folder,
                                 positive_float, positive_int, read_command_line)
from analytic.design import DesignError
from analytic.limits import PATHS
from crosscheck.cases import QUICK_CASES, as_built_cases, default_suite, file_cases, quick_suite, sample_cases
from crosscheck.comparison import DEFAULT_DT, step_study
from crosscheck.report import format_plain, format_summary, format_table, write_report
from crosscheck.runner import run

#: The exit codes under the names of what they mean here.
EXIT_AGREE, EXIT_DISAGREE = EXIT_OK, EXIT_FAILED


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="python -m crosscheck",
        description="Run designs through the analytic and the pymunk models and check that they agree.")
    parser.add_argument("designs", nargs="*", help="design TOML files (none: the default suite)")
    parser.add_argument("--quick", action="store_true",
                        help=f"instead of the default suite, its {len(QUICK_CASES)} designs of the paper's machine "
                             "(as published, at 61 deg, with losses) and one failure: seconds, not a minute")
    parser.add_argument("--sample", type=int, default=None, metavar="N",
                        help="designs drawn over the paper's Table II bounds (default suite: 24)")
    parser.add_argument("--as-built", type=positive_int, default=0, metavar="N",
                        help="also N machines as built, drawn at random (the sample's designs of each kind, with a "
                             "sling and a pouch of mass, a trough, a target's level, sometimes the ideal release "
                             "and every loss; seeded by --seed)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the sample (default 0)")
    parser.add_argument("--dt", type=positive_float, default=DEFAULT_DT, help=f"engine step, s (default {DEFAULT_DT})")
    parser.add_argument("--report", metavar="DIR", help="write crosscheck.json and plots here")
    parser.add_argument("--json", action="store_true", help="print the comparisons as JSON")
    parser.add_argument("--table", action="store_true",
                        help="also print every design's every quantity (always in --report's table.txt)")
    parser.add_argument("--workers", type=positive_int, default=min(2, os.cpu_count() or 1),
                        help="processes (default: 2, the machine's cores)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument("--path", choices=PATHS, default=PATHS[0],
                        help="the analytic model's path: fast (the default: compiled once per checkout, tens of "
                             "seconds, then a millisecond a design) or reference (scipy: no compile, the same "
                             "numbers to round-off, tens of milliseconds a design; what make run uses)")
    return parser


def main(argv: list[str] | None = None) -> int:
    args = read_command_line(build_parser(), argv)
    if args.report:
        try:
            output_folder(args.report, "--report")
        except OutputPathError as error:
            print(error, file=sys.stderr)
            return EXIT_INVALID
    try:
        if args.designs:
            cases = file_cases(args.designs) + sample_cases(args.sample or 0, args.seed)
        elif args.quick:
            cases = quick_suite() + sample_cases(args.sample or 0, args.seed)
        else:
            cases = default_suite(24 if args.sample is None else args.sample, args.seed)
        cases += as_built_cases(args.as_built, args.seed)
    except DesignError as error:
        print(f"invalid design: {error}", file=sys.stderr)
        return EXIT_INVALID

    report = run(cases, dt=args.dt, workers=args.workers, progress=not args.no_progress, path=args.path)
    comparisons = list(report.comparisons)
    study = None
    if args.report:
        # The step study's analytic shot is the run's own (no second shot, nor a compile of another scope,
        # nor any compile with --path reference): the paper's design, else the first that throws (a
        # user's files may hold none: then no study).
        shots = report.analytic_shots
        i = next((i for i, c in enumerate(cases) if c.name == "table3"),
                 next((i for i, shot in enumerate(shots) if shot is not None and shot.ok), None))
        if i is not None:
            study = step_study(cases[i].design, analytic=lambda design: shots[i])
        paths = write_report(args.report, comparisons, study)
    if args.json:
        print(json.dumps(report.to_json(), indent=2))
    else:
        if args.quick and not args.table:   # ``make run``'s check: one sentence, the detail in --report
            print(format_plain(comparisons, None if not args.report else f"{args.report}/table.txt"))
            return EXIT_AGREE if report.agree else EXIT_DISAGREE
        if args.table:
            print(format_table(comparisons))
            print()
        title = "quick cross-check, analytic against engine" if args.quick else None
        print(format_summary(comparisons, study, steps_detail=args.table, title=title))
        if args.report:
            print(f"report in {args.report}: " + ", ".join(p.name for p in paths))
    return EXIT_AGREE if report.agree else EXIT_DISAGREE
