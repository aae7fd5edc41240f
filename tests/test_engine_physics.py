"""The engine's physics: conservation, joint drift, contact forces, failures, and the rope sling."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from analytic.design import Design
from analytic.design_file import default_design
from analytic import outcome
from analytic.limits import flight_time_limit
from analytic.result import Stage, Status
from analytic.reference import simulate as analytic_simulate
from support import PHRASES, failure_designs, with_machine, with_projectile
from engine_model import kinematics as kin
from engine_model.build import build
from engine_model import DEFAULT_DT, simulate
from engine_model.readout import row_reader
from engine_model.stepping import read_state

#: The brief's conservation requirement: stage 1-2 energy to 1e-4 of the energy
#: the counterweight releases (a sound leapfrog run at 1e-4 s keeps 3.5e-5).
ENERGY_TOLERANCE = 1e-4
#: How closely the measured joint separation must equal the one-step chord error
#: predicted from the analytic motion (the prediction neglects O(dt^3) terms).
CHORD_TOLERANCE = 1e-2


@pytest.fixture(scope="module")
def vacuum() -> Design:
    return with_projectile(default_design(), drag="none")


@pytest.fixture(scope="module")
def engine(vacuum):
    return simulate(vacuum)


@pytest.fixture(scope="module")
def analytic(vacuum):
    return analytic_simulate(vacuum)


def test_energy_is_conserved_through_stages_1_and_2(engine):
    shot = engine
    assert shot.ok and shot.history.energy.total.shape == shot.history.t.shape
    assert np.abs(shot.history.energy.total).max() < ENERGY_TOLERANCE * shot.counterweight_energy_released
    # The budget adds up and the projectile got its share by release.
    assert shot.history.energy.total == pytest.approx(shot.history.energy.machine + shot.history.energy.projectile)
    assert shot.history.energy.projectile[-1] > 0.5 * shot.counterweight_energy_released


def test_joint_drift_is_only_the_one_step_chord_error(engine, analytic):
    # pymunk moves each body's centre in a straight line and turns it about that
    # centre; a joint whose anchors then travel on arcs opens by the chord error,
    # and the next step (error_bias = 0) closes it again, so nothing accumulates.
    # Predicted from the analytic model's motion for a step dt:
    #   pivot: dt^2/2 theta'^2 |arm_cg|  (the pivot is off the arm's centre)
    #   hinge: dt^2/2 |theta'^2 r_arm - (theta'+phi')^2 r_link|  (arm centre and
    #          counterweight centre to the hinge)
    #   sling: dt^2 v_rel^2 / (2 L_s) + dt^2/2 theta'^2 (r_tip . e_sling)
    diagnostics = engine.diagnostics
    m, dt = analytic.design.machine, DEFAULT_DT
    theta, phi, psi = analytic.history.q.T
    arm_rate, link_rate, sling_rate = analytic.history.qdot[:, 0], analytic.history.qdot[:, 0] + analytic.history.qdot[:, 1], \
        analytic.history.qdot[:, 0] + analytic.history.qdot[:, 2]
    along = np.column_stack([-np.sin(theta), np.cos(theta)])
    centre, short, tip = m.arm_cg * along, -m.arm_short * along, m.arm_long * along
    link = m.counterweight_link * np.column_stack([np.sin(theta + phi), -np.cos(theta + phi)])
    sling = np.column_stack([-np.sin(theta + psi), np.cos(theta + psi)])
    predicted = {
        "pivot": 0.5 * dt**2 * arm_rate**2 * abs(m.arm_cg),
        "hinge": 0.5 * dt**2 * np.hypot(*(arm_rate[:, None]**2 * (short - centre)
                                          + link_rate[:, None]**2 * link).T),
        "sling": dt**2 * (m.sling_length * sling_rate)**2 / (2 * m.sling_length)
        + 0.5 * dt**2 * arm_rate**2 * np.sum((tip - centre) * sling, axis=1),
    }
    for joint, chord in predicted.items():
        assert diagnostics.joint_drift[joint] == pytest.approx(chord.max(), rel=CHORD_TOLERANCE), joint
    assert diagnostics.joint_drift["groove"] < 1e-12  # a straight groove has no chord error


def test_joint_drift_below_a_micrometre_at_the_default_step(engine):
    # Required of the engine. The drift is the chord error above, ~dt^2: 3.4e-6 m
    # at 1e-4 s, which is why the default step is 5e-5 s (8.5e-7 m).
    assert engine.diagnostics.dt == DEFAULT_DT  # the step simulate takes unless told
    assert engine.diagnostics.max_joint_drift < 1e-6


def test_the_base_carries_the_weight_at_rest(vacuum):
    # At rest the sling lies along the base, so it pulls horizontally: the base's
    # push equals the projectile's weight, and the pull is the sling's tension.
    rig = build(vacuum)
    rig.space.iterations = 1000
    rig.space.step(0.5 * DEFAULT_DT)
    row = read_state(rig)
    p = kin.PROJECTILE
    tip = rig.arm.local_to_world((0.0, vacuum.machine.arm_long))
    tension, normal = kin.contact_forces((-row[p + kin.VX], -row[p + kin.VY]), (row[p + kin.VX], row[p + kin.VY]),
                                         tip, (row[p + kin.X], row[p + kin.Y]), True, vacuum, DEFAULT_DT)
    # 1000 solver iterations from a cold start leave about 1e-8 of the forces unconverged.
    assert normal == pytest.approx(vacuum.projectile.mass * vacuum.environment.gravity, rel=1e-7)
    assert tension == pytest.approx(rig.sling.impulse / (0.5 * DEFAULT_DT), rel=1e-7)


def test_sling_tension_recovered_from_momentum_matches_pymunk_and_the_analytic_model(engine, analytic):
    shot = engine
    # pymunk reports only |impulse|; the sign comes from the projectile's momentum.
    rig = build(shot.design)
    rig.space.step(0.5 * DEFAULT_DT)
    for _ in range(1000):  # 0.1 s, still sliding (lift-off at 0.148 s)
        before = read_state(rig)
        rig.space.step(DEFAULT_DT)
    after = read_state(rig)
    p = kin.PROJECTILE
    tip = rig.arm.local_to_world((0.0, shot.design.machine.arm_long))
    tension, _ = kin.contact_forces((before[p + kin.VX], before[p + kin.VY]), (after[p + kin.VX], after[p + kin.VY]),
                                    tip, (after[p + kin.X], after[p + kin.Y]), True, shot.design, DEFAULT_DT)
    assert abs(tension) == pytest.approx(rig.sling.impulse / DEFAULT_DT, rel=1e-6)
    # Against the analytic tension history (signed): within 1e-4 of its largest value.
    engine_tension = np.interp(analytic.history.t, shot.history.t, shot.history.sling_tension)
    scale = np.abs(analytic.history.sling_tension).max()
    assert np.abs(engine_tension - analytic.history.sling_tension).max() < 1e-3 * scale
    assert shot.min_sling_tension < 0.0  # the rigid sling pushes before release (analytic: -3.99 N)


def test_coordinates_follow_the_analytic_model(engine, analytic):
    shot = engine
    q = np.column_stack([np.interp(analytic.history.t, shot.history.t, shot.history.q[:, i]) for i in range(3)])
    assert np.abs(q - analytic.history.q).max() < 1e-4  # rad
    assert shot.history.stage[0] == Stage.SLIDE and shot.history.stage[-1] == Stage.SWING
    assert shot.history.t[shot.history.stage == Stage.SWING][0] >= shot.liftoff_time


@pytest.mark.parametrize("expected", failure_designs(), ids=lambda s: s.value)
def test_failures_are_named_as_the_analytic_model_names_them(expected):
    design = failure_designs()[expected]
    assert analytic_simulate(design).status is expected  # the reference classification
    shot = simulate(design)
    assert shot.status is expected, shot.message
    assert PHRASES[expected] in shot.message
    assert shot.range is None and shot.to_json()["range"] is None
    # Only these were released: a flight that never lands, and one short of its target.
    assert (shot.release_time is not None) is (expected in (Status.NO_LANDING, Status.SHORT_OF_TARGET))
    assert len(shot.history.t) >= 1 and np.all(np.isfinite(shot.history.q))


def test_a_flight_that_never_lands_is_a_result_with_the_bound_in_its_message():
    design = failure_designs()[Status.NO_LANDING]
    shot = simulate(design)
    assert shot.status is Status.NO_LANDING
    height, vertical_velocity = shot.release_position[1] + design.machine.pivot_height, shot.release_velocity[1]
    limit = flight_time_limit(height, vertical_velocity, design.environment.gravity)
    assert shot.message == outcome.no_landing_message(limit)  # "... within 64.9 s of flight ..."
    assert shot.landing_time is None and shot.apex_height is None and shot.flight_time is None
    assert shot.history.flight_path.shape == (len(shot.history.flight_t), 2) and shot.history.flight_t[0] == shot.release_time
    # Ended as soon as a landing in time was impossible (183 steps), not after 1.3e6.
    assert shot.diagnostics.flight_steps < 1000


def test_never_fires_reports_the_arm_acceleration_at_rest_as_the_analytic_model_does():
    # The engine measures it from its opening half step from rest; the analytic
    # model solves its equations at rest (+1.842 rad/s^2 for this design). Both
    # messages come from analytic.outcome, to four significant digits.
    design = failure_designs()[Status.NEVER_FIRES]
    shot = simulate(design)
    assert shot.status is Status.NEVER_FIRES
    assert shot.message == analytic_simulate(design).message


def test_a_throw_behind_the_pivot_is_a_flagged_result():
    # The lead's case: the sling let go 170 deg ahead of the arm flings the projectile backwards.
    design = with_machine(default_design(), release_rule="sling", release_angle=math.radians(170.0))
    shot = simulate(design)
    assert shot.ok and shot.range < 0.0 and shot.landed_behind_pivot
    assert "behind the pivot" in shot.message


def test_the_rope_never_pushes_and_never_gains_energy(vacuum, engine):
    rigid = engine
    rope = simulate(vacuum, sling="rope")
    assert rope.ok and rope.diagnostics.sling == "rope"
    assert rope.min_sling_tension > -1e-9  # round-off only
    assert rope.history.energy.total.max() < 1e-6 * rope.counterweight_energy_released
    # The same motion as the rigid sling until the rigid sling first pushes; the
    # rope then goes slack. (Not to round-off: pymunk's rope acts only once it is
    # stretched, so in the first step from rest, exactly at its length, it does
    # not pull; the projectile lags by 1.4e-7 m for that step.)
    first_push = rigid.history.t[np.argmax(rigid.history.sling_tension < 0.0)]
    before = rigid.history.t < first_push - 1e-3
    rope_path = np.column_stack([np.interp(rigid.history.t[before], rope.history.t, rope.history.path[:, i]) for i in range(2)])
    assert np.abs(rope_path - rigid.history.path[before]).max() < 1e-6
    slack = (rope.history.t > first_push) & (rope.history.t < rope.release_time)
    assert np.any(np.abs(rope.history.sling_tension[slack]) < 1e-9)  # slack: no pull but round-off


def test_the_state_read_from_chipmunk_is_the_one_pymunks_properties_give(vacuum):
    """``engine_model.readout`` calls Chipmunk's getters directly (the binding, where it fits); every entry
    is the same double as pymunk's properties give."""
    from engine_model import readout
    from engine_model.after_release import _bodies
    from engine_model.readout import origin_reader

    rig = build(vacuum)
    rig.space.step(0.5 * DEFAULT_DT)
    for _ in range(2000):   # into the swing: every body moving and turning
        rig.space.step(DEFAULT_DT)
    bodies = (rig.arm, rig.counterweight, rig.projectile, rig.frame)
    by_properties = []
    for i, body in enumerate(bodies):
        velocity = body.velocity_at_local_point((0.0, 0.0)) if i == 0 else body.velocity
        by_properties += [*body.position, body.angle, *velocity, body.angular_velocity]
    assert read_state(rig) == tuple(by_properties)
    assert row_reader(*bodies)() == tuple(by_properties)   # the loop's reader, the static frame read once
    rolling = build(dataclasses.replace(vacuum, base=dataclasses.replace(vacuum.base, mobility="rolling", mass=10.0)))
    for _ in range(2000):
        rolling.space.step(DEFAULT_DT)
    reader = row_reader(rolling.arm, rolling.counterweight, rolling.projectile, rolling.frame)
    assert reader() == read_state(rolling) and read_state(rolling)[kin.FRAME + kin.VX] != 0.0
    moving = (kin.ARM + kin.W, kin.COUNTERWEIGHT + kin.VX, kin.PROJECTILE + kin.VX, kin.PROJECTILE + kin.VY)
    assert all(by_properties[i] != 0.0 for i in moving)   # not a state at rest
    origins = []
    for body in _bodies(rig).values():
        origins += [*body.position, body.angle, *body.velocity_at_local_point((0.0, 0.0)), body.angular_velocity]
    assert origin_reader(*_bodies(rig).values())() == tuple(origins)   # the run after release's reader
    # Friction's bookkeeping: a joint's impulse and limit, a body's velocity.
    assert readout.impulse(rig.pivot) == rig.pivot.impulse != 0.0
    readout.set_max_force(rig.pivot, 1234.5678)
    assert readout.max_force(rig.pivot) == rig.pivot.max_force == 1234.5678
    assert readout.velocity(rig.projectile) == tuple(rig.projectile.velocity)



