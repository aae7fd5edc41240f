"""Command line: ``python -m crosscheck [DESIGN.toml ...]`` (a thin layer over compare and report)."""

from __future__ import annotations

import argparse
import json
import os
import sys
from concurrent.futures import ProcessPoolExecutor
from functools import partial

from tqdm import tqdm

from analytic import fast
from analytic.command_line import (OutputPathError, negative_numbers_as_values, output_folder,
                                   positive_float, positive_int)
from analytic.design import DesignError
from analytic.result import Shot
from crosscheck.cases import QUICK_CASES, Case, default_suite, file_cases, quick_suite, sample_cases
from crosscheck.compare import DEFAULT_DT, Comparison, compare, step_study
from crosscheck.report import format_summary, format_table, write_report

EXIT_AGREE, EXIT_DISAGREE, EXIT_INVALID = 0, 1, 2


def run_cases(cases: list[Case], dt: float, workers: int, progress: bool = True) -> list[Comparison]:
    """Compare every case, on ``workers`` processes, in the order given.

    The analytic side of every case is shot first, in one fast-path batch
    (``analytic.fast.simulate_fast_many``, all cores, well under a second);
    the engine runs then take the processes.
    """
    task = partial(compare, dt=dt)
    fast.compile(progress=progress)
    analytic = fast.simulate_fast_many([case.design for case in cases])
    bar = tqdm(total=len(cases), desc="cross-check", unit="design", disable=not progress, file=sys.stderr)
    if workers <= 1:
        results = []
        for case, shot in zip(cases, analytic, strict=True):
            results.append(task(case, analytic_shot=shot))
            bar.update()
    else:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            results = []
            for result in pool.map(partial(_compare_shot, dt=dt), cases, analytic):
                results.append(result)
                bar.update()
    bar.close()
    return results


def _compare_shot(case: Case, shot: Shot, dt: float) -> Comparison:
    return compare(case, dt=dt, analytic_shot=shot)


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
    parser.add_argument("--seed", type=int, default=0, help="seed of the sample (default 0)")
    parser.add_argument("--dt", type=positive_float, default=DEFAULT_DT, help=f"engine step, s (default {DEFAULT_DT})")
    parser.add_argument("--report", metavar="DIR", help="write crosscheck.json and plots here")
    parser.add_argument("--json", action="store_true", help="print the comparisons as JSON")
    parser.add_argument("--table", action="store_true",
                        help="also print every design's every quantity (always in --report's table.txt)")
    parser.add_argument("--workers", type=positive_int, default=min(2, os.cpu_count() or 1),
                        help="processes (default: 2, the machine's cores)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(negative_numbers_as_values(sys.argv[1:] if argv is None else argv))
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
    except DesignError as error:
        print(f"invalid design: {error}", file=sys.stderr)
        return EXIT_INVALID

    comparisons = run_cases(cases, args.dt, args.workers, progress=not args.no_progress)
    study = None
    if args.report:
        reference = next((c.design for c in cases if c.name == "table3"), cases[0].design)
        study = step_study(reference)
        paths = write_report(args.report, comparisons, study)
    if args.json:
        print(json.dumps({"agree": all(c.agree for c in comparisons),
                          "comparisons": [c.to_json() for c in comparisons]}, indent=2))
    else:
        if args.table:
            print(format_table(comparisons))
            print()
        # --quick (``make run``'s check) prints the verdict and the worst cases only; the engine's
        # step, drift and convergence go to --report's table.txt (and with --table, here too).
        title = "quick cross-check, analytic against engine" if args.quick else None
        print(format_summary(comparisons, study, steps_detail=args.table, title=title,
                             engine_detail=not (args.quick and not args.table)))
        if args.report:
            print(f"report in {args.report}: " + ", ".join(p.name for p in paths))
    return EXIT_AGREE if all(c.agree for c in comparisons) else EXIT_DISAGREE
