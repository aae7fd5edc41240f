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


def test_gravity_too_weak_for_a_time_scale_is_an_engine_error_not_a_warning():
    """Found by the fuzz test: 5e-324 m/s^2 made the step budget infinite and the history's
    times NaN (a numpy warning); the analytic model reports the design as never firing."""
    import dataclasses

    import pytest

    design = default_design()
    design = dataclasses.replace(design, environment=dataclasses.replace(design.environment, gravity=5e-324))
    with pytest.raises(EngineError, match="gravity = .* no finite time bound"):
        simulate(design)
