"""Sweep inputs: files and units read and checked, chunks expanded the same whatever the chunking,
Saltelli's layout as SALib's, and kernel rows bit for bit those of the designs they stand for."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from analytic.design import DesignError
from analytic.design_file import design_from_dict, read_toml
from analytic.fast import pack
from analytic.parameters import Params
from analytic.sweep import designs, expand, spec, sweep_file
from analytic.sweep.distributions import Normal, Uniform
from analytic.sweep.spec import design_data
from analytic.sweep.sweep_file import DATA_DIR, load_sweep, sweep_from_dict

TABLE3 = read_toml(DATA_DIR / "paper_table3.toml")


def grid_sweep(**grid) -> spec.Sweep:
    return sweep_from_dict({"design": "paper_table3", "grid": grid})


def sample_sweep(method: str, n: int, chunk_size: int = 64, **fields) -> spec.Sweep:
    return sweep_from_dict({"design": "paper_table3", "chunk_size": chunk_size,
                            "sample": {"n": n, "method": method, "seed": 7, **fields}})


def every_row(sweep: spec.Sweep) -> tuple[np.ndarray, dict]:
    parts = [expand.chunk_inputs(sweep, chunk) for chunk in range(sweep.chunks)]
    return (np.concatenate([index for index, _ in parts]),
            {field: np.concatenate([values[field] for _, values in parts]) for field in sweep.fields})


# --------------------------------------------------------------------------- #
# Reading
# --------------------------------------------------------------------------- #

def test_the_readme_example_reads_as_a_grid_in_c_order(tmp_path):
    path = tmp_path / "sweep.toml"
    path.write_text('design = "paper_table3.toml"\n[grid]\n'
                    '"machine.sling_length" = {from = 0.40, to = 0.61, steps = 50}\n'
                    '"machine.release_angle" = {from = 30.0, to = 60.0, steps = 40}\n')
    sweep = load_sweep(path)
    assert sweep.shots == 2000 and sweep.fields == ("machine.sling_length", "machine.release_angle")
    index, values = every_row(sweep)
    assert np.array_equal(index, np.arange(2000))
    # The last field varies fastest; the ends are exact.
    assert values["machine.release_angle"][:2].tolist() == [30.0, 30.0 + 30.0 / 39]
    assert values["machine.sling_length"][39] == 0.40 and values["machine.sling_length"][40] > 0.40
    assert values["machine.sling_length"][-1] == 0.61 and values["machine.release_angle"][-1] == 60.0


@pytest.mark.parametrize("text, unit, expected", [
    ("40 cm", "m", 0.40), ("2 deg", "deg", 2.0), ("0.035 rad", "deg", math.degrees(0.035)),
    ("50 g", "kg", 0.05), ("1.5 m/s", "m/s", 1.5), ("3 km/h", "m/s", 3 / 3.6), (0.25, "m", 0.25),
], ids=["cm", "deg", "rad-to-deg", "g", "m/s", "km/h", "plain-number"])
def test_quantities_with_units_convert_to_design_file_units(text, unit, expected):
    assert sweep_file.quantity("grid.x.from", text, unit) == pytest.approx(expected, rel=1e-15)


@pytest.mark.parametrize("text, reason", [("40 kg", "must be in units of m"), ("forty cm", "pint can read"),
                                          ("40", "must be in units of m"), (True, "must be a number")],
                         ids=["wrong-dimension", "not-a-quantity", "no-unit", "boolean"])
def test_bad_quantities_name_field_value_and_reason(text, reason):
    with pytest.raises(DesignError, match=reason) as error:
        sweep_file.quantity("grid.machine.sling_length.from", text, "m")
    assert error.value.field == "grid.machine.sling_length.from" and error.value.value == text


def test_dotted_keys_without_quotes_read_like_quoted_ones():
    quoted = sweep_from_dict({"design": "paper_table3",
                              "grid": {"machine.sling_length": {"from": 0.4, "to": 0.6, "steps": 3}}})
    dotted = sweep_from_dict({"design": "paper_table3",
                              "grid": {"machine": {"sling_length": {"from": 0.4, "to": 0.6, "steps": 3}}}})
    assert quoted.grid == dotted.grid


@pytest.mark.parametrize("data, field, reason", [
    ({"grid": {"machine.sling_lenght": {"from": 0.4, "to": 0.6, "steps": 3}}},
     "grid.machine.sling_lenght", "unknown field"),
    ({"grid": {"machine.sling_length": {"from": 0.4, "to": 0.6, "steps": 0}}},
     "grid.machine.sling_length.steps", "at least 2"),
    ({"grid": {"machine.sling_length": {"from": 0.6, "to": 0.4, "steps": 3}}},
     "grid.machine.sling_length.to", "greater than from"),
    ({"sample": {"n": 8, "method": "random", "seed": 0,
                 "projectile.mass": {"distribution": "normal", "mean": 0.0456, "sd": -0.001}}},
     "sample.projectile.mass.sd", "must be positive"),
    ({"sample": {"n": 8, "method": "random", "seed": 0,
                 "projectile.mass": {"distribution": "normal", "mean": 0.0456, "sd": 0.001, "from": 1.0, "to": 2.0}}},
     "sample.projectile.mass", "truncation window"),
    ({"sample": {"n": 8, "method": "random", "seed": 0,
                 "projectile.mass": {"distribution": "lognormal", "mean": 0.0456, "sd": 0.001}}},
     "sample.projectile.mass.distribution", "must be one of"),
    ({"sample": {"n": 8, "method": "random", "seed": 0}, "uncertain": {
        "environment.wind_speed": {"distribution": "normal", "sd": 0}}},
     "uncertain.environment.wind_speed.sd", "must be positive"),
    ({"sample": {"n": 1000, "method": "sobol", "seed": 0, "projectile.mass": {"from": 0.04, "to": 0.05}}},
     "sample.n", "power of 2"),
    ({"sample": {"n": 8, "method": "latin", "seed": 0, "projectile.mass": {"from": 0.04, "to": 0.05}}},
     "sample.method", "must be one of"),
    ({"uncertain": {"environment.wind_speed": {"distribution": "normal", "sd": 1.0}}},
     "sample", "required table with [uncertain]"),
    ({"grid": {"projectile.drag_coefficient": {"from": 0.2, "to": 0.5, "steps": 3}}},
     "projectile.drag_coefficient", "only used with drag"),
    ({"grid": {"machine.arm_mass": {"from": 0.2, "to": 0.5, "steps": 3}}},
     "machine.arm_mass", "not both"),
    ({"grid": {"machine.counterweight_link": {"from": 0.1, "to": 0.5, "steps": 3}}},
     "machine.counterweight_link", "would strike the base"),
    ({"sample": {"n": 8, "method": "random", "seed": 0}, "uncertain": {
        "projectile.mass": {"distribution": "normal", "sd": 0.01}}},
     "projectile.mass", "must be positive"),
    ({}, "grid", "needs [grid] or [sample]"),
    ({"grid": {}, "problem": "paper_problem"}, "problem", "not both"),
], ids=["unknown-field", "zero-steps", "reversed-range", "negative-sd", "empty-truncation", "unknown-distribution",
        "zero-uncertainty", "sobol-not-power-of-2", "unknown-method", "uncertain-without-sample",
        "field-the-design-refuses", "field-of-another-form", "corner-cannot-be-built", "normal-reaching-negative",
        "nothing-varies", "two-bases"])
def test_bad_sweep_files_are_refused_naming_field_and_reason(data, field, reason):
    with pytest.raises(DesignError, match=re.escape(reason)) as error:
        sweep_from_dict({"design": "paper_table3", **data})
    assert field in error.value.field


def test_a_problem_base_needs_every_free_variable_varied_and_takes_its_bounds():
    with pytest.raises(DesignError, match="the problem leaves it free") as error:
        sweep_from_dict({"problem": "paper_problem", "sample": {"n": 4, "method": "random", "seed": 0,
                                                                 "machine.sling_length": {}}})
    assert error.value.field.startswith("machine.")
    sweep = load_sweep(DATA_DIR / "sweeps" / "problem.toml")
    # Table II (paper_problem.toml): the short arm in m, the release angle in deg.
    assert sweep.sample.fields[0].distribution.support == pytest.approx((0.01, 0.30), rel=1e-15)
    assert sweep.sample.fields[-1].distribution.support == pytest.approx((-80.0, 80.0), rel=1e-15)


def test_every_shipped_sweep_file_reads():
    for path in sorted((DATA_DIR / "sweeps").glob("*.toml")):
        assert load_sweep(path).shots > 0, path.name


# --------------------------------------------------------------------------- #
# Expansion
# --------------------------------------------------------------------------- #

@pytest.mark.parametrize("method, n", [("random", 50), ("sobol", 16)])
def test_draws_do_not_depend_on_the_chunk_size(method, n):
    fields = {"projectile.mass": {"from": 0.040, "to": 0.050},
              "environment.wind_speed": {"distribution": "normal", "mean": 0.0, "sd": 2.0},
              "machine.sling_length": {"distribution": "normal", "mean": 0.6, "sd": 0.01, "from": 0.59}}
    whole = every_row(sample_sweep(method, n, chunk_size=10_000, **fields))
    for size in (1, 7, 33):
        index, values = every_row(sample_sweep(method, n, chunk_size=size, **fields))
        assert np.array_equal(index, whole[0])
        for field in whole[1]:
            assert np.array_equal(values[field], whole[1][field]), (size, field)
    assert whole[1]["machine.sling_length"].min() >= 0.59


def test_saltelli_rows_are_salib_s_own_sample():
    from SALib.sample import sobol

    sample = spec.Sample(n=32, method="sobol", seed=3,
                         fields=tuple(spec.Varied(f"x{i}", Uniform(0.0, 1.0)) for i in range(4)))
    problem = {"num_vars": 4, "names": ["a", "b", "c", "d"], "bounds": [[0.0, 1.0]] * 4}
    salib = sobol.sample(problem, 32, calc_second_order=False, seed=3)
    assert np.array_equal(expand.unit_block(sample, 0, sample.rows), salib)
    assert np.array_equal(expand.unit_block(sample, 45, 101), salib[45:101])


def test_a_grid_with_a_sample_draws_the_same_sample_at_every_point_and_scatters_around_it():
    sweep = sweep_from_dict({"design": "paper_table3", "chunk_size": 5,
                             "grid": {"machine.release_angle": {"values": [30.0, 40.0, 50.0]}},
                             "sample": {"n": 4, "method": "random", "seed": 1},
                             "uncertain": {"machine.release_angle": {"distribution": "uniform", "half_width": 1.0},
                                           "environment.wind_speed": {"distribution": "normal", "sd": 1.0}}})
    assert sweep.shots == 12 and sweep.fields == ("machine.release_angle", "environment.wind_speed")
    _, values = every_row(sweep)
    offsets = values["machine.release_angle"].reshape(3, 4) - np.array([[30.0], [40.0], [50.0]])
    assert np.allclose(offsets, offsets[0], atol=1e-12) and np.all(np.abs(offsets) <= 1.0)
    assert np.array_equal(values["environment.wind_speed"].reshape(3, 4)[1], values["environment.wind_speed"][:4])


def test_distributions_map_unit_numbers_by_their_inverse_cdf():
    from scipy.stats import norm

    unit = np.array([0.0, 0.025, 0.5, 0.975, 1.0])
    assert np.allclose(Normal(1.0, 2.0).ppf(unit)[1:4], norm.ppf(unit[1:4], 1.0, 2.0), rtol=1e-12)
    assert np.all(np.isfinite(Normal(0.0, 1.0).ppf(unit)))      # 0 and 1 clipped, not infinite
    assert Normal(0.0, 1.0).support == pytest.approx((-8.21, 8.21), abs=0.01)
    assert Uniform(2.0, 4.0).ppf(unit).tolist() == [2.0, 2.05, 3.0, 3.95, 4.0]


# --------------------------------------------------------------------------- #
# Kernel rows
# --------------------------------------------------------------------------- #

DIRECT_FIELDS = ("machine.pivot_height", "machine.arm_long", "machine.arm_short", "machine.arm_mass",
                 "machine.arm_cg", "machine.arm_inertia", "machine.counterweight_mass", "machine.counterweight_link",
                 "machine.counterweight_inertia", "machine.sling_length", "machine.release_angle",
                 "projectile.mass", "projectile.diameter", "projectile.drag_coefficient", "environment.gravity",
                 "environment.air_density", "environment.air_viscosity", "environment.wind_speed",
                 "environment.target_height", "losses.axle_friction", "losses.axle_radius",
                 "losses.hinge_friction", "losses.hinge_radius", "losses.base_friction", "base.trough_height",
                 "machine.sling_mass", "machine.pouch_mass")
#: The floating arm's direct fields beyond those (its guide and track friction).
FLOATING_FIELDS = ("losses.guide_friction", "losses.track_friction")


def assert_rows_are_the_designs(base: spec.Base, columns: dict) -> None:
    rows = designs.kernel_rows(base, columns)
    for i in range(len(rows)):
        design = design_from_dict(design_data(base, {f: float(v[i]) for f, v in columns.items()}))
        expected = pack(design)
        differ = [Params._fields[j] for j in np.flatnonzero(expected.view(np.int64) != rows[i].view(np.int64))]
        assert not differ, f"row {i}: {differ}"


def jitter(base: spec.Base, fields, size: int = 40, scale: float = 0.02) -> dict:
    rng = np.random.default_rng(5)
    return {f: base.values[f] * (1.0 + rng.uniform(-scale, scale, size)) + rng.uniform(0, 0.01, size)
            for f in fields}


def test_rows_of_a_direct_design_varying_every_field_at_once(tmp_path):
    data = {key: dict(value) if isinstance(value, dict) else value for key, value in TABLE3.items()}
    data["machine"] = {k: v for k, v in data["machine"].items() if k != "arm_beam"}
    data["machine"].update(arm_mass=0.3, arm_cg=0.23, arm_inertia=0.022, sling_mass=0.012, pouch_mass=0.004)
    data["projectile"] = {"mass": 0.0456, "diameter": 0.04267, "drag": "constant", "drag_coefficient": 0.3}
    data["losses"] = {"axle_friction": 0.15, "axle_radius": 0.0064, "hinge_friction": 0.15, "hinge_radius": 0.005,
                      "base_friction": 0.3}
    data["base"] = {"trough_height": 0.1}   # varied too: the arm's angle at rest follows it
    path = tmp_path / "direct.toml"
    import tomli_w

    path.write_bytes(tomli_w.dumps(data).encode())
    base = sweep_from_dict({"design": str(path), "grid": {"projectile.mass": {"values": [0.05]}}}).base
    assert set(DIRECT_FIELDS + FLOATING_FIELDS) == {f for f in designs.PARAM_OF_FIELD}
    assert_rows_are_the_designs(base, jitter(base, DIRECT_FIELDS))


def test_rows_of_a_floating_arm_varying_its_guide_and_track_friction():
    """The static coefficients not given follow their kinetic ones in every row (``Losses.static``)."""
    base = sweep_from_dict({"design": "paper_table3_floating", "grid": {"projectile.mass": {"values": [0.05]}}}).base
    rng = np.random.default_rng(6)
    columns = {f: rng.uniform(0.0, 0.5, 40) for f in FLOATING_FIELDS}
    assert_rows_are_the_designs(base, {**columns, **jitter(base, ("machine.sling_length",))})


@pytest.mark.parametrize("fields", [("machine.sling_length", "machine.release_angle"),
                                    ("machine.arm_long", "machine.arm_short"),
                                    ("machine.arm_beam.width", "machine.arm_beam.density", "machine.pivot_height"),
                                    ("projectile.diameter", "environment.gravity"),
                                    ("projectile.drag_factor",), ("projectile.diameter", "projectile.drag_factor")],
                         ids=["sling-release", "arm-from-beam", "beam-itself", "area-and-time-limit",
                              "drag-factor", "drag-area"])
def test_rows_of_the_beam_arm_design(fields):
    base = grid_sweep(**{"machine.sling_length": {"values": [0.6]}}).base
    assert_rows_are_the_designs(base, jitter(base, fields))


def test_rows_of_the_problem_s_paper_form():
    sweep = load_sweep(DATA_DIR / "sweeps" / "problem.toml")
    _, values = expand.chunk_inputs(sweep, 0)
    assert_rows_are_the_designs(sweep.base, {f: v[:60] for f, v in values.items()})


def test_every_corner_checked_means_every_inner_design_builds():
    sweep = sweep_from_dict({"design": "paper_table3", "sample": {
        "n": 200, "method": "random", "seed": 0,
        "machine.arm_short": {"from": 0.05, "to": 0.30}, "machine.counterweight_link": {"from": 0.05, "to": 0.29},
        "machine.pivot_height": {"from": 0.5942, "to": 0.66}, "machine.arm_long": {"from": 0.67, "to": 0.9}}})
    _, values = expand.chunk_inputs(sweep, 0)
    for i in range(len(values["machine.arm_short"])):
        design_from_dict(design_data(sweep.base, {f: float(v[i]) for f, v in values.items()}))

