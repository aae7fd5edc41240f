"""The engine's calls into pymunk: its private cffi binding where that fits this pymunk, its public API otherwise.

The engine reads 24 numbers from four bodies after every step, and reads and
sets its friction constraints' impulses and limits before and after it. Two
mechanisms do that, with the same functions and the same numbers, bit for bit:

* ``"binding"``: the C functions pymunk's own properties call, through
  pymunk's private cffi binding (``pymunk._chipmunk.lib``, on a body's
  ``_body``, a constraint's ``_constraint``, a space's ``_space``): the
  same doubles without the ``Vec2d`` and the Python call a property wraps
  around each, which for a state row otherwise cost about as much as the
  step itself (200 solver iterations). Steps are taken by ``cpSpaceStep``
  where ``Space.step`` has no bookkeeping to do (``stepper``).
* ``"public"``: pymunk's public API (``body.position``, ``body.velocity``,
  ``body.velocity_at_local_point``, ``body.local_to_world``, ``body.angle``,
  ``body.angular_velocity``, ``body.force = ...``, ``space.step``,
  ``constraint.impulse``, ``constraint.max_force``), which any pymunk 7 keeps.

The private names are pymunk's internals, which a release may rename or
change without notice; the binding is used only where every one of them
imports and a probe (``_binding_fits``: a small space stepped, and every
reading and setting through the binding compared with the public API's) gives
the public API's very doubles: checked once, at import. Anything else is the
public mechanism. The environment variable ``TREBUCHET_PYMUNK`` (read once, at
import) picks: ``public`` for the public API, unset, empty or ``binding`` for
the binding where it fits. ``mechanism()`` tells which is in use. This module
is the only one of the engine that touches pymunk's private names
(``tests/test_engine_mechanisms.py`` checks that, and runs shots both ways).
"""

from __future__ import annotations

import operator
import os
from collections.abc import Callable
from typing import NamedTuple

import pymunk

#: The environment variable that picks the mechanism, and the values it takes.
VARIABLE = "TREBUCHET_PYMUNK"
MECHANISMS = ("binding", "public")


class _Calls(NamedTuple):
    """One mechanism's calls: ``body`` and ``constraint`` give what the others take (a Chipmunk handle,
    or the pymunk object itself); ``step`` takes a space's handle (the binding's alone: the public
    mechanism's steps are ``space.step``'s)."""

    body: Callable
    constraint: Callable
    position: Callable
    angle: Callable
    velocity: Callable
    spin: Callable
    velocity_at: Callable
    local_to_world: Callable
    set_force: Callable
    impulse: Callable
    max_force: Callable
    set_max_force: Callable
    step: Callable | None


def _itself(thing):
    return thing


def _public_set_force(body: pymunk.Body, force: tuple[float, float]) -> None:
    body.force = force


def _public_set_max_force(joint: pymunk.Constraint, limit: float) -> None:
    joint.max_force = limit


def _public_calls() -> _Calls:
    """pymunk's public API: its properties and methods."""
    get = operator.attrgetter
    return _Calls(_itself, _itself, get("position"), get("angle"), get("velocity"), get("angular_velocity"),
                  pymunk.Body.velocity_at_local_point, pymunk.Body.local_to_world, _public_set_force,
                  get("impulse"), get("max_force"), _public_set_max_force, None)


def _binding_calls() -> _Calls:
    """The C functions pymunk's properties call, through its private cffi binding (ImportError or
    AttributeError where this pymunk has not got them)."""
    from pymunk._chipmunk import lib

    return _Calls(operator.attrgetter("_body"), operator.attrgetter("_constraint"), lib.cpBodyGetPosition,
                  lib.cpBodyGetAngle, lib.cpBodyGetVelocity, lib.cpBodyGetAngularVelocity,
                  lib.cpBodyGetVelocityAtLocalPoint, lib.cpBodyLocalToWorld, lib.cpBodySetForce,
                  lib.cpConstraintGetImpulse, lib.cpConstraintGetMaxForce, lib.cpConstraintSetMaxForce,
                  lib.cpSpaceStep)


#: The ``pymunk.Space`` attributes ``stepper`` reads: pymunk 7's own bookkeeping.
_SPACE_ATTRIBUTES = ("_space", "_bodies_to_check", "_add_later", "_remove_later", "_post_step_callbacks",
                     "_handlers", "threaded")


def fits_this_pymunk(space: pymunk.Space) -> bool:
    """Whether ``space`` has every attribute ``stepper`` checks (pymunk's bookkeeping, not its API)."""
    return all(hasattr(space, name) for name in _SPACE_ATTRIBUTES)


