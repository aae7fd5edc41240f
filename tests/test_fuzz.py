"""Fuzzing every entry point: no design file and no valid design ends in a traceback, a hang or a NaN.

Over generated design files (``fuzz_designs.design_files``: every form, values of every kind TOML
holds where numbers, texts or tables belong, missing keys and tables, stray keys, absurd numbers)
each command line exits 2 with one line naming the field before any simulation starts, or runs the
valid design to its outcome's exit code; reading a file raises only ``DesignError``. Over valid but
extreme designs (``fuzz_designs.extreme_designs``: every number across its valid range, the sling's
and the pouch's mass, the trough's and the target's height among them) both
analytic paths end in a known ``Status`` with a message, finite numbers wherever the shot got, and
the same status; the engine gives a ``Shot`` or ``EngineError``.

Each test states how many examples the suite draws (``support.examples``): under the default
``quick`` hypothesis profile they are derandomized, so every run (and CI) sees the same ones;
``HYPOTHESIS_PROFILE=thorough`` draws 15 times as many, afresh (``tests/conftest.py``). Every test
here shoots or reads hundreds of designs, so all are ``slow``.
"""

from __future__ import annotations

import contextlib
import dataclasses
import io
import json
import math
import re
import tempfile
import tomllib
from pathlib import Path
from unittest import mock

import numpy as np
import pytest
import tomli_w
from hypothesis import HealthCheck, Phase, given, settings

import analytic.cli
import analytic.reference
import crosscheck.cli
import engine_model.cli
from analytic import Shot, Status, shoot, simulate, simulate_fast
from analytic.design import Base, Design, DesignError, Environment, Machine, Projectile
from analytic.design_file import design_from_dict, toml_key
from analytic.fast import simulate_fast_many
from engine_model import EngineError
from engine_model import simulate as engine_simulate
from fuzz_designs import OUT_OF_RANGE_NUMBERS, design_files, extreme_batches, extreme_designs
from support import examples


def fuzz(suite: int):
    """Hypothesis settings of every test here: ``suite`` examples in the suite (``examples``: the
    profile scales them and says whether they are derandomized), no deadline (an extreme design
    may take seconds), no example database (the runs repeat exactly), and no shrinking: each
    attempt to shrink an extreme design runs the models again (seconds each), so a failure could
    shrink past any time limit (pytest-timeout's failure is one more failure to shrink); the
    example that failed is reported as it is, and a derandomized one reproduces."""
    return settings(max_examples=examples(suite), deadline=None, database=None,
                    phases=[Phase.explicit, Phase.generate],
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                           HealthCheck.large_base_example, HealthCheck.filter_too_much])


# --------------------------------------------------------------------------- #
# Design files
# --------------------------------------------------------------------------- #

def _read_back(data: dict) -> tuple[str, dict]:
    """The file's text, and its tables as the commands read them."""
    text = tomli_w.dumps(data)
    return text, tomllib.loads(text)


def _check_refusal(error: DesignError, touched: list[tuple[str, ...]]) -> None:
    """A refusal names, in one line, a field of a table the mutations touched."""
    assert "\n" not in str(error) and str(error).startswith(error.field)
    tables = {toml_key(path[0]) for path in touched}
    assert any(error.field == table or error.field.startswith(table + ".") for table in tables), (
        error.field, touched)


def _design_or_error(parsed: dict, name: str):
    try:
        return design_from_dict(parsed, name=name)
    except DesignError as error:
        return error


@pytest.mark.slow
@fuzz(3300)
@given(design_files())
def test_reading_a_generated_file_gives_a_design_or_design_error(file):
    data, touched = file
    result = _design_or_error(_read_back(data)[1], "fuzzed")   # anything but DesignError escapes
    if isinstance(result, DesignError):
        _check_refusal(result, touched)


#: Each command line, how it is run on a file, what it simulates with (patched to count its
#: calls), and the exit codes of a valid design: the analytic model's 0 (a throw) or 3 (a named
#: failure); the engine's also 1 (a run it cannot trust); the cross-check's 0 or 1 (agreement).
COMMANDS = {
    "analytic": (lambda path: analytic.cli.main(["simulate", path, "--json"]),
                 (analytic.reference, "simulate"), {0, 3}),
    "engine_model": (lambda path: engine_model.cli.main(["simulate", path, "--json"]),
                     (engine_model.cli, "simulate"), {0, 1, 3}),
    "crosscheck": (lambda path: crosscheck.cli.main([path, "--json", "--workers", "1", "--no-progress"]),
                   (crosscheck.cli, "run"), {0, 1}),
}


