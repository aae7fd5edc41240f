"""Shared fixtures: the default design and variants of it."""

from __future__ import annotations

import dataclasses

import pytest

from analytic.design import Design
from analytic.design_file import default_design


def with_machine(design: Design, **changes) -> Design:
    """``design`` with machine fields replaced (validated again)."""
    return dataclasses.replace(design, machine=dataclasses.replace(design.machine, **changes))


def with_projectile(design: Design, **changes) -> Design:
    return dataclasses.replace(design, projectile=dataclasses.replace(design.projectile, **changes))


def with_environment(design: Design, **changes) -> Design:
    return dataclasses.replace(design, environment=dataclasses.replace(design.environment, **changes))


@pytest.fixture(scope="session")
def table3() -> Design:
    """The paper's Table III optimum with the documented arm assumption (golf-ball drag)."""
    return default_design()


@pytest.fixture(scope="session")
def table3_vacuum(table3) -> Design:
    """Table III without drag: the dynamics alone, for conservation checks."""
    return with_projectile(table3, drag="none")
