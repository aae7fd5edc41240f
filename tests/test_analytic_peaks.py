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


def test_the_compiled_search_takes_the_same_steps():
    from analytic import compiled

    h = 4e-3
    for offset in (-0.3, 0.1, 0.45):
        a = T0 - (0.5 + offset) * h
        b = a + h
        u = peaks.search_golden(a, b)
        assert compiled.peaks_.search_golden(a, b) == u
        python, native = peaks.search_from(a, b, u, -_skewed(u)), compiled.peaks_.search_from(a, b, u, -_skewed(u))
        assert tuple(python) == tuple(native)
        while True:
            done, u, python = peaks.search_next(python)
            done_c, u_c, native = compiled.peaks_.search_next(native)
            assert (done, u, tuple(python)) == (done_c, u_c, tuple(native))
            if done:
                break
            python = peaks.search_update(python, u, -_skewed(u))
            native = compiled.peaks_.search_update(native, u, -_skewed(u))
    assert np.isfinite(u)