def test_stepping_through_chipmunk_gives_pymunks_step_bit_for_bit(vacuum):
    """``readout.stepper`` calls ``cpSpaceStep`` itself once ``Space.step`` has nothing else to do."""
    import pymunk

    from engine_model.readout import fits_this_pymunk, stepper

    rigs = [build(vacuum), build(vacuum)]
    for rig in rigs:
        rig.space.step(0.5 * DEFAULT_DT)
    step = stepper(rigs[1].space)
    for _ in range(2000):
        rigs[0].space.step(DEFAULT_DT)
        step(DEFAULT_DT)
    assert read_state(rigs[1]) == read_state(rigs[0]) and read_state(rigs[0])[kin.ARM + kin.W] != 0.0
    assert fits_this_pymunk(rigs[1].space)   # on this pymunk the steps above were Chipmunk's own
    # A space with a post-step callback (or a body not yet stepped) is left to pymunk's step.
    space, called = pymunk.Space(), []
    space.add(pymunk.Body(1.0, 1.0))
    step = stepper(space)
    for _ in range(3):
        space.add_post_step_callback(lambda space, key: called.append(key), len(called))
        step(0.01)
    assert len(called) == 3
    # A pymunk without that bookkeeping gets its own step throughout.
    class Bare:
        def step(self, dt):
            called.append(dt)

    stepper(Bare())(0.5)
    assert called[-1] == 0.5