def _run_command(command: str, data: dict, touched: list[tuple[str, ...]]) -> None:
    run, (module, simulator), valid_codes = COMMANDS[command]
    text, parsed = _read_back(data)
    with tempfile.TemporaryDirectory() as directory:
        path = Path(directory) / "fuzzed.toml"
        path.write_text(text, encoding="utf-8")
        expected = _design_or_error(parsed, path.stem)
        out, err = io.StringIO(), io.StringIO()
        with mock.patch.object(module, simulator, wraps=getattr(module, simulator)) as work, \
                contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = run(str(path))   # an exception escaping main fails the test
    if isinstance(expected, DesignError):
        assert code == 2 and work.call_count == 0
        assert err.getvalue() == f"invalid design: {expected}\n"
        _check_refusal(expected, touched)
    else:
        assert code in valid_codes, (code, err.getvalue())
        report = json.loads(out.getvalue(), parse_constant=_refuse_non_finite)
        if command == "engine_model" and code == 1:
            assert err.getvalue().startswith("engine error: ") and not out.getvalue()
        elif command == "crosscheck":
            assert report["agree"] == (code == 0)
        else:
            assert Status(report["status"]) and report["message"]


def _refuse_non_finite(constant: str):
    raise AssertionError(f"{constant} in the JSON output")


#: Examples per command in the suite. Most files are invalid and refused at once; a valid one
#: costs a reference shot with histories (analytic), an engine run (about a second on the
#: default's numbers) or both models and the comparison (crosscheck).
FILES = {"analytic": 900, "engine_model": 145, "crosscheck": 145}


def _file_strategy(command: str):
    # The engine's runs on valid extreme designs are fuzzed apart, on fewer designs: its
    # files hold the default's numbers or ones no field accepts, so a valid one runs in a second.
    return design_files() if command == "analytic" else design_files(numbers=OUT_OF_RANGE_NUMBERS)


@pytest.mark.slow
@pytest.mark.parametrize("command", COMMANDS)
def test_every_command_refuses_a_bad_file_naming_the_field_or_runs_a_good_one(command):
    @fuzz(FILES[command])
    @given(_file_strategy(command))
    def check(file):
        _run_command(command, *file)

    check()


# --------------------------------------------------------------------------- #
# Valid extreme designs
# --------------------------------------------------------------------------- #

_NOT_A_NUMBER = re.compile(r"\b(nan|inf)\b", re.IGNORECASE)
#: Statuses reached only after release: the shot has a release state.
_RELEASED = {Status.OK, Status.NO_LANDING, Status.SHORT_OF_TARGET}
#: Statuses whose flight rose to its highest point: the shot has an apex.
_WITH_APEX = {Status.OK, Status.SHORT_OF_TARGET}
#: A landed shot's apex may lie this fraction of the machine's size (pivot height, long arm, sling and
#: the target's level) under the target: the integrators' relative tolerance, 1e-10, with room.
APEX_SLACK = 1e-9


def _check_shot(shot: Shot) -> None:
    """A known status, a message without NaN or inf, finite numbers wherever the shot got."""
    assert isinstance(shot.status, Status) and shot.message and not _NOT_A_NUMBER.search(shot.message)
    scalars = [shot.liftoff_time, shot.release_time, shot.landing_time, shot.apex_height,
               shot.min_sling_tension, shot.counterweight_energy_released]
    assert all(math.isfinite(v) for v in scalars if v is not None), scalars
    for pair in (shot.release_position, shot.release_velocity, shot.landing_position):
        assert pair is None or np.all(np.isfinite(pair))
    if shot.status in _RELEASED:
        assert shot.release_time is not None and shot.release_speed is not None
    elif shot.status is not Status.STEP_FAILED:
        assert shot.release_time is None
    assert (shot.landing_time is not None) == shot.ok
    assert (shot.apex_height is not None) == (shot.status in _WITH_APEX)
    target, m = shot.design.environment.target_height, shot.design.machine
    if shot.status is Status.SHORT_OF_TARGET:   # short of a raised target: the apex is under it
        assert 0.0 < target and shot.apex_height < target, (shot.apex_height, target)
    elif shot.ok:   # it came down through the target's level, so it rose to it (to the integrator's tolerance
        # of the machine's size: released on the base it may be 1e-10 m under it, _RELEASED_ON_THE_BASE)
        slack = APEX_SLACK * (m.pivot_height + m.arm_long + m.sling_length + abs(target))
        assert shot.apex_height >= target - slack, (shot.apex_height, target)
    if shot.history is not None:
        h = shot.history
        for values in (h.t, h.q, h.qdot, h.path, h.flight_t, h.flight_path):
            assert np.all(np.isfinite(values))
    json.dumps(shot.to_json(), allow_nan=False)


