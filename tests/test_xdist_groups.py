"""``make test`` runs the suite on every core with pytest-xdist's ``--dist loadgroup``, which keeps the
tests of a module marked ``xdist_group`` on one worker (a Dask cluster's, the rolling shots', the
recorded motion's: their module fixtures set up once). With pytest 9.2, pytest-xdist 3.8 silently
stopped grouping (pytest-xdist issue 1386: the ``@group`` it appends to a test's id no longer takes),
which ``pyproject.toml`` keeps out; these tests say so if the installed pair does not group."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: A module whose three tests are one group.
GROUPED = 'import pytest\n\npytestmark = pytest.mark.xdist_group("{group}")\n\n\n' \
          '@pytest.mark.parametrize("i", range(3))\ndef test(i):\n    pass\n'
#: A line of ``pytest -v`` under xdist: the worker and the test's id.
PASSED = re.compile(r"^\[(gw\d+)\] \[\s*\d+%\] PASSED (\S+)")


def test_the_makefile_runs_the_suite_with_dist_loadgroup():
    recipe = [line for line in (ROOT / "Makefile").read_text().splitlines() if "-m pytest -n" in line]
    assert len(recipe) == 1 and "--dist loadgroup" in recipe[0], recipe


def test_the_installed_pytest_and_xdist_keep_each_group_on_one_worker(tmp_path):
    # Two grouped modules and one without a group, on two workers, alone (no plugin but xdist).
    (tmp_path / "pytest.ini").write_text("[pytest]\n")
    for group in ("first", "second"):
        (tmp_path / f"test_{group}.py").write_text(GROUPED.format(group=group))
    (tmp_path / "test_alone.py").write_text('import pytest\n\n\n@pytest.mark.parametrize("i", range(4))\n'
                                            'def test(i):\n    pass\n')
    env = {key: value for key, value in os.environ.items() if not key.startswith("PYTEST_")}
    done = subprocess.run([sys.executable, "-m", "pytest", "-p", "xdist.plugin", "-p", "no:cacheprovider", "-n", "2",
                           "--dist", "loadgroup", "-v"], cwd=tmp_path, capture_output=True, text=True,
                          env=dict(env, PYTEST_DISABLE_PLUGIN_AUTOLOAD="1"), timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    workers = defaultdict(set)
    for match in filter(None, map(PASSED.match, done.stdout.splitlines())):
        workers[match.group(2).split("::")[0]].add(match.group(1))
    assert set(workers) == {"test_first.py", "test_second.py", "test_alone.py"}, done.stdout
    assert len(workers["test_first.py"]) == len(workers["test_second.py"]) == 1, \
        f"a group ran on several workers: {dict(workers)} (pytest-xdist issue 1386 with pytest 9.2)"
