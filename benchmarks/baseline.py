"""A baseline: an earlier commit's sources, timed beside this checkout's (``benchmarks.paired``)."""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Callable

from benchmarks.measure import CHECKOUT, checkout_commit, git_output
from benchmarks.paired import paired, paired_env


class BaselineError(RuntimeError):
    """The baseline commit could not be checked out or benchmarked (the message says why)."""


def baseline_source(rev: str, folder: Path, repository: Path = CHECKOUT) -> str:
    """Write commit ``rev``'s tree of ``repository`` (this checkout's, by default) into ``folder``
    (``git archive``); returns the full commit id. BaselineError, in one line naming ``rev``, where
    git is missing, ``repository`` has no history (a source archive), ``rev`` is not in a shallow
    clone's history, or it is no commit."""
    try:
        git_output(repository, "--version")
    except (OSError, subprocess.CalledProcessError) as error:
        raise BaselineError(f"--baseline {rev}: git is not installed ({error})") from error
    if checkout_commit(repository) is None:
        raise BaselineError(f"--baseline {rev}: {repository} has no git history (a source archive, not a "
                            "clone), so it holds no other commit to time")
    try:
        commit = git_output(repository, "rev-parse", "--verify", "--end-of-options", f"{rev}^{{commit}}")
    except subprocess.CalledProcessError as error:
        if git_output(repository, "rev-parse", "--is-shallow-repository") == "true":
            raise BaselineError(f"--baseline {rev}: not in the history of {repository}, a shallow clone "
                                "(git fetch --unshallow brings the rest)") from error
        raise BaselineError(f"--baseline {rev}: not a commit of {repository} ({error.stderr.strip()})") from error
    archive = subprocess.run(["git", "archive", commit], cwd=repository, capture_output=True, check=True).stdout
    subprocess.run(["tar", "-x", "-C", str(folder)], input=archive, check=True)
    if not (Path(folder) / "analytic" / "__init__.py").is_file():   # else this checkout's would be imported
        raise BaselineError(f"--baseline {rev}: commit {commit[:7]} has no analytic package")
    return commit


def with_baseline(run_figures: Callable[[], dict], rev: str, designs: int, seed: int, progress: bool,
                  cold_rounds: int = 0, repository: Path = CHECKOUT) -> dict:
    """This checkout's figures (``run_figures``), then commit ``rev`` of ``repository`` (this
    checkout's, by default) against this checkout's, interleaved (``benchmarks.paired``):
    ``figures["baseline"]`` holds, per key of ``paired.SHOT_KEYS`` and the batches (and
    ``compile_s`` with ``cold_rounds``), both sides' figures and their ratio."""
    with tempfile.TemporaryDirectory(prefix="bench-baseline-") as folder:
        commit = baseline_source(rev, Path(folder), repository)   # a revision that is not a commit stops here
        figures = run_figures()
        if progress:
            print(f"  against {rev}, interleaved (its first shot compiles its fast path) ...", file=sys.stderr,
                  flush=True)
        try:
            compared = paired(CHECKOUT, Path(folder), paired_env(CHECKOUT), paired_env(Path(folder)), designs, seed,
                              cold_rounds=cold_rounds, progress=progress)
        except RuntimeError as error:
            raise BaselineError(f"--baseline {rev}: {error}") from error
    figures["baseline"] = {"rev": rev, "commit": commit, **compared}
    return figures
