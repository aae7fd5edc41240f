"""Warnings for valid designs far outside anything buildable: the shot runs, and says which input is implausible.

A design is valid when it can be built and computed (``analytic.design``:
positive lengths and masses, a tip that reaches the base, numbers whose
products stay within the float range), at any size; it can still describe a
machine larger or smaller than any built, or weather no one has seen, and then the numbers that come out are arithmetic,
not predictions. ``plausibility_warnings(design, shot)`` says so, one line
per implausible input, each naming the field, its value and the limit it
passes. Every ``Shot``, from either model, carries them in ``shot.warnings``
(and ``--json`` in ``"warnings"``, empty when there is nothing to say).

The limits are deliberately far from the usual: a warning means "this is not
a trebuchet on Earth", never "this is an unusual trebuchet".
"""

from __future__ import annotations

import math

#: m/s. The strongest surface wind gust measured: 113 m/s (408 km/h), Barrow
#: Island, Australia, 10 April 1996 (World Meteorological Organization's
#: archive of weather extremes).
MAX_WIND_SPEED = 113.0
#: m/s. The speed of sound in air at 20 deg C. The drag curves
#: (``analytic.aero``) are for incompressible flow; beyond this the projectile
#: meets a shock wave they know nothing of.
SPEED_OF_SOUND = 343.0
#: Counterweight to projectile mass. The paper's design has 143 (6.5 kg :
#: 45.6 g); 10^4 is two orders of magnitude past it, where the arm and sling
#: the model takes as rigid and massless-jointed would have to carry the
#: counterweight's whole force into a projectile of next to no mass.
MAX_MASS_RATIO = 1e4
#: kg. A counterweight beyond any built: the largest working trebuchet, Warwick Castle's
#: (built 2005, rebuilt 2023), stands 18 m tall and weighs 22 t in all, counterweight, arm
#: and frame (BBC News, "New trebuchet attraction installed at Warwick Castle", 2023:
#: https://www.bbc.co.uk/news/uk-england-coventry-warwickshire-65099834); 100 t is
#: more than four times that whole machine. The model has no size limit (``analytic.design``
#: refuses only what overflows the float range), so past this its numbers are arithmetic.
MAX_COUNTERWEIGHT_MASS = 1e5
#: m. The machine's height standing, its long arm upright (``pivot_height + arm_long``):
#: from a desk-top kit's 5 cm (the smallest sold are 0.2-0.3 m tall; below a few
#: centimetres the pin's friction and the sling's stiffness, which shrink with area, rival
#: the weights, which shrink with volume, and the model has only the weights) to 50 m,
#: nearly three times Warwick Castle's 18 m, the tallest built.
HEIGHT_RANGE = (0.05, 50.0)
#: m/s^2. Gravity at the surface of the Moon (1.62) and of Jupiter's cloud
#: tops (24.8), the extremes among bodies in the solar system one speaks of
#: standing on.
GRAVITY_RANGE = (1.62, 24.8)