#: Designs drawn per batch (the invalid draws are dropped: at least half remain). A batch's shots
#: take under a second; drawing its designs is what costs: each design is a few hundred of
#: hypothesis's choices, and a draw of 50 runs past hypothesis's buffer in most attempts (41 of 44
#: for one batch, measured), each discarded. Six batches of 25 shoot 141 designs in the suite's
#: derandomized draws, each batch in several threads' chunks (``fast.BATCH_CHUNK``), in 3 s.
BATCH = 25


def _check_batch(designs) -> None:
    shots = shoot(designs)
    singles = simulate_fast_many(designs)
    assert list(shots.status) == [s.status for s in singles]
    for shot in singles:
        _check_shot(shot)
    released = np.array([status in _RELEASED for status in shots.status])
    assert np.all(np.isfinite(shots.release_velocity[released])) and np.all(np.isfinite(shots.end_time))
    assert np.all(np.isfinite(shots.range[shots.ok])) and np.all(np.isnan(shots.range[~shots.ok]))


# Its own time limit, twice the suite's: drawing batches of extreme designs can take minutes on
# a busy machine (two of 50 designs took 406 s, measured).
@pytest.mark.slow
@pytest.mark.timeout(600)
@fuzz(6)
@given(extreme_batches(BATCH))
def test_batches_of_extreme_designs_end_in_named_outcomes(designs):
    _check_batch(designs)


#: The designs ``_check_both_paths`` passed in this process, by ``repr`` (every field, exactly;
#: -0.0 apart from 0.0). Hypothesis reaches one design by several draws (an edge value or a
#: default part drawn either way): 25 examples of the test below held 19 distinct
#: designs, one of them four times. Both paths are deterministic, so a design drawn again is not
#: shot again (seconds each, some 30); every distinct design is still checked, and a failure still fails
#: the test that first drew it.
_PASSED_BOTH_PATHS: set[str] = set()


def _check_both_paths(design) -> None:
    key = repr(design)
    if key in _PASSED_BOTH_PATHS:
        return
    reference, fast = simulate(design), simulate_fast(design)
    _check_shot(reference)
    _check_shot(fast)
    assert reference.status is fast.status, (reference.message, fast.message)
    _PASSED_BOTH_PATHS.add(key)


# Up to 30 s each on both paths (many extreme designs run to their stages' step limits, the
# reference path with histories): 20 examples, fewer distinct designs (see above). Its own time
# limit, twice the suite's: at 25 examples this test took 200 s on a quiet machine and passed the
# suite's 300 s on a busy one.
@pytest.mark.slow
@pytest.mark.timeout(600)
@fuzz(20)
@given(extreme_designs())
def test_an_extreme_design_ends_alike_on_both_analytic_paths(design):
    _check_both_paths(design)


#: A design the test above drew in CI (2026-11-29): the projectile leaves the base and is released
#: 6e-14 s later, on it to rounding, falling; the reference path released it 5.8e-11 m above the
#: base and landed it, the fast path 1.7e-10 m below and never did (``sequence.lands_at_release``).
_RELEASED_ON_THE_BASE = Design(
    machine=Machine(pivot_height=300000.0, arm_long=1000000.0, arm_short=299999.9999997, arm_mass=5e-324,
                    arm_cg=0.0, arm_inertia=2.2250738585072014e-308, counterweight_mass=0.0001837110022908359,
                    counterweight_link=2.3413322323389492e-07, counterweight_inertia=0.0,
                    sling_length=1000000.0, release_angle=0.0, release_rule="velocity", kind="hinged"),
    projectile=Projectile(mass=1e-12, diameter=2.2250738585072014e-308, drag="none"),
    environment=Environment(gravity=1000000.0, air_density=0.0, air_viscosity=0.0001882091398162802,
                            wind_speed=1.9952623149688795),
    name="extreme")


