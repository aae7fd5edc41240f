"""The engine's public API: ``from engine_model import simulate`` gives a ``Shot`` carrying its diagnostics."""

from __future__ import annotations

import engine_model
from analytic.design_file import default_design
from analytic.result import Shot, Status
from engine_model import EngineDiagnostics, EngineError, simulate


def test_the_package_exposes_the_four_names():
    assert sorted(engine_model.__all__) == ["DEFAULT_DT", "EngineDiagnostics", "EngineError", "simulate"]
    assert issubclass(EngineError, RuntimeError)


def test_simulate_returns_a_shot_with_the_engine_diagnostics():
    # A coarse step keeps this quick; the contract does not depend on it.
    shot = simulate(default_design(), dt=4e-4)
    assert isinstance(shot, Shot) and shot.status is Status.OK
    assert isinstance(shot.diagnostics, EngineDiagnostics)
    assert (shot.diagnostics.dt, shot.diagnostics.sling) == (4e-4, "rigid")
    assert shot.diagnostics.machine_steps == len(shot.history.t) and shot.diagnostics.flight_steps > 0
