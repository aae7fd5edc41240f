"""Tests of analytic.aero: drag coefficients against published values, their limits and input checks."""

import math

import numpy as np
import pytest
from scipy.interpolate import PchipInterpolator

from analytic import aero
from analytic.parameters import params
from support import with_projectile

# Sea-level air and a regulation golf ball (minimum diameter, R&A/USGA Rules of Equipment).
AIR_DENSITY = 1.225
AIR_VISCOSITY = 1.81e-5
BALL_DIAMETER = 0.04267

# Pure Stokes 24/Re leaves out the Oseen term 3 Re/16, 0.2 % at Re = 0.01.
STOKES_REL_TOL = 0.01
# Morrison's fit and the Clift-Grace-Weber curve differ by up to 16 % (both fit the
# standard curve, Morrison's runs low in the Newton regime); a typo in a coefficient
# shifts Cd by far more.
MORRISON_REL_TOL = 0.20
# The golf-ball table is a visual digitisation (+-0.01); papers state round values.
GOLF_TEXT_ABS_TOL_CRISIS_START = 0.05   # "~0.5" where the ball-to-ball spread exceeds 0.1
GOLF_TEXT_ABS_TOL = 0.03                # "~0.2" and LES values, spread below 0.05
# Machine precision for two evaluations of the same cubic.
INTERPOLATION_ABS_TOL = 1e-12


def morrison_2013(re):
    """F. A. Morrison, An Introduction to Fluid Mechanics (CUP 2013); Eq. 1 of her 2016 note."""
    return (24.0 / re + 2.6 * (re / 5.0) / (1.0 + (re / 5.0) ** 1.52)
            + 0.411 * (re / 2.63e5) ** -7.94 / (1.0 + (re / 2.63e5) ** -8.0)
            + 0.25 * (re / 1e6) / (1.0 + re / 1e6))


@pytest.mark.parametrize("model", aero.DRAG_MODELS)
def test_each_drag_name_reaches_its_own_curve_through_its_code(table3, model):
    # A design names its drag model; the model's numbers (``analytic.parameters``) carry it as
    # a code, which ``force_factor`` dispatches on. The code must select the curve the name does,
    # from creeping flow through the golf ball's crisis to past the smooth sphere's.
    p = params(with_projectile(table3, drag=model, drag_coefficient=0.45 if model == "constant" else None))
    constant = None if math.isnan(p.cd) else p.cd
    for re in (1e-3, 1e2, 1e5, 5e5):
        speed = re * p.mu / (p.rho * p.diameter)
        factor = aero.force_factor(int(p.drag), speed, p.diameter, p.rho, p.mu, p.cd, aero.DRAG_TABLE)
        assert factor == pytest.approx(aero.drag_coefficient(model, re, constant) * speed, rel=1e-12), re


# --------------------------------------------------------------------------- #
# Smooth sphere
# --------------------------------------------------------------------------- #

@pytest.mark.parametrize("re", [1e-4, 1e-3, 1e-2], ids=["Re=1e-4", "Re=1e-3", "Re=1e-2"])
def test_smooth_sphere_stokes_limit(re):
    # Stokes (1851): Cd = 24/Re for Re << 1.
    assert aero.drag_coefficient("smooth-sphere", re) == pytest.approx(24.0 / re, rel=STOKES_REL_TOL)


def test_smooth_sphere_oseen_correction():
    # Oseen (1910): Cd = 24/Re (1 + 3 Re/16) to first order in Re.
    re = 1e-3
    assert aero.drag_coefficient("smooth-sphere", re) == pytest.approx(24.0 / re * (1 + 3 * re / 16), rel=1e-9)


@pytest.mark.parametrize("re", np.logspace(3, np.log10(5e4), 12), ids=lambda re: f"Re={re:.3g}")
def test_smooth_sphere_newton_plateau(re):
    # Standard drag curve, 1e3 <= Re <= 5e4: Cd between 0.385 and 0.49
    # (Morsi & Alexander 1972, J. Fluid Mech. 55, 193, Table 1, compiled data).
    assert 0.38 <= aero.drag_coefficient("smooth-sphere", re) <= 0.50


