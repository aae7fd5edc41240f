"""A measured track in a calibration: its keys in a ``[[shot]]``, the model's path of the tracked point, and its time origin.

A shot may measure, beside or instead of its range, the motion of one point
seen on video::

    track = "shot3.csv"            # t, x, y (analytic.calibrate.track_file), relative to the calibration file
    track_point = "projectile"     # or "arm_tip" (the long arm's tip)
    track_length_unit = "px"       # or "m"
    track_scale = 41.5             # px per metre             (px only)
    track_origin = [212.0, 873.5]  # the pivot's place, px     (px only)
    track_y_down = true            # image rows count down     (px only; default false)
    track_uncertainty = "1.5 px"   # one sd of each coordinate: bare in the track's unit, or "6 mm"

In metres, x is forward from the pivot (the way the projectile flies) and y up
from the base (the ground); in pixels, x counts forward and y up (down with
``track_y_down``) from ``track_origin``, the pivot's place in the image, so
y there is height above the pivot. Time is in seconds from any origin: the
fit finds the track's time at the firing instant (``align``), and compares
every point with the model at ``t - time_origin`` s from firing. Before the
firing the machine stands at rest; after the model's last instant (the
landing for the projectile, the release for the arm's tip: the machine is not
followed past release) a point is compared with that last position and
counted as ``outside`` (the report warns: trim the track there).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from analytic.design import Design, DesignError, require_number
from analytic.units import LENGTH, parse

#: What a track may follow: name -> the part of ``analytic.geometry.PARTS``.
TRACK_POINTS = {"projectile": "projectile", "arm_tip": "long_tip"}
TRACK_UNITS = ("m", "px")
#: A ``[[shot]]``'s keys of a track.
TRACK_KEYS = ("track", "track_point", "track_length_unit", "track_scale", "track_origin", "track_y_down",
              "track_uncertainty")
#: Sample spacing of the model's path, s, through stages 1-2 and in flight: the compiled
#: shot's own interpolant read there (``analytic.fast.motion``) and joined by cubic splines
#: between. Against the reference path's continuous solution (sampled 1.7e-4 s and 1.3e-3 s
#: apart) the splines' worst error over the prototype and the punkin, floating-arm and backyard
#: presets is 9.6e-8 m in stages 1-2 (the prototype's, its projectile at up to 19 m/s) and
#: 2e-9 m in flight: far below any video's pixel (mm to cm).
SWING_STEP, FLIGHT_STEP = 1e-3, 5e-3
#: Points of the coarse search for the time origin over every offset at which the track and
#: the model overlap; Gauss-Newton refines the best of them (``align``).
COARSE_OFFSETS = 400
#: Gauss-Newton on the time origin stops when its step is below this, s: far below any
#: finite-difference step of the fit can feel (the Jacobian needs the profile smooth).
ALIGN_TOLERANCE = 1e-12
ALIGN_ITERATIONS = 60


@dataclass(frozen=True)
class Track:
    """A shot's measured track, in metres.

    Attributes
    ----------
    file : as the calibration file names it.
    point : ``TRACK_POINTS`` key.
    t : (n,) times, s, from the file's own origin.
    xy : (n, 2) positions, m: x forward from the pivot, y up from ``y_from``'s level.
    y_from : ``"base"`` (tracks in metres: height above the ground) or ``"pivot"`` (tracks in
        pixels: height above ``track_origin``, the pivot).
    sd : one standard deviation of each coordinate, m.
    lines : (n,) each point's line in the file.
    unit, scale, origin, y_down : as the file gave them (px per metre, (2,) px), for the report.
    """

    file: str
    point: str
    t: np.ndarray
    xy: np.ndarray
    y_from: str
    sd: float
    lines: np.ndarray
    unit: str
    scale: float | None = None
    origin: tuple[float, float] | None = None
    y_down: bool = False

    @property
    def points(self) -> int:
        return len(self.t)

    def measured(self, design: Design) -> np.ndarray:
        """(n, 2) the points in the model's coordinates, m from the pivot at rest (y up from the pivot)."""
        lift = design.machine.pivot_height if self.y_from == "base" else 0.0
        return self.xy - np.array([0.0, lift])


