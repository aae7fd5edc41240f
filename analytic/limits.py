"""The limits that end a stage or a shot, written once for both analytic paths and the engine.

Plain ``math`` on floats: the reference path runs these functions as they
are, the compiled path compiles the same source (``analytic.fast.compiled``), and
the engine model imports them (they hold no dynamics).
"""

from __future__ import annotations

import math

#: Default integrator tolerances of both analytic paths: a 100x tighter run changes the
#: range by 1.5e-10 relative on the paper's design and by at most 6.5e-9 where a golf
#: ball slows through its drag table's end (over ``benchmarks.designs``).
DEFAULT_RTOL = 1e-10
DEFAULT_ATOL = 1e-10

#: The analytic model's two paths, as the tools' ``--path`` options name them: the compiled
#: ``analytic.fast`` and scipy's ``analytic.reference``.
FAST, REFERENCE = "fast", "reference"
PATHS = (FAST, REFERENCE)

#: Stage 1 ends as never_lifts_off once the sling is this close to vertical
#: (|sin beta|, within about 0.57 deg): the projectile is being dragged under
#: the arm tip, and the reduced stage-1 equations become singular there.
SLING_VERTICAL_LIMIT = 1e-2

#: Time from firing to release allowed, in pendulum periods of the whole
#: machine (``swing_time_limit``): a throwing machine releases well within
#: one; three without lift-off or release mean it never will.
SWING_PERIODS = 3.0

#: The flight bound is this many times the vacuum flight time, plus
#: ``FLIGHT_TIME_MARGIN``: drag shortens the climb and at worst stretches the
#: fall to the terminal speed, so only a broken or absurd flight reaches it.
FLIGHT_TIME_FACTOR = 100.0
#: s, added to the flight bound so that a flight starting at rest still gets time.
FLIGHT_TIME_MARGIN = 60.0

#: Accepted integrator steps each stage may take (indexed by stage number:
#: slide, swing, flight, the machine after release) before the shot ends as
#: step_failed. The time limits above bound a stage's time, not its work:
#: where the motion turns stiff (a projectile a billionth of the counterweight,
#: drag that stops it within nanoseconds, a sling a thousand times the arm,
#: whose stage-1 terms cancel to rounding noise) the step size collapses without ever falling below the
#: resolution of t, and a stage would take billions of steps. Measured on the
#: cross-check suite and 400 designs over the paper's bounds: a slide takes at
#: most 43 steps, a swing 483 (one that never releases, to its time limit), a
#: flight 43, the no-landing balloon's 9,642. Each limit is ten times the
#: largest seen, twice for the flight: a few seconds of the reference path.
#: The machine after release runs as long as the flight, and gets the flight's
#: limit for each stretch between friction's mode switches.
STAGE_STEP_LIMITS = (0, 5_000, 5_000, 20_000, 20_000)


def swing_time_limit(largest_length: float, gravity: float) -> float:
    """Longest time from firing to release, s: ``SWING_PERIODS`` periods ``2 pi sqrt(L / g)``.

    ``largest_length``: arm_long + sling_length + arm_short + counterweight_link, m.
    """
    return SWING_PERIODS * 2.0 * math.pi * math.sqrt(largest_length / gravity)


def flight_time_limit(height_above_base: float, vertical_velocity: float, gravity: float) -> float:
    """Longest flight allowed from release, s: ``FLIGHT_TIME_FACTOR`` vacuum flights plus a margin.

    The vacuum flight time from ``height_above_base`` (m) with upward speed
    ``vertical_velocity`` (m/s) is ``(vy + sqrt(vy^2 + 2 g y)) / g``.
    """
    vacuum = (vertical_velocity
              + math.sqrt(max(vertical_velocity * vertical_velocity + 2.0 * gravity * height_above_base, 0.0))
              ) / gravity
    return FLIGHT_TIME_FACTOR * vacuum + FLIGHT_TIME_MARGIN