def test_smooth_sphere_at_re_5e4():
    # Morsi & Alexander (1972), Table 1: Cd = 0.49 at Re = 5e4.
    assert aero.drag_coefficient("smooth-sphere", 5e4) == pytest.approx(0.49, abs=0.03)


@pytest.mark.parametrize("re", [0.01, 1.0, 10.0, 100.0, 1e3, 1e4, 3e4, 1e5, 2e5],
                         ids=lambda re: f"Re={re:g}")
def test_smooth_sphere_agrees_with_morrison(re):
    cd = aero.drag_coefficient("smooth-sphere", re)
    reference = morrison_2013(re)
    assert abs(cd / reference - 1) < MORRISON_REL_TOL, f"Cd {cd:.4g} vs Morrison {reference:.4g} at Re {re:g}"


def test_smooth_sphere_drag_crisis():
    # Subcritical ~0.5 up to Re ~ 2e5, then the crisis drops Cd below 0.2 past
    # Re ~ 3.5-4e5 (standard curve; Morrison's independent fit does the same).
    assert aero.drag_coefficient("smooth-sphere", 2e5) > 0.4
    for re in (4.5e5, 1e6):
        assert aero.drag_coefficient("smooth-sphere", re) < 0.2
        assert morrison_2013(re) < 0.2


def test_smooth_sphere_has_no_jumps_above_re_30():
    # The tabulated 4e5 break alone would jump by 21 %; the breaks are moved to
    # where the pieces cross. Steps of 1e-5 in log10 Re change Cd by < 0.1 %.
    re = np.logspace(np.log10(30.0), 7.0, 550_001)
    cd = np.array([aero.drag_coefficient("smooth-sphere", r) for r in re])
    steps = np.abs(np.diff(cd)) / cd[:-1]
    assert steps.max() < 1e-3, f"largest step {steps.max():.3g} at Re {re[steps.argmax()]:.6g}"


@pytest.mark.parametrize("re_break", [0.01, 20.0], ids=["Re=0.01", "Re=20"])
def test_smooth_sphere_small_jumps_at_the_low_breaks(re_break):
    # Documented: the table's pieces do not cross there; the jumps are 0.003 % and 0.8 %.
    below = aero.drag_coefficient("smooth-sphere", re_break * (1 - 1e-12))
    above = aero.drag_coefficient("smooth-sphere", re_break * (1 + 1e-12))
    assert abs(above / below - 1) < 0.01


def test_smooth_sphere_cd_is_infinite_at_re_zero():
    assert aero.drag_coefficient("smooth-sphere", 0.0) == math.inf


# --------------------------------------------------------------------------- #
# Golf ball
# --------------------------------------------------------------------------- #

@pytest.mark.parametrize(("re", "expected", "tol"), [
    (5e4, 0.5, GOLF_TEXT_ABS_TOL_CRISIS_START),
    (1e5, 0.2, GOLF_TEXT_ABS_TOL),
], ids=["Re=5e4", "Re=1e5"])
def test_golf_ball_lyu_text_values(re, expected, tol):
    # Lyu, Kensrud, Smith & Tosaya (2018), Proceedings 2, 238, section 3.1.1:
    # non-spinning Cd ~ 0.5 at Re = 5e4 and ~ 0.2 at Re = 1e5.
    assert aero.drag_coefficient("golf-ball", re) == pytest.approx(expected, abs=tol)


@pytest.mark.parametrize(("re", "expected"), [(4.3e4, 0.49), (1.1e5, 0.22)], ids=["Re=4.3e4", "Re=1.1e5"])
def test_golf_ball_li_les_values(re, expected):
    # J. Li, PhD thesis, Hokkaido University (2016), section 3.1: LES of a
    # non-spinning golf ball, subcritical 0.49 at Re = 4.3e4, supercritical 0.22 at 1.1e5.
    assert aero.drag_coefficient("golf-ball", re) == pytest.approx(expected, abs=GOLF_TEXT_ABS_TOL)


