"""Draw a shot as numbered PNG frames (and an optional GIF) off-screen with matplotlib's Agg canvas.

Frames are drawn from the recorded ``Shot`` alone (coordinates, projectile path,
flight path), time-warped: the swing in slow motion, the flight in real time,
with the playback speed shown. Every frame has one view of the whole shot, so
the ground carries a fixed scale in metres (its labels under the ground, clear
of the machine), and an inset shows the machine close up, as large as the
space the trajectory leaves: large through the swing, when the sky is still
empty, and shrinking into its corner as the projectile climbs towards it, to
the size the whole trajectory leaves by the landing (``inset_rects``); the landing is marked with
the range, and the last frame sums the shot up in a box placed where the
trajectory is not. After release the machine swings on as it moved, where the
shot kept that motion (``engine_model.simulate(..., machine_after_release=True)``,
which the ``render`` command asks for); otherwise it is drawn as it was at
release. A fixed machine's counterweight is a box bolted across the short
arm, turning with it, with no link. A rolling frame is drawn on
two wheels, carried along by its displacement, the wheels turning as they
roll. Frames are deterministic: the PNGs carry no software version or
time stamp.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Polygon
from matplotlib.transforms import Affine2D
from matplotlib.ticker import FuncFormatter

from analytic.design import Design
from analytic.geometry import machine_points
from analytic.plot_units import ShownLocator
from analytic.result import Shot, Stage
from analytic.units import display

#: Frame size, px (FRAME_INCHES at FRAME_DPI).
FRAME_DPI = 100
FRAME_INCHES = (9.6, 5.4)
FRAME_SIZE = (960, 540)
#: Drawn colours; the projectile's is used by nothing else (tests find it by colour).
PROJECTILE_COLOUR = "#ff0000"
PROJECTILE_MARKER_PX = 9.0
#: Density used only to draw the counterweight as a sphere of its mass (cast iron), kg/m^3.
COUNTERWEIGHT_DRAW_DENSITY = 7200.0
#: A fixed machine's counterweight is drawn as a box of its mass at that density, this many times
#: as wide across the arm as it is deep along it, and at least this fraction of the short arm deep
#: (a dense weight on a long arm would be a speck); its bolts at these fractions of its depth.
BOX_ASPECT = 2.0
BOX_MIN_DEPTH = 0.35
BOLTS = (-0.25, 0.25)
#: Fraction of the view left around what must be seen.
MARGIN = 0.06
#: Most trace points drawn (the trace is thinned evenly beyond this).
TRACE_POINTS = 1500
#: Playback: frames per second; the swing (under half a second) in slow motion
#: by this factor, about 3 s on screen; the flight at this multiple of real
#: time; the last frame, with the summary, held this many seconds.
DEFAULT_FPS = 25.0
SWING_SLOW_MOTION = 8.0
FLIGHT_SPEED = 1.0
FINAL_HOLD = 2.0
#: The machine's close-up: (left, bottom, width, height) as fractions of the frame: the
#: smallest, used where no larger one keeps clear of the trajectory (``INSET_SCALES``).
INSET = (0.01, 0.52, 0.30, 0.42)
#: Sizes the close-up tries, largest first, as multiples of ``INSET``'s (its top-left corner kept).
INSET_SCALES = (1.8, 1.6, 1.45, 1.3, 1.15, 1.0)
#: The top of the close-up when it goes in the top-right corner, under the header's two lines.
INSET_RIGHT_TOP = 0.86
#: Frames ahead whose trajectory each frame's close-up already keeps clear of, so that it has
#: shrunk out of the projectile's way before the projectile gets there (0.2 s of playback at 25 fps).
INSET_LOOKAHEAD = 5
#: Sizes a frame's close-up may take between its size at the landing and the largest of
#: ``INSET_SCALES``: this many, evenly spaced (the steps of its shrinking).
INSET_STEPS = 25
#: Room under the ground for the scale's labels, as a fraction of what the view must show.
LABEL_ROOM = 0.06
#: Pixels kept between a placed box (close-up, summary) and the trajectory.
CLEARANCE_PX = 8.0
#: Where the summary box may go, its centre in fractions of the frame, tried in order: the
#: empty sky above the flight first, then lower down.
SUMMARY_PLACES = ((0.5, 0.8), (0.68, 0.8), (0.82, 0.8), (0.5, 0.62), (0.82, 0.62), (0.5, 0.45), (0.82, 0.45),
                  (0.5, 0.3), (0.3, 0.3), (0.82, 0.3))
#: A floating arm's track reaches this many times ``arm_short`` each side of the guide, and the guide
#: as high above the track: past the axle's and the counterweight's travel (``arm_short`` each way).
SUPPORT_REACH = 1.4
#: A rolling frame's wheels, drawn with this radius as a fraction of the pivot
#: height (for the picture only: the model's frame has no wheel size).
WHEEL_RADIUS_FRACTION = 0.12

_STAGE_NAMES = {Stage.SLIDE: "stage 1: slide", Stage.SWING: "stage 2: swing", Stage.FLIGHT: "stage 3: flight"}


@dataclass(frozen=True)
class FrameState:
    """What one frame shows (positions in m from the pivot; each point shape (2,)).

    Attributes
    ----------
    time : s from firing.
    label : stage (or outcome) text.
    long_tip, short_tip, counterweight, projectile : part positions.
    sling_attached : draw the sling (until release).
    trace : (k, 2) projectile path so far.
    frame_x : the frame's displacement, m (0 for a fixed frame); the part
        positions already include it.
    axle_x : a floating arm's axle on its track, m from the origin (0 for the other kinds); the
        part positions already include it.
    """

    time: float
    label: str
    long_tip: np.ndarray
    short_tip: np.ndarray
    counterweight: np.ndarray
    projectile: np.ndarray
    sling_attached: bool
    trace: np.ndarray
    frame_x: float = 0.0
    axle_x: float = 0.0


def end_time(shot: Shot) -> float:
    """Last instant of the shot, s: the landing, or the last recorded sample of a failed shot."""
    return shot.landing_time if shot.landing_time is not None else float(shot.history.t[-1])


def frame_times(shot: Shot, fps: float, swing_slow_motion: float = SWING_SLOW_MOTION,
                flight_speed: float = FLIGHT_SPEED) -> tuple[np.ndarray, np.ndarray]:
    """Instants drawn and the playback speed of each (time-warped), ending at the shot's end.

    Until release a frame every ``1 / (fps * swing_slow_motion)`` s of
    simulated time (slow motion: the swing lasts under half a second); in
    flight every ``flight_speed / fps`` s.

    Returns
    -------
    times : (n,) s from firing, increasing; the last is ``end_time(shot)``.
    speed : (n,) playback speed at each frame, as a multiple of real time (< 1: slow motion).
    """
    end = end_time(shot)
    release = shot.release_time if shot.release_time is not None else math.inf
    times, speeds, time = [], [], 0.0
    while time < end - 1e-9 / fps:
        speed = 1.0 / swing_slow_motion if time < release else flight_speed
        times.append(time)
        speeds.append(speed)
        # Frames on a grid of each phase, so that the release instant starts the flight's grid.
        following = time + speed / fps
        if time < release < following:
            following = release
        time = following
    times.append(end)
    speeds.append(speeds[-1] if speeds else flight_speed)
    return np.array(times), np.array(speeds)


def frame_state(shot: Shot, time: float) -> FrameState:
    """The machine and projectile at ``time`` (interpolated between recorded samples)."""
    history = shot.history
    release = shot.release_time
    in_flight = release is not None and time > release
    swing_time = min(time, float(history.t[-1]))
    q = np.array([np.interp(swing_time, history.t, history.q[:, i]) for i in range(3)])
    frame_x = float(np.interp(swing_time, history.t, history.frame_x)) if len(history.frame_x) else 0.0
    if in_flight and history.machine_t is not None:   # the machine swinging on without its projectile
        q[:2] = [np.interp(time, history.machine_t, history.machine_q[:, i]) for i in range(2)]
        frame_x = float(np.interp(time, history.machine_t, history.machine_frame_x))
    if not shot.design.base.rolling:
        frame_x = 0.0
    axle_x = 0.0
    if shot.design.machine.kind == "floating-arm":   # the axle on its track, where the guide holds the weight
        axle_x = -shot.design.machine.arm_short * math.sin(float(q[0]))
    points = {name: point + np.array([frame_x + axle_x, 0.0])
              for name, point in machine_points(q, shot.design.machine).items()}
    on_machine = history.t <= swing_time
    trace = [history.path[on_machine]]
    if in_flight:
        flying = history.flight_t <= time
        projectile = np.array([np.interp(time, history.flight_t, history.flight_path[:, i]) for i in range(2)])
        trace.append(history.flight_path[flying])
        label = _STAGE_NAMES[Stage.FLIGHT]
    else:
        projectile = np.array([np.interp(swing_time, history.t, history.path[:, i]) for i in range(2)])
        stage = Stage(int(history.stage[max(int(np.searchsorted(history.t, swing_time, side="right")) - 1, 0)]))
        label = _STAGE_NAMES[stage]
    if shot.landing_time is not None and time >= shot.landing_time:
        label = "landed"
    elif not shot.ok and time >= float(history.t[-1]):
        label = f"{label} - {shot.status.value}"
    trace.append(projectile[None, :])
    return FrameState(time, label, points["long_tip"], points["short_tip"], points["counterweight"],
                      projectile, not in_flight, np.vstack(trace), frame_x, axle_x)


def _fit(x_min: float, x_max: float, y_min: float, y_max: float, aspect: float) -> tuple[float, ...]:
    """The box with a margin, widened to ``aspect`` (width / height), its bottom kept."""
    width, height = x_max - x_min, y_max - y_min
    x_min, x_max = x_min - MARGIN * width, x_max + MARGIN * width
    y_min, y_max = y_min - MARGIN * height, y_max + MARGIN * height
    width, height = x_max - x_min, y_max - y_min
    if width / height < aspect:
        extra = 0.5 * (aspect * height - width)
        x_min, x_max = x_min - extra, x_max + extra
    else:
        y_max = y_min + width / aspect
    return x_min, x_max, y_min, y_max


def _reach(design: Design) -> float:
    m = design.machine
    return max(m.arm_long + m.sling_length, m.arm_short + m.counterweight_link)


def camera(design: Design, state: FrameState) -> tuple[float, float, float, float]:
    """View (x_min, x_max, y_min, y_max), m: the machine's reach and ``state``'s trace, with a
    margin, widened to the frame's aspect ratio (the base stays at the bottom).

    ``render_shot`` calls it once, with the whole shot's trace, so that every
    frame has the same ground scale."""
    reach, h = _reach(design), design.machine.pivot_height
    top = max(reach, state.trace[:, 1].max())
    return _fit(min(state.frame_x - reach, state.trace[:, 0].min()),
                max(state.frame_x + reach, state.trace[:, 0].max()),
                -h - LABEL_ROOM * (top + h), top, FRAME_SIZE[0] / FRAME_SIZE[1])


def machine_view(design: Design, rect: tuple[float, float, float, float] = INSET) -> tuple[float, float, float, float]:
    """The inset's view, m: the machine's reach from the base up, at the aspect ratio of ``rect``."""
    reach, h = _reach(design), design.machine.pivot_height
    return _fit(-reach, reach, -h, reach, rect[2] * FRAME_SIZE[0] / (rect[3] * FRAME_SIZE[1]))


def _box_px(rect: tuple[float, float, float, float]) -> tuple[float, float, float, float]:
    """A rectangle in fractions of the frame (left, bottom, width, height) as pixels
    (left, top, right, bottom), rows from the top."""
    left, bottom, width, height = rect
    return (left * FRAME_SIZE[0], (1.0 - bottom - height) * FRAME_SIZE[1], (left + width) * FRAME_SIZE[0],
            (1.0 - bottom) * FRAME_SIZE[1])


def _crossed(box: tuple[float, float, float, float], points: np.ndarray) -> int:
    """How many of ``points`` ((k, 2) pixels) fall within ``CLEARANCE_PX`` of ``box`` (pixels)."""
    left, top, right, bottom = box
    inside = ((points[:, 0] > left - CLEARANCE_PX) & (points[:, 0] < right + CLEARANCE_PX)
              & (points[:, 1] > top - CLEARANCE_PX) & (points[:, 1] < bottom + CLEARANCE_PX))
    return int(np.count_nonzero(inside))


def _overlap(a: tuple[float, ...], b: tuple[float, ...]) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def inset_rect(view: tuple[float, float, float, float], trace: np.ndarray) -> tuple[float, float, float, float]:
    """The close-up's rectangle (fractions of the frame): the largest of ``INSET_SCALES`` that keeps
    clear of ``trace`` ((k, 2), m) drawn in ``view``, in the top-left corner where ``INSET`` is, or
    in the top-right one under the header; ``INSET`` where none is clear."""
    points = pixels_of(view, trace)
    left, bottom, width, height = INSET
    top = bottom + height
    for scale in INSET_SCALES:
        w, h = scale * width, scale * height
        for rect in ((left, top - h, w, h), (1.0 - left - w, INSET_RIGHT_TOP - h, w, h)):
            if rect[1] > 0.0 and not _crossed(_box_px(rect), points):
                return rect
    return INSET


def _corner_rect(rect: tuple[float, float, float, float], scale: float) -> tuple[float, float, float, float]:
    """``INSET`` at ``scale`` in the corner ``rect`` holds: its top kept, and its left side, or its right
    side for a rectangle in the frame's right half."""
    w, h = scale * INSET[2], scale * INSET[3]
    left = rect[0] if rect[0] + 0.5 * rect[2] < 0.5 else rect[0] + rect[2] - w
    return (left, rect[1] + rect[3] - h, w, h)


