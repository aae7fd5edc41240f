"""The bodies' state read, and the space stepped, straight from Chipmunk, the C library under pymunk.

A state row (``engine_model.kinematics``) is 24 numbers read from four
bodies after every step. pymunk's properties wrap each reading in a
``Vec2d`` and a Python call: reading a row through them took 24 us, as long
as the step itself (200 solver iterations). The same C getters called
through pymunk's own cffi binding (``pymunk._chipmunk.lib``, the functions
pymunk's properties call) take 7 us and return the very same doubles
(``tests/test_engine_physics.py`` compares every entry with the properties').

``stepper`` does the same for the step: ``Space.step`` wraps Chipmunk's
``cpSpaceStep`` in bookkeeping for objects added or removed inside a step
and for post-step callbacks, which these spaces never have (no shapes, no
collision handlers): 1.5 us of the 23 us of a machine step, and about half
of a free projectile's step.
"""

from __future__ import annotations

from collections.abc import Callable

import pymunk
from pymunk._chipmunk import lib

_POSITION, _ANGLE = lib.cpBodyGetPosition, lib.cpBodyGetAngle
_VELOCITY, _SPIN = lib.cpBodyGetVelocity, lib.cpBodyGetAngularVelocity
_VELOCITY_AT = lib.cpBodyGetVelocityAtLocalPoint
_LOCAL_TO_WORLD = lib.cpBodyLocalToWorld
_SET_FORCE = lib.cpBodySetForce
_STEP = lib.cpSpaceStep
_ORIGIN = (0.0, 0.0)


def body_row(body: pymunk.Body, origin: bool) -> tuple[float, float, float, float, float, float]:
    """``(x, y, angle, vx, vy, w)`` of ``body``: its origin's position, and the velocity of its
    origin (``origin``; pymunk's ``velocity_at_local_point((0, 0))``) or of its centre of gravity
    (pymunk's ``velocity``)."""
    c = body._body
    position = _POSITION(c)
    velocity = _VELOCITY_AT(c, _ORIGIN) if origin else _VELOCITY(c)
    return position.x, position.y, _ANGLE(c), velocity.x, velocity.y, _SPIN(c)


def motion(body: pymunk.Body) -> tuple[float, float, float, float]:
    """``(x, y, vx, vy)``: ``body.position`` and ``body.velocity`` (its centre of gravity's)."""
    c = body._body
    position, velocity = _POSITION(c), _VELOCITY(c)
    return position.x, position.y, velocity.x, velocity.y


def set_force(body: pymunk.Body, fx: float, fy: float) -> None:
    """``body.force = (fx, fy)``, without pymunk's attribute checks. With ``motion``, the paper's
    flight (6,516 steps) takes 132 ms instead of 164 ms, to the same landing, bit for bit."""
    _SET_FORCE(body._body, (fx, fy))


def mounted_row(arm: pymunk.Body, mount: tuple[float, float]) -> tuple[float, float, float, float, float, float]:
    """``(x, y, angle, vx, vy, w)`` of a counterweight bolted to ``arm`` with its centre at the arm's
    local point ``mount`` (m): that point's position and velocity, the arm's angle and spin."""
    a = arm._body
    position, velocity = _LOCAL_TO_WORLD(a, mount), _VELOCITY_AT(a, mount)
    return position.x, position.y, _ANGLE(a), velocity.x, velocity.y, _SPIN(a)


def slider_row(arm: pymunk.Body, slider: pymunk.Body) -> tuple[float, float, float, float, float, float]:
    """``(x, y, angle, vx, vy, w)`` of a floating arm's counterweight: its centre, the slider on the
    guide (a body that never turns, so its centre's reading is exact), with the arm's angle and spin
    (the counterweight turns with the arm)."""
    a, c = arm._body, slider._body
    position, velocity = _POSITION(c), _VELOCITY(c)
    return position.x, position.y, _ANGLE(a), velocity.x, velocity.y, _SPIN(a)


def rig_row(arm: pymunk.Body, counterweight: pymunk.Body | None, projectile: pymunk.Body,
            frame: pymunk.Body, mount: tuple[float, float] | None = None,
            slider: pymunk.Body | None = None) -> tuple[float, ...]:
    """The 24 numbers of a state row: the arm's origin velocity, the others' centre-of-gravity one
    (their origin is their centre of gravity); a counterweight bolted to the arm (``counterweight``
    None) is the arm's point ``mount`` (``mounted_row``), or a floating arm's ``slider``
    (``slider_row``)."""
    a, p, f = arm._body, projectile._body, frame._body
    ap, av = _POSITION(a), _VELOCITY_AT(a, _ORIGIN)
    if slider is not None:
        weight = slider_row(arm, slider)
    elif counterweight is None:
        weight = mounted_row(arm, mount)
    else:
        c = counterweight._body
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
    Chipmunk handles looked up once, and a static frame (a fixed base: Chipmunk never moves a
    static body) read once. 5.1 us a row against ``rig_row``'s 6.5 us; the same doubles."""
    if counterweight is None:
        return lambda: rig_row(arm, None, projectile, frame, mount, slider)
    a, c, p = arm._body, counterweight._body, projectile._body
    position, angle, velocity, velocity_at, spin = _POSITION, _ANGLE, _VELOCITY, _VELOCITY_AT, _SPIN
    origin = _ORIGIN
    if frame.body_type != pymunk.Body.STATIC:
        f = frame._body

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
    ha, hb, hd = a._body, b._body, d._body
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

    pymunk's step checks the bodies added since the last one, locks the space
    so that objects added or removed from callbacks wait for the step's end,
    and runs post-step callbacks. A step with none of that to do (no collision
    handlers, no post-step callbacks, no threads, nothing waiting) is taken by
    Chipmunk directly; any other (the first after a body was added, say) by
    ``space.step``. Checked at every step: 0.2 us. Objects removed between
    steps (the base's groove at lift-off) pymunk removes at once, as before.
    On a pymunk whose space lacks any of the attributes checked
    (``fits_this_pymunk``), every step is ``space.step``'s: the same
    numbers, slower.
    """
    if not fits_this_pymunk(space):
        return space.step
    handle = space._space

    def step(dt: float) -> None:
        if (space._bodies_to_check or space._add_later or space._remove_later or space._post_step_callbacks
                or space._handlers or space.threaded):
            space.step(dt)
        else:
            _STEP(handle, dt)

    return step


#: The ``pymunk.Space`` attributes ``stepper`` reads: pymunk 7's own bookkeeping.
_SPACE_ATTRIBUTES = ("_space", "_bodies_to_check", "_add_later", "_remove_later", "_post_step_callbacks",
                     "_handlers", "threaded")


def fits_this_pymunk(space: pymunk.Space) -> bool:
    """Whether ``space`` has every attribute ``stepper`` checks (pymunk is not pinned above 7)."""
    return all(hasattr(space, name) for name in _SPACE_ATTRIBUTES)
