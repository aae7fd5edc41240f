"""The fast path: whole shots at compiled speed, one design or arrays of them on every core.

``simulate_fast(design)`` gives the same ``Shot`` summary as
``analytic.reference.simulate`` (status, message, lift-off, release, landing,
apex) without the histories, from the compiled three-stage shot in
``analytic.fast.kernel``. ``shoot(designs)`` runs many designs at once on all
cores (Python threads; the compiled shot releases the GIL) and returns
arrays (``Shots``): what the optimiser and the cross-check use by default.

The two paths run the same model source (``analytic.eom``, ``stages``,
``geometry``, ``aero``, ``limits``; compiled here by ``analytic.fast.compiled``),
the same integrator algorithm with the same coefficients (DOP853, scipy's
arrays) and the same root tolerance, so with the same tolerances they agree
to round-off (2e-15 relative in range, median over the benchmark's
designs), or, where a rounding sends the step control down another sequence
of steps, to the integrator's own error (7e-9 at worst there): far inside
what the tests demand (1e-7 relative in range, 1e-6 s in event times, the
same outcome).

Friction (``[losses]``) runs on this path too, from the same stage
functions; its energy audit does not: ``Shot.energy_dissipated`` is None
here (the reference path integrates the drag's work on its continuous
solution, which this path does not keep).

The kernel is compiled in a few scopes (``analytic.scope``): the ideal
machine without its peak loads, with them, and everything. A batch runs in the
smallest scope that holds all its designs and what is asked of them (the
same bits in any scope that holds it), and a scope compiles only when first
needed. Each scope's machine code is cached on disk (numba ``cache=True``):
``compile(scope)`` loads or builds it and says how long that took; the first
shot in a scope calls it, and ``compile_all`` (``python -m analytic compile``,
which ``make`` runs) readies them all.
"""

from __future__ import annotations

import contextlib
import itertools
import math
import os
import subprocess
import sys
import time
from collections import namedtuple
from concurrent.futures import ThreadPoolExecutor
from typing import Sequence

import numba
import numpy as np
from scipy.integrate import DOP853

from analytic import ideal, outcome, stages
from analytic.fast import kernel
from analytic.fast.compiled import kernel_scope
from analytic.aero import DRAG_TABLE
from analytic.design import Design, largest_length
from analytic.friction import holders, rest_balance
from analytic.limits import DEFAULT_ATOL, DEFAULT_RTOL, swing_time_limit
from analytic.geometry import IDEAL_RULE
from analytic.parameters import N_PARAMS, Params, params
from analytic.result import PEAK_NAMES, Shot, Shots, Status
from analytic.scope import SCOPES, Scope, needed, needed_rows

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


def check_tolerances(rtol: float, atol: float) -> None:
    for name, value in (("rtol", rtol), ("atol", atol)):
        if not (0.0 < value < 1.0):
            raise ValueError(f"{name} = {value!r}: the integrator tolerance must lie in (0, 1)")


# --------------------------------------------------------------------------- #
# Compilation
# --------------------------------------------------------------------------- #

#: Seconds each scope's ``compile`` took, by scope name.
_compile_seconds: dict[str, float] = {}
#: ``kernel.shots``' recording arguments when it records nothing.
_NO_RECORDING = np.empty(0, kernel.RECORDING_DTYPE)
_NO_SAMPLES = np.empty(0, kernel.SAMPLE_DTYPE)


def _entry_signature() -> tuple:
    """numba types of ``kernel.shots``' arguments, as every caller passes them."""
    rows = np.zeros((1, N_PARAMS))
    out = np.empty(1, kernel.RESULT_DTYPE)
    return tuple(numba.typeof(a) for a in (rows, 0, 1, DRAG_TABLE, COEFFICIENTS, DEFAULT_RTOL,
                                           DEFAULT_ATOL, True, out, _NO_RECORDING, _NO_SAMPLES))


