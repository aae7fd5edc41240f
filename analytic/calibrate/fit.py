"""The fit: weighted least squares of the model's predictions against measured shots.

Residuals are ``(predicted - measured) / uncertainty`` over every measured
quantity of every shot, minimised by ``scipy.optimize.least_squares``
(dogbox: a trust region within the box of the bounds). Shots are the
compiled fast path's (``analytic.fast.simulate_fast`` at the default
tolerances, no peak loads): the reference path's numbers to the integrator's
error, hundreds of times sooner, which a fit of hundreds of shots feels.

The Jacobian is our own finite difference, with steps chosen against the
integrator's noise (``STEP``), central inside the bounds and one-sided
(second order) near one; it is also the Jacobian the uncertainties come from.
The covariance is ``(J^T J)^-1`` of the weighted residuals, NOT scaled by the
reduced chi-square: the stated uncertainties are taken as true, so that a
single shot fitting a single parameter (no degrees of freedom left) still has
an uncertainty, the one its measurement's uncertainty carries. The chi-square
and its degrees of freedom are reported so that a user who doubts their
uncertainties can judge, or scale by ``sqrt(chi2 / dof)`` themselves.
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass

import numpy as np

from analytic.calibrate.spec import QUANTITIES, CalibrationSpec, ShotSpec
from analytic.calibrate.track import TrackPrediction
from analytic.design import DesignError

#: Finite-difference step, as a fraction of each parameter's scale. Measured on the
#: prototype's design at the default tolerances: the range's integrator noise is
#: 1.6e-11 m on the fast path, 1.8e-11 m on the reference (standard deviation about a
#: quadratic through 21 shots over +-1e-6 kg of counterweight), 4.2e-9 and 2.2e-9 m with
#: axle friction 0.15 and base friction 0.3 (stick and slip events); central differences of the range in the
#: counterweight, the air density and the release angle at steps of 1e-4 and 1e-3 of
#: their values agree to 3e-5 (truncation), while at 1e-8 noise moves them by 3e-5 and
#: at 1e-10 by 1 %. A step of 1e-4 moves the range by ~1e-3 m, 10^7 times the noise.
STEP = 1e-4
#: Weighted residual of a quantity a shot did not reach (it did not throw, or its design
#: cannot be built at the trial parameters): far beyond any real misfit, so the trust
#: region rejects the step and shrinks, and finite, so its arithmetic holds.
FAILURE_RESIDUAL = 1e6
#: Singular values of the scaled Jacobian below this fraction of the largest are taken as
#: zero: the finite differences are good to ~3e-5 (``STEP``), so a direction this weak is
#: noise, a combination of parameters the data cannot fix.
SINGULAR_RATIO = 1e-6
#: A fitted value closer than this (fraction of its scale) to a bound is "at the bound".
AT_BOUND = 1e-6
#: One-sided slopes of a measurement that differ by more than this fraction of the larger
#: mean a jump between the probes, not a slope: smooth ones differ by ~``STEP`` relative.
JUMP_RATIO = 0.1
#: A weighted residual beyond this many standard deviations at the fit is reported (a
#: measurement the model cannot meet within the bounds, or an uncertainty stated too small).
MISFIT = 3.0
#: Most residual evaluations (each shoots every shot once).
MAX_EVALUATIONS = 200
#: The fit's stopping tolerances (``least_squares``' ftol, xtol, gtol): relative changes of
#: 1e-8 in the parameters or the chi-square are far below any a measurement can see (a
#: parameter's uncertainty is rarely under 1e-4 of it) and far above the integrator's noise.
TOLERANCE = 1e-8
#: Two fitted parameters whose correlation passes this (in size) are reported: the data fix
#: mostly one combination of them, and each alone is known far less well than the pair.
HIGH_CORRELATION = 0.9


class CalibrationError(RuntimeError):
    """A fit that cannot proceed: a shot that does not throw where the fit must shoot it."""


@dataclass(frozen=True)
class Prediction:
    """One shot at one set of parameters.

    Attributes
    ----------
    status : the shot's status (``Status`` value), or ``design_error`` if its design
        cannot be built there.
    message : the shot's message (or the design's error).
    values : quantity -> predicted value, file units (None where the shot did not reach it).
    track : the model against the shot's track (``analytic.calibrate.track``), None without one
        or where the shot has no motion to follow.
    """

    status: str
    message: str
    values: dict[str, float | None]
    track: TrackPrediction | None = None

    @property
    def ok(self) -> bool:
        return self.status == "ok"


def predict(spec: CalibrationSpec, shot: ShotSpec, values) -> Prediction:
    """Shoot ``shot``'s design with the parameters at ``values`` (fast path, no peak loads); with a
    track, its sampled motion too (the same shot's numbers) against the track."""
    from analytic.fast import simulate_fast

    try:
        design = spec.design_at(shot, values)
    except DesignError as error:
        return Prediction("design_error", str(error), dict.fromkeys(QUANTITIES))
    path = None
    if shot.track is None:
        result = simulate_fast(design, loads=False)
    else:
        from analytic.calibrate.track import model_path

        result, path = model_path(design, shot.track.point)
    angle = result.launch_angle
    predicted = {"range": result.range, "release_time": result.release_time,
                 "liftoff_time": result.liftoff_time,
                 "release_angle": None if angle is None else math.degrees(angle)}
    if path is None:
        return Prediction(result.status.value, result.message, predicted)
    from analytic.calibrate.track import predict_track

    return Prediction(result.status.value, result.message, predicted, predict_track(shot.track, design, path))


def weighted_residuals(shot: ShotSpec, prediction: Prediction) -> np.ndarray:
    """(len(shot.measurements) + 2 n,) ``(predicted - measured) / uncertainty``, ``FAILURE_RESIDUAL``
    where the shot did not reach a quantity: each quantity, then x and y of each of the track's
    n points in turn."""
    out = []
    for m in shot.measurements:
        value = prediction.values[m.quantity] if prediction.ok else None
        out.append(FAILURE_RESIDUAL if value is None else (value - m.value) / m.uncertainty)
    if shot.track is None:
        return np.array(out)
    if prediction.ok and prediction.track is not None:
        return np.concatenate([out, prediction.track.residuals(shot.track)])
    return np.concatenate([out, np.full(2 * shot.track.points, FAILURE_RESIDUAL)])


@dataclass(frozen=True)
class Calibration:
    """The result of ``calibrate``.

    Attributes
    ----------
    spec : the calibration file, checked.
    values : (P,) fitted parameters, file units, in ``spec.parameters``' order.
    uncertainties : (P,) one standard deviation each (``sqrt`` of the covariance's
        diagonal), NaN for a parameter the data cannot fix.
    covariance : (P, P), NaN rows and columns for parameters the data cannot fix.
    start : (P,) where the fit started.
    fitted : one ``Prediction`` per shot at ``values``; initial : the same at ``start``.
    residuals : (M,) weighted residuals at ``values``, M = every measurement, shot by shot.
    chi_square : the sum of their squares; degrees_of_freedom : M - P.
    at_bound : (P,) which parameters ended on one of their bounds.
    singular : (P,) which parameters the data cannot fix (the Jacobian's null space).
    warnings : one line each, for the report.
    evaluations : residual evaluations (each shoots every shot); shots : shots simulated;
        failed_shots : those of them that did not throw (or could not be built) on the way.
    message : ``least_squares``' own; converged : its success flag; seconds : wall time.
    time_origin_sd : one standard deviation of each shot's fitted time origin, s (None for a
        shot without a track, NaN where a parameter the data cannot fix leaves it undefined):
        the spread at fixed parameters and the parameters' own carried through, as if the
        origin were fitted beside them.
    """

    spec: CalibrationSpec
    values: np.ndarray
    uncertainties: np.ndarray
    covariance: np.ndarray
    start: np.ndarray
    fitted: tuple[Prediction, ...]
    initial: tuple[Prediction, ...]
    residuals: np.ndarray
    chi_square: float
    degrees_of_freedom: int
    at_bound: np.ndarray
    singular: np.ndarray
    warnings: tuple[str, ...]
    evaluations: int
    shots: int
    failed_shots: int
    message: str
    converged: bool
    seconds: float
    time_origin_sd: tuple[float | None, ...] = ()

    @property
    def reduced_chi_square(self) -> float | None:
        """chi2 / dof, None without degrees of freedom (as many measurements as parameters)."""
        return self.chi_square / self.degrees_of_freedom if self.degrees_of_freedom > 0 else None

    @property
    def p_value(self) -> float | None:
        """The probability of a chi-square at least this large if the model and the stated
        uncertainties were right (None without degrees of freedom)."""
        from scipy.stats import chi2 as chi2_distribution

        if self.degrees_of_freedom <= 0:
            return None
        return float(chi2_distribution.sf(self.chi_square, self.degrees_of_freedom))

    @property
    def correlation(self) -> np.ndarray:
        """(P, P) the covariance as correlations (NaN where a parameter is not fixed)."""
        sd = np.sqrt(np.diag(self.covariance))
        with np.errstate(invalid="ignore", divide="ignore"):
            return self.covariance / np.outer(sd, sd)


class _Model:
    """Residuals and their Jacobian at any parameters, each set of parameters shot once."""

    def __init__(self, spec: CalibrationSpec, progress: bool):
        from analytic.cli_shared import progress_bar

        self.spec = spec
        self.cache: dict[bytes, tuple[np.ndarray, tuple[Prediction, ...]]] = {}
        self.shots = 0
        self.failed_shots = 0
        self.bar = progress_bar(desc="calibrate", unit=" shots", file=sys.stderr, disable=not progress, leave=False)
        p = spec.parameters
        self.lower = np.array([q.lower for q in p])
        self.upper = np.array([q.upper for q in p])
        self.steps = STEP * np.array([q.scale for q in p])
        #: parameter index -> the measurements (indices into the residuals) that jumped between
        #: its probes at the last Jacobian.
        self.jumps: dict[int, np.ndarray] = {}
        #: which residuals are measured quantities (True) rather than a track's points: a point that
        #: barely moves with a parameter has one-sided slopes of the integrator's noise, no jump.
        self.quantity_rows = np.concatenate([[True] * len(shot.measurements)
                                             + [False] * (2 * shot.track.points if shot.track else 0)
                                             for shot in spec.shots]).astype(bool)

    def evaluate(self, x: np.ndarray) -> tuple[np.ndarray, tuple[Prediction, ...]]:
        key = np.asarray(x, dtype=float).tobytes()
        if key not in self.cache:
            predictions = tuple(predict(self.spec, shot, x) for shot in self.spec.shots)
            residuals = np.concatenate([weighted_residuals(shot, prediction)
                                        for shot, prediction in zip(self.spec.shots, predictions, strict=True)])
            self.cache[key] = residuals, predictions
            self.shots += len(predictions)
            self.failed_shots += sum(not prediction.ok for prediction in predictions)
            self.bar.update(len(predictions))
            self.bar.set_postfix(chi2=f"{float(residuals @ residuals):.4g}", refresh=False)
        return self.cache[key]

    def residuals(self, x: np.ndarray) -> np.ndarray:
        return self.evaluate(x)[0]

    def failed(self, residuals: np.ndarray) -> bool:
        return bool(np.any(residuals >= FAILURE_RESIDUAL))

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        """(M, P) d residuals / d parameters: central differences, or one-sided (second order)
        where a bound or a failing shot is within two steps on one side."""
        x = np.asarray(x, dtype=float)
        f0 = self.residuals(x)
        columns = []
        for j, h in enumerate(self.steps):
            def at(k: float, j=j, h=h) -> np.ndarray | None:
                probe = x.copy()
                probe[j] += k * h
                if not self.lower[j] <= probe[j] <= self.upper[j]:
                    return None
                f = self.residuals(probe)
                return None if self.failed(f) and not self.failed(f0) else f

            up, down = at(+1.0), at(-1.0)
            if up is not None and down is not None:
                forward, backward = (up - f0) / h, (f0 - down) / h
                column = (forward + backward) / 2.0
                # A jump between the probes (the velocity rule's release moving to another
                # crossing, say) makes the two one-sided slopes disagree wildly, where a smooth
                # measurement's differ by ~STEP: take the one on x's own side of the jump (the
                # smaller) and remember it.
                jumps = np.abs(forward - backward) > JUMP_RATIO * np.maximum(np.abs(forward), np.abs(backward))
                jumps &= self.quantity_rows
                if jumps.any():
                    column = np.where(jumps, np.where(np.abs(forward) < np.abs(backward), forward, backward),
                                      column)
                    self.jumps[j] = np.flatnonzero(jumps)
                else:
                    self.jumps.pop(j, None)
                columns.append(column)
                continue
            self.jumps.pop(j, None)
            for sign, near in ((+1.0, up), (-1.0, down)):
                far = at(2.0 * sign) if near is not None else None
                if far is not None:
                    columns.append(sign * (-3.0 * f0 + 4.0 * near - far) / (2.0 * h))
                    break
            else:
                name = self.spec.parameters[j].name
                raise CalibrationError(f"{name}: no shot can be taken on either side of {x[j]:g} "
                                       f"(steps of {h:g}): a shot stops throwing or its design cannot be "
                                       f"built there; narrow [bounds] or give another [start]")
        return np.column_stack(columns)


def calibrate(spec: CalibrationSpec, *, progress: bool = False) -> Calibration:
    """Fit ``spec``'s parameters to its shots by weighted least squares.

    Parameters
    ----------
    spec : a checked calibration file (``load_calibration``).
    progress : a progress bar on stderr (shots simulated, the current chi-square).

    Returns
    -------
    Calibration

    Raises
    ------
    CalibrationError
        if a shot does not throw at the starting parameters (the fit has nowhere to
        start from), or no finite difference can be taken around the solution.
    """
    from scipy.optimize import least_squares

    began = time.perf_counter()
    model = _Model(spec, progress)
    params = spec.parameters
    start = np.array([p.start for p in params])
    try:
        _, initial = model.evaluate(start)
        for shot, prediction in zip(spec.shots, initial, strict=True):
            if not prediction.ok:
                at = ", ".join(f"{p.name} = {v:g}" for p, v in zip(params, start, strict=True))
                raise CalibrationError(f"{shot.label} ({shot.design_file}) does not throw at the start "
                                       f"({at}): {prediction.status}: {prediction.message}; give a [start] "
                                       f"where every shot throws")
        scales = np.array([p.scale for p in params])
        result = least_squares(model.residuals, start, jac=model.jacobian, bounds=(model.lower, model.upper),
                               method="dogbox", x_scale=scales, ftol=TOLERANCE, xtol=TOLERANCE, gtol=TOLERANCE,
                               max_nfev=MAX_EVALUATIONS)
        values = np.asarray(result.x, dtype=float)
        residuals, fitted = model.evaluate(values)
        jacobian = model.jacobian(values)
        covariance, singular = _covariance(jacobian, scales)
        origin_sd = _time_origin_sd(model, values, fitted, covariance)
    finally:
        model.bar.close()
    at_bound = np.array([result.active_mask[j] != 0 or min(values[j] - p.lower, p.upper - values[j])
                         <= AT_BOUND * p.scale for j, p in enumerate(params)])
    chi_square = float(residuals @ residuals)
    dof = spec.measurements - len(params) - spec.time_origins
    warnings = _warnings(spec, values, at_bound, singular, fitted, result)
    for j, rows in sorted(model.jumps.items()):
        labels = _measurement_labels(spec)
        warnings.append(f"{', '.join(labels[i] for i in rows)} jumps within {model.steps[j]:.3g} of "
                        f"{params[j].name} = {values[j]:.6g}: the model is not smooth there (the velocity rule's "
                        f"release can move to another crossing of the angle), so the fit may sit on the jump; "
                        f"the uncertainty uses the slope on its own side")
    with np.errstate(invalid="ignore"):
        uncertainties = np.sqrt(np.diag(covariance))
    warnings += _plausibility_warnings(spec, values, covariance)
    return Calibration(spec, values, uncertainties, covariance, start, fitted, initial, residuals, chi_square, dof,
                       at_bound, singular, tuple(warnings), len(model.cache), model.shots, model.failed_shots, result.message,
                       bool(result.success), time.perf_counter() - began, origin_sd)


def _time_origin_sd(model: _Model, values: np.ndarray, fitted, covariance: np.ndarray) -> tuple[float | None, ...]:
    """``Calibration.time_origin_sd``: each track's time origin is refitted at every set of parameters
    (``analytic.calibrate.track.align``), so its variance is its own at fixed parameters,
    ``1 / sum((v / sd)^2)`` over the points (v the model's velocity there), plus ``g^T C g``, g its
    change with the parameters (central differences at the fit's steps, one-sided at a bound)."""
    spec = model.spec
    out: list[float | None] = []
    for k, (shot, prediction) in enumerate(zip(spec.shots, fitted, strict=True)):
        if shot.track is None or prediction.track is None:
            out.append(None)
            continue
        slope = prediction.track.velocity.ravel() / shot.track.sd
        own = 1.0 / float(slope @ slope) if slope @ slope > 0.0 else math.inf
        gradient = []
        for j, h in enumerate(model.steps):
            sides = []
            for sign in (+1.0, -1.0):
                probe = values.copy()
                probe[j] += sign * h
                moved = (model.evaluate(probe)[1][k].track if model.lower[j] <= probe[j] <= model.upper[j]
                         else None)
                sides.append(None if moved is None else moved.time_origin)
            centre = prediction.track.time_origin
            up, down = sides
            gradient.append((up - down) / (2.0 * h) if up is not None and down is not None
                            else (up - centre) / h if up is not None
                            else (centre - down) / h if down is not None else math.nan)
        g = np.array(gradient)
        variance = own + float(g @ covariance @ g)
        out.append(math.sqrt(variance) if math.isfinite(variance) and variance >= 0.0 else math.nan)
    return tuple(out)


def _plausibility_warnings(spec: CalibrationSpec, values: np.ndarray, covariance: np.ndarray) -> list[str]:
    """A fitted value outside its plausible range (``analytic.plausibility.FITTED_RANGES``), and
    each pair of parameters correlated beyond ``HIGH_CORRELATION``, with what it probably means."""
    from analytic.plausibility import fitted_value_warning

    lines = [line for p, v in zip(spec.parameters, values, strict=True)
             if (line := fitted_value_warning(p.name, float(v))) is not None]
    sd = np.sqrt(np.abs(np.diag(covariance)))
    for i, first in enumerate(spec.parameters):
        for j in range(i + 1, len(spec.parameters)):
            r = covariance[i, j] / (sd[i] * sd[j]) if sd[i] > 0.0 and sd[j] > 0.0 else math.nan
            if math.isfinite(r) and abs(r) > HIGH_CORRELATION:
                second = spec.parameters[j].name
                lines.append(f"{first.name} and {second} correlate at {r:+.2f}: the shots fix mostly one "
                             f"combination of them ({'more of one with less of the other' if r < 0 else 'both up or both down'} "
                             f"throws the same), so each alone is uncertain and neither value should be read on "
                             f"its own; predictions carry the correlation and stay usable near the measured "
                             f"settings; shots that tell them apart (another setting, a measured release angle "
                             f"or time) would separate them")
    return lines


def _measurement_labels(spec: CalibrationSpec) -> list[str]:
    """``shot[i] quantity`` for every measurement (``shot[i] track line N x``: a track's point), in the
    residuals' order."""
    return [label for shot in spec.shots for label in
            [f"{shot.label} {m.quantity}" for m in shot.measurements]
            + ([f"{shot.label} track line {line} {axis}" for line in shot.track.lines for axis in "xy"]
               if shot.track else [])]


def _covariance(jacobian: np.ndarray, scales: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(J^T J)^-1 and which parameters lie in J's (numerical) null space.

    Worked in scaled parameters (each over its scale), so that "small" compares like
    with like; a parameter the data cannot fix gets NaN in its row and column, and the
    rest the inverse over the directions the data do fix.
    """
    scaled = jacobian * scales
    _, s, vt = np.linalg.svd(scaled, full_matrices=False)
    keep = s > SINGULAR_RATIO * s[0] if s.size and s[0] > 0.0 else np.zeros(s.shape, dtype=bool)
    weak = vt[~keep]
    # A parameter takes part in a direction the data cannot see when that direction leans on it.
    singular = np.any(np.abs(weak) > 1e-3, axis=0) if weak.size else np.zeros(len(scales), dtype=bool)
    inverse = (vt[keep].T / s[keep] ** 2) @ vt[keep]
    covariance = inverse * np.outer(scales, scales)
    covariance[singular, :] = math.nan
    covariance[:, singular] = math.nan
    return covariance, singular


def _warnings(spec, values, at_bound, singular, fitted, result) -> list[str]:
    lines = []
    for j, p in enumerate(spec.parameters):
        if singular[j]:
            lines.append(f"{p.name}: the data cannot fix it (the Jacobian is singular in it: the measurements "
                         f"do not change with it, or only together with another parameter); its uncertainty "
                         f"is undefined")
        if at_bound[j]:
            bound = "lower" if values[j] - p.lower <= p.upper - values[j] else "upper"
            lines.append(f"{p.name} = {values[j]:g} {p.unit}".rstrip() + f": at its {bound} bound "
                         f"({p.lower if bound == 'lower' else p.upper:g}); the data want it beyond, so its "
                         f"uncertainty is not a confidence interval")
    for shot, prediction in zip(spec.shots, fitted, strict=True):
        if not prediction.ok:
            lines.append(f"{shot.label} ({shot.design_file}) does not throw at the fitted parameters: "
                         f"{prediction.status}: {prediction.message}")
            continue
        weighted = weighted_residuals(shot, prediction)
        for m, r in zip(shot.measurements, weighted[:len(shot.measurements)], strict=True):
            if abs(r) > MISFIT:
                lines.append(f"{shot.label} {m.quantity}: predicted {prediction.values[m.quantity]:.4g} {m.unit} "
                             f"against {m.value:.4g} measured, {r:+.1f} standard deviations at the fit")
        if shot.track is not None and prediction.track is not None:
            lines += _track_warnings(shot, prediction.track, weighted[len(shot.measurements):])
    if not result.success or result.status == 0:
        lines.append(f"the fit did not converge: {result.message}")
    return lines


def _track_warnings(shot: ShotSpec, track: TrackPrediction, weighted: np.ndarray) -> list[str]:
    """A track the model misses by more than ``MISFIT`` standard deviations (root mean square), and
    points past the model's last instant."""
    lines = []
    rms = float(np.sqrt(np.mean(weighted ** 2)))
    if rms > MISFIT:
        lines.append(f"{shot.label} track {shot.track.file}: the model misses its points by {rms:.1f} standard "
                     f"deviations (root mean square) at the fit: track_uncertainty stated too small, a scale or "
                     f"an origin off, or motion the model lacks")
    if track.outside.any():
        last = "landing" if shot.track.point == "projectile" else "release (the arm is not followed past it)"
        first = int(shot.track.lines[np.argmax(track.outside)])
        lines.append(f"{shot.label} track {shot.track.file}: {int(track.outside.sum())} point(s) from line {first} "
                     f"on lie past the model's {last}, compared with its last position: trim them from the track")
    return lines