#: The probe's step, s, and the body's local point its velocity and position are read at, m.
_PROBE_STEP = 0.01
_PROBE_POINT = (0.1, -0.2)


def _probe_space() -> tuple[pymunk.Space, pymunk.Body, pymunk.SimpleMotor]:
    """A body moving and turning under gravity, held by a motor that saturates: every reading nonzero."""
    space = pymunk.Space()
    space.gravity = (0.3, -9.81)
    body = pymunk.Body(2.0, 0.7)
    body.position, body.angle = (0.25, -1.5), 0.3
    body.velocity, body.angular_velocity = (1.25, -0.5), 0.75
    motor = pymunk.SimpleMotor(space.static_body, body, 0.0)
    motor.max_force = 0.2   # too little to stop the turning
    space.add(body, motor)
    space.step(_PROBE_STEP)   # the bodies' first step is ``space.step``'s (it checks them)
    return space, body, motor


def _readings(calls: _Calls, body: pymunk.Body, joint: pymunk.Constraint) -> tuple[float, ...]:
    b, j = calls.body(body), calls.constraint(joint)
    vectors = (calls.position(b), calls.velocity(b), calls.velocity_at(b, _PROBE_POINT),
               calls.local_to_world(b, _PROBE_POINT))
    return (*(c for v in vectors for c in (v.x, v.y)), calls.angle(b), calls.spin(b), calls.impulse(j),
            calls.max_force(j), *body.force)


def _binding_fits(calls: _Calls) -> bool:
    """The binding's calls do on this pymunk what its public API does, bit for bit: two probe spaces,
    one set, stepped and read through ``calls``, the other through the public API, read the same,
    and a space has every attribute ``stepper`` reads."""
    public = _public_calls()
    readings = []
    for mechanism in (calls, public):
        space, body, motor = _probe_space()
        mechanism.set_max_force(mechanism.constraint(motor), 0.5)
        mechanism.set_force(mechanism.body(body), (0.4, 1.1))
        if mechanism.step is None:
            space.step(_PROBE_STEP)
        else:
            mechanism.step(space._space, _PROBE_STEP)
        # The force applies through the step and is then cleared: set it again to read it back.
        mechanism.set_force(mechanism.body(body), (0.4, 1.1))
        readings.append(_readings(mechanism, body, motor))
    return readings[0] == readings[1] and fits_this_pymunk(space)


def _choose(setting: str | None, binding: Callable[[], _Calls] = _binding_calls) -> tuple[str, _Calls]:
    """The mechanism ``setting`` (``TREBUCHET_PYMUNK``'s value) picks, and its calls: the binding's
    where they load (``binding``) and fit (``_binding_fits``) unless ``setting`` is ``"public"``,
    the public API's otherwise."""
    if setting not in (None, "", *MECHANISMS):
        raise ValueError(f"{VARIABLE}={setting!r}: must be one of {', '.join(map(repr, MECHANISMS))} "
                         f"(unset: the binding where it fits this pymunk)")
    if setting != "public":
        try:
            calls = binding()
            if _binding_fits(calls):
                return "binding", calls
        except (ImportError, AttributeError, TypeError):   # renamed, gone or changed in this pymunk
            pass
    return "public", _public_calls()


_MECHANISM, _CALLS = _choose(os.environ.get(VARIABLE))
_BODY, _CONSTRAINT = _CALLS.body, _CALLS.constraint
_POSITION, _ANGLE, _VELOCITY, _SPIN = _CALLS.position, _CALLS.angle, _CALLS.velocity, _CALLS.spin
_VELOCITY_AT, _LOCAL_TO_WORLD, _SET_FORCE = _CALLS.velocity_at, _CALLS.local_to_world, _CALLS.set_force
_IMPULSE, _MAX_FORCE, _SET_MAX_FORCE = _CALLS.impulse, _CALLS.max_force, _CALLS.set_max_force
_ORIGIN = (0.0, 0.0)


def mechanism() -> str:
    """The mechanism in use: ``"binding"`` (pymunk's private cffi binding) or ``"public"`` (its public API)."""
    return _MECHANISM


def body_row(body: pymunk.Body, origin: bool) -> tuple[float, float, float, float, float, float]:
    """``(x, y, angle, vx, vy, w)`` of ``body``: its origin's position, and the velocity of its
    origin (``origin``; pymunk's ``velocity_at_local_point((0, 0))``) or of its centre of gravity
    (pymunk's ``velocity``)."""
    c = _BODY(body)
    position = _POSITION(c)
    velocity = _VELOCITY_AT(c, _ORIGIN) if origin else _VELOCITY(c)
    return position.x, position.y, _ANGLE(c), velocity.x, velocity.y, _SPIN(c)


