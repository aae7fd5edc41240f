"""Messages a newcomer reads at a glance: a guess for a mistyped name, an empty file named as such,
notes only when true, a unit on every figure, rows named so they can be told apart, progress bars
that stay readable in a log, and ``make run``'s cross-check in one sentence."""

from __future__ import annotations

import dataclasses
import io
import shutil

from pathlib import Path

import pytest

from analytic.cli import EXIT_INVALID, main
from analytic.cli_shared import progress_bar
from analytic.report import format_shot
from crosscheck.cases import file_cases
from crosscheck.comparison import Comparison, Row
from crosscheck.report import format_plain
from support import TABLE3_FILE


def _design_file(tmp_path, old: str, new: str):
    path = tmp_path / "design.toml"
    text = TABLE3_FILE.read_text()
    assert old in text
    path.write_text(text.replace(old, new))
    return path


@pytest.mark.parametrize("old, new, guess", [
    ("sling_length = 0.6100", "slinglength = 0.6100", "did you mean 'sling_length'?"),
    ("sling_length = 0.6100", 'sling_length = "6 ftt"', "did you mean 'ft'?"),
    ("[machine]\n", "[machin]\n", "did you mean 'machine'?"),
], ids=["key", "unit", "table"])
def test_a_mistyped_name_gets_a_guess(tmp_path, capsys, old, new, guess):
    assert main(["simulate", str(_design_file(tmp_path, old, new))]) == EXIT_INVALID
    assert guess in capsys.readouterr().err


def test_a_mistyped_field_to_adjust_gets_a_guess(capsys):
    assert main(["aim", str(TABLE3_FILE), "--target", "40", "--adjust", "projectile.mas"]) == EXIT_INVALID
    assert "did you mean 'mass'?" in capsys.readouterr().err


def test_no_guess_when_nothing_is_close(tmp_path, capsys):
    assert main(["simulate", str(_design_file(tmp_path, "sling_length = 0.6100", "zzz = 0.6100"))]) == EXIT_INVALID
    assert "did you mean" not in capsys.readouterr().err


def test_an_empty_file_says_it_is_empty(tmp_path, capsys):
    path = tmp_path / "empty.toml"
    path.write_text("# nothing yet\n")
    assert main(["simulate", str(path)]) == EXIT_INVALID
    err = capsys.readouterr().err
    assert "is empty" in err and "required table is missing" not in err


def test_the_pushed_sling_note_only_when_the_tension_is_negative():
    from analytic.design_file import default_design
    from analytic.reference import simulate

    shot = simulate(default_design())
    note = "(negative: the rigid sling pushed)"
    for tension in (-abs(shot.min_sling_tension), abs(shot.min_sling_tension)):
        line = next(line for line in format_shot(dataclasses.replace(shot, min_sling_tension=tension)).splitlines()
                    if "min sling tension" in line)
        assert (note in line) == (tension < 0), line


def test_crosscheck_rows_from_files_are_named_by_their_file_when_the_name_says_nothing(tmp_path):
    copies = [tmp_path / "heavy.toml", tmp_path / "light.toml"]
    for path in copies:
        shutil.copy(TABLE3_FILE, path)   # both keep the default's name, paper-table3
    twins = [tmp_path / "a" / "twin.toml", tmp_path / "b" / "twin.toml"]
    named = tmp_path / "mine.toml"
    named.write_text(TABLE3_FILE.read_text().replace('name = "paper-table3"', 'name = "backyard"'))
    for path, name in zip(twins, ("same", "same"), strict=True):
        path.parent.mkdir()
        path.write_text(TABLE3_FILE.read_text().replace('name = "paper-table3"', f'name = "{name}"'))
    names = [case.name for case in file_cases([*map(str, copies), str(named), *map(str, twins)])]
    assert names == ["heavy", "light", "backyard", "twin", "twin"]


def _comparison(case: str, group: str, range_difference: float, ok: bool = True) -> Comparison:
    row = Row("range", "m", 40.0, 40.0 + range_difference, range_difference, 0.05, ok)
    return Comparison(case, group, "ok", "ok", (row,))


def test_make_runs_cross_check_is_one_sentence_and_introduces_the_deliberate_failure():
    comparisons = [_comparison("table3", "paper", 4e-5), _comparison("fails-no_landing", "failure", 0.0)]
    comparisons[1] = dataclasses.replace(comparisons[1], analytic_status="no_landing", engine_status="no_landing",
                                         rows=())
    text = format_plain(comparisons, "out/crosscheck/table.txt").splitlines()
    # 4e-5 m in 40 m: 1e-6 of the range
    assert text[0] == "the engine and the analytic model agree on all 2 designs, to 1e-06 of the range at worst"
    assert "fails-no_landing is a design made to fail on purpose, ending in no landing" in text[1]
    assert text[-1].endswith("out/crosscheck/table.txt")


def test_a_disagreement_is_said_as_plainly():
    comparisons = [_comparison("table3", "paper", 1.0, ok=False), _comparison("other", "paper", 0.0)]
    assert format_plain(comparisons).startswith("the engine and the analytic model DISAGREE on 1 of 2 designs: "
                                                "table3")


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_a_progress_bar_in_a_log_is_a_line_at_a_time():
    log = io.StringIO()
    for _ in progress_bar(range(1000), desc="work", file=log):
        pass
    text = log.getvalue()
    assert "\r" not in text and text.endswith("\n")
    lines = text.splitlines()
    assert 2 <= len(lines) <= 3 and "1000/1000" in lines[-1]   # the start, the end (and no flood between)


def test_a_progress_bar_on_a_terminal_is_redrawn_in_place():
    screen = _Terminal()
    for _ in progress_bar(range(10), desc="work", file=screen):
        pass
    assert "\r" in screen.getvalue()


def test_the_engines_pushed_sling_note_only_when_the_tension_is_negative():
    from analytic.design_file import default_design
    from engine_model import simulate
    from engine_model.report import format_shot as engine_table

    shot = simulate(default_design(), dt=4e-4)
    note = "(negative: the rigid sling pushed)"
    for tension in (-abs(shot.min_sling_tension), abs(shot.min_sling_tension)):
        line = next(line for line in engine_table(dataclasses.replace(shot, min_sling_tension=tension)).splitlines()
                    if line.startswith("min sling tension"))
        assert (note in line) == (tension < 0), line


@pytest.mark.parametrize("package, arguments", [
    ("analytic", ["simulate"]), ("engine_model", ["simulate"]),
    ("crosscheck", ["analytic/data/designs/fails-never_fires.toml", "--workers", "1", "--no-progress"])])
def test_a_reader_that_goes_away_ends_the_command_quietly(package, arguments):
    """``python -m PACKAGE ... | head -1``: the pipe is closed here before anything is
    written, so every write fails, and the command stops with 141 (128 + SIGPIPE) and no traceback."""
    import subprocess
    import sys

    from analytic.cli_shared import EXIT_PIPE_CLOSED

    process = subprocess.Popen([sys.executable, "-m", package, *arguments], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, cwd=Path(__file__).parents[1])
    process.stdout.close()
    err = process.stderr.read().decode()
    process.stderr.close()
    assert process.wait(timeout=120) == EXIT_PIPE_CLOSED, err
    assert err == ""
