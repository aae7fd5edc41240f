"""A shot as the page draws it: ``simulate --json``'s object plus the sampled motion (``history``)."""

from __future__ import annotations

from typing import Any

import numpy as np

from analytic.design import Design
from analytic.fast import simulate_fast
from analytic.geometry import machine_points
from analytic.fast.motion import Motion, simulate_motion
from analytic.reference import FLIGHT_OUTPUT_STEP, SWING_OUTPUT_STEP
from analytic.result import History, Shot
from analytic.summary import FLIGHT_LOSSES, LOSS_LABELS, present_losses, summary_rows

#: Decimals kept of a position (m) and a time (s) in ``history``: 10 um and 1 us, far below a
#: pixel of the stage at any preset's scale, and a third of the digits of a full float.
POSITION_DECIMALS = 5
TIME_DECIMALS = 6
#: The parts the stage draws, in ``analytic.geometry.PARTS`` names.
DRAWN_PARTS = ("long_tip", "short_tip", "counterweight", "projectile")


#: Spacings of the stage's history the page asks for, s (``simulate``'s ``sample_step`` and
#: ``flight_sample_step``). The page draws at the screen's rate and interpolates linearly between
#: samples: 2 ms through the swing is a sample about every frame at 1/10 speed. Drawn so, every
#: preset's arm tips, counterweight and projectile stay within 0.4 mm of the reference path's own
#: 0.5 ms samples through the swing and 1.3 mm of its 5 ms ones in flight: under half a pixel of the
#: following camera on a 900-pixel stage (``tests/test_workbench_api.py`` checks it), at a
#: quarter of the samples.
PAGE_SAMPLE_STEP = 2e-3
PAGE_FLIGHT_SAMPLE_STEP = 2e-2
#: The spacings a request may ask for, s: no finer than the reference path's own, no coarser
#: than would leave a swing with a handful of samples.
SAMPLE_STEP_BOUNDS = {"sample_step": (SWING_OUTPUT_STEP, 0.02), "flight_sample_step": (FLIGHT_OUTPUT_STEP, 0.2)}


def shot_json(design: Design, sample_step: float | None = None,
              flight_sample_step: float | None = None) -> dict[str, Any]:
    """The answer of ``POST /api/shot``: the keys of ``python -m analytic simulate --json``,
    ``summary`` (``summary_json_rows``) and ``history`` (``history_json``), its samples
    ``sample_step`` and ``flight_sample_step`` apart (None: the reference path's own).

    From the compiled path with its motion recorded (``analytic.fast.motion.simulate_motion``): the
    same numbers and samples as the reference shot to round-off, but for ``min_sling_tension``,
    ``min_ground_force``, ``max_frame_speed`` and a rolling frame's place at landing, which it
    does not sample (null), without the reference path's integration in Python."""
    shot, motion = simulate_motion(design, sample_step=sample_step, flight_sample_step=flight_sample_step)
    return {**shot.to_json(), "summary": summary_json_rows(shot), "history": history_json(shot, motion=motion)}


def summary_json_rows(shot: Shot) -> list[dict[str, Any]]:
    """The shot's summary rows (``analytic.summary.summary_rows``, what ``simulate`` prints), each
    ``Row.to_json``: the page shows them converting each value by its ``kind``."""
    return [row.to_json() for row in summary_rows(shot)]


def summary_json(design: Design) -> dict[str, Any]:
    """The answer of ``POST /api/summary``: the same keys from the compiled fast path (no
    histories, so no efficiencies nor energies), and its ``summary`` rows."""
    shot = simulate_fast(design)
    return {**shot.to_json(), "summary": summary_json_rows(shot)}


def _rounded(values: np.ndarray, decimals: int) -> list:
    return np.round(np.asarray(values, dtype=float), decimals).tolist()


def _every(t: np.ndarray, step: float | None) -> np.ndarray | slice:
    """Indices of the samples of ``t`` about ``step`` apart (the first in each ``step`` of time,
    and the last sample); all of them for None."""
    if step is None or len(t) < 2:
        return slice(None)
    starts = np.flatnonzero(np.diff(np.floor(np.asarray(t) / step))) + 1
    return np.unique(np.concatenate([[0], starts, [len(t) - 1]]))


