"""Where a load peaks: Brent's bounded search around each local maximum of its samples, for both paths.

Both analytic paths sample each load (``stages.loads_at``) at every accepted
step's end, then search the integrator's dense output around every sample
that is a local maximum of the samples (``local_peak``: at least as large as
the samples on either side of it), and keep the largest value found. A load
can have two humps in a stretch (a light arm lets the sling whip and load
twice), and a step straddling the higher one leaves its samples below the
other hump's: the largest sample alone can sit on the wrong hump.

An interior local maximum is searched on the two steps beside it, as one
bracket. The search is Brent's bounded minimiser (Brent 1973, ch. 5) on minus
the load, the algorithm of scipy's ``minimize_scalar(method="bounded")``, to
``PEAK_TIME_TOLERANCE`` plus sqrt(eps) |t|; it starts from the three samples
(``search_around``), so that its first trial is the vertex of the parabola
through them. A local maximum at a stretch's end (at least as large as its one
neighbour) is the peak there unless the load is larger just inside the step
(``inside_end``); then that one step is searched from its golden section
point (``search_golden``, ``search_from``), step for step scipy's.

It is written in reverse communication, as plain arithmetic on floats that
the compiled path compiles too: ``search_golden`` gives the first time to
evaluate, ``search_from`` makes the search's state from the value there,
``search_next`` gives the next time (or says the search is done) and
``search_update`` takes the value found there. The caller evaluates the load,
on its own dense output.

The state is a ``Search``: the bracket ``[a, b]``; the best three points so
far ``x, w, v`` (times) with minus the load there ``fx, fw, fv``; the last
two steps ``d, e``; and the evaluations made.
"""

from __future__ import annotations

import math
from typing import NamedTuple

#: Peak loads are located to this time tolerance, s (plus sqrt(eps) |t|).
PEAK_TIME_TOLERANCE = 1e-10
#: The most evaluations one search makes.
SEARCH_CALLS = 500
_SQRT_EPS = math.sqrt(2.2e-16)
_GOLDEN = 0.5 * (3.0 - math.sqrt(5.0))


class Search(NamedTuple):
    """The state of one search (see the module's docstring); times in s, values minus the load."""

    a: float
    b: float
    x: float
    w: float
    v: float
    fx: float
    fw: float
    fv: float
    d: float
    e: float
    calls: float


def local_peak(before, value, after):
    """Whether a load's sample ``value`` is searched for a peak: at least as large as the samples on
    either side of it, ``before`` and ``after`` (-inf where there is none, at a stretch's ends).
    Never where any of them is NaN."""
    return value >= before and value >= after


def search_golden(a, b):
    """Where a search of ``[a, b]`` from nothing but the bracket starts: its golden section point
    (scipy's ``minimize_scalar(method="bounded")`` starts there)."""
    return a + _GOLDEN * (b - a)


def search_from(a, b, x, fx):
    """The search of ``[a, b]`` after its first evaluation, ``fx`` at ``x = search_golden(a, b)``:
    step for step scipy's bounded minimiser."""
    return Search(a, b, x, x, x, fx, fx, fx, 0.0, 0.0, 1.0)


def search_around(t_before, before, t_peak, peak, t_after, after):
    """The search of ``[t_before, t_after]`` for the largest load around its largest sample, ``peak`` at
    ``t_peak``, from the samples on either side (``before`` at ``t_before``, ``after`` at ``t_after``):
    no evaluation yet.

    The three samples are the search's first three points (Brent's x, w, v), so that its first
    step is the vertex of the parabola through them; the bracket is the two steps beside the
    sample. On the benchmark's designs (``python -m benchmarks``'s sample) a search takes 7.6
    evaluations, against 2 x 24 for a search of each step on its own from its golden section point,
    to the same tolerance; a shot makes about 12 (one for each local maximum of each load's samples).
    """
    if before >= after:
        return Search(t_before, t_after, t_peak, t_before, t_after, -peak, -before, -after, 0.0, t_after - t_before,
                      0.0)
    return Search(t_before, t_after, t_peak, t_after, t_before, -peak, -after, -before, 0.0, t_after - t_before, 0.0)


def inside_end(a, b, at_start):
    """The time just inside the step ``[a, b]`` from its start (``at_start``) or its end, by the
    search's own tolerance: where a load whose largest sample is at that end is evaluated to tell
    whether it peaks there (no larger value just inside) or within the step."""
    if at_start:
        return a + min(_SQRT_EPS * abs(a) + PEAK_TIME_TOLERANCE / 3.0, 0.5 * (b - a))
    return b - min(_SQRT_EPS * abs(b) + PEAK_TIME_TOLERANCE / 3.0, 0.5 * (b - a))


def search_next(s):
    """``(done, u, s)``: the next time ``u`` to evaluate and the state with its step, or done
    (the bracket is within the tolerance of the best point, or ``SEARCH_CALLS`` were made)."""
    xm = 0.5 * (s.a + s.b)
    tol1 = _SQRT_EPS * abs(s.x) + PEAK_TIME_TOLERANCE / 3.0
    tol2 = 2.0 * tol1
    if abs(s.x - xm) <= tol2 - 0.5 * (s.b - s.a) or s.calls >= SEARCH_CALLS or not s.b > s.a:
        return True, s.x, s
    d, e = s.d, s.e
    golden = True
    if abs(e) > tol1:   # a parabola through x, w and v
        r = (s.x - s.w) * (s.fx - s.fv)
        q = (s.x - s.v) * (s.fx - s.fw)
        p = (s.x - s.v) * q - (s.x - s.w) * r
        q = 2.0 * (q - r)
        if q > 0.0:
            p = -p
        q = abs(q)
        r = e
        e = d
        if abs(p) < abs(0.5 * q * r) and p > q * (s.a - s.x) and p < q * (s.b - s.x):
            d = p / q
            u = s.x + d
            if (u - s.a) < tol2 or (s.b - u) < tol2:
                d = tol1 if xm >= s.x else -tol1
            golden = False
    if golden:
        e = (s.a - s.x) if s.x >= xm else (s.b - s.x)
        d = _GOLDEN * e
    u = s.x + (1.0 if d >= 0.0 else -1.0) * max(abs(d), tol1)
    return False, u, Search(s.a, s.b, s.x, s.w, s.v, s.fx, s.fw, s.fv, d, e, s.calls)


def search_update(s, u, fu):
    """The state after evaluating minus the load, ``fu``, at ``u`` (from ``search_next``)."""
    a, b = s.a, s.b
    calls = s.calls + 1.0
    if fu <= s.fx:
        if u >= s.x:
            a = s.x
        else:
            b = s.x
        return Search(a, b, u, s.x, s.w, fu, s.fx, s.fw, s.d, s.e, calls)
    if u < s.x:
        a = u
    else:
        b = u
    if fu <= s.fw or s.w == s.x:
        return Search(a, b, s.x, u, s.w, s.fx, fu, s.fw, s.d, s.e, calls)
    if fu <= s.fv or s.v == s.x or s.v == s.w:
        return Search(a, b, s.x, s.w, u, s.fx, s.fw, fu, s.d, s.e, calls)
    return Search(a, b, s.x, s.w, s.v, s.fx, s.fw, s.fv, s.d, s.e, calls)
