"""The fast path: whole shots at compiled speed, one design or arrays of them on every core.

``simulate_fast(design)`` gives the same ``Shot`` summary as
``analytic.simulate.simulate`` (status, message, lift-off, release, landing,
apex) without the histories, from the compiled three-stage shot in
``analytic.kernel``. ``shoot(designs)`` runs many designs at once on all
cores (numba threads) and returns arrays (``Shots``): what the optimiser and
the cross-check use by default.

The two paths share the equations' source (``kernel.terms``,
``kernel.slide_constraint``), the integrator's algorithm and coefficients
(DOP853, scipy's arrays), the events and their root tolerance, so with the
same tolerances they agree to round-off (2e-15 relative in range, median
over the benchmark's designs), or, where a rounding sends the step control
down another sequence of steps, to the integrator's own error (7e-9 at worst
there) -- far inside what the tests demand (1e-7 relative in range, 1e-6 s
in event times, the same failure).

The machine code is cached on disk (numba ``cache=True``): ``compile()``
loads or builds it and says how long that took; the first shot calls it.
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass
from typing import Sequence

import numba
import numpy as np
from scipy.integrate import DOP853

from analytic import aero, kernel
from analytic.design import Design, initial_angles, swing_time_limit
from analytic.integrate import IntegrationError
from analytic.result import Shot, Status
from analytic.simulate import (
    DEFAULT_ATOL,
    DEFAULT_RTOL,
    hits_base_message,
    never_fires_message,
    never_lifts_off_message,
    never_releases_message,
    no_landing_message,
    thrown_message,
)

_RULES = {"velocity": kernel.RULE_VELOCITY, "sling": kernel.RULE_SLING}
_DRAGS = {"none": kernel.DRAG_NONE, "constant": kernel.DRAG_CONSTANT,
          "smooth-sphere": kernel.DRAG_SMOOTH, "golf-ball": kernel.DRAG_GOLF}
_STATUS = {kernel.OK: Status.OK, kernel.NEVER_FIRES: Status.NEVER_FIRES,
           kernel.NEVER_LIFTS_OFF: Status.NEVER_LIFTS_OFF,
           kernel.HITS_BASE: Status.HITS_BASE_BEFORE_RELEASE, kernel.NEVER_RELEASES: Status.NEVER_RELEASES}
#: Failure kinds of the fast path that are not a ``Status`` (the reference path raises
#: ``IntegrationError`` for both).
STEP_FAILED, NO_LANDING = "integration_error", "no_landing"

#: Designs a thread takes at a time in ``shoot``.
BATCH_CHUNK = 4
#: DOP853's coefficient arrays, from scipy's own class (so both paths step identically).
COEFFICIENTS = tuple(np.ascontiguousarray(a, dtype=np.float64) for a in
                     (DOP853.A, DOP853.B, DOP853.C, DOP853.E3, DOP853.E5, DOP853.D,
                      DOP853.A_EXTRA, DOP853.C_EXTRA))


def drag_table() -> np.ndarray:
    """The drag models' constants in the kernel's layout, from ``analytic.aero`` (shape (N_DRAG_TABLE,))."""
    table = np.concatenate([
        [aero._OSEEN_END, aero._LOW_END, aero._INTERMEDIATE_END], aero._CD_BREAKS,
        [aero._GOLF_RE_MIN, aero._GOLF_RE_MAX, aero._GOLF_CD_MIN_RE, aero._GOLF_CD_MAX_RE],
        aero._GOLF_LOG_RE, np.ravel(aero._GOLF_COEFFS)])
    assert table.shape == (kernel.N_DRAG_TABLE,), table.shape
    return table


DRAG_TABLE = drag_table()


def pack(design: Design) -> np.ndarray:
    """A design as the kernel's row, shape (N_DESIGN,) (SI, radians; codes for rule and drag)."""
    m, proj, env = design.machine, design.projectile, design.environment
    theta0, phi0, psi0 = initial_angles(m)
    row = np.empty(kernel.N_DESIGN)
    row[:12] = (m.arm_long, m.arm_short, m.arm_cg, m.arm_mass, m.arm_inertia, m.counterweight_mass,
                m.counterweight_link, m.counterweight_inertia, m.sling_length, proj.mass,
                m.pivot_height, env.gravity)
    row[kernel.ALPHA] = m.release_angle
    row[kernel.RULE] = _RULES[m.release_rule]
    row[kernel.DRAG] = _DRAGS[proj.drag]
    row[kernel.CD] = math.nan if proj.drag_coefficient is None else proj.drag_coefficient
    row[kernel.DIAMETER] = proj.diameter
    row[kernel.RHO] = env.air_density
    row[kernel.MU] = env.air_viscosity
    row[kernel.WIND] = env.wind_speed
    row[kernel.AREA] = proj.frontal_area
    row[kernel.T_LIMIT] = swing_time_limit(m, env.gravity)
    row[kernel.THETA0], row[kernel.PHI0], row[kernel.PSI0] = theta0, phi0, psi0
    return row