def history_json(shot: Shot, sample_step: float | None = None, flight_sample_step: float | None = None, *,
                 motion: Motion | None = None) -> dict[str, Any] | None:
    """The sampled motion in ground coordinates (m from the pivot at rest, s from firing),
    thinned to about ``sample_step`` and ``flight_sample_step`` (s; None: every sample), for a
    shot sampled finely (the engine model's, on each of its steps).

    ``t`` (n,) and, on it, ``stage``, ``frame_x`` (n,) (zeros for a fixed frame) and each
    part of ``DRAWN_PARTS`` (n, 2) relative to the pivot; ``flight_t`` (k,) and
    ``flight_path`` (k, 2); ``energy`` (J): ``released``, the potential energy counterweight and
    arm gave up by release, and of it ``projectile`` (the projectile's energy at release),
    ``sling`` (the sling's and the pouch's, ``Shot.sling_energy_at_release``: 0 for a massless
    sling) and ``kept`` (the arm's and counterweight's motion then); None where the shot did not
    release; and ``parts`` (``energy_parts``), what the energy bar draws.
    The samples are ``motion``'s if given, else ``shot.history``'s.
    """
    history = shot.history if motion is None else motion
    if history is None:
        return None
    keep, flown = _every(history.t, sample_step), _every(history.flight_t, flight_sample_step)
    points = machine_points(history.q[keep], shot.design.machine)
    frame_x = history.frame_x if len(history.frame_x) == len(history.t) else np.zeros(len(history.t))
    released = shot.release_time is not None and shot.counterweight_energy_released is not None
    sling = shot.sling_energy_at_release or 0.0
    # the machine's energy counts from the start: its motion at release less the energy given up;
    # it holds the sling's and the pouch's, shown apart.
    kept = float(_machine_energy(history) + shot.counterweight_energy_released - sling) if released else None
    energy = {"released": shot.counterweight_energy_released,
              "projectile": shot.projectile_energy_at_release if released else None,
              "sling": sling if released else None, "kept": kept}
    return {
        "t": _rounded(history.t[keep], TIME_DECIMALS),
        "stage": [int(s) for s in history.stage[keep]],
        "frame_x": _rounded(frame_x[keep], POSITION_DECIMALS),
        "parts": {name: _rounded(points[name], POSITION_DECIMALS) for name in DRAWN_PARTS},
        "flight_t": _rounded(history.flight_t[flown], TIME_DECIMALS),
        "flight_path": _rounded(history.flight_path[flown], POSITION_DECIMALS),
        "energy": {**energy, "parts": energy_parts(shot, energy)},
    }


def energy_parts(shot: Shot, energy: dict[str, float | None]) -> list[dict[str, Any]]:
    """Where the energy the counterweight and arm released went, as the page's bar draws it, each
    ``{"name", "label", "joules"}``: the projectile (what it still has on landing), what the air took
    of it in flight, the sling and the pouch, the arm's and counterweight's motion, then each other
    loss the design has (``analytic.summary.present_losses``: the frictions, the drag before
    release). They share out ``energy["released"]``; [] for a shot that did not release."""
    if energy["projectile"] is None or not energy["released"] or shot.energy_dissipated is None:
        return []
    lost = shot.energy_dissipated
    flight = sum(lost[name] for name in FLIGHT_LOSSES)
    parts = [("projectile", "projectile", energy["projectile"] - flight),
             *((name, LOSS_LABELS[name], lost[name]) for name in FLIGHT_LOSSES),
             ("sling", "sling and pouch", energy["sling"]), ("kept", "arm and counterweight", energy["kept"]),
             *((name, LOSS_LABELS[name], lost[name]) for name in present_losses(shot) if name not in FLIGHT_LOSSES)]
    return [{"name": name, "label": label, "joules": float(joules)} for name, label, joules in parts]


def _machine_energy(history: History | Motion) -> float:
    """The machine's energy at release over its energy at rest, J (the last sample's)."""
    return history.machine_energy_at_release if isinstance(history, Motion) else history.energy.machine[-1]
