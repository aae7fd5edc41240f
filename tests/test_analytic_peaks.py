"""The search for a load's peak within a step (``analytic.peaks``), written once for both paths."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from analytic import peaks


def _search(load, a, b, module=peaks):
    """Run the search for the largest ``load(t)`` on ``[a, b]``; returns ``(t, value, evaluations)``."""
    u = module.search_golden(a, b)
    s = module.search_from(a, b, u, -load(u))
    while True:
        done, u, s = module.search_next(s)
        if done:
            return s.x, -s.fx, int(s.calls)
        s = module.search_update(s, u, -load(u))


# A smooth, skewed peak, as a load is around its largest: its derivative, -0.3 W sin(W (t - T0))
# + 3 C (t - T0)^2, vanishes at T0, where the second derivative is -0.3 W^2 < 0: a maximum.
T0, W, C = 0.4123456789, 37.0, 5.0


def _skewed(t):
    return 1.0 + 0.3 * math.cos(W * (t - T0)) + C * (t - T0) ** 3


@pytest.mark.parametrize("offset", [-0.45, -0.1, 0.2, 0.49], ids=lambda o: f"peak at {o:+.2f} of the step")
def test_the_search_is_scipys_bounded_minimiser_step_for_step(offset):
    # The reference the search reproduces: scipy's minimize_scalar(method="bounded") with the same
    # tolerance, on minus the load; the same point, the same value, the same count, to the bit.
    h = 4e-3
    a = T0 - (0.5 + offset) * h
    b = a + h
    t, value, calls = _search(_skewed, a, b)
    expected = minimize_scalar(lambda t: -_skewed(t), bounds=(a, b), method="bounded",
                               options={"xatol": peaks.PEAK_TIME_TOLERANCE, "maxiter": peaks.SEARCH_CALLS})
    assert (t, -value, calls) == (expected.x, expected.fun, expected.nfev)
    assert abs(t - T0) <= 2 * (math.sqrt(2.2e-16) * T0 + peaks.PEAK_TIME_TOLERANCE)


def test_a_load_rising_to_the_steps_end_peaks_there():
    # No interior maximum: the search ends at the bracket's end, never beyond it, with the value there.
    t, value, _ = _search(lambda t: 3.0 * t, 1.0, 1.5)
    assert 1.5 - 1e-7 <= t <= 1.5 and value == pytest.approx(4.5, rel=1e-7)


def _step_together(python, native):
    """Run a Python and a compiled search of ``_skewed`` side by side, asserting the same state at
    every step; returns the time found."""
    from analytic.fast import compiled

    assert tuple(python) == tuple(native)
    while True:
        done, u, python = peaks.search_next(python)
        done_c, u_c, native = compiled.peaks_.search_next(native)
        assert (done, u, tuple(python)) == (done_c, u_c, tuple(native))
        if done:
            return u
        python = peaks.search_update(python, u, -_skewed(u))
        native = compiled.peaks_.search_update(native, u, -_skewed(u))


def test_the_compiled_search_takes_the_same_steps():
    from analytic.fast import compiled

    h = 4e-3
    for offset in (-0.3, 0.1, 0.45):
        a = T0 - (0.5 + offset) * h
        b = a + h
        u = peaks.search_golden(a, b)
        assert compiled.peaks_.search_golden(a, b) == u
        python, native = peaks.search_from(a, b, u, -_skewed(u)), compiled.peaks_.search_from(a, b, u, -_skewed(u))
        u = _step_together(python, native)
    assert np.isfinite(u)


def _search_around(load, t_before, t_peak, t_after, module=peaks):
    """Run the search from three samples of ``load``; returns ``(t, value, evaluations)``."""
    s = module.search_around(t_before, load(t_before), t_peak, load(t_peak), t_after, load(t_after))
    while True:
        done, u, s = module.search_next(s)
        if done:
            return s.x, -s.fx, int(s.calls)
        s = module.search_update(s, u, -load(u))


# Steps of 4 ms around T0, the largest sample at either side of the peak, steps of unequal length.
AROUND = [(-4.1e-3, -1.3e-3, 2.6e-3), (-3.0e-3, 0.9e-3, 4.4e-3), (-2.2e-3, 0.2e-3, 1.7e-3), (-5e-3, -0.1e-3, 3e-3)]


@pytest.mark.parametrize("before, peak, after", AROUND, ids=lambda v: f"{v * 1e3:+.1f} ms")
def test_the_search_from_three_samples_finds_the_peak_of_both_steps(before, peak, after):
    # The same peak as scipy's bounded minimiser gives on each of the two steps on its own (to the
    # tolerance both stop at), in a fraction of its evaluations.
    t_before, t_peak, t_after = T0 + before, T0 + peak, T0 + after
    assert _skewed(t_peak) > max(_skewed(t_before), _skewed(t_after))   # the largest of the three samples
    t, value, calls = _search_around(_skewed, t_before, t_peak, t_after)
    bounded = [minimize_scalar(lambda t: -_skewed(t), bounds=bounds, method="bounded",
                               options={"xatol": peaks.PEAK_TIME_TOLERANCE, "maxiter": peaks.SEARCH_CALLS})
               for bounds in ((t_before, t_peak), (t_peak, t_after))]
    best = min(bounded, key=lambda r: r.fun)
    assert abs(t - T0) <= 2 * (math.sqrt(2.2e-16) * T0 + peaks.PEAK_TIME_TOLERANCE)
    assert value == pytest.approx(-best.fun, rel=1e-14)
    assert t_before <= t <= t_after
    assert calls <= 10 < sum(r.nfev for r in bounded) / 2


@pytest.mark.parametrize("at_start", [True, False], ids=["start", "end"])
def test_just_inside_a_stretchs_end_is_one_search_tolerance_in(at_start):
    a, b = 0.25, 0.2503
    inside = peaks.inside_end(a, b, at_start)
    tolerance = math.sqrt(2.2e-16) * (a if at_start else b) + peaks.PEAK_TIME_TOLERANCE / 3.0
    assert a < inside < b
    assert abs(inside - (a if at_start else b)) == pytest.approx(tolerance, rel=1e-12)
    # A step shorter than that: the midpoint, still inside.
    assert peaks.inside_end(a, a + 1e-12, at_start) == pytest.approx(a + 0.5e-12, rel=1e-6)


def test_the_compiled_search_from_three_samples_takes_the_same_steps():
    from analytic.fast import compiled

    for before, peak, after in AROUND:
        args = (T0 + before, _skewed(T0 + before), T0 + peak, _skewed(T0 + peak), T0 + after, _skewed(T0 + after))
        python, native = peaks.search_around(*args), compiled.peaks_.search_around(*args)
        u = _step_together(python, native)
        for at_start in (True, False):
            assert compiled.peaks_.inside_end(args[0], args[4], at_start) == peaks.inside_end(args[0], args[4],
                                                                                                at_start)
