"""Designs sampled across the paper's Table II bounds all end in a result or a named failure."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from analytic.design import BeamArm, Design, Machine, Projectile, paper_geometry
from analytic.result import Status
from analytic.reference import simulate

#: A hang guard, not a speed claim: a typical shot takes ~0.05 s, the slowest
#: seen in a 1500-design scan under 1 s; 30 s means something looped.
HANG_GUARD_SECONDS = 30.0

# Table II of the paper (cm and degrees), converted to m / rad at this edge.
BOUNDS = {"arm_short": (0.01, 0.30), "counterweight_link": (0.16, 0.45), "clearance": (0.16, 0.45),
          "sling_length": (0.01, 0.61), "starting_angle": (10.0, 80.0), "release_angle": (-80.0, 80.0)}
WOODEN_ARM = BeamArm(width=0.019, depth=0.038, density=450.0)  # the default design's pine arm
LIGHT_ARM = BeamArm(width=0.005, depth=0.005, density=100.0)   # a few grams: nearly massless


def _between(name):
    low, high = BOUNDS[name]
    return st.floats(low, high, allow_nan=False)


@st.composite
def paper_designs(draw) -> Design:
    arm = draw(st.sampled_from([WOODEN_ARM, LIGHT_ARM]))
    arm_short, link, clearance = draw(_between("arm_short")), draw(_between("counterweight_link")), draw(_between("clearance"))
    h, arm_long = paper_geometry(arm_short, link, clearance, math.radians(draw(_between("starting_angle"))))
    mass, cg, inertia = arm.properties(arm_long, arm_short)
    machine = Machine(h, arm_long, arm_short, mass, cg, inertia, counterweight_mass=6.5,
                      counterweight_link=link, counterweight_inertia=0.009345,
                      sling_length=draw(_between("sling_length")),
                      release_angle=math.radians(draw(_between("release_angle"))),
                      release_rule=draw(st.sampled_from(["velocity", "sling"])))
    return Design(machine, Projectile(0.0456, 0.04267, "golf-ball"), name="sampled")


def _check_outcome(design: Design) -> None:
    start = time.perf_counter()
    shot = simulate(design)
    assert time.perf_counter() - start < HANG_GUARD_SECONDS
    assert isinstance(shot.status, Status) and shot.message
    assert np.all(np.isfinite(shot.q)) and np.all(np.isfinite(shot.energy.total if shot.energy else 0.0))
    if shot.ok:
        values = [shot.range, shot.release_speed, shot.apex_height, shot.flight_time, shot.min_sling_tension]
        assert all(math.isfinite(v) for v in values)
        assert shot.release_speed > 0 and shot.flight_time > 0 and shot.apex_height > 0
        if design.machine.release_rule == "velocity":
            assert shot.launch_angle == pytest.approx(design.machine.release_angle, abs=1e-8)
    else:
        assert shot.range is None and shot.release_time is None


@settings(max_examples=25, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(paper_designs())
def test_sampled_designs_end_in_a_result_or_a_named_failure(design):
    _check_outcome(design)


@pytest.mark.slow
@settings(max_examples=300, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(paper_designs())
def test_many_sampled_designs_end_in_a_result_or_a_named_failure(design):
    _check_outcome(design)
