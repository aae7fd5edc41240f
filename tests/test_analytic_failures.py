"""Valid designs that do not throw end in a named status, never a crash, NaN or hang."""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytic.design import Design, Machine, Projectile, paper_geometry
from analytic.result import Status
from analytic.simulate import simulate

from conftest import with_machine


def paper_machine(arm_short, link, clearance, sling, starting_deg, release_deg, rule, projectile_mass) -> Design:
    """A light-armed (10 g point) machine in the paper's variables, 6.5 kg counterweight, no drag.

    The cases below were found by a seeded random scan over the paper's Table II
    bounds with projectile masses 0.01-3 kg (1500 designs), one per failure kind.
    """
    h, arm_long = paper_geometry(arm_short, link, clearance, math.radians(starting_deg))
    machine = Machine(h, arm_long, arm_short, 0.01, 0.0, 0.0, 6.5, link, 0.009345, sling,
                      math.radians(release_deg), rule)
    return Design(machine, Projectile(projectile_mass, 0.04, "none"), name="failure-case")


CASES = {
    "never_fires": (lambda t3: with_machine(t3, counterweight_mass=0.2), Status.NEVER_FIRES),
    "never_lifts_off": (lambda t3: paper_machine(0.0565, 0.3376, 0.1727, 0.0314, 46.04, -5.41, "velocity", 1.963),
                        Status.NEVER_LIFTS_OFF),
    "hits_base_before_release": (lambda t3: paper_machine(0.1278, 0.3219, 0.2749, 0.4566, 36.63, -5.34, "velocity", 0.7738),
                                 Status.HITS_BASE_BEFORE_RELEASE),
    "never_releases": (lambda t3: paper_machine(0.0436, 0.3133, 0.3640, 0.5790, 52.99, 56.88, "sling", 0.2125),
                       Status.NEVER_RELEASES),
}


@pytest.mark.parametrize("case", list(CASES))
def test_failure_is_named(table3, case):
    build, expected = CASES[case]
    shot = simulate(build(table3))
    assert shot.status is expected, shot.message
    assert shot.release_time is None and shot.range is None and shot.to_json()["range"] is None
    assert np.all(np.isfinite(shot.q)) and len(shot.t) >= 1
    assert PHRASES[expected] in shot.message


PHRASES = {Status.NEVER_FIRES: "cannot lift the arm", Status.NEVER_LIFTS_OFF: "never lifts off",
           Status.HITS_BASE_BEFORE_RELEASE: "came back down to the base",
           Status.NEVER_RELEASES: "never reached the release angle"}


def test_never_fires_when_the_counterweight_torque_loses(table3):
    # Statics (hand calculation): at rest the counterweight hangs plumb from the
    # short-arm tip, lever arm Lb cos(start); the arm's weight acts at d cos(start)
    # on the other side. With a 0.2 kg counterweight: 0.2*0.2405 = 0.048 < 0.306*0.230 = 0.070 kg m.
    m = table3.machine
    weak = with_machine(table3, counterweight_mass=0.2)
    assert 0.2 * m.arm_short < m.arm_mass * m.arm_cg
    assert simulate(weak).status is Status.NEVER_FIRES


def test_landing_behind_the_pivot_is_a_flagged_result(table3):
    # Sling released 170 deg ahead of the arm: the projectile is flung backwards (found by scan).
    shot = simulate(with_machine(table3, release_rule="sling", release_angle=math.radians(170.0)))
    assert shot.ok and shot.range < 0
    assert shot.landed_behind_pivot and shot.to_json()["landed_behind_pivot"] is True
    assert "behind the pivot" in shot.message
