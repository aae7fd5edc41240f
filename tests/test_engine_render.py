"""Frames: how many, how big, where the projectile is drawn, and byte-identical on a second run."""

from __future__ import annotations

import dataclasses
import struct

import numpy as np
import pytest

from analytic.design import Base
from analytic.design_file import default_design
from engine_model.render import (BOX_ASPECT, BOX_MIN_DEPTH, FINAL_HOLD, FRAME_SIZE, PROJECTILE_COLOUR,
                                 WHEEL_RADIUS_FRACTION, FrameState, camera, draw_frame, frame_state, frame_times,
                                 render_shot, summary)
from analytic.geometry import machine_points
from engine_model import simulate


@pytest.fixture(scope="module")
def shot():
    # A coarser step than the default keeps this quick; the frames do not care.
    return simulate(default_design(), dt=4e-4)


def _png_size_and_chunks(path) -> tuple[tuple[int, int], list[bytes]]:
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    chunks, i = [], 8
    while i < len(data):
        length = struct.unpack(">I", data[i:i + 4])[0]
        chunks.append(data[i + 4:i + 8])
        i += 12 + length
    width, height = struct.unpack(">II", data[16:24])
    return (width, height), chunks


def test_frames_are_time_warped_slow_swing_real_time_flight_up_to_the_landing(shot, tmp_path):
    fps, slow = 4.0, 8.0
    times, speeds = frame_times(shot, fps, swing_slow_motion=slow, flight_speed=1.0)
    paths = render_shot(shot, tmp_path, fps=fps, swing_slow_motion=slow, progress=False)
    assert [p.name for p in paths] == [f"frame_{i:05d}.png" for i in range(len(times))]
    assert times[0] == 0.0 and times[-1] == shot.landing_time and np.all(np.diff(times) > 0.0)
    swing = times[:-1] < shot.release_time
    steps = np.diff(times)
    # A frame every 1/32 s of simulated time through the swing, every 1/4 s in flight (the
    # last of each phase may be shorter: the release and the landing are frames too).
    assert steps[swing][:-1] == pytest.approx(1.0 / (fps * slow))
    assert steps[~swing][:-1] == pytest.approx(1.0 / fps)
    in_swing = times < shot.release_time
    assert np.all(speeds[in_swing] == 1.0 / slow) and np.all(speeds[~in_swing] == 1.0)
    assert shot.release_time in times   # the flight's grid starts at the release
    size, chunks = _png_size_and_chunks(paths[-1])
    assert size == FRAME_SIZE == (960, 540)
    assert not {b"tEXt", b"iTXt", b"zTXt", b"tIME"} & set(chunks)  # nothing that varies between runs
    # An RGB file (colour type 2 in IHDR) of the frame's pixels, which are opaque: nothing dropped.
    from PIL import Image

    assert paths[-1].read_bytes()[25] == 2
    state = frame_state(shot, float(times[-1]))
    drawn = draw_frame(shot.design, state, camera(shot.design, state))
    assert np.all(drawn[:, :, 3] == 255)
    with Image.open(paths[0]) as first:
        assert first.mode == "RGB" and np.asarray(first).shape == (540, 960, 3)


def test_every_frame_has_the_same_view_and_the_last_sums_up(shot):
    times, _ = frame_times(shot, 4.0)
    view = camera(shot.design, frame_state(shot, float(times[-1])))
    # The whole flight and the machine in view: a fixed ground scale for every frame.
    assert view[0] < -1.0 and view[1] > shot.range and view[3] > shot.apex_height - shot.design.machine.pivot_height
    assert frame_state(shot, float(times[-1])).label == "landed"
    text = summary(shot)
    assert text.startswith(f"range {shot.range:.2f} m") and "release speed" in text


def test_gif_and_mp4_are_written_with_the_last_frame_held(shot, tmp_path):
    from PIL import Image

    paths = render_shot(shot, tmp_path, fps=2.0, gif=True, mp4=True, progress=False)
    with Image.open(tmp_path / "shot.gif") as gif:
        # Pillow folds the held copies of the last frame into one longer frame.
        assert gif.n_frames == len(paths) and gif.size == (960, 540)
        gif.seek(gif.n_frames - 1)
        assert gif.info["duration"] == 500 * (1 + round(FINAL_HOLD * 2.0))
    assert (tmp_path / "shot.mp4").stat().st_size > 1000


