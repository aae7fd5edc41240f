"""Valid but implausible designs run, and their shots say which input is implausible and why."""

from __future__ import annotations

import json

import numpy as np
import pytest
from support import with_environment, with_machine, with_projectile

import engine_model
from analytic import fast
from analytic.cli import main as analytic_main
from analytic.design_file import save_design
from analytic.plausibility import GRAVITY_RANGE, MAX_MASS_RATIO, MAX_WIND_SPEED, SPEED_OF_SOUND
from analytic.reference import simulate
from analytic.result import Shot, Status


def _only_warning(shot: Shot) -> str:
    assert len(shot.warnings) == 1, shot.warnings
    return shot.warnings[0]


def test_the_default_design_has_nothing_to_say(table3):
    assert simulate(table3).warnings == ()
    assert fast.simulate_fast(table3).warnings == ()


@pytest.mark.parametrize("wind", [-1e5, 1e3, -(MAX_WIND_SPEED + 1.0)], ids=["-1e5", "1e3", "just past"])
def test_a_wind_beyond_any_storm_is_flagged_on_every_path(table3, wind):
    design = with_environment(table3, wind_speed=wind)
    for shot in (simulate(design, histories=False), fast.simulate_fast(design)):
        assert "environment.wind_speed" in _only_warning(shot) and f"{MAX_WIND_SPEED:g} m/s" in shot.warnings[0]


def test_the_strongest_wind_measured_is_not_flagged(table3):
    assert fast.simulate_fast(with_environment(table3, wind_speed=-MAX_WIND_SPEED)).warnings == ()


def test_the_engine_flags_the_same(table3):
    shot = engine_model.simulate(with_environment(table3, wind_speed=-1e5))
    assert shot.warnings == fast.simulate_fast(with_environment(table3, wind_speed=-1e5)).warnings != ()


def test_a_projectile_heavier_than_its_counterweight_is_flagged(table3):
    design = with_projectile(table3, mass=7.0)   # counterweight 6.5 kg
    warning = _only_warning(fast.simulate_fast(design))
    assert warning.startswith("projectile.mass = 7 kg is not lighter than machine.counterweight_mass = 6.5 kg")


def test_a_counterweight_of_a_mountain_is_flagged(table3):
    mass = table3.projectile.mass * MAX_MASS_RATIO * 10
    warning = _only_warning(simulate(with_machine(table3, counterweight_mass=mass), histories=False))
    assert warning.startswith("machine.counterweight_mass / projectile.mass = 1e+05 is beyond 10000")


@pytest.mark.parametrize("gravity", [GRAVITY_RANGE[0] / 2, GRAVITY_RANGE[1] * 2])
def test_gravity_beyond_the_solar_systems_surfaces_is_flagged(table3, gravity):
    assert "environment.gravity" in _only_warning(fast.simulate_fast(with_environment(table3, gravity=gravity)))


def test_a_release_faster_than_sound_is_flagged(table3):
    shot = Shot(table3, Status.OK, "thrown", release_velocity=np.array([SPEED_OF_SOUND, 1.0]))
    assert _only_warning(shot).startswith("the release speed, 343 m/s, is beyond the speed of sound")
    assert Shot(table3, Status.OK, "thrown", release_velocity=np.array([300.0, 0.0])).warnings == ()


def test_json_carries_the_warnings_as_a_list(table3, tmp_path, capsys):
    path = tmp_path / "storm.toml"
    save_design(with_environment(table3, wind_speed=-1e5), path)
    assert analytic_main(["simulate", str(path), "--json"]) == 0   # a valid design still runs
    data = json.loads(capsys.readouterr().out)
    assert len(data["warnings"]) == 1 and data["warnings"][0].startswith("environment.wind_speed = -100000 m/s")
    assert analytic_main(["simulate", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["warnings"] == []


def test_the_table_prints_the_warning(table3, tmp_path, capsys):
    path = tmp_path / "storm.toml"
    save_design(with_environment(table3, wind_speed=-1e5), path)
    assert analytic_main(["simulate", str(path)]) == 0
    assert capsys.readouterr().out.splitlines()[-1].startswith("warning  environment.wind_speed")
