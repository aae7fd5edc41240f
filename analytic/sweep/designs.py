"""A chunk's designs as the compiled kernel's rows, built column by column without ``Design`` objects.

Building and validating one ``Design`` per row costs about as much as
shooting it, so the rows are assembled as columns: the base design's row,
tiled, with each varied field's column written in, and the quantities derived
from several fields (the paper's and the beam's forms, drag area, time
limit, angles at rest) recomputed wherever one of their inputs varies: with
the model's own scalar functions per row, or its arithmetic element-wise
where IEEE operations round alike (never numpy's own transcendental
functions or powers, which may round differently in the last bit). Every row is equal, bit for
bit, to ``analytic.fast.pack`` of the design the design file would give
(a test holds it to that), and every design is valid: the sweep built its
box's corners before it started (``analytic.sweep.spec``).
"""

from __future__ import annotations

import math

import numpy as np

from analytic.design import FRICTIONS, BeamArm, largest_length
from analytic.design_file import design_from_dict
from analytic.limits import swing_time_limit
from analytic.parameters import Params, params
from analytic.sweep.spec import ANGLE_FIELDS, Base, design_data

#: Design-file fields copied into one ``Params`` field each (``analytic.parameters``' table).
PARAM_OF_FIELD = {
    "machine.arm_long": "La", "machine.arm_short": "Lb", "machine.arm_cg": "d", "machine.arm_mass": "mA",
    "machine.arm_inertia": "IA", "machine.counterweight_mass": "mW", "machine.counterweight_link": "Lw",
    "machine.counterweight_inertia": "IW", "machine.sling_length": "Ls", "projectile.mass": "mP",
    "machine.pivot_height": "h", "environment.gravity": "g", "machine.release_angle": "alpha",
    "projectile.drag_coefficient": "cd", "projectile.diameter": "diameter",
    "environment.air_density": "rho", "environment.air_viscosity": "mu", "environment.wind_speed": "wind",
    "losses.axle_friction": "mua", "losses.axle_radius": "ra", "losses.hinge_friction": "muh",
    "losses.hinge_radius": "rh", "losses.base_friction": "mub", "losses.guide_friction": "mug",
    "losses.track_friction": "mut", "base.trough_height": "ht", "environment.target_height": "yt",
    "machine.sling_mass": "mS", "machine.pouch_mass": "mQ",
}
_COLUMN = {name: i for i, name in enumerate(Params._fields)}
_PAPER_INPUTS = ("machine.arm_short", "machine.counterweight_link", "machine.clearance", "machine.starting_angle")
_BEAM = "machine.arm_beam"
_BEAM_INPUTS = ("machine.arm_long", "machine.arm_short", f"{_BEAM}.width", f"{_BEAM}.depth", f"{_BEAM}.density")
_TIME_LIMIT_INPUTS = ("machine.arm_long", "machine.sling_length", "machine.arm_short",
                      "machine.counterweight_link", "environment.gravity")


class _Machine:
    """The attributes of a machine that ``largest_length`` reads, as columns."""

    def __init__(self, values: dict):
        for field in ("arm_long", "sling_length", "arm_short", "counterweight_link"):
            setattr(self, field, values[f"machine.{field}"])


def base_row(base: Base, values: dict[str, float]) -> tuple[np.ndarray, dict[str, float]]:
    """The kernel row (N_PARAMS,) and every field's SI value of the base with ``values`` written in.

    A problem's base has no values for its free variables; any design in its
    box serves, since the sweep overwrites every column they reach.
    """
    design = design_from_dict(design_data(base, values))
    si = {field: math.radians(v) if field in ANGLE_FIELDS else v for field, v in base.values.items()}
    si.update({field: math.radians(v) if field in ANGLE_FIELDS else v for field, v in values.items()})
    m = design.machine
    for name in ("pivot_height", "arm_long", "arm_mass", "arm_cg", "arm_inertia"):
        si[f"machine.{name}"] = getattr(m, name)
    si["projectile.drag_factor"] = design.projectile.drag_factor
    return np.array(params(design), dtype=np.float64), si


