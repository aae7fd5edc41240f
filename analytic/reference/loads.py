"""The reference path's stage machinery beside the shot: the right-hand side it hands scipy,
Python's float errors, and the peak loads and the sling's smallest tension.

``analytic.reference`` runs the shot; this module is what it evaluates on the
integrator's steps: each stage's derivative for scipy (``stage_rhs``), the
largest of each load over a stage (``stage_peaks``, sampled at every step's
end and located on the interpolants of the steps beside each local maximum of
the samples, as the compiled path does: ``analytic.fast.kernel_loads``) and the sling's
smallest tension on the continuous solution (``smallest_tension``).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import minimize_scalar

from analytic import peaks as peak_search
from analytic import stages
from analytic.aero import DRAG_TABLE
from analytic.reference.ode import Segment, step_interpolant
from analytic.outcome import Stage
from analytic.parameters import Params
from analytic.result import PEAK_NAMES

#: What Python's float arithmetic raises where the compiled path's IEEE
#: arithmetic (numba's ``error_model="numpy"``) quietly gives inf or NaN: a
#: division by zero, the sine of an overflowed angle, an overflowing power. A
#: trial stage of an extreme design can get there; the integrator then rejects
#: the step, or the shot ends as step_failed, on both paths alike.
FLOAT_ERRORS = (ArithmeticError, ValueError)


def quietly(function, *args, otherwise):
    """``function(*args)``, or ``otherwise`` where Python's floats raise one of ``FLOAT_ERRORS``."""
    try:
        return function(*args)
    except FLOAT_ERRORS:
        return otherwise


def stage_rhs(stage: Stage, p: Params, size: int):
    """The stage's right-hand side ``rhs(t, y)`` for scipy, NaN where Python's floats raise.

    The model reads the state as Python floats (``y.tolist()``): the same IEEE arithmetic as on
    numpy's scalars, at a fraction of the cost of each operation."""
    def rhs(t, y):
        out = np.empty(size)
        try:
            stages.derivative(stage, y.tolist(), p, DRAG_TABLE, out)
        except FLOAT_ERRORS:
            out[:] = math.nan   # the compiled path's inf or NaN: a rejected step
        return out

    return rhs


NO_PEAKS = np.full((len(stages.LOAD_NAMES), 2), -np.inf)
NO_PEAKS.flags.writeable = False


def pieces_peaks(stage: Stage, pieces: list[Segment], p: Params, loads: bool, peaks: np.ndarray, rtol: float,
                  atol: float) -> np.ndarray:
    """``peaks`` updated with each piece's (``stage_peaks``) where it beats them, as the compiled
    path does for each stretch it integrates."""
    peaks = peaks.copy()
    for piece in pieces:
        found = stage_peaks(stage, piece, p, loads, rtol, atol)
        later = found[:, 0] > peaks[:, 0]
        peaks[later] = found[later]
    return peaks


def sling_tension_at(stage: Stage, y: np.ndarray, p: Params) -> float:
    """Sling tension at a stage-1 or stage-2 state (``eom.loads``), N (NaN where ``FLOAT_ERRORS``
    say it cannot be computed)."""
    return quietly(lambda: stages.loads_at(int(stage), y, p)[2], otherwise=math.nan)


def smallest_tension(t: np.ndarray, stage: np.ndarray, tension: np.ndarray, segments, p: Params) -> float:
    """The minimum of the sling tension, refined between the output samples.

    The samples are ``SWING_OUTPUT_STEP`` (or ``simulate``'s ``sample_step``) apart
    while a push of the sling can last about a millisecond, so the sampled minimum is
    refined by a bounded scalar minimisation on the integrator's continuous solution
    around it.
    """
    i = int(np.argmin(tension))
    stage_i = Stage(stage[i])
    if stage_i not in dict(segments):   # never fired: the rest state alone
        return float(tension[i])
    solution = dict(segments)[stage_i].solution
    same = np.flatnonzero(stage == stage_i)
    low, high = t[max(i - 1, same[0])], t[min(i + 1, same[-1])]
    if solution is None or high <= low:
        return float(tension[i])
    low, high = max(low, solution.t_min), min(high, solution.t_max)
    best = minimize_scalar(lambda s: sling_tension_at(stage_i, solution(s), p), bounds=(low, high),
                           method="bounded", options={"xatol": 1e-9})
    return float(min(best.fun, tension[i]))


