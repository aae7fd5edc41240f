"""A target above or below the base (``environment.target_height``): where the flight lands, the shot
that falls short of it (``short_of_target``), a pit, and the design file's field.

The reference numbers are the closed-form vacuum flight from each model's own release state
(``docs/derivation.md``, the landing condition): without drag the flight is a parabola, so the
landing at the target's level follows from the release alone.
"""

from __future__ import annotations

import json
import math

import pytest

from analytic.cli import EXIT_INVALID, EXIT_NO_THROW, EXIT_OK
from analytic.cli import main as analytic_main
from analytic.design import DesignError
from analytic.design_file import default_design, design_from_dict, design_to_dict
from analytic.fast import shoot, simulate_fast
from analytic.reference import simulate
from analytic.result import Status
from engine_model import simulate as engine_simulate
from engine_model.cli import main as engine_main
from support import TABLE3_FILE, with_environment, with_machine, with_projectile

FOOT = 0.3048   # m, the international foot (1959)
#: Both analytic paths integrate the vacuum flight with DOP853, exact for a parabola (a polynomial
#: of degree 2 in t) to round-off, and locate the landing root to 1e-14 s plus 4 ulp of t: at
#: 20 m/s that is ~1e-13 m; this allows the round-off of a few hundred steps of size ~1 on top.
PATH_CLOSED_FORM = 1e-9   # m
#: The engine's flight is a leapfrog under constant gravity (exact at its steps for a parabola)
#: with its landing on the parabola through its last three samples (exact for one), from its own
#: release state; its positions are single steps of pymunk's float arithmetic, summed over ~2000
#: steps of 2 ms: round-off of ~1e-12 m each.
ENGINE_CLOSED_FORM = 1e-8   # m
#: The paper's design released 30 deg downward: 1.79 m above the base, falling (its release, as
#: both models give it: ``crosscheck.cases.target_cases``).
DOWNWARD = math.radians(-30.0)


def _at(design, height):
    return with_environment(design, target_height=height)


def _vacuum_landing(shot, target_height):
    """The range and flight time of the vacuum parabola from ``shot``'s release to the target's level."""
    (x0, y0), (vx, vy) = shot.release_position, shot.release_velocity
    g, h = shot.design.environment.gravity, shot.design.machine.pivot_height
    t = (vy + math.sqrt(vy * vy + 2.0 * g * (y0 + h - target_height))) / g
    return x0 + vx * t, t


VACUUM = with_projectile(default_design(), drag="none")
MODELS = {"reference": lambda d: simulate(d, histories=False), "fast": simulate_fast, "engine": engine_simulate}
TOLERANCE = {"reference": PATH_CLOSED_FORM, "fast": PATH_CLOSED_FORM, "engine": ENGINE_CLOSED_FORM}


@pytest.mark.parametrize("height", [3.0, 8.0, -5.0], ids=["raised-3m", "raised-8m", "pit-5m"])
@pytest.mark.parametrize("model", list(MODELS))
def test_a_vacuum_flight_lands_where_the_parabola_meets_the_target(model, height):
    shot = MODELS[model](_at(VACUUM, height))
    assert shot.status is Status.OK, shot.message
    expected_range, expected_time = _vacuum_landing(shot, height)
    assert shot.range == pytest.approx(expected_range, abs=TOLERANCE[model])
    assert shot.flight_time == pytest.approx(expected_time, abs=TOLERANCE[model])
    assert shot.landing_position[1] == pytest.approx(height - VACUUM.machine.pivot_height, abs=TOLERANCE[model])


@pytest.mark.parametrize("model", list(MODELS))
def test_a_raised_target_shortens_the_range_and_a_pit_lengthens_it(model):
    """The landing is on the way down, so a higher target is met sooner and nearer (with drag too)."""
    ranges = [MODELS[model](_at(default_design(), height)).range for height in (3.0, 0.0, -5.0)]
    assert ranges[0] < ranges[1] < ranges[2]


@pytest.mark.parametrize("model", list(MODELS))
def test_a_target_above_the_apex_is_short_of_target(model):
    base = MODELS[model](default_design())
    target = base.apex_height + 1.0
    shot = MODELS[model](_at(default_design(), target))
    assert shot.status is Status.SHORT_OF_TARGET and shot.status.value == "short_of_target"
    assert shot.range is None and shot.landing_time is None
    # its apex is the one the shot to the base reaches (the same flight up to it)
    assert shot.apex_height == pytest.approx(base.apex_height, rel=1e-9)
    assert f"{shot.apex_height:.4g} m" in shot.message and f"{target:.4g} m" in shot.message


def test_short_of_target_in_a_batch_is_a_failure_with_its_apex():
    designs = [default_design(), _at(default_design(), 40.0)]
    shots = shoot(designs)
    assert list(shots.status) == [Status.OK, Status.SHORT_OF_TARGET]
    assert math.isnan(shots.range[1]) and shots.apex_height[1] == pytest.approx(shots.apex_height[0], rel=1e-12)


