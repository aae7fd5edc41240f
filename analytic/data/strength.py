"""Will it break: the arm's materials and the projectiles' limits, each with its source, and the beam's stress.

Plain data and arithmetic on floats, no dynamics: the design reads the tables
(``analytic.design``), and the shot's readouts (``analytic.result.Shot``)
turn the peak loads either model measured into a stress, a safety factor and
a verdict on the projectile, after the shot, in Python (nothing here runs in
the compiled kernel).

The arm's **strength** is the stress at which its material fails in bending:
for the woods the modulus of rupture of small clear specimens (no knots), for
the metals the yield strength (the stress past which the arm bends for good).
The **safety factor** is that strength over the peak bending stress of a shot:
above 1 the arm holds by that margin; at or below 1 it breaks (wood) or takes
a set (metal). The figures are averages (wood) and typical or minimum values
(metal) of a sound piece: real lumber with knots and sloping grain is weaker,
so builders aim at a safety factor of 2 or more.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: Standard gravity, m/s^2: what "g" means in files and tables (``projectile.max_acceleration``),
#: not the design's own ``environment.gravity`` (3rd CGPM, 1901).
STANDARD_GRAVITY = 9.80665

_WOOD = ("USDA Forest Products Laboratory, Wood Handbook: Wood as an Engineering Material, "
         "FPL-GTR-282 (2021), Table 5-3a: clear wood at 12 % moisture, modulus of rupture")


@dataclass(frozen=True)
class Material:
    """An arm material: its bending strength (Pa), which strength that is, and where the value comes from."""

    name: str
    strength: float
    strength_kind: str
    source: str


#: The arm's materials (``machine.arm_beam.material``) by name.
MATERIALS = {material.name: material for material in (
    Material("pine", 59e6, "modulus of rupture", f"{_WOOD} (eastern white pine, 59 000 kPa)"),
    Material("oak", 99e6, "modulus of rupture", f"{_WOOD} (northern red oak, 99 000 kPa)"),
    Material("ash", 103e6, "modulus of rupture", f"{_WOOD} (white ash, 103 000 kPa)"),
    Material("douglas-fir", 85e6, "modulus of rupture", f"{_WOOD} (coast Douglas-fir, 85 000 kPa)"),
    Material("aluminium-6061", 276e6, "yield strength",
             "Aluminum Association, Aluminum Standards and Data; ASM Handbook Vol. 2: 6061-T6 typical "
             "tensile yield strength 276 MPa (40 ksi); the minimum for extrusions is 240 MPa (35 ksi)"),
    Material("steel-s235", 235e6, "yield strength",
             "EN 10025-2: S235 minimum yield strength 235 MPa (thickness up to 16 mm)"),
)}


@dataclass(frozen=True)
class ProjectileKind:
    """A projectile kind: the largest acceleration it survives (in g) and the basis of that figure."""

    name: str
    max_acceleration_g: float
    basis: str


#: The projectile kinds (``projectile.kind``) by name. Only the golf ball's and the softball's
#: figures rest on measured impacts (floors: the ball survives them every time); the others are
#: estimates, and the docs say how each was made (``docs/guide/will-it-break.md``).
PROJECTILE_KINDS = {kind.name: kind for kind in (
    ProjectileKind("golf-ball", 10000.0,
                   "a drive: about 70 m/s in about 0.5 ms of contact (Penner, Rep. Prog. Phys. 66, 131, 2003) "
                   "is 14 000 g on average, survived every time; 10 000 g is a floor"),
    ProjectileKind("softball", 5000.0,
                   "a bat's hit: about 60 m/s of change in about 1 ms of contact (Nathan, Am. J. Phys. 68, "
                   "979, 2000, for the baseball) is 6 000 g on average, survived; 5 000 g is a floor"),
    ProjectileKind("pumpkin", 50.0,
                   "an estimate: pumpkins survive trebuchets (tens of g) and burst in air cannons "
                   "(hundreds of g); 50 g is the lower end"),
    ProjectileKind("water-balloon", 40.0,
                   "an estimate: a hand-held launcher's throw (about 30 m/s in a 1 m pull, 45 g) bursts "
                   "some balloons; 40 g"),
    ProjectileKind("egg", 30.0,
                   "an estimate: a strong egg takes about 34 N between plates before it cracks; a 58 g egg "
                   "pressed by its own inertia reaches that at 60 g; halved for a pouch's uneven support"),
)}


def bending_stress(moment: float, width: float, depth: float) -> float:
    """The peak bending stress of a rectangular section, Pa: ``6 M / (width depth^2)``.

    The stress at the section's outer fibres, ``M c / I`` with ``c = depth / 2`` and
    ``I = width depth^3 / 12`` (Euler-Bernoulli); ``depth`` lies in the plane of the bending.

    Parameters
    ----------
    moment : the bending moment's magnitude, N m.
    width, depth : the section, m.
    """
    return 6.0 * moment / (width * depth * depth)


def safety_factor(stress: float, strength: float) -> float:
    """``strength / stress``, the margin before failure; infinite for an unloaded section."""
    return math.inf if stress == 0.0 else strength / stress