#: numba's name for the pass that lowers a function to LLVM and, for the entry point, optimises
#: and emits the whole kernel (``_compile_progress``'s last label).
LOWERING_PASS = "native_lowering"


@contextlib.contextmanager
def _compile_progress(enabled: bool, scope: Scope):
    """While compiling (not while loading from the cache): a line on stderr, then a running count."""
    from numba.core import event
    from analytic.cli_shared import progress_bar

    class Listener(event.Listener):
        """Counts the model's and the kernel's functions as they compile (numba's own helpers too,
        unnamed), and names the one under way."""
        bar = None
        under_way: list[str] = []

        def on_start(self, ev):
            if self.bar is None:
                print(f"compiling the fast path's {scope.name} scope once (tens of seconds); "
                      "later runs load it from the cache in under a second", file=sys.stderr, flush=True)
                self.bar = progress_bar(desc="compiling", unit=" functions", file=sys.stderr, mininterval=0.5,
                                leave=False)   # gone when done: `analytic compile` then prints the time
            function = ev.data["dispatcher"].py_func
            if function.__module__.startswith("analytic."):
                self.under_way.append(function.__name__)
                self.bar.set_postfix_str(function.__name__, refresh=False)

        def on_end(self, ev):
            if ev.data["dispatcher"].py_func.__module__.startswith("analytic."):
                self.under_way.pop()
                self.bar.set_postfix_str(self.under_way[-1] if self.under_way else "", refresh=False)
            self.bar.update()

    class LastStep(event.Listener):
        """Names the last seconds, in which no function is counted: the entry point's lowering,
        where LLVM optimises the whole kernel and emits its machine code.

        It knows that step by numba's name for its pass (``LOWERING_PASS``), which numba does not
        promise to keep: where the name or the event's fields differ, the label is not shown, and
        nothing else changes (a listener that raised would fail the compile)."""

        def on_start(self, ev):
            try:
                data = ev.data
                if (listener.bar is not None and data.get("qualname") == entry_point(scope).py_func.__qualname__
                        and str(data.get("name", "")).startswith(LOWERING_PASS)):
                    listener.bar.set_postfix_str("the whole kernel's machine code")
            except Exception:
                pass

        def on_end(self, ev):
            pass

    if not enabled:
        yield
        return
    listener = Listener()
    with contextlib.ExitStack() as listening:
        listening.enter_context(event.install_listener("numba:compile", listener))
        with contextlib.suppress(Exception):   # (an event kind numba no longer has: no last label)
            listening.enter_context(event.install_listener("numba:run_pass", LastStep()))
        yield
    if listener.bar is not None:
        listener.bar.close()


def entry_point(scope: Scope):
    """``scope``'s compiled ``kernel.shots`` (``analytic.fast.compiled.kernel_scope``)."""
    return kernel_scope(scope)["kernel"].shots


def compile(scope: Scope | None = None, *, progress: bool = False) -> float:
    """Load ``scope``'s kernel from the disk cache, or compile and cache it; seconds taken.

    The first shot in a scope calls it; later calls return the first call's
    time. In a fresh checkout a scope compiles once (tens of seconds; ``make``
    does it when it installs); afterwards it loads, in under a second.

    Parameters
    ----------
    scope : one of ``analytic.scope.SCOPES``; None: each of them in turn (the seconds summed).
    progress : when it compiles, say so on stderr and count the functions compiled.
    """
    if scope is None:
        return sum(compile(each, progress=progress) for each in SCOPES)
    if scope.name not in _compile_seconds:
        began = time.perf_counter()
        with _compile_progress(progress, scope):
            entry_point(scope).compile(_entry_signature())
        _compile_seconds[scope.name] = time.perf_counter() - began
    return _compile_seconds[scope.name]


