"""The compiled path's recorded motion (``analytic.fast.motion``) against the reference path's histories.

Both paths take the same DOP853 steps (``tests/test_analytic_fast.py``) and read
their samples off the same interpolants, so the samples agree to round-off in
stages 1-2. The flight's agree as closely as the two paths' ranges do
(``RANGE_REL``), since its positions grow to tens of metres.
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
import pytest

from analytic import fast
from analytic.fast import kernel
from analytic.design import Base
from analytic.fast.motion import simulate_motion
from analytic.reference import simulate
from analytic.result import Status
from benchmarks.designs import ROLLING_FRAME, TYPICAL_LOSSES
from support import assert_records_equal, failure_designs, sling_designs, table3_variants, table_ii_sample

#: Each design's pair of paths is shot once for the two tests that read it (``_both_paths``): under
#: pytest-xdist (``make test``: ``--dist loadgroup``) the module runs whole on one worker.
pytestmark = pytest.mark.xdist_group("analytic-motion")

#: The fast and reference paths' agreement on the range (``tests/test_analytic_fast.py``).
RANGE_REL = 1e-7
#: Stages 1-2 samples, rad and rad/s: round-off of the same arithmetic in two orders (observed 1e-14
#: and 3e-13 on the paper's design; a thousand times that leaves room for other CPUs' last bits).
ANGLE_ABS, RATE_ABS = 1e-11, 1e-9
#: ... and relative to a rate, where the motion itself amplifies round-off: fails-never_lifts_off's sling
#: rate, as the sling passes under the tip, parted from 8e-11 to 1.5e-9 rad/s of its 10.5 rad/s in the
#: shot's last 2 ms on an AMD EPYC (2026-11-29): 1.5e-10 of the rate. (The paths' range agreement,
#: RANGE_REL, is a thousand times looser still.)
RATE_REL = 1e-9
#: The page's spacings (``workbench.shot``), and the reference's own (None).
SPACINGS = [(2e-3, 2e-2), (None, None)]


def _designs():
    t3 = table3_variants()
    designs = [t3["table3"], t3["sling-rule-ahead"], t3["golf-ball-headwind"]]
    designs += [dataclasses.replace(t3["table3"], name="lossy", losses=TYPICAL_LOSSES),
                dataclasses.replace(t3["table3"], name="rolling", base=ROLLING_FRAME),
                dataclasses.replace(t3["table3"], name="lossy-rolling", losses=TYPICAL_LOSSES, base=ROLLING_FRAME)]
    designs += table_ii_sample(4, 3)
    designs += list(failure_designs().values())
    # a sling and a pouch with mass: the machine's energy holds theirs, potential as well as kinetic
    slings = sling_designs()
    designs += [dataclasses.replace(slings[name], name=name)
                for name in ("sling-hinged", "sling-rolling", "sling-floating")]
    return designs


@functools.cache
def _both_paths(design, spacing, flight_spacing):
    """The compiled path's shot and motion, and the reference path's shot with its histories, of
    ``design`` at these spacings: once a process, since the history test at the reference's own
    spacings and the energy test read the same pair (seconds for the balloon that never lands).
    ``tests/conftest.py`` keeps this module on one pytest-xdist worker, so it is once a run."""
    return (simulate_motion(design, sample_step=spacing, flight_sample_step=flight_spacing),
            simulate(design, sample_step=spacing, flight_sample_step=flight_spacing, sampled_loads=False))


@pytest.mark.parametrize("spacing, flight_spacing", SPACINGS)
@pytest.mark.parametrize("design", _designs(), ids=lambda d: d.name)
def test_the_recorded_motion_is_the_reference_history(design, spacing, flight_spacing):
    (shot, motion), reference = _both_paths(design, spacing, flight_spacing)
    history = reference.history
    assert shot.status is reference.status
    np.testing.assert_array_equal(motion.stage, history.stage)
    np.testing.assert_allclose(motion.t, history.t, rtol=0.0, atol=1e-12)
    np.testing.assert_allclose(motion.q, history.q, rtol=0.0, atol=ANGLE_ABS)
    np.testing.assert_allclose(motion.qdot, history.qdot, rtol=RATE_REL, atol=RATE_ABS)
    frame_x = history.frame_x if len(history.frame_x) else np.zeros(len(history.t))
    np.testing.assert_allclose(motion.frame_x, frame_x, rtol=0.0, atol=1e-12)
    assert len(motion.flight_t) == len(history.flight_t)
    if len(history.flight_t):
        scale = np.abs(history.flight_path).max()
        np.testing.assert_allclose(motion.flight_path, history.flight_path, rtol=0.0, atol=RANGE_REL * scale)
        np.testing.assert_allclose(motion.flight_t[1:], history.flight_t[1:], rtol=RANGE_REL)


@pytest.mark.parametrize("design", _designs(), ids=lambda d: d.name)
def test_the_energies_are_the_reference_paths(design):
    (shot, motion), reference = _both_paths(design, None, None)
    for name in ("counterweight_energy_released", "projectile_energy_at_release", "energy_efficiency"):
        assert (getattr(shot, name) is None) == (getattr(reference, name) is None), name
        if getattr(reference, name) is not None:
            assert getattr(shot, name) == pytest.approx(getattr(reference, name), rel=1e-10), name
    if reference.release_time is not None:
        assert motion.machine_energy_at_release == pytest.approx(reference.history.energy.machine[-1], rel=1e-9,
                                                                 abs=1e-9 * reference.counterweight_energy_released)
    # Friction's work is integrated with the motion on both paths; the drag's is the reference's
    # Gauss rule on each flight step against the recording's energy balance over the flight, from
    # the compiled path's landing velocity: the two paths' states agree to RANGE_REL, so a kinetic
    # energy (v squared) to twice that, of the energy the projectile carries. (Observed 1.4e-9 J of
    # 14 J on this machine, 1.6e-7 J with NUMBA_CPU_NAME=generic.)
    scale = reference.projectile_energy_at_release or 1.0
    for loss, work in reference.energy_dissipated.items():
        assert shot.energy_dissipated[loss] == pytest.approx(work, abs=2 * RANGE_REL * scale), loss


def test_recording_changes_nothing_the_summary_holds():
    """The result records with and without the recording are the same to the bit, but for the
    evaluations the recording's interpolants add."""
    for design in _designs():
        plain = fast.shoot_one(design, 1e-10, 1e-10, True)
        recorded = fast.shoot_one(design, 1e-10, 1e-10, True, _recording(2e-3, 2e-2, 100_000),
                                  np.empty(200_000, kernel.SAMPLE_DTYPE))
        assert_records_equal(recorded, plain, skip=("evaluations",), err_msg=design.name)
        assert recorded["evaluations"] >= plain["evaluations"]


