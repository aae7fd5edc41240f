"""The firing table: for each target and projectile mass, every setting of one field that lands on the target.

One scan of the field's bounds per projectile mass (``analytic.aim.scan``, one
fast batch), then ``analytic.aim.aim`` at each target from that scan: every
crossing of the target bracketed on the scan's grid, located on the fast path
and confirmed on the reference path within ``analytic.aim.AIM_TOLERANCE``. A
target no setting reaches is out of reach, never a guess.

With a calibration (``analytic.calibrate``), the design is shot at the fitted
parameters (the calibration's ``[given]`` fields too), and each setting carries
the band its fit gives: the range's standard deviation there is
``sqrt(g^T C g + s^2)``, the fit's own spread carried to the setting by the
delta method (``analytic.calibrate.predict.range_with_sd``) and the scatter of
one shot about it, ``s``, taken as the calibration's stated range uncertainty
(the root mean square of its shots', as the fit itself takes them as true).
So the band says where the next shot at that setting lands: one standard
deviation (68 %) and two (95 %).

Settings are in design-file units here (SI, angles in degrees), as
``analytic.aim`` gives them; ``FiringTable.to_json`` gives them in the units
``analytic.Design`` holds (angles in radians).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from analytic.aim import SCAN_POINTS, aim, default_bounds, scan
from analytic.design import Design, DesignError
from analytic.fields import Field, field
from analytic.units import ANGLE

#: The field the projectile's mass is set through.
MASS_FIELD = "projectile.mass"


@dataclass(frozen=True)
class Fitted:
    """A calibration as the table uses it.

    Attributes
    ----------
    result : the ``analytic.calibrate.Calibration``.
    shots : measured shots the fit rests on; measurements : measured quantities in them.
    shot_sd : m, the scatter of one shot's range about the model (the stated range
        uncertainties' root mean square).
    offset : deg, the fitted ``release_angle_offset`` (0 without one): the pin a builder sets
        is the release angle less it.
    """

    result: object
    shots: int
    measurements: int
    shot_sd: float
    offset: float

    @property
    def spec(self):
        return self.result.spec


@dataclass(frozen=True)
class Entry:
    """One target at one projectile mass.

    Attributes
    ----------
    target : m; projectile_mass : kg.
    settings : every setting that lands on the target, increasing, file units (empty: out of reach).
    landed : the reference path's range at each, m.
    metres_per_unit : d range / d setting at each, m per file unit.
    range_sd : one standard deviation of the range at each, m (fit and one shot's scatter),
        None without a calibration; fit_sd : the fit's part alone.
    predicted : the calibrated fast path's range at each, m (the band's centre), None without one.
    """

    target: float
    projectile_mass: float
    settings: tuple[float, ...]
    landed: tuple[float, ...]
    metres_per_unit: tuple[float, ...]
    range_sd: tuple[float, ...] | None = None
    fit_sd: tuple[float, ...] | None = None
    predicted: tuple[float, ...] | None = None

    @property
    def status(self) -> str:
        return "ok" if self.settings else "out_of_reach"

    def bands(self, sigmas: float) -> list[tuple[float, float]] | None:
        """Each setting's band of ``sigmas`` standard deviations about its predicted range, m."""
        if self.range_sd is None or not self.settings:
            return None
        return [(c - sigmas * sd, c + sigmas * sd) for c, sd in zip(self.predicted, self.range_sd, strict=True)]

    def band(self) -> list[list[float]] | None:
        """``[[lo1, hi1], [lo2, hi2]]``: one and two standard deviations, m, the widest of the
        entry's settings' (so that it holds whichever setting is used); None without one."""
        out = []
        for sigmas in (1.0, 2.0):
            bands = self.bands(sigmas)
            if bands is None:
                return None
            out.append([min(lo for lo, _ in bands), max(hi for _, hi in bands)])
        return out if all(math.isfinite(v) for pair in out for v in pair) else None


