"""The design as the model's numbers: one tuple of floats in the equations' symbols.

``Params`` is what every function of the model takes (``analytic.eom``,
``analytic.stages``); its field order is also the layout of a design row, the
form in which the compiled path receives designs (``analytic.fast.pack``) and
reads them, as a record of the same fields (``PARAMS_DTYPE``): the order is
written here once, and both paths read it by name.

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
alpha       release angle, rad (rule "ideal": the arm angle at   machine.release_angle
            release, ``analytic.ideal``; NaN until it is found)
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
ht          the trough's height above the base, m (stage 1's     base.trough_height
            projectile on ``y = -(h - ht)``)
mS, mQ      sling mass (a uniform rod, tip to projectile) and    machine.sling_mass, pouch_mass
            pouch mass (a point at the projectile), kg
==========  ===================================================  ==========================
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from analytic.aero import DRAG_MODELS
from analytic.design import KINDS, largest_length, rest_angle, static_coefficient
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
    ht: float
    yt: float
    mS: float
    mQ: float


#: Length of a design row (``Params`` in order).
N_PARAMS = len(Params._fields)


def params(design) -> Params:
    """The ``Params`` of an ``analytic.design.Design``.

    Built positionally, one line per group of fields in ``Params``' order (a keyword call of
    42 fields costs about three times as much, on every fast-path shot);
    ``tests/test_analytic_parameters.py`` checks each field against its design field by name.
    """
    m, proj, env, losses, base = design.machine, design.projectile, design.environment, design.losses, design.base
    theta0 = rest_angle(m, base.trough_height)   # design.initial_angles' first two, as floats
    return Params._make((
        m.arm_long, m.arm_short, m.arm_cg, m.arm_mass, m.arm_inertia,                       # La Lb d mA IA
        m.counterweight_mass, m.counterweight_link, m.counterweight_inertia,                # mW Lw IW
        m.sling_length, proj.mass, m.pivot_height, env.gravity, _alpha(m),                  # Ls mP h g alpha
        float(RELEASE_RULES.index(m.release_rule)), float(DRAG_MODELS.index(proj.drag)),    # rule drag
        math.nan if proj.drag_coefficient is None else proj.drag_coefficient,               # cd
        proj.diameter, proj.drag_area, env.air_density, env.air_viscosity, env.wind_speed,  # diameter area rho mu wind
        float(base.rolling), base.mass if base.rolling else 0.0,                            # rolling Mf
        swing_time_limit(largest_length(m), env.gravity), theta0, -theta0,                  # t_limit theta0 phi0
        losses.axle_friction, losses.axle_radius, losses.hinge_friction, losses.hinge_radius,  # mua ra muh rh
        losses.base_friction,                                                               # mub
        static_coefficient(losses.axle_static_friction, losses.axle_friction),              # mua_s
        static_coefficient(losses.hinge_static_friction, losses.hinge_friction),            # muh_s
        static_coefficient(losses.base_static_friction, losses.base_friction),              # mub_s
        float(KINDS.index(m.kind)), float(proj.drag_during_swing),                          # kind drag_swing
        losses.guide_friction, losses.track_friction,                                       # mug mut
        static_coefficient(losses.guide_static_friction, losses.guide_friction),            # mug_s
        static_coefficient(losses.track_static_friction, losses.track_friction),            # mut_s
        base.trough_height,                                                                 # ht
        env.target_height,                                                                  # yt
        m.sling_mass, m.pouch_mass))                                                        # mS mQ


def _alpha(machine) -> float:
    """``Params.alpha`` of a machine: its release angle; NaN for the ideal rule, which ignores it
    (``analytic.ideal`` puts the arm angle it finds there)."""
    return math.nan if machine.release_rule == "ideal" else machine.release_angle


#: ``Params`` as a numpy record type, field for field: the compiled kernel reads each design row
#: through it in place (``kernel.params``); numba passes a record to a function as one pointer,
#: a ``Params`` tuple as its 44 numbers.
PARAMS_DTYPE = np.dtype([(name, np.float64) for name in Params._fields])