def test_golf_ball_crisis_comes_well_before_the_smooth_spheres():
    # Beratlis, Balaras & Squires (2019), J. Fluid Mech., "On the origin of the drag
    # force on dimpled spheres": dimples cut Cd "by more than a factor of two"
    # against a smooth sphere at the same Re.
    assert aero.drag_coefficient("golf-ball", 1e5) < 0.5 * aero.drag_coefficient("smooth-sphere", 1e5)
    re = np.logspace(4, 6, 2001)

    def first_re_below(model, level):
        return next(r for r in re if aero.drag_coefficient(model, r) < level)

    assert first_re_below("golf-ball", 0.3) < 1e5 < 3e5 < first_re_below("smooth-sphere", 0.3)


def test_golf_ball_matches_scipy_pchip_in_log_re():
    reference = PchipInterpolator(np.log10(aero.GOLF_BALL_REYNOLDS), aero.GOLF_BALL_DRAG_COEFFICIENT)
    re = np.logspace(np.log10(aero.GOLF_BALL_REYNOLDS[0]), np.log10(aero.GOLF_BALL_REYNOLDS[-1]), 3001)
    ours = np.array([aero.drag_coefficient("golf-ball", r) for r in re])
    assert np.max(np.abs(ours - reference(np.log10(re)))) < INTERPOLATION_ABS_TOL


@pytest.mark.parametrize("i", range(len(aero.GOLF_BALL_REYNOLDS)), ids=lambda i: f"node{i}")
def test_golf_ball_passes_through_and_is_continuous_at_the_nodes(i):
    re, cd = aero.GOLF_BALL_REYNOLDS[i], aero.GOLF_BALL_DRAG_COEFFICIENT[i]
    for r in (re * (1 - 1e-9), re, re * (1 + 1e-9)):
        assert aero.drag_coefficient("golf-ball", r) == pytest.approx(cd, abs=1e-6)


@pytest.mark.parametrize("i", range(len(aero.GOLF_BALL_REYNOLDS) - 1), ids=lambda i: f"interval{i}")
def test_golf_ball_does_not_overshoot_between_nodes(i):
    lo, hi = aero.GOLF_BALL_REYNOLDS[i], aero.GOLF_BALL_REYNOLDS[i + 1]
    cd_lo, cd_hi = aero.GOLF_BALL_DRAG_COEFFICIENT[i], aero.GOLF_BALL_DRAG_COEFFICIENT[i + 1]
    cd = np.array([aero.drag_coefficient("golf-ball", r) for r in np.geomspace(lo, hi, 201)])
    assert cd.min() >= min(cd_lo, cd_hi) - 1e-12
    assert cd.max() <= max(cd_lo, cd_hi) + 1e-12
    assert np.all(np.diff(cd) <= 1e-12) or np.all(np.diff(cd) >= -1e-12)


def test_golf_ball_falls_monotonically_through_the_crisis():
    cd = np.array([aero.drag_coefficient("golf-ball", r) for r in np.geomspace(5e4, 1.5e5, 1001)])
    assert np.all(np.diff(cd) <= 0.0)


@pytest.mark.parametrize(("re", "end"), [(0.0, 0), (1e3, 0), (4.99e4, 0), (2.51e5, -1), (1e7, -1)],
                         ids=["Re=0", "Re=1e3", "Re=4.99e4", "Re=2.51e5", "Re=1e7"])
def test_golf_ball_is_clamped_outside_the_table(re, end):
    assert aero.drag_coefficient("golf-ball", re) == aero.GOLF_BALL_DRAG_COEFFICIENT[end]


# --------------------------------------------------------------------------- #
# The force factor Cd |v|
# --------------------------------------------------------------------------- #

MODELS_WITH_CONSTANTS = [("none", None), ("constant", 0.3), ("smooth-sphere", None), ("golf-ball", None)]


def factor(model, speed, constant=None, air_density=AIR_DENSITY):
    return aero.drag_force_factor(model, speed, BALL_DIAMETER, air_density, AIR_VISCOSITY, constant)


