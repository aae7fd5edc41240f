"""The trebuchet in the pymunk rigid-body engine: ``simulate(design)`` gives a ``Shot`` with ``EngineDiagnostics``."""

from engine_model.budget import DEFAULT_DT
from engine_model.build import EngineError
from engine_model.diagnostics import EngineDiagnostics
from engine_model.shot import simulate

__all__ = ["DEFAULT_DT", "EngineDiagnostics", "EngineError", "simulate"]