def motion(body: pymunk.Body) -> tuple[float, float, float, float]:
    """``(x, y, vx, vy)``: ``body.position`` and ``body.velocity`` (its centre of gravity's)."""
    c = _BODY(body)
    position, velocity = _POSITION(c), _VELOCITY(c)
    return position.x, position.y, velocity.x, velocity.y


def velocity(body: pymunk.Body) -> tuple[float, float]:
    """``body.velocity``, its centre of gravity's."""
    velocity = _VELOCITY(_BODY(body))
    return velocity.x, velocity.y


def set_force(body: pymunk.Body, fx: float, fy: float) -> None:
    """``body.force = (fx, fy)``; the binding skips pymunk's attribute checks, which in flight (a step
    of one free body) are a large part of the step."""
    _SET_FORCE(_BODY(body), (fx, fy))


def impulse(joint: pymunk.Constraint) -> float:
    """``joint.impulse``: its impulse in the last step."""
    return _IMPULSE(_CONSTRAINT(joint))


def max_force(joint: pymunk.Constraint) -> float:
    """``joint.max_force``: its limit."""
    return _MAX_FORCE(_CONSTRAINT(joint))


def set_max_force(joint: pymunk.Constraint, limit: float) -> None:
    """``joint.max_force = limit``."""
    _SET_MAX_FORCE(_CONSTRAINT(joint), limit)


def mounted_row(arm: pymunk.Body, mount: tuple[float, float]) -> tuple[float, float, float, float, float, float]:
    """``(x, y, angle, vx, vy, w)`` of a counterweight bolted to ``arm`` with its centre at the arm's
    local point ``mount`` (m): that point's position and velocity, the arm's angle and spin."""
    a = _BODY(arm)
    position, velocity = _LOCAL_TO_WORLD(a, mount), _VELOCITY_AT(a, mount)
    return position.x, position.y, _ANGLE(a), velocity.x, velocity.y, _SPIN(a)


def slider_row(arm: pymunk.Body, slider: pymunk.Body) -> tuple[float, float, float, float, float, float]:
    """``(x, y, angle, vx, vy, w)`` of a floating arm's counterweight: its centre, the slider on the
    guide (a body that never turns, so its centre's reading is exact), with the arm's angle and spin
    (the counterweight turns with the arm)."""
    a, c = _BODY(arm), _BODY(slider)
    position, velocity = _POSITION(c), _VELOCITY(c)
    return position.x, position.y, _ANGLE(a), velocity.x, velocity.y, _SPIN(a)


def rig_row(arm: pymunk.Body, counterweight: pymunk.Body | None, projectile: pymunk.Body,
            frame: pymunk.Body, mount: tuple[float, float] | None = None,
            slider: pymunk.Body | None = None) -> tuple[float, ...]:
    """The 24 numbers of a state row: the arm's origin velocity, the others' centre-of-gravity one
    (their origin is their centre of gravity); a counterweight bolted to the arm (``counterweight``
    None) is the arm's point ``mount`` (``mounted_row``), or a floating arm's ``slider``
    (``slider_row``)."""
    a, p, f = _BODY(arm), _BODY(projectile), _BODY(frame)
    ap, av = _POSITION(a), _VELOCITY_AT(a, _ORIGIN)
    if slider is not None:
        weight = slider_row(arm, slider)
    elif counterweight is None:
        weight = mounted_row(arm, mount)
    else:
        c = _BODY(counterweight)
        cp, cv = _POSITION(c), _VELOCITY(c)
        weight = (cp.x, cp.y, _ANGLE(c), cv.x, cv.y, _SPIN(c))
    pp, pv = _POSITION(p), _VELOCITY(p)
    fp, fv = _POSITION(f), _VELOCITY(f)
    return (ap.x, ap.y, _ANGLE(a), av.x, av.y, _SPIN(a), *weight,
            pp.x, pp.y, _ANGLE(p), pv.x, pv.y, _SPIN(p), fp.x, fp.y, _ANGLE(f), fv.x, fv.y, _SPIN(f))


