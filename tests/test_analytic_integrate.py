"""The event-locating integrator: roots, directions, and the armed predicate."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from analytic.reference.ode import Event, integrate, step_interpolant

TOL = dict(rtol=1e-12, atol=1e-12, output_step=0.01)


def test_falling_root_of_a_free_fall_is_the_closed_form_time():
    # y'' = -g from y = 1 at rest reaches 0 at t = sqrt(2 / g) (elementary kinematics).
    g = 9.81
    seg = integrate(lambda t, y: np.array([y[1], -g]), 0.0, np.array([1.0, 0.0]), 5.0,
                    (Event("ground", lambda t, y: y[0], direction=-1),), **TOL)
    assert seg.event == "ground"
    assert seg.t_end == pytest.approx(math.sqrt(2.0 / g), abs=1e-12)


def test_direction_filter_skips_rising_crossings():
    # y = sin(t): rising root at 0 (start, not counted), falling at pi, rising at 2 pi.
    seg = integrate(lambda t, y: np.array([math.cos(t)]), 0.0, np.array([0.0]), 10.0,
                    (Event("rise", lambda t, y: y[0], direction=+1),), **TOL)
    assert seg.t_end == pytest.approx(2.0 * math.pi, abs=1e-9)


def test_armed_predicate_rejects_the_opposite_direction_many_times():
    """A direction that wobbles around alpha + 180 deg (many rising roots of
    sin(alpha - angle), all disarmed) before sweeping clockwise to alpha."""
    alpha = math.radians(45.0)

    def angle(t):  # rad; wobbles about 225 deg, then sweeps clockwise past 45 deg
        return math.radians(220.0 + 20.0 * math.sin(30.0 * t) - 20.0 * t * t)

    def value(t, y):
        return math.sin(alpha - y[0])

    def armed(t, y):
        return math.cos(alpha - y[0]) > 0.0

    def rate(t, y):
        return np.array([math.radians(600.0 * math.cos(30.0 * t) - 40.0 * t)])

    seg = integrate(rate, 0.0, np.array([angle(0.0)]), 5.0,
                    (Event("release", value, direction=+1, armed=armed),), **TOL)
    # Independent answer: scan the closed-form angle for its first clockwise
    # pass through 45 deg, then refine that bracket.
    grid = np.linspace(0.0, 5.0, 500001)
    values = np.array([value(t, [angle(t)]) for t in grid])
    along = np.array([armed(t, [angle(t)]) for t in grid])
    rising = np.flatnonzero((values[:-1] < 0) & (values[1:] >= 0))
    first = next(i for i in rising if along[i + 1])
    expected = brentq(lambda t: angle(t) - alpha, grid[first], grid[first + 1], xtol=1e-15)
    assert sum(1 for i in rising if i < first and not along[i + 1]) >= 3, \
        "the test must exercise several disarmed roots"
    assert seg.event == "release"
    assert seg.t_end == pytest.approx(expected, abs=1e-9)


def test_non_terminal_events_are_recorded_and_end_is_reported():
    seg = integrate(lambda t, y: np.array([math.cos(t)]), 0.0, np.array([0.0]), 7.0,
                    (Event("peak", lambda t, y: math.cos(t), direction=-1, terminal=False),), **TOL)
    assert seg.event is None and seg.t_end == pytest.approx(7.0)
    assert [t for t, _ in seg.roots["peak"]] == pytest.approx([math.pi / 2], abs=1e-9)
    assert np.all(np.diff(seg.t) > 0)


def test_a_value_that_starts_at_zero_and_comes_back_within_the_first_step_is_found(monkeypatch):
    """x = t - t^2 / T starts at exactly 0 (as a friction switch leaves a joint's rate), is positive
    until t = T = 0.01 s and falls through 0 there, inside the first step (a quadratic is exact
    for DOP853; a second state keeps the first step from being tiny): 0 at the step's start and a
    negative value at its end, which a sign test alone misses (without the probes, no event)."""
    import analytic.reference.ode

    def run():
        return integrate(lambda t, y: np.array([1.0 - 2.0 * t / 0.01, 0.0]), 0.0, np.array([0.0, 100.0]), 10.0,
                         (Event("back", lambda t, y: y[0], direction=-1),), rtol=1e-10, atol=1e-10,
                         output_step=None)

    seg = run()
    assert seg.event == "back" and len(seg.step_t) == 2     # found in the first step
    assert seg.t_end == pytest.approx(0.01, abs=1e-14)
    monkeypatch.setattr(analytic.reference.ode, "ZERO_START_PROBES", 1)   # no probes: missed
    assert run().event is None


#: The hump of the tests below: x = cos t (an oscillator from t = 1) rises above ``HUMP_LEVEL`` only
#: within acos(0.999) = 0.0447 s of its top at t = 2 pi, so ``x - HUMP_LEVEL`` crosses zero twice
#: in 0.089 s; at these tolerances DOP853 steps over the oscillator in strides of 0.35 s or more
#: (measured: one step from 6.020 to 6.374 s holds both roots), so no sign change between a
#: step's ends shows them: as no release did where the velocity passed the release angle and came back.
HUMP_LEVEL = 0.999
#: How near the closed form a root of the hump is, s: the integrated x is off by a few 1e-10 at
#: rtol 1e-10 after 5 s, and x crosses the level at a slope of only sin(acos 0.999) = 0.045 per s
#: (measured: 1.4e-9 and 6.1e-9 s off).
HUMP_ROOT_TIME = 2e-8


def _oscillator(value, direction, level=HUMP_LEVEL):
    """Integrate x'' = -x from (cos 1, -sin 1) at t = 1 s watching ``value(x - level)`` (``direction``)."""
    return integrate(lambda t, y: np.array([y[1], -y[0]]), 1.0, np.array([math.cos(1.0), -math.sin(1.0)]), 9.0,
                     (Event("hump", lambda t, y: value(y[0] - level), direction=direction),),
                     rtol=1e-10, atol=1e-10, output_step=None)


@pytest.mark.parametrize("sign, direction, side",
                         [(1.0, +1, -1.0), (1.0, -1, +1.0), (-1.0, +1, +1.0), (-1.0, -1, -1.0)],
                         ids=["rises-and-falls-back, rising counted", "rises-and-falls-back, falling counted",
                              "dips-and-comes-back, rising counted", "dips-and-comes-back, falling counted"])
def test_a_value_that_crosses_zero_and_back_within_one_step_is_found(sign, direction, side):
    """Both roots of the hump lie in one step whose ends' values share a sign; the counted one (the
    first or the second, by the direction) is found. Closed form: x = cos t, the roots at 2 pi -/+ acos(level)."""
    seg = _oscillator(lambda x: sign * x, direction)
    half = math.acos(HUMP_LEVEL)
    assert seg.event == "hump"
    assert seg.t_end == pytest.approx(2.0 * math.pi + side * half, abs=HUMP_ROOT_TIME)
    last = seg.steps[-1]   # the step that holds the root spans the whole hump
    assert last.t_old < 2.0 * math.pi - half and last.t > 2.0 * math.pi + half


def test_a_value_that_turns_back_short_of_zero_within_a_step_has_no_root():
    # cos t tops out at 1 < 1.001: the step's turn is searched, and no root is made up.
    seg = _oscillator(lambda x: x, +1, level=1.001)
    assert seg.event is None and seg.t_end == 9.0


#: A narrow dip inside a step [0, 1] s: 0.01 - w^2 / (w^2 + (t - t_c)^2) is below zero only within
#: w sqrt(1 / 0.01 - 1) = 0.00995 s of t_c = 0.4 s (closed form), 2 % of the step; positive at both ends.
DIP_CENTRE, DIP_WIDTH, DIP_LEVEL = 0.4, 1e-3, 0.01


def _dip(t):
    return DIP_LEVEL - DIP_WIDTH**2 / (DIP_WIDTH**2 + (t - DIP_CENTRE) ** 2)


def _dip_rate(t):
    return 2.0 * (t - DIP_CENTRE) * DIP_WIDTH**2 / (DIP_WIDTH**2 + (t - DIP_CENTRE) ** 2) ** 2


def _turn(module, value, direction):
    """The shared search of a turning step [0, 1] of ``value`` (``analytic.sequence``, or its compiled
    twin), as both paths drive it; returns its bracket and every time it evaluated."""
    a, b = 0.0, 1.0
    before, after = value(a), value(b)
    assert module.turns_back(before, after, _dip_rate(a), _dip_rate(b))
    u = module.turn_first(a, b, _dip_rate(a), _dip_rate(b))
    v = value(u)
    search = module.turn_search(a, b, before, after, u, v)
    times = [u]
    while True:
        done, u_next, search = module.turn_next(search, before, v)
        if done:
            return module.turn_bracket(a, b, before, after, u, v, direction), times
        u, v = u_next, value(u_next)
        times.append(u)
        search = module.turn_update(search, before, u, v)


@pytest.mark.parametrize("direction, side", [(-1, -1.0), (+1, +1.0)], ids=["falling counted", "rising counted"])
def test_a_narrow_dip_inside_a_step_is_bracketed_alike_by_both_paths_search(direction, side):
    from analytic import sequence
    from analytic.fast import compiled

    (start, v_start, end, v_end), times = _turn(sequence, _dip, direction)
    assert _turn(compiled.sequence_, _dip, direction) == ((start, v_start, end, v_end), times)   # step for step
    assert len(times) <= 10
    root = DIP_CENTRE + side * DIP_WIDTH * math.sqrt(1.0 / DIP_LEVEL - 1.0)
    assert start < root < end and sequence.counted_crossing(v_start, v_end, direction)
    assert brentq(_dip, start, end, xtol=1e-15) == pytest.approx(root, abs=1e-12)


def test_a_dip_that_stays_short_of_zero_brackets_nothing():
    from analytic import sequence

    (start, v_start, end, v_end), times = _turn(sequence, lambda t: _dip(t) + 1.0, -1)
    assert (start, end) == (0.0, 1.0) and not sequence.counted_crossing(v_start, v_end, -1)
    assert len(times) < 60   # the search ended at the dip's bottom, short of zero


def test_a_step_s_interpolant_rebuilt_from_its_record_is_scipy_s_own_for_that_step():
    # ``step_interpolant`` sets scipy's solver to a kept step's state and asks it for the dense
    # output; the interpolants scipy built while integrating (``continuous``) are the reference.
    def pendulum(t, y):
        return np.array([y[1], -9.81 * math.sin(y[0]) - 0.3 * y[1] * abs(y[1])])

    segment = integrate(pendulum, 0.0, np.array([2.5, 0.0]), 3.0, rtol=1e-10, atol=1e-10, output_step=None,
                        continuous=True)
    own = segment.solution.interpolants
    assert len(segment.steps) == len(own) > 20
    for step, interpolant in zip(segment.steps, own, strict=True):
        rebuilt = step_interpolant(pendulum, step, rtol=1e-10, atol=1e-10)
        times = np.linspace(step.t_old, step.t, 7)
        assert np.array_equal(rebuilt(times), interpolant(times))   # to the bit
    # The control: the previous step's record gives another interpolant.
    other = step_interpolant(pendulum, segment.steps[3], rtol=1e-10, atol=1e-10)
    middle = 0.5 * (segment.steps[4].t_old + segment.steps[4].t)
    assert not np.array_equal(other(middle), own[4](middle))
