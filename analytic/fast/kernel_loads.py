"""Peak loads in the compiled shot: each load sampled at every step's end, then located on the
interpolants of the steps beside each local maximum of its samples, as the reference path does.

``analytic.fast.kernel.integrate`` calls ``keep_step`` and ``sample_loads`` after
each accepted step and ``finish_peaks`` at a stretch's end. The search is
``analytic.peaks``' (the model's), on the same steps and samples as
``analytic.reference.loads.stage_peaks``. ``out``, the shot's result record
(``kernel.RESULT_DTYPE``), counts the evaluations they take.
"""

from __future__ import annotations

import math

from analytic.fast.marks import internal
from analytic.fast.dop853 import N_STAGES, dense_eval, dense_prepare
from analytic.peaks import (inside_end, local_peak, search_around, search_from, search_golden, search_next,
                            search_update)
from analytic.stages import LOAD_NAMES, loads_at

N_LOADS = len(LOAD_NAMES)

# --------------------------------------------------------------------------- #
# Peak loads: sampled at every step's end, searched around each local maximum
# --------------------------------------------------------------------------- #
# Per load k (``stages.LOAD_NAMES``): ``recent[0, k]`` and ``recent[1, k]`` are
# the stretch's last two samples (-inf: none yet), ``recent[:, N_LOADS]`` their
# times (NaN: none); ``best[k]`` is the largest value the stretch has given so
# far and its time (-inf: none).
#
# A sample is known to be a local maximum (``analytic.peaks.local_peak``) one
# sample later. The two steps beside it are then the integrator's last two, which
# it keeps in two buffers, alternately: the stages K2[b, 0:13] of buffer b (and,
# once its interpolant is built, its three more stages, 13:16), its start and
# full end ``live_y[b]``, and ``live_t[b] = (t_start, h, t_end)``, t_end where
# the stretch stopped within it; ``dense[b]`` is its interpolant where
# ``built[b]``. So each local maximum is searched as soon as it is known, and no
# step is kept longer; only the stretch's last sample waits for ``finish_peaks``.


@internal
def keep_step(buffer, t_start, h, t_end, y, y_new, live_y, live_t, built):
    """Record the step just taken (its stages are in ``K2[buffer]``): its ends and times; no
    interpolant yet."""
    for i in range(y.shape[0]):
        live_y[buffer, 0, i], live_y[buffer, 1, i] = y[i], y_new[i]
    live_t[buffer, 0], live_t[buffer, 1], live_t[buffer, 2] = t_start, h, t_end
    built[buffer] = False


@internal
def _prepare(b, stage, K2, live_y, live_t, dense, built, tmp, coef, p, table, out):
    """The dense output of the step in live buffer ``b`` in ``dense[b]``, unless it is ``built`` already."""
    if built[b]:
        return
    dense_prepare(stage, live_t[b, 0], live_t[b, 1], live_y[b, 0], live_y[b, 1], K2[b, N_STAGES], coef, K2[b],
                  dense[b], tmp, p, table)
    out.evaluations += 3
    built[b] = True


@internal
def _load_on_step(u, k, b, stage, K2, live_y, live_t, dense, built, tmp, coef, p, table, out):
    """Load ``k`` at time ``u`` on the dense output of the step in live buffer ``b`` (built if it is not)."""
    _prepare(b, stage, K2, live_y, live_t, dense, built, tmp, coef, p, table, out)
    out.evaluations += 1   # each load is one evaluation of the accelerations
    dense_eval(u, live_t[b, 0], live_t[b, 1], live_y[b, 0], dense[b], tmp)
    return loads_at(stage, tmp, p)[k]