def test_the_same_shot_renders_byte_identical_frames(shot, tmp_path):
    first = render_shot(shot, tmp_path / "a", fps=2.0, gif=True, progress=False)
    second = render_shot(shot, tmp_path / "b", fps=2.0, gif=True, progress=False)   # frames and GIF alike
    for a, b in zip(first + [tmp_path / "a" / "shot.gif"], second + [tmp_path / "b" / "shot.gif"], strict=True):
        assert a.read_bytes() == b.read_bytes(), a.name


def test_the_projectile_is_drawn_where_it_is(shot):
    # A hand-made state and view: the view spans x -2..14 m (16 m over 960 px,
    # 60 px/m) and y -1..8 m (9 m over 540 px, 60 px/m). The projectile at
    # (5, 3) m falls at column (5 + 2) * 60 = 420, row (8 - 3) * 60 = 300.
    state = FrameState(time=1.0, label="test", long_tip=np.array([-0.5, 0.5]), short_tip=np.array([0.2, -0.2]),
                       counterweight=np.array([0.2, -0.4]), projectile=np.array([5.0, 3.0]),
                       sling_attached=False, trace=np.array([[0.0, -0.59], [5.0, 3.0]]))
    pixels = draw_frame(shot.design, state, (-2.0, 14.0, -1.0, 8.0)).astype(int)
    assert pixels.shape == (FRAME_SIZE[1], FRAME_SIZE[0], 4)
    red = tuple(int(PROJECTILE_COLOUR[i:i + 2], 16) for i in (1, 3, 5))
    rows, cols = np.nonzero(np.all(np.abs(pixels[:, :, :3] - red) < 40, axis=2))
    assert len(rows) > 20, "projectile not drawn"
    assert (cols.mean(), rows.mean()) == pytest.approx((420.0, 300.0), abs=1.0)


def _dark_columns(pixels: np.ndarray, rows: slice) -> np.ndarray:
    """Columns of the near-black (#303030) pixels within ``rows``: wheels, or the counterweight."""
    band = pixels[rows, :, :3].astype(int)
    return np.nonzero(np.all(np.abs(band - 0x30) < 24, axis=2))[1]


@pytest.mark.parametrize("frame_x", [0.0, 1.0, -0.5])
def test_a_rolling_frame_is_drawn_on_wheels_where_it_is(shot, frame_x):
    # The view of the test above (60 px/m, y = -1..8 m): the wheels stand on the
    # base at y = -h, so they fill rows (8 + h) * 60 upwards by 2 r * 60 px, and
    # they are centred at x = frame_x -/+ h/2, columns (frame_x -/+ h/2 + 2) * 60.
    design = dataclasses.replace(shot.design, base=Base("rolling", 20.0))
    h = design.machine.pivot_height
    state = FrameState(time=0.0, label="test", long_tip=np.array([frame_x - 0.5, 0.5]),
                       short_tip=np.array([frame_x + 0.2, 3.0]), counterweight=np.array([frame_x + 0.2, 5.0]),
                       projectile=np.array([5.0, 3.0]), sling_attached=False,
                       trace=np.array([[5.0, 3.0]]), frame_x=frame_x)
    view = (-2.0, 14.0, -1.0, 8.0)
    ground_row = round((8.0 + h) * 60.0)
    wheel_rows = slice(ground_row - round(2 * WHEEL_RADIUS_FRACTION * h * 60.0), ground_row)
    columns = _dark_columns(draw_frame(design, state, view), wheel_rows)
    left, right = columns[columns < (frame_x + 2.0) * 60.0], columns[columns > (frame_x + 2.0) * 60.0]
    assert len(left) > 20 and len(right) > 20, "wheels not drawn"
    assert left.mean() == pytest.approx((frame_x - 0.5 * h + 2.0) * 60.0, abs=1.5)
    assert right.mean() == pytest.approx((frame_x + 0.5 * h + 2.0) * 60.0, abs=1.5)
    # A fixed frame stands on the base with no wheels.
    fixed = dataclasses.replace(state, frame_x=0.0)
    assert len(_dark_columns(draw_frame(shot.design, fixed, view), wheel_rows)) == 0


def test_frames_of_a_rolling_shot_follow_its_frame(shot):
    rolling_shot = simulate(dataclasses.replace(shot.design, base=Base("rolling", 2.0)), dt=4e-4)
    moving = int(np.argmax(np.abs(rolling_shot.history.frame_x)))
    state = frame_state(rolling_shot, float(rolling_shot.history.t[moving]))
    assert state.frame_x == rolling_shot.history.frame_x[moving] != 0.0
    # Every part is drawn carried along by the frame (positions relative to the pivot, plus X).
    points = machine_points(rolling_shot.history.q[moving], rolling_shot.design.machine)
    for part in ("long_tip", "short_tip", "counterweight"):
        assert getattr(state, part) == pytest.approx(points[part] + [state.frame_x, 0.0], abs=1e-12), part
    assert state.projectile == pytest.approx(rolling_shot.history.path[moving], abs=1e-12)   # already over the ground
    assert camera(rolling_shot.design, state)[0] < state.frame_x - rolling_shot.design.machine.arm_long