def row_reader(arm: pymunk.Body, counterweight: pymunk.Body | None, projectile: pymunk.Body,
               frame: pymunk.Body, mount: tuple[float, float] | None = None,
               slider: pymunk.Body | None = None) -> Callable[[], tuple[float, ...]]:
    """``rig_row`` of these bodies as a function of nothing, for a loop of steps: the bodies'
    handles looked up once, and a static frame (a fixed base: Chipmunk never moves a
    static body) read once. The same doubles, with fewer calls per row than ``rig_row``."""
    if counterweight is None:
        return lambda: rig_row(arm, None, projectile, frame, mount, slider)
    a, c, p = _BODY(arm), _BODY(counterweight), _BODY(projectile)
    position, angle, velocity, velocity_at, spin = _POSITION, _ANGLE, _VELOCITY, _VELOCITY_AT, _SPIN
    origin = _ORIGIN
    if frame.body_type != pymunk.Body.STATIC:
        f = _BODY(frame)

        def read() -> tuple[float, ...]:
            ap, av, cp, cv = position(a), velocity_at(a, origin), position(c), velocity(c)
            pp, pv, fp, fv = position(p), velocity(p), position(f), velocity(f)
            return (ap.x, ap.y, angle(a), av.x, av.y, spin(a), cp.x, cp.y, angle(c), cv.x, cv.y, spin(c),
                    pp.x, pp.y, angle(p), pv.x, pv.y, spin(p), fp.x, fp.y, angle(f), fv.x, fv.y, spin(f))
        return read
    fixed = body_row(frame, False)

    def read_fixed() -> tuple[float, ...]:
        ap, av, cp, cv, pp, pv = position(a), velocity_at(a, origin), position(c), velocity(c), position(p), velocity(p)
        return (ap.x, ap.y, angle(a), av.x, av.y, spin(a), cp.x, cp.y, angle(c), cv.x, cv.y, spin(c),
                pp.x, pp.y, angle(p), pv.x, pv.y, spin(p), *fixed)
    return read_fixed


def origin_reader(a: pymunk.Body, b: pymunk.Body | None, held: pymunk.Body,
                  d: pymunk.Body, mount: tuple[float, float] | None = None) -> Callable[[], tuple[float, ...]]:
    """``body_row(body, origin=True)`` of the four bodies, concatenated, as a function of nothing,
    for the rolling machine's run after release: their handles looked up once, and ``held`` (the
    projectile, taken out of the space: nothing moves it) read once. The same doubles. A counterweight
    bolted to the arm (``b`` None) is the arm's point ``mount`` (``mounted_row``)."""
    if b is None:
        still, frame = body_row(held, True), d
        return lambda: (*body_row(a, True), *mounted_row(a, mount), *still, *body_row(frame, True))
    ha, hb, hd = _BODY(a), _BODY(b), _BODY(d)
    position, angle, velocity_at, spin, origin = _POSITION, _ANGLE, _VELOCITY_AT, _SPIN, _ORIGIN
    still = body_row(held, True)

    def read() -> tuple[float, ...]:
        ap, av, bp, bv = position(ha), velocity_at(ha, origin), position(hb), velocity_at(hb, origin)
        dp, dv = position(hd), velocity_at(hd, origin)
        return (ap.x, ap.y, angle(ha), av.x, av.y, spin(ha), bp.x, bp.y, angle(hb), bv.x, bv.y, spin(hb),
                *still, dp.x, dp.y, angle(hd), dv.x, dv.y, spin(hd))
    return read


def stepper(space: pymunk.Space) -> Callable[[float], None]:
    """A function of ``dt`` that does what ``space.step(dt)`` does, for a space of bodies and joints.

    The public mechanism's is ``space.step``. pymunk's step checks the bodies
    added since the last one, locks the space so that objects added or
    removed from callbacks wait for the step's end, and runs post-step
    callbacks. On the binding, a step with none of that to do (no collision
    handlers, no post-step callbacks, no threads, nothing waiting) is taken by
    Chipmunk's ``cpSpaceStep`` directly, which in flight (one free body) is
    about half the step; any other (the first after a body was added, say)
    by ``space.step``. Checked at every step. Objects removed between steps
    (the base's groove at lift-off) pymunk removes at once, as before. A space
    that lacks any of the attributes checked (``fits_this_pymunk``) gets
    ``space.step`` too.
    """
    if _CALLS.step is None or not fits_this_pymunk(space):
        return space.step
    handle, cp_step = space._space, _CALLS.step

    def step(dt: float) -> None:
        if (space._bodies_to_check or space._add_later or space._remove_later or space._post_step_callbacks
                or space._handlers or space.threaded):
            space.step(dt)
        else:
            cp_step(handle, dt)

    return step
