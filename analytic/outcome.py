"""How a shot can end: the statuses, the stages, and what each outcome says to the user.

Shared by both analytic paths and the engine model (which may import this
module: it holds no dynamics), so a design that fails is named and explained
the same way whichever model ran it. A valid design that does not throw is a
result with a ``Status`` and a message, never an exception.
"""

from __future__ import annotations

import enum
import math

from analytic.limits import STAGE_STEP_LIMITS


class Status(enum.StrEnum):
    """How a shot ended. Only ``OK`` is a throw; the rest are named failures of a valid design.

    A ``str`` whose text is its value (``str(Status.OK) == "ok"``), so that numpy compares an
    array of them (``Shots.status == Status.OK``) and writes them as their values.
    """

    OK = "ok"
    NEVER_FIRES = "never_fires"                            # the counterweight cannot lift the arm
    NEVER_LIFTS_OFF = "never_lifts_off"                    # the projectile stays on the base
    HITS_BASE_BEFORE_RELEASE = "hits_base_before_release"  # back on the base before release
    NEVER_RELEASES = "never_releases"                      # release condition not met in time
    NO_LANDING = "no_landing"                              # the flight never comes down in time
    STEP_FAILED = "step_failed"                            # the integrator could not take a step
    SHORT_OF_TARGET = "short_of_target"                    # the flight's apex is below the target

    @property
    def code(self) -> int:
        """The integer the compiled path reports for this status (its position in the enum)."""
        return _CODES[self]

    @classmethod
    def from_code(cls, code: int) -> Status:
        return _STATUSES[code]


_STATUSES = tuple(Status)
_CODES = {status: i for i, status in enumerate(_STATUSES)}


#: The losses a shot accounts for (``Shot.energy_dissipated``'s keys), J: the
#: main axle's friction, the counterweight hinge's, the base's (stage 1),
#: the air's drag in flight, then its drag before release (``projectile.drag_during_swing``;
#: 0 without it), and a floating arm's guide's and track's friction.
LOSS_NAMES = ("axle", "hinge", "base", "drag", "swing_drag", "guide", "track")


def friction_work_names(floating: bool, floating_base: bool = False) -> tuple[str, ...]:
    """The frictions whose work a shot's state carries (``analytic.states.friction_work``), in order:
    the axle's, the hinge's and the base's, or a floating arm's axle's, guide's and track's (it
    has no hinge), then, with ``floating_base`` (``analytic.states.floating_base``), its base's."""
    if floating:
        return ("axle", "guide", "track", "base") if floating_base else ("axle", "guide", "track")
    return ("axle", "hinge", "base")


def dissipated(work, drag: float, swing_drag: float, floating: bool, floating_base: bool = False) -> dict[str, float]:
    """``Shot.energy_dissipated``, keyed ``LOSS_NAMES``: the friction's ``work`` (its slots,
    ``friction_work_names``), the drag's in flight and before release, 0 for every other loss."""
    losses = dict.fromkeys(LOSS_NAMES, 0.0)
    losses.update(zip(friction_work_names(floating, floating_base), work, strict=True))
    losses.update(drag=drag, swing_drag=swing_drag)
    return losses


class Stage(enum.IntEnum):
    """The three stages of a shot (``docs/derivation.md``)."""

    SLIDE = 1   # projectile on the base, dragged by the sling
    SWING = 2   # free swing in the sling
    FLIGHT = 3  # point-mass flight with drag and wind


class LiftoffFailure(enum.IntEnum):
    """Why the projectile never left the base (the detail of ``Status.NEVER_LIFTS_OFF``)."""

    UNDER_TIP = 1   # dragged under the arm tip: the sling turned vertical
    ARM_BACK = 2    # the arm swung back down to the base
    TIME_LIMIT = 3  # still on the base at the time limit
    STALLED = 4     # friction stopped the arm before lift-off


# --------------------------------------------------------------------------- #
# What each outcome says
# --------------------------------------------------------------------------- #

#: Whose friction holds the arm at rest, in words, where only the axle's can (``never_fires_message``).
AXLE_HOLDS = "the axle's"