def pack_many(designs: Sequence[Design]) -> np.ndarray:
    """Designs as kernel rows, shape (S, N_DESIGN)."""
    rows = np.empty((len(designs), kernel.N_DESIGN))
    for i, design in enumerate(designs):
        rows[i] = pack(design)
    return rows


def _check_tolerances(rtol: float, atol: float) -> None:
    for name, value in (("rtol", rtol), ("atol", atol)):
        if not (0.0 < value < 1.0):
            raise ValueError(f"{name} = {value!r}: the integrator tolerance must lie in (0, 1)")


# --------------------------------------------------------------------------- #
# Compilation
# --------------------------------------------------------------------------- #

_compile_seconds: float | None = None


def compile(*, progress: bool = False) -> float:
    """Load the kernel's machine code from the disk cache, or compile and cache it; seconds taken.

    Called by the first shot; later calls return the first call's time. In
    a fresh checkout this compiles (about a minute on 2 cores); afterwards
    it loads (about 0.3 s). ``progress``: say so on stderr.
    """
    global _compile_seconds
    if _compile_seconds is None:
        if progress:
            print("loading the compiled fast path (a fresh checkout compiles it once, about a minute) ...",
                  file=sys.stderr, flush=True)
        began = time.perf_counter()
        rows = pack_many([_warm_up_design()])
        out = np.empty((1, kernel.N_RESULT))
        args = (rows, DRAG_TABLE, COEFFICIENTS, DEFAULT_RTOL, DEFAULT_ATOL, out)
        # Compile (or load) without running: running the parallel kernel would
        # start numba's thread pool, and a process that later forks workers
        # (the cross-check's pool) must not have one.
        kernel.shots.compile(tuple(numba.typeof(a) for a in args))
        kernel.shot.compile(tuple(numba.typeof(a) for a in (rows[0], *args[1:5], out[0])))
        _compile_seconds = time.perf_counter() - began
    return _compile_seconds


def _warm_up_design() -> Design:
    from analytic.design_file import default_design

    return default_design()


# --------------------------------------------------------------------------- #
# One design
# --------------------------------------------------------------------------- #

def simulate_fast(design: Design, *, rtol: float = DEFAULT_RTOL, atol: float = DEFAULT_ATOL) -> Shot:
    """``simulate(design)``'s summary, compiled: no histories, energies or sling tension.

    Raises ``IntegrationError`` where the reference path does (step size
    underflow, a flight that never comes down).
    """
    _check_tolerances(rtol, atol)
    compile()
    out = np.empty(kernel.N_RESULT)
    kernel.shot(pack(design), DRAG_TABLE, COEFFICIENTS, rtol, atol, out)
    return to_shot(design, out)


def to_shot(design: Design, out: np.ndarray) -> Shot:
    """The ``Shot`` (no histories) of a kernel result row."""
    code = int(out[kernel.STATUS])
    if code == kernel.STEP_FAILED:
        raise IntegrationError(f"integration failed at t = {out[kernel.END_T]:.6g} s: "
                               f"the step size fell below the resolution of t")
    m = design.machine
    t_limit = swing_time_limit(m, design.environment.gravity)
    if code == kernel.NO_LANDING:
        raise IntegrationError(no_landing_message(out[kernel.END_T] - out[kernel.RELEASE_T]))
    status = _STATUS[code]

    def maybe(i: int) -> float | None:
        return None if math.isnan(out[i]) else float(out[i])

    fields = dict(liftoff_time=maybe(kernel.LIFTOFF_T))
    if status is Status.NEVER_FIRES:
        message = never_fires_message(out[kernel.VALUE])
    elif status is Status.NEVER_LIFTS_OFF:
        event = {kernel.UNDER_TIP: "under_tip", kernel.ARM_BACK: "arm_back",
                 kernel.TIME_LIMIT: None}[int(out[kernel.DETAIL])]
        message = never_lifts_off_message(event, t_limit)
    elif status is Status.HITS_BASE_BEFORE_RELEASE:
        message = hits_base_message(out[kernel.END_T])
    elif status is Status.NEVER_RELEASES:
        message = never_releases_message(m, t_limit)
    else:
        message = thrown_message(out[kernel.LANDING_X])
        fields.update(release_time=float(out[kernel.RELEASE_T]),
                      release_position=out[[kernel.RELEASE_X, kernel.RELEASE_Y]].copy(),
                      release_velocity=out[[kernel.RELEASE_VX, kernel.RELEASE_VY]].copy(),
                      landing_time=float(out[kernel.LANDING_T]),
                      landing_position=np.array([out[kernel.LANDING_X], -m.pivot_height]),
                      apex_height=float(out[kernel.APEX]))
    return Shot(design, status, message, **fields)


