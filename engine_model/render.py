"""Draw a shot as numbered PNG frames (and an optional GIF) off-screen with matplotlib's Agg canvas.

Frames are drawn from the recorded ``Shot`` alone (coordinates, projectile path,
flight path), at fixed intervals of simulated time. The camera starts on the
machine and widens to keep the projectile's trace in view, so the last frame,
at the landing instant, shows the whole flight. The machine is drawn as it
was at release from then on (the ``Shot`` records its motion only up to
release). A rolling frame is drawn on two wheels, carried along by its
displacement, the wheels turning as they roll. Frames are deterministic: the
PNGs carry no software version or time stamp.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Circle
from matplotlib.transforms import Affine2D

from analytic.design import Design
from analytic.geometry import machine_points
from analytic.result import Shot, Stage

#: Frame size, px (FRAME_INCHES at FRAME_DPI).
FRAME_DPI = 100
FRAME_INCHES = (9.6, 5.4)
FRAME_SIZE = (960, 540)
#: Drawn colours; the projectile's is used by nothing else (tests find it by colour).
PROJECTILE_COLOUR = "#ff0000"
PROJECTILE_MARKER_PX = 9.0
#: Density used only to draw the counterweight as a sphere of its mass (cast iron), kg/m^3.
COUNTERWEIGHT_DRAW_DENSITY = 7200.0
#: Fraction of the view left around what must be seen.
MARGIN = 0.06
#: Most trace points drawn (the trace is thinned evenly beyond this).
TRACE_POINTS = 1500
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


def end_time(shot: Shot) -> float:
    """Last instant of the shot, s: the landing, or the last recorded sample of a failed shot."""
    return shot.landing_time if shot.landing_time is not None else float(shot.t[-1])


def frame_times(shot: Shot, fps: float, slow_motion: float = 1.0) -> np.ndarray:
    """Instants drawn, s: every ``1 / (fps * slow_motion)`` s of simulated time from 0, plus the end.

    Returns
    -------
    (n,) times; the last is ``end_time(shot)`` (added if not on the grid).
    """
    interval = 1.0 / (fps * slow_motion)
    end = end_time(shot)
    times = interval * np.arange(int(math.floor(end / interval + 1e-9)) + 1)
    if end - times[-1] > 1e-9 * interval:
        times = np.append(times, end)
    return times


def frame_state(shot: Shot, time: float) -> FrameState:
    """The machine and projectile at ``time`` (interpolated between recorded samples)."""
    release = shot.release_time
    in_flight = release is not None and time > release
    swing_time = min(time, float(shot.t[-1]))
    q = np.array([np.interp(swing_time, shot.t, shot.q[:, i]) for i in range(3)])
    points = machine_points(q, shot.design.machine)
    frame_x = 0.0
    if shot.design.base.rolling and len(shot.frame_x):
        frame_x = float(np.interp(swing_time, shot.t, shot.frame_x))
        points = {name: point + np.array([frame_x, 0.0]) for name, point in points.items()}
    on_machine = shot.t <= swing_time
    trace = [shot.path[on_machine]]
    if in_flight:
        flying = shot.flight_t <= time
        projectile = np.array([np.interp(time, shot.flight_t, shot.flight_path[:, i]) for i in range(2)])
        trace.append(shot.flight_path[flying])
        label = _STAGE_NAMES[Stage.FLIGHT]
    else:
        projectile = np.array([np.interp(swing_time, shot.t, shot.path[:, i]) for i in range(2)])
        stage = Stage(int(shot.stage[max(int(np.searchsorted(shot.t, swing_time, side="right")) - 1, 0)]))
        label = _STAGE_NAMES[stage]
    if not shot.ok and time >= float(shot.t[-1]):
        label = f"{label} - {shot.status.value}"
    trace.append(projectile[None, :])
    return FrameState(time, label, points["long_tip"], points["short_tip"], points["counterweight"],
                      projectile, not in_flight, np.vstack(trace), frame_x)


def camera(design: Design, state: FrameState) -> tuple[float, float, float, float]:
    """View (x_min, x_max, y_min, y_max), m: the machine's reach and the trace so far, with a
    margin, widened to the frame's aspect ratio (the base stays at the bottom)."""
    m = design.machine
    reach = max(m.arm_long + m.sling_length, m.arm_short + m.counterweight_link)
    x_min = min(state.frame_x - reach, state.trace[:, 0].min())
    x_max = max(state.frame_x + reach, state.trace[:, 0].max())
    y_min, y_max = -m.pivot_height, max(reach, state.trace[:, 1].max())
    width, height = x_max - x_min, y_max - y_min
    x_min, x_max = x_min - MARGIN * width, x_max + MARGIN * width
    y_min, y_max = y_min - MARGIN * height, y_max + MARGIN * height
    aspect = FRAME_SIZE[0] / FRAME_SIZE[1]
    width, height = x_max - x_min, y_max - y_min
    if width / height < aspect:
        extra = 0.5 * (aspect * height - width)
        x_min, x_max = x_min - extra, x_max + extra
    else:
        y_max = y_min + width / aspect
    return x_min, x_max, y_min, y_max