def inset_rects(view: tuple[float, float, float, float], traces: list[np.ndarray],
                machine: tuple[float, float, float, float] | None = None) -> list[tuple[float, ...]]:
    """Each frame's close-up (fractions of the frame), for frames whose trajectories so far are ``traces``
    (each (k, 2), m, the last the whole shot's): in the corner ``inset_rect`` picks for the whole shot,
    the largest size up to ``INSET_SCALES[0]`` clear of the trajectory ``INSET_LOOKAHEAD`` frames on
    and of the box ``machine`` ((x_min, x_max, y_min, y_max), m: where the scene draws the machine),
    never growing again once it has shrunk, and never smaller than ``inset_rect``'s."""
    final = inset_rect(view, traces[-1])
    if machine is not None:   # its corners as pixels (left, top, right, bottom)
        (left, top), (right, bottom) = pixels_of(view, np.array([[machine[0], machine[3]], [machine[1], machine[2]]]))
        machine = (left, top, right, bottom)
    smallest = final[2] / INSET[2]
    scales = np.linspace(max(INSET_SCALES[0], smallest), smallest, INSET_STEPS)
    rects, largest = [], scales[0]
    for i in range(len(traces)):
        points = pixels_of(view, traces[min(i + INSET_LOOKAHEAD, len(traces) - 1)])
        clear = next((scale for scale in scales if scale <= largest
                      and not _crossed(_box_px(_corner_rect(final, scale)), points)
                      and not (machine is not None and _overlap(_box_px(_corner_rect(final, scale)), machine))),
                     smallest)
        largest = clear
        rects.append(final if clear == smallest else _corner_rect(final, clear))
    return rects


