"""Calibration from a measured track: synthetic tracks recovered within their stated uncertainty, the
time origin found, Tracker's exports read, every bad track refused before any shot.

A synthetic track is the reference path's own motion (``analytic.reference.simulate``'s
history: the projectile's centre, or the long arm's tip from ``analytic.geometry``) at the
true parameters, on a camera's frames, shifted to an unknown time origin, with seeded
Gaussian noise of the stated uncertainty, in metres or in image pixels (y down). The fit runs
on the fast path and its own splines (``analytic.calibrate.track``), so it does not fit its
own interpolation; the only reference numbers are the true parameters themselves.
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.stats import chi2
from support import DATA

from analytic.calibrate import calibrate, load_calibration
from analytic.calibrate.track import align, model_path
from analytic.calibrate.track_file import TrackFileError, read_track
from analytic.cli import main
from analytic.design import DesignError, Losses
from analytic.design_file import load_design, save_design
from analytic.geometry import machine_points
from analytic.reference import simulate

PROTOTYPE_FILE = DATA / "designs" / "prototype-61.toml"
TRACK_EXAMPLE = DATA / "calibration" / "prototype-track.toml"
#: The axle's radius, m, as analytic/data/calibration/prototype.toml assumes (the paper gives none).
AXLE_RADIUS = 0.0064
#: The synthetic truth: greased-steel-to-dry-wood axle friction (docs/guide/losses.md: 0.1 to
#: 0.5) and drag 20 % above the golf-ball curve (within the ball-to-ball spread of Lyu et al.'s
#: drag crisis, analytic/aero.py).
TRUE_FRICTION, TRUE_DRAG = 0.3, 1.2
#: The camera: 120 frames a second; the video starts this long before the firing (the
#: unknown time origin the fit must find), and follows the projectile for this long after it.
FRAME_RATE, TIME_ORIGIN, FOLLOWED = 120.0, 1.734, 2.0
#: Frames of the machine at rest before the firing.
FRAMES_AT_REST = 12
#: Noise: a track in metres, one sd per coordinate; one in pixels: 1 px at 50 px/m (2 cm, a
#: 1920-px frame spanning 38 m), the pivot at pixel (200, 1000), rows counting down.
METRE_SD, PIXEL_SD, SCALE, ORIGIN_PX = 0.01, 1.0, 50.0, (200.0, 1000.0)
#: An arm tip tracked through the swing: the tip is a sharp mark, 5 mm.
TIP_SD = 0.005
#: Standard errors within which a noisy fit must land (the done-when line), and the noise-free
#: fit's (the minimum is the truth but for the splines' 1e-7 m, track.SWING_STEP's note).
WITHIN, NOISE_FREE = 2.0, 0.01


def true_design():
    base = load_design(PROTOTYPE_FILE)
    return dataclasses.replace(base, losses=Losses(axle_friction=TRUE_FRICTION, axle_radius=AXLE_RADIUS),
                               projectile=dataclasses.replace(base.projectile, drag_factor=TRUE_DRAG))


def synthetic_track(design, point: str) -> tuple[np.ndarray, np.ndarray]:
    """(n,) s from firing and (n, 2) m from the pivot: ``point`` on the camera's frames, from
    ``FRAMES_AT_REST`` before the firing to ``FOLLOWED`` s after it (the arm tip: to its release)."""
    shot = simulate(design, sample_step=1.0 / FRAME_RATE, flight_sample_step=1.0 / FRAME_RATE, loads=False,
                    sampled_loads=False)
    assert shot.ok
    h = shot.history
    if point == "projectile":
        t, xy = np.r_[h.t, h.flight_t[1:]], np.r_[h.path, h.flight_path[1:]]
        t, xy = t[t <= FOLLOWED], xy[t <= FOLLOWED]
    else:
        t, xy = h.t[:-1], machine_points(h.q[:-1], design.machine)["long_tip"]   # the frames before release
    before = -np.arange(FRAMES_AT_REST, 0, -1) / FRAME_RATE
    return np.r_[before, t], np.r_[np.repeat(xy[:1], FRAMES_AT_REST, axis=0), xy]


def write_track(path, t, xy, header="t,x,y", delimiter=","):
    path.write_text(header + "\n" + "\n".join(delimiter.join(f"{v:.9g}" for v in row)
                                              for row in np.c_[t, xy]) + "\n")


def track_case(folder, point: str, unit: str, seed: int | None, range_shot: bool = False) -> str:
    """A calibration file fitting friction and drag to one synthetic track (plus, with
    ``range_shot``, a range measured at 50 deg): the path of it."""
    design = true_design()
    t, xy = synthetic_track(design, point)
    rng = np.random.default_rng(seed)
    if unit == "m":
        sd = METRE_SD if point == "projectile" else TIP_SD
        measured = xy + np.array([0.0, design.machine.pivot_height])   # y up from the base
        if seed is not None:
            measured = measured + sd * rng.standard_normal(xy.shape)
        keys = f'track_length_unit = "m"\ntrack_uncertainty = "{sd * 1000:g} mm"\n'
    else:
        measured = np.array(ORIGIN_PX) + xy * SCALE * np.array([1.0, -1.0])   # image pixels, rows down
        if seed is not None:
            measured = measured + PIXEL_SD * rng.standard_normal(xy.shape)
        keys = (f'track_length_unit = "px"\ntrack_scale = {SCALE}\ntrack_origin = {list(ORIGIN_PX)}\n'
                f'track_y_down = true\ntrack_uncertainty = {PIXEL_SD}\n')
    write_track(folder / "track.csv", t + TIME_ORIGIN, measured)
    save_design(load_design(PROTOTYPE_FILE), folder / "design.toml")
    text = (f'fit = ["losses.axle_friction", "drag_factor"]\ndesign = "design.toml"\n'
            f'[given]\n"losses.axle_radius" = {AXLE_RADIUS}\n'
            f'[[shot]]\ntrack = "track.csv"\ntrack_point = "{point}"\n{keys}')
    if range_shot:
        at_50 = dataclasses.replace(design, machine=dataclasses.replace(design.machine,
                                                                        release_angle=math.radians(50.0)))
        distance = simulate(at_50, histories=False, loads=False).range + 0.3 * rng.standard_normal()
        text += f'[[shot]]\n"machine.release_angle" = 50.0\nrange = {distance!r}\nrange_uncertainty = 0.3\n'
    (folder / "shots.toml").write_text(text)
    return str(folder / "shots.toml")


def _errors_in_sd(result) -> np.ndarray:
    return (result.values - np.array([TRUE_FRICTION, TRUE_DRAG])) / result.uncertainties


# --------------------------------------------------------------------------- #
# Recovery of known parameters
# --------------------------------------------------------------------------- #

@pytest.mark.parametrize("unit", ["m", "px"])
def test_a_noisy_projectile_track_gives_back_friction_and_drag(tmp_path, unit):
    """The projectile from rest through the swing and 2 s of flight, with noise, time origin unknown."""
    result = calibrate(load_calibration(track_case(tmp_path, "projectile", unit, seed=1)))
    assert result.converged
    errors = _errors_in_sd(result)
    assert np.all(np.abs(errors) < WITHIN), (result.values, result.uncertainties, errors)
    origin = result.fitted[0].track.time_origin
    assert abs(origin - TIME_ORIGIN) < WITHIN * result.time_origin_sd[0], (origin, result.time_origin_sd)
    # the chi-square is that of noise of the stated size: within chi-square(dof)'s 99.9 % interval
    low, high = chi2.ppf([0.0005, 0.9995], result.degrees_of_freedom)
    assert low < result.chi_square < high, (result.chi_square, result.degrees_of_freedom)


def test_a_noise_free_track_in_pixels_gives_back_the_truth(tmp_path):
    result = calibrate(load_calibration(track_case(tmp_path, "projectile", "px", seed=None)))
    errors = _errors_in_sd(result)
    assert np.all(np.abs(errors) < NOISE_FREE), (result.values, result.uncertainties, errors)
    assert abs(result.fitted[0].track.time_origin - TIME_ORIGIN) < NOISE_FREE * result.time_origin_sd[0]


def test_an_arm_tip_track_beside_a_range_shot(tmp_path):
    """The swing fixes the friction, the range at another setting the drag: mixed shots, through
    the command line, its JSON in today's shape, and the plot of the track."""
    shots = track_case(tmp_path, "arm_tip", "m", seed=3, range_shot=True)
    out = tmp_path / "out"
    assert main(["calibrate", shots, "--json", "--quiet", "--out", str(out)]) == 0
    data = json.loads((out / "calibration.json").read_text())
    values = np.array([data["parameters"][n]["value"] for n in ("losses.axle_friction", "drag_factor")])
    sds = np.array([data["parameters"][n]["uncertainty"] for n in ("losses.axle_friction", "drag_factor")])
    errors = (values - np.array([TRUE_FRICTION, TRUE_DRAG])) / sds
    assert np.all(np.abs(errors) < WITHIN), (values, sds, errors)
    track, ranged = data["shots"]
    assert track["measured"] is None and track["track"]["point"] == "arm_tip"
    assert track["track"]["outside"] == 0   # the tip is tracked to its release, no further
    assert abs(track["track"]["time_origin"] - TIME_ORIGIN) < WITHIN * track["track"]["time_origin_uncertainty"]
    assert ranged["quantities"]["range"]["measured"] == ranged["measured"] and "track" not in ranged
    assert data["degrees_of_freedom"] == 2 * track["track"]["points"] + 1 - 2 - 1
    assert (out / "tracks.png").stat().st_size > 0


