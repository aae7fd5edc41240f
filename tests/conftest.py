"""Fixtures: the default design and its vacuum twin (shared material lives in ``support``); every
module of the project imported before any test; and, under pytest-xdist (``make test``), which
test each worker takes next."""

from __future__ import annotations

import importlib
import os
import pkgutil

import pytest
from hypothesis import Phase, settings

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

#: Hypothesis profiles, by name: ``HYPOTHESIS_PROFILE=thorough`` selects the second (``quick``
#: otherwise: the suite's, ``make test`` and CI). A test that sets no count of examples takes the
#: profile's (the two paths' property test in ``test_analytic_fast.py``: about a minute on one
#: core under ``quick``); a test that needs its own count (a shot of an extreme design costs
#: seconds, a design file's read microseconds) gives the suite's through ``support.examples``,
#: which scales it as the profile's count is to quick's. ``quick``: derandomized (every run
#: draws the same designs); ``thorough``: 15 times as many, drawn afresh each run, not shrunk (a
#: shrink step is a shot on both paths; the failing example and the blob that reproduces it are
#: printed as found).
PROFILES = {"quick": dict(max_examples=200, derandomize=True),
            "thorough": dict(max_examples=3000, derandomize=False, print_blob=True,
                             phases=(Phase.explicit, Phase.reuse, Phase.generate))}
for _name, _values in PROFILES.items():
    settings.register_profile(_name, **_values)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "quick"))

#: The longest tests, by their seconds on the 2-core machine the suite is timed on (``--durations``;
#: the calibration's from whole-suite runs, the bench's alone, the numba mechanisms' alone with the
#: other mechanism's cold compile): they start first, the longest first, so that the last of them
#: ends while short tests remain to even out the workers. Only the order depends on these figures;
#: a test missing here runs after them, in file order with the other slow tests. (A module marked
#: ``xdist_group`` is one unit of work under ``--dist loadgroup``; xdist hands out the units of
#: several tests before the single tests, largest first.)
LONGEST = {"tests/test_analytic_calibrate_predict.py::test_held_out_predictions_fall_within_their_bands_at_the_"
           "stated_rate": 70,
           "tests/test_benchmarks.py::test_bench_times_a_baseline_beside_this_checkout_and_writes_the_page_"
           "from_its_figures": 28,
           "tests/test_analytic_numba_mechanisms.py::test_both_mechanisms_give_the_same_bits": 45}


def pytest_collection_modifyitems(config, items):
    """On pytest-xdist's workers, the ``slow`` tests first (the ``LONGEST`` first, longest first,
    then the others in file order), then the rest: each worker takes the next test as it finishes
    one, so the long tests start while hundreds of short ones remain to even out the workers'
    loads, and none is left to run alone at the end. Every worker sorts alike, as xdist requires.
    In one process the order stays pytest's own, so that a module's fixtures are set up once."""
    if hasattr(config, "workerinput"):
        items.sort(key=lambda item: (item.get_closest_marker("slow") is None, -LONGEST.get(item.nodeid, 0)))


@pytest.fixture(scope="session")
def lagrangian():
    """The machine's sympy Lagrangian (``tests/sympy_model.py``), derived once per process."""
    from sympy_model import machine

    return machine()


@pytest.fixture(scope="session")
def table3() -> Design:
    """The paper's Table III optimum with the documented arm assumption (golf-ball drag)."""
    return default_design()


@pytest.fixture(scope="session")
def table3_vacuum(table3) -> Design:
    """Table III without drag: the dynamics alone, for conservation checks."""
    return with_projectile(table3, drag="none")
