"""The fast path's scopes (``analytic.scope``): smaller compiled copies of the model that give the same bits.

A design runs in the smallest scope that holds what it needs; these tests check that
the choice follows the model's own tests of a design (``friction.lossy``, the frame, the
kind, the swing's drag), that every smaller scope gives the rows of the scope that handles
everything bit for bit on the designs it takes, and that the ideal scope really leaves out
what it is for: numba compiles none of the friction's, the floating arm's, the rolling
frame's, the loads' or the recording's functions into it.
"""

from __future__ import annotations

import dataclasses
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from analytic import fast
from analytic.fast import kernel
from analytic.aero import DRAG_TABLE
from analytic.design import Losses
from analytic.design_file import default_design
from analytic.friction import lossy
from analytic.parameters import Params, params
from analytic.reference import DEFAULT_ATOL, DEFAULT_RTOL
from analytic.scope import EVERYTHING, IDEAL, IDEAL_LOADS, SCOPES, needed, needed_rows, needs
from benchmarks.designs import ROLLING_FRAME, TYPICAL_LOSSES, bench_designs
from support import assert_records_equal, fixed_designs, floating_designs, with_projectile


#: One design for each thing the ideal scopes leave out, each with its own reason.
BEYOND_THE_IDEAL = {
    "axle friction": Losses(axle_friction=0.1, axle_radius=0.01),
    "hinge friction": Losses(hinge_friction=0.1, hinge_radius=0.01),
    "base friction": Losses(base_friction=0.3),
}
#: The floating arm's own frictions (a hinged machine has neither a guide nor a track).
FLOATING_ONLY = {
    "guide friction": Losses(guide_friction=0.2),
    "track friction": Losses(track_friction=0.2),
}


def beyond_the_ideal() -> dict[str, object]:
    table3 = default_design()
    designs = {name: dataclasses.replace(table3, losses=losses) for name, losses in BEYOND_THE_IDEAL.items()}
    designs["rolling frame"] = dataclasses.replace(table3, base=ROLLING_FRAME)
    floating = floating_designs()["floating"]
    designs["floating arm"] = floating
    designs.update({name: dataclasses.replace(floating, losses=losses) for name, losses in FLOATING_ONLY.items()})
    designs["drag during the swing"] = with_projectile(table3, drag_during_swing=True)
    return designs


def _rows(scope, rows, loads):
    out = np.empty(len(rows), kernel.RESULT_DTYPE)
    fast.compile(scope)
    fast.entry_point(scope)(rows, 0, len(rows), DRAG_TABLE, fast.COEFFICIENTS, DEFAULT_RTOL, DEFAULT_ATOL, loads,
                            out, fast._NO_RECORDING, fast._NO_SAMPLES)
    return out


def test_the_ideal_designs_run_in_the_ideal_scopes():
    table3 = params(default_design())
    assert needed(table3, loads=False) is IDEAL and needed(table3, loads=True) is IDEAL_LOADS
    assert needed(table3, loads=False, recording=True) is EVERYTHING   # only it records the motion
    # A fixed (bolted) machine is ideal too; the scopes handle both arms without a slider.
    assert needed(params(fixed_designs()["fixed"]), loads=False) is IDEAL
    assert needed_rows(fast.pack_many(bench_designs(20, 0)), loads=False) is IDEAL


@pytest.mark.parametrize("name", list(beyond_the_ideal()))
def test_a_design_beyond_the_ideal_runs_in_the_scope_that_handles_everything(name):
    design = beyond_the_ideal()[name]
    assert needed(params(design), loads=False) is EVERYTHING
    # One such design in a batch of ideal ones takes the whole batch there.
    rows = fast.pack_many([*bench_designs(5, 0), design])
    assert needed_rows(rows, loads=False) is EVERYTHING and needed_rows(rows[:-1], loads=False) is IDEAL


def test_a_scope_s_test_of_friction_is_the_model_s():
    designs = [*beyond_the_ideal().values(), *fixed_designs().values(), *floating_designs().values(),
               *(dataclasses.replace(d, losses=TYPICAL_LOSSES) for d in bench_designs(10, 1))]
    for design in designs:
        p = params(design)
        assert bool(needs(p)[0]) == lossy(p), design.name
    rows = fast.pack_many(designs)
    assert needs(Params(*rows.T))[0].tolist() == [lossy(params(d)) for d in designs]


@pytest.mark.parametrize("scope", [IDEAL, IDEAL_LOADS], ids=lambda s: s.name)
def test_a_smaller_scope_gives_the_same_bits_as_the_scope_that_handles_everything(scope):
    # The bench's designs (the paper's optimum and 120 drawn over Table II) and the fixed
    # machines without friction or a rolling frame: every result entry, the peak loads with them.
    designs = [*bench_designs(120, 0), *(d for d in fixed_designs().values()
                                          if not lossy(params(d)) and d.base.mobility == "fixed")]
    rows = fast.pack_many(designs)
    assert needed_rows(rows, scope.loads) is scope
    smaller, everything = _rows(scope, rows, scope.loads), _rows(EVERYTHING, rows, scope.loads)
    assert_records_equal(smaller, everything)
    thrown = smaller["status"] == kernel.OK
    assert thrown.sum() > 60   # the comparison covers real shots, not only failures
    assert np.isfinite(smaller["peaks"]).any() == scope.loads


def test_each_entry_point_is_cached_under_its_own_name():
    from analytic.fast import compiled

    names = {fast.entry_point(scope).py_func.__qualname__ for scope in SCOPES}
    label = compiled.PUBLIC_LABEL if compiled.mechanism() == "public" else ""
    assert names == {f"shots_{scope.name}{label}" for scope in SCOPES}


@pytest.mark.slow
def test_the_ideal_scope_compiles_nothing_of_what_it_leaves_out(tmp_path):
    # A cold compile of the ideal scope (about 12 s), in a fresh process with an empty cache:
    # numba compiles a function only where a call to it survives the pruning.
    code = """if True:
        import json
        from analytic import fast, scope
        from analytic.fast import compiled
        fast.compile(scope.IDEAL)
        twins = compiled.kernel_scope(scope.IDEAL)
        print(json.dumps({module: sorted(name for name, f in vars(namespace).items() if compiled.is_compiled(f))
                          for module, namespace in twins.items()}))
    """
    done = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True,
                          env=dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path)))
    compiled = json.loads(done.stdout.splitlines()[-1])
    # What it runs is compiled (the check can see a compiled function) ...
    assert {"terms", "slide_accelerations", "swing_accelerations"} <= set(compiled["eom"])
    assert {"derivative", "event_value", "fires"} <= set(compiled["stages"])
    assert {"state_size"} <= set(compiled["states"])
    assert {"integrate", "shots"} <= set(compiled["kernel"])
    # ... and what it leaves out is not.
    assert compiled["friction"] == [] and compiled["floating_arm"] == [] and compiled["kernel_loads"] == []
    # Brent's search of analytic.peaks runs in every scope, for the events' turns (analytic.sequence);
    # what only the loads call (search_golden, inside_end) is left out.
    assert set(compiled["peaks"]) == {"search_around", "search_from", "search_next", "search_update"}
    assert not {"rolling_terms", "swing_drag", "floating_supports_in_air"} & set(compiled["eom"])
    assert not {"decide_modes", "switch_mode", "friction_solution", "friction_event"} & set(compiled["states"])
    assert not {"loads_at", "floating_supports"} & set(compiled["stages"])
    assert not {"record_row", "record_step", "record_last"} & set(compiled["kernel"])