def friction_holders(axle: bool = True, guide: bool = False, track: bool = False) -> str:
    """Whose static friction holds the arm at rest, in words: the axle's, and a floating arm's guide's
    and track's, each named where it has friction (``analytic.friction.holders``; the engine's
    friction joints)."""
    names = [name for name, present in ((AXLE_HOLDS, axle), ("the guide's", guide), ("the track's", track))
             if present]
    if len(names) <= 1:
        return names[0] if names else AXLE_HOLDS
    return f"{', '.join(names[:-1])} and {names[-1]}"


def never_fires_message(arm_acceleration: float, drive: float | None = None, axle_hold: float | None = None,
                        base_hold: float | None = None, holders: str = AXLE_HOLDS, held_by: str | None = None) -> str:
    """``arm_acceleration``: the arm's angular acceleration at rest, rad/s^2 (clockwise is negative).

    With friction, the torque balance at rest, N m (``analytic.friction.rest_balance``;
    the engine's ``engine_model.friction.static_balance``): ``drive`` gravity's torque
    turning the arm clockwise, ``axle_hold`` and ``base_hold`` the most the axle's and
    the base's friction can hold against it. ``base_hold`` None: the model weighs the
    axle's alone (the engine), and the base holds, through the sling, what the axle does not.
    ``holders``: whose friction ``axle_hold`` is, in words (``friction_holders``). ``held_by``: whose
    friction a model found holding the arm without weighing the torques (the engine's floating arm).
    """
    if drive is None and held_by is not None:
        return (f"the counterweight cannot lift the arm: {held_by} friction holds it at rest (at rest the "
                f"arm's angular acceleration is {arm_acceleration:+.3g} rad/s^2)")
    if drive is None:
        return (f"the counterweight cannot lift the arm: at rest the arm's angular "
                f"acceleration is {arm_acceleration:+.4g} rad/s^2, not clockwise (negative)")
    axle = (f"gravity turns the arm clockwise with {drive:.4g} N m against at most {axle_hold:.4g} N m "
            f"of {holders} static friction")
    if 0.0 < drive <= axle_hold:   # the same words from either model
        return f"the counterweight cannot lift the arm: {holders} friction holds it at rest ({axle})"
    if base_hold is None:
        if drive <= 0.0:
            return f"the counterweight cannot lift the arm: {axle}"
        return (f"the counterweight cannot lift the arm: friction holds the machine at rest ({axle}; the "
                f"base's friction holds the projectile, and the sling holds the arm by it: at rest the arm's "
                f"angular acceleration is {arm_acceleration:+.3g} rad/s^2)")
    balance = (f"gravity turns the arm clockwise with {drive:.4g} N m against friction that can hold "
               f"{axle_hold + base_hold:.4g} N m (axle {axle_hold:.4g} N m, base {base_hold:.4g} N m)")
    if drive <= 0.0:
        return f"the counterweight cannot lift the arm: {balance}"
    if drive <= axle_hold + base_hold:
        return f"friction holds the machine at rest, it never fires: {balance}"
    return (f"the counterweight cannot lift the arm: {balance}, but slipping the arm's angular "
            f"acceleration would be {arm_acceleration:+.4g} rad/s^2, not clockwise")


def never_lifts_off_message(reason: LiftoffFailure, time_limit: float) -> str:
    text = {LiftoffFailure.UNDER_TIP: "it was dragged under the arm tip (the sling turned vertical)",
            LiftoffFailure.ARM_BACK: "the arm swung back down to the base",
            LiftoffFailure.TIME_LIMIT: f"it was still on the base after the time limit of {time_limit:.3g} s",
            LiftoffFailure.STALLED: "friction stopped the arm while the projectile was still on the base"}
    return f"the projectile never lifts off: {text[LiftoffFailure(reason)]}"


def hits_base_message(time: float) -> str:
    return (f"the projectile came back down to the base at t = {time:.4f} s "
            f"before the release condition was met")


def never_releases_message(release_rule: str, release_angle: float, time_limit: float) -> str:
    """``release_angle`` in rad; the message gives it in degrees, as design files do."""
    if release_rule == "ideal":   # its search found no release that lands, and the arm never stopped
        return (f"no release in the swing lands, and the arm did not stop its swing within the "
                f"time limit of {time_limit:.3g} s")
    rule = "velocity direction" if release_rule == "velocity" else "sling-to-arm angle"
    return (f"the {rule} never reached the release angle of {math.degrees(release_angle):g} deg "
            f"within the time limit of {time_limit:.3g} s")