@pytest.mark.parametrize("model", list(MODELS))
def test_released_above_a_target_it_never_rises_to_it_lands_on_the_way_down(model):
    design = _at(with_machine(VACUUM, release_angle=DOWNWARD), 1.0)
    shot = MODELS[model](design)
    assert shot.status is Status.OK, shot.message
    assert shot.release_velocity[1] < 0.0
    release_height = shot.release_position[1] + design.machine.pivot_height
    assert release_height > 1.0
    assert shot.apex_height == pytest.approx(release_height, abs=1e-3 if model == "engine" else 0.0)
    assert shot.range == pytest.approx(_vacuum_landing(shot, 1.0)[0], abs=TOLERANCE[model])


@pytest.mark.parametrize("model", list(MODELS))
def test_released_below_a_raised_target_and_falling_is_short_at_release(model):
    shot = MODELS[model](_at(with_machine(default_design(), release_angle=DOWNWARD), 2.5))
    assert shot.status is Status.SHORT_OF_TARGET, shot.message
    release_height = shot.release_position[1] + default_design().machine.pivot_height
    assert shot.apex_height == pytest.approx(release_height, abs=1e-12)


@pytest.mark.parametrize("model", ["reference", "fast"])
def test_a_pit_lets_the_flight_go_below_the_base(model):
    shot = MODELS[model](_at(default_design(), -5.0))
    assert shot.ok
    assert shot.landing_position[1] == pytest.approx(-5.0 - default_design().machine.pivot_height, abs=1e-9)


def test_the_reference_flight_path_of_a_short_shot_ends_at_its_apex():
    shot = simulate(_at(default_design(), 40.0))
    assert shot.history.flight_path[-1, 1] + default_design().machine.pivot_height == pytest.approx(
        shot.apex_height, abs=1e-9)


# --------------------------------------------------------------------------- #
# The design file's field
# --------------------------------------------------------------------------- #

def _table3_with(line: str) -> str:
    """Table III's design file with ``line`` added to its ``[environment]`` table."""
    return TABLE3_FILE.read_text().replace("[environment]", f"[environment]\n{line}", 1)


def _file_data(**environment):
    data = design_to_dict(default_design())
    data["environment"].update(environment)
    return data


def test_the_field_takes_units_and_round_trips():
    design = design_from_dict(_file_data(target_height="12 ft"))
    assert design.environment.target_height == pytest.approx(12 * FOOT, rel=1e-12)
    assert design_from_dict(design_to_dict(design)).environment.target_height == design.environment.target_height
    assert "target_height" not in design_to_dict(default_design())["environment"]   # the default is left out


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, "high", True], ids=str)
def test_a_bad_target_height_is_refused_naming_the_field(value):
    with pytest.raises(DesignError, match=r"environment\.target_height"):
        design_from_dict(_file_data(target_height=value))


def test_the_command_line_refuses_a_non_finite_target_height(tmp_path, capsys):
    path = tmp_path / "nan.toml"
    path.write_text(_table3_with("target_height = nan"))
    assert analytic_main(["simulate", str(path)]) == EXIT_INVALID
    err = capsys.readouterr().err
    assert "environment.target_height" in err and "nan" in err and "Traceback" not in err


@pytest.mark.parametrize("main", [analytic_main, engine_main], ids=["analytic", "engine"])
def test_simulate_json_reports_the_range_at_the_target_and_a_short_shot(main, tmp_path, capsys):
    raised, short = tmp_path / "raised.toml", tmp_path / "short.toml"
    raised.write_text(_table3_with('target_height = "3 m"'))
    short.write_text(_table3_with("target_height = 40.0"))
    assert main(["simulate", str(TABLE3_FILE), "--json"]) == EXIT_OK
    base = json.loads(capsys.readouterr().out)
    assert main(["simulate", str(raised), "--json"]) == EXIT_OK
    landed = json.loads(capsys.readouterr().out)
    assert set(landed) == set(base) and landed["status"] == "ok" and landed["range"] < base["range"]
    assert main(["simulate", str(short), "--json"]) == EXIT_NO_THROW
    missed = json.loads(capsys.readouterr().out)
    assert missed["status"] == "short_of_target" and missed["range"] is None and missed["apex_height"] < 40.0


def test_aim_lands_on_the_distance_at_the_targets_level():
    from analytic.aim import AIM_TOLERANCE, aim, format_aim
    from analytic.fields import field

    design = _at(default_design(), 3.0)
    result = aim(design, "machine.release_angle", 30.0)
    assert result.solutions and result.to_json()["target_height"] == 3.0
    for solution in result.solutions:   # each lands 30 m out at the target's level, not at the base's
        shot = simulate(field("machine.release_angle").replace(design, solution.value), histories=False)
        assert shot.range == pytest.approx(30.0, abs=AIM_TOLERANCE)
        assert shot.landing_position[1] + design.machine.pivot_height == pytest.approx(3.0, abs=1e-9)
    short = int((result.status == "short_of_target").sum())
    assert short > 0   # the steepest downward releases leave below a target 3 m up
    text = format_aim(result)
    assert "3.0000 m above the base" in text and f"{short} of the {len(result.status)} settings" in text
