"""How a figure is measured: the best of repeated runs, a cold compile in a fresh process, and where it ran."""

from __future__ import annotations

import datetime
import math
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Callable

import numba
import scipy

#: This checkout: the sources these modules are, and the repository whose commit the figures name.
CHECKOUT = Path(__file__).resolve().parents[1]


def best_time(run: Callable[[], object], repeat: int) -> tuple[float, object]:
    """Best wall-clock seconds of ``repeat`` calls of ``run``, and the first call's result."""
    best, first = math.inf, None
    for i in range(repeat):
        began = time.perf_counter()
        result = run()
        best = min(best, time.perf_counter() - began)
        if i == 0:
            first = result
    return best, first


def cold_compile_seconds(folder: Path | None = None, env: dict | None = None,
                         scope: str = "everything") -> tuple[float, float]:
    """(compile, import) seconds of the fast path in a fresh process with an empty numba cache:
    this checkout's, or that of the sources in ``folder`` (run there, with ``env``).

    A checkout that compiles its kernel in scopes (``analytic.scope``) compiles the one named
    ``scope``; the one that handles every design by default, as a checkout before the
    scopes compiled its only kernel.
    """
    code = ("import time; t = time.perf_counter(); from analytic import fast; i = time.perf_counter() - t\n"
            "try:\n    from analytic import scope\nexcept ImportError:\n    print(fast.compile(), i)\n"
            f"else:\n    print(fast.compile(getattr(scope, {scope.upper()!r})), i)")
    with tempfile.TemporaryDirectory(prefix="numba-cold-") as cache:
        env = dict(os.environ if env is None else env, NUMBA_CACHE_DIR=cache)
        done = subprocess.run([sys.executable, "-c", code], env=env, cwd=folder, check=True, capture_output=True,
                              text=True)
    compile_s, import_s = (float(v) for v in done.stdout.split())
    return compile_s, import_s


def cache_load_seconds() -> float:
    """Seconds a fresh process takes to load every scope of the fast path from this checkout's
    (warm) disk cache: what each later run pays before its first shot."""
    code = "from analytic import fast; print(fast.compile())"
    done = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True)
    return float(done.stdout.split()[-1])


def git_output(repository: Path, *arguments: str) -> str:
    """``git arguments`` run in ``repository``: its output, stripped (CalledProcessError if it fails,
    OSError without git)."""
    return subprocess.run(["git", *arguments], cwd=repository, capture_output=True, text=True,
                          check=True).stdout.strip()


def checkout_commit(repository: Path = CHECKOUT) -> str | None:
    """The full id of the commit ``repository`` has checked out; None where it is not a git checkout of
    its own (a source archive, even one unpacked inside another repository's folder) or git is missing."""
    try:
        if Path(git_output(repository, "rev-parse", "--show-toplevel")).resolve() != Path(repository).resolve():
            return None
        return git_output(repository, "rev-parse", "--verify", "HEAD^{commit}")
    except (OSError, subprocess.CalledProcessError):
        return None


def machine_facts() -> dict:
    """When and where the figures were measured: date (UTC), processors, CPU model, versions, commit
    (its first 7 digits; None for sources outside git, such as an unpacked archive)."""
    model = None
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    commit = checkout_commit()
    return {"date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "cpu_count": os.cpu_count(), "cpu_model": model, "python": platform.python_version(),
            "numba": numba.__version__, "scipy": scipy.__version__,
            "commit": None if commit is None else commit[:7]}