@internal
def _search_sample(k, left, right, t_before, before, t_peak, value, t_after, after, stage, K2, live_y, live_t,
                   dense, built, tmp, coef, p, table, out):
    """Load ``k``'s largest value and its time, ``(value, t)``, around its sample ``value`` at ``t_peak``,
    a local maximum of its samples, with the samples ``before`` and ``after`` it: on the steps in live
    buffers ``left`` (ending at the sample) and ``right`` (from it), -1 for none. As
    ``analytic.reference.loads.stage_peaks`` searches; the sample itself where it is the peak."""
    if left >= 0 and right >= 0 and t_before < t_peak < t_after:
        # Both steps beside the sample, as one bracket: each time on its own step's interpolant.
        search = search_around(t_before, before, t_peak, value, t_after, after)
    else:   # the sample ends the stretch: the one step beside it
        one = left if left >= 0 else right
        if one < 0:
            return value, t_peak
        a, b = live_t[one, 0], live_t[one, 2]
        if not b > a:
            return value, t_peak
        inside = inside_end(a, b, left < 0)
        if not _load_on_step(inside, k, one, stage, K2, live_y, live_t, dense, built, tmp, coef, p, table,
                             out) > value:
            return value, t_peak   # still rising into the stretch's end: the peak is the sample there
        left, right = one, one
        u = search_golden(a, b)
        search = search_from(a, b, u, -_load_on_step(u, k, one, stage, K2, live_y, live_t, dense, built, tmp, coef,
                                                     p, table, out))
    while True:
        done, u, search = search_next(search)
        if done:
            return -search.fx, search.x
        ref = left if u < t_peak else right
        search = search_update(search, u, -_load_on_step(u, k, ref, stage, K2, live_y, live_t, dense, built, tmp,
                                                         coef, p, table, out))


@internal
def start_peaks(recent, best, built):
    """A stretch's peak state before its first sample: no samples, no steps, nothing found."""
    built[0], built[1] = False, False
    for k in range(N_LOADS):
        recent[0, k], recent[1, k] = -math.inf, -math.inf
        best[k, 0], best[k, 1] = -math.inf, -math.inf
    recent[0, N_LOADS], recent[1, N_LOADS] = math.nan, math.nan


@internal
def sample_loads(t, values, buffer, recent, best, stage, K2, live_y, live_t, dense, built, tmp, coef, p, table,
                 out):
    """Take the loads ``values`` at ``t``, where the step in live ``buffer`` stopped (-1: the
    stretch's first sample, no step), and search around the sample before it where that one is
    a local maximum, keeping each load's largest in ``best``."""
    t_before, t_last = recent[0, N_LOADS], recent[1, N_LOADS]
    # The step ending at the last sample, none where that sample opened the stretch.
    left = 1 - buffer if buffer >= 0 and not math.isnan(t_before) else -1
    for k in range(N_LOADS):
        if values[k] > best[k, 0]:
            best[k, 0], best[k, 1] = values[k], t
        if buffer >= 0 and local_peak(recent[0, k], recent[1, k], values[k]):
            # (Not larger than the sample searched: taken before it or after, it changes nothing.)
            found, when = _search_sample(k, left, buffer, t_before, recent[0, k], t_last, recent[1, k], t, values[k],
                                         stage, K2, live_y, live_t, dense, built, tmp, coef, p, table, out)
            if found > best[k, 0]:
                best[k, 0], best[k, 1] = found, when
        recent[0, k], recent[1, k] = recent[1, k], values[k]
    recent[0, N_LOADS], recent[1, N_LOADS] = t_last, t


@internal
def finish_peaks(buffer, recent, best, peaks, stage, K2, live_y, live_t, dense, built, tmp, coef, p, table, out):
    """At the stretch's end, its last step in live ``buffer`` (-1: none): search around the last
    sample where it is a local maximum, then keep each load's largest in ``peaks`` (N_LOADS, 2) where
    it beats them."""
    t_last = recent[1, N_LOADS]
    for k in range(N_LOADS):
        if local_peak(recent[0, k], recent[1, k], -math.inf):
            found, when = _search_sample(k, buffer, -1, recent[0, N_LOADS], recent[0, k], t_last, recent[1, k],
                                         math.nan, -math.inf, stage, K2, live_y, live_t, dense, built, tmp, coef, p,
                                         table, out)
            if found > best[k, 0]:
                best[k, 0], best[k, 1] = found, when
        if best[k, 0] > peaks[k, 0]:
            peaks[k, 0], peaks[k, 1] = best[k, 0], best[k, 1]