def _recording(spacing: float, flight_spacing: float, sample_limit: int) -> np.ndarray:
    """A recording's state before the shot (``analytic.fast.kernel.RECORDING_DTYPE``)."""
    rec = np.zeros(1, kernel.RECORDING_DTYPE)
    rec["spacing"], rec["flight_spacing"], rec["sample_limit"] = spacing, flight_spacing, sample_limit
    return rec


def test_a_machine_that_never_moves_is_drawn_at_rest():
    design = failure_designs()[Status.NEVER_FIRES]
    shot, motion = simulate_motion(design)
    assert shot.status is Status.NEVER_FIRES
    assert motion.t.tolist() == [0.0] and len(motion.flight_t) == 0
    assert motion.q[0].tolist() == pytest.approx(simulate(design).history.q[0].tolist(), abs=1e-15)


def test_a_buffer_too_small_is_reported_not_overrun():
    design = table3_variants()["table3"]
    rec = _recording(1e-3, 1e-2, 100_000)
    samples = np.zeros(10, kernel.SAMPLE_DTYPE)
    samples["t"] = -7.0
    fast.shoot_one(design, 1e-10, 1e-10, False, rec, samples)
    assert rec["ran_out"][0] and rec["rows"][0] == len(samples)
    assert samples["t"].tolist() == pytest.approx([1e-3 * i for i in range(10)], abs=1e-12)


@pytest.mark.parametrize("value", [0.0, -1e-3, float("nan"), "2 ms"])
def test_a_spacing_must_be_a_positive_number(value):
    with pytest.raises(ValueError, match="sample_step = .*: must be a positive number of seconds"):
        simulate_motion(table3_variants()["table3"], sample_step=value)


def test_a_rolling_frame_moves_in_the_motion():
    design = dataclasses.replace(table3_variants()["table3"], base=Base("rolling", 20.0))
    _, motion = simulate_motion(design)
    assert np.abs(motion.frame_x).max() > 1e-3
