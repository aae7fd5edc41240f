"""Integrate an ODE until an event, with events that may be armed or disarmed by the state.

``scipy.integrate.solve_ivp`` stops at any root of a terminal event; the release
rule needs more (a root counts only when the velocity points along the release
angle, not opposite it, and the direction may sweep past the opposite many
times first). So this module steps scipy's ``DOP853`` solver itself, watches
the event functions between accepted steps, and locates each root on the
step's dense output with Brent's method -- the same scheme ``solve_ivp`` uses,
plus an ``armed`` predicate checked at the root. A step whose two ends show
no sign change may still hold two roots of an event, where its value crosses
zero and comes back; so the value's rate is watched at the step's ends too,
and a step where the value turns back is searched for its extremum
(``analytic.sequence``: the policy both paths share, with its reasons).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, NamedTuple

import numpy as np
from scipy.integrate import DOP853, OdeSolution
from scipy.optimize import brentq

from analytic.sequence import (counted_crossing, event_rate, leaves_zero, past_root, probe_bracket, probe_time,
                               probe_update, rate_offset, tangent_state, turn_bracket, turn_first, turn_next,
                               turn_search, turn_update, turns_back)
from analytic.stages import ROOT_RELATIVE_TOLERANCE, ROOT_TIME_TOLERANCE, ZERO_START_PROBES, first_event


class IntegrationError(RuntimeError):
    """The solver failed (step size underflow, non-finite state, or ``step_limit``: it took
    ``max_steps`` steps without finishing) at ``time``, s; ``segment`` is what it integrated
    until then (a ``Segment`` ending at the last finite state, or None)."""

    def __init__(self, message: str, time: float, step_limit: bool = False, segment=None):
        super().__init__(message)
        self.time = time
        self.step_limit = step_limit
        self.segment = segment


@dataclass(frozen=True)
class Event:
    """A zero crossing to watch for.

    Attributes
    ----------
    name : reported back when this event ends the integration.
    value : ``value(t, y) -> float``, continuous along the solution.
    direction : +1 counts rising crossings only, -1 falling only, 0 both.
    armed : optional ``armed(t, y) -> bool`` evaluated at the root; a root
        where it is false is ignored and integration continues.
    terminal : stop at the first counted root (otherwise just record it); of two
        within the root finder's tolerance of each other, at the one listed first
        in ``events`` (``analytic.stages.first_event``).
    turns : also search a step whose values at its ends have one sign but whose
        value turns back within it, for a root there (``analytic.sequence``).
    """

    name: str
    value: Callable[[float, np.ndarray], float]
    direction: int = 0
    armed: Callable[[float, np.ndarray], bool] | None = None
    terminal: bool = True
    turns: bool = True


@dataclass(frozen=True)
class Segment:
    """One integrated stretch.

    Attributes
    ----------
    t : (n,) output times (a fixed grid of spacing ``output_step`` plus the end), s.
    y : (n, m) states at ``t``.
    event : name of the terminal event that ended it, or None if ``t_end`` was reached.
    t_end : float, where it ended, s; y_end : (m,) the state there.
    roots : name -> list of (t, y) for non-terminal events that were counted.
    solution : the continuous solution on [t[0], t_end] (``OdeSolution``; None
        for a segment of zero length, or when neither samples nor ``continuous`` were asked for).
    step_t : (k,) the start, every accepted step's end and the end, s.
    step_y : (k, m) the states there.
    step_f : (k, m) the derivative there, as the integrator computed it (a row of NaN where it
        did not: the start and an event's root).
    steps : each accepted step whole, as a ``Step`` (``step_interpolant`` builds its dense output
        from it): ``steps[j]`` is the one from ``step_t[j]`` (an event's root ends the last early).
    """

    t: np.ndarray
    y: np.ndarray
    event: str | None
    t_end: float
    y_end: np.ndarray
    roots: dict[str, list[tuple[float, np.ndarray]]]
    solution: OdeSolution | None = None
    step_t: np.ndarray | None = None
    step_y: np.ndarray | None = None
    step_f: np.ndarray | None = None
    steps: tuple[Step, ...] | None = None


class Step(NamedTuple):
    """One accepted DOP853 step, whole: from ``(t_old, y_old)`` to ``(t, y)`` (derivative ``f``
    there), with its twelve stages' derivatives and the first at its start (``K``, (13, m)):
    what the step's dense output is made of (``step_interpolant``). Its size is ``t - t_old``,
    as scipy computes it."""

    t_old: float
    t: float
    y_old: np.ndarray
    y: np.ndarray
    f: np.ndarray
    K: np.ndarray


def integrate(fun: Callable[[float, np.ndarray], np.ndarray], t0: float, y0: np.ndarray,
              t_end: float, events: tuple[Event, ...] = (), *, rtol: float, atol: float,
              output_step: float | None, continuous: bool = False, max_steps: int | None = None) -> Segment:
    """Integrate ``y' = fun(t, y)`` from ``t0`` until a terminal event or ``t_end``.

    Parameters
    ----------
    fun : right-hand side, returns shape (m,).
    y0 : (m,) initial state.
    events : watched zero crossings; a crossing counts when the value goes
        from strictly one side of zero to zero or the other side, between a
        step's ends or, for an event with ``turns``, within a step where it
        turns back (``analytic.sequence``).
    rtol, atol : DOP853 tolerances.
    output_step : spacing of the returned samples, s. None: no samples but the
        two ends and no continuous ``solution``; the step's interpolant is then
        built only for a step that holds an event's root (3 evaluations saved
        on every other step).
    continuous : build the continuous ``solution`` even without samples.
    max_steps : accepted steps allowed before ``t_end`` (the reference path's stages:
        ``analytic.limits.STAGE_STEP_LIMITS``); None for no limit.

    Raises
    ------
    IntegrationError
        The step size fell below the resolution of t, the state became
        non-finite, or ``max_steps`` steps did not reach the end.
    """
    solver = DOP853(fun, t0, np.asarray(y0, dtype=float), t_end, rtol=rtol, atol=atol)
    trace = _Trace.start(t0, solver.y, events)
    record = output_step is not None or continuous
    if not np.isfinite(solver.h_abs):
        # A non-finite start or derivative: scipy would shrink a NaN step forever.
        raise trace.failure(f"non-finite derivative at the start, t = {t0:.6g} s", solver.t, t0, solver.y)
    previous = [event.value(t0, solver.y) for event in events]
    # Each event's rate at the step's start: none at the stretch's start, whose first step is not
    # searched for turns (analytic.sequence).
    rates = [math.nan] * len(events)
    behind = np.empty(len(solver.y))
    next_output = t0 + output_step if output_step is not None else np.inf
    steps = 0
    while solver.status == "running":
        _step(solver, steps, max_steps, trace)
        steps += 1
        dense = solver.dense_output() if record else _LazyDense(solver)
        if record:
            trace.step_ends.append(solver.t)
            trace.interpolants.append(dense)
        current = [event.value(solver.t, solver.y) for event in events]
        rates_after = _rates(events, current, solver.t, solver.y, solver.f, rate_offset(solver.t - solver.t_old),
                             behind)
        hit_t, hit_k = _first_root(events, previous, current, rates, rates_after, dense, solver.t_old, solver.t,
                                   trace.roots)
        previous, rates = current, rates_after
        t_stop = solver.t if hit_k < 0 else hit_t
        trace.step_t.append(t_stop)
        trace.step_y.append(solver.y.copy() if hit_k < 0 else dense(t_stop))
        trace.step_f.append(solver.f.copy() if hit_k < 0 else trace.unknown)
        while next_output < t_stop:
            trace.sample(next_output, dense(next_output))
            next_output += output_step
        if hit_k >= 0:
            return trace.ended_at(events[hit_k].name, hit_t, dense(hit_t), record)
    if trace.times[-1] < solver.t:
        trace.sample(solver.t, solver.y.copy())
    return trace.segment(None, solver.t, solver.y.copy(), trace.solution())


def _step(solver: DOP853, steps: int, max_steps: int | None, trace: _Trace) -> None:
    """One accepted step of ``solver`` (its ``steps``-th), kept whole in ``trace``; an ``IntegrationError``
    where it cannot be taken: ``max_steps`` steps taken already, the step size underflowed, or the
    state became non-finite (the segment up to the last finite state)."""
    if max_steps is not None and steps >= max_steps:
        raise trace.failure(f"{max_steps} steps did not reach the end, at t = {solver.t:.6g} s with a step "
                            f"of {solver.step_size:.3g} s", solver.t, solver.t, solver.y, step_limit=True)
    message = solver.step()
    if solver.status == "failed":
        raise trace.failure(f"integration failed at t = {solver.t:.6g} s: {message}", solver.t, solver.t, solver.y)
    if not np.all(np.isfinite(solver.y)):
        raise trace.failure(f"non-finite state at t = {solver.t:.6g} s", solver.t, solver.t_old, solver.y_old)
    # scipy gives each step new y and f arrays, and writes the next step's stages over K.
    trace.steps.append(Step(solver.t_old, solver.t, solver.y_old, solver.y, solver.f, solver.K.copy()))


def _first_root(events: tuple[Event, ...], previous: list[float], current: list[float], rates: list[float],
                rates_after: list[float], dense, t_old: float, t_new: float,
                roots: dict[str, list]) -> tuple[float, int]:
    """The terminal root that ends the step ``[t_old, t_new]``, from each event's values and rates at its
    ends (``previous``, ``rates``; ``current``, ``rates_after``) and the step's ``dense`` output:
    ``(t, k)``, the root and its event's index (``(inf, -1)``: none; of two at one instant, the
    event listed first: ``stages.first_event``). The non-terminal roots that count are added to
    ``roots``."""
    hit_t, hit_k = np.inf, -1
    for k, (event, before, after) in enumerate(zip(events, previous, current, strict=True)):
        for t_root in _crossings(event, before, after, rates[k], rates_after[k], dense, t_old, t_new):
            y_root = dense(t_root)
            if event.armed is not None and not event.armed(t_root, y_root):
                continue
            if event.terminal:
                hit_t, hit_k = first_event(t_root, k, hit_t, hit_k)
                break
            roots[event.name].append((t_root, y_root))
    return hit_t, hit_k


@dataclass
class _Trace:
    """What ``integrate`` keeps of a stretch as it goes, to make its ``Segment``: the samples (``times``,
    ``states``), every step's end, state and derivative (``step_*``: ``unknown`` where none was computed),
    the steps whole, the interpolants (``step_ends`` their breaks) and the non-terminal roots counted."""

    times: list
    states: list
    step_t: list
    step_y: list
    step_f: list
    unknown: np.ndarray
    steps: list
    step_ends: list
    interpolants: list
    roots: dict[str, list[tuple[float, np.ndarray]]]

    @classmethod
    def start(cls, t0: float, y0: np.ndarray, events: tuple[Event, ...]) -> _Trace:
        """The trace of a stretch starting at ``(t0, y0)``, watching ``events``."""
        unknown = np.full(len(y0), np.nan)
        return cls([t0], [y0.copy()], [t0], [y0.copy()], [unknown], unknown, [], [t0], [],
                   {e.name: [] for e in events if not e.terminal})

    def sample(self, t: float, y: np.ndarray) -> None:
        self.times.append(t)
        self.states.append(y)

    def solution(self) -> OdeSolution | None:
        """The continuous solution of the steps kept; None without one."""
        return OdeSolution(self.step_ends, self.interpolants) if self.interpolants else None

    def segment(self, event: str | None, t_end: float, y_end: np.ndarray, solution: OdeSolution | None) -> Segment:
        return Segment(np.array(self.times), np.array(self.states), event, t_end, y_end, self.roots, solution,
                       np.array(self.step_t), np.array(self.step_y), np.array(self.step_f), tuple(self.steps))

    def ended_at(self, event: str, t_hit: float, y_hit: np.ndarray, record: bool) -> Segment:
        """The segment ended by ``event``'s root at ``(t_hit, y_hit)``: the last sample, and the roots counted
        up to it; the continuous solution where it was ``record``-ed."""
        self.sample(t_hit, y_hit)
        for name in self.roots:
            self.roots[name] = [(t, y) for t, y in self.roots[name] if t <= t_hit]
        return self.segment(event, t_hit, y_hit, OdeSolution(self.step_ends, self.interpolants) if record else None)

    def failure(self, message: str, t_failed: float, t_last: float, y_last: np.ndarray,
                step_limit: bool = False) -> IntegrationError:
        """The error of a failure at ``t_failed``, with the segment integrated up to the last finite state
        ``(t_last, y_last)``."""
        if self.times[-1] < t_last:
            self.sample(t_last, y_last.copy())
        if self.step_t[-1] < t_last:
            self.step_t.append(t_last)
            self.step_y.append(y_last.copy())
            self.step_f.append(self.unknown)
        return IntegrationError(message, t_failed, step_limit, self.segment(None, t_last, y_last.copy(),
                                                                            self.solution()))


def step_interpolant(fun: Callable[[float, np.ndarray], np.ndarray], step: Step, *, rtol: float, atol: float):
    """The dense output of an accepted ``step`` (a ``Segment``'s ``steps``), as scipy built it
    for that step: its stages kept, only the interpolant's three extra ones evaluated.

    Cheaper than keeping every step's interpolant for the few that hold a peak (3
    derivatives a step), or than taking the step again (16 derivatives: a solver's first, the
    twelve stages, the three). scipy's ``DOP853`` builds it from the state of its last step,
    which this sets (``t_old``, ``y_old``, ``h_previous`` and the stages ``K``: attributes of
    scipy's solver, not its documented interface; ``tests/test_analytic_integrate.py`` checks
    the result, to the bit, against the interpolants scipy built while integrating).
    """
    solver = DOP853(fun, step.t_old, step.y_old, step.t, rtol=rtol, atol=atol, first_step=step.t - step.t_old)
    solver.t_old, solver.y_old, solver.h_previous = step.t_old, step.y_old, step.t - step.t_old
    solver.t, solver.y, solver.f = step.t, step.y, step.f
    solver.K[:] = step.K
    return solver.dense_output()


class _LazyDense:
    """The solver's last-step interpolant, built on first use (for root finding)."""

    def __init__(self, solver: DOP853):
        self._solver = solver
        self._dense = None

    def __call__(self, t: float) -> np.ndarray:
        if self._dense is None:
            self._dense = self._solver.dense_output()
        return self._dense(t)