def track_spec(label: str, raw: dict, folder: Path) -> Track | None:
    """The track a ``[[shot]]`` table gives (its ``TRACK_KEYS``), or None without ``track``.

    Raises
    ------
    DesignError
        naming the key (``shot[2].track_scale``), its value and the reason; a file that cannot
        be read names the file, its line and the reason (``analytic.calibrate.track_file``).
    """
    from analytic.calibrate.track_file import TrackFileError, read_track

    given = {key: raw[key] for key in TRACK_KEYS if key in raw}
    if "track" not in given:
        if given:
            key = next(iter(given))
            raise DesignError(f"{label}.{key}", given[key], f"without {label}.track: give the track's file too, "
                                                            f"or remove it")
        return None
    name = given["track"]
    if not isinstance(name, str) or not name:
        raise DesignError(f"{label}.track", name, "must be a file name (text), relative to this file")
    point = _choice(label, "track_point", given.get("track_point"), tuple(TRACK_POINTS))
    unit = _choice(label, "track_length_unit", given.get("track_length_unit"), TRACK_UNITS)
    pixels = unit == "px"
    for key in ("track_scale", "track_origin", "track_y_down"):
        if key in given and not pixels:
            raise DesignError(f"{label}.{key}", given[key], "only for a track in pixels (track_length_unit = "
                                                            "\"px\"); a track in metres is x forward from the "
                                                            "pivot and y up from the base")
    scale = origin = None
    y_down = False
    if pixels:
        for key in ("track_scale", "track_origin"):
            if key not in given:
                raise DesignError(f"{label}.{key}", None, "required for a track in pixels: track_scale (px per "
                                                          "metre) and track_origin ([px, px], the pivot's place)")
        scale = require_number(f"{label}.track_scale", given["track_scale"])
        if not scale > 0.0:
            raise DesignError(f"{label}.track_scale", given["track_scale"], "must be positive (px per metre)")
        origin = given["track_origin"]
        if not (isinstance(origin, list) and len(origin) == 2):
            raise DesignError(f"{label}.track_origin", origin, "must be [x, y] in pixels: the pivot's place")
        origin = tuple(require_number(f"{label}.track_origin", value) for value in origin)
        y_down = given.get("track_y_down", False)
        if not isinstance(y_down, bool):
            raise DesignError(f"{label}.track_y_down", y_down, "must be true (image rows count down) or false")
    sd = _uncertainty(label, given.get("track_uncertainty"), unit, scale)
    try:
        table = read_track(folder / name)
    except TrackFileError as error:
        raise DesignError(f"{label}.track", name, f"{error.path}" + (f", line {error.line}" if error.line else "")
                          + f": {error.reason}") from None
    xy = table.xy
    if pixels:
        xy = (xy - np.array(origin)) / scale
        if y_down:
            xy = xy * np.array([1.0, -1.0])
    return Track(name, point, table.t, np.ascontiguousarray(xy, dtype=float), "pivot" if pixels else "base", sd,
                 table.lines, unit, scale, origin, y_down)


def _choice(label: str, key: str, value: Any, choices: tuple[str, ...]) -> str:
    if value is None:
        raise DesignError(f"{label}.{key}", None, f"required with a track: one of {', '.join(choices)}")
    if value not in choices:
        raise DesignError(f"{label}.{key}", value, f"must be one of {', '.join(choices)}")
    return value


def _uncertainty(label: str, value: Any, unit: str, scale: float | None) -> float:
    """``track_uncertainty`` in metres: a bare number in the track's unit, or a text with a unit
    (a length, or ``"2 px"`` for a track in pixels)."""
    key = f"{label}.track_uncertainty"
    if value is None:
        examples = '"5 mm" or "2 px"' if scale else '"5 mm"'
        raise DesignError(key, None, f"required with a track: one standard deviation of each coordinate, in the "
                                     f"track's unit ({unit}) or with a unit ({examples})")
    if isinstance(value, str):
        text = value.strip()
        if text.endswith("px"):
            if scale is None:
                raise DesignError(key, value, "in pixels, but the track is in metres: give a length (\"5 mm\")")
            try:
                sd = float(text[:-2]) / scale
            except ValueError:
                raise DesignError(key, value, "must be a number of pixels (\"2 px\") or a length (\"5 mm\")") \
                    from None
        else:
            sd = parse(key, text, LENGTH)
    else:
        sd = require_number(key, value)
        sd = sd / scale if scale is not None else sd
    if not (math.isfinite(sd) and sd > 0.0):
        raise DesignError(key, value, "must be positive (one standard deviation of each coordinate)")
    return float(sd)


# --------------------------------------------------------------------------- #
# The model's path of the tracked point, and the time origin
# --------------------------------------------------------------------------- #

@dataclass(frozen=True)
class ModelPath:
    """The tracked point's path in a shot of the model: cubic splines through its samples, one per stage.

    Attributes
    ----------
    t : (k,) the samples' times, s from firing; xy : (k, 2) the point there, m from the pivot at rest.
    pieces : ((start, end, spline), ...) each stage's spline of position in time.
    end : the last instant modelled, s (landing; the arm tip's: release).
    """

    t: np.ndarray
    xy: np.ndarray
    pieces: tuple
    end: float

    def at(self, times: np.ndarray, derivative: int = 0) -> np.ndarray:
        """(..., 2) the position (or its ``derivative``-th time derivative) at ``times``, s from firing:
        at rest before firing, held at the last position after ``end`` (derivatives 0 there)."""
        times = np.asarray(times, dtype=float)
        flat = times.ravel()
        out = np.zeros((flat.size, 2))
        if derivative == 0:
            out[flat < self.pieces[0][0]] = self.xy[0]
            out[flat > self.end] = self.xy[-1]
        for start, end, spline in self.pieces:
            inside = (flat >= start) & (flat <= end)
            if inside.any():
                out[inside] = spline(flat[inside], derivative)
        return out.reshape(*times.shape, 2)