def test_the_frames_are_labelled_in_the_chosen_units(shot):
    # 1 ft = 0.3048 m by definition
    assert summary(shot, "imperial").startswith(f"range {shot.range / 0.3048:.2f} ft")
    assert f"apex {shot.apex_height / 0.3048:.2f} ft" in summary(shot, "imperial")
    from engine_model.scene import Drawing

    axis = Drawing(shot.design, units="imperial").figure.axes[0].xaxis
    axis.axes.set_xlim(-5.0, 50.0)
    ticks = axis.get_major_locator()()
    assert all(abs(t / 0.3048 - round(t / 0.3048)) < 1e-9 for t in ticks)   # whole feet
    assert axis.get_major_formatter()(20 * 0.3048, 0) == "20 ft"


def _colour_mask(pixels: np.ndarray, colour: str, tolerance: int = 30) -> np.ndarray:
    rgb = np.array([int(colour[i:i + 2], 16) for i in (1, 3, 5)])
    return np.all(np.abs(pixels[:, :, :3].astype(int) - rgb) < tolerance, axis=2)


def test_the_summary_box_keeps_clear_of_the_trajectory(shot, tmp_path):
    """The last frame's box (found by its grey edge, #808080) holds no point of the trajectory,
    placed in pixels here from the shot's own path and the frames' view (the box is opaque, so
    the drawn trajectory could hide under it)."""
    from PIL import Image

    paths = render_shot(shot, tmp_path, fps=2.0, progress=False)
    with Image.open(paths[-1]) as last:
        pixels = np.asarray(last)
    grey = _colour_mask(pixels, "#808080", 12)
    # The box's edges are the long straight runs of its grey: rows and columns with many of them.
    rows, cols = np.flatnonzero(grey.sum(axis=1) > 150), np.flatnonzero(grey.sum(axis=0) > 60)
    top, bottom, left, right = rows.min(), rows.max(), cols.min(), cols.max()
    assert bottom - top > 40 and right - left > 100, "no summary box found"
    x_min, x_max, y_min, y_max = camera(shot.design, frame_state(shot, shot.landing_time))
    path = np.vstack([shot.history.path, shot.history.flight_path])
    columns = (path[:, 0] - x_min) / (x_max - x_min) * FRAME_SIZE[0]
    rows = (y_max - path[:, 1]) / (y_max - y_min) * FRAME_SIZE[1]
    assert not np.any((columns > left) & (columns < right) & (rows > top) & (rows < bottom))


def test_the_ground_scale_is_labelled_under_the_ground_clear_of_the_machine(shot):
    """The view leaves room under the ground for the scale's labels (LABEL_ROOM), and the "0 m"
    label is drawn there, under the machine's feet rather than behind its legs."""
    state = frame_state(shot, 0.0)
    view = camera(shot.design, frame_state(shot, shot.landing_time))
    pixels = draw_frame(shot.design, state, view)
    ground_row = int(round((view[3] + shot.design.machine.pivot_height) / (view[3] - view[2]) * FRAME_SIZE[1]))
    below = pixels[ground_row + 3:]
    assert below.shape[0] >= 14   # a label's height at 8 pt
    zero_column = int(round(-view[0] / (view[1] - view[0]) * FRAME_SIZE[0]))
    assert _colour_mask(below[:, zero_column - 15:zero_column + 15], "#5a4a3a", 40).any()


def test_the_machine_swings_on_after_release_in_the_frames():
    """Asked for, the engine steps the fixed machine on from release to landing: its motion starts
    where stages 1-2 left it and the frames in flight draw the arm where it has swung to, not
    frozen at its release angle; not asked for, nothing is stepped."""
    shot = simulate(default_design(), dt=4e-4, machine_after_release=True)
    history = shot.history
    assert history.machine_t[0] == pytest.approx(shot.release_time) and history.machine_t[-1] == shot.landing_time
    assert history.machine_q[0] == pytest.approx(history.q[-1, :2], abs=1e-9)
    at_release = frame_state(shot, shot.release_time)
    tips = [frame_state(shot, shot.release_time + dt).long_tip for dt in (0.1, 0.2, 0.4)]
    moved = [float(np.hypot(*(tip - at_release.long_tip))) for tip in tips]
    assert max(moved) > 0.2, moved   # the 70 cm arm's tip swings tens of centimetres on
    assert simulate(default_design(), dt=4e-4).history.machine_t is None


