"""How closely the analytic and engine models must agree: named limits, one reason each.

Scale of the engine's own error, for reference: on the paper's Table III design
at the default 0.05 ms step it is about 1.6e-6 relative in release speed and
2.7e-6 in range, falling 4x per halving of the step (``python -m crosscheck
--report`` measures it again, and ``tests/test_crosscheck.py`` holds it to order 2). The limits below leave
room for designs that whip harder than Table III, while a modelling mistake
(a wrong inertia, pymunk's default soft joints) still shows up as a failure:
those cost 1e-3 to 5e-2 (``tests/test_crosscheck.py``).
"""

from __future__ import annotations

import math

#: Release speed, relative. 0.05 %: ~300x the engine's step error on Table III,
#: room for short slings that whip much faster (4e-4 at 0.1 ms seen in the sample).
RELEASE_SPEED_REL = 5e-4

#: Each release-velocity component, as a fraction of the release speed: the
#: same budget as the speed, shared between directions.
RELEASE_VELOCITY_REL = 5e-4

#: Launch angle, rad (0.05 deg). With the velocity rule both models release
#: on the same direction by construction; with the sling rule the direction
#: follows from the state, whose error is the speed's (5e-4 rad ~ 0.03 deg).
LAUNCH_ANGLE = math.radians(0.05)

#: Range, relative. 0.1 %: range goes as speed squared (2 x 0.05 %).
RANGE_REL = 1e-3

#: Range tolerance floor, m: a throw landing near the pivot has a tiny range
#: but the same absolute error as its flight length; 0.1 % of 1 m = 1 mm.
RANGE_FLOOR = 1.0

#: Apex height, relative: like the range, it goes as the speed squared.
APEX_HEIGHT_REL = 1e-3

#: Lift-off and release instants, s: ten engine steps at the default step;
#: the engine finds events by interpolating between steps, so its error is a
#: fraction of a step, but slow crossings (a normal force fading gently) widen it.
EVENT_TIME = 5e-4

#: Engine runs are trusted when their own stage 1-2 energy error (a fraction
#: of the counterweight's available energy; ``EngineDiagnostics.energy_error``)
#: is at most this. On Table III it is ~1e-5 at the default step and the
#: release-speed error 1.6e-6; the worst sampled design showed a speed error
#: ~9x its energy error, so 2e-5 keeps an untrusted run's speed error under
#: the 5e-4 budget. Above it, the cross-check halves the engine step.
ENGINE_ENERGY_TRUST = 2e-5

#: How many times the cross-check may halve the engine step for one design.
MAX_STEP_HALVINGS = 2

#: Release position, m: 1 mm, the distance the projectile covers in 40 us at
#: 25 m/s -- far below the event-time budget, but positions are exact in both
#: models at a given instant, so a larger difference means different machines.
RELEASE_POSITION = 1e-3

#: A rolling frame's displacement at the projectile's landing (``Shot.frame_landing_displacement``),
#: m: 0.1 mm. The engine's error at the default step, measured by halving the step on the
#: rolling and friction groups' nine rolling cases: its value moves by at most 5.4e-6 m (the
#: 2 kg frame; second order, so ~7e-6 m at the default step, which is its difference from the
#: analytic value), 14x inside. Leaving out the joints' friction after release moves it by
#: 1.7e-2 m on ``table3-rolling-10kg-all-losses``, 170x outside.
FRAME_LANDING_DISPLACEMENT = 1e-4

