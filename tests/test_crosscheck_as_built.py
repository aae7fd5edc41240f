"""The cross-check's machines as built, drawn at random (``python -m crosscheck --as-built N``): seeded,
leaving the sample's draws alone, spanning every new part on every kind."""

from __future__ import annotations

from unittest import mock

import pytest

import crosscheck.cli
from crosscheck.cases import (AS_BUILT_MASS_FRACTION, AS_BUILT_TROUGH_FRACTION, Case, as_built_cases,
                              sample_cases)
from engine_model.build import SLING_MASS_FRACTION

#: Designs drawn for the span test: enough that each part is left off and each kind, rule and loss
#: turns up (each has a chance of a quarter or more a design).
SPAN = 40


@pytest.fixture(scope="module")
def drawn() -> list[Case]:
    return as_built_cases(SPAN, seed=0)


def test_the_draw_is_seeded_and_leaves_the_samples_geometry_alone(drawn):
    assert [c.design for c in as_built_cases(6, seed=0)] == [c.design for c in drawn[:6]]
    assert [c.design for c in as_built_cases(6, seed=1)] != [c.design for c in drawn[:6]]
    for case, sample in zip(drawn, sample_cases(SPAN, seed=0), strict=True):
        m, s = case.design.machine, sample.design.machine
        assert (m.pivot_height, m.arm_long, m.arm_short, m.arm_mass, m.sling_length) == (
            s.pivot_height, s.arm_long, s.arm_short, s.arm_mass, s.sling_length), case.name
        assert case.group == "as-built" and case.name.startswith(sample.name.replace("sample-", "as-built-"))


def test_the_draw_spans_every_part_on_every_kind(drawn):
    designs = [case.design for case in drawn]
    for d in designs:
        most = AS_BUILT_MASS_FRACTION * d.projectile.mass
        assert 0.0 <= d.machine.pouch_mass <= most
        carried = d.projectile.mass + d.machine.pouch_mass
        assert d.machine.sling_mass == 0.0 or SLING_MASS_FRACTION * carried <= d.machine.sling_mass <= most
        assert 0.0 <= d.base.trough_height <= AS_BUILT_TROUGH_FRACTION * d.machine.pivot_height
    for field in (lambda d: d.machine.sling_mass, lambda d: d.machine.pouch_mass, lambda d: d.base.trough_height):
        assert any(field(d) == 0.0 for d in designs) and any(field(d) > 0.0 for d in designs)
    targets = [d.environment.target_height for d in designs]
    assert min(targets) < 0.0 < max(targets) and 0.0 in targets
    assert any(case.expected == "short_of_target" for case in drawn)
    kinds = {kind: [d for d in designs if d.machine.kind == kind] for kind in ("hinged", "fixed", "floating-arm")}
    for kind, mine in kinds.items():
        assert mine and any(d.losses.ideal for d in mine) and any(not d.losses.ideal for d in mine), kind
    assert any(d.losses.base_friction > 0.0 for d in kinds["floating-arm"])
    assert {d.machine.release_rule for d in designs} == {"velocity", "ideal"}


def test_the_command_line_adds_the_draw_to_its_suite():
    class Drawn(Exception):
        pass

    def capture(cases, **options):
        raise Drawn(cases)

    with mock.patch.object(crosscheck.cli, "run", capture), pytest.raises(Drawn) as drawn:
        crosscheck.cli.main(["--quick", "--as-built", "3", "--seed", "7"])
    cases = drawn.value.args[0]
    assert [c.design for c in cases[-3:]] == [c.design for c in as_built_cases(3, seed=7)]
    assert [c.group for c in cases[:-3]] != [] and "as-built" not in {c.group for c in cases[:-3]}
    with pytest.raises(SystemExit) as refused:
        crosscheck.cli.main(["--as-built", "-1"])
    assert refused.value.code == 2
