"""The analytic trebuchet model: a hand-derived Lagrange simulator on two paths.

The public names, each loaded on first use (so ``import analytic`` stays
quick and numba is imported only when the fast path is first used)::

    from analytic import Design, load_design, default_design, simulate, shoot, Shot, Shots, Status

* ``simulate(design) -> Shot``: the reference path (scipy), with its ``History`` for plots;
* ``simulate_fast(design) -> Shot``: the same summary, compiled;
* ``shoot(designs) -> Shots``: many designs at once on every core, as arrays.
"""

from __future__ import annotations

import importlib

#: Public name -> the module that defines it.
_EXPORTS = {
    "Design": "analytic.design", "Machine": "analytic.design", "Projectile": "analytic.design",
    "Environment": "analytic.design", "Base": "analytic.design", "Losses": "analytic.design",
    "DesignError": "analytic.design",
    "load_design": "analytic.design_file", "save_design": "analytic.design_file",
    "default_design": "analytic.design_file",
    "simulate": "analytic.reference",
    "simulate_fast": "analytic.fast", "shoot": "analytic.fast",
    "Shot": "analytic.result", "Shots": "analytic.result", "History": "analytic.result", "Status": "analytic.outcome",
    "Stage": "analytic.outcome",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module 'analytic' has no attribute {name!r}")
    value = getattr(importlib.import_module(_EXPORTS[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))
