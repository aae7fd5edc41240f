"""Fixtures: the default design and its vacuum twin (shared material lives in ``support``)."""

from __future__ import annotations

import pytest

from analytic.design import Design
from analytic.design_file import default_design
from support import with_projectile


@pytest.fixture(scope="session")
def table3() -> Design:
    """The paper's Table III optimum with the documented arm assumption (golf-ball drag)."""
    return default_design()


@pytest.fixture(scope="session")
def table3_vacuum(table3) -> Design:
    """Table III without drag: the dynamics alone, for conservation checks."""
    return with_projectile(table3, drag="none")