def stage_peaks(stage: Stage, segment: Segment, p: Params, loads: bool, rtol: float, atol: float) -> np.ndarray:
    """The largest of each load (``stages.LOAD_NAMES``) over a stage-1 or stage-2 segment, and when,
    shape (N_LOADS, 2).

    Sampled at the start, every accepted step's end and the end; then, around
    every sample that is a local maximum of the samples (``analytic.peaks``),
    located on the interpolants of the two steps on either side of it (the
    search started from the three samples), or at the segment's end on its one
    step where the load is larger just inside it. The largest value found
    (samples and searches, in time order, the first of equals) is the peak. The
    compiled path does the same on the same steps. Not ``loads``: none (-inf).
    """
    peaks = np.full((len(stages.LOAD_NAMES), 2), -np.inf)
    if not loads:
        return peaks
    values = np.array([stages.loads_at(int(stage), y, p) if np.isnan(f[0]) else
                       stages.loads_after_step(int(stage), y, f, p)
                       for y, f in zip(segment.step_y.tolist(), segment.step_f.tolist(), strict=True)])   # (k, N_LOADS)
    times = segment.step_t.tolist()
    rhs = stage_rhs(stage, p, segment.step_y.shape[1])
    built: dict[int, object] = {}

    def interpolant(j: int):
        """The dense output of the step from sample j to sample j + 1 (its full length)."""
        if j not in built:
            built[j] = step_interpolant(rhs, segment.steps[j], rtol=rtol, atol=atol)
        return built[j]

    n = len(times)
    for k in range(values.shape[1]):
        load_k = values[:, k].tolist()
        for i, value in enumerate(load_k):
            if value > peaks[k, 0]:
                peaks[k] = value, times[i]
            before = load_k[i - 1] if i > 0 else -math.inf
            after = load_k[i + 1] if i + 1 < n else -math.inf
            if peak_search.local_peak(before, value, after):
                found = _search_sample(stage, p, interpolant, times, load_k, i, k)
                if found is not None and found[0] > peaks[k, 0]:
                    peaks[k] = found
    return peaks


def _search_sample(stage: Stage, p: Params, interpolant, times: list[float], load_k: list[float], i: int,
                   k: int) -> tuple[float, float] | None:
    """Load ``k``'s largest value and its time around its sample ``i``, a local maximum of ``load_k``
    (on ``times``), on the steps' ``interpolant``: None where the sample itself is the peak."""
    n = len(times)
    if 0 < i < n - 1 and times[i - 1] < times[i] < times[i + 1]:
        # Both steps beside the sample, as one bracket: each time on its own step's interpolant.
        def load(u):
            return -stages.loads_at(int(stage), interpolant(i - 1 if u < times[i] else i)(u).tolist(), p)[k]

        search = peak_search.search_around(times[i - 1], load_k[i - 1], times[i], load_k[i], times[i + 1],
                                           load_k[i + 1])
    else:   # the sample ends the segment: the one step beside it
        j = i - 1 if i > 0 else i
        if j + 1 >= n or not times[j + 1] > times[j]:
            return None

        def load(u):
            return -stages.loads_at(int(stage), interpolant(j)(u).tolist(), p)[k]

        inside = peak_search.inside_end(times[j], times[j + 1], i == j)
        if -load(inside) <= load_k[i]:
            return None   # still rising into the segment's end: the peak is the sample there
        u = peak_search.search_golden(times[j], times[j + 1])
        search = peak_search.search_from(times[j], times[j + 1], u, load(u))
    while True:
        done, u, search = peak_search.search_next(search)
        if done:
            return -search.fx, search.x
        search = peak_search.search_update(search, u, load(u))


def peak_fields(peaks: np.ndarray) -> dict[str, float]:
    """``Shot`` fields of the peaks (N_LOADS, 2); none that were never sampled."""
    fields = {}
    for (value, time), name in zip(peaks, PEAK_NAMES, strict=True):
        if np.isfinite(value):
            fields[name], fields[f"{name}_time"] = float(value), float(time)
    return fields
