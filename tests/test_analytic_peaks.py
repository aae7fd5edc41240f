"""The search for a load's peak between samples (``analytic.peaks``), written once for both paths."""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytic import peaks


def _search(load, t_before, t_peak, t_after):
    """Run the search on ``load(t)`` from its samples at the three times (NaN: no sample); returns
    ``(t, value, evaluations)``."""
    def sample(t):
        return 0.0 if math.isnan(t) else load(t)

    s = peaks.search_start(t_before, sample(t_before), t_peak, load(t_peak), t_after, sample(t_after))
    calls = 0
    while True:
        done, u, s = peaks.search_next(s)
        if done:
            return s.x, -s.fx, calls
        calls += 1
        s = peaks.search_update(s, u, -load(u))


# A smooth, skewed peak, as a load is around its largest: 1 + 0.3 cos(w (t - t0)) with a cubic term,
# peak at t0 exactly (its derivative 0.3 w sin(0) + 3 c (t - t0)^2 vanishes there, and it is a maximum).
T0, W, C = 0.4123456789, 37.0, 5.0


def _skewed(t):
    return 1.0 + 0.3 * math.cos(W * (t - T0)) + C * (t - T0) ** 3


@pytest.mark.parametrize("offset", [-0.45, -0.1, 0.0, 0.2, 0.49], ids=lambda o: f"peak at {o:+.2f} steps")
def test_the_peak_between_three_samples_is_found_to_the_tolerance(offset):
    h = 4e-3   # a step: the cosine's width is 1/37 s, so the samples straddle the peak closely
    t_peak = T0 - offset * h
    t, value, calls = _search(_skewed, t_peak - h, t_peak, t_peak + h)
    tolerance = math.sqrt(2.2e-16) * T0 + peaks.PEAK_TIME_TOLERANCE
    assert abs(t - T0) <= 2 * tolerance
    assert value == pytest.approx(_skewed(T0), rel=1e-14)
    # Started from the samples' parabola, it needs a handful of evaluations; scipy's bounded
    # minimiser from the golden section takes about two dozen on each of the two steps.
    assert calls <= 8


@pytest.mark.parametrize("side", ["before", "after"])
def test_a_peak_at_a_stretchs_end_is_searched_on_its_one_step(side):
    # The largest sample is the stretch's last (first): the bracket is the step before (after) it.
    h = 4e-3
    if side == "before":
        t, value, _ = _search(_skewed, T0 - 0.7 * h, T0 + 0.3 * h, math.nan)
    else:
        t, value, _ = _search(_skewed, math.nan, T0 - 0.3 * h, T0 + 0.7 * h)
    assert abs(t - T0) <= 2 * (math.sqrt(2.2e-16) * T0 + peaks.PEAK_TIME_TOLERANCE)
    assert value == pytest.approx(_skewed(T0), rel=1e-14)


def test_a_load_rising_to_the_stretchs_end_peaks_there():
    # No interior maximum: the search ends at the bracket's end, never beyond it, with the value there.
    t, value, _ = _search(lambda t: 3.0 * t, 1.0, 1.5, math.nan)
    assert 1.5 - 1e-7 <= t <= 1.5 and value == pytest.approx(4.5, rel=1e-7)


def test_the_result_is_never_below_the_largest_sample():
    # A plateau with noise: whatever the search does, it keeps the best point it saw, the sample included.
    rng = np.random.default_rng(3)
    for _ in range(50):
        bumps = rng.normal(0.0, 1e-12, 3)
        times = np.sort(rng.uniform(0.0, 1.0, 3))

        def load(t):
            return 2.0 + bumps[0] * math.sin(1e3 * t) + bumps[1] * math.cos(7e2 * t)

        _, value, _ = _search(load, *times)
        assert value >= load(times[1])


def test_the_compiled_search_takes_the_same_steps():
    from analytic import compiled

    h = 4e-3
    for offset in (-0.3, 0.1, 0.45):
        t_peak = T0 - offset * h
        args = (t_peak - h, _skewed(t_peak - h), t_peak, _skewed(t_peak), t_peak + h, _skewed(t_peak + h))
        python, native = peaks.search_start(*args), compiled.peaks_.search_start(*args)
        assert tuple(python) == tuple(native)
        while True:
            done, u, python = peaks.search_next(python)
            done_c, u_c, native = compiled.peaks_.search_next(native)
            assert (done, u, tuple(python)) == (done_c, u_c, tuple(native))
            if done:
                break
            python = peaks.search_update(python, u, -_skewed(u))
            native = compiled.peaks_.search_update(native, u, -_skewed(u))