def _rates(events, values, t: float, y: np.ndarray, f: np.ndarray, offset: float, behind: np.ndarray) -> list[float]:
    """Each event's rate at ``(t, y)`` where its value is ``values[k]`` and the state's derivative ``f``
    (``analytic.sequence.event_rate``, over ``offset`` s); NaN for one whose turns are not searched
    (``Event.turns``); ``behind`` is scratch."""
    tangent_state(y, f, offset, behind)
    return [event_rate(value, event.value(t - offset, behind), offset) if event.turns else math.nan
            for event, value in zip(events, values, strict=True)]


def _crossings(event: Event, before: float, after: float, rate_before: float, rate_after: float, dense,
               t_old: float, t_new: float):
    """Roots of ``event.value`` in (t_old, t_new] in the counted direction, from its values and rates
    at the step's ends.

    Normally a step holds at most one root; if the armed check rejects it the
    step's remainder is searched again, so a step that holds both the crossing
    of the opposite direction and the real one still finds the real one. A step
    whose value turns back (``analytic.sequence.turns_back``) is searched for
    its extremum first, and the root on the counted side of it bracketed.
    """
    def value(t: float) -> float:
        return event.value(t, dense(t))

    start, v_start, end, v_end = t_old, before, t_new, after
    if leaves_zero(before, after):
        # Left zero at the step's start (a rate a friction switch set to 0): it may have come
        # back within the step. Probe the dense output for the other side, and bracket there.
        i, low, v_low, high, v_high = 1, -1, math.nan, -1, math.nan
        while i < ZERO_START_PROBES:
            i, low, v_low, high, v_high = probe_update(i, value(probe_time(t_old, t_new, i)), after,
                                                       low, v_low, high, v_high)
        start, v_start, end, v_end = probe_bracket(t_old, t_new, before, after, low, v_low, high, v_high)
    elif turns_back(before, after, rate_before, rate_after):
        u = turn_first(t_old, t_new, rate_before, rate_after)
        v = value(u)
        search = turn_search(t_old, t_new, before, after, u, v)
        while True:
            done, u_next, search = turn_next(search, before, v)
            if done:
                break
            u, v = u_next, value(u_next)
            search = turn_update(search, before, u, v)
        start, v_start, end, v_end = turn_bracket(t_old, t_new, before, after, u, v, event.direction)
    while counted_crossing(v_start, v_end, event.direction):
        t_root = end if v_end == 0.0 else brentq(value, start, end, xtol=ROOT_TIME_TOLERANCE,
                                                 rtol=ROOT_RELATIVE_TOLERANCE)
        yield t_root
        # Rejected: look for a later root in the same step, past this one.
        start = past_root(t_root, t_new)
        if start >= t_new:
            return
        v_start = value(start)
        end, v_end = t_new, after
