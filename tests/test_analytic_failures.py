"""Valid designs that do not throw end in a named status, never a crash, NaN or hang."""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytic.result import Status
from analytic.reference import simulate
from support import PHRASES, failure_designs, with_machine

#: No real design is known to make the integrator fail a step (a rejected step
#: shrinks until it succeeds); its record and message are tested with the
#: kernel's own record of one (``test_analytic_fast``).
NO_KNOWN_DESIGN = {Status.STEP_FAILED}


@pytest.mark.parametrize("expected", failure_designs(), ids=lambda s: s.value)
def test_failure_is_named(expected):
    shot = simulate(failure_designs()[expected])
    assert shot.status is expected, shot.message
    assert PHRASES[expected] in shot.message
    assert shot.range is None and shot.to_json()["range"] is None and shot.landing_time is None
    # Released only if the failure came after release.
    assert (shot.release_time is not None) == (expected in (Status.NO_LANDING, Status.SHORT_OF_TARGET))
    assert np.all(np.isfinite(shot.history.q)) and len(shot.history.t) >= 1


def test_every_failure_kind_has_a_design():
    assert set(failure_designs()) == set(Status) - {Status.OK} - NO_KNOWN_DESIGN


def test_never_fires_exactly_below_the_static_threshold(table3):
    # Hand derivation (docs/derivation.md, 3.4 at rest): with q' = 0 and the
    # counterweight plumb, f2 = 0 and the projectile's weight cancels from r1, so
    # theta'' has the sign of r1 = g sin(theta0) (mA d - mW Lb): the machine fires
    # iff mW > mA d / Lb (0.2925 kg for the default arm).
    m = table3.machine
    threshold = m.arm_mass * m.arm_cg / m.arm_short
    below = simulate(with_machine(table3, counterweight_mass=0.99 * threshold))
    above = simulate(with_machine(table3, counterweight_mass=1.01 * threshold))
    assert below.status is Status.NEVER_FIRES
    assert above.status is not Status.NEVER_FIRES and len(above.history.t) > 10


def test_landing_behind_the_pivot_is_a_flagged_result(table3):
    # Sling released 170 deg ahead of the arm: the projectile is flung backwards (found by scan).
    shot = simulate(with_machine(table3, release_rule="sling", release_angle=math.radians(170.0)))
    assert shot.ok and shot.range < 0
    assert shot.landed_behind_pivot and shot.to_json()["landed_behind_pivot"] is True
    assert "behind the pivot" in shot.message


def test_a_sling_shorter_than_one_steps_rise_of_the_tip_still_ends_cleanly():
    """A 2.2 cm sling: the tip can rise past the sling's reach within one trial
    step of the integrator (found by hypothesis and by the optimiser's search)."""
    from analytic.design_space import default_problem, design_at

    design = design_at(default_problem(), [0.2685888, 0.2815835, 0.2368245, 0.0219153, 0.5273128, 0.7839298])
    shot = simulate(design)  # before the fix: ValueError "out of the sling's reach"
    assert np.all(np.isfinite(shot.history.q)) and shot.message
    # Every accepted stage-1 state keeps the tip within the sling's reach of the base.
    m = design.machine
    on_base = shot.history.stage == 1
    tip_height = m.arm_long * np.cos(shot.history.q[on_base, 0]) + m.pivot_height
    assert on_base.sum() > 5 and np.max(tip_height) <= m.sling_length * (1.0 + 1e-12)
