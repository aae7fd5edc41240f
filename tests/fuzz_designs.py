"""Hypothesis strategies for the fuzz tests: design files mutated every way, and valid extreme designs.

Kept apart from ``test_fuzz.py`` so that the strategies read as a description
of what is generated, and the tests as what must hold for it.
"""

from __future__ import annotations

import copy
import dataclasses
import datetime
import functools
import math

from hypothesis import strategies as st

from analytic.aero import DRAG_MODELS
from analytic.design import (MAX_MAGNITUDE, MAX_SLING_RELEASE_ANGLE, MAX_VELOCITY_RELEASE_ANGLE,
                             MIN_SLING_FRACTION, Base, Design, DesignError, Environment, Machine, Projectile)
from analytic.design_file import design_to_dict, default_design
from analytic.geometry import RELEASE_RULES

# --------------------------------------------------------------------------- #
# Numbers across their whole valid range
# --------------------------------------------------------------------------- #

#: The smallest positive float (subnormal), the smallest normal one: the valid
#: range's lower end for a positive number, as a file may give it.
SMALLEST_POSITIVE = 5e-324
SMALLEST_NORMAL = 2.2250738585072014e-308
#: The largest number the valid extreme designs draw, SI: far past any machine (Trebuchator's
#: largest has a 3.6e5 kg counterweight). Any number up to ``MAX_MAGNITUDE`` (1.16e77) is valid on
#: its own, but drawn that large most designs overflow a product of their numbers and are refused
#: (``analytic.design.computable_scales``), too many to fill a batch of valid ones; up to 1e12 the
#: products the model forms stay below 1e74 (the largest, the drag's: density, Cd, diameter
#: squared and speed squared at 1e12 each). The design files' fuzzing reaches ``MAX_MAGNITUDE``
#: and passes it (``OUT_OF_RANGE_NUMBERS``, ``ANY_NUMBERS``).
LARGEST = 1e12
#: One value in this many is drawn from the ends of the valid range rather than from its bulk.
EDGE_ODDS = 8

# The strategies of numbers below are built once a process for each set of arguments
# (``functools.cache``) rather than at every draw of a design: hypothesis checks a strategy it has
# not seen before on its first draw, and that check was most of the time of the extreme designs'
# fuzz tests (their shots, a fraction of a second a batch). The same strategies draw the same values.


@functools.cache
def log_uniform(low: float, high: float) -> st.SearchStrategy[float]:
    """Floats spread evenly over the decades from ``low`` to ``high`` (both positive)."""
    return st.floats(math.log10(low), math.log10(high)).map(lambda e: min(max(10.0**e, low), high))


@functools.cache
def sometimes(edges: tuple[float, ...], bulk: st.SearchStrategy[float]) -> st.SearchStrategy[float]:
    """``bulk``, or one of the ``edges`` of the valid range about once in ``EDGE_ODDS``."""
    return st.integers(0, EDGE_ODDS - 1).flatmap(lambda i: st.sampled_from(edges) if i == 0 else bulk)


@functools.cache
def positive(low: float) -> st.SearchStrategy[float]:
    """A positive number: log-uniform from ``low`` up to ``LARGEST``, or an end of that range
    (the smallest positive float, the smallest normal one, ``LARGEST``)."""
    return sometimes((SMALLEST_POSITIVE, SMALLEST_NORMAL, LARGEST), log_uniform(low, LARGEST))


@functools.cache
def non_negative(low: float) -> st.SearchStrategy[float]:
    """``positive(low)``, or zero."""
    return st.one_of(st.just(0.0), positive(low))


@functools.cache
def signed(low: float) -> st.SearchStrategy[float]:
    """Zero, or a number of magnitude log-uniform from ``low`` to the largest, either sign."""
    magnitude = sometimes((LARGEST,), log_uniform(low, LARGEST))
    return st.one_of(st.just(0.0), magnitude, magnitude.map(lambda x: -x))