# --------------------------------------------------------------------------- #
# Friction: the ``friction`` group of ``crosscheck.cases``
# --------------------------------------------------------------------------- #
# The friction cases are held to the same limits as every other case: the
# engine needs no looser one. Its friction limits are set from loads
# predicted by a line through the last two steps (``engine_model.friction.
# predicted_loads``), which is second order: on the paper's design with all
# of ``cases.REALISTIC_LOSSES`` the range moves by 3.6e-4 m from 1e-4 s to
# 5e-5 s and 9.9e-5 m from 5e-5 s to 2.5e-5 s (3.6x; the ideal design's
# 4.1x), so its error at the default step is ~1.3e-4 m, 3e-6 of the range
# (the ideal design's: 2.7e-6), against RANGE_REL = 1e-3. Setting the limits
# from the last step's load alone (a one-step lag) is first order: it cost
# 6.5e-4 m (1.5e-5 of the range) at the default step, halving with the step;
# that too would fit every limit above. With static coefficients above the
# kinetic ones the engine's limit drops from static to kinetic only after the
# step in which a joint broke free, a first-order error at each break-away:
# on the paper's design with a sticking hinge (``cases.STICKING_STATIC_HINGE``)
# the range differs from the analytic model's by 1.0e-3, 3.6e-4 and 2.5e-4 m
# at 1e-4, 5e-5 and 2.5e-5 s (2.0e-5 of the range at the default step, 50x
# inside RANGE_REL), the hinge's work by 2.1e-4 J of 17.8 J at the default step.

#: Work each loss took (``Shot.energy_dissipated``: axle, hinge, base, drag),
#: relative: each is a force or torque (going as the speed squared or the
#: load) times a path, so it shares the range's budget of 0.1 %. The engine's
#: own error, from halving its step on the paper's design and three sampled
#: ones with all losses: each loss moves by under 1.3e-5 of itself from 5e-5 s
#: to 2.5e-5 s (the most: the light arm's hinge and axle), over 50x inside.
ENERGY_DISSIPATED_REL = 1e-3

#: Floor of the dissipated-work tolerance, as a fraction of the energy the
#: counterweight released by release (``Shot.counterweight_energy_released``):
#: a loss near zero (the base's on a design that lifts off at once, the drag
#: of a short throw) is compared absolutely. 1e-5 of 24 J on the paper's
#: design is 0.24 mJ, 1 % of its base's loss; the engine's energy audit
#: closes to 7e-6 of the available energy at the default step.
ENERGY_DISSIPATED_FLOOR = 1e-5

# --------------------------------------------------------------------------- #
# Peak loads and the frame's displacement
# --------------------------------------------------------------------------- #

#: Each peak load through stages 1-2 (``analytic.result.PEAK_NAMES``: the axle's
#: and the hinge's force, the sling's tension, the projectile's felt
#: acceleration), relative. The engine takes each load from a body's momentum
#: change over a step (``engine_model.loads``), not from a joint's impulse
#: alone, and its peaks converge at order 2 like the release: 1.9e-5 off on the
#: paper's design at the default step (its axle and hinge), 4.7e-6 at half of
#: it; over the default suite's thrown designs at most 4.4e-5 (a light arm on a
#: rolling frame). 0.2 % is 100x the paper's design's error, as for every
#: quantity (``tests/test_crosscheck.py``), and a modelling mistake still fails
#: it: the arm's inertia 10 % off moves every peak load of the paper's design
#: by 13-14x this, a threefold counterweight inertia by 120-145x. Their times
#: are not compared: a flat maximum's instant is ill-conditioned.
PEAK_LOAD_REL = 2e-3

#: The arm's bending moment at the axle (``peak_arm_bending_moment``), relative.
#: The engine takes it from the long side's Newton-Euler equation on the arm
#: body's angular acceleration and its centre's (``engine_model.loads``); the
#: angular acceleration converges at order 1 only, so the peak does too: 2.6e-5
#: off on the paper's design at the default step, 1.5e-5 at half of it; over the
#: default suite at most 2.7e-4 (a wooden arm, bolted counterweight). 0.3 % is
#: 11x that and 116x the paper's design's error (every tolerance is at least
#: 100x it, ``tests/test_crosscheck.py``), and a modelling mistake still fails
#: it: the long side's mass 10 % off moves the paper's peak by 5.2 % (17x this),
#: dropping its weight and inertia (the sling's pull alone) by 52 %.
ARM_BENDING_MOMENT_REL = 3e-3