def plausibility_warnings(design, shot) -> tuple[str, ...]:
    """One line per input of ``design`` that makes ``shot`` implausible, in field order; () if none.

    Parameters
    ----------
    design : the ``analytic.design.Design`` that was shot.
    shot : its ``analytic.result.Shot`` (only ``release_velocity`` is read).

    Returns
    -------
    tuple of str
        Each names the field (``table.field``) or the result, its value, the
        limit and why the limit matters.
    """
    m, projectile, env = design.machine, design.projectile, design.environment
    found = []
    if projectile.mass >= m.counterweight_mass:
        found.append(f"projectile.mass = {projectile.mass:g} kg is not lighter than machine.counterweight_mass"
                     f" = {m.counterweight_mass:g} kg: a counterweight lifts a projectile many times"
                     f" lighter (143 times in the paper's design)")
    elif m.counterweight_mass / projectile.mass > MAX_MASS_RATIO:
        found.append(f"machine.counterweight_mass / projectile.mass = {m.counterweight_mass / projectile.mass:.3g}"
                     f" is beyond {MAX_MASS_RATIO:g}: no arm or sling stays rigid between such masses,"
                     f" as the model assumes")
    if m.counterweight_mass > MAX_COUNTERWEIGHT_MASS:
        found.append(f"machine.counterweight_mass = {m.counterweight_mass:g} kg is beyond"
                     f" {MAX_COUNTERWEIGHT_MASS:g} kg, more than four times the whole of the largest trebuchet"
                     f" built (Warwick Castle's, 22 t): no frame, axle or arm is known to carry it")
    found.extend(_height_warning(m))
    if abs(env.wind_speed) > MAX_WIND_SPEED:
        found.append(f"environment.wind_speed = {env.wind_speed:g} m/s is beyond the strongest wind ever"
                     f" measured ({MAX_WIND_SPEED:g} m/s)")
    low, high = GRAVITY_RANGE
    if not low <= env.gravity <= high:
        found.append(f"environment.gravity = {env.gravity:g} m/s^2 is outside {low:g}-{high:g} m/s^2,"
                     f" the Moon to Jupiter")
    if shot.release_velocity is not None:
        vx, vy = shot.release_velocity
        speed = math.hypot(vx, vy)
        if speed > SPEED_OF_SOUND:
            found.append(f"the release speed, {speed:.4g} m/s, is beyond the speed of sound"
                         f" ({SPEED_OF_SOUND:g} m/s): the drag curves hold only well below it")
    return tuple(found)


def _height_warning(machine) -> list[str]:
    """A line when the machine standing, long arm upright, is outside ``HEIGHT_RANGE``; none inside."""
    height, (low, high) = machine.pivot_height + machine.arm_long, HEIGHT_RANGE
    if height > high:
        return [f"machine.pivot_height + machine.arm_long = {height:g} m, the machine standing with its long arm"
                f" upright, is beyond {high:g} m, nearly three times the tallest trebuchet built (Warwick"
                f" Castle's, 18 m): no beam or sling that long is known to stay as rigid as the model takes"
                f" them"]
    if height < low:
        return [f"machine.pivot_height + machine.arm_long = {height:g} m, the machine standing with its long arm"
                f" upright, is below {low:g} m: at that size the pin's friction and the sling's stiffness,"
                f" which the model does not have, rival the weights that drive it"]
    return []


#: Plausible ranges of what calibration fits, file units: name -> (low, high, why). A kinetic
#: Coulomb coefficient: greased steel 0.05-0.15, dry wood on wood 0.25-0.5, rubber on
#: concrete about 1; a bearing beyond 1 grips harder than rubber on a road. A drag factor:
#: the drag crisis moves a sphere's Cd by a factor of 2-4 between balls and Reynolds
#: numbers (``analytic.aero``), so a curve right to within a factor of 2 either way.
#: A release-angle offset: a pin or hook lets go within a few degrees of its setting; 10 deg
#: is more than a 240 fps video's 6.3 deg between frames.
FITTED_RANGES = {"friction": (0.0, 1.0, "a Coulomb coefficient beyond 1 grips harder than rubber on concrete"),
                 "drag_factor": (0.5, 2.0, "a drag curve off by more than a factor of 2 is another shape of "
                                           "projectile"),
                 "release_angle_offset": (-10.0, 10.0, "a release pin lets go within a few degrees of its "
                                                       "setting")}


def fitted_value_warning(name: str, value: float) -> str | None:
    """A line when a fitted parameter ``name`` (calibration's spelling) leaves ``FITTED_RANGES``; None inside.

    The line names the parameter, its value, the range and what a value outside it
    probably means: a loss the model lacks (a headwind, a grade, a stretching sling)
    charged to this parameter, or measurement uncertainties stated too small.
    """
    key = "friction" if name.endswith("_friction") else name
    if key not in FITTED_RANGES:
        return None
    low, high, why = FITTED_RANGES[key]
    if low <= value <= high:
        return None
    return (f"{name} = {value:.3g} is outside its plausible range {low:g} to {high:g} ({why}): probably the "
            f"shots lose (or gain) range to something the model does not have, a headwind, a slope, a "
            f"stretching sling or a slipping hook, and the fit charges it all to {name}; predictions near the "
            f"measured settings can still hold, but do not read the value as {name} itself")
