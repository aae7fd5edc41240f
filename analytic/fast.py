"""The fast path: whole shots at compiled speed, one design or arrays of them on every core.

``simulate_fast(design)`` gives the same ``Shot`` summary as
``analytic.reference.simulate`` (status, message, lift-off, release, landing,
apex) without the histories, from the compiled three-stage shot in
``analytic.kernel``. ``shoot(designs)`` runs many designs at once on all
cores (numba threads) and returns arrays (``Shots``): what the optimiser and
the cross-check use by default.

The two paths run the same model source (``analytic.eom``, ``stages``,
``geometry``, ``aero``, ``limits``; compiled here by ``analytic.compiled``),
the same integrator algorithm with the same coefficients (DOP853, scipy's
arrays) and the same root tolerance, so with the same tolerances they agree
to round-off (2e-15 relative in range, median over the benchmark's
designs), or, where a rounding sends the step control down another sequence
of steps, to the integrator's own error (7e-9 at worst there): far inside
what the tests demand (1e-7 relative in range, 1e-6 s in event times, the
same outcome).

The machine code is cached on disk (numba ``cache=True``): ``compile()``
loads or builds it and says how long that took; the first shot calls it.
"""

from __future__ import annotations

import math
import sys
import time
from typing import Sequence

import numba
import numpy as np
from scipy.integrate import DOP853

from analytic import kernel, outcome
from analytic.aero import DRAG_TABLE
from analytic.design import Design, swing_time_limit
from analytic.parameters import N_PARAMS, params
from analytic.result import Shot, Shots, Status
from analytic.reference import DEFAULT_ATOL, DEFAULT_RTOL

#: Designs a thread takes at a time in ``shoot``.
BATCH_CHUNK = 4
#: DOP853's coefficient arrays, from scipy's own class (so both paths step identically).
COEFFICIENTS = tuple(np.ascontiguousarray(a, dtype=np.float64) for a in
                     (DOP853.A, DOP853.B, DOP853.C, DOP853.E3, DOP853.E5, DOP853.D,
                      DOP853.A_EXTRA, DOP853.C_EXTRA))


def pack(design: Design) -> np.ndarray:
    """A design as the kernel's row, shape (N_PARAMS,): its ``analytic.parameters.Params`` in order."""
    return np.array(params(design), dtype=np.float64)


def pack_many(designs: Sequence[Design]) -> np.ndarray:
    """Designs as kernel rows, shape (S, N_PARAMS)."""
    rows = np.empty((len(designs), N_PARAMS))
    for i, design in enumerate(designs):
        rows[i] = params(design)
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
        rows = np.zeros((1, N_PARAMS))
        out = np.empty((1, kernel.N_RESULT))
        args = (rows, DRAG_TABLE, COEFFICIENTS, DEFAULT_RTOL, DEFAULT_ATOL, out)
        # Compile (or load) without running, so that loading starts no threads
        # (see ``shoot`` on processes and threads).
        kernel.shots.compile(tuple(numba.typeof(a) for a in args))
        kernel.shot.compile(tuple(numba.typeof(a) for a in (rows[0], *args[1:5], out[0])))
        _compile_seconds = time.perf_counter() - began
    return _compile_seconds


# --------------------------------------------------------------------------- #
# One design
# --------------------------------------------------------------------------- #

def simulate_fast(design: Design, *, rtol: float = DEFAULT_RTOL, atol: float = DEFAULT_ATOL) -> Shot:
    """``simulate(design)``'s summary, compiled: no histories, energies or sling tension.

    Parameters
    ----------
    design : a validated ``Design``.
    rtol, atol : the integrator's tolerances, as for ``analytic.reference.simulate``.

    Returns
    -------
    Shot
        Status, message, lift-off, release, landing and apex; a valid design
        that does not throw is a ``Shot`` with its failure's status, never an
        exception.
    """
    _check_tolerances(rtol, atol)
    compile()
    out = np.empty(kernel.N_RESULT)
    kernel.shot(pack(design), DRAG_TABLE, COEFFICIENTS, rtol, atol, out)
    return to_shot(design, out)