def no_landing_message(flight_time_limit: float) -> str:
    return (f"the projectile did not come down within {flight_time_limit:.3g} s of flight "
            f"(is the wind or the drag far outside anything real?)")


def short_of_target_message(apex_height: float, target_height: float, length=None) -> str:
    """``apex_height`` (the flight's highest point) and ``target_height``, m above the base;
    ``length`` formats a length in the user's units (``analytic.units``; default metres)."""
    length = length or (lambda metres: f"{metres:.4g} m")
    return (f"the projectile never reaches the target: its highest point, {length(apex_height)} above the base, "
            f"is below the target's height of {length(target_height)}")


def step_failed_message(time: float, stage: Stage, step_limit: bool = False) -> str:
    """``step_limit``: the stage used up its ``analytic.limits.STAGE_STEP_LIMITS`` steps (else the
    step size fell below the resolution of t, or the state became non-finite)."""
    why = (f"it took {STAGE_STEP_LIMITS[int(stage)]} steps without finishing the stage" if step_limit else
           "the step size fell below the resolution of t or the state became non-finite")
    return (f"the integrator could not continue at t = {time:.6g} s in stage {int(stage)} "
            f"({Stage(stage).name.lower()}): {why}; the design is probably far outside anything buildable")


def step_budget_message(part: str, steps: int, dt: float, time_bound: float, limit: int,
                        ahead: bool = False) -> str:
    """Why a fixed-step model's run (the engine's) ended ``STEP_FAILED``: ``part`` took (or, ``ahead``,
    would take) ``steps`` steps of ``dt`` s, ``limit`` the most it may; ``time_bound`` s, the time it had."""
    took = "would need" if ahead else "took"
    return (f"the engine stopped: {part} {took} {steps} steps of {dt:g} s ({steps * dt:.4g} s of motion, "
            f"against a time bound of {time_bound:.4g} s), and the engine's limit is {limit} steps; "
            f"the design is far outside anything buildable (a machine this slow: check gravity and the "
            f"masses), or use a larger --dt")


def failure_message(status: Status, *, time: float = 0.0, detail: int = 0, time_limit: float = math.nan,
                    release: tuple[str, float] = ("sling", math.nan), fires: tuple = (math.nan,),
                    step_limit: bool = False, apex: tuple[float, float] = (math.nan, math.nan)) -> str:
    """The message of a shot that ended in the failure ``status``, whichever model or path ran it.

    Each failure reads what it reports: ``fires`` the arguments of
    ``never_fires_message``; ``detail`` the ``LiftoffFailure`` (``NEVER_LIFTS_OFF``) or
    the ``Stage`` (``STEP_FAILED``); ``time`` when the shot ended (the flight's length
    for ``NO_LANDING``), s; ``time_limit`` the firing-to-release limit, s; ``release``
    the machine's ``(release_rule, release_angle)``, rad; ``step_limit`` whether the
    stage ran out of steps; ``apex`` the flight's highest point and the target's height, m above
    the base (``SHORT_OF_TARGET``).
    """
    status = Status(status)
    if status is Status.NEVER_FIRES:
        return never_fires_message(*fires)
    if status is Status.NEVER_LIFTS_OFF:
        return never_lifts_off_message(LiftoffFailure(int(detail)), time_limit)
    if status is Status.HITS_BASE_BEFORE_RELEASE:
        return hits_base_message(time)
    if status is Status.NEVER_RELEASES:
        return never_releases_message(*release, time_limit)
    if status is Status.NO_LANDING:
        return no_landing_message(time)
    if status is Status.STEP_FAILED:
        return step_failed_message(time, Stage(int(detail)), step_limit)
    if status is Status.SHORT_OF_TARGET:
        return short_of_target_message(*apex)
    raise ValueError(f"{status!r} is not a failure")


def thrown_message(range_: float) -> str:
    return "thrown, but the projectile landed behind the pivot" if range_ < 0.0 else "thrown"
