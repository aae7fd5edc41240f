"""A calibration's tracks in its report: each track's JSON, its lines of text, and the plot of the track over the model.

JSON, a track shot's ``"track"`` in ``calibrate --json``'s ``shots``::

    {"file", "point", "length_unit", "points", "uncertainty" (m), "time_origin" (s, the
     track's time at the firing instant), "time_origin_uncertainty" (s), "rms_residual"
     ([x, y], m), "rms_weighted_residual", "chi_square", "outside" (points past the model's
     last instant), "t" (s, the track's own), "measured", "predicted" ([[x, y], ...], m)}

Positions are metres in the track's own coordinates: x forward from the
pivot; y up from the base for a track in metres, up from the pivot for one in
pixels (``analytic.calibrate.track``). The plot (``tracks.png``) has a row per
track: the path (measured points over the model's at the fit, and at the
start), x and y against time from firing, and the residuals with the stated
one-sd band; heights there are above the base for every track.
"""

from __future__ import annotations

import math

import numpy as np

from analytic.calibrate.fit import Calibration, weighted_residuals
from analytic.calibrate.spec import ShotSpec

#: The plot's file in ``calibrate --out``.
TRACK_PLOT_FILE = "tracks.png"


def _rows(result: Calibration):
    """(index, shot, fitted, initial) of each shot with a track the model followed at the fit."""
    for k, (shot, fitted, initial) in enumerate(zip(result.spec.shots, result.fitted, result.initial, strict=True)):
        if shot.track is not None:
            yield k, shot, fitted, initial


def track_json(result: Calibration, k: int) -> dict | None:
    """Shot ``k``'s ``"track"`` (module docstring), None without a track."""
    shot, prediction = result.spec.shots[k], result.fitted[k]
    track = shot.track
    if track is None:
        return None
    out = {"file": track.file, "point": track.point, "length_unit": track.unit, "points": track.points,
           "uncertainty": track.sd, "t": track.t.tolist(), "measured": track.xy.tolist()}
    fit = prediction.track if prediction.ok else None
    sd = result.time_origin_sd[k] if k < len(result.time_origin_sd) else None
    if fit is None:
        return {**out, "time_origin": None, "time_origin_uncertainty": None, "rms_residual": None,
                "rms_weighted_residual": None, "chi_square": None, "outside": None, "predicted": None}
    miss = fit.predicted - track.xy
    weighted = fit.residuals(track)
    return {**out, "time_origin": fit.time_origin,
            "time_origin_uncertainty": None if sd is None or not math.isfinite(sd) else sd,
            "rms_residual": np.sqrt(np.mean(miss ** 2, axis=0)).tolist(),
            "rms_weighted_residual": float(np.sqrt(np.mean(weighted ** 2))),
            "chi_square": float(weighted @ weighted), "outside": int(fit.outside.sum()),
            "predicted": fit.predicted.tolist()}


def track_lines(result: Calibration, k: int, system: str = "metric") -> list[str]:
    """The report's lines of shot ``k``'s track ([] without one)."""
    from analytic.units import display

    data = track_json(result, k)
    if data is None:
        return []
    scale, unit = display(1.0, "m", system)
    lines = [f"    track {data['file']} ({data['point'].replace('_', ' ')}, {data['points']} points, "
             f"+- {data['uncertainty'] * scale:.3g} {unit} each coordinate)"]
    if data["time_origin"] is None:
        return lines + ["      the model has no motion to compare with it"]
    sd = data["time_origin_uncertainty"]
    x, y = data["rms_residual"]
    lines.append(f"      fired at t = {data['time_origin']:.5f} s of the track"
                 + (f" +- {sd * 1e3:.2g} ms" if sd is not None else "")
                 + f"; rms residual x {x * scale:.3g} {unit}, y {y * scale:.3g} {unit} "
                 f"({data['rms_weighted_residual']:.2f} sd), chi-square {data['chi_square']:.4g}"
                 + (f"; {data['outside']} point(s) past the model's end" if data["outside"] else ""))
    return lines