# The engine's step limits for a step given (``MACHINE_STEP_LIMIT``, ``FLIGHT_STEP_LIMIT``): a
# machine too slow for the fixed step (at a gravity of 1e-6 m/s^2 the paper's machine would need
# 1e9 steps) ends STEP_FAILED with the reason, instead of running for hours. Each limit is lowered
# here below what the paper's design needs (about 9,000 steps to release, 1,750 in flight and, on
# a rolling frame, 66,000 after release), so that the test runs in a second.

def test_a_machine_that_needs_more_steps_than_the_budget_stops_and_says_why(vacuum, monkeypatch):
    import engine_model.stepping as engine_stepping

    monkeypatch.setattr(engine_stepping, "MACHINE_STEP_LIMIT", 2_000)
    shot = simulate(vacuum, dt=DEFAULT_DT)   # a step given: no step budget
    assert shot.status is Status.STEP_FAILED
    assert "stages 1-2 took 2000 steps of 5e-05 s" in shot.message and "gravity" in shot.message
    assert len(shot.history.t) == 2_001            # the half step and 2,000 whole ones, then it stopped


def test_a_flight_that_needs_more_steps_than_the_budget_stops_and_says_why(vacuum, monkeypatch):
    import engine_model.flight as engine_flight

    monkeypatch.setattr(engine_flight, "FLIGHT_STEP_LIMIT", 100)
    shot = simulate(vacuum)
    assert shot.status is Status.STEP_FAILED
    assert shot.message.startswith("the engine stopped: the flight took 100 steps")
    assert shot.release_time is not None and shot.landing_time is None


