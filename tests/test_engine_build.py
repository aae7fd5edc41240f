"""The pymunk machine is the design: start geometry, body properties, joint settings."""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytic.design_file import default_design
from support import with_machine
from engine_model.build import EngineError, arm_body_properties, build


@pytest.fixture(scope="module")
def design():
    return default_design()


def test_start_geometry_is_the_rest_position(design):
    # Hand geometry, independent of initial_angles: the long tip rests on the base
    # behind the pivot, the short tip is diametrically opposite, the counterweight
    # hangs plumb below it, and the sling lies forward along the base.
    m = design.machine
    rig = build(design)
    tip = np.array([-math.sqrt(m.arm_long**2 - m.pivot_height**2), -m.pivot_height])
    short = -tip * m.arm_short / m.arm_long
    assert rig.arm.local_to_world((0.0, m.arm_long)) == pytest.approx(tip, abs=1e-12)
    assert rig.arm.local_to_world((0.0, -m.arm_short)) == pytest.approx(short, abs=1e-12)
    assert rig.arm.position == pytest.approx((0.0, 0.0), abs=1e-15)
    assert rig.counterweight.position == pytest.approx(short - [0.0, m.counterweight_link], abs=1e-12)
    assert rig.counterweight.local_to_world((0.0, m.counterweight_link)) == pytest.approx(short, abs=1e-12)
    assert rig.projectile.position == pytest.approx(tip + [m.sling_length, 0.0], abs=1e-12)


def test_bodies_carry_the_design_masses(design):
    m = design.machine
    rig = build(design)
    assert (rig.arm.mass, rig.arm.moment) == (m.arm_mass, m.arm_inertia)
    assert tuple(rig.arm.center_of_gravity) == (0.0, m.arm_cg)
    assert (rig.counterweight.mass, rig.counterweight.moment) == (m.counterweight_mass, m.counterweight_inertia)
    assert rig.projectile.mass == design.projectile.mass


def test_every_joint_corrects_its_whole_error_each_step(design):
    rig = build(design)
    assert len(rig.space.constraints) == 4  # pivot, hinge, sling, groove
    for joint in rig.space.constraints:
        assert joint.error_bias == 0.0 and joint.max_bias == math.inf and not joint.collide_bodies
    assert not rig.space.shapes
    assert tuple(rig.space.gravity) == (0.0, -design.environment.gravity) and rig.space.damping == 1.0


@pytest.mark.parametrize("changes", [{"arm_mass": 0.01}, {"arm_inertia": 0.0}, {"arm_mass": 0.05, "arm_cg": -0.1}],
                         ids=["light", "no-own-inertia", "light-short-side"])
def test_ballast_at_the_pivot_keeps_the_arm_dynamics(design, changes):
    # A pinned arm moves only through its weight's moment m*cg and its inertia about the pivot.
    m = with_machine(design, **changes).machine
    mass, cg, moment = arm_body_properties(with_machine(design, **changes))
    assert mass >= m.arm_mass and moment > 0.0
    assert mass * cg == pytest.approx(m.arm_mass * m.arm_cg, rel=1e-14, abs=1e-15)
    assert moment + mass * cg**2 == pytest.approx(m.arm_inertia + m.arm_mass * m.arm_cg**2, rel=1e-14)


def test_a_massless_lever_is_refused(design):
    with pytest.raises(EngineError, match="massless lever"):
        build(with_machine(design, arm_inertia=0.0, arm_cg=0.0))


def test_a_point_counterweight_hangs_on_a_distance_joint(design):
    rig = build(with_machine(design, counterweight_inertia=0.0))
    assert type(rig.hinge).__name__ == "PinJoint"
    assert rig.hinge.distance == design.machine.counterweight_link


def test_the_rope_is_a_one_sided_sling(design):
    rig = build(design, sling="rope")
    assert type(rig.sling).__name__ == "SlideJoint"
    assert (rig.sling.min, rig.sling.max) == (0.0, design.machine.sling_length)
    with pytest.raises(ValueError, match="sling"):
        build(design, sling="chain")
