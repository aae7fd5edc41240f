"""What a shot produced: ``Shot`` (one design; its ``History`` when one was recorded) and ``Shots`` (many, as arrays)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import Any, Callable, Sequence

import numpy as np

from analytic.design import Design
from analytic.outcome import LOSS_NAMES, Stage, Status
from analytic.plausibility import plausibility_warnings
from analytic.data.strength import bending_stress, safety_factor
from analytic.summary import hinge_load_label, origin_label, row_text, summary_rows

__all__ = ["EnergyBudget", "History", "JSON_KEYS", "LOSS_NAMES", "PEAK_NAMES", "SHOT_COLUMNS", "Shot", "Shots",
           "Stage", "Status", "arrow_table", "hinge_load_label", "ideal_range", "origin_label"]


#: The peak loads over stages 1-2, each a ``Shot`` field (and ``<name>_time``), in the order of
#: ``analytic.stages.LOAD_NAMES``: N, N, N, m/s^2, N m.
PEAK_NAMES = ("peak_axle_load", "peak_hinge_load", "peak_sling_tension", "peak_projectile_acceleration",
              "peak_arm_bending_moment")
#: Keys of the ``--json`` object, shared by ``analytic`` and ``engine_model``.
JSON_KEYS = (
    "design", "status", "message", "liftoff_time", "release_time",
    "release_position", "release_velocity", "release_speed", "launch_angle",
    "range", "range_from_release", "apex_height", "flight_time", "landing_time",
    "landed_behind_pivot", "energy_efficiency", "range_efficiency", "min_sling_tension",
    "frame_release_displacement", "frame_release_velocity", "frame_landing_displacement",
    *(f"{name}{suffix}" for name in PEAK_NAMES for suffix in ("", "_time")),
    "energy_dissipated", "warnings",
    "peak_arm_stress", "arm_safety_factor", "projectile_survives",
)
#: Keys a floating-arm machine's ``--json`` object has besides ``JSON_KEYS`` (absent for other kinds).
FLOATING_JSON_KEYS = ("min_track_force", "max_track_force", "max_guide_force", "axle_displacement_at_release")


@dataclass(frozen=True)
class EnergyBudget:
    """Mechanical energy through stages 1 and 2, J; each array has shape (n,) on ``History.t``.

    ``projectile`` is kinetic plus potential energy of the projectile relative to
    its start; ``machine`` likewise for arm and counterweight (and the sling and the pouch,
    which stay on the machine at release), and a rolling frame's kinetic energy (negative as the counterweight falls); ``total =
    projectile + machine`` is conserved by the ideal machine (drag acts only in
    flight). ``dissipated`` maps the friction losses (``outcome.friction_work_names``:
    axle, hinge, base; a floating arm's axle, guide, track) to the work each has taken so far, (n,) J, zeros
    for the ideal machine: ``total + sum(dissipated) = 0`` (the energy audit).
    """

    projectile: np.ndarray
    machine: np.ndarray
    total: np.ndarray
    dissipated: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def lost(self) -> np.ndarray:
        """(n,) J: the work all friction has taken so far (0 if none is recorded)."""
        return sum(self.dissipated.values(), np.zeros_like(self.total))


@dataclass(frozen=True)
class History:
    """A shot's motion sampled through stages 1-2 and its flight (``Shot.history``).

    Positions are in ground coordinates, m from the pivot's position at rest,
    as ``Shot``'s. n samples through stages 1-2 (the last is the release
    instant, or the failure's), k through the flight.

    Attributes
    ----------
    t : (n,) sample times, s from firing.
    stage : (n,) int, the ``Stage`` of each sample (1 or 2).
    q, qdot : (n, 3) coordinates [theta, phi, psi] (rad) and their rates (rad/s).
    path : (n, 2) projectile centre, m.
    sling_tension : (n,) N.
    energy : ``EnergyBudget`` on ``t``.
    frame_x : (n,) the frame's X on ``t``, m (a floating arm's: its axle's x_A); (0,) for a fixed frame in the
        analytic model.
    flight_t : (k,) flight sample times, s from firing; (0,) if the projectile never flew.
    flight_path : (k, 2) projectile centre in flight, m.
    axle_load, hinge_load, projectile_acceleration, arm_bending_moment : (n,) the loads on ``t``
        (N, N, m/s^2, N m; the bending moment's magnitude), or
        None where they are not recorded (the engine model; ``simulate(sampled_loads=False)``).
    machine_t, machine_q, machine_frame_x : the machine without its projectile from release to
        landing: (m,) times, s from firing; (m, 2) [theta, phi], rad ((m, 3) [theta, phi, psi] where a
        sling with mass or a pouch swings on with it); (m,) the frame's X, m.
        None unless asked for (the engine's ``simulate(machine_after_release=True)``, for drawing).
    """

    t: np.ndarray
    stage: np.ndarray
    q: np.ndarray
    qdot: np.ndarray
    path: np.ndarray
    sling_tension: np.ndarray
    energy: EnergyBudget
    frame_x: np.ndarray
    flight_t: np.ndarray
    flight_path: np.ndarray
    axle_load: np.ndarray | None = None
    hinge_load: np.ndarray | None = None
    projectile_acceleration: np.ndarray | None = None
    arm_bending_moment: np.ndarray | None = None
    machine_t: np.ndarray | None = None
    machine_q: np.ndarray | None = None
    machine_frame_x: np.ndarray | None = None


@dataclass(frozen=True, init=False)
class Shot:
    """The outcome of simulating one design.

    Scalars are SI (s, m, m/s, J, N); angles are radians. A field the shot
    never reached is ``None`` (never NaN): e.g. ``release_time`` is ``None``
    when ``status`` is ``NEVER_RELEASES``. ``history`` is None for a
    summary-only shot (the fast path, or ``simulate(histories=False)``).

    Positions and velocities are in ground coordinates, m from the pivot's
    position at rest (a mark on the ground); for a fixed frame that is the
    pivot itself. A rolling frame carries the pivot X along (``frame_*``).

    Attributes
    ----------
    design : the design simulated.
    status, message : how it ended, in words a user can act on.
    liftoff_time, release_time, landing_time : s from firing, or None.
    release_position : (2,) projectile centre at release [x, y], m from the pivot at rest.
    release_velocity : (2,) projectile velocity at release [vx, vy] over the ground, m/s.
    landing_position : (2,) where the projectile reaches base level, m from the pivot at rest.
    apex_height : highest point of the flight above the base, m.
    min_sling_tension : smallest sling tension in stages 1 and 2, N (negative: the rigid sling pushed).
    history : the sampled motion, energies and loads (``History``), or None where none was
        recorded (the fast path, ``simulate(histories=False)``).
    counterweight_energy_released : J, potential energy given up by counterweight
        and arm between firing and release.
    projectile_energy_at_release : J, the projectile's kinetic and potential energy at
        release over its energy at rest (None where not computed: the fast path's summary).
    sling_energy_at_release : J, the sling's and the pouch's kinetic and potential energy at
        release over their energy at rest: what the counterweight gave them, which stays on the
        machine, not the projectile's (``analytic.eom.sling_energy``); 0 for a massless sling and
        pouch, None where not computed, as ``projectile_energy_at_release``.
    frame_release_displacement, frame_release_velocity : the frame's X (m) and X' (m/s)
        at release: 0 for a fixed frame, None if not released. A floating arm's frame stands
        still; these hold its axle's x_A (from the guide) and x_A', as ``max_frame_speed`` its
        axle's largest speed along the track.
    frame_landing_displacement, frame_landing_velocity : the same at the projectile's landing
        time (the machine swings on after release, its joints' friction with it): 0 for a
        fixed frame, None if not landed or not computed (the fast path; the reference path's
        summary unless asked, ``analytic.reference.simulate``'s ``after_release``).
    max_frame_speed : largest ``|X'|`` from firing to landing, m/s (None where not computed).
    peak_axle_load, peak_hinge_load : largest force of the frame on the arm at the axle and
        between the arm and the counterweight at the hinge (a fixed machine's: at its mount), N,
        through stages 1-2 (``analytic.eom.loads``: the sizes a bearing's friction would scale with).
    peak_sling_tension : largest sling tension through stages 1-2, N.
    peak_projectile_acceleration : largest acceleration the projectile feels (the sling's
        and the base's force on it over its mass, gravity excluded), m/s^2.
    peak_arm_bending_moment : largest magnitude of the bending moment the arm's cross-section at
        the axle carries through stages 1-2, N m (``analytic.eom.arm_bending_moment``: the long
        side as a uniform rod, ``analytic.geometry.arm_long_side``).
    peak_*_time : when each peak occurs, s from firing. None for a machine that never
        fires or a failed integration (the engine model: ``engine_model.loads``).
    min_ground_force : smallest vertical push of the ground on the frame through stages
        1-2, N (``analytic.eom.ground_force``; None for a summary). Negative: a
        frame not bolted down would jump.
    min_track_force, max_track_force : a floating arm's track's smallest and largest vertical
        force on the axle through stages 1-2, N (negative: the captured axle is pulled down);
        sampled at the history's points (``analytic.floating_arm.support_forces``); None for
        other kinds and for a summary.
    max_guide_force : a floating arm's guide's largest horizontal force on the counterweight
        (magnitude) through stages 1-2, N, sampled as the track's; None likewise.
    warnings : what the user should know about this result, in words, () if nothing:
        one line per implausible input (``analytic.plausibility``, added on
        construction for every model) after any the model itself gave (for
        example a rolling frame that would jump).
    diagnostics : how far the model that made the shot can be trusted, or None
        (the engine model's ``EngineDiagnostics``).
    energy_dissipated : J taken by each loss from firing to the shot's end, keyed
        ``LOSS_NAMES`` (zeros where a loss is absent): friction up to release (or the
        failure), the drag's work in flight (``analytic.reference.drag_work``) and before
        release (``swing_drag``, ``analytic.reference.swing_drag_work``); None
        where not computed (the fast path).
    """

    design: Design
    status: Status
    message: str
    liftoff_time: float | None = None
    release_time: float | None = None
    landing_time: float | None = None
    release_position: np.ndarray | None = None
    release_velocity: np.ndarray | None = None
    landing_position: np.ndarray | None = None
    apex_height: float | None = None
    min_sling_tension: float | None = None
    energy_dissipated: dict[str, float] | None = None
    counterweight_energy_released: float | None = None
    projectile_energy_at_release: float | None = None
    frame_release_displacement: float | None = None
    frame_release_velocity: float | None = None
    frame_landing_displacement: float | None = None
    frame_landing_velocity: float | None = None
    max_frame_speed: float | None = None
    history: History | None = None
    min_ground_force: float | None = None
    peak_axle_load: float | None = None
    peak_axle_load_time: float | None = None
    peak_hinge_load: float | None = None
    peak_hinge_load_time: float | None = None
    peak_sling_tension: float | None = None
    peak_sling_tension_time: float | None = None
    peak_projectile_acceleration: float | None = None
    peak_projectile_acceleration_time: float | None = None
    peak_arm_bending_moment: float | None = None
    peak_arm_bending_moment_time: float | None = None
    min_track_force: float | None = None
    max_track_force: float | None = None
    max_guide_force: float | None = None
    sling_energy_at_release: float | None = None
    warnings: tuple[str, ...] = ()
    diagnostics: Any = None

    def __init__(self, design: Design, status: Status, message: str, **results):
        """A shot of ``design``: its ``status`` and ``message``, and any other field (the
        attributes above) by keyword; a field not given is None (``warnings``: none).

        The dataclass's own ``__init__`` would set each of a frozen class's fields through its
        own ``object.__setattr__`` call, most of the time a fast-path shot spends outside its
        compiled kernel; this one fills the instance's ``__dict__`` at once, with the same
        fields and the same refusal of an unknown one.
        """
        if not _SHOT_DEFAULTS.keys() >= results.keys():
            unknown = ", ".join(sorted(results.keys() - _SHOT_DEFAULTS.keys()))
            raise TypeError(f"Shot() got unexpected keyword arguments: {unknown}")
        attributes = self.__dict__
        attributes.update(design=design, status=status, message=message)
        attributes.update(_SHOT_DEFAULTS)
        attributes.update(results)
        self.__post_init__()

    def __post_init__(self):
        # The model's own warnings first, then the plausibility checks; a copy
        # (dataclasses.replace) passes them all back in, so keep each once.
        lines = tuple(self.warnings) + plausibility_warnings(self.design, self)
        if lines or self.warnings != ():
            object.__setattr__(self, "warnings", tuple(dict.fromkeys(lines)))
        if self.energy_dissipated is not None and not set(LOSS_NAMES) <= set(self.energy_dissipated):
            # A model may leave out a loss it does not have: none taken.
            object.__setattr__(self, "energy_dissipated", {**dict.fromkeys(LOSS_NAMES, 0.0),
                                                           **self.energy_dissipated})

    @property
    def axle_displacement_at_release(self) -> float | None:
        """A floating arm's axle's x at release, m from the guide (``x_A = -Lb sin theta``, carried as
        ``frame_release_displacement``); None for other kinds or if not released."""
        return self.frame_release_displacement if self.design.machine.kind == "floating-arm" else None

    @property
    def ok(self) -> bool:
        return self.status is Status.OK

    @property
    def peak_arm_stress(self) -> float | None:
        """The peak bending stress in the arm, Pa, at the section of its peak bending moment (the axle's):
        ``6 M / (width depth^2)`` of the design's ``arm_section`` (``analytic.data.strength.bending_stress``);
        None without a section or a peak moment."""
        section, moment = self.design.machine.arm_section, self.peak_arm_bending_moment
        if section is None or moment is None or not math.isfinite(moment):
            return None
        return bending_stress(moment, section.width, section.depth)

    @property
    def arm_safety_factor(self) -> float | None:
        """The arm's strength (its material's, or as given) over ``peak_arm_stress``: above 1 it holds;
        None without a strength or a stress."""
        stress = self.peak_arm_stress
        strength = None if stress is None else self.design.machine.arm_section.bending_strength
        return None if strength is None else safety_factor(stress, strength)

    @property
    def projectile_survives(self) -> bool | None:
        """Whether the projectile's peak acceleration stays within its limit
        (``Projectile.acceleration_limit``); None without a limit or a peak acceleration."""
        limit, peak = self.design.projectile.acceleration_limit, self.peak_projectile_acceleration
        if limit is None or peak is None or not math.isfinite(peak):
            return None
        return bool(peak <= limit)

    def _repr_html_(self) -> str:
        """A summary table for Jupyter: the outcome, the rows of ``analytic.summary.summary_rows``
        (metric), any warnings."""
        import html

        rows = [("status", f"{self.status.value}: {self.message}")]
        rows += [(row.label, " ".join(row_text(row))) for row in summary_rows(self)]
        rows += [("warning", warning) for warning in self.warnings]
        body = "".join(f"<tr><th style='text-align:left'>{html.escape(label)}</th>"
                       f"<td style='text-align:left'>{html.escape(value)}</td></tr>" for label, value in rows)
        return f"<table><caption>Shot of {html.escape(self.design.name)}</caption>{body}</table>"

    def plot(self, path=None, **options):
        """The shot's figure (``analytic.plot.shot_figure``); written to ``path`` if given.

        Returns the ``matplotlib.figure.Figure``, which Jupyter shows inline.
        """
        from analytic import plot

        figure = plot.shot_figure(self)
        if path is not None:
            plot.save_figure(figure, path, **options)
        return figure

    @property
    def release_speed(self) -> float | None:
        return None if self.release_velocity is None else float(np.hypot(*self.release_velocity))

    @property
    def launch_angle(self) -> float | None:
        """Velocity direction at release above the horizontal, rad."""
        if self.release_velocity is None:
            return None
        return float(math.atan2(self.release_velocity[1], self.release_velocity[0]))

    @property
    def range(self) -> float | None:
        """Horizontal distance from the pivot's position at rest to the landing point, m
        (negative: behind it)."""
        return None if self.landing_position is None else float(self.landing_position[0])

    @property
    def range_from_release(self) -> float | None:
        if self.landing_position is None or self.release_position is None:
            return None
        return float(self.landing_position[0] - self.release_position[0])

    @property
    def flight_time(self) -> float | None:
        if self.landing_time is None or self.release_time is None:
            return None
        return self.landing_time - self.release_time

    @property
    def landed_behind_pivot(self) -> bool | None:
        return None if self.range is None else self.range < 0.0

    @property
    def energy_efficiency(self) -> float | None:
        """Projectile energy at release / potential energy released by counterweight and arm."""
        if (self.projectile_energy_at_release is None or self.release_time is None
                or not self.counterweight_energy_released):
            return None
        return float(self.projectile_energy_at_release / self.counterweight_energy_released)

    @property
    def range_efficiency(self) -> float | None:
        """Range / the vacuum range at 45 deg if the counterweight's whole available drop
        went into the projectile: ``2 m_w drop / m_p`` with ``drop`` from its start height
        to its lowest reachable point (``arm_short + counterweight_link`` below the pivot)."""
        if self.range is None:
            return None
        return self.range / ideal_range(self.design)

    def to_json(self) -> dict[str, Any]:
        """The ``--json`` object (keys ``JSON_KEYS``); angles in degrees, ``None`` where not reached."""
        def number(value: float | None) -> float | None:
            return None if value is None else float(value)

        def pair(value: np.ndarray | None) -> list[float] | None:
            return None if value is None else [float(v) for v in value]

        angle = self.launch_angle
        return {
            "design": self.design.name,
            "status": self.status.value,
            "message": self.message,
            "liftoff_time": number(self.liftoff_time),
            "release_time": number(self.release_time),
            "release_position": pair(self.release_position),
            "release_velocity": pair(self.release_velocity),
            "release_speed": number(self.release_speed),
            "launch_angle": None if angle is None else math.degrees(angle),
            "range": number(self.range),
            "range_from_release": number(self.range_from_release),
            "apex_height": number(self.apex_height),
            "flight_time": number(self.flight_time),
            "landing_time": number(self.landing_time),
            "landed_behind_pivot": self.landed_behind_pivot,
            "energy_efficiency": number(self.energy_efficiency),
            "range_efficiency": number(self.range_efficiency),
            "min_sling_tension": number(self.min_sling_tension),
            "frame_release_displacement": number(self.frame_release_displacement),
            "frame_release_velocity": number(self.frame_release_velocity),
            "frame_landing_displacement": number(self.frame_landing_displacement),
            **{f"{name}{suffix}": number(getattr(self, f"{name}{suffix}"))
               for name in PEAK_NAMES for suffix in ("", "_time")},
            "energy_dissipated": (None if self.energy_dissipated is None
                                  else {name: float(self.energy_dissipated[name]) for name in LOSS_NAMES}),
            "warnings": list(self.warnings),
            "peak_arm_stress": number(self.peak_arm_stress),
            "arm_safety_factor": number(self.arm_safety_factor),
            "projectile_survives": self.projectile_survives,
            **({name: number(getattr(self, name)) for name in FLOATING_JSON_KEYS}
               if self.design.machine.kind == "floating-arm" else {}),
        }


#: Each ``Shot`` field after ``message``, with its default (``Shot.__init__``): all plain values, no
#: factories, so one dict serves every shot.
_SHOT_DEFAULTS = {f.name: f.default for f in fields(Shot)[3:]}


def ideal_range(design: Design) -> float:
    """Vacuum range at 45 deg if the counterweight's available drop all went into the projectile, m.

    The counterweight starts hanging plumb from the raised short-arm tip (the long
    arm's on the trough, ``asin((h - trough_height) / arm_long)`` below horizontal) and can
    at most fall to ``arm_short + counterweight_link`` below the pivot, so
    ``E = m_w g drop`` and ``R = v^2 / g = 2 E / (m_p g) = 2 m_w drop / m_p``.
    """
    m = design.machine
    start = math.asin((m.pivot_height - design.base.trough_height) / m.arm_long)
    start_height = m.arm_short * math.sin(start) - m.counterweight_link
    drop = start_height + m.arm_short + m.counterweight_link
    return 2.0 * m.counterweight_mass * drop / design.projectile.mass


#: The columns of a table of shots (``Shots.columns``, ``Shots.to_arrow``, a sweep's Parquet files),
#: in order, each with its numpy dtype: ``status`` is the ``Status`` value as text; the rest are
#: SI (NaN where a shot did not get there), the release position and velocity by component, and
#: the launch angle (rad, ``Shot.launch_angle``: under the ideal rule, the pin to set).
SHOT_COLUMNS = {
    "status": np.str_, "range": np.float64, "liftoff_time": np.float64, "release_time": np.float64,
    "landing_time": np.float64, "release_x": np.float64, "release_y": np.float64, "release_vx": np.float64,
    "release_vy": np.float64, "launch_angle": np.float64, "apex_height": np.float64, "end_time": np.float64,
    "steps": np.int64, "evaluations": np.int64, **{f"{name}{suffix}": np.float64 for name in PEAK_NAMES for suffix in ("", "_time")},
}


@dataclass(frozen=True)
class Shots:
    """Results of many shots, one row per design (``analytic.fast.shoot``).

    Every array has the designs along its first axis, of length S; a quantity
    a shot never reached is NaN. ``len(shots)`` is S; ``shots[i]`` is design
    i's ``Shot`` (as ``analytic.fast.simulate_fast`` gives it: no history), for
    shots of ``Design`` objects (shots of packed kernel rows know no designs).

    Attributes
    ----------
    status : (S,) object, each a ``Status``.
    liftoff_time, release_time, landing_time : (S,) s from firing.
    release_position, release_velocity : (S, 2) m and m/s from the pivot.
    range : (S,) m from the pivot to the landing point.
    apex_height : (S,) m above the base.
    end_time : (S,) s, when the shot ended (the failure's instant for a failure).
    steps, evaluations : (S,) int, accepted integrator steps and right-hand-side evaluations (with
        the evaluations of the accelerations that finding the peak loads takes).
    peak_axle_load, peak_hinge_load, peak_sling_tension, peak_projectile_acceleration, peak_arm_bending_moment : (S,)
        the largest loads through stages 1-2 (N, N, N, m/s^2, N m; ``Shot``), and each one's
        ``*_time`` (S,), s.
    designs : the S designs shot, or None (shot from packed rows).
    shot_at : ``shot_at(i)``, design i's ``Shot``, from the path that made these shots; None with
        ``designs``.
    """

    status: np.ndarray
    liftoff_time: np.ndarray
    release_time: np.ndarray
    landing_time: np.ndarray
    release_position: np.ndarray
    release_velocity: np.ndarray
    range: np.ndarray
    apex_height: np.ndarray
    end_time: np.ndarray
    steps: np.ndarray
    evaluations: np.ndarray
    peak_axle_load: np.ndarray
    peak_axle_load_time: np.ndarray
    peak_hinge_load: np.ndarray
    peak_hinge_load_time: np.ndarray
    peak_sling_tension: np.ndarray
    peak_sling_tension_time: np.ndarray
    peak_projectile_acceleration: np.ndarray
    peak_projectile_acceleration_time: np.ndarray
    peak_arm_bending_moment: np.ndarray
    peak_arm_bending_moment_time: np.ndarray
    designs: tuple[Design, ...] | None = field(default=None, repr=False, compare=False, kw_only=True)
    shot_at: Callable[[int], Shot] | None = field(default=None, repr=False, compare=False, kw_only=True)

    @staticmethod
    def statuses(codes: np.ndarray) -> np.ndarray:
        """(S,) object array of ``Status`` from their integer ``codes`` (``Status.code``), by lookup."""
        return _STATUS_MEMBERS[np.asarray(codes, dtype=np.intp)]

    @property
    def ok(self) -> np.ndarray:
        """(S,) bool: the design threw."""
        return self.status == Status.OK

    def __len__(self) -> int:
        return len(self.status)

    def __getitem__(self, i: int) -> Shot:
        if self.shot_at is None:
            raise TypeError("these shots were made from packed kernel rows and know no designs: "
                            "shoot a sequence of Design to index them")
        return self.shot_at(range(len(self))[i])

    def columns(self, names: Sequence[str] = tuple(SHOT_COLUMNS)) -> dict[str, np.ndarray]:
        """The named ``SHOT_COLUMNS`` (all by default) as arrays of shape (S,), in their dtypes."""
        def column(name: str) -> np.ndarray:
            if name in _COMPONENTS:
                pair, k = _COMPONENTS[name]
                return getattr(self, pair)[:, k]
            if name == "launch_angle":   # Shot.launch_angle's arithmetic, row by row (NaN: no release)
                return np.array([math.atan2(vy, vx) for vx, vy in self.release_velocity.tolist()])
            return getattr(self, name)

        return {name: np.asarray(column(name), dtype=SHOT_COLUMNS[name]) for name in names}

    def to_arrow(self, names: Sequence[str] = tuple(SHOT_COLUMNS)):
        """The ``columns`` as a ``pyarrow.Table``, as a sweep stores them (``arrow_table``)."""
        return arrow_table(self.columns(names))

    def to_pandas(self, names: Sequence[str] = tuple(SHOT_COLUMNS)):
        """The ``columns`` as a ``pandas.DataFrame`` (through ``to_arrow``: ``status`` is categorical)."""
        return self.to_arrow(names).to_pandas()


_STATUS_MEMBERS = np.array(list(Status), dtype=object)
#: The columns that are one component of a ``Shots`` pair: (its field, the component).
_COMPONENTS = {"release_x": ("release_position", 0), "release_y": ("release_position", 1),
               "release_vx": ("release_velocity", 0), "release_vy": ("release_velocity", 1)}


def arrow_table(columns: dict[str, np.ndarray]):
    """Columns (each (S,)) as a ``pyarrow.Table``; a ``status`` column dictionary-encoded.

    Only the status repeats: it is stored, and read back, as a dictionary (a
    byte per row in memory, not its text); encoding the floats too costs a
    third more time for larger files (measured on a chunk of 4096 shots).
    """
    import pyarrow as pa

    return pa.table({name: pa.array(np.asarray(column)).dictionary_encode() if name == "status"
                     else pa.array(np.asarray(column)) for name, column in columns.items()})