@pytest.mark.slow
def test_the_uncertainties_of_track_fits_are_their_spread(tmp_path):
    """Over six seeds, the fits' Mahalanobis distances from the truth sum as chi-square(12): the
    covariance (time origin profiled out) is the right size, not just the values near the truth."""
    total = 0.0
    for seed in range(6):
        folder = tmp_path / f"seed{seed}"
        folder.mkdir()
        result = calibrate(load_calibration(track_case(folder, "projectile", "m", seed=10 + seed)))
        error = result.values - np.array([TRUE_FRICTION, TRUE_DRAG])
        total += float(error @ np.linalg.solve(result.covariance, error))
    low, high = chi2.ppf([0.0005, 0.9995], 12)
    assert low < total < high, total


def test_the_time_origin_is_found_on_the_exact_path():
    """``align`` on the model's own path shifted by a known time gives the shift back."""
    design = true_design()
    _, path = model_path(design, "projectile")
    times = np.linspace(-0.05, 1.5, 60)
    track = SimpleNamespace(t=times + TIME_ORIGIN)
    assert align(track, path.at(times), path) == pytest.approx(TIME_ORIGIN, abs=1e-9)


@pytest.mark.slow
def test_the_example_track_calibrates_near_its_truth():
    """analytic/data/calibration/prototype-track.toml: a Tracker export of a synthetic shot with the
    truth above (its header says how it was made)."""
    result = calibrate(load_calibration(TRACK_EXAMPLE))
    errors = _errors_in_sd(result)
    assert np.all(np.abs(errors) < WITHIN + 1.0), (result.values, result.uncertainties, errors)