@functools.cache
def fraction() -> st.SearchStrategy[float]:
    """A number strictly between 0 and 1: uniform, or within a few decades of either end."""
    near_zero = log_uniform(1e-12, 0.5)
    return st.one_of(st.floats(0.0, 1.0, exclude_min=True, exclude_max=True), near_zero,
                     near_zero.map(lambda x: 1.0 - x))


@functools.cache
def open_angle(limit: float) -> st.SearchStrategy[float]:
    """An angle strictly between ``-limit`` and ``limit``, rad: anywhere, or near either end or zero."""
    return st.one_of(st.floats(-limit, limit, exclude_min=True, exclude_max=True),
                     fraction().map(lambda f: limit * (1.0 - f)),
                     fraction().map(lambda f: -limit * (1.0 - f)),
                     st.just(0.0))


# --------------------------------------------------------------------------- #
# Valid but extreme designs
# --------------------------------------------------------------------------- #

#: Smallest value of the bulk of each kind of quantity, SI: lengths over 15
#: decades, masses over 26 (down to a 1e-20 kg projectile), the rest alike.
LENGTH_LOW, MASS_LOW, INERTIA_LOW = 1e-9, 1e-20, 1e-20
GRAVITY_LOW, DENSITY_LOW, VISCOSITY_LOW, WIND_LOW, DRAG_COEFFICIENT_LOW = 1e-6, 1e-12, 1e-12, 1e-6, 1e-6


def mass_near(reference: float, low: float, high: float) -> st.SearchStrategy[float]:
    """A mass anywhere in its valid range, or ``reference`` times a ratio log-uniform from ``low``
    to ``high``: independent masses would make half the machines too weak to fire."""
    relative = log_uniform(low, high).map(lambda r: min(LARGEST, max(SMALLEST_POSITIVE, reference * r)))
    return st.one_of(positive(MASS_LOW), relative)


@st.composite
def extreme_machines(draw) -> Machine:
    """A machine with every number across its valid range and the lengths in any proportion
    the contract allows (the long arm reaches the base, the counterweight clears it)."""
    arm_long = draw(sometimes((LARGEST,), log_uniform(LENGTH_LOW, LARGEST)))
    pivot_height = arm_long * draw(fraction())
    arm_short = pivot_height * draw(fraction())
    counterweight_link = (pivot_height - arm_short) * draw(fraction())
    # The arm's centre of mass anywhere on it, the pivot included.
    arm_cg = draw(st.one_of(st.just(0.0), fraction().map(lambda f: -arm_short + f * (arm_long + arm_short))))
    sling_length = min(LARGEST, arm_long * draw(log_uniform(MIN_SLING_FRACTION, 1e12)))
    counterweight_mass = draw(positive(MASS_LOW))
    rule = draw(st.sampled_from(RELEASE_RULES))
    limit = MAX_VELOCITY_RELEASE_ANGLE if rule == "velocity" else MAX_SLING_RELEASE_ANGLE
    try:
        return Machine(pivot_height=pivot_height, arm_long=arm_long, arm_short=arm_short,
                       arm_mass=draw(mass_near(counterweight_mass, 1e-6, 10.0)), arm_cg=arm_cg,
                       arm_inertia=draw(non_negative(INERTIA_LOW)),
                       counterweight_mass=counterweight_mass, counterweight_link=counterweight_link,
                       counterweight_inertia=draw(non_negative(INERTIA_LOW)), sling_length=sling_length,
                       release_angle=draw(open_angle(limit)), release_rule=rule)
    except DesignError:
        # A product above underflowed to zero or rounded onto a bound: not a valid design.
        return None