def compile_all(scopes: Sequence[Scope] = SCOPES, *, progress: bool = False) -> dict[str, float]:
    """Ready each of ``scopes`` (``compile``): seconds each took, by scope name.

    What ``python -m analytic compile`` (and so ``make``) runs, so that no later command
    stalls on a compile. With two processors or more the scopes compile in child processes,
    one per processor (each scope has its own files in the disk cache): the largest each in
    a child of its own, the smallest in turn in the last; this process then loads them. On 2
    cores the largest compiles beside the other two, which take about as long together.
    """
    workers = min(default_threads(), len(scopes))
    if workers <= 1:
        return {scope.name: compile(scope, progress=progress) for scope in scopes}

    def child(group: Sequence[Scope]) -> dict[str, float]:
        # Each scope's seconds on a line as it is ready; then the child leaves at once (os._exit),
        # its cache written: tearing down what a cold compile leaves behind takes a second, for nothing.
        code = ("import os; from analytic import fast, scope\n"
                + "".join(f"print('{s.name}', fast.compile(scope.{s.name.upper()}), flush=True)\n" for s in group)
                + "os._exit(0)")
        seconds = dict.fromkeys((s.name for s in group), math.nan)
        with subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True) as running:
            for line in running.stdout:
                name, _, value = line.partition(" ")
                if name in seconds:
                    seconds[name] = float(value)
                    if progress:
                        print(f"  {name}: {seconds[name]:.1f} s", file=sys.stderr, flush=True)
        return seconds

    if progress:
        print(f"compiling the fast path's scopes ({', '.join(s.name for s in scopes)}), {workers} at a time, "
              "once (tens of seconds); later runs load them from the cache", file=sys.stderr, flush=True)
    largest_first = sorted(scopes, key=SCOPES.index, reverse=True)
    groups = [[scope] for scope in largest_first[:workers - 1]] + [largest_first[workers - 1:]]
    children: dict[str, float] = {}
    with ThreadPoolExecutor(workers) as pool:
        for seconds in pool.map(child, groups):
            children.update(seconds)
    # Load what the children compiled (or, where one failed, compile it here).
    return {scope.name: max(children[scope.name], compile(scope)) if math.isfinite(children[scope.name])
            else compile(scope, progress=progress) for scope in scopes}


def _ready(scope: Scope):
    """``scope``'s compiled entry point, loaded or compiled: only a scope's first use in a
    checkout compiles, and then says so on stderr with its progress, on a terminal as a bar
    and elsewhere (a notebook, a log, a pipe) as a line every few seconds
    (``cli_shared.progress_bar``); loading from the cache says nothing."""
    if scope.name not in _compile_seconds:
        compile(scope, progress=True)
    return entry_point(scope)


# --------------------------------------------------------------------------- #
# One design
# --------------------------------------------------------------------------- #

def simulate_fast(design: Design, *, rtol: float = DEFAULT_RTOL, atol: float = DEFAULT_ATOL,
                  loads: bool = True) -> Shot:
    """``simulate(design)``'s summary, compiled: no histories or energies; the peak loads.

    Parameters
    ----------
    design : a validated ``Design``.
    rtol, atol : the integrator's tolerances, as for ``analytic.reference.simulate``.
    loads : find the peak loads (False: they are None, a little sooner; the benchmark
        measures how much).

    Returns
    -------
    Shot
        Status, message, lift-off, release, landing, apex and the peak loads; a valid design
        that does not throw is a ``Shot`` with its failure's status, never an
        exception.
    """
    check_tolerances(rtol, atol)
    return to_shot(design, shoot_one(design, rtol, atol, loads))