def pixels_of(view: tuple[float, float, float, float], points: np.ndarray) -> np.ndarray:
    """``pixel`` of each of ``points`` ((k, 2), m): (k, 2) columns and rows."""
    x_min, x_max, y_min, y_max = view
    return np.column_stack([(points[:, 0] - x_min) / (x_max - x_min) * FRAME_SIZE[0],
                            (y_max - points[:, 1]) / (y_max - y_min) * FRAME_SIZE[1]])


def pixel(view: tuple[float, float, float, float], point: np.ndarray) -> tuple[float, float]:
    """Where a point (m) falls in a frame drawn with ``view``: (column, row) in px from the top left."""
    x_min, x_max, y_min, y_max = view
    return ((point[0] - x_min) / (x_max - x_min) * FRAME_SIZE[0],
            (y_max - point[1]) / (y_max - y_min) * FRAME_SIZE[1])


class _Machine:
    """The machine's artists on one axes (the whole scene, or the inset's close-up)."""

    def __init__(self, ax, design: Design, marker_px: float):
        m = design.machine
        h = m.pivot_height
        foot = 0.5 * h
        self.base, = ax.plot([], [], color="#5a4a3a", linewidth=2.0)
        self.wheels = []
        if design.base.rolling:
            # Legs down to the axles, a beam between them, and two wheels
            # whose spokes turn as they roll without slipping.
            wheel = WHEEL_RADIUS_FRACTION * h
            axle = wheel - h
            self.frame_lines, = ax.plot([], [], color="#7a6a5a", linewidth=2.5, solid_joinstyle="miter")
            self.frame_shape = np.array([[-foot, axle], [0.0, 0.0], [foot, axle], [-foot, axle]])
            for centre in (-foot, foot):
                rim = Circle((centre, axle), wheel, facecolor="none", edgecolor="#303030", linewidth=2.0,
                             zorder=2)
                spokes, = ax.plot([centre - wheel, centre + wheel, np.nan, centre, centre],
                                  [axle, axle, np.nan, axle - wheel, axle + wheel],
                                  color="#303030", linewidth=1.0, zorder=2)
                ax.add_patch(rim)
                self.wheels.append((rim, spokes, centre, axle, wheel))
            # The mark on the ground under the pivot at rest, which ranges are measured from.
            ax.plot([0.0], [-h], marker="^", color="#5a4a3a", markersize=7, zorder=1)
        elif m.kind == "floating-arm":
            _supports(ax, m)
        else:
            ax.plot([-foot, 0.0, foot], [-h, 0.0, -h], color="#7a6a5a", linewidth=2.5, solid_joinstyle="miter")
        self.trace, = ax.plot([], [], color="#f0a030", linewidth=1.0, linestyle=(0, (2, 2)))
        self.sling, = ax.plot([], [], color="#404040", linewidth=1.0)
        self.link, = ax.plot([], [], color="#404040", linewidth=1.5)
        self.arm, = ax.plot([], [], color="#8b5a2b", linewidth=4.0, solid_capstyle="round")
        self.bolted = m.kind != "hinged"   # fixed and floating arm: the counterweight bolted to the arm
        if self.bolted:
            depth = max((m.counterweight_mass / (BOX_ASPECT**2 * COUNTERWEIGHT_DRAW_DENSITY)) ** (1.0 / 3.0),
                        BOX_MIN_DEPTH * m.arm_short)
            # Corners along the arm (toward the long tip) and across it, about the counterweight's centre.
            self.box_shape = np.array([[-0.5, -0.5 * BOX_ASPECT], [0.5, -0.5 * BOX_ASPECT],
                                       [0.5, 0.5 * BOX_ASPECT], [-0.5, 0.5 * BOX_ASPECT]]) * depth
            self.bolt_shape = np.array([[f * depth, 0.0] for f in BOLTS])
            self.counterweight = Polygon(self.box_shape, closed=True, facecolor="#303030",
                                         edgecolor="#101010", zorder=3)
            self.bolts, = ax.plot([], [], marker="o", linestyle="none", color="#e0e0e0", markersize=2.0,
                                  zorder=4)
        else:
            radius = (3.0 * m.counterweight_mass / (4.0 * math.pi * COUNTERWEIGHT_DRAW_DENSITY)) ** (1.0 / 3.0)
            self.counterweight = Circle((0.0, 0.0), radius, color="#303030", zorder=3)
        ax.add_patch(self.counterweight)
        self.pivot, = ax.plot([0.0], [0.0], marker="o", color="black", markersize=4, zorder=4)
        self.projectile, = ax.plot([], [], marker="o", linestyle="none", color=PROJECTILE_COLOUR,
                                   markersize=marker_px * 72.0 / FRAME_DPI, zorder=5)
        self.ax, self.h, self.floating = ax, h, m.kind == "floating-arm"
        #: What moves from frame to frame (``_Drawing`` redraws only these over a still background;
        #: the base follows the view, with which the background is drawn again).
        self.moving = [self.trace, self.sling, self.link, self.arm, self.counterweight, self.pivot,
                       self.projectile] + ([self.bolts] if self.bolted else [])
        if self.wheels:
            self.moving += [self.frame_lines] + [artist for rim, spokes, *_ in self.wheels for artist in (rim, spokes)]

    def draw(self, state: FrameState, view: tuple[float, float, float, float]) -> None:
        x_min, x_max, y_min, y_max = view
        self.ax.set_xlim(x_min, x_max)
        self.ax.set_ylim(y_min, y_max)
        self.base.set_data([x_min, x_max], [-self.h, -self.h])
        if self.wheels:
            x = state.frame_x
            self.frame_lines.set_data(self.frame_shape[:, 0] + x, self.frame_shape[:, 1])
            self.pivot.set_data([x], [0.0])
            for rim, spokes, centre, axle, radius in self.wheels:
                rim.center = (centre + x, axle)
                # Rolling forward (x growing) turns a wheel clockwise by x / radius.
                turn = Affine2D().rotate_around(centre, axle, -x / radius).translate(x, 0.0)
                spokes.set_transform(turn + self.ax.transData)
        if self.floating:
            self.pivot.set_data([state.axle_x], [0.0])
        self.arm.set_data([state.short_tip[0], state.long_tip[0]], [state.short_tip[1], state.long_tip[1]])
        if self.bolted:
            self._draw_box(state)
        else:
            self.link.set_data([state.short_tip[0], state.counterweight[0]],
                               [state.short_tip[1], state.counterweight[1]])
            self.counterweight.center = (float(state.counterweight[0]), float(state.counterweight[1]))
        if state.sling_attached:
            self.sling.set_data([state.long_tip[0], state.projectile[0]], [state.long_tip[1], state.projectile[1]])
        else:
            self.sling.set_data([], [])
        trace = state.trace[:: max(1, len(state.trace) // TRACE_POINTS)]
        self.trace.set_data(trace[:, 0], trace[:, 1])
        self.projectile.set_data([state.projectile[0]], [state.projectile[1]])


    def _draw_box(self, state: FrameState) -> None:
        """The bolted counterweight: its box and bolts turned with the arm, about the counterweight's centre."""
        along = state.long_tip - state.short_tip
        along = along / np.hypot(*along)
        across = np.array([-along[1], along[0]])
        turn = np.column_stack([along, across])   # local (along, across) -> world
        self.counterweight.set_xy(state.counterweight + self.box_shape @ turn.T)
        bolts = state.counterweight + self.bolt_shape @ turn.T
        self.bolts.set_data(bolts[:, 0], bolts[:, 1])


def _supports(ax, machine) -> None:
    """A floating arm's track (a horizontal rail at the axle's height, on two posts to the base) and
    guide (a vertical rail along x = 0 from the base up past the counterweight's highest point)."""
    h, reach = machine.pivot_height, SUPPORT_REACH * machine.arm_short
    rail = dict(color="#7a6a5a", linewidth=2.5, solid_capstyle="butt", zorder=1)
    ax.plot([-reach, reach], [0.0, 0.0], **rail)
    ax.plot([-reach, -reach, np.nan, reach, reach], [0.0, -h, np.nan, 0.0, -h], color="#7a6a5a", linewidth=1.5,
            zorder=1)
    ax.plot([0.0, 0.0], [-h, reach], **rail)


class _Drawing:
    """One matplotlib Figure (Agg canvas): the whole scene with a ground scale in metres, the
    machine close up in an inset, the time and playback speed, the landing and a summary."""

    def __init__(self, design: Design, inset: bool = True, units: str = "metric"):
        self.design, self.units = design, units
        self.figure = Figure(figsize=FRAME_INCHES, dpi=FRAME_DPI)
        FigureCanvasAgg(self.figure)
        ax = self.figure.add_axes((0.0, 0.0, 1.0, 1.0))
        # The ground scale: metre ticks along the base, inside the frame.
        for side in ("top", "right", "left"):
            ax.spines[side].set_visible(False)
        ax.spines["bottom"].set_position(("data", -design.machine.pivot_height))
        ax.spines["bottom"].set_color("#5a4a3a")
        ax.tick_params(axis="x", direction="inout", pad=2, labelsize=8, colors="#5a4a3a")
        ax.tick_params(axis="y", left=False, labelleft=False)
        per_m, unit = display(1.0, "m", units)
        if per_m != 1.0:   # ticks at round numbers of the shown unit (analytic.plot_units)
            ax.xaxis.set_major_locator(ShownLocator(per_m))
        ax.xaxis.set_major_formatter(FuncFormatter(lambda x, _: f"{x * per_m:.6g} {unit}"))
        ax.set_facecolor("none")
        self.scene = _Machine(ax, design, PROJECTILE_MARKER_PX)
        self.landing, = ax.plot([], [], marker="v", linestyle="none", color="#2060c0", markersize=9, zorder=6)
        self.landing_text = ax.text(0.0, 0.0, "", color="#2060c0", ha="center", va="bottom", fontsize=11,
                                    fontweight="bold", zorder=6)
        # The design's name, still; under it the time, the stage and the playback speed, moving.
        ax.text(0.99, 0.98, design.name, transform=ax.transAxes, va="top", ha="right", family="monospace",
                fontsize=11)
        self.text = ax.text(0.99, 0.98 - 1.25 * 11.0 / 72.0 * FRAME_DPI / FRAME_SIZE[1], "",
                            transform=ax.transAxes, va="top", ha="right", family="monospace", fontsize=11)
        self.summary = ax.text(0.5, 0.55, "", transform=ax.transAxes, va="center", ha="center",
                               family="monospace", fontsize=12, zorder=7,
                               bbox=dict(boxstyle="round", facecolor="white", edgecolor="#808080", linewidth=1.5))
        self.inset = None
        if inset:
            inset_ax = self.figure.add_axes(INSET)
            inset_ax.set_xticks([])
            inset_ax.set_yticks([])
            for spine in inset_ax.spines.values():
                spine.set_color("#a0a0a0")
            # The inset's title belongs to the figure, so that it stays in the still background.
            self.inset_title = self.figure.text(INSET[0], INSET[1] + INSET[3] + 0.01, "the machine, close up",
                                                fontsize=9, ha="left", va="bottom", animated=True)
            self.inset = _Machine(inset_ax, design, 0.6 * PROJECTILE_MARKER_PX)
            self.inset_view = machine_view(design)
            inset_ax.set_animated(True)
        # Drawn each frame over the still background (``pixels``), in the order of a whole draw.
        self._moving = sorted(self.scene.moving + [self.landing, self.landing_text, self.text, self.summary],
                              key=lambda artist: artist.get_zorder())
        for artist in self._moving:
            artist.set_animated(True)
        self._background, self._background_view = None, None

    def layout(self, rect: tuple[float, float, float, float]) -> None:
        """Put the close-up at ``rect`` (fractions of the frame; ``inset_rects``), its title above it."""
        if self.inset is None:
            return
        self.inset.ax.set_position(rect)
        self.inset_title.set_position((rect[0], rect[1] + rect[3] + 0.01))
        self.inset_view = machine_view(self.design, rect)

    def _place_summary(self, state: FrameState, view: tuple[float, float, float, float]) -> None:
        """Put the summary box at the first of ``SUMMARY_PLACES`` clear of the trajectory, the close-up
        and the header; where none is, at the one the trajectory crosses least."""
        renderer = self.figure.canvas.get_renderer()
        points = pixels_of(view, state.trace)
        blocked = [(0.55 * FRAME_SIZE[0], 0.0, FRAME_SIZE[0], 0.1 * FRAME_SIZE[1])]   # the header, top right
        if self.inset is not None:
            rect = self.inset.ax.get_position().bounds
            blocked.append(_box_px((rect[0], rect[1], rect[2], rect[3] + 0.05)))
        best = None
        for x, y in SUMMARY_PLACES:
            self.summary.set_position((x, y))
            extent = self.summary.get_window_extent(renderer)
            box = (extent.x0, FRAME_SIZE[1] - extent.y1, extent.x1, FRAME_SIZE[1] - extent.y0)
            cost = _crossed(box, points) + 10_000 * any(_overlap(box, b) for b in blocked)
            if best is None or cost < best[0]:
                best = (cost, (x, y))
            if cost == 0:
                return
        self.summary.set_position(best[1])

    def draw(self, state: FrameState, view: tuple[float, float, float, float], speed: float | None = None,
             shot: Shot | None = None) -> None:
        self.scene.draw(state, view)
        if self.inset is not None:
            # The close-up follows a rolling frame.
            x_min, x_max, y_min, y_max = self.inset_view
            self.inset.draw(state, (x_min + state.frame_x, x_max + state.frame_x, y_min, y_max))
        playback = "" if speed is None else (f"  {1.0 / speed:g}x slow motion" if speed < 1.0
                                             else "  real time" if speed == 1.0 else f"  {speed:g}x")
        self.text.set_text(f"t = {state.time:7.4f} s  {state.label}{playback}")
        landed = shot is not None and shot.landing_time is not None and state.time >= shot.landing_time
        if landed:
            x = float(shot.landing_position[0])
            self.landing.set_data([x], [-self.design.machine.pivot_height])
            self.landing_text.set_position((x, -self.design.machine.pivot_height + 0.03 * (view[3] - view[2])))
            self.landing_text.set_text("{:.1f} {}".format(*display(shot.range, "m", self.units)))
            self.summary.set_text(summary(shot, self.units))
            self.summary.set_visible(True)
            self._place_summary(state, view)
        else:
            self.landing.set_data([], [])
            self.landing_text.set_text("")
            self.summary.set_visible(False)

    def pixels(self) -> np.ndarray:
        """The frame as drawn now, (rows, columns, 4) RGBA.

        What does not move (the ground scale, the fixed frame's legs) is
        drawn once per view and kept as a background; each frame restores it
        and draws over it what moves, in order of depth, then the inset
        whole (it lies above the scene). Measured: a quarter of drawing the
        whole figure each frame, for the same picture but where what moves
        crosses the ground scale's ticks (over them now, under them before: a few pixels).
        """
        canvas = self.figure.canvas
        view = (self.scene.ax.get_xlim(), self.scene.ax.get_ylim())
        if self._background is None or view != self._background_view:
            canvas.draw()
            self._background, self._background_view = canvas.copy_from_bbox(self.figure.bbox), view
        else:
            canvas.restore_region(self._background)
        for artist in self._moving:
            self.figure.draw_artist(artist)
        if self.inset is not None:
            self.figure.draw_artist(self.inset.ax)
            self.figure.draw_artist(self.inset_title)
        return np.asarray(canvas.buffer_rgba()).copy()

    def save(self, path: Path) -> np.ndarray:
        """Draw once, write the PNG from the canvas's pixels, and return them (RGB, contiguous).

        One draw per frame rather than two (``savefig`` would draw the figure
        again); Pillow writes no time stamp or version, so frames stay deterministic.
        """
        from PIL import Image

        pixels = self.pixels()
        # zlib's fastest level: a third of the frame's time at the default
        # level, for files about 1.3x as large (the pixels are the same). The
        # figure is opaque, so the file is RGB: 16 ms a frame instead of 20, and 13 % smaller.
        # Pillow drops the alpha channel in C; numpy's copy of the strided pixels[..., :3]
        # took 6 ms a frame, and the GIF and MP4 writers copied them again.
        rgb = Image.fromarray(pixels, "RGBA").convert("RGB")
        rgb.save(path, format="PNG", dpi=(FRAME_DPI, FRAME_DPI), compress_level=1)
        return np.asarray(rgb)


def summary(shot: Shot, units: str = "metric") -> str:
    """The last frame's box: what the shot did, in a builder's units (``metric`` or ``imperial``)."""
    def shown(value: float, unit: str) -> str:
        return "{:.2f} {}".format(*display(value, unit, units))

    lines = [f"range {shown(shot.range, 'm')}", f"release speed {shown(shot.release_speed, 'm/s')}",
             f"launch angle {math.degrees(shot.launch_angle):.1f} deg", f"apex {shown(shot.apex_height, 'm')}",
             f"flight {shot.flight_time:.2f} s"]
    return "\n".join(lines)


def draw_frame(design: Design, state: FrameState, view: tuple[float, float, float, float]) -> np.ndarray:
    """One frame of the whole scene (no inset) as pixels, shape (FRAME_SIZE[1], FRAME_SIZE[0], 4), RGBA uint8."""
    drawing = _Drawing(design, inset=False)
    drawing.draw(state, view)
    return drawing.pixels()


def render_shot(shot: Shot, out_dir: str | Path, *, fps: float = DEFAULT_FPS,
                swing_slow_motion: float = SWING_SLOW_MOTION, flight_speed: float = FLIGHT_SPEED,
                gif: bool = False, mp4: bool = False, progress: bool = True, units: str = "metric") -> list[Path]:
    """Write ``frame_00000.png``, ... (one per ``frame_times``) to ``out_dir``; ``shot.gif`` and
    ``shot.mp4`` if asked, the last frame held for ``FINAL_HOLD`` s in both.

    Every frame has the same view (the whole shot, a fixed ground scale in
    metres, or feet with ``units="imperial"``) with the machine close up in an inset.

    Returns
    -------
    The frame paths, in order.
    """
    from analytic.cli_shared import progress_bar

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    times, speeds = frame_times(shot, fps, swing_slow_motion, flight_speed)
    states = [frame_state(shot, float(time)) for time in times]
    view = camera(shot.design, states[-1])
    drawing = _Drawing(shot.design, units=units)
    reach, shifts = _reach(shot.design), [state.frame_x for state in states]
    rects = inset_rects(view, [state.trace for state in states],
                        (min(shifts) - reach, max(shifts) + reach, -shot.design.machine.pivot_height, reach))
    paths, frames = [], []
    for i, (state, speed, rect) in enumerate(progress_bar(list(zip(states, speeds, rects)), desc="frames",
                                                          unit="frame", disable=not progress, file=sys.stderr)):
        drawing.layout(rect)
        drawing.draw(state, view, float(speed), shot)
        path = out / f"frame_{i:05d}.png"
        rgb = drawing.save(path)
        paths.append(path)
        if gif or mp4:
            frames.append(rgb)
    if frames:
        frames += [frames[-1]] * int(round(FINAL_HOLD * fps))
    if gif:
        write_gif(frames, out / "shot.gif", fps, progress)
    if mp4:
        write_mp4(frames, out / "shot.mp4", fps, progress)
    return paths


def write_gif(frames: list[np.ndarray], path: Path, fps: float, progress: bool = False) -> None:
    """A looping GIF of RGB frames ((rows, columns, 3) uint8), every frame on one 256-colour palette.

    The palette is chosen once (Pillow's median cut) from the first, middle
    and last frames, which hold every colour the scene draws; each frame is
    then mapped onto it without dithering. Quantising each frame on its own
    took 20 times as long and let the colours flicker between frames.
    """
    from PIL import Image
    from analytic.cli_shared import progress_bar

    sample = np.concatenate([frames[0], frames[len(frames) // 2], frames[-1]], axis=0)
    palette = Image.fromarray(sample, "RGB").quantize(256, method=Image.Quantize.MEDIANCUT,
                                                      dither=Image.Dither.NONE)
    with progress_bar(total=len(frames) + 1, desc=f"writing {path.name}", unit="frame", disable=not progress,
              file=sys.stderr) as bar:
        images = []
        for frame in frames:
            images.append(Image.fromarray(frame, "RGB").quantize(palette=palette, dither=Image.Dither.NONE))
            bar.update()
        images[0].save(path, format="GIF", save_all=True, append_images=images[1:],
                       duration=round(1000.0 / fps), loop=0)
        bar.update()


def write_mp4(frames: list[np.ndarray], path: Path, fps: float, progress: bool = False) -> None:
    """An H.264 MP4 of RGB frames through imageio-ffmpeg's packaged ffmpeg (no system install).

    x264's ``veryfast`` preset: these flat, mostly still frames gain nothing from the slower
    presets' motion searches, which cost time and, here, give no smaller file.
    """
    import imageio_ffmpeg
    from analytic.cli_shared import progress_bar

    rows, columns = frames[0].shape[:2]
    writer = imageio_ffmpeg.write_frames(str(path), (columns, rows), fps=fps, codec="libx264",
                                         macro_block_size=2, ffmpeg_log_level="error",
                                         output_params=["-fflags", "+bitexact", "-preset", "veryfast"])
    writer.send(None)
    for frame in progress_bar(frames, desc=f"writing {path.name}", unit="frame", disable=not progress, file=sys.stderr):
        writer.send(np.ascontiguousarray(frame))
    writer.close()