@st.composite
def extreme_projectiles(draw, counterweight_mass: float) -> Projectile:
    drag = draw(st.sampled_from(DRAG_MODELS))
    coefficient = draw(positive(DRAG_COEFFICIENT_LOW)) if drag == "constant" else None
    return Projectile(mass=draw(mass_near(counterweight_mass, 1e-9, 1.0)), diameter=draw(positive(LENGTH_LOW)),
                      drag=drag, drag_coefficient=coefficient)


@st.composite
def extreme_environments(draw) -> Environment:
    return Environment(gravity=draw(positive(GRAVITY_LOW)), air_density=draw(non_negative(DENSITY_LOW)),
                       air_viscosity=draw(positive(VISCOSITY_LOW)), wind_speed=draw(signed(WIND_LOW)))


#: The sling's and the pouch's mass as a fraction of the projectile's: none, or log-uniform from a
#: tiny fraction to a million times the projectile's (a chain flail throwing a pebble).
PART_MASS_RATIOS = (1e-12, 1e6)


@functools.cache
def part_mass_ratio() -> st.SearchStrategy[float]:
    """A sling's or a pouch's mass over the projectile's: 0, or ``PART_MASS_RATIOS``' range or ends."""
    low, high = PART_MASS_RATIOS
    return st.one_of(st.just(0.0), sometimes((low, high), log_uniform(low, high)))


@st.composite
def as_built_parts(draw, machine: Machine, projectile: Projectile) -> tuple[Machine, Base, float]:
    """The machine with a sling and a pouch of mass (``part_mass_ratio`` of the projectile's), a base
    with a trough (none, or any fraction of the pivot's height: near the base or just under the
    pivot), and a target's level (``signed``: far below the base to far above any apex, or the base's)."""
    masses = {name: min(LARGEST, projectile.mass * draw(part_mass_ratio())) for name in ("sling_mass", "pouch_mass")}
    trough = draw(st.one_of(st.just(0.0), fraction().map(lambda f: machine.pivot_height * f)))
    return dataclasses.replace(machine, **masses), Base(trough_height=trough), draw(signed(LENGTH_LOW))


@st.composite
def wholly_extreme_designs(draw) -> Design | None:
    """Every number of the design drawn across its valid range, the machine as built
    (``as_built_parts``) (None: the draw is no valid design)."""
    machine = draw(extreme_machines())
    if machine is None:
        return None
    try:
        projectile = draw(extreme_projectiles(machine.counterweight_mass))
        machine, base, target = draw(as_built_parts(machine, projectile))
        environment = dataclasses.replace(draw(extreme_environments()), target_height=target)
        return Design(machine, projectile, environment, name="extreme", base=base)
    except DesignError:
        # Numbers each within range whose products are not (``analytic.design.computable_scales``), a
        # part's mass rounded to a subnormal, a trough rounded onto the pivot.
        return None


#: Parts of a design that can be taken from another valid design without breaking the
#: contract's relations between fields (the lengths go together, the rule with its angle,
#: the drag model with its coefficient).
PARTS = {
    "machine": (("pivot_height", "arm_long", "arm_short", "arm_cg", "counterweight_link", "sling_length"),
                ("arm_mass",), ("arm_inertia",), ("counterweight_mass",), ("counterweight_inertia",),
                ("release_angle", "release_rule"), ("sling_mass",), ("pouch_mass",)),
    "projectile": (("mass",), ("diameter",), ("drag", "drag_coefficient")),
    "environment": (("gravity",), ("air_density",), ("air_viscosity",), ("wind_speed",), ("target_height",)),
    "base": (("trough_height",),),
}


