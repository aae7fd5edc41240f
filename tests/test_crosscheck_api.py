"""crosscheck's public names (``from crosscheck import run, compare, Case, Report``) on one design, as a user calls them."""

from __future__ import annotations

import dataclasses

import numpy as np

import crosscheck
from analytic import default_design
from crosscheck import Case, Report, compare, run


def test_the_public_names_are_the_documented_ones():
    assert {"run", "compare", "Case", "Report", "Comparison", "quick_suite", "default_suite"} <= set(crosscheck.__all__)
    assert all(name in crosscheck.__doc__ for name in ("run(", "compare(", "Case(", "Report"))


def test_run_cross_checks_one_design():
    design = default_design()
    report = run([Case(design.name, design, "paper")], workers=1)
    assert isinstance(report, Report) and [c.case for c in report.comparisons] == [design.name]
    comparison = report.comparisons[0]
    assert comparison.analytic_status == comparison.engine_status == "ok"
    quantities = {row.quantity for row in comparison.rows}
    assert {"outcome", "range", "release_time"} <= quantities
    assert report.agree and report.disagreements == ()
    assert comparison.verdict == "agree" and comparison.to_json()["verdict"] == "agree"
    assert report.to_json() == {"agree": True, "comparisons": [comparison.to_json()],
                                "verdicts": {"agree": 1, "disagree": 0, "sensitive": 0, "engine_failed": 0,
                                             "engine_untrusted": 0}}


def test_a_disagreement_is_reported_not_raised():
    # The same design against an engine whose every shot lands 5 % further than it does: the
    # range row fails (the cross-check's range tolerance is well under 5 %), the verdict says so.
    import engine_model

    def engine_too_far(design, dt):
        shot = engine_model.simulate(design, dt=dt)
        x, y = shot.landing_position
        return dataclasses.replace(shot, landing_position=np.array([1.05 * x, y]))

    design = default_design()
    comparison = compare(Case(design.name, design, "paper"), engine=engine_too_far)
    assert not comparison.agree
    assert "range" in [row.quantity for row in comparison.rows if not row.ok]
    report = Report((comparison,), dt=2e-4)
    assert not report.agree and report.disagreements == (comparison,)
