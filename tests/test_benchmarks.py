"""The benchmarks' command lines: ``python -m benchmarks``, its older name ``python -m analytic bench``, the
paired benchmark's worker protocol, and the baseline: a commit's sources written out and timed beside
this checkout's. The baseline's tests take their commits from a small repository of their own (a
stand-in package whose history renames what the worker reads), not from this project's history, which
a shallow clone or a source archive lacks. The figures themselves are tested in test_analytic_fast.py."""

from __future__ import annotations

import functools
import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path
from types import SimpleNamespace

import pytest

from benchmarks import cli
from benchmarks.baseline import BaselineError, baseline_source, with_baseline
from benchmarks.measure import CHECKOUT, checkout_commit, machine_facts
from benchmarks.paired import SHOT_KEYS, paired, paired_env


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
    from benchmarks.paired import Worker

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


# --------------------------------------------------------------------------- #
# The baseline, from a repository of the tests' own
# --------------------------------------------------------------------------- #

#: The stand-in's shot: a design is a number, its range ``SCALE`` times it, after a little work
#: (each timed shot must take a measurable time).
_SHOT = '''
SCALE = {scale}


def _shot(design):
    sum(range(2000))
    return SimpleNamespace(range=SCALE * design)
'''
#: Its history, oldest first: each commit's files, ``None`` for a file the commit deletes. The first
#: has the older names the worker still reads (``analytic.simulate``, the sample in
#: ``analytic.bench``, no ``loads`` switch, a batch without a ``threads`` argument); the second the
#: present ones; the third shoots every design 1.5 times as far.
_HISTORY = (
    {"analytic/__init__.py": '"""A stand-in for the analytic package: the names the paired worker reads."""\n',
     "analytic/fast.py": "from types import SimpleNamespace\n\nimport numpy as np\n" + _SHOT.format(scale=2.0) + '''

def compile():
    return 0.0


def simulate_fast(design):
    return _shot(design)


def pack_many(designs):
    return np.array([[design] for design in designs])


def shoot(rows):
    return SCALE * np.asarray(rows)[:, 0]
''',
     "analytic/simulate.py": "from analytic.fast import _shot\n\n\ndef simulate(design, histories=True):\n"
                             "    return _shot(design)\n",
     "analytic/bench.py": "def bench_designs(count, seed):\n    return [1.0 + 0.5 * i for i in range(count + 1)]\n"},
    {"analytic/simulate.py": None, "analytic/bench.py": None,
     "analytic/reference.py": "from analytic.fast import _shot\n\n\ndef simulate(design, histories=True):\n"
                              "    return _shot(design)\n",
     "analytic/fast.py": "from types import SimpleNamespace\n\nimport numpy as np\n" + _SHOT.format(scale=2.0) + '''

def compile(scope=None):
    return 0.0


def simulate_fast(design, loads=True):
    return _shot(design)


def pack_many(designs):
    return np.array([[design] for design in designs])


def shoot(rows, threads=None):
    return SCALE * np.asarray(rows)[:, 0]
''',
     "benchmarks/__init__.py": "",
     "benchmarks/designs.py": "def bench_designs(count, seed):\n    return [1.0 + 0.5 * i for i in range(count + 1)]\n"},
    {"analytic/fast.py": lambda text: text.replace("SCALE = 2.0", "SCALE = 3.0")},
)
#: git run apart from the user's and the system's configuration and any repository around the tests.
_GIT_ENV = {**{key: value for key, value in os.environ.items() if not key.startswith("GIT_")},
            "GIT_CONFIG_GLOBAL": os.devnull, "GIT_CONFIG_NOSYSTEM": "1", "GIT_AUTHOR_NAME": "tests",
            "GIT_AUTHOR_EMAIL": "tests@example.invalid", "GIT_COMMITTER_NAME": "tests",
            "GIT_COMMITTER_EMAIL": "tests@example.invalid"}


def _git(folder: Path, *arguments: str) -> str:
    return subprocess.run(["git", *arguments], cwd=folder, env=_GIT_ENV, capture_output=True, text=True,
                          check=True).stdout.strip()