@dataclass(frozen=True)
class FiringTable:
    """A firing table.

    Attributes
    ----------
    design : the design as given (before any calibration).
    field : the field adjusted.
    targets : (T,) m; masses : (M,) kg.
    entries : (M * T) entries, mass by mass, targets increasing within each.
    bounds : (2,) the settings searched, file units (the release angle as it releases: with a
        calibrated offset, the pin set is the release less it).
    reachable : one per mass, (lowest, highest) range over the bounds, m, or None if nothing throws.
    fitted : the calibration, or None.
    """

    design: Design
    field: Field
    targets: np.ndarray
    masses: np.ndarray
    entries: tuple[Entry, ...]
    bounds: tuple[float, float]
    reachable: tuple[tuple[float, float] | None, ...]
    fitted: Fitted | None = None

    @property
    def design_unit(self) -> str:
        """The unit ``analytic.Design`` holds the field in (the JSON's settings)."""
        return "rad" if self.field.kind is ANGLE else self.field.kind.file_unit

    def to_design_units(self, value: float) -> float:
        return math.radians(value) if self.field.kind is ANGLE else float(value)

    def to_json(self, system: str = "metric") -> dict:
        """``{"rows": [...], "units": {...}, "calibration": ...}``: SI, settings as ``analytic.Design``
        holds them (angles in radians), whatever ``system`` the text was shown in."""
        rows = [{"target": e.target, "projectile_mass": e.projectile_mass, "field": self.field.name,
                 "settings": [self.to_design_units(v) for v in e.settings], "status": e.status, "band": e.band()}
                for e in self.entries]
        fitted = None if self.fitted is None else {
            "file": str(self.fitted.spec.path), "shots": self.fitted.shots,
            "measurements": self.fitted.measurements, "shot_sd": self.fitted.shot_sd,
            "parameters": {p.name: {"value": float(v), "uncertainty": float(u)} for p, v, u in
                           zip(self.fitted.spec.parameters, self.fitted.result.values,
                               self.fitted.result.uncertainties, strict=True)}}
        return {"rows": rows, "units": {"target": "m", "projectile_mass": "kg", "settings": self.design_unit,
                                        "band": "m", "shown": system},
                "calibration": fitted}


def steps_of(name: str, start: float, stop: float, steps: int, *, written: str | None = None) -> np.ndarray:
    """``steps`` values from ``start`` to ``stop``, all positive: ``DesignError`` naming ``name`` and
    the values as ``written`` for a count below 1, an inverted or (with several steps) empty range,
    one step over a range, or a value not above 0."""
    text = written if written is not None else f"{start:g}:{stop:g}:{steps}"
    if isinstance(steps, bool) or not isinstance(steps, int) or steps < 1:
        raise DesignError(name, text, "STEPS must be a whole number of at least 1")
    if not (math.isfinite(start) and math.isfinite(stop)):
        raise DesignError(name, text, "FROM and TO must be finite")
    if start > stop:
        raise DesignError(name, text, "FROM is above TO: give them in increasing order")
    if steps == 1 and start != stop:
        raise DesignError(name, text, "one step needs FROM = TO (or give more steps)")
    if steps > 1 and start == stop:
        raise DesignError(name, text, "FROM = TO: give one step, or a range")
    if not start > 0.0:
        raise DesignError(name, text, "FROM must be positive")
    return np.linspace(start, stop, steps)


def fitted_from(result) -> Fitted:
    """``Fitted`` of a ``Calibration``."""
    from analytic.calibrate.spec import RELEASE_ANGLE_OFFSET

    spec = result.spec
    sds = [m.uncertainty for shot in spec.shots for m in shot.measurements if m.quantity == "range"]
    offset = sum(float(v) for p, v in zip(spec.parameters, result.values, strict=True)
                 if p.name == RELEASE_ANGLE_OFFSET)
    return Fitted(result, len(spec.shots), spec.measurements, math.sqrt(float(np.mean(np.square(sds)))), offset)


def check_calibration(spec, target_field: Field, masses_given: bool) -> None:
    """Refuse an adjusted field (or a projectile mass) that the calibration (an
    ``analytic.calibrate.CalibrationSpec``) fits or sets: the table would set it and the
    calibration overwrite it."""
    fixed = {p.field.name for p in spec.parameters if p.field is not None} | set(spec.given)
    fixed = {field(name).name for name in fixed}
    if target_field.name in fixed:
        raise DesignError("--adjust", target_field.name, f"the calibration {spec.path.name} fits or sets it "
                                                         f"([given]); adjust another field")
    if masses_given and MASS_FIELD in fixed:
        raise DesignError("--projectile-mass", MASS_FIELD, f"the calibration {spec.path.name} fits or sets it")


def check_choices(target_field: Field, masses_given: bool, spec=None) -> None:
    """Refuse masses given while the table adjusts the mass, and fields a calibration ``spec`` holds."""
    if masses_given and target_field.name == MASS_FIELD:
        raise DesignError("--projectile-mass", "given", f"the table adjusts {MASS_FIELD} itself (--adjust); "
                                                        f"leave --projectile-mass out")
    if spec is not None:
        check_calibration(spec, target_field, masses_given)


def design_at_mass(design: Design, mass: float | None, fitted: Fitted | None) -> tuple[Design, Design]:
    """``(design, shot)``: the design with its projectile's ``mass`` (kg, None: its own), and the same at
    the fitted parameters (the design itself without a calibration)."""
    if mass is not None:
        design = field(MASS_FIELD).replace(design, float(mass))
    if fitted is None:
        return design, design
    shot = _shot_spec(fitted, design)
    return design, fitted.spec.design_at(shot, fitted.result.values)