def model_path(design: Design, point: str) -> tuple[Any, ModelPath | None]:
    """The compiled shot of ``design`` (no peak loads) and ``point``'s path in it (None where the
    shot has no motion to follow: it never fires)."""
    from scipy.interpolate import CubicSpline

    from analytic.fast.motion import simulate_motion
    from analytic.geometry import machine_points

    shot, motion = simulate_motion(design, sample_step=SWING_STEP, flight_sample_step=FLIGHT_STEP, loads=False)
    if len(motion.t) < 2:
        return shot, None
    xy = machine_points(motion.q, design.machine)[TRACK_POINTS[point]] + np.c_[motion.frame_x,
                                                                                np.zeros(len(motion.t))]
    runs = [(motion.t, xy, motion.stage)]
    if point == "projectile" and len(motion.flight_t) > 1:
        runs.append((motion.flight_t, motion.flight_path, np.full(len(motion.flight_t), -1)))
    t = np.concatenate([r[0] for r in runs])
    path = np.concatenate([r[1] for r in runs])
    stage = np.concatenate([r[2] for r in runs])
    pieces = []
    breaks = np.flatnonzero(np.diff(stage) != 0) + 1
    for first, last in zip(np.r_[0, breaks], np.r_[breaks, len(t)], strict=True):
        first = max(first - 1, 0)   # each piece starts at the previous one's last sample: the path is continuous
        times, points = t[first:last], path[first:last]
        keep = np.r_[True, np.diff(times) > 1e-9 * max(SWING_STEP, 1.0)]
        times, points = times[keep], points[keep]
        if len(times) >= 2:
            pieces.append((float(times[0]), float(times[-1]), CubicSpline(times, points, axis=0)))
    if not pieces:
        return shot, None
    return shot, ModelPath(t, path, tuple(pieces), float(t[-1]))


def align(track: Track, measured: np.ndarray, path: ModelPath) -> float:
    """The track's time at the firing instant, s: the time origin that brings the track closest to
    ``path`` (least squares over every point, ``measured``: (n, 2) in the model's coordinates).

    A coarse search over every offset at which the two overlap (``COARSE_OFFSETS``), then
    Gauss-Newton on the best (each step no longer than the search's spacing, and halved until
    the sum of squares falls), to ``ALIGN_TOLERANCE``: the fit's finite differences see the
    profile smooth.
    """
    t = track.t
    low, high = t[0] - path.end, t[-1]
    offsets = np.linspace(low, high, COARSE_OFFSETS)
    misses = path.at(t[None, :] - offsets[:, None]) - measured[None]
    cost = np.einsum("ijk,ijk->i", misses, misses)
    origin = float(offsets[int(np.argmin(cost))])
    spacing = (high - low) / (COARSE_OFFSETS - 1)

    def sum_of_squares(at: float) -> float:
        miss = path.at(t - at) - measured
        return float(np.einsum("ij,ij->", miss, miss))

    best = sum_of_squares(origin)
    for _ in range(ALIGN_ITERATIONS):
        miss = (path.at(t - origin) - measured).ravel()
        slope = -path.at(t - origin, 1).ravel()      # d miss / d origin
        curvature = float(slope @ slope)
        if curvature == 0.0:
            break
        step = float(np.clip(-(slope @ miss) / curvature, -spacing, spacing))
        while abs(step) > ALIGN_TOLERANCE:
            trial = sum_of_squares(origin + step)
            if trial <= best:
                origin, best = origin + step, trial
                break
            step *= 0.5
        if abs(step) <= ALIGN_TOLERANCE:
            break
    return origin


@dataclass(frozen=True)
class TrackPrediction:
    """The model against one track at one set of parameters.

    Attributes
    ----------
    time_origin : the track's time at the firing instant, s (``align``).
    predicted : (n, 2) the model's point at each of the track's times, m, in the track's own
        coordinates (``Track.xy``'s: y up from its ``y_from``).
    velocity : (n, 2) its velocity there, m/s.
    outside : (n,) bool, points after the model's last instant (``ModelPath.end``).
    curve_t, curve : (k,) s from firing, (k, 2) m: the model's whole path, in the track's coordinates.
    lift : m added to the model's y for the track's coordinates (the pivot's height, or 0).
    """

    time_origin: float
    predicted: np.ndarray
    velocity: np.ndarray
    outside: np.ndarray
    curve_t: np.ndarray
    curve: np.ndarray
    lift: float

    def residuals(self, track: Track) -> np.ndarray:
        """(2n,) weighted residuals ``(predicted - measured) / sd``, x and y of each point in turn."""
        return ((self.predicted - track.xy) / track.sd).ravel()


def predict_track(track: Track, design: Design, path: ModelPath) -> TrackPrediction:
    """The model's ``path`` against ``track`` at its fitted time origin."""
    measured = track.measured(design)
    origin = align(track, measured, path)
    times = track.t - origin
    lift = float(track.xy[0, 1] - measured[0, 1])
    shift = np.array([0.0, lift])
    return TrackPrediction(origin, path.at(times) + shift, path.at(times, 1), times > path.end, path.t.copy(),
                           path.xy + shift, lift)