# --------------------------------------------------------------------------- #
# Reading a track file
# --------------------------------------------------------------------------- #

def test_a_tracker_export_reads_as_it_is(tmp_path):
    """Tracker's table export: the track's name above the header, tab-separated, other columns, a
    frame without a marked step; and a semicolon export with decimal commas."""
    tab = tmp_path / "tracker.txt"
    tab.write_text("mass A\nt\tx\ty\tv_{x}\n0.000\t1.25\t-0.5\t\n0.033\t\t\t\n0.067\t1.5\t-0.25\t3.7\n"
                   "0.100\t1.75\t0\t3.7\n0.133\t2\t0.25\t\n0.167\t2.25\t0.5\t\n")
    table = read_track(tab)
    assert table.t.tolist() == [0.0, 0.067, 0.1, 0.133, 0.167] and table.skipped == 1
    assert table.xy[:, 0].tolist() == [1.25, 1.5, 1.75, 2.0, 2.25] and table.lines.tolist() == [3, 5, 6, 7, 8]
    semicolons = tmp_path / "comma.csv"
    semicolons.write_text("#multi:\n\"t\";\"y\";\"x\"\n" + "".join(f"0,{i};{i},5;{2 * i}\n" for i in range(5)))
    table = read_track(semicolons)
    assert table.t.tolist() == [0.0, 0.1, 0.2, 0.3, 0.4]
    assert table.xy.tolist() == [[2 * i, i + 0.5] for i in range(5)]


BAD_FILES = {
    "no-header": ("0,1,2\n" * 6, "line 1: data before a header row"),
    "no-columns": ("time,pos\n", "no header row naming t, x and y"),
    "two-tracks": ("t\tx\ty\tx\ty\n" + "0\t1\t2\t3\t4\n" * 6, "names 'x' 2 times"),
    "not-a-number": ("t,x,y\n0,1,2\n0.1,1,two\n", "line 3: y is 'two': not a number"),
    "time-backwards": ("t,x,y\n0,1,2\n0.2,1,2\n0.1,1,2\n0.3,1,2\n0.4,1,2\n",
                       "line 4: t = 0.1 does not come after the previous row's 0.2"),
    "one-coordinate": ("t,x,y\n0,1,\n", "line 2: y is empty"),
    "too-few": ("t,x,y\n0,1,2\n0.1,1,2\n", "2 points below the header on line 1: a track needs at least 5"),
    "thousands": ("t;x;y\n0;1,000.5;2\n", "line 2: x is '1,000.5': not a number"),
}