@pytest.fixture(scope="module")
def history(tmp_path_factory) -> SimpleNamespace:
    """The stand-in's repository (``_HISTORY``): ``repo``, its folder; ``commits``, their ids, oldest first;
    ``files``, each commit's files."""
    repo = tmp_path_factory.mktemp("stand-in")
    _git(repo, "init", "-q")
    commits, files = [], []
    for number, changes in enumerate(_HISTORY, start=1):
        for name, text in changes.items():
            path = repo / name
            if text is None:
                path.unlink()
                continue
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text(path.read_text()) if callable(text) else text)
        _git(repo, "add", "--all")
        _git(repo, "commit", "-q", "-m", f"commit {number}")
        commits.append(_git(repo, "rev-parse", "HEAD"))
        files.append(sorted(_git(repo, "ls-files").splitlines()))
    return SimpleNamespace(repo=repo, commits=commits, files=files)


def _written(folder: Path) -> list[str]:
    return sorted(str(path.relative_to(folder)) for path in folder.rglob("*") if path.is_file())


def test_a_baselines_sources_are_its_commits_whole_tree_and_import_as_its_own(history, tmp_path):
    assert baseline_source("HEAD~2", tmp_path, history.repo) == history.commits[0]
    assert _written(tmp_path) == history.files[0]        # the commit's, not the working tree's
    assert (tmp_path / "analytic" / "bench.py").is_file() and not (tmp_path / "benchmarks").exists()
    # Its own analytic package comes first, before the one installed from this checkout.
    done = subprocess.run([sys.executable, "-c", "import analytic; print(analytic.__file__)"], cwd=tmp_path,
                          env=dict(os.environ, PYTHONPATH=str(tmp_path)), capture_output=True, text=True, check=True)
    assert done.stdout.strip() == str(tmp_path / "analytic" / "__init__.py")


def test_a_revision_that_is_no_commit_is_refused_in_one_line_that_names_it(history, tmp_path):
    with pytest.raises(BaselineError) as refused:
        baseline_source("no-such-revision", tmp_path, history.repo)
    message = str(refused.value)
    assert message.startswith(f"--baseline no-such-revision: not a commit of {history.repo} (") and "\n" not in message
    assert not any(tmp_path.iterdir())


def test_the_command_refuses_a_baseline_it_cannot_take_with_exit_2_and_one_line(capsys):
    # From any copy of this project: a clone has no such commit, an archive no history at all.
    assert cli.main(["--designs", "1", "--repeat", "1", "--quiet", "--sweep-shots", "0",
                     "--baseline", "no-such-revision-here"]) == 2
    captured = capsys.readouterr()
    assert captured.err.startswith("--baseline no-such-revision-here: ") and captured.err.count("\n") == 1
    assert captured.out == ""


def test_a_shallow_clone_and_a_source_archive_say_they_lack_the_history(history, tmp_path):
    shallow = tmp_path / "shallow"
    _git(tmp_path, "clone", "-q", "--depth", "1", f"file://{history.repo}", str(shallow))
    (tmp_path / "head").mkdir()
    assert baseline_source("HEAD", tmp_path / "head", shallow) == history.commits[-1]   # the commit it has
    with pytest.raises(BaselineError) as refused:
        baseline_source("HEAD~2", tmp_path, shallow)
    assert str(refused.value) == (f"--baseline HEAD~2: not in the history of {shallow}, a shallow clone "
                                  "(git fetch --unshallow brings the rest)")
    # An unpacked archive, alone and inside another repository's folder (whose history is not its own).
    around = tmp_path / "around"
    _git(tmp_path, "init", "-q", str(around))
    for unpacked in (tmp_path / "archive", around / "archive"):
        unpacked.mkdir()
        archive = subprocess.run(["git", "archive", "HEAD"], cwd=history.repo, env=_GIT_ENV, capture_output=True,
                                 check=True).stdout
        subprocess.run(["tar", "-x", "-C", str(unpacked)], input=archive, check=True)
        with pytest.raises(BaselineError) as refused:
            baseline_source("HEAD~1", tmp_path, unpacked)
        assert str(refused.value) == (f"--baseline HEAD~1: {unpacked} has no git history (a source archive, "
                                      "not a clone), so it holds no other commit to time")


