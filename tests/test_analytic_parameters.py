"""``analytic.parameters.params``: each field of ``Params`` holds the design field its table names.

``params`` builds the tuple positionally (a keyword call is 4 us of a fast shot), so a field
written in the wrong place would pass anything that reads the tuple by position. This test
reads every field by name, on designs whose numbers all differ, so a swap of any two fails,
and so does the compiled kernel's record over a packed row (``kernel.params``).
"""

from __future__ import annotations

import dataclasses
import math

import pytest

from analytic.aero import DRAG_MODELS
from analytic.design import (KINDS, Base, Design, Environment, Losses, Machine, Projectile,
                             initial_angles, largest_length)
from analytic.fast import pack
from analytic.geometry import RELEASE_RULES
from analytic.fast.kernel import params as row_params
from analytic.limits import swing_time_limit
from analytic.parameters import PARAMS_DTYPE, Params, params


def distinct_design(*, statics: bool, drag: str, kind: str, rolling: bool) -> Design:
    """A valid design whose numbers differ from each other where its kind allows (a floating arm has
    no link and no hinge; only it has a guide and a track)."""
    floating, hinged = kind == "floating-arm", kind == "hinged"
    machine = Machine(pivot_height=3.7, arm_long=5.9, arm_short=1.7, arm_mass=13.1, arm_cg=1.1,
                      arm_inertia=29.3, counterweight_mass=97.0, counterweight_link=0.71 if hinged else 0.0,
                      counterweight_inertia=0.37, sling_length=4.3, release_angle=math.radians(41.0),
                      release_rule="sling", kind=kind, sling_mass=0.059, pouch_mass=0.031)
    projectile = Projectile(mass=0.53, diameter=0.19, drag=drag,
                            drag_coefficient=0.47 if drag == "constant" else None, drag_factor=1.3,
                            drag_during_swing=not rolling)
    environment = Environment(gravity=9.79, air_density=1.19, air_viscosity=1.83e-5, wind_speed=-3.1,
                              target_height=-2.3 if rolling else 4.1)
    joints = (dict(guide_friction=0.037, track_friction=0.041) if floating
              else dict(hinge_friction=0.017, hinge_radius=0.029) if hinged else {})
    if not floating:
        joints["base_friction"] = 0.31
    statics = {f"{joint}_static_friction": value for joint, value in
               (("axle", 0.013), ("base", 0.43), ("hinge", 0.019), ("guide", 0.047), ("track", 0.053))
               if f"{joint}_friction" in joints or joint == "axle"} if statics else {}
    losses = Losses(axle_friction=0.011, axle_radius=0.023, **joints, **statics)
    base = Base(mobility="rolling", mass=211.0, trough_height=0.67) if rolling else Base(trough_height=0.59)
    return Design(machine=machine, projectile=projectile, environment=environment, losses=losses, base=base)


#: (drag, kind, rolling) of the designs tested.
CASES = [("constant", "hinged", True), ("golf-ball", "floating-arm", False), ("none", "fixed", False)]


def expected(design: Design) -> dict[str, float]:
    """``Params``' fields by name, from the table in ``analytic/parameters.py``'s docstring."""
    m, proj, env, losses = design.machine, design.projectile, design.environment, design.losses
    theta0, phi0, _ = initial_angles(m, design.base.trough_height)
    return dict(
        La=m.arm_long, Lb=m.arm_short, d=m.arm_cg, mA=m.arm_mass, IA=m.arm_inertia,
        mW=m.counterweight_mass, Lw=m.counterweight_link, IW=m.counterweight_inertia, Ls=m.sling_length,
        mP=proj.mass, h=m.pivot_height, g=env.gravity, alpha=m.release_angle,
        rule=RELEASE_RULES.index(m.release_rule), drag=DRAG_MODELS.index(proj.drag),
        cd=math.nan if proj.drag_coefficient is None else proj.drag_coefficient,
        diameter=proj.diameter, area=proj.frontal_area * proj.drag_factor, rho=env.air_density,
        mu=env.air_viscosity, wind=env.wind_speed, rolling=1.0 if design.base.mobility == "rolling" else 0.0,
        Mf=design.base.mass if design.base.mobility == "rolling" else 0.0,
        t_limit=swing_time_limit(largest_length(m), env.gravity), theta0=theta0, phi0=phi0,
        mua=losses.axle_friction, ra=losses.axle_radius, muh=losses.hinge_friction, rh=losses.hinge_radius,
        mub=losses.base_friction, mua_s=losses.static("axle"), muh_s=losses.static("hinge"),
        mub_s=losses.static("base"), kind=KINDS.index(m.kind), drag_swing=1.0 if proj.drag_during_swing else 0.0,
        mug=losses.guide_friction, mut=losses.track_friction, mug_s=losses.static("guide"),
        mut_s=losses.static("track"), ht=design.base.trough_height, yt=env.target_height,
        mS=m.sling_mass, mQ=m.pouch_mass)


def assert_fields(read, design: Design) -> None:
    """Each field ``read(name)`` gives is the design's number that ``expected`` names."""
    for name, value in expected(design).items():
        actual = read(name)
        assert actual == value or (math.isnan(value) and math.isnan(actual)), (name, actual, value)


@pytest.mark.parametrize("statics", [True, False])
@pytest.mark.parametrize("drag, kind, rolling", CASES)
def test_each_field_holds_its_design_field(statics, drag, kind, rolling):
    design = distinct_design(statics=statics, drag=drag, kind=kind, rolling=rolling)
    got = params(design)
    assert isinstance(got, Params)
    assert list(expected(design)) == list(Params._fields)
    assert all(type(value) is float for value in got), [type(value) for value in got]
    assert_fields(lambda name: getattr(got, name), design)


@pytest.mark.parametrize("statics", [True, False])
@pytest.mark.parametrize("drag, kind, rolling", CASES)
def test_the_kernels_record_over_a_packed_row_reads_each_field_by_name(statics, drag, kind, rolling):
    # The kernel reads a design row through PARAMS_DTYPE (kernel.params, the same function it compiles):
    # each named field of the record must be the one Params has under that name.
    design = distinct_design(statics=statics, drag=drag, kind=kind, rolling=rolling)
    record = row_params(pack(design))
    assert record.dtype == PARAMS_DTYPE and PARAMS_DTYPE.names == Params._fields
    assert_fields(lambda name: float(record[name]), design)


def test_every_two_fields_differ_in_some_design():
    """The control: two fields equal in every design tested could be swapped unseen."""
    cases = [expected(distinct_design(statics=statics, drag=drag, kind=kind, rolling=rolling))
             for statics in (True, False) for drag, kind, rolling in CASES]
    names = list(Params._fields)
    same = [(a, b) for i, a in enumerate(names) for b in names[i + 1:]
            if all(case[a] == case[b] or (math.isnan(case[a]) and math.isnan(case[b])) for case in cases)]
    assert same == []