@st.composite
def partly_extreme_designs(draw) -> Design | None:
    """The default design with a few of its parts (``PARTS``) taken from a wholly extreme one:
    a working machine with one or two absurd numbers gets to release and flight, where the
    wholly extreme ones mostly stop early (None: the draw is no valid design)."""
    base, extreme = default_design(), draw(wholly_extreme_designs())
    if extreme is None:
        return None
    parts = [(table, fields) for table, groups in PARTS.items() for fields in groups]
    chosen = draw(st.lists(st.sampled_from(parts), min_size=1, max_size=3, unique=True))
    tables = {table: {f.name: getattr(getattr(base, table), f.name) for f in dataclasses.fields(getattr(base, table))}
              for table in PARTS}
    for table, fields in chosen:
        for name in fields:
            tables[table][name] = getattr(getattr(extreme, table), name)
    if ("base", ("trough_height",)) in chosen:   # the same fraction of the pivot's height, so that it is one
        tables["base"]["trough_height"] *= tables["machine"]["pivot_height"] / extreme.machine.pivot_height
    try:
        return Design(Machine(**tables["machine"]), Projectile(**tables["projectile"]),
                      Environment(**tables["environment"]), name="partly-extreme", base=Base(**tables["base"]))
    except DesignError:
        # The default's arm on extreme lengths (its centre of mass off the arm) and the like.
        return None


def extreme_designs() -> st.SearchStrategy[Design]:
    """Valid designs with numbers anywhere in their valid range: every release rule, every drag
    model, wind either way, a sling and a pouch of any mass, a trough, a target at any level;
    wholly extreme, or the default with a few extreme parts."""
    return st.one_of(wholly_extreme_designs(), partly_extreme_designs()).filter(lambda d: d is not None)