@pytest.mark.parametrize("name", list(BAD_FILES))
def test_a_bad_track_file_is_refused_naming_the_file_line_and_reason(tmp_path, capsys, name):
    text, reason = BAD_FILES[name]
    (tmp_path / "bad.csv").write_text(text)
    with pytest.raises(TrackFileError, match="bad.csv"):
        read_track(tmp_path / "bad.csv")
    (tmp_path / "shots.toml").write_text(f'fit = ["drag_factor"]\n[[shot]]\ndesign = "{PROTOTYPE_FILE}"\n'
                                         f'track = "bad.csv"\ntrack_point = "projectile"\n'
                                         f'track_length_unit = "m"\ntrack_uncertainty = 0.01\n')
    assert main(["calibrate", str(tmp_path / "shots.toml"), "--quiet", "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "shot[1].track = 'bad.csv'" in err and str(tmp_path / "bad.csv") in err and reason in err, err
    assert not (tmp_path / "out").exists()


BAD_KEYS = {
    "missing-file": ('track = "nowhere.csv"\ntrack_point = "projectile"\ntrack_length_unit = "m"\n'
                     'track_uncertainty = 0.01', "shot[1].track = 'nowhere.csv'", "No such file"),
    "no-point": ('track = "good.csv"\ntrack_length_unit = "m"\ntrack_uncertainty = 0.01',
                 "shot[1].track_point", "required with a track"),
    "bad-point": ('track = "good.csv"\ntrack_point = "counterweight"\ntrack_length_unit = "m"\n'
                  'track_uncertainty = 0.01', "shot[1].track_point", "projectile, arm_tip"),
    "pixels-without-scale": ('track = "good.csv"\ntrack_point = "projectile"\ntrack_length_unit = "px"\n'
                             'track_origin = [1, 2]\ntrack_uncertainty = 1', "shot[1].track_scale", "required"),
    "origin-of-one": ('track = "good.csv"\ntrack_point = "projectile"\ntrack_length_unit = "px"\n'
                      'track_scale = 50\ntrack_origin = [1]\ntrack_uncertainty = 1', "shot[1].track_origin",
                      "must be [x, y]"),
    "scale-on-metres": ('track = "good.csv"\ntrack_point = "projectile"\ntrack_length_unit = "m"\n'
                        'track_scale = 50\ntrack_uncertainty = 0.01', "shot[1].track_scale", "only for a track"),
    "pixels-sd-on-metres": ('track = "good.csv"\ntrack_point = "projectile"\ntrack_length_unit = "m"\n'
                            'track_uncertainty = "2 px"', "shot[1].track_uncertainty", "in pixels"),
    "no-sd": ('track = "good.csv"\ntrack_point = "projectile"\ntrack_length_unit = "m"',
              "shot[1].track_uncertainty", "required with a track"),
    "negative-sd": ('track = "good.csv"\ntrack_point = "projectile"\ntrack_length_unit = "m"\n'
                    'track_uncertainty = "-3 mm"', "shot[1].track_uncertainty", "must be positive"),
    "point-without-track": ('range = 26.8\nrange_uncertainty = 0.5\ntrack_point = "projectile"',
                            "shot[1].track_point", "without shot[1].track"),
    "neither": ('track_length_unit = "m"', "shot[1].track_length_unit", "without shot[1].track"),
}


@pytest.mark.parametrize("name", list(BAD_KEYS))
def test_a_bad_track_key_is_refused_before_any_shot(tmp_path, capsys, name):
    keys, where, reason = BAD_KEYS[name]
    write_track(tmp_path / "good.csv", np.linspace(0.0, 0.4, 5), np.ones((5, 2)))
    (tmp_path / "shots.toml").write_text(f'fit = ["drag_factor"]\n[[shot]]\ndesign = "{PROTOTYPE_FILE}"\n{keys}\n')
    with pytest.raises(DesignError, match=re.escape(reason)):
        load_calibration(tmp_path / "shots.toml")
    assert main(["calibrate", str(tmp_path / "shots.toml"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert where in err and reason in err, err


def test_a_shot_with_neither_range_nor_track_is_refused(tmp_path):
    (tmp_path / "shots.toml").write_text(f'fit = ["drag_factor"]\n[[shot]]\ndesign = "{PROTOTYPE_FILE}"\n')
    with pytest.raises(DesignError, match=r"shot\[1\].range.*or a measured track"):
        load_calibration(tmp_path / "shots.toml")
