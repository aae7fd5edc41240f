"""Peak loads in the compiled shot: each load sampled at every step's end, then located on the
interpolants of the steps beside its largest sample, as the reference path does.

``analytic.fast.kernel.integrate`` calls ``keep_step`` and ``sample_loads`` after
each accepted step, ``save_step`` before a step buffer is reused, and
``finish_peaks`` at a stretch's end. The search is ``analytic.peaks``' (the
model's), on the same steps as ``analytic.reference.loads.stage_peaks``.
"""

from __future__ import annotations

import math

import numpy as np

from analytic.fast.marks import internal
from analytic.fast.dop853 import N_STAGES, dense_eval, dense_prepare
from analytic.peaks import inside_end, search_around, search_from, search_golden, search_next, search_update
from analytic.stages import LOAD_NAMES, loads_at

N_LOADS = len(LOAD_NAMES)

# --------------------------------------------------------------------------- #
# Peak loads: sampled at every step's end, located around the largest sample
# --------------------------------------------------------------------------- #
# Per load k (``stages.LOAD_NAMES``): ``samples[k]`` holds the largest sample
# ``(t, value)`` at 2, 3 and the samples before and after it at 0, 1 and 4, 5
# (NaN times: none); ``sides[k]`` the steps on either side of it: the step ending
# at the sample (0) and the step after it (1), -1 for none; ``pending[k]``: side
# 1 is the next step. ``last`` holds the previous sample's values, then its time.
#
# A step is its stages K[0:13], its start and full end ``(y, y_new)`` and
# ``(t_start, h, t_end)``, t_end where the stretch stopped within it. The
# integrator keeps its last two steps in two buffers, alternately (``LIVE + b``
# for buffer b); a step that a load still needs when its buffer is about to be
# taken again is saved, once, in a slot of the pool (0 to ``POOL_SLOTS - 1``).
# While a load rises, each step replaces the last and nothing is copied; the
# interpolants are built at the end, for the few steps around a peak.
POOL_SLOTS = 2 * N_LOADS
LIVE = POOL_SLOTS


@internal
def save_step(buffer, sides, K2, live_y, live_t, pool_k, pool_y, pool_t):
    """Move every load's reference to live ``buffer`` into a free pool slot, copying the step once."""
    slot = -1
    for k in range(N_LOADS):
        for side in range(2):
            if sides[k, side] == LIVE + buffer:
                if slot < 0:
                    slot = 0
                    taken = True
                    while taken:
                        taken = False
                        for j in range(N_LOADS):
                            if sides[j, 0] == slot or sides[j, 1] == slot:
                                taken = True
                        if taken:
                            slot += 1
                    n = live_y.shape[2]
                    for q in range(N_STAGES + 1):
                        for i in range(n):   # loops: a slice copy costs 4 s of compile (its error message)
                            pool_k[slot, q, i] = K2[buffer, q, i]
                    for i in range(n):
                        pool_y[slot, 0, i], pool_y[slot, 1, i] = live_y[buffer, 0, i], live_y[buffer, 1, i]
                    for j in range(3):
                        pool_t[slot, j] = live_t[buffer, j]
                sides[k, side] = slot


@internal
def sample_loads(t, values, buffer, samples, sides, pending, last, ended):
    """Take the loads ``values`` at ``t``, where the step in live ``buffer`` stopped (-1: the
    stretch's first sample, no step). ``ended``: no step follows."""
    here = LIVE + buffer if buffer >= 0 else -1
    for k in range(N_LOADS):
        if pending[k]:
            sides[k, 1] = here
            samples[k, 4], samples[k, 5] = t, values[k]
            pending[k] = False
        if values[k] > samples[k, 3]:
            samples[k, 0], samples[k, 1] = last[N_LOADS], last[k]
            samples[k, 2], samples[k, 3] = t, values[k]
            samples[k, 4] = math.nan
            sides[k, 0], sides[k, 1] = here, -1
            pending[k] = not ended
        last[k] = values[k]
    last[N_LOADS] = t


@internal
def _prepare(ref, stage, K2, live_y, live_t, pool_k, pool_y, pool_t, built, F, K, tmp, coef, p, table, out):
    """The dense output of step ``ref`` (live buffer ``ref - LIVE``, or pool slot ``ref``) in ``F[ref]``,
    unless it is ``built`` already."""
    if built[ref]:
        return
    live = ref >= LIVE
    n = pool_y.shape[2]
    for q in range(N_STAGES + 1):
        for i in range(n):
            K[q, i] = K2[ref - LIVE, q, i] if live else pool_k[ref, q, i]
    y_old = live_y[ref - LIVE, 0] if live else pool_y[ref, 0]
    y_end = live_y[ref - LIVE, 1] if live else pool_y[ref, 1]
    t_start = live_t[ref - LIVE, 0] if live else pool_t[ref, 0]
    h = live_t[ref - LIVE, 1] if live else pool_t[ref, 1]
    dense_prepare(stage, t_start, h, y_old, y_end, K[N_STAGES], coef, K, F[ref], tmp, p, table)
    out.evaluations += 3
    built[ref] = True


