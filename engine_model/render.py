"""Draw a shot as numbered PNG frames (and an optional GIF or MP4) off-screen with matplotlib's Agg canvas.

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

The work is split by what each part knows: ``engine_model.timeline``, what
each frame shows (plain numbers from the ``Shot``); ``engine_model.layout``,
where things go in the frame (the view, the close-up's place, pixels);
``engine_model.scene``, the matplotlib artists that draw them. This module
runs them over a shot and writes the files; the names the package documents
(``frame_times``, ``camera``, ``inset_rects``, the constants, ...) stay
importable from it.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from analytic.design import Design
from analytic.result import Shot
from engine_model.layout import (CLEARANCE_PX, FRAME_DPI, FRAME_INCHES, FRAME_SIZE, INSET, INSET_LOOKAHEAD,
                                 INSET_RIGHT_TOP, INSET_SCALES, INSET_STEPS, LABEL_ROOM, MARGIN, camera,
                                 inset_rect, inset_rects, machine_reach, machine_view, pixel, pixels_of)
from engine_model.scene import (BOLTS, BOX_ASPECT, BOX_MIN_DEPTH, COUNTERWEIGHT_DRAW_DENSITY, PROJECTILE_COLOUR,
                                PROJECTILE_MARKER_PX, SUMMARY_PLACES, SUPPORT_REACH, TRACE_POINTS,
                                WHEEL_RADIUS_FRACTION, Drawing, summary)
from engine_model.timeline import (DEFAULT_FPS, FLIGHT_SPEED, SWING_SLOW_MOTION, FrameState, end_time, frame_state,
                                   frame_times)

__all__ = ["BOLTS", "BOX_ASPECT", "BOX_MIN_DEPTH", "CLEARANCE_PX", "COUNTERWEIGHT_DRAW_DENSITY", "DEFAULT_FPS",
           "FINAL_HOLD", "FLIGHT_SPEED", "FRAME_DPI", "FRAME_INCHES", "FRAME_SIZE", "INSET", "INSET_LOOKAHEAD",
           "INSET_RIGHT_TOP", "INSET_SCALES", "INSET_STEPS", "LABEL_ROOM", "MARGIN", "PROJECTILE_COLOUR",
           "PROJECTILE_MARKER_PX", "SUMMARY_PLACES", "SUPPORT_REACH", "SWING_SLOW_MOTION", "TRACE_POINTS",
           "WHEEL_RADIUS_FRACTION", "FrameState", "camera", "draw_frame", "end_time", "frame_state", "frame_times",
           "inset_rect", "inset_rects", "machine_view", "pixel", "pixels_of", "render_shot", "summary",
           "write_gif", "write_mp4"]

#: The last frame, with the summary, held this many seconds in the GIF and the MP4.
FINAL_HOLD = 2.0


def draw_frame(design: Design, state: FrameState, view: tuple[float, float, float, float]) -> np.ndarray:
    """One frame of the whole scene (no inset) as pixels, shape (FRAME_SIZE[1], FRAME_SIZE[0], 4), RGBA uint8."""
    drawing = Drawing(design, inset=False)
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
    drawing = Drawing(shot.design, units=units)
    reach, shifts = machine_reach(shot.design), [state.frame_x for state in states]
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
