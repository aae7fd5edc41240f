"""``python -m analytic simulate``: JSON contract, table, plot, exit codes."""

from __future__ import annotations

import gc
import json
import math
import subprocess
import sys

import pytest

from analytic.cli import EXIT_INVALID, EXIT_NO_THROW, EXIT_OK, main
from analytic.design_file import default_design, dumps_design, save_design
from analytic.result import JSON_KEYS

from analytic.result import Status
from support import failure_designs


def test_json_has_every_contract_key(capsys):
    assert main(["simulate", "--json"]) == EXIT_OK
    out = json.loads(capsys.readouterr().out)
    assert set(JSON_KEYS) <= set(out)
    assert out["status"] == "ok" and out["design"] == "paper-table3"
    assert out["launch_angle"] == pytest.approx(43.4, abs=1e-6)  # the design's release angle, deg
    assert math.hypot(*out["release_velocity"]) == pytest.approx(out["release_speed"])
    assert out["range"] == pytest.approx(out["range_from_release"] + out["release_position"][0])


def test_table_output(capsys):
    assert main(["simulate"]) == EXIT_OK
    out = capsys.readouterr().out
    assert "status   ok" in out and "range (from pivot)" in out


def test_plot_is_written(tmp_path, capsys):
    target = tmp_path / "sub" / "shot.png"
    assert main(["simulate", "--plot", str(target)]) == EXIT_OK
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_invalid_design_file_exits_2_naming_the_field(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text(dumps_design(default_design()).replace("sling_length = 0.61", "sling_length = -0.61"))
    assert main(["simulate", str(path)]) == EXIT_INVALID
    err = capsys.readouterr().err
    assert "sling_length = -0.61: must be positive" in err


def test_a_design_that_does_not_throw_exits_non_zero(tmp_path, capsys):
    path = tmp_path / "weak.toml"
    save_design(failure_designs()[Status.NEVER_FIRES], path)
    assert main(["simulate", "--json", str(path)]) == EXIT_NO_THROW
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == "never_fires" and out["range"] is None


def test_module_entry_point_runs():
    done = subprocess.run([sys.executable, "-m", "analytic", "simulate", "--json"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout)["status"] == "ok"


def test_only_the_process_own_command_freezes_the_collector(tmp_path):
    """``main`` hides the objects of start-up from the collector (``gc.freeze``) when it runs
    the process's own command line, and leaves a caller's collector alone (a test process
    that froze would keep every cycle it had not yet collected)."""
    path = tmp_path / "bad.toml"
    path.write_text(dumps_design(default_design()).replace("sling_length = 0.61", "sling_length = -0.61"))
    before = gc.get_freeze_count()
    assert main(["simulate", str(path)]) == EXIT_INVALID
    assert gc.get_freeze_count() == before
    code = ("import gc, sys; from analytic.cli import main; "
            f"sys.argv = ['analytic', 'simulate', {str(path)!r}]; "
            "code = main(); print(code, gc.get_freeze_count() > 0)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.stdout.split() == [str(EXIT_INVALID), "True"], done.stderr


def test_the_reference_path_never_imports_numba():
    """``python -m analytic simulate`` and the optimiser's evaluator on the reference path need no
    compiler: the parser of every command must not import the fast path (with numba, 0.16 s more
    of a 0.77 s run), nor an ``Evaluator(path="reference")``."""
    code = ("import sys; from analytic.cli import main; sys.argv = ['analytic', 'simulate', '--json']; "
            "code = main(); print(code, 'numba' in sys.modules, file=sys.stderr); "
            "from analytic.optimise.evaluate import Evaluator; from analytic.design_space import default_problem; "
            "Evaluator(default_problem(), path='reference', workers=1).close(); "
            "print('numba' in sys.modules, file=sys.stderr)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.stderr.split()[-3:] == [str(EXIT_OK), "False", "False"], done.stderr