def test_a_rolling_run_after_release_that_would_exceed_the_budget_is_not_started(monkeypatch):
    import engine_model.after_release as after_release
    import engine_model.shot as engine_shot
    import engine_model.stepping as engine_stepping

    design = dataclasses.replace(default_design(), base=dataclasses.replace(
        default_design().base, mobility="rolling", mass=20.0))
    started = []
    monkeypatch.setattr(engine_stepping, "MACHINE_STEP_LIMIT", 20_000)   # stages 1-2 take about 7,600
    monkeypatch.setattr(engine_shot, "run_after_release", lambda *a, **k: started.append(a))
    shot = simulate(design, dt=DEFAULT_DT)
    needed = after_release.after_release_steps(shot.release_time, shot.landing_time, DEFAULT_DT)
    assert needed > 20_000
    assert shot.status is Status.STEP_FAILED and not started
    assert f"the rolling machine's run after release would need {needed} steps" in shot.message


# The step budget of a shot at the default step (``engine_model.budget.MACHINE_FINE_STEPS`` and the
# constants after it): a design that never releases runs to the swing's time bound, which took
# 147,168 steps (5.3 s) at the default step for the cross-check's, 362,151 (11.9 s) on the Moon.

def _moon(design: Design) -> Design:
    return dataclasses.replace(design, environment=dataclasses.replace(design.environment, gravity=1.62))