def track_bars(result: Calibration) -> tuple[list[str], list[float]]:
    """The residual panel's bars: each measured quantity's weighted residual and, for a track, the
    root mean square of its points' (labels ``shot:quantity``, ``shot:track rms``)."""
    labels, values = [], []
    for shot, prediction in zip(result.spec.shots, result.fitted, strict=True):
        weighted = weighted_residuals(shot, prediction)
        weighted = np.where(np.abs(weighted) >= 1e6, np.nan, weighted)
        for m, r in zip(shot.measurements, weighted, strict=False):
            labels.append(f"{shot.number}:{m.quantity.replace('_time', ' t').replace('release_angle', 'angle')}")
            values.append(float(r))
        if shot.track is not None:
            labels.append(f"{shot.number}:track rms")
            rest = weighted[len(shot.measurements):]
            values.append(float(np.sqrt(np.mean(rest ** 2))))
    return labels, values


def _lift(result: Calibration, shot: ShotSpec) -> float:
    """m to add to the track's y for a height above the base (the fitted design's pivot height for
    a track in pixels)."""
    if shot.track.y_from == "base":
        return 0.0
    return result.spec.design_at(shot, result.values).machine.pivot_height


def tracks_figure(result: Calibration, system: str = "metric"):
    """The plot of every track over the model (module docstring), in ``system``'s units."""
    from matplotlib.figure import Figure

    from analytic.plot_units import in_units

    rows = list(_rows(result))
    fig = Figure(figsize=(14.0, 4.2 * len(rows)), layout="constrained")
    axes = fig.subplots(len(rows), 3, squeeze=False)
    fitted_at = ", ".join(f"{p.name} = {v:.4g} {p.unit}".rstrip()
                          for p, v in zip(result.spec.parameters, result.values, strict=True))
    fig.suptitle(f"{result.spec.path.name}: tracks over the model fitted at {fitted_at}", fontsize=10)
    for (k, shot, fitted, initial), (path_ax, time_ax, miss_ax) in zip(rows, axes, strict=True):
        track = shot.track
        up = np.array([0.0, _lift(result, shot)])
        measured = track.xy + up
        title = f"{shot.label} {track.file} ({track.point.replace('_', ' ')})"
        if not (fitted.ok and fitted.track is not None):
            path_ax.plot(*measured.T, ".", color="k", ms=3, label="measured")
            path_ax.set(title=f"{title}: the model does not throw at the fit", xlabel="x (m)", ylabel="y (m)")
            for ax in (time_ax, miss_ax):
                ax.set_axis_off()
            continue
        fit = fitted.track
        end = track.t[-1] - fit.time_origin
        shown = fit.curve_t <= end + 0.05 * (end - (track.t[0] - fit.time_origin))
        if initial.ok and initial.track is not None:
            start = initial.track
            keep = start.curve_t <= end
            path_ax.plot(*(start.curve[keep] + up).T, "--", color="tab:grey", lw=1, label="model at start")
        path_ax.plot(*(fit.curve[shown] + up).T, "-", color="tab:blue", lw=1.5, label="model at the fit")
        path_ax.plot(*measured.T, ".", color="k", ms=3, label="measured")
        path_ax.set(title=title, xlabel="x forward from the pivot (m)", ylabel="height above the base (m)")
        path_ax.set_aspect("equal", adjustable="datalim")
        times = track.t - fit.time_origin
        for axis, colour in ((0, "tab:blue"), (1, "tab:orange")):
            name = "xy"[axis]
            time_ax.plot(fit.curve_t[shown], fit.curve[shown, axis] + up[axis], "-", color=colour, lw=1.2,
                         label=f"{name}, model")
            time_ax.plot(times, measured[:, axis], ".", color=colour, ms=3, mec="k", mew=0.3,
                         label=f"{name}, measured")
            miss_ax.plot(times, fit.predicted[:, axis] - track.xy[:, axis], ".", color=colour, ms=3,
                         label=f"{name}")
        time_ax.set(title=f"against time: fired at t = {fit.time_origin:.4f} s of the track",
                    xlabel="time from firing (s)", ylabel="position (m)")
        miss_ax.axhspan(-track.sd, track.sd, color="tab:green", alpha=0.15, label="+- one stated sd")
        miss_ax.axhline(0.0, color="k", lw=0.8)
        if fit.outside.any():
            miss_ax.axvline(float(times[np.argmax(fit.outside)]), color="tab:red", lw=0.8,
                            label="past the model's end")
        miss_ax.set(title="residual (model - measured)", xlabel="time from firing (s)", ylabel="residual (m)")
        for ax in (path_ax, time_ax, miss_ax):
            ax.legend(fontsize=8)
            ax.grid(alpha=0.3)
    return in_units(fig, system)
