"""The benchmarks' command lines: ``python -m benchmarks``, its older name ``python -m analytic bench``, and the
command each baseline commit is run by. The figures themselves are tested in test_analytic_fast.py."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from benchmarks.baseline import baseline_command, baseline_source


def _run(*argv: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", *argv], capture_output=True, text=True,
                          cwd=Path(__file__).resolve().parents[1])


def test_analytic_bench_is_the_benchmarks_command_under_its_older_name():
    # Every option and the exit code pass through: the help is the benchmarks' own, and a refused
    # option gives the benchmarks' message and exit code 2.
    alias, command = _run("analytic", "bench", "--help"), _run("benchmarks", "--help")
    assert alias.returncode == command.returncode == 0
    assert alias.stdout == command.stdout
    for option in ("--json", "--designs", "--cold", "--plot", "--sweep-shots", "--baseline", "--markdown"):
        assert option in alias.stdout, option
    refused = _run("analytic", "bench", "--designs", "-1")
    assert refused.returncode == 2 and "--designs = -1" in refused.stderr and "need designs >= 0" in refused.stderr


def test_a_baseline_runs_by_its_own_command(tmp_path):
    # bfde05d, the performance page's baseline, had only ``python -m analytic bench``.
    old = tmp_path / "old"
    old.mkdir()
    baseline_source("bfde05d", old)
    assert baseline_command(old)[1:] == ["-m", "analytic", "bench"]
    # A tree with the benchmarks package is run by its ``python -m benchmarks``.
    (tmp_path / "new" / "benchmarks").mkdir(parents=True)
    (tmp_path / "new" / "benchmarks" / "__main__.py").write_text("")
    assert baseline_command(tmp_path / "new")[1:] == ["-m", "benchmarks"]