@internal
def _load_on_step(u, k, ref, stage, live_y, live_t, pool_y, pool_t, F, tmp, p):
    """Load ``k`` at time ``u`` on the dense output of step ``ref`` (built)."""
    live = ref >= LIVE
    t_start = live_t[ref - LIVE, 0] if live else pool_t[ref, 0]
    h = live_t[ref - LIVE, 1] if live else pool_t[ref, 1]
    y_old = live_y[ref - LIVE, 0] if live else pool_y[ref, 0]
    dense_eval(u, t_start, h, y_old, F[ref], tmp)
    return loads_at(stage, tmp, p)[k]


@internal(allocates=True)
def finish_peaks(stage, samples, sides, K2, live_y, live_t, pool_k, pool_y, pool_t, peaks, coef, p, table,
                  out):
    """Locate each load's largest value around its largest sample (``analytic.peaks``' search on
    its steps' interpolants, as ``analytic.reference.loads.stage_peaks`` does) and keep it in
    ``peaks`` (N_LOADS, 2) where it beats it. ``out``, the shot's result record
    (``kernel.RESULT_DTYPE``), counts the evaluations."""
    n = pool_y.shape[2]
    F = np.empty((POOL_SLOTS + 2, 7, n))
    built = np.empty(POOL_SLOTS + 2, dtype=np.bool_)
    for ref in range(POOL_SLOTS + 2):
        built[ref] = False
    K = np.empty((N_STAGES + 4, n))
    tmp = np.empty(n)
    for k in range(N_LOADS):
        if not samples[k, 3] > -math.inf:
            continue
        t_peak, value = samples[k, 2], samples[k, 3]
        left, right = sides[k, 0], sides[k, 1]
        if left >= 0 and right >= 0 and samples[k, 0] < t_peak < samples[k, 4]:
            # Both steps beside the sample, as one bracket: each time on its own step's interpolant.
            search = search_around(samples[k, 0], samples[k, 1], t_peak, value, samples[k, 4], samples[k, 5])
            searching = True
        else:   # the largest sample ends the stretch: the one step beside it
            left = left if left >= 0 else right
            right = left
            searching = left >= 0
            a, b = math.nan, math.nan
            if searching:
                a = live_t[left - LIVE, 0] if left >= LIVE else pool_t[left, 0]
                b = live_t[left - LIVE, 2] if left >= LIVE else pool_t[left, 2]
                searching = b > a
            if searching:
                _prepare(left, stage, K2, live_y, live_t, pool_k, pool_y, pool_t, built, F, K, tmp, coef, p, table,
                         out)
                out.evaluations += 1   # each load is one evaluation of the accelerations
                inside = inside_end(a, b, left == sides[k, 1])
                # Still rising into the stretch's end: the peak is the sample there.
                searching = _load_on_step(inside, k, left, stage, live_y, live_t, pool_y, pool_t, F, tmp, p) > value
            u = search_golden(a, b)
            if searching:
                out.evaluations += 1
                search = search_from(a, b, u, -_load_on_step(u, k, left, stage, live_y, live_t, pool_y, pool_t, F,
                                                             tmp, p))
            else:
                search = search_from(a, b, u, -value)
        while searching:
            done, u, search = search_next(search)
            if done:
                break
            ref = left if u < t_peak else right
            _prepare(ref, stage, K2, live_y, live_t, pool_k, pool_y, pool_t, built, F, K, tmp, coef, p, table,
                     out)
            out.evaluations += 1
            search = search_update(search, u, -_load_on_step(u, k, ref, stage, live_y, live_t, pool_y, pool_t, F,
                                                             tmp, p))
        if searching and -search.fx > value:
            t_peak, value = search.x, -search.fx
        if value > peaks[k, 0]:
            peaks[k, 0], peaks[k, 1] = value, t_peak


@internal
def keep_step(buffer, t_start, h, t_end, y, y_new, live_y, live_t):
    """Record the step just taken (its stages are in ``K2[buffer]``): its ends and times."""
    for i in range(y.shape[0]):
        live_y[buffer, 0, i], live_y[buffer, 1, i] = y[i], y_new[i]
    live_t[buffer, 0], live_t[buffer, 1], live_t[buffer, 2] = t_start, h, t_end
