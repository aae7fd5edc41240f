"""Fixtures: the default design and its vacuum twin (shared material lives in ``support``); every
module of the project imported before any test."""

from __future__ import annotations

import importlib
import pkgutil

import pytest

import analytic
import crosscheck
import engine_model
from analytic.design import Design
from analytic.design_file import default_design
from support import with_projectile


def _import_every_project_module() -> None:
    """Hypothesis draws some values from the constants written in the modules loaded so far (its
    "local constants"), so a derandomized test drew different examples depending on which of the
    project's modules the tests before it happened to import: alone, in the whole suite, or on
    whichever pytest-xdist worker it landed after whatever tests. With every module loaded first,
    each test draws the same examples in any order, on any worker. (The ``__main__`` modules only
    call ``cli.main``.)"""
    for package in (analytic, engine_model, crosscheck):
        for module in pkgutil.walk_packages(package.__path__, package.__name__ + "."):
            if not module.name.endswith(".__main__"):
                importlib.import_module(module.name)


_import_every_project_module()


@pytest.fixture(scope="session")
def table3() -> Design:
    """The paper's Table III optimum with the documented arm assumption (golf-ball drag)."""
    return default_design()


@pytest.fixture(scope="session")
def table3_vacuum(table3) -> Design:
    """Table III without drag: the dynamics alone, for conservation checks."""
    return with_projectile(table3, drag="none")
