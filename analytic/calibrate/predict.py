"""Predicted ranges at new settings of one design field, with the fit's uncertainty carried to them.

``calibrate ... --predict FIELD=VALUE[,VALUE...]`` shoots the calibration's
base design (its first shot's: the shot's design with its own settings) with
FIELD at each VALUE and the parameters at their fitted values, on the
fast path as the fit does. Each range's standard deviation comes from
the fit's covariance C by the delta method: ``range_sd = sqrt(g^T C g)``,
with g the range's gradient in the parameters, central differences at the
fit's own finite-difference steps (``analytic.calibrate.fit.STEP`` of each
parameter's scale). It is linear error propagation: good while the range is
close to linear in the parameters over one standard deviation, which the
plot's band lets one judge by eye.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic.calibrate.fit import STEP, Calibration, predict
from analytic.calibrate.spec import CalibrationSpec, ShotSpec, with_fields
from analytic.design import DesignError
from analytic.fields import Field, field
from analytic.units import ANGLE, parse

#: Points of the fitted curve in the calibration plot.
CURVE_POINTS = 21


@dataclass(frozen=True)
class RangePrediction:
    """The predicted range at one setting.

    Attributes
    ----------
    field : the design field varied (``machine.counterweight_mass``).
    value : its setting, file units (deg for angles).
    range, range_sd : m, None where the shot does not throw there.
    message : the shot's status and message where it does not throw, else "".
    """

    field: str
    value: float
    range: float | None
    range_sd: float | None
    message: str = ""

    def to_json(self) -> dict:
        """``{"field", "value", "range", "range_sd"}``, SI (the value in radians for an angle)."""
        value = math.radians(self.value) if field(self.field).kind is ANGLE else self.value
        return {"field": self.field, "value": value, "range": self.range, "range_sd": self.range_sd}


def parse_predict(text: str) -> tuple[Field, tuple[float, ...]]:
    """``FIELD=VALUE[,VALUE...]`` as the command line gives it: the field and its values (file units).

    Values are bare numbers in the field's file unit or texts with units (``2.5 kg``).

    Raises
    ------
    DesignError
        naming ``--predict``, the text and the reason.
    """
    name, equals, values = text.partition("=")
    if not equals or not name.strip() or not values.strip():
        raise DesignError("--predict", text, "expected FIELD=VALUE[,VALUE...], e.g. "
                                             "machine.counterweight_mass=5,6.5,8")
    try:
        target = field(name.strip())
    except DesignError as error:
        raise DesignError("--predict", text, error.reason) from None
    parsed = []
    for item in values.split(","):
        item = item.strip()
        try:
            parsed.append(float(item))
        except ValueError:
            parsed.append(float(parse("--predict", item, target.kind)))
        if not math.isfinite(parsed[-1]):
            raise DesignError("--predict", text, f"{item!r} is not a finite number")
    return target, tuple(parsed)


def check_settings(spec: CalibrationSpec, target: Field, values) -> None:
    """Refuse, before the fit, a setting at which the base design cannot be built.

    Raises
    ------
    DesignError
        naming ``--predict``, the field, the value and the design's reason.
    """
    for value in values:
        try:
            spec.design_at(_at_setting(spec, target, value), [p.start for p in spec.parameters])
        except DesignError as error:
            raise DesignError("--predict", f"{target.name}={value:g}", str(error)) from None


def _at_setting(spec: CalibrationSpec, target: Field, value: float) -> ShotSpec:
    """The base shot (the first) with ``target`` set to ``value``."""
    from dataclasses import replace

    base = spec.shots[0]
    return replace(base, design=with_fields(base.design, {target.name: value}), measurements=(), track=None)


def range_with_sd(result: Calibration, target: Field, value: float) -> RangePrediction:
    """The range at one setting and its delta-method standard deviation (module docstring)."""
    spec = result.spec
    shot = _at_setting(spec, target, value)
    centre = predict(spec, shot, result.values)
    if not centre.ok:
        return RangePrediction(target.name, value, None, None, f"{centre.status}: {centre.message}")
    gradient = []
    for j, parameter in enumerate(spec.parameters):
        step = STEP * parameter.scale
        probes = []
        for sign in (+1.0, -1.0):
            x = np.array(result.values, dtype=float)
            x[j] += sign * step
            probes.append(predict(spec, shot, x).values["range"])
        if None in probes:   # a side does not throw: one-sided from the centre
            up, down = probes
            gradient.append((up - centre.values["range"]) / step if up is not None
                            else (centre.values["range"] - down) / step if down is not None else math.nan)
        else:
            gradient.append((probes[0] - probes[1]) / (2.0 * step))
    g = np.array(gradient)
    variance = float(g @ result.covariance @ g)
    sd = math.sqrt(variance) if math.isfinite(variance) and variance >= 0.0 else None
    return RangePrediction(target.name, value, float(centre.values["range"]), sd)


def predict_ranges(result: Calibration, target: Field, values) -> tuple[RangePrediction, ...]:
    """``range_with_sd`` at each of ``values`` (file units), in order."""
    return tuple(range_with_sd(result, target, float(v)) for v in values)


def varied_field(spec: CalibrationSpec) -> Field | None:
    """The one design field the shots set to different values (the plot's x axis), or None."""
    names = {name for shot in spec.shots for name in shot.settings}
    varied = [name for name in sorted(names)
              if len({shot.settings.get(name) for shot in spec.shots}) > 1]
    return field(varied[0]) if len(varied) == 1 else None


def fitted_curve(result: Calibration, target: Field, extra=()) -> tuple[RangePrediction, ...]:
    """``CURVE_POINTS`` predictions across the shots' settings of ``target`` and ``extra`` ones."""
    settings = [target.get(shot.design) for shot in result.spec.shots] + list(extra)
    low, high = min(settings), max(settings)
    pad = 0.08 * (high - low) or 0.1 * abs(high) or 1.0
    return predict_ranges(result, target, np.linspace(low - pad, high + pad, CURVE_POINTS))
