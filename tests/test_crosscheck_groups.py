"""The default suite's groups that no file of their own compares, case by case: the seeded sample,
the rolling frames and the floating arms; and that every group of the suite is compared somewhere.

``python -m crosscheck`` runs the whole suite; the tests compare it group by group, each case
once, so that a disagreement names its case and the suite's cases are spread over the workers."""

from __future__ import annotations

import pytest

from crosscheck.cases import default_suite
from crosscheck.comparison import compare

#: Where each group of the default suite is compared case by case.
COMPARED_IN = {"paper": "test_crosscheck.py", "exercise": "test_crosscheck.py", "failure": "test_crosscheck.py",
               "friction": "test_crosscheck.py", "stage-1-events": "test_crosscheck.py",
               "fixed": "test_crosscheck_fixed.py", "floating-friction": "test_crosscheck_floating_friction.py",
               "swing-drag": "test_crosscheck_swing_drag.py", "trough": "test_crosscheck_trough.py",
               "ideal-release": "test_crosscheck_ideal_release.py", "target": "test_crosscheck_target.py",
               "sling-mass": "test_crosscheck_sling_mass.py",
               "floating-base-friction": "test_crosscheck_floating_base_friction.py",
               "sample": "test_crosscheck_groups.py", "rolling": "test_crosscheck_groups.py",
               "floating-arm": "test_crosscheck_groups.py"}
#: The groups' slower designs, run as slow (measured one by one on the shared 2-core machine,
#: busy, 2026-11-29: 3 to 9 s, where the others take 1.8 s or less). Every rolling frame is: its engine
#: steps the machine on through the whole flight (1.2 to 5.7 s).
SLOW = {"sample-0-016-wooden", "sample-0-023-light", "large-floating-arm"}


def _group(name: str) -> list:
    """The default suite's cases of group ``name``, as ``python -m crosscheck`` runs them, each a
    parameter (slow where ``SLOW`` or a rolling frame says)."""
    return [pytest.param(case, marks=pytest.mark.slow) if case.name in SLOW or name == "rolling" else case
            for case in default_suite() if case.group == name]


def _assert_agree(case) -> None:
    result = compare(case)
    failing = [(r.quantity, r.analytic, r.engine, r.tolerance) for r in result.rows if not r.ok]
    assert result.agree, f"{case.name}: {result.error or failing}"


def test_every_group_of_the_default_suite_is_compared_case_by_case():
    assert {case.group for case in default_suite()} == set(COMPARED_IN)


@pytest.mark.parametrize("case", _group("sample"), ids=lambda c: c.name)
def test_models_agree_on_the_sampled_designs(case):
    _assert_agree(case)


@pytest.mark.parametrize("case", _group("rolling"), ids=lambda c: c.name)
def test_models_agree_on_the_rolling_frames(case):
    _assert_agree(case)


@pytest.mark.parametrize("case", _group("floating-arm"), ids=lambda c: c.name)
def test_models_agree_on_the_floating_arms(case):
    _assert_agree(case)
