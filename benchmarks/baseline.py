"""A baseline: an earlier commit's sources, timed beside this checkout's (``benchmarks.paired``)."""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Callable

from benchmarks.paired import paired, paired_env


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


def with_baseline(run_figures: Callable[[], dict], rev: str, designs: int, seed: int, progress: bool,
                  cold_rounds: int = 0) -> dict:
    """This checkout's figures (``run_figures``), then commit ``rev``'s against this checkout's,
    interleaved (``benchmarks.paired``): ``figures["baseline"]`` holds, per key of
    ``paired.SHOT_KEYS`` and the batches (and ``compile_s`` with ``cold_rounds``), both sides'
    figures and their ratio."""
    here = Path(__file__).resolve().parents[1]
    with tempfile.TemporaryDirectory(prefix="bench-baseline-") as folder:
        commit = baseline_source(rev, Path(folder))      # a revision that is not a commit stops here
        figures = run_figures()
        if progress:
            print(f"  against {rev}, interleaved (its first shot compiles its fast path) ...", file=sys.stderr,
                  flush=True)
        try:
            compared = paired(here, Path(folder), paired_env(here), paired_env(Path(folder)), designs, seed,
                              cold_rounds=cold_rounds, progress=progress)
        except RuntimeError as error:
            raise BaselineError(f"--baseline {rev}: {error}") from error
    figures["baseline"] = {"rev": rev, "commit": commit, **compared}
    return figures