def shoot_one(design: Design, rtol: float, atol: float, loads: bool, rec: np.ndarray = None,
              samples: np.ndarray = None) -> np.void:
    """The kernel's result record (``kernel.RESULT_DTYPE``) of one design; ``rec`` (one record of
    ``kernel.RECORDING_DTYPE``) and ``samples`` (of ``kernel.SAMPLE_DTYPE``) record its motion
    (``analytic.fast.kernel.shot``; None: not recorded)."""
    p = params(design)
    if p.rule == IDEAL_RULE:   # the arm angle of the longest throw (analytic.ideal)
        p = p._replace(alpha=_ideal_arm_angle(np.array(p, dtype=np.float64), rtol, atol))
    row = np.array(p, dtype=np.float64)[np.newaxis]
    shots = _ready(needed(p, loads, recording=rec is not None))
    out = np.empty(1, kernel.RESULT_DTYPE)
    shots(row, 0, 1, DRAG_TABLE, COEFFICIENTS, rtol, atol, bool(loads), out,
          _NO_RECORDING if rec is None else rec, _NO_SAMPLES if samples is None else samples)
    return out[0]


#: A result record's fields as Python values (``to_shot``): one conversion (``numpy.void.item``), not one a field.
_Result = namedtuple("_Result", kernel.RESULT_DTYPE.names)


def to_shot(design: Design, out: np.void) -> Shot:
    """The ``Shot`` (no histories) of a kernel result record ``out`` (``kernel.RESULT_DTYPE``)."""
    row = _Result._make(out.item())
    status = Status.from_code(row.status)
    fields = {}
    if not math.isnan(row.liftoff_time):
        fields["liftoff_time"] = row.liftoff_time
    for (value, at), name in zip(row.peaks.tolist(), PEAK_NAMES, strict=True):
        if math.isfinite(value):
            fields[name], fields[f"{name}_time"] = value, at
    if not math.isnan(row.release_time):
        fields.update(release_time=row.release_time, release_position=row.release_position.copy(),
                      release_velocity=row.release_velocity.copy(),
                      frame_release_displacement=row.frame_release_displacement,
                      frame_release_velocity=row.frame_release_velocity)
    if status is Status.OK:
        message = outcome.thrown_message(row.landing_x)
        fields.update(landing_time=row.landing_time,
                      landing_position=np.array([row.landing_x,
                                                 design.environment.target_height - design.machine.pivot_height]),
                      apex_height=row.apex_height)
    elif status is Status.SHORT_OF_TARGET:
        message = outcome.failure_message(status, apex=(row.apex_height, design.environment.target_height))
        fields["apex_height"] = row.apex_height
    else:
        t_limit = swing_time_limit(largest_length(design.machine), design.environment.gravity)
        message = failure_message(design, status, row.detail, row.rest_acceleration, row.out_of_steps,
                                  row.end_time, row.release_time, t_limit)
    return Shot(design, status, message, **fields)


def failure_message(design: Design, status: Status, detail: int, rest_acceleration: float, out_of_steps: bool,
                    end_time: float, release_time: float, t_limit: float) -> str:
    """The message of a failed shot from the kernel's record of it (``outcome.failure_message``)."""
    fires = (rest_acceleration,)
    if status is Status.NEVER_FIRES and not design.losses.ideal:
        p = params(design)
        fires = (stages.fires(p).ddtheta, *rest_balance(p), outcome.friction_holders(*holders(p)))
    m = design.machine
    return outcome.failure_message(status, time=end_time - release_time if status is Status.NO_LANDING else end_time,
                                   detail=detail, time_limit=t_limit, release=(m.release_rule, m.release_angle),
                                   fires=fires, step_limit=out_of_steps)


# --------------------------------------------------------------------------- #
# Many designs
# --------------------------------------------------------------------------- #