def _shot_spec(fitted: Fitted, design: Design):
    from analytic.calibrate.spec import ShotSpec

    return ShotSpec(0, design.name, design, ())


def check_inputs(design: Design, target_field: Field, masses, fitted: Fitted | None) -> tuple[float, float]:
    """Build every design the table shoots (each mass, at the fitted parameters); ``DesignError``
    naming the mass otherwise. The bounds to search, file units."""
    target_field.check(design)
    for mass in masses:
        try:
            built, shot = design_at_mass(design, mass, fitted)
        except DesignError as error:
            if mass is None:
                raise
            raise DesignError("--projectile-mass", f"{mass:g} kg", f"the design cannot be built: {error}") from None
        target_field.check(shot)
    return default_bounds(target_field, design_at_mass(design, None, fitted)[1])


def firing_table(design: Design, field_name: str, targets, masses=None, *, calibration=None,
                 points: int = SCAN_POINTS, progress: bool = False,
                 check: Callable[[], None] | None = None) -> FiringTable:
    """The settings of ``field_name`` that land on each target, at each projectile mass.

    Parameters
    ----------
    design : the design; every other field keeps its value.
    field_name : a numeric design field (``analytic.fields.field``), not ``projectile.mass`` when
        ``masses`` are given.
    targets : (T,) m, > 0.
    masses : (M,) kg, > 0; default the design's own projectile.
    calibration : an ``analytic.calibrate.Calibration`` to shoot at and take bands from, or None.
    points : settings scanned over the bounds (``analytic.aim.SCAN_POINTS``).
    progress : a progress bar on stderr, an entry a step.
    check : called before every shot after each scan (``analytic.aim.aim``); what it raises ends
        the table there and is raised again.

    Returns
    -------
    FiringTable

    Raises
    ------
    DesignError
        naming the bad input (field, target, mass, a field the calibration fits) before any shot.
    """
    from analytic.aim import check_inputs as check_aim
    from analytic.cli_shared import progress_bar

    target_field = field(field_name)
    targets = np.asarray(targets, dtype=float)
    given_masses = masses is not None
    masses = np.asarray([design.projectile.mass] if masses is None else masses, dtype=float)
    check_choices(target_field, given_masses, None if calibration is None else calibration.spec)
    fitted = None if calibration is None else fitted_from(calibration)
    bounds = check_inputs(design, target_field, masses, fitted)
    for target in targets:
        check_aim(float(target), bounds, None)
    entries, reachable = [], []
    bar = progress_bar(total=len(masses) * len(targets), desc="firing table", unit=" entries",
                       disable=not progress, leave=False)
    try:
        for mass in masses:
            base, shot_design = design_at_mass(design, mass if given_masses else None, fitted)
            values = np.linspace(bounds[0], bounds[1], points)
            ranges, status = scan(shot_design, target_field, values)
            span = None
            for target in targets:
                found = aim(shot_design, target_field.name, float(target), bounds=bounds, points=points,
                            scanned=(values, ranges, status), check=check)
                span = found.reachable
                entries.append(_entry(found, float(mass), base, target_field, fitted))
                bar.update(1)
            reachable.append(span)
    finally:
        bar.close()
    return FiringTable(design, target_field, targets, masses, tuple(entries), bounds, tuple(reachable), fitted)


def _entry(found, mass: float, base: Design, target_field: Field, fitted: Fitted | None) -> Entry:
    """An ``Entry`` of one aim: settings as a builder sets them, and with a calibration their bands."""
    offset = fitted.offset if fitted is not None and target_field.name == "machine.release_angle" else 0.0
    settings = tuple(s.value - offset for s in found.solutions)
    entry = Entry(found.target, mass, settings, tuple(s.range for s in found.solutions),
                  tuple(s.metres_per_unit for s in found.solutions))
    if fitted is None or not settings:
        return entry
    from analytic.calibrate.predict import range_with_sd

    # The calibration's prediction machinery, its one shot this entry's design.
    result = dataclasses.replace(fitted.result, spec=dataclasses.replace(
        fitted.spec, shots=(_shot_spec(fitted, base),)))
    predicted, fit_sd = [], []
    for value in settings:
        prediction = range_with_sd(result, target_field, value)
        predicted.append(math.nan if prediction.range is None else prediction.range)
        fit_sd.append(math.nan if prediction.range_sd is None else prediction.range_sd)
    total = tuple(math.hypot(sd, fitted.shot_sd) for sd in fit_sd)
    return dataclasses.replace(entry, range_sd=total, fit_sd=tuple(fit_sd), predicted=tuple(predicted))
