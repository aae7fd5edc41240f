"""``python -m engine_model``: exit codes, JSON keys, messages, and the render command."""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys
from pathlib import Path

import pytest

from analytic.design import Base
from analytic.design_file import default_design, save_design
from analytic.result import JSON_KEYS, Status
from support import failure_designs, with_machine
from engine_model.cli import EXIT_ENGINE_ERROR, EXIT_INVALID, EXIT_NO_THROW, EXIT_OK, main


def test_simulate_json_has_the_shared_keys_and_the_drift(capsys):
    assert main(["simulate", "--json"]) == EXIT_OK
    data = json.loads(capsys.readouterr().out)
    assert list(data) == list(JSON_KEYS) + ["max_joint_drift"]
    assert data["status"] == "ok" and data["design"] == "paper-table3"
    assert 0.0 < data["max_joint_drift"] < 1e-4
    assert data["launch_angle"] == pytest.approx(43.4)  # the velocity rule's release angle, degrees
    assert (data["frame_release_displacement"], data["frame_release_velocity"]) == (0.0, 0.0)  # bolted down


def test_a_rolling_frame_is_reported_in_json_and_table(capsys, tmp_path):
    path = tmp_path / "wheels.toml"
    save_design(dataclasses.replace(default_design(), base=Base("rolling", 5.0)), path)
    assert main(["simulate", str(path), "--json", "--dt", "4e-4"]) == EXIT_OK
    data = json.loads(capsys.readouterr().out)
    # The 5 kg frame moves back a few mm and is rolling forward at release (0.86 m/s at the default step).
    assert -0.01 < data["frame_release_displacement"] < 0.0 < 0.5 < data["frame_release_velocity"] < 1.5
    assert main(["simulate", str(path), "--dt", "4e-4"]) == EXIT_OK
    out = capsys.readouterr().out
    assert "frame velocity at release" in out and "frame at landing" in out and "momentum error" in out


def test_simulate_table_names_the_outcome(capsys, tmp_path):
    path = tmp_path / "coarse.toml"
    save_design(default_design(), path)
    assert main(["simulate", str(path), "--dt", "2e-4", "--sling", "rope"]) == EXIT_OK
    out = capsys.readouterr().out
    assert "status" in out and "ok" in out and "range from pivot" in out and "rope sling" in out


def test_a_swing_beyond_the_step_budget_says_so_and_how_to_keep_the_step(capsys, tmp_path):
    # The design that never releases, on the Moon: 362,151 steps at the default step (11.9 s).
    design = failure_designs()[Status.NEVER_RELEASES]
    path = tmp_path / "moon.toml"
    save_design(dataclasses.replace(design, environment=dataclasses.replace(design.environment, gravity=1.62)),
                path)
    assert main(["simulate", str(path)]) == EXIT_NO_THROW
    out = capsys.readouterr().out
    assert "never_releases" in out
    assert "step budget" in out and "20,001 steps discarded" in out and "--dt 5e-05 keeps the default step" in out


def test_an_invalid_design_exits_2_with_the_field_named(capsys, tmp_path):
    path = tmp_path / "bad.toml"
    save_design(default_design(), path)
    path.write_text(path.read_text().replace("sling_length = 0.61", "sling_length = -0.61"))
    assert main(["simulate", str(path)]) == EXIT_INVALID
    assert "sling_length" in capsys.readouterr().err


def test_a_failed_throw_exits_3(capsys, tmp_path):
    path = tmp_path / "weak.toml"
    save_design(failure_designs()[Status.NEVER_FIRES], path)
    assert main(["simulate", str(path), "--json"]) == EXIT_NO_THROW
    assert json.loads(capsys.readouterr().out)["status"] == "never_fires"


def test_a_flight_that_never_lands_exits_3(capsys, tmp_path):
    path = tmp_path / "balloon.toml"
    save_design(failure_designs()[Status.NO_LANDING], path)
    assert main(["simulate", str(path), "--json"]) == EXIT_NO_THROW
    data = json.loads(capsys.readouterr().out)
    # 64.9 s: the flight bound for the engine's release state (analytic.limits.flight_time_limit).
    assert data["status"] == "no_landing" and "64.9 s" in data["message"] and data["range"] is None


def test_a_design_the_engine_cannot_model_exits_1(capsys, tmp_path):
    path = tmp_path / "lever.toml"
    save_design(with_machine(default_design(), arm_inertia=0.0, arm_cg=0.0), path)
    assert main(["simulate", str(path)]) == EXIT_ENGINE_ERROR
    assert "massless lever" in capsys.readouterr().err


def test_render_writes_frames_and_a_gif(capsys, tmp_path):
    out = tmp_path / "frames"
    assert main(["render", "--out", str(out), "--fps", "1", "--slow-motion", "2", "--dt", "4e-4", "--gif",
                 "--quiet"]) == EXIT_OK
    frames = sorted(out.glob("frame_*.png"))
    # t = 0 s in slow motion (a frame per 0.5 s until the release at 0.42 s), then the
    # release and every 1 s of flight: 1.42, 2.42, 3.42 s, and the landing at 3.64 s.
    assert len(frames) == 6
    assert (out / "shot.gif").stat().st_size > 0
    assert f"{len(frames)} frames" in capsys.readouterr().out


def test_module_entry_point_runs():
    done = subprocess.run([sys.executable, "-m", "engine_model", "simulate", "--dt", "4e-4"],
                          capture_output=True, text=True, cwd=Path(__file__).resolve().parents[1])
    assert done.returncode == EXIT_OK, done.stderr
    assert "paper-table3" in done.stdout