def default_threads() -> int:
    """Threads a batch runs on by default: the processors this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:   # not on Linux
        return os.cpu_count() or 1


def _shoot_rows(rows: np.ndarray, rtol: float, atol: float, threads: int | None,
                loads: bool = True) -> np.ndarray:
    """The kernel's result records (S,) of ``kernel.RESULT_DTYPE`` for design rows (S, N_PARAMS), on
    ``threads`` threads."""
    check_tolerances(rtol, atol)
    rows = np.ascontiguousarray(rows, dtype=np.float64)
    if rows.ndim != 2 or rows.shape[1] != N_PARAMS:
        raise ValueError(f"designs: expected rows of shape (S, {N_PARAMS}), got {rows.shape}")
    threads = default_threads() if threads is None else threads
    loads = bool(loads)
    if threads < 1:
        raise ValueError(f"threads = {threads!r}: need at least one")
    ideal_rows = np.flatnonzero(rows[:, _RULE] == IDEAL_RULE)
    if len(ideal_rows):   # each its arm angle of the longest throw (analytic.ideal), found first
        rows = rows.copy()
        for i in ideal_rows:
            rows[i, _ALPHA] = _ideal_arm_angle(rows[i], rtol, atol)
    shots = _ready(needed_rows(rows, loads))
    n = len(rows)
    out = np.empty(n, kernel.RESULT_DTYPE)
    threads = min(threads, -(-n // BATCH_CHUNK))
    if threads <= 1:
        shots(rows, 0, n, DRAG_TABLE, COEFFICIENTS, rtol, atol, loads, out, _NO_RECORDING, _NO_SAMPLES)
        return out
    # Shots differ in cost (by 10x over the paper's bounds): each thread takes
    # the next few rows when it is done, rather than one block per thread.
    # The kernel releases the GIL, and next() on a count is atomic under it.
    starts = itertools.count(0, BATCH_CHUNK)

    def work() -> None:
        for start in starts:
            if start >= n:
                return
            shots(rows, start, min(start + BATCH_CHUNK, n), DRAG_TABLE, COEFFICIENTS, rtol, atol, loads, out,
                  _NO_RECORDING, _NO_SAMPLES)

    with ThreadPoolExecutor(threads) as pool:
        for done in [pool.submit(work) for _ in range(threads)]:
            done.result()
    return out


#: Columns of a design row: the release rule and its angle (``Params.rule``, ``Params.alpha``).
_RULE, _ALPHA = Params._fields.index("rule"), Params._fields.index("alpha")
#: Samples of the ideal rule's search pass (``_ideal_window``): it records only each stage's
#: first and last (its spacing is the whole time limit), within ``motion._EDGE_ROWS``.
_WINDOW_SAMPLES = 16


def _ideal_arm_angle(row: np.ndarray, rtol: float, atol: float) -> float:
    """The ideal rule's arm angle at release for the design row ``row``, rad (``analytic.ideal``):
    the window from the search pass, then compiled shots released at candidate arm angles."""
    row = row.copy()
    row[_ALPHA] = ideal.SEARCH_ANGLE
    window = _ideal_window(row, rtol, atol)
    if window is None:   # it never swings free: the shot fails before any release, as the search pass did
        return ideal.SEARCH_ANGLE
    shots = _ready(needed_rows(row[np.newaxis], False))

    def ranges(angles):
        rows = np.repeat(row[np.newaxis], len(angles), axis=0)
        rows[:, _ALPHA] = angles
        out = np.empty(len(rows), kernel.RESULT_DTYPE)
        shots(rows, 0, len(rows), DRAG_TABLE, COEFFICIENTS, rtol, atol, False, out, _NO_RECORDING, _NO_SAMPLES)
        return np.where(out["status"] == kernel.OK, out["landing_x"], np.nan)

    return ideal.best_arm_angle(ranges, *window)


def _ideal_window(row: np.ndarray, rtol: float, atol: float) -> tuple[float, float] | None:
    """The ideal rule's search pass of ``row`` (its alpha the search's): the arm angle at lift-off and
    at the end of the free swing, rad, from the compiled shot's recording of its stages' edges; None
    if the machine never swings free."""
    rec = np.zeros(1, kernel.RECORDING_DTYPE)
    rec["spacing"], rec["flight_spacing"], rec["sample_limit"] = math.inf, math.inf, 1
    samples = np.empty(_WINDOW_SAMPLES, kernel.SAMPLE_DTYPE)
    out = np.empty(1, kernel.RESULT_DTYPE)
    _ready(needed_rows(row[np.newaxis], False, recording=True))(
        row[np.newaxis], 0, 1, DRAG_TABLE, COEFFICIENTS, rtol, atol, False, out, rec, samples)
    swing = samples[:int(rec["rows"][0])]
    swing = swing[swing["stage"] == kernel.SWING]
    if rec["ran_out"][0] or len(swing) == 0 or math.isnan(out["liftoff_time"][0]):
        return None
    return float(swing["state"][0, 0]), float(swing["state"][-1, 0])


def scope_for(designs: Sequence[Design], loads: bool = True) -> Scope:
    """The scope ``simulate_fast_many(designs)`` (``loads``: ``shoot(designs, loads=...)``) runs in."""
    return needed_rows(pack_many(designs), loads)


def simulate_fast_many(designs: Sequence[Design], *, rtol: float = DEFAULT_RTOL,
                       atol: float = DEFAULT_ATOL, threads: int | None = None) -> list[Shot]:
    """``simulate_fast`` for every design in one batch on all cores; one ``Shot`` per design."""
    out = _shoot_rows(pack_many(designs), rtol, atol, threads)
    return [to_shot(design, row) for design, row in zip(designs, out, strict=True)]


def shoot(designs: Sequence[Design] | np.ndarray, *, rtol: float = DEFAULT_RTOL,
          atol: float = DEFAULT_ATOL, threads: int | None = None, loads: bool = False) -> Shots:
    """Simulate many designs on several threads at once (all this process's processors by default).

    The compiled shot releases the GIL, so plain Python threads run shots in
    parallel; no thread pool of numba's is involved, so a process may shoot
    from any thread, and fork or spawn workers that shoot too.

    Parameters
    ----------
    designs : a sequence of S ``Design``, or their rows, shape (S, N_PARAMS), from ``pack_many``.
    rtol, atol : the integrator's tolerances.
    threads : threads to run on (default ``default_threads()``).
    loads : find the peak loads (they cost about a fifth of a shot more; without them the
        ``peak_*`` arrays are NaN). Off by default: a batch serves a search or a sweep,
        where a load is wanted only as an output, objective or constraint.

    Returns
    -------
    Shots
        Arrays of length S; a failed design has its status and NaN where it did not reach.
        Shots of ``Design`` objects index as ``shots[i]``: design i's ``Shot``, the same
        ``to_shot`` builds for ``simulate_fast``.
    """
    packed = isinstance(designs, np.ndarray)
    rows = designs if packed else pack_many(designs)
    out = _shoot_rows(rows, rtol, atol, threads, loads)
    landed = out["status"] == kernel.OK
    known = None if packed else tuple(designs)
    return Shots(status=Shots.statuses(out["status"]),
                 liftoff_time=out["liftoff_time"],
                 release_time=out["release_time"],
                 landing_time=np.where(landed, out["landing_time"], np.nan),
                 release_position=out["release_position"].copy(),
                 release_velocity=out["release_velocity"].copy(),
                 range=np.where(landed, out["landing_x"], np.nan),
                 apex_height=np.where(landed | (out["status"] == kernel.SHORT_OF_TARGET), out["apex_height"], np.nan),
                 end_time=out["end_time"],
                 steps=out["steps"],
                 evaluations=out["evaluations"],
                 **_peaks(out), designs=known,
                 shot_at=None if packed else lambda i: to_shot(known[i], out[i]))


def _peaks(out: np.ndarray) -> dict[str, np.ndarray]:
    """The peak loads and their times of result records (S,), each (S,), NaN where none."""
    peaks = {}
    for k, name in enumerate(PEAK_NAMES):
        values = out["peaks"][:, k, 0]
        known = np.isfinite(values)
        peaks[name] = np.where(known, values, np.nan)
        peaks[f"{name}_time"] = np.where(known, out["peaks"][:, k, 1], np.nan)
    return peaks
