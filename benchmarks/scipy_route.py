"""The cheaper route not taken, measured: scipy's DOP853 stepping the model compiled as its right-hand side."""

from __future__ import annotations

import numpy as np
from numba import njit
from scipy.integrate import solve_ivp

from analytic import fast, stages, states
from analytic.fast import compiled
from analytic.aero import DRAG_TABLE
from analytic.parameters import params
from analytic.reference import DEFAULT_ATOL, DEFAULT_RTOL, simulate
from analytic.result import Stage
from benchmarks.measure import best_time


def scipy_with_compiled_model(design, repeat: int = 3) -> dict:
    """The cheaper route not taken, measured: scipy's DOP853 with the model compiled as its right-hand side.

    Stage 2 (lift-off to release, a fixed interval, no events) of ``design``
    through ``scipy.integrate.solve_ivp`` at the default tolerances, once with
    the Python model and once with the same model compiled, and the fast
    path's whole three-stage shot beside them. The compiled right-hand side
    alone cannot make scipy fast: its stepping is Python.
    """
    derivative = compiled.stages_.derivative

    @njit
    def compiled_rhs(t, y, p):
        out = np.empty(6)
        derivative(states.SWING, y, p, DRAG_TABLE, out)
        return out

    def python_rhs(t, y, p):
        out = np.empty(6)
        stages.derivative(states.SWING, y, p, DRAG_TABLE, out)
        return out

    shot = simulate(design)
    history = shot.history
    first = int(np.argmax(history.stage == Stage.SWING)) - 1    # the lift-off sample
    y0 = np.concatenate([history.q[first], history.qdot[first]])
    span = (history.t[first], shot.release_time)
    p = params(design)
    compiled_rhs(0.0, y0, p)

    def swing(rhs) -> float:
        return best_time(lambda: solve_ivp(rhs, span, y0, method="DOP853", rtol=DEFAULT_RTOL,
                                           atol=DEFAULT_ATOL), repeat)[0]

    return {"scipy_swing_python_rhs_s": swing(lambda t, y: python_rhs(t, y, p)),
            "scipy_swing_compiled_rhs_s": swing(lambda t, y: compiled_rhs(t, y, p)),
            "fast_whole_shot_s": best_time(lambda: fast.simulate_fast(design), 20)[0]}