# --------------------------------------------------------------------------- #
# Many designs
# --------------------------------------------------------------------------- #

def _shoot_rows(rows: np.ndarray, rtol: float, atol: float) -> np.ndarray:
    """The kernel's result rows (S, N_RESULT) for design rows (S, N_DESIGN), on all threads."""
    _check_tolerances(rtol, atol)
    rows = np.ascontiguousarray(rows, dtype=np.float64)
    if rows.ndim != 2 or rows.shape[1] != kernel.N_DESIGN:
        raise ValueError(f"designs: expected rows of shape (S, {kernel.N_DESIGN}), got {rows.shape}")
    compile()
    out = np.empty((len(rows), kernel.N_RESULT))
    # Shots differ in cost (by 10x over the paper's bounds): hand them to the
    # threads a few at a time rather than in one block per thread.
    with numba.parallel_chunksize(BATCH_CHUNK):
        kernel.shots(rows, DRAG_TABLE, COEFFICIENTS, rtol, atol, out)
    return out


def simulate_fast_many(designs: Sequence[Design], *, rtol: float = DEFAULT_RTOL,
                       atol: float = DEFAULT_ATOL) -> list[Shot | IntegrationError]:
    """``simulate_fast`` for every design in one batch on all cores.

    A design whose integration fails gets its ``IntegrationError`` in its
    place in the list (not raised), so one bad design does not lose the rest.
    """
    out = _shoot_rows(pack_many(designs), rtol, atol)
    shots: list[Shot | IntegrationError] = []
    for design, row in zip(designs, out, strict=True):
        try:
            shots.append(to_shot(design, row))
        except IntegrationError as error:
            shots.append(error)
    return shots


@dataclass(frozen=True)
class Shots:
    """Results of many shots; every array has the designs along its first axis (S).

    Attributes
    ----------
    status : (S,) str, a ``Status`` value or ``STEP_FAILED`` / ``NO_LANDING``.
    liftoff_time, release_time, landing_time : (S,) s (nan where not reached).
    release_position, release_velocity : (S, 2) m and m/s from the pivot (nan where not reached).
    range : (S,) m from the pivot to the landing point (nan for a failure).
    apex_height : (S,) m above the base (nan for a failure).
    end_time : (S,) s, when the shot ended (the failure's instant for a failure).
    steps, evaluations : (S,) accepted integrator steps and right-hand-side evaluations.
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

    @property
    def ok(self) -> np.ndarray:
        """(S,) bool: the design threw."""
        return self.status == Status.OK.value

    def __len__(self) -> int:
        return len(self.status)


_STATUS_NAMES = np.array([Status.OK.value, Status.NEVER_FIRES.value, Status.NEVER_LIFTS_OFF.value,
                          Status.HITS_BASE_BEFORE_RELEASE.value, Status.NEVER_RELEASES.value,
                          STEP_FAILED, NO_LANDING])


def shoot(designs: Sequence[Design] | np.ndarray, *, rtol: float = DEFAULT_RTOL,
          atol: float = DEFAULT_ATOL) -> Shots:
    """Simulate many designs on all cores (numba threads; ``numba.set_num_threads`` limits them).

    Parameters
    ----------
    designs : a sequence of ``Design``, or their kernel rows (S, N_DESIGN) from ``pack_many``.
    """
    rows = designs if isinstance(designs, np.ndarray) else pack_many(designs)
    out = _shoot_rows(rows, rtol, atol)
    landed = out[:, kernel.STATUS] == kernel.OK
    return Shots(status=_STATUS_NAMES[out[:, kernel.STATUS].astype(int)],
                 liftoff_time=out[:, kernel.LIFTOFF_T],
                 release_time=out[:, kernel.RELEASE_T],
                 landing_time=np.where(landed, out[:, kernel.LANDING_T], np.nan),
                 release_position=out[:, [kernel.RELEASE_X, kernel.RELEASE_Y]],
                 release_velocity=out[:, [kernel.RELEASE_VX, kernel.RELEASE_VY]],
                 range=np.where(landed, out[:, kernel.LANDING_X], np.nan),
                 apex_height=np.where(landed, out[:, kernel.APEX], np.nan),
                 end_time=out[:, kernel.END_T],
                 steps=out[:, kernel.STEPS].astype(int),
                 evaluations=out[:, kernel.EVALS].astype(int))