@pytest.mark.parametrize(("model", "constant"), MODELS_WITH_CONSTANTS, ids=[m for m, _ in MODELS_WITH_CONSTANTS])
def test_force_is_finite_and_vanishes_at_zero_speed(model, constant):
    # The drag force is proportional to factor * speed.
    speeds = (1e-3, 1e-6, 1e-9, 1e-300, 0.0)
    factors = [factor(model, v, constant) for v in speeds]
    assert all(math.isfinite(f) and f >= 0.0 for f in factors)
    forces = [f * v for f, v in zip(factors, speeds, strict=True)]
    assert forces[-1] == 0.0
    assert forces[2] <= 1.01e-6 * forces[0]   # falls at least linearly with the speed


@pytest.mark.parametrize(("model", "constant"), MODELS_WITH_CONSTANTS, ids=[m for m, _ in MODELS_WITH_CONSTANTS])
def test_factor_vanishes_at_zero_speed_except_for_stokes(model, constant):
    # Cd |v| -> 0 when Cd stays bounded; the smooth sphere's Cd ~ 24/Re keeps it finite (next test).
    if model == "smooth-sphere":
        assert factor(model, 0.0) > 0.0
    else:
        assert factor(model, 0.0, constant) == 0.0


def test_smooth_sphere_factor_tends_to_stokes_drag():
    # Stokes drag 3 pi mu d v = (rho/2)(pi d^2/4) Cd v^2  =>  Cd |v| = 24 mu / (rho d).
    stokes = 24.0 * AIR_VISCOSITY / (AIR_DENSITY * BALL_DIAMETER)
    assert factor("smooth-sphere", 0.0) == pytest.approx(stokes, rel=1e-12)
    assert factor("smooth-sphere", 1e-6) == pytest.approx(stokes, rel=STOKES_REL_TOL)


@pytest.mark.parametrize(("model", "constant"), MODELS_WITH_CONSTANTS, ids=[m for m, _ in MODELS_WITH_CONSTANTS])
@pytest.mark.parametrize("speed", [1e-4, 0.01, 3.0, 17.0, 21.0, 26.0, 60.0, 150.0], ids=lambda v: f"v={v:g}")
def test_factor_is_cd_times_speed(model, constant, speed):
    re = aero.reynolds_number(speed, BALL_DIAMETER, AIR_DENSITY, AIR_VISCOSITY)
    expected = aero.drag_coefficient(model, re, constant) * speed
    assert factor(model, speed, constant) == pytest.approx(expected, rel=1e-12, abs=1e-300)


@pytest.mark.parametrize(("model", "constant"), MODELS_WITH_CONSTANTS, ids=[m for m, _ in MODELS_WITH_CONSTANTS])
def test_factor_is_zero_in_vacuum(model, constant):
    for speed in (0.0, 20.0):
        assert factor(model, speed, constant, air_density=0.0) == 0.0


def test_reynolds_number_of_the_default_ball():
    # rho v d / mu = 1.225 * 20 * 0.04267 / 1.81e-5 = 1.045415 / 1.81e-5 = 57 757.73
    assert aero.reynolds_number(20.0, BALL_DIAMETER, AIR_DENSITY, AIR_VISCOSITY) == pytest.approx(57757.73, rel=1e-6)


# --------------------------------------------------------------------------- #
# Bad input
# --------------------------------------------------------------------------- #

@pytest.mark.parametrize("model", ["golf", "Smooth-Sphere", ""], ids=["golf", "capitalised", "empty"])
def test_unknown_model_is_rejected_by_name(model):
    with pytest.raises(ValueError, match=repr(model)):
        aero.drag_coefficient(model, 1e4)
    with pytest.raises(ValueError, match=repr(model)):
        factor(model, 10.0)


