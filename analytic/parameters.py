"""The design as the model's numbers: one tuple of floats in the equations' symbols.

``Params`` is what every function of the model takes (``analytic.eom``,
``analytic.stages``); its field order is also the layout of a design row, the
form in which the compiled path receives designs (``analytic.fast.pack``):
the order is written here once, and both paths read it by name.

Symbols (``docs/derivation.md``):

==========  ===================================================  ==========================
field       meaning                                              design field
==========  ===================================================  ==========================
La, Lb      long and short arm, m                                machine.arm_long, arm_short
d           pivot to arm centre of mass (long side positive), m  machine.arm_cg
mA, IA      arm mass (kg), inertia about its centre (kg m^2)     machine.arm_mass, arm_inertia
mW, Lw, IW  counterweight mass, link, inertia about its centre   machine.counterweight_*
Ls          sling, m                                             machine.sling_length
mP          projectile mass, kg                                  projectile.mass
h, g        pivot height (m), gravity (m/s^2)                    machine.pivot_height, environment.gravity
alpha       release angle, rad                                   machine.release_angle
rule        release rule code (``geometry.RELEASE_RULES``)       machine.release_rule
drag        drag model code (``aero.DRAG_MODELS``)               projectile.drag
cd          constant drag coefficient (NaN unless "constant")    projectile.drag_coefficient
diameter    projectile diameter, m; area its drag area, m^2      projectile.diameter, drag_factor
            (the frontal area times the drag factor)
rho, mu     air density (kg/m^3), viscosity (Pa s)               environment.air_*
wind        wind speed, m/s, positive = tailwind                 environment.wind_speed
rolling     1.0 if the frame rolls, 0.0 if it is fixed             base.mobility
Mf          frame mass, kg (0 for a fixed frame: not read)       base.mass
t_limit     firing-to-release time limit, s                      (``limits.swing_time_limit``)
theta0      arm angle at rest, rad                               (``design.initial_angles``)
phi0        counterweight angle at rest, rad                     (``design.initial_angles``)
mua, ra     axle's Coulomb coefficient and radius (m)            losses.axle_friction, axle_radius
muh, rh     hinge's Coulomb coefficient and radius (m)           losses.hinge_friction, hinge_radius
mub         base's Coulomb coefficient (stage 1)                 losses.base_friction
mua_s,      the static coefficients of the axle, the hinge and   losses.*_static_friction
muh_s,      the base (each at least its kinetic one; the
mub_s       kinetic one when the file does not give it)
kind        machine kind code (``design.KINDS``; ``eom.FIXED``)  machine.kind
drag_swing  1.0 if the drag acts in stages 1-2 too, else 0.0      projectile.drag_during_swing
mug, mut    the floating arm's guide and track Coulomb           losses.guide_friction, track_friction
            coefficients
mug_s,      their static coefficients (each at least its         losses.guide_static_friction,
mut_s       kinetic one; the kinetic one when not given)         track_static_friction
==========  ===================================================  ==========================
"""

from __future__ import annotations

import math
from typing import NamedTuple

from analytic.aero import DRAG_MODELS
from analytic.design import KINDS, initial_angles, largest_length
from analytic.limits import swing_time_limit
from analytic.geometry import RELEASE_RULES


class Params(NamedTuple):
    """A design's numbers in the model's symbols (SI, radians; the table above)."""

    La: float
    Lb: float
    d: float
    mA: float
    IA: float
    mW: float
    Lw: float
    IW: float
    Ls: float
    mP: float
    h: float
    g: float
    alpha: float
    rule: float
    drag: float
    cd: float
    diameter: float
    area: float
    rho: float
    mu: float
    wind: float
    rolling: float
    Mf: float
    t_limit: float
    theta0: float
    phi0: float
    mua: float
    ra: float
    muh: float
    rh: float
    mub: float
    mua_s: float
    muh_s: float
    mub_s: float
    kind: float
    drag_swing: float
    mug: float
    mut: float
    mug_s: float
    mut_s: float


#: Length of a design row (``Params`` in order).
N_PARAMS = len(Params._fields)


def params(design) -> Params:
    """The ``Params`` of an ``analytic.design.Design``."""
    m, proj, env, losses = design.machine, design.projectile, design.environment, design.losses
    theta0, phi0, _ = initial_angles(m)
    return Params(
        La=m.arm_long, Lb=m.arm_short, d=m.arm_cg, mA=m.arm_mass, IA=m.arm_inertia,
        mW=m.counterweight_mass, Lw=m.counterweight_link, IW=m.counterweight_inertia,
        Ls=m.sling_length, mP=proj.mass, h=m.pivot_height, g=env.gravity,
        alpha=m.release_angle, rule=float(RELEASE_RULES.index(m.release_rule)),
        drag=float(DRAG_MODELS.index(proj.drag)),
        cd=math.nan if proj.drag_coefficient is None else proj.drag_coefficient,
        diameter=proj.diameter, area=proj.drag_area,
        rho=env.air_density, mu=env.air_viscosity, wind=env.wind_speed,
        rolling=float(design.base.rolling), Mf=design.base.mass if design.base.rolling else 0.0,
        t_limit=swing_time_limit(largest_length(m), env.gravity), theta0=theta0, phi0=phi0,
        mua=losses.axle_friction, ra=losses.axle_radius, muh=losses.hinge_friction, rh=losses.hinge_radius,
        mub=losses.base_friction, mua_s=losses.static("axle"), muh_s=losses.static("hinge"),
        mub_s=losses.static("base"), kind=float(KINDS.index(m.kind)),
        drag_swing=float(proj.drag_during_swing), mug=losses.guide_friction, mut=losses.track_friction,
        mug_s=losses.static("guide"), mut_s=losses.static("track"))
