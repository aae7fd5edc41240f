"""The README stays one screen, its Python example runs and prints what it says, its links and
its table of command lines match the files and the commands that exist."""

from __future__ import annotations

import contextlib
import io
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
README = ROOT / "README.md"
#: Lines the README may have: one screen, with the links into the docs (the issue's limit).
MAX_README_LINES = 150
#: A comment "# → TEXT" on a line of the example states what that line prints.
CLAIM = re.compile(r"#\s*→\s*(.+?)\s*$")


def readme() -> str:
    return README.read_text(encoding="utf-8")


def python_blocks(text: str) -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.MULTILINE | re.DOTALL)


def test_the_readme_is_one_screen():
    lines = readme().count("\n")
    assert lines <= MAX_README_LINES, f"README.md has {lines} lines, over {MAX_README_LINES}"


def test_the_readme_example_runs_and_prints_what_its_comments_say(tmp_path, monkeypatch):
    blocks = python_blocks(readme())
    assert len(blocks) == 1, "the README has one Python example"
    claims = [match.group(1) for line in blocks[0].splitlines() if (match := CLAIM.search(line))]
    assert claims, "the example states what it prints"
    monkeypatch.chdir(tmp_path)      # it writes shot.png where it runs
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(blocks[0], "README.md", "exec"), {"__name__": "readme_example"})
    lines = printed.getvalue().splitlines()
    for claim in claims:
        assert claim in lines, f"the README says the example prints {claim!r}; it printed {lines}"
    assert (tmp_path / "shot.png").stat().st_size > 0


def test_every_relative_link_in_the_readme_names_a_file_that_exists():
    targets = re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", readme())
    local = [target for target in targets if "://" not in target]
    assert local
    missing = [target for target in local if not (ROOT / target).exists()]
    assert not missing, f"README.md links to missing files: {missing}"


def subcommands(package: str) -> set[str]:
    """The subcommands ``python -m PACKAGE --help`` lists (its ``{a,b,...}`` choice)."""
    usage = subprocess.run([sys.executable, "-m", package, "--help"], cwd=ROOT, capture_output=True,
                           text=True, check=True).stdout
    return set(re.search(r"\{([a-z_,-]+)\}", usage).group(1).split(","))


@pytest.mark.parametrize("package", ["analytic", "engine_model"])
def test_the_readme_has_one_line_per_subcommand(package):
    listed = re.findall(rf"^\| `python -m {package} ([\w-]+)", readme(), flags=re.MULTILINE)
    assert len(listed) == len(set(listed)), f"a subcommand of {package} is listed twice: {listed}"
    assert set(listed) == subcommands(package)


def test_the_readme_lists_the_crosscheck_command():
    assert re.search(r"^\| `python -m crosscheck[ `]", readme(), flags=re.MULTILINE)
