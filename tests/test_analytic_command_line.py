"""Errors at the edges of every command: exit 2 and one line saying what was wrong, before any work."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from analytic.cli import main as analytic_main
from analytic.cli_shared import (OutputPathError, negative_numbers_as_values, output_file, output_folder,
                                 positive_float, positive_int)
from benchmarks.cli import main as bench_main
from crosscheck.cli import main as crosscheck_main
from engine_model.cli import main as engine_main

# A folder that cannot be created, even by root: /proc takes no new entries.
UNCREATABLE = "/proc/no-such-folder/out"


@pytest.fixture()
def a_file(tmp_path) -> Path:
    path = tmp_path / "a-file"
    path.write_text("not a folder")
    return path


def _bad_outputs(a_file: Path) -> dict[str, str]:
    return {"existing file": str(a_file), "under a file": str(a_file / "sub"), "uncreatable": UNCREATABLE}


# Every command's output option, with the rest of a command line that would otherwise run.
COMMANDS = {
    "analytic simulate --plot": (analytic_main, ["simulate", "--plot"], "{}/x.png"),
    "analytic optimise --out": (analytic_main, ["optimise", "--quiet", "--out"], "{}"),
    "benchmarks --plot": (bench_main, ["--quiet", "--designs", "0", "--plot"], "{}/x.png"),
    "engine_model render --out": (engine_main, ["render", "--quiet", "--out"], "{}"),
    "crosscheck --report": (crosscheck_main, ["--no-progress", "--report"], "{}"),
}


FOLDER_OPTIONS = [name for name, (_, _, form) in COMMANDS.items() if form == "{}"]
FILE_OPTIONS = [name for name in COMMANDS if name not in FOLDER_OPTIONS]
# A folder option cannot be an existing file; a file option may (the file is overwritten).
CASES = ([(command, kind) for command in FOLDER_OPTIONS for kind in ("existing file", "under a file", "uncreatable")]
         + [(command, kind) for command in FILE_OPTIONS for kind in ("under a file", "uncreatable")])


@pytest.mark.parametrize("command, kind", CASES, ids=[f"{c} {k}" for c, k in CASES])
def test_an_unwritable_output_is_exit_2_with_one_line_before_any_work(command, kind, a_file, capsys):
    main, argv, form = COMMANDS[command]
    path = form.format(_bad_outputs(a_file)[kind])
    assert main([*argv, path]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert len(err.splitlines()) == 1, err
    assert err.startswith(f"{argv[-1]} {path}: ")
    assert "choose" in err or "give" in err   # what to do
    assert captured.out == ""                 # nothing was simulated first


@pytest.mark.parametrize("command", ["analytic simulate --plot", "benchmarks --plot"])
def test_an_unsupported_plot_format_is_exit_2(command, tmp_path, capsys):
    main, argv, _ = COMMANDS[command]
    assert main([*argv, str(tmp_path / "x.txt")]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"--plot {tmp_path / 'x.txt'}: cannot write .txt files; use one of .png, .pdf, .svg"
    assert not (tmp_path / "x.txt").exists()


def test_a_plot_without_extension_prints_the_path_it_writes(tmp_path, capsys):
    assert analytic_main(["simulate", "--plot", str(tmp_path / "adir")]) == 0
    out = capsys.readouterr().out
    assert f"plot written to {tmp_path / 'adir.png'}" in out
    assert (tmp_path / "adir.png").is_file() and not (tmp_path / "adir").exists()


@pytest.mark.parametrize("argv", [["simulate", "--iterations", "0"], ["simulate", "--dt", "-1e-4"],
                                  ["simulate", "--dt", "0"], ["render", "--out", "x", "--fps", "-5"]],
                         ids=["iterations 0", "dt -1e-4", "dt 0", "fps -5"])
def test_bad_engine_numbers_are_exit_2_naming_the_option(argv, capsys):
    with pytest.raises(SystemExit) as stop:
        engine_main(argv)
    assert stop.value.code == 2
    last = capsys.readouterr().err.strip().splitlines()[-1]
    assert f"argument {argv[-2]}: {argv[-1]} must be" in last


def test_crosscheck_negative_step_is_exit_2(capsys):
    with pytest.raises(SystemExit) as stop:
        crosscheck_main(["--dt", "-1e-4"])
    assert stop.value.code == 2
    assert "argument --dt: -1e-4 must be a positive number" in capsys.readouterr().err


# --------------------------------------------------------------------------- #
# The helpers themselves
# --------------------------------------------------------------------------- #

def test_output_folder_is_created_and_returned(tmp_path):
    folder = output_folder(tmp_path / "a" / "b")
    assert folder.is_dir() and folder == tmp_path / "a" / "b"


@pytest.mark.parametrize("given, written", [("shot", "shot.png"), ("shot.PDF", "shot.PDF"), ("s.svg", "s.svg")])
def test_output_file_extension(tmp_path, given, written):
    assert output_file(tmp_path / "sub" / given) == tmp_path / "sub" / written
    assert (tmp_path / "sub").is_dir()


def test_output_file_refuses_a_folder_of_that_name(tmp_path):
    (tmp_path / "x.png").mkdir()
    with pytest.raises(OutputPathError, match="is a folder; give a file name"):
        output_file(tmp_path / "x.png")


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_output_folder_refuses_a_read_only_folder(tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o555)
    with pytest.raises(OutputPathError, match="cannot create the folder"):
        output_folder(locked / "out")


@pytest.mark.parametrize("argv, expected", [
    (["--dt", "-1e-4"], ["--dt=-1e-4"]),
    (["--dt", "-.5", "x.toml"], ["--dt=-.5", "x.toml"]),
    (["--dt=1e-4", "-1"], ["--dt=1e-4", "-1"]),
    (["--json", "--quiet"], ["--json", "--quiet"]),
    (["-h"], ["-h"]),
])
def test_negative_numbers_become_option_values(argv, expected):
    assert negative_numbers_as_values(argv) == expected


@pytest.mark.parametrize("text", ["0", "-3", "1.5", "many"])
def test_positive_int_refuses(text):
    with pytest.raises(Exception, match="must be at least 1|not a whole number"):
        positive_int(text)


@pytest.mark.parametrize("text", ["0", "-1e-4", "inf", "nan", "fast"])
def test_positive_float_refuses(text):
    with pytest.raises(Exception, match="must be a positive number|not a number"):
        positive_float(text)