def kernel_rows(base: Base, columns: dict[str, np.ndarray]) -> np.ndarray:
    """The kernel rows (m, N_PARAMS) of the base design with each varied field's column written in.

    Parameters
    ----------
    base : the sweep's base (a design or a problem).
    columns : field -> (m,) values in file units (degrees for angles); every
        free variable of a problem must be among them.
    """
    size = len(next(iter(columns.values())))
    anchor = {field: float(column[0]) for field, column in columns.items()}
    row, si = base_row(base, anchor)
    values: dict = dict(si)
    for field, column in columns.items():
        values[field] = np.radians(column) if field in ANGLE_FIELDS else np.asarray(column, dtype=np.float64)
    varied = set(columns)
    machine = base.data["machine"]
    # The design's form: from its file, or from the fields the sweep writes into it.
    paper_form = "clearance" in machine or "machine.clearance" in varied
    beam_form = "arm_beam" in machine or bool(varied & set(_BEAM_INPUTS[2:]))

    def per_row(function, *fields):
        """``function`` of each row's scalar values of ``fields``, as a list."""
        return [function(*args) for args in zip(*(np.broadcast_to(values[f], (size,)) for f in fields))]

    if paper_form and varied & set(_PAPER_INPUTS):
        # ``paper_geometry``'s arithmetic, in its order, without its per-value checks (the
        # corners were built); element-wise IEEE operations round as the scalar ones do.
        arm_short, link, clearance, angle = (np.broadcast_to(values[f], (size,)) for f in _PAPER_INPUTS)
        pivot_height = arm_short + link + clearance
        values["machine.pivot_height"] = pivot_height
        values["machine.arm_long"] = pivot_height / np.array([math.sin(a) for a in angle])
        varied |= {"machine.pivot_height", "machine.arm_long"}
    if beam_form and varied & set(_BEAM_INPUTS):
        if varied & {f"{_BEAM}.width", f"{_BEAM}.depth", f"{_BEAM}.density"}:
            arm = per_row(lambda la, lb, w, d, rho: BeamArm(w, d, rho).properties(la, lb), *_BEAM_INPUTS)
        else:
            beam = BeamArm(**machine["arm_beam"])
            arm = per_row(beam.properties, "machine.arm_long", "machine.arm_short")
        arm = np.array(arm)
        values["machine.arm_mass"], values["machine.arm_cg"], values["machine.arm_inertia"] = arm.T
        varied |= {"machine.arm_mass", "machine.arm_cg", "machine.arm_inertia"}

    rows = np.tile(row, (size, 1))
    for field in varied & set(PARAM_OF_FIELD):
        rows[:, _COLUMN[PARAM_OF_FIELD[field]]] = values[field]
    for friction in FRICTIONS:
        # ``Losses.static``: a static coefficient the design does not give is its kinetic one.
        kinetic = f"losses.{friction}_friction"
        if kinetic in varied and f"losses.{friction}_static_friction" not in base.values:
            rows[:, _COLUMN[PARAM_OF_FIELD[kinetic] + "_s"]] = values[kinetic]
    if varied & {"projectile.diameter", "projectile.drag_factor"}:
        # ``Projectile.drag_area``: the frontal area, then times the drag factor.
        rows[:, _COLUMN["area"]] = per_row(lambda d, factor: math.pi * d**2 / 4.0 * factor,
                                           "projectile.diameter", "projectile.drag_factor")
    if varied & set(_TIME_LIMIT_INPUTS):
        lengths = largest_length(_Machine({f: np.broadcast_to(values[f], (size,)) for f in values
                                           if f.startswith("machine.")}))
        rows[:, _COLUMN["t_limit"]] = [swing_time_limit(length, g) for length, g in
                                       zip(lengths, np.broadcast_to(values["environment.gravity"], (size,)))]
    if varied & {"machine.pivot_height", "machine.arm_long", "base.trough_height"}:
        # ``initial_angles``: the arm at rest, its tip on the trough (0: the base); the counterweight plumb.
        ratio = -(np.broadcast_to(values["machine.pivot_height"], (size,))
                  - values.get("base.trough_height", 0.0)) / values["machine.arm_long"]
        theta = np.array([math.acos(r) for r in ratio])
        rows[:, _COLUMN["theta0"]], rows[:, _COLUMN["phi0"]] = theta, -theta
    return rows
