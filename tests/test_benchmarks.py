"""The benchmarks' command lines: ``python -m benchmarks``, its older name ``python -m analytic bench``, and the
paired benchmark's worker protocol. The figures themselves are tested in test_analytic_fast.py."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path



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


def test_the_paired_worker_answers_each_request_and_names_an_unknown_one(tmp_path):
    # This checkout's sources, one design, every request the driver sends.
    from benchmarks.paired import Worker, paired_env

    here = Path(__file__).resolve().parents[1]
    worker = Worker(here, paired_env(here))
    try:
        setup = worker.ask(op="setup", count=1, seed=0, batch_repeat=2)
        assert setup["designs"] == 2 and len(setup["ranges"]) == 2 and setup["cpus"]
        assert worker.ask(op="pin", cpu=setup["cpus"][-1]) == {"cpu": setup["cpus"][-1]}
        for what in ("fast", "fast_no_loads", "reference"):
            seconds = worker.ask(op="time", what=what, indices=[1, 0], repeat=2)["seconds"]
            assert len(seconds) == 2 and all(s > 0.0 for s in seconds)
        for op in ("batch", "batch_one"):
            answer = worker.ask(op=op)
            assert answer["shots"] == 4 and answer["seconds"] > 0.0
        assert "unknown op 'nap'" in worker.ask(op="nap")["error"]
    finally:
        worker.close()