#: The frame's displacement at release (``Shot.frame_release_displacement``),
#: relative: it is the machine's momentum's share of a distance, like the range
#: (0.1 %). The engine's error at the default step is at most 2.4e-7 m
#: (on a 44 mm displacement, 5.6e-6 of it), falling 4/3 x from there to half the
#: step (order 2) on every rolling design of the default suite; a frame 10 %
#: heavier than the design's moves the displacement of the paper's machine on a
#: 10 kg frame by 2.2x this.
FRAME_DISPLACEMENT_REL = 1e-3

#: Floor of the frame's displacement, m: a heavy frame barely moves (a fixed one
#: not at all), and its error is then the event time's; 1e-3 of 1 mm is 1 um,
#: over 200x the 100 kg frame's error (3.8e-9 m).
FRAME_DISPLACEMENT_FLOOR = 1e-3

# --------------------------------------------------------------------------- #
# A difference resolved: the engine refined, the design's own sensitivity measured
# --------------------------------------------------------------------------- #

#: The share of a quantity's tolerance that the engine's own error may take where the two models
#: differ. A case whose quantities all agree needs no more; where one differs, the engine's step is
#: halved until its error, estimated from the last two steps (``ENGINE_ORDER``), is at most this
#: share of each differing quantity's tolerance (``crosscheck.comparison.refine``), so that what is
#: left of the difference is the models'. Half: a difference still over the tolerance is then at
#: least half a tolerance outside anything the engine's step explains.
ENGINE_ERROR_SHARE = 0.5

#: The engine's order of convergence in its step, by quantity, for the estimate of a run's error
#: from two steps ``h`` and ``h/2``: ``|q(h/2) - q(h)| / (2**p - 1)``. Order 2 for the events, the
#: release, the flight and the loads (``tests/test_crosscheck.py`` holds the release and the
#: range to it; the peak loads converge alike, see ``PEAK_LOAD_REL``); order 1 for the arm's
#: bending moment, which rests on the arm body's angular acceleration (``ARM_BENDING_MOMENT_REL``).
ENGINE_ORDER = {"peak_arm_bending_moment": 1}
#: The order of every quantity ``ENGINE_ORDER`` does not name.
ENGINE_DEFAULT_ORDER = 2

#: How many times past the step it trusted the cross-check may halve the engine's step to resolve
#: a difference. With ``MAX_STEP_HALVINGS`` that is 1/128 of the default step at the finest, and
#: every run is held to ``REFINEMENT_STEP_LIMIT`` steps besides (``engine_budget``): a design whose
#: error the budget cannot bring under the share above is ``engine_untrusted``, reported with the
#: error reached, never a disagreement.
MAX_REFINEMENTS = 5

#: Most pymunk steps of stages 1-2 (and of a rolling machine's run after release) in one of the
#: cross-check's engine runs: 2.5x the engine's own ``MACHINE_STEP_LIMIT``, so that a swing of
#: about 2.5 s can be halved three times past the default step (to 3.1e-6 s), which with the
#: extrapolation of ``crosscheck.comparison.refine`` resolves the slowest-converging design of
#: seeds 1-20 (a sling whirling 28 turns before release). A run this long takes about
#: 30 s and 0.3 GB; the budget is spent only where the two models differ.
REFINEMENT_STEP_LIMIT = 1_000_000

#: The largest relative change of each input in the sensitivity runs (``crosscheck.sensitivity``):
#: a few parts in 1e9, far below anything a builder measures and far above the last bit (2.2e-16),
#: so the spread it gives is the design's own amplification, not round-off.
SENSITIVITY_PERTURBATION = 4e-9

#: How many perturbed copies of a design the sensitivity runs shoot: four draws of every input,
#: each with its own signs, enough to find a direction the outcome is sensitive in (an amplified
#: difference shows in every draw that moves the amplifying input at all).
SENSITIVITY_RUNS = 4