@pytest.mark.parametrize("re", [-1.0, -1e-300, math.nan, math.inf], ids=["-1", "-tiny", "nan", "inf"])
@pytest.mark.parametrize("model", ["smooth-sphere", "golf-ball", "none"])
def test_bad_reynolds_number_is_rejected_with_its_value(model, re):
    with pytest.raises(ValueError, match=r"reynolds.*" + repr(re).replace("-", r"\-")):
        aero.drag_coefficient(model, re)


def test_constant_model_needs_a_valid_constant():
    assert aero.drag_coefficient("constant", 1e4, 0.25) == 0.25
    with pytest.raises(ValueError, match="None"):
        aero.drag_coefficient("constant", 1e4)
    with pytest.raises(ValueError, match="-0.1"):
        aero.drag_coefficient("constant", 1e4, -0.1)


def test_constant_is_refused_by_the_other_models():
    with pytest.raises(ValueError, match="0.47"):
        aero.drag_coefficient("smooth-sphere", 1e4, 0.47)


@pytest.mark.parametrize(("name", "args"), [
    ("speed", (-1.0, BALL_DIAMETER, AIR_DENSITY, AIR_VISCOSITY)),
    ("speed", (math.nan, BALL_DIAMETER, AIR_DENSITY, AIR_VISCOSITY)),
    ("diameter", (1.0, 0.0, AIR_DENSITY, AIR_VISCOSITY)),
    ("air_density", (1.0, BALL_DIAMETER, -1.0, AIR_VISCOSITY)),
    ("air_viscosity", (1.0, BALL_DIAMETER, AIR_DENSITY, 0.0)),
], ids=["negative-speed", "nan-speed", "zero-diameter", "negative-density", "zero-viscosity"])
def test_bad_physical_arguments_are_rejected_by_name(name, args):
    with pytest.raises(ValueError, match=name):
        aero.reynolds_number(*args)
    with pytest.raises(ValueError, match=name):
        aero.drag_force_factor("golf-ball", *args, None)


# --------------------------------------------------------------------------- #
# The table's cache file (``aero._load_table``)
# --------------------------------------------------------------------------- #

def _same_doubles(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and bool(np.all(a.view(np.int64) == b.view(np.int64)))


def test_the_cached_table_is_the_built_one_bit_for_bit(tmp_path, monkeypatch):
    cache = tmp_path / "cache" / "drag_table.npy"
    monkeypatch.setattr(aero, "_table_cache", lambda: cache)
    built = aero._load_table()                 # no file yet: built, and written
    assert cache.exists() and not list(cache.parent.glob("*.partial"))
    assert _same_doubles(built, aero._build_table())

    def no_build():
        raise AssertionError("built again although the cache file is sound")

    monkeypatch.setattr(aero, "_build_table", no_build)
    assert _same_doubles(aero._load_table(), built)


@pytest.mark.parametrize("content", [b"", b"not a numpy file", None], ids=["empty", "garbage", "wrong-shape"])
def test_an_unsound_cache_file_is_rebuilt_and_replaced(tmp_path, monkeypatch, content):
    cache = tmp_path / "drag_table.npy"
    if content is None:
        np.save(cache, np.zeros(3))
    else:
        cache.write_bytes(content)
    monkeypatch.setattr(aero, "_table_cache", lambda: cache)
    assert _same_doubles(aero._load_table(), aero._build_table())
    assert _same_doubles(np.load(cache), aero._build_table())


def test_a_cache_that_cannot_be_written_still_gives_the_table(tmp_path, monkeypatch):
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    monkeypatch.setattr(aero, "_table_cache", lambda: blocker / "drag_table.npy")   # under a file
    assert _same_doubles(aero._load_table(), aero._build_table())


def test_the_cache_is_named_by_the_module_and_the_libraries_that_build_it():
    name = aero._table_cache().name
    assert name.startswith("drag_table-") and name.endswith(".npy") and len(name) == len("drag_table-.npy") + 16


def test_with_the_table_cached_the_engine_imports_no_scipy():
    import subprocess
    import sys

    aero._load_table()   # writes the cache if it was missing
    code = "import sys, engine_model.cli, engine_model.render; print(any(m.startswith('scipy') for m in sys.modules))"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stdout.strip() == "False"