def test_a_shot_that_ends_within_the_fine_steps_is_the_one_a_given_step_gives(engine, vacuum):
    given = simulate(vacuum, dt=DEFAULT_DT)
    assert engine.diagnostics.dt == DEFAULT_DT and engine.diagnostics.discarded_steps == 0
    assert np.array_equal(engine.history.t, given.history.t) and np.array_equal(engine.history.q, given.history.q)
    assert engine.range == given.range and engine.landing_time == given.landing_time


def test_the_budget_gives_a_swing_that_never_releases_its_verdict_in_few_steps():
    import engine_model.budget as engine_budget

    design = _moon(failure_designs()[Status.NEVER_RELEASES])
    assert analytic_simulate(design).status is Status.NEVER_RELEASES   # the analytic verdict, as on Earth
    shot = simulate(design)
    assert shot.status is Status.NEVER_RELEASES and PHRASES[Status.NEVER_RELEASES] in shot.message
    diagnostics = shot.diagnostics
    # The default step gave up after MACHINE_FINE_STEPS; the swing's whole bound took the coarse steps.
    assert diagnostics.discarded_steps == engine_budget.MACHINE_FINE_STEPS + 1
    assert diagnostics.dt == engine_budget.coarse_step(design) > 10 * DEFAULT_DT
    assert diagnostics.machine_steps <= engine_budget.MACHINE_COARSE_STEPS + 2


