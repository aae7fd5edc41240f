"""What each frame of a drawn shot shows: the instants drawn, time-warped, and the machine's state at each.

The swing plays in slow motion and the flight in real time (``frame_times``);
at each instant the machine and the projectile are where the recorded ``Shot``
puts them, interpolated between its samples (``frame_state``): after release,
the machine as it swung on where the shot kept that motion, else as it was at
release. Plain numbers only: drawing them is ``engine_model.scene``'s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic.geometry import machine_points
from analytic.result import Shot, Stage

#: Playback: frames per second; the swing (under half a second) in slow motion
#: by this factor, about 3 s on screen; the flight at this multiple of real
#: time.
DEFAULT_FPS = 25.0
SWING_SLOW_MOTION = 8.0
FLIGHT_SPEED = 1.0

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
    sling_end : after release, where the end of a sling with mass or a pouch is as it swings on
        (``analytic.design.Machine.sling_mass``, ``pouch_mass``); None otherwise.
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
    sling_end: np.ndarray | None = None


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
        # With its sling's angle where a sling with mass or a pouch swings on too.
        swinging = history.machine_q.shape[1]
        q[:swinging] = [np.interp(time, history.machine_t, history.machine_q[:, i]) for i in range(swinging)]
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
    machine = shot.design.machine
    sling_end = points["projectile"] if in_flight and (machine.sling_mass > 0.0 or machine.pouch_mass > 0.0) else None
    return FrameState(time, label, points["long_tip"], points["short_tip"], points["counterweight"],
                      projectile, not in_flight, np.vstack(trace), frame_x, axle_x, sling_end)