@pytest.mark.parametrize("mobility", ["fixed", "rolling"])
def test_a_projectile_released_on_the_base_lands_there_on_both_paths(mobility):
    design = dataclasses.replace(_RELEASED_ON_THE_BASE, base=Base(mobility=mobility, mass=1.0 if mobility == "rolling" else None))
    reference, fast = simulate(design), simulate_fast(design)
    for shot in (reference, fast):
        _check_shot(shot)
        assert shot.status is Status.OK, shot.message
        height = shot.release_position[1] + design.machine.pivot_height
        # On the base and level to rounding (1e-15 of the machine's size; 1e-10 of the speed: the
        # vertical velocity's sign is the CPU's, -3e-10 m/s here and +1.2e-10 m/s on a generic
        # CPU, -1e-9 m/s rolling), and so down within the time a throw from that height at that
        # vertical speed takes.
        bound, vy, g = 1e-15 * design.machine.arm_long, shot.release_velocity[1], design.environment.gravity
        assert abs(height) < bound and abs(vy) <= 1e-10 * shot.release_speed
        assert 0.0 <= shot.landing_time - shot.release_time <= (abs(vy) + math.sqrt(vy * vy + 2.0 * g * bound)) / g
    assert fast.landing_position[0] == pytest.approx(reference.landing_position[0], rel=1e-9)


#: A design the test above drew under the thorough profile (2026-11-29): every length of the counterweight's
#: side subnormal, the projectile of the smallest mass, the arm without inertia. The mass matrix's
#: determinant at rest underflows to 0, so the equations cannot be evaluated even there; the reference
#: path divided by it in Python's floats while it read the ground's push off its one sample (a
#: ``ZeroDivisionError``), the fast path's floats gave NaN and it ended ``step_failed``.
_SINGULAR_AT_REST = Design(
    machine=Machine(pivot_height=4.94065645841e-312, arm_long=1e12, arm_short=5.895764e-318,
                    arm_mass=2.2250738585072014e-308, arm_cg=0.0, arm_inertia=0.0,
                    counterweight_mass=2.368301617789194e-12, counterweight_link=2.941296385125e-312,
                    counterweight_inertia=2.2250738585072014e-308, sling_length=1e12,
                    release_angle=0.01896792732683835),
    projectile=Projectile(mass=5e-324, diameter=1e12, drag="constant", drag_coefficient=1589169991.2623234),
    environment=Environment(gravity=1.0, air_density=0.0, air_viscosity=0.022328822502264763, wind_speed=1.0,
                            target_height=6.834561359161395),
    name="extreme")


def test_a_machine_whose_equations_fail_at_rest_is_step_failed_on_both_paths():
    reference, fast = simulate(_SINGULAR_AT_REST), simulate_fast(_SINGULAR_AT_REST)
    for shot in (reference, fast):
        _check_shot(shot)
        assert shot.status is Status.STEP_FAILED, shot.message
    assert reference.min_ground_force is None and len(reference.history.t) == 1


def _check_engine(design) -> None:
    try:
        shot = engine_simulate(design)
    except EngineError as error:
        assert str(error)
        return
    _check_shot(shot)


#: A design the test below drew under the thorough profile (2026-11-29): a link of 1.1e-9 m on a
#: machine 1.5e11 m across, whose direction the engine's float positions cannot resolve (its angle's
#: rate came out 0/0, a NaN with numpy's warning, where the design is valid).
_UNRESOLVED_LINK = Design(
    machine=Machine(pivot_height=146105105438.30902, arm_long=146105273357.28842, arm_short=146105105434.3467,
                    arm_mass=7.103542823313798e-05, arm_cg=146105273330.1658, arm_inertia=0.0,
                    counterweight_mass=2.996162799767079, counterweight_link=1.0790956301414151e-09,
                    counterweight_inertia=1.0, sling_length=146105273357.28842, release_angle=-2.5406458143929807,
                    release_rule="sling"),
    projectile=Projectile(mass=0.0042122974740022405, diameter=23802231328.29468, drag="none"),
    environment=Environment(gravity=0.0006284389916746591, air_density=1.0, air_viscosity=22.05283629530754),
    name="extreme")


def test_the_engine_refuses_a_link_its_positions_cannot_resolve():
    with pytest.raises(EngineError, match=r"^machine\.counterweight_link = 1\.0791e-09 m is under"):
        engine_simulate(_UNRESOLVED_LINK)


@pytest.mark.slow
@fuzz(5)
@given(extreme_designs())
def test_the_engine_gives_a_shot_or_engine_error_on_extreme_designs(design):
    _check_engine(design)