def extreme_batches(size: int) -> st.SearchStrategy[list[Design]]:
    """Lists of up to ``size`` extreme designs (at least half of them): the draws that are no
    valid design are dropped rather than the whole batch (a batch of 50 valid draws in a row
    is rare: hypothesis would give up)."""
    return (st.lists(st.one_of(wholly_extreme_designs(), partly_extreme_designs()), min_size=size, max_size=size)
            .map(lambda designs: [d for d in designs if d is not None])
            .filter(lambda designs: len(designs) >= size // 2))


# --------------------------------------------------------------------------- #
# Design files, mutated
# --------------------------------------------------------------------------- #

def file_forms() -> dict[str, dict]:
    """The default design as each file form holds it: direct, the paper's variables, an arm cut
    from a beam, both alternatives together, and as built (a sling and a pouch of 10 g, a trough
    0.2 m up, a target 3 m up). A fresh copy each call, for a draw to mutate."""
    return copy.deepcopy(_file_forms())


@functools.cache
def _file_forms() -> dict[str, dict]:
    """``file_forms``, built once a process: reading the default design's file for each form,
    each draw, would be most of a draw's cost (63 % of the file-reading fuzz test's profile)."""
    beam = {"width": 0.019, "depth": 0.038, "density": 450.0}

    def form(paper: bool, with_beam: bool) -> dict:
        data = design_to_dict(default_design())
        if paper:
            for key in ("pivot_height", "arm_long"):
                del data["machine"][key]
            data["machine"].update(clearance=0.16, starting_angle=58.0)
        if with_beam:
            for key in ("arm_mass", "arm_cg", "arm_inertia"):
                del data["machine"][key]
            data["machine"]["arm_beam"] = dict(beam)
        return data

    as_built = form(False, False)
    as_built["machine"].update(sling_mass=0.01, pouch_mass=0.01)
    as_built["base"] = {"trough_height": 0.2}
    as_built["environment"]["target_height"] = 3.0
    return {"direct": form(False, False), "paper": form(True, False), "beam": form(False, True),
            "paper-beam": form(True, True), "as-built": as_built}


#: Text without the surrogates a UTF-8 file cannot hold.
TEXT = st.text(st.characters(blacklist_categories=("Cs",)), max_size=12)
#: Keys a table might be given by mistake: the alternative forms' keys in the wrong place,
#: near-misses of real ones, and arbitrary text.
STRAY_KEYS = st.one_of(
    st.sampled_from(["clearance", "starting_angle", "arm_beam", "arm_mass", "arm_cg", "arm_inertia",
                     "pivot_height", "arm_long", "drag_coefficient", "name", "machine", "projectile",
                     "environment", "width", "Sling_length", "sling-length", "release angle", "gravity "]),
    TEXT)

#: Numbers no design accepts anywhere: not finite, or past the float range the model computes
#: in (``MAX_MAGNITUDE``, 1.16e77 in SI).
_PAST = math.nextafter(MAX_MAGNITUDE, math.inf)
OUT_OF_RANGE_NUMBERS = st.one_of(
    st.sampled_from([math.nan, math.inf, -math.inf, 1e300, -1e300, _PAST, -_PAST, 10**400, -10**400]),
    st.floats(min_value=_PAST, allow_infinity=False), st.floats(max_value=-_PAST, allow_infinity=False),
    st.integers(min_value=10**78, max_value=10**100), st.integers(max_value=-10**78, min_value=-10**100))
#: Numbers a design may accept or refuse by field: zero, signs, the ends of the range, anything finite.
ANY_NUMBERS = st.one_of(
    OUT_OF_RANGE_NUMBERS,
    st.sampled_from([0.0, -0.0, -1.0, 1e6, -1e6, MAX_MAGNITUDE, -MAX_MAGNITUDE, SMALLEST_POSITIVE,
                     -SMALLEST_POSITIVE, 1e-300, 90.0, 180.0]),
    st.floats(allow_nan=False, allow_infinity=False), st.integers(min_value=-10**7, max_value=10**7))
#: Values of every other kind a TOML file can hold, none of them a number or a valid table.
NOT_NUMBERS = st.recursive(
    st.one_of(TEXT, st.booleans(), st.dates(), st.times(),
              st.datetimes(timezones=st.one_of(st.none(), st.just(datetime.timezone.utc)))),
    lambda inner: st.one_of(st.lists(inner, max_size=3), st.dictionaries(STRAY_KEYS, inner, max_size=2)),
    max_leaves=4)


def _paths(data: dict, prefix: tuple[str, ...] = ()) -> list[tuple[str, ...]]:
    """Every key's path in the nested tables, tables included."""
    paths = []
    for key, value in data.items():
        paths.append(prefix + (key,))
        if isinstance(value, dict):
            paths += _paths(value, prefix + (key,))
    return paths


def _tables(data: dict, prefix: tuple[str, ...] = ()) -> list[tuple[str, ...]]:
    """The path of every table, the top level (``()``) included."""
    return [prefix] + [path for key, value in data.items() if isinstance(value, dict)
                       for path in _tables(value, prefix + (key,))]


def _at(data: dict, path: tuple[str, ...]) -> dict:
    for key in path:
        data = data[key]
    return data


@st.composite
def design_files(draw, numbers: st.SearchStrategy = ANY_NUMBERS) -> tuple[dict, list[tuple[str, ...]]]:
    """A design file's tables, one of the forms (``file_forms``) with up to three mutations, and
    the paths the mutations touched.

    Each mutation puts a value of any kind TOML holds (``numbers`` or ``NOT_NUMBERS``) at an
    existing key or table, deletes one, or adds a stray key (``STRAY_KEYS``) to a table.
    """
    forms = _file_forms()
    data = copy.deepcopy(forms[draw(st.sampled_from(sorted(forms)))])
    touched = []
    for _ in range(draw(st.integers(0, 3))):
        kind = draw(st.sampled_from(["set", "delete", "add"]))
        if kind == "add":
            table = draw(st.sampled_from(_tables(data)))
            path = table + (draw(STRAY_KEYS),)
        else:
            paths = _paths(data)
            if not paths:
                continue
            path = draw(st.sampled_from(paths))
        if kind == "delete":
            del _at(data, path[:-1])[path[-1]]
        else:
            _at(data, path[:-1])[path[-1]] = draw(st.one_of(numbers, NOT_NUMBERS))
        touched.append(path)
    return data, touched