def pixel(view: tuple[float, float, float, float], point: np.ndarray) -> tuple[float, float]:
    """Where a point (m) falls in a frame drawn with ``view``: (column, row) in px from the top left."""
    x_min, x_max, y_min, y_max = view
    return ((point[0] - x_min) / (x_max - x_min) * FRAME_SIZE[0],
            (y_max - point[1]) / (y_max - y_min) * FRAME_SIZE[1])


class _Drawing:
    """One matplotlib Figure (Agg canvas) and its artists, updated frame by frame."""

    def __init__(self, design: Design):
        m = design.machine
        self.design = design
        self.figure = Figure(figsize=FRAME_INCHES, dpi=FRAME_DPI)
        FigureCanvasAgg(self.figure)
        ax = self.figure.add_axes((0.0, 0.0, 1.0, 1.0))
        ax.set_axis_off()
        self.axes = ax
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
        else:
            ax.plot([-foot, 0.0, foot], [-h, 0.0, -h], color="#7a6a5a", linewidth=2.5, solid_joinstyle="miter")
        self.trace, = ax.plot([], [], color="#f0a030", linewidth=1.0, linestyle=(0, (2, 2)))
        self.sling, = ax.plot([], [], color="#404040", linewidth=1.0)
        self.link, = ax.plot([], [], color="#404040", linewidth=1.5)
        self.arm, = ax.plot([], [], color="#8b5a2b", linewidth=4.0, solid_capstyle="round")
        radius = (3.0 * m.counterweight_mass / (4.0 * math.pi * COUNTERWEIGHT_DRAW_DENSITY)) ** (1.0 / 3.0)
        self.counterweight = Circle((0.0, 0.0), radius, color="#303030", zorder=3)
        ax.add_patch(self.counterweight)
        self.pivot, = ax.plot([0.0], [0.0], marker="o", color="black", markersize=4, zorder=4)
        self.projectile, = ax.plot([], [], marker="o", linestyle="none", color=PROJECTILE_COLOUR,
                                   markersize=PROJECTILE_MARKER_PX * 72.0 / FRAME_DPI, zorder=5)
        self.text = ax.text(0.01, 0.98, "", transform=ax.transAxes, va="top", ha="left",
                            family="monospace", fontsize=11)

    def draw(self, state: FrameState, view: tuple[float, float, float, float]) -> None:
        x_min, x_max, y_min, y_max = view
        self.axes.set_xlim(x_min, x_max)
        self.axes.set_ylim(y_min, y_max)
        h = self.design.machine.pivot_height
        self.base.set_data([x_min, x_max], [-h, -h])
        if self.wheels:
            x = state.frame_x
            self.frame_lines.set_data(self.frame_shape[:, 0] + x, self.frame_shape[:, 1])
            self.pivot.set_data([x], [0.0])
            for rim, spokes, centre, axle, radius in self.wheels:
                rim.center = (centre + x, axle)
                # Rolling forward (x growing) turns a wheel clockwise by x / radius.
                turn = Affine2D().rotate_around(centre, axle, -x / radius).translate(x, 0.0)
                spokes.set_transform(turn + self.axes.transData)
        self.arm.set_data([state.short_tip[0], state.long_tip[0]], [state.short_tip[1], state.long_tip[1]])
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
        self.text.set_text(f"{self.design.name}\nt = {state.time:7.4f} s  {state.label}")

    def pixels(self) -> np.ndarray:
        self.figure.canvas.draw()
        return np.asarray(self.figure.canvas.buffer_rgba()).copy()

    def save(self, path: Path) -> None:
        self.figure.savefig(path, dpi=FRAME_DPI, format="png", metadata={"Software": None})


def draw_frame(design: Design, state: FrameState, view: tuple[float, float, float, float]) -> np.ndarray:
    """One frame as pixels, shape (FRAME_SIZE[1], FRAME_SIZE[0], 4), RGBA uint8."""
    drawing = _Drawing(design)
    drawing.draw(state, view)
    return drawing.pixels()


def render_shot(shot: Shot, out_dir: str | Path, *, fps: float = 30.0, slow_motion: float = 1.0,
                gif: bool = False, progress: bool = True) -> list[Path]:
    """Write ``frame_00000.png``, ... (one per ``frame_times``) to ``out_dir``, and ``shot.gif`` if asked.

    Returns
    -------
    The frame paths, in order.
    """
    from tqdm import tqdm

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    drawing = _Drawing(shot.design)
    paths = []
    for i, time in enumerate(tqdm(frame_times(shot, fps, slow_motion), desc="frames", unit="frame",
                                  disable=not progress)):
        state = frame_state(shot, float(time))
        drawing.draw(state, camera(shot.design, state))
        path = out / f"frame_{i:05d}.png"
        drawing.save(path)
        paths.append(path)
    if gif:
        write_gif(paths, out / "shot.gif", fps)
    return paths


def write_gif(frames: list[Path], path: Path, fps: float) -> None:
    """Assemble PNG frames into a looping GIF with Pillow (installed with matplotlib)."""
    from PIL import Image

    images = [Image.open(frame).convert("RGB").convert("P", palette=Image.Palette.ADAPTIVE) for frame in frames]
    images[0].save(path, save_all=True, append_images=images[1:], duration=round(1000.0 / fps), loop=0,
                   optimize=False)