def test_the_paired_driver_times_two_commits_alike_and_says_whether_their_ranges_agree(history, tmp_path):
    # The first commit's older names and the second's present ones shoot the same ranges; the third's
    # are 1.5 times as far.
    folders = [tmp_path / f"commit-{number}" for number in (1, 2, 3)]
    for folder, commit in zip(folders, history.commits, strict=True):
        folder.mkdir()
        baseline_source(commit, folder, history.repo)
    older, present, farther = folders
    same = paired(present, older, paired_env(present), paired_env(older), 3, 0, batch_repeat=2)
    assert same["designs"] == 4 and same["same_designs"] and same["max_range_rel_diff"] == 0.0
    assert set(same["figures"]) == {*SHOT_KEYS, "batch_shots_per_s", "batch_one_thread_shots_per_s"}
    for key, entry in same["figures"].items():
        assert entry["this"] > 0.0 and entry["baseline"] > 0.0, key
        assert entry["ratio"] == pytest.approx(entry["this"] / entry["baseline"]), key
    differ = paired(farther, present, paired_env(farther), paired_env(present), 3, 0, batch_repeat=2)
    assert not differ["same_designs"] and differ["max_range_rel_diff"] == pytest.approx(0.5)


@pytest.mark.skipif(not (CHECKOUT / ".git").exists(),
                    reason="no .git: a source archive of this project has no history to take a baseline from")
def test_a_baseline_of_this_checkouts_own_head_is_its_committed_tree_and_the_figures_name_it(tmp_path):
    # Where this checkout has its history (a clone, shallow or not), --baseline reads it by default.
    commit = baseline_source("HEAD", tmp_path)
    assert commit == checkout_commit() and machine_facts()["commit"] == commit[:7]
    assert _written(tmp_path) == sorted(_git(CHECKOUT, "ls-tree", "-r", "--name-only", "HEAD").splitlines())


@pytest.mark.slow
def test_bench_times_a_baseline_beside_this_checkout_and_writes_the_page_from_its_figures(history, tmp_path,
                                                                                           capsys, monkeypatch):
    # This checkout's figures, then its fast path interleaved with the stand-in's second commit; the
    # stand-in's ranges are not the model's, and the page says so.
    monkeypatch.setattr(cli, "with_baseline", functools.partial(with_baseline, repository=history.repo))
    page = tmp_path / "performance.md"
    assert cli.main(["--json", "--designs", "2", "--repeat", "1", "--quiet", "--sweep-shots", "0",
                     "--baseline", "HEAD~1", "--markdown", str(page)]) == 0
    figures = json.loads(capsys.readouterr().out)
    baseline = figures["baseline"]
    assert baseline["rev"] == "HEAD~1" and baseline["commit"] == history.commits[1]
    assert baseline["designs"] == 3 and not baseline["same_designs"]
    for key in ("fast_median_shot_s", "fast_no_loads_median_shot_s", "batch_shots_per_s",
                "reference_median_shot_s", "batch_one_thread_shots_per_s"):
        entry = baseline["figures"][key]
        assert entry["this"] > 0.0 and entry["baseline"] > 0.0
    text = page.read_text()
    commit = checkout_commit()
    assert figures["commit"] == (None if commit is None else commit[:7])
    where = "from sources outside git (no commit)" if commit is None else f"at commit `{figures['commit']}`"
    assert f"Measured on {figures['date']} {where}, on {figures['cpu_count']} processors" in text
    assert f"## Against commit `{history.commits[1][:7]}` (`--baseline HEAD~1`)" in text
    assert "their ranges do NOT agree" in text
    assert f"| {figures['batch_shots_per_s']:,.0f} shots/s | `batch_shots_per_s` |" in text
    entry = baseline["figures"]["reference_median_shot_s"]
    assert f"| `reference_median_shot_s` | {entry['this'] * 1e3:.3f} ms | {entry['baseline'] * 1e3:.3f} ms |" in text