def to_shot(design: Design, out: np.ndarray) -> Shot:
    """The ``Shot`` (no histories) of a kernel result row ``out`` (N_RESULT,)."""
    status = Status.from_code(int(out[kernel.STATUS]))
    m = design.machine
    t_limit = swing_time_limit(m, design.environment.gravity)

    def maybe(i: int) -> float | None:
        return None if math.isnan(out[i]) else float(out[i])

    fields = dict(liftoff_time=maybe(kernel.LIFTOFF_T))
    if not math.isnan(out[kernel.RELEASE_T]):
        fields.update(release_time=float(out[kernel.RELEASE_T]),
                      release_position=out[[kernel.RELEASE_X, kernel.RELEASE_Y]].copy(),
                      release_velocity=out[[kernel.RELEASE_VX, kernel.RELEASE_VY]].copy())
    if status is Status.OK:
        message = outcome.thrown_message(out[kernel.LANDING_X])
        fields.update(landing_time=float(out[kernel.LANDING_T]),
                      landing_position=np.array([out[kernel.LANDING_X], -m.pivot_height]),
                      apex_height=float(out[kernel.APEX]))
    else:
        message = failure_message(design, status, out[kernel.DETAIL], out[kernel.VALUE],
                                  out[kernel.END_T], out[kernel.RELEASE_T], t_limit)
    return Shot(design, status, message, **fields)


def failure_message(design: Design, status: Status, detail: float, value: float, end_time: float,
                    release_time: float, t_limit: float) -> str:
    """The message of a failed shot from the kernel's record of it."""
    if status is Status.NEVER_FIRES:
        return outcome.never_fires_message(value)
    if status is Status.NEVER_LIFTS_OFF:
        return outcome.never_lifts_off_message(outcome.LiftoffFailure(int(detail)), t_limit)
    if status is Status.HITS_BASE_BEFORE_RELEASE:
        return outcome.hits_base_message(end_time)
    if status is Status.NEVER_RELEASES:
        m = design.machine
        return outcome.never_releases_message(m.release_rule, m.release_angle, t_limit)
    if status is Status.NO_LANDING:
        return outcome.no_landing_message(end_time - release_time)
    return outcome.step_failed_message(end_time, outcome.Stage(int(detail)), step_limit=value == 1.0)


# --------------------------------------------------------------------------- #
# Many designs
# --------------------------------------------------------------------------- #

def _shoot_rows(rows: np.ndarray, rtol: float, atol: float) -> np.ndarray:
    """The kernel's result rows (S, N_RESULT) for design rows (S, N_PARAMS), on all threads."""
    _check_tolerances(rtol, atol)
    rows = np.ascontiguousarray(rows, dtype=np.float64)
    if rows.ndim != 2 or rows.shape[1] != N_PARAMS:
        raise ValueError(f"designs: expected rows of shape (S, {N_PARAMS}), got {rows.shape}")
    compile()
    out = np.empty((len(rows), kernel.N_RESULT))
    # Shots differ in cost (by 10x over the paper's bounds): hand them to the
    # threads a few at a time rather than in one block per thread.
    with numba.parallel_chunksize(BATCH_CHUNK):
        kernel.shots(rows, DRAG_TABLE, COEFFICIENTS, rtol, atol, out)
    return out


def simulate_fast_many(designs: Sequence[Design], *, rtol: float = DEFAULT_RTOL,
                       atol: float = DEFAULT_ATOL) -> list[Shot]:
    """``simulate_fast`` for every design in one batch on all cores; one ``Shot`` per design."""
    out = _shoot_rows(pack_many(designs), rtol, atol)
    return [to_shot(design, row) for design, row in zip(designs, out, strict=True)]


_STATUS_NAMES = np.array([status.value for status in Status])


def shoot(designs: Sequence[Design] | np.ndarray, *, rtol: float = DEFAULT_RTOL,
          atol: float = DEFAULT_ATOL) -> Shots:
    """Simulate many designs on all cores (numba threads; ``numba.set_num_threads`` limits them).

    Threads and processes, as measured: numba runs the batch on GNU OpenMP
    where libgomp is installed (as on our machines; ``numba.threading_layer()``
    says which), else on its own workqueue, which must be called from one
    Python thread at a time. A process that has run a batch may fork workers,
    but a forked worker that runs a batch itself is terminated by GNU OpenMP
    ("fork() called from a process already using GNU OpenMP"): forked workers
    must not shoot (the cross-check's run only the engine), and workers that
    shoot are spawned (Dask's are).

    Parameters
    ----------
    designs : a sequence of S ``Design``, or their rows, shape (S, N_PARAMS), from ``pack_many``.
    rtol, atol : the integrator's tolerances.

    Returns
    -------
    Shots
        Arrays of length S; a failed design has its status and NaN where it did not reach.
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