def test_the_budget_takes_a_late_release_again_at_a_step_fitted_to_it():
    """The cross-check's latest release (3.5 s): found by the coarse run, then swung at the step that
    spreads 1.1 times its time over ``MACHINE_REFINED_STEPS``; held to the cross-check's limits
    (measured against the reference path: 1.0e-8 in release speed at the default step, 5e-9 at the
    fitted one, 1.1e-4 s)."""
    import engine_model.budget as engine_budget
    from crosscheck import tolerances as tol
    from crosscheck.cases import sample_cases

    design = sample_cases(17, 0)[16].design
    reference = analytic_simulate(design)
    shot = simulate(design)
    diagnostics = shot.diagnostics
    assert DEFAULT_DT < diagnostics.dt < 3 * DEFAULT_DT
    assert diagnostics.dt == pytest.approx(engine_budget.REFINE_MARGIN * reference.release_time
                                           / engine_budget.MACHINE_REFINED_STEPS, rel=0.01)
    assert diagnostics.machine_steps + diagnostics.discarded_steps <= engine_budget.SHOT_STEP_BUDGET
    assert shot.ok
    assert abs(shot.release_speed / reference.release_speed - 1.0) < tol.RELEASE_SPEED_REL
    assert abs(shot.range - reference.range) < tol.RANGE_REL * max(reference.range, tol.RANGE_FLOOR)
    assert abs(shot.release_time - reference.release_time) < tol.EVENT_TIME


def test_the_budget_fits_a_rolling_machines_run_after_release_in_what_is_left(monkeypatch):
    import engine_model.budget as engine_budget

    design = dataclasses.replace(default_design(), base=dataclasses.replace(
        default_design().base, mobility="rolling", mass=20.0))
    monkeypatch.setattr(engine_budget, "SHOT_STEP_BUDGET", 30_000)   # 7,639 in stages 1-2, 65,938 after
    shot = simulate(design)
    diagnostics = shot.diagnostics
    assert shot.ok and diagnostics.dt == DEFAULT_DT and diagnostics.after_release_dt > 2 * DEFAULT_DT
    assert diagnostics.machine_steps + diagnostics.after_release_steps <= 30_000 + 1
    # Where the frame is at landing, against the analytic model: within the range's relative limit.
    reference = analytic_simulate(design)
    assert shot.frame_landing_displacement == pytest.approx(reference.frame_landing_displacement, rel=1e-3)


def test_a_release_between_the_fine_steps_and_the_fitted_ones_goes_on_at_the_default_step():
    """The paper's design releases at 0.38 s; under a gravity of 1 m/s^2, at 1.2 s: after the fine
    steps (1 s), within the default step's share of the refined ones (1.6 s). The run at the default
    step pauses for the coarse run, then goes on; the numbers are the ones a given step gives."""
    import engine_model.budget as engine_budget

    design = default_design()
    design = dataclasses.replace(design, environment=dataclasses.replace(design.environment, gravity=1.0))
    shot = simulate(design)
    given = simulate(design, dt=DEFAULT_DT)
    assert engine_budget.MACHINE_FINE_STEPS < given.diagnostics.machine_steps < engine_budget.MACHINE_REFINED_STEPS
    assert shot.diagnostics.dt == DEFAULT_DT and 0 < shot.diagnostics.discarded_steps <= engine_budget.MACHINE_COARSE_STEPS + 2
    assert np.array_equal(shot.history.q, given.history.q) and shot.range == given.range


def test_the_budget_makes_the_engine_throw_at_any_gravity():
    """At 1e-4 m/s^2 the paper's design needs 1.6e8 steps to its swing's bound at the default step,
    and its flight took 400,000 flight steps and ended step_failed. Within the budget every part's
    step follows the machine's time scale: the range agrees with the analytic model to 1.4e-7
    (2.7e-6 on Earth: tests/test_engine_accuracy.py), within the cross-check's RANGE_REL."""
    import engine_model.budget as engine_budget
    from crosscheck import tolerances as tol

    design = default_design()
    design = dataclasses.replace(design, environment=dataclasses.replace(design.environment, gravity=1e-4))
    reference = analytic_simulate(design)
    shot = simulate(design)
    diagnostics = shot.diagnostics
    assert shot.ok and reference.ok
    assert diagnostics.machine_steps + diagnostics.discarded_steps <= engine_budget.SHOT_STEP_BUDGET
    assert diagnostics.flight_steps <= 1.1 * engine_budget.FLIGHT_BUDGET_STEPS   # a dragged flight is shorter
    assert abs(shot.range / reference.range - 1.0) < tol.RANGE_REL
    assert abs(shot.release_speed / reference.release_speed - 1.0) < tol.RELEASE_SPEED_REL
