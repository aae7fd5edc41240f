"""Drag on a sphere: the drag models and their drag coefficient against Reynolds number."""

from __future__ import annotations

DRAG_MODELS = ("none", "constant", "smooth-sphere", "golf-ball")


def reynolds_number(speed: float, diameter: float, air_density: float, air_viscosity: float) -> float:
    """Re = rho |v| d / mu for the air-relative speed."""
    return air_density * speed * diameter / air_viscosity


def drag_coefficient(model: str, reynolds: float, constant: float | None = None) -> float:
    """Drag coefficient of the projectile under ``model`` at Reynolds number ``reynolds``."""
    if model == "none":
        return 0.0
    if model == "constant":
        assert constant is not None
        return constant
    raise NotImplementedError(f"drag model {model!r} not implemented yet")
