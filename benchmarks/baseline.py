"""A baseline: an earlier commit's own benchmark, run just before and just after this checkout's."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Callable

#: The keys compared with a baseline, and the baseline's key each is divided by (the
#: pre-friction code has no ``fast_no_loads_median_shot_s``: its shots had no loads to find).
BASELINE_RATIOS = {"fast_median_shot_s": ("fast_median_shot_s", "fast_no_loads_median_shot_s"),
                   "fast_no_loads_median_shot_s": ("fast_no_loads_median_shot_s", "fast_median_shot_s"),
                   "batch_shots_per_s": ("batch_shots_per_s",),
                   "reference_median_shot_s": ("reference_median_shot_s",)}


class BaselineError(RuntimeError):
    """The baseline commit could not be checked out or benchmarked (the message says why)."""


def baseline_source(rev: str, folder: Path) -> str:
    """Write commit ``rev``'s tree into ``folder`` (``git archive``); returns the full commit id."""
    here = Path(__file__).resolve().parent
    try:
        top = subprocess.run(["git", "rev-parse", "--show-toplevel"], cwd=here, capture_output=True, text=True,
                             check=True).stdout.strip()
        commit = subprocess.run(["git", "rev-parse", "--verify", f"{rev}^{{commit}}"], cwd=top,
                                capture_output=True, text=True, check=True).stdout.strip()
        archive = subprocess.run(["git", "archive", commit], cwd=top, capture_output=True, check=True).stdout
    except FileNotFoundError as error:
        raise BaselineError(f"--baseline {rev}: git is not installed ({error})") from error
    except subprocess.CalledProcessError as error:
        raise BaselineError(f"--baseline {rev}: not a commit of this repository "
                            f"({error.stderr.strip() if isinstance(error.stderr, str) else error.stderr.decode().strip()})"
                            ) from error
    subprocess.run(["tar", "-x", "-C", str(folder)], input=archive, check=True)
    if not (Path(folder) / "analytic" / "__init__.py").is_file():   # else this checkout's would be imported
        raise BaselineError(f"--baseline {rev}: commit {commit[:7]} has no analytic package")
    return commit


def baseline_command(folder: Path) -> list[str]:
    """The command of the benchmark in ``folder``, its own: ``python -m benchmarks`` where it has
    that package, else the ``python -m analytic bench`` of the commits before it."""
    if (Path(folder) / "benchmarks" / "__main__.py").is_file():
        return [sys.executable, "-m", "benchmarks"]
    return [sys.executable, "-m", "analytic", "bench"]


def baseline_figures(folder: Path, designs: int, seed: int, repeat: int, progress: bool) -> dict:
    """The benchmark of the sources in ``folder`` (its own command, ``baseline_command``, with
    ``--json``), run with this interpreter and its packages; its fast path compiles there first
    (cached in ``folder``)."""
    own = baseline_command(folder)
    options = subprocess.run([*own, "--help"], cwd=folder, env=_baseline_env(folder), capture_output=True,
                             text=True)
    if options.returncode != 0:
        raise BaselineError(f"the baseline's bench does not start: {options.stderr.strip()[-400:]}")
    command = [*own, "--json", "--quiet", "--designs", str(designs), "--seed", str(seed), "--repeat", str(repeat)]
    for flag, extra in (("--no-cold", ["--no-cold"]), ("--sweep-shots", ["--sweep-shots", "0"])):
        if flag in options.stdout:
            command += extra
    if progress:
        print("  the baseline's benchmark (its first shot compiles its fast path) ...", file=sys.stderr, flush=True)
    done = subprocess.run(command, cwd=folder, env=_baseline_env(folder), capture_output=True, text=True)
    try:
        return json.loads(done.stdout)
    except json.JSONDecodeError as error:
        raise BaselineError(f"the baseline's bench gave no figures (exit {done.returncode}): "
                            f"{done.stderr.strip()[-400:]}") from error


def _baseline_env(folder: Path) -> dict:
    """The environment of the baseline's processes: its own sources first, no progress bars."""
    return dict(os.environ, PYTHONPATH=str(folder), PYTHONDONTWRITEBYTECODE="1")


def with_baseline(run_figures: Callable[[], dict], rev: str, designs: int, seed: int, repeat: int,
                  progress: bool) -> dict:
    """This checkout's figures with commit ``rev``'s measured just before and just after them (B A B),
    and each key of ``BASELINE_RATIOS`` as a ratio to the mean of the two."""
    with tempfile.TemporaryDirectory(prefix="bench-baseline-") as folder:
        commit = baseline_source(rev, Path(folder))
        before = baseline_figures(Path(folder), designs, seed, repeat, progress)
        figures = run_figures()
        after = baseline_figures(Path(folder), designs, seed, repeat, progress)
    base = {}
    for key, candidates in BASELINE_RATIOS.items():
        found = next((name for name in candidates if name in before and name in after), None)
        if found is not None:
            base[key] = {"baseline_key": found, "baseline": [before[found], after[found]],
                         "ratio": figures[key] / (0.5 * (before[found] + after[found]))}
    figures["baseline"] = {"rev": rev, "commit": commit, "figures": base}
    return figures