def test_the_close_up_fills_the_empty_sky_through_the_swing_and_gives_way_to_the_flight(shot):
    """Through the swing, until the projectile is about to fly, the close-up takes the largest of INSET_SCALES
    (0.54 x 0.76 of the frame: 1.8 times INSET's 0.30 x 0.42); in flight it shrinks, never
    growing back, and no frame's close-up covers the trajectory drawn in that frame (its pixels
    worked out here from the frame's own trace and the view, as in the summary box's test)."""
    from engine_model.render import INSET, INSET_LOOKAHEAD, INSET_SCALES, inset_rect, inset_rects

    times, _ = frame_times(shot, 25.0)
    states = [frame_state(shot, float(time)) for time in times]
    view = camera(shot.design, states[-1])
    rects = inset_rects(view, [state.trace for state in states])
    swing = np.flatnonzero(times < shot.release_time)[:-INSET_LOOKAHEAD]   # before it makes way for the flight
    areas = np.array([w * h for _, _, w, h in rects])
    assert areas[swing] == pytest.approx(INSET_SCALES[0] ** 2 * INSET[2] * INSET[3], rel=1e-12)
    assert areas[swing][0] > 0.4   # of the frame
    assert np.all(np.diff(areas) <= 1e-15) and areas[-1] < areas[0]
    final = inset_rect(view, states[-1].trace)
    assert areas[-1] >= final[2] * final[3] - 1e-15
    x_min, x_max, y_min, y_max = view
    for state, (left, bottom, width, height) in zip(states, rects, strict=True):
        columns = (state.trace[:, 0] - x_min) / (x_max - x_min) * FRAME_SIZE[0]
        rows = (y_max - state.trace[:, 1]) / (y_max - y_min) * FRAME_SIZE[1]
        inside = ((columns > left * FRAME_SIZE[0]) & (columns < (left + width) * FRAME_SIZE[0])
                  & (rows > (1 - bottom - height) * FRAME_SIZE[1]) & (rows < (1 - bottom) * FRAME_SIZE[1]))
        assert not inside.any(), state.time


def test_a_fixed_machines_counterweight_is_a_box_across_the_short_arm_with_no_link(shot):
    # A view of 2 m over 960 px (480 px/m) and y 2..3.125 m, the arm level at y = 2.5 m with the
    # counterweight's centre at x = 1.2 m: column 576, row 300. The box is BOX_MIN_DEPTH of the short
    # arm deep along the arm (x) and BOX_ASPECT times that across it (y); nothing dark hangs below
    # it (no link). The hinged machine's counterweight, drawn in the same place, is a round sphere.
    design = dataclasses.replace(shot.design, machine=dataclasses.replace(
        shot.design.machine, kind="fixed", counterweight_link=0.0))
    depth = BOX_MIN_DEPTH * design.machine.arm_short * 480.0
    state = FrameState(time=0.0, label="test", long_tip=np.array([0.4, 2.5]), short_tip=np.array([1.2, 2.5]),
                       counterweight=np.array([1.2, 2.5]), projectile=np.array([0.2, 2.2]),
                       sling_attached=False, trace=np.array([[0.2, 2.2]]))
    view = (0.0, 2.0, 2.0, 3.125)

    def dark_box(design):
        """Width, height and centre (px) of the dark pixels within 100 px of the counterweight (the
        header's text is elsewhere)."""
        pixels = draw_frame(design, state, view)[200:400, 476:676, :3].astype(int)
        rows, cols = np.nonzero(np.all(np.abs(pixels - 0x30) < 0x28, axis=2))
        return (cols.max() - cols.min(), rows.max() - rows.min(),
                476 + (cols.max() + cols.min()) / 2, 200 + (rows.max() + rows.min()) / 2)

    width, height, column, row = dark_box(design)
    assert (width, height) == pytest.approx((depth, BOX_ASPECT * depth), abs=3.0)
    assert (column, row) == pytest.approx((576.0, 300.0), abs=1.5)
    width, height, *_ = dark_box(shot.design)
    assert width == pytest.approx(height, abs=2.0) and width < 0.8 * BOX_ASPECT * depth
