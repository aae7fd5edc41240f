"""What several test files share: design variants, the known designs, Table II samples, shared limits.

Test files import shared material from here and from no other test file;
``conftest.py`` holds only fixtures. The designs come from the project's own
files (``analytic/data``), so no number of theirs is typed twice.
"""

from __future__ import annotations

import dataclasses
import datetime
import math
import tomllib
from pathlib import Path

import numpy as np
from hypothesis import settings
from hypothesis import strategies as st

import analytic
from analytic.design import Base, BeamArm, Design, Losses
from analytic.design_file import beam_arm_from_dict, default_design, load_design
from analytic.design_space import VARIABLE_NAMES, default_problem, design_at, from_unit, sample_designs, variables_of
from crosscheck.cases import LIGHT_ARM
from analytic.result import Status

DATA = Path(analytic.__file__).with_name("data")
#: The default design (the paper's Table III) and the optimiser's problem (Table II).
TABLE3_FILE = DATA / "paper_table3.toml"
PROBLEM_FILE = DATA / "paper_problem.toml"
#: One known design per failure status, ``fails-<status>.toml``; the cross-check reads them too.
FAILURE_DESIGN_DIR = DATA / "designs"


# --------------------------------------------------------------------------- #
# Variants of a design
# --------------------------------------------------------------------------- #

def with_machine(design: Design, **changes) -> Design:
    """``design`` with machine fields replaced (validated again)."""
    return dataclasses.replace(design, machine=dataclasses.replace(design.machine, **changes))


def with_projectile(design: Design, **changes) -> Design:
    return dataclasses.replace(design, projectile=dataclasses.replace(design.projectile, **changes))


def with_environment(design: Design, **changes) -> Design:
    return dataclasses.replace(design, environment=dataclasses.replace(design.environment, **changes))


def table3_variants() -> dict[str, Design]:
    """Table III and variants that each exercise one input, by name: the release rules at
    several angles, every drag model, wind both ways, counterweight inertia 0 and large,
    heavy and light arms, an arm whose centre lies on the short side."""
    t3 = default_design()
    deg = math.radians
    variants = {
        "table3": t3,
        "release-61deg": with_machine(t3, release_angle=deg(61.0)),  # the prototype's, paper section IV
        "downward-release": with_machine(t3, release_angle=deg(-30.0)),
        "very-late-release": with_machine(t3, release_angle=deg(-75.0)),
        "steep-release": with_machine(t3, release_angle=deg(75.0)),
        "sling-rule-behind": with_machine(t3, release_rule="sling", release_angle=deg(-40.0)),
        "sling-rule-ahead": with_machine(t3, release_rule="sling", release_angle=deg(20.0)),
        "point-counterweight": with_machine(t3, counterweight_inertia=0.0),
        "large-counterweight-inertia": with_machine(t3, counterweight_inertia=0.08),
        "heavy-arm": with_machine(t3, arm_mass=1.2, arm_inertia=0.09),
        "light-arm": with_machine(t3, arm_mass=0.05),  # under 2 % of the counterweight: engine ballast
        "arm-centre-on-short-side": with_machine(t3, arm_cg=-0.1),
        "vacuum": with_projectile(t3, drag="none"),
        "constant-drag-tailwind": with_environment(with_projectile(t3, drag="constant", drag_coefficient=0.4),
                                                   wind_speed=4.0),
        "smooth-sphere-headwind": with_environment(with_projectile(t3, drag="smooth-sphere"), wind_speed=-5.0),
        "golf-ball-tailwind": with_environment(t3, wind_speed=5.0),
        "golf-ball-headwind": with_environment(t3, wind_speed=-5.0),
    }
    return {name: dataclasses.replace(design, name=name) for name, design in variants.items()}


# --------------------------------------------------------------------------- #
# The project's own files
# --------------------------------------------------------------------------- #

def table3_file() -> dict:
    """The default design's file as ``tomllib`` reads it (its beam table, say)."""
    with TABLE3_FILE.open("rb") as handle:
        return tomllib.load(handle)


def table3_beam() -> BeamArm:
    """The pine beam the default design's arm is cut from (its file's ``[machine.arm_beam]``)."""
    return beam_arm_from_dict(table3_file()["machine"]["arm_beam"])


def problem_dict() -> dict:
    """The default problem file as a dict, to vary in tests."""
    with PROBLEM_FILE.open("rb") as handle:
        return tomllib.load(handle)


def release_angle_problem_dict() -> dict:
    """The paper's problem file with every variable but the release angle fixed at Table III, in vacuum."""
    data = problem_dict()
    values = variables_of(default_design().machine)
    for name, value in zip(VARIABLE_NAMES[:5], values[:5], strict=True):
        data["variables"][name] = {"value": math.degrees(value) if name.endswith("angle") else value}
    data["projectile"]["drag"] = "none"
    data["name"] = "release-angle-vacuum"
    return data


# --------------------------------------------------------------------------- #
# Designs that do not throw
# --------------------------------------------------------------------------- #

def failure_designs() -> dict[Status, Design]:
    """The known design for each failure status, read from ``analytic/data/designs``."""
    paths = sorted(FAILURE_DESIGN_DIR.glob("fails-*.toml"))
    return {Status(path.stem.removeprefix("fails-")): load_design(path) for path in paths}


#: A phrase each failure's message must hold (``analytic.outcome`` writes them for both models).
PHRASES = {Status.NEVER_FIRES: "cannot lift the arm", Status.NEVER_LIFTS_OFF: "never lifts off",
           Status.HITS_BASE_BEFORE_RELEASE: "came back down to the base",
           Status.NEVER_RELEASES: "never reached the release angle",
           Status.NO_LANDING: "did not come down", Status.SHORT_OF_TARGET: "never reaches the target"}


# --------------------------------------------------------------------------- #
# Fixed (bolted) counterweights
# --------------------------------------------------------------------------- #

#: The sample fixed design: the paper's Table III machine with its counterweight bolted.
TABLE3_FIXED_FILE = DATA / "paper_table3_fixed.toml"


def bolted(design: Design) -> Design:
    """``design`` with its counterweight bolted to the arm (kind "fixed", no link)."""
    return with_machine(design, kind="fixed", counterweight_link=0.0)


def fixed_designs() -> dict[str, Design]:
    """Fixed machines: the sample file, with the axle's and the base's friction, on a rolling
    frame (with and without them), every ``table3_variants`` one bolted, and one design per
    failure status (``fixed_failure_designs``)."""
    table3 = load_design(TABLE3_FIXED_FILE)
    lossy = dataclasses.replace(table3, losses=Losses(axle_friction=0.15, axle_radius=0.01, base_friction=0.3,
                                                      axle_static_friction=0.2, base_static_friction=0.4))
    designs = {"fixed": table3, "fixed-lossy": lossy,
               "fixed-rolling": dataclasses.replace(table3, base=Base("rolling", 5.0)),
               "fixed-rolling-lossy": dataclasses.replace(lossy, base=Base("rolling", 5.0))}
    designs.update({f"fixed-{name}": bolted(design) for name, design in table3_variants().items()})
    designs.update({f"fixed-{status.value}": design for status, design in fixed_failure_designs().items()})
    return designs


TABLE3_FLOATING_FILE = DATA / "paper_table3_floating.toml"


def floating(design: Design) -> Design:
    """``design`` as a floating-arm machine (its counterweight rigid on the short end, no link)."""
    return with_machine(design, kind="floating-arm", counterweight_link=0.0)


def floating_designs() -> dict[str, Design]:
    """Ideal floating-arm machines: the sample file (the paper's Table III machine), released by the
    sling rule, with the axle's friction, the first four ``table_ii_sample(4, seed=28)`` designs (the pine arm and the light
    one; the first never fires, the others throw), the large machine (``crosscheck.cases.large_design``:
    a 3 m arm, 200 kg counterweight) and ``floating_failure_designs``."""
    from crosscheck.cases import large_design

    table3 = load_design(TABLE3_FLOATING_FILE)
    designs = {"floating": table3,
               "floating-sling-rule": with_machine(table3, release_rule="sling", release_angle=math.radians(-40.0))}
    designs.update({f"floating-sample-{i}": floating(d) for i, d in enumerate(table_ii_sample(4, seed=28))})
    designs["floating-large"] = large_design("floating-arm")
    designs["floating-axle-friction"] = dataclasses.replace(
        table3, losses=Losses(axle_friction=0.15, axle_radius=0.01, axle_static_friction=0.2))
    designs.update({f"floating-{status.value}": d for status, d in floating_failure_designs().items()})
    return designs


def floating_failure_designs() -> dict[Status, Design]:
    """Floating-arm designs that fail: ``failure_designs``' never_lifts_off and hits_base_before_release
    ones as floating arms (each keeps its status), the paper's with a counterweight too light to lift the arm
    (0.2 kg, as ``crosscheck.cases.FIXED_UNFIRED_COUNTERWEIGHT``: its torque at rest, 0.2 * 0.2405
    = 0.048 kg m, is less than the arm's 0.306 * 0.230 = 0.070 kg m) and ``fails-no_landing.toml``'s
    10 mg balloon (terminal speed 0.021 m/s) flung 60 deg downward by the sample floating machine."""
    table3 = load_design(TABLE3_FLOATING_FILE)
    known = failure_designs()
    balloon = known[Status.NO_LANDING]
    return {Status.NEVER_FIRES: with_machine(table3, counterweight_mass=0.2),
            Status.NEVER_LIFTS_OFF: floating(known[Status.NEVER_LIFTS_OFF]),
            Status.HITS_BASE_BEFORE_RELEASE: floating(known[Status.HITS_BASE_BEFORE_RELEASE]),
            Status.NO_LANDING: dataclasses.replace(with_machine(table3, release_angle=balloon.machine.release_angle),
                                                   projectile=balloon.projectile)}


def fixed_failure_designs() -> dict[Status, Design]:
    """A fixed design for each failure status: the known hinged ones (``failure_designs``) bolted
    where that keeps their status; otherwise one found for the fixed machine (below)."""
    known = failure_designs()
    designs = {status: bolted(known[status]) for status in
               (Status.NEVER_FIRES, Status.NEVER_LIFTS_OFF, Status.HITS_BASE_BEFORE_RELEASE)}
    # The sample fixed design flinging fails-no_landing.toml's balloon at 3 mg (the 10 mg one
    # lands: the fixed machine's flight bound is longer); terminal speed 0.0066 m/s.
    balloon = known[Status.NO_LANDING]
    designs[Status.NO_LANDING] = with_projectile(with_machine(load_design(TABLE3_FIXED_FILE),
                                                              release_angle=balloon.machine.release_angle),
                                                 drag=balloon.projectile.drag, mass=3e-6,
                                                 diameter=balloon.projectile.diameter,
                                                 drag_coefficient=balloon.projectile.drag_coefficient)
    # Found by a scan with the fast path (table_ii_sample(3000, seed=77) bolted, the sling rule at
    # angles uniform over 90-170 deg and drag-free projectiles of 0.01-3 kg, numpy seed 7: the one
    # design of 3000 that never released), kept as found.
    scanned = table_ii_sample(3000, seed=77)[0]
    designs[Status.NEVER_RELEASES] = dataclasses.replace(
        scanned, name="fixed-never_releases",
        machine=dataclasses.replace(scanned.machine, kind="fixed", counterweight_link=0.0,
                                    pivot_height=0.825535176314764, arm_long=0.8974691788281115,
                                    arm_short=0.2277579099969643, arm_mass=0.36558628115926706,
                                    arm_cg=0.3348556344155736, arm_inertia=0.038617488232758346,
                                    counterweight_mass=6.5, counterweight_inertia=0.009346195228721923,
                                    sling_length=0.14272494375751954, release_angle=1.942013725289827,
                                    release_rule="sling"),
        projectile=dataclasses.replace(scanned.projectile, mass=1.5855422281496712, drag="none",
                                       drag_coefficient=None))
    return designs


# --------------------------------------------------------------------------- #
# Designs over the paper's Table II bounds
# --------------------------------------------------------------------------- #

def table_ii_sample(count: int, seed: int) -> list[Design]:
    """``count`` designs drawn uniformly over the problem file's bounds (seeded), alternating
    the problem's arm (the default design's pine beam) and ``LIGHT_ARM``."""
    problem = default_problem()
    return sample_designs(problem, count, seed, lambda i: f"table-ii-{seed}-{i:03d}", arms=(problem.arm, LIGHT_ARM))


@st.composite
def paper_designs(draw) -> Design:
    """A design over the problem file's Table II bounds (angles drawn in degrees, as the paper
    gives them), with the pine or the light arm and either release rule; the problem's
    counterweight, golf ball and air."""
    problem = default_problem()
    arm = draw(st.sampled_from([problem.arm, LIGHT_ARM]))
    values = {}
    for name in ("arm_short", "counterweight_link", "clearance", "starting_angle", "sling_length", "release_angle"):
        variable = problem.variables[VARIABLE_NAMES.index(name)]
        if name.endswith("angle"):
            values[name] = math.radians(draw(st.floats(math.degrees(variable.lower), math.degrees(variable.upper))))
        else:
            values[name] = draw(st.floats(variable.lower, variable.upper))
    rule = draw(st.sampled_from(["velocity", "sling"]))
    vector = np.array([values[name] for name in VARIABLE_NAMES])
    return design_at(dataclasses.replace(problem, arm=arm, release_rule=rule), vector, name="sampled")


#: Each friction coefficient of ``[losses]`` that the designs below draw: 0 in about one draw of
#: ``NO_LOSS_ODDS``, else uniform over the range a real machine of this size may have (Coulomb
#: coefficients as handbooks list them: a greased metal pin in a wooden or bronze bearing
#: 0.05-0.2, a dry one up to 0.5; a leather pouch or a wooden sled on a wooden base 0.2-0.6).
LOSS_COEFFICIENTS = {"axle_friction": (0.03, 0.5), "hinge_friction": (0.03, 0.5), "base_friction": (0.1, 0.7)}
#: The pin radius of each joint, m, drawn with it (with a zero coefficient too: a frictionless
#: bearing): 2-20 mm, from a 4 mm pin to a 40 mm axle (the default design's axle has a 6.4 mm
#: radius, its hinge pin 5 mm).
LOSS_RADII = {"axle_friction": ("axle_radius", 0.002, 0.02), "hinge_friction": ("hinge_radius", 0.002, 0.02)}
#: Static coefficients as a multiple of their kinetic one: ``name: (kinetic coefficient, low, high)``
#: (dry wood, greased steel: 1-1.5x; up to 2x to reach the sticking regime often).
STATIC_COEFFICIENTS: dict[str, tuple[str, float, float]] = {
    "axle_static_friction": ("axle_friction", 1.0, 2.0), "hinge_static_friction": ("hinge_friction", 1.0, 2.0),
    "base_static_friction": ("base_friction", 1.0, 2.0)}
NO_LOSS_ODDS = 4
#: Frame masses a design rolls on, kg: README's table of the paper's design on wheels spans
#: 0.5 to 100 kg (a frame that light jumps most); 200 is 30 times the whole machine.
FRAME_MASSES = (0.5, 200.0)


@st.composite
def losses(draw) -> Losses:
    """``[losses]`` with each coefficient 0 or drawn (``LOSS_COEFFICIENTS``), each joint's radius
    drawn, and each static coefficient at or above its kinetic one (``STATIC_COEFFICIENTS``)."""
    values = {}
    for name, (low, high) in LOSS_COEFFICIENTS.items():
        values[name] = 0.0 if draw(st.integers(0, NO_LOSS_ODDS - 1)) == 0 else draw(st.floats(low, high))
        if name in LOSS_RADII:
            radius, low, high = LOSS_RADII[name]
            values[radius] = draw(st.floats(low, high))   # with a zero coefficient: a frictionless bearing
    for name, (kinetic, low, high) in STATIC_COEFFICIENTS.items():
        values[name] = values[kinetic] * draw(st.floats(low, high))
    return Losses(**values)


def bases() -> st.SearchStrategy[Base]:
    """A fixed frame, or a rolling one of a mass drawn log-uniformly over ``FRAME_MASSES``."""
    low, high = FRAME_MASSES
    masses = st.floats(math.log(low), math.log(high)).map(lambda x: min(max(math.exp(x), low), high))
    return st.one_of(st.just(Base()), masses.map(lambda mass: Base("rolling", mass)))


@st.composite
def lossy_designs(draw) -> Design:
    """``paper_designs`` with drawn ``losses`` on a drawn frame (``bases``)."""
    return dataclasses.replace(draw(paper_designs()), losses=draw(losses()), base=draw(bases()))


def examples(suite: int) -> int:
    """How many examples a hypothesis test with its own count draws under the loaded profile
    (``HYPOTHESIS_PROFILE``, ``tests/conftest.py``): ``suite`` under ``quick``, the suite's (each
    such test says why that many cover its property), and as many times more under another
    profile as its ``max_examples`` is to quick's (15 times under ``thorough``)."""
    scale = settings.default.max_examples / settings.get_profile("quick").max_examples
    return max(1, round(suite * scale))


# --------------------------------------------------------------------------- #
# Values of the wrong kind, as a TOML file can hold them
# --------------------------------------------------------------------------- #

#: Each with the reason a number field gives for refusing it (design and problem files alike).
NOT_NUMBERS = {
    "text": ("forty-three", "must be a number"),   # no quantity pint reads (units: test_analytic_units.py)
    "list": ([43.4], "must be a number"),
    "table": ({"value": 43.4}, "must be a number"),
    "bool": (True, "must be a number"),
    "date": (datetime.date(1979, 5, 27), "must be a number"),
    "datetime": (datetime.datetime(1979, 5, 27, 7, 32, tzinfo=datetime.timezone.utc), "must be a number"),
    "nan": (math.nan, "must be finite"),
    "inf": (math.inf, "must be finite"),
    "minus-inf": (-math.inf, "must be finite"),
    "huge": (1e300, "past the float range"),
    "huge-negative": (-1e300, "past the float range"),
    "huge-integer": (10**400, "past the float range"),   # tomllib reads it: beyond any float
}


# --------------------------------------------------------------------------- #
# Limits shared by the optimiser's tests
# --------------------------------------------------------------------------- #

#: The release-angle problem's known answer comes from a cubic spline through
#: swing samples 0.5 ms apart; it moves by 1e-7 m (2e-9 relative) and 4e-5 deg
#: if a 3-point parabola is used instead, so these bound the comparison with
#: room to spare (test_analytic_optimise_known.py).
RANGE_TOLERANCE = 1e-8
ANGLE_TOLERANCE_DEG = 1e-3
#: SLSQP stops once a step gains < ftol = 1e-10 of the (scaled) range; with the
#: release-angle problem's curvature (about 2400 m per unit coordinate squared)
#: that leaves a slope of up to sqrt(2 * 2400 * 6e-9) = 5e-3 m per unit, 1e-4 of
#: the 62 m range.
RESIDUAL_LIMIT = 1e-4
#: Seeds of the paper's problem agree on the range to this (relative): the range
#: carries ~4e-11 relative noise at rtol 1e-10, and SLSQP stops once a step
#: gains < 1e-10 (its ftol).
SEED_RANGE_AGREEMENT = 1e-8
#: ... and on every design variable to 0.01 cm or 0.01 deg, the resolution of the
#: paper's Table III (what a builder could tell apart).
SEED_DESIGN_AGREEMENT = 0.01


# --------------------------------------------------------------------------- #
# The engine's shots as comparable records (test_engine_mechanisms.py)
# --------------------------------------------------------------------------- #

def shot_record(shot) -> dict[str, str]:
    """Every field of an engine ``shot`` (its ``to_json()`` and the whole ``Shot``: history,
    diagnostics), flattened to ``{path: text}``: a number as its ``repr`` (exact, and NaN equal to
    NaN), an array as its dtype, shape and SHA-256 of its bytes. Two shots with equal records hold
    the same doubles everywhere."""
    import hashlib

    record: dict[str, str] = {}

    def add(path: str, value) -> None:
        if dataclasses.is_dataclass(value) and not isinstance(value, type):
            for field in dataclasses.fields(value):
                add(f"{path}.{field.name}", getattr(value, field.name))
        elif isinstance(value, dict):
            for key, item in value.items():
                add(f"{path}[{key!r}]", item)
        elif isinstance(value, (list, tuple)):
            for i, item in enumerate(value):
                add(f"{path}[{i}]", item)
        elif isinstance(value, np.ndarray):
            digest = hashlib.sha256(np.ascontiguousarray(value).tobytes()).hexdigest()
            record[path] = f"{value.dtype}{value.shape} sha256:{digest}"
        else:
            record[path] = repr(value)

    add("json", shot.to_json())
    add("shot", shot)
    return record


def engine_records(names: list[str]) -> dict[str, dict[str, str]]:
    """``shot_record`` of the engine's shot of each named design of the cross-check's default suite."""
    from crosscheck.cases import default_suite
    from engine_model import simulate

    cases = {case.name: case.design for case in default_suite()}
    return {name: shot_record(simulate(cases[name])) for name in names}


def assert_records_equal(actual: np.ndarray, expected: np.ndarray, *, skip: tuple[str, ...] = (), err_msg: str = ""):
    """Two structured arrays (or records) equal field by field, NaN equal to NaN (the compiled path's
    results, ``analytic.fast.kernel.RESULT_DTYPE``): a field named in ``skip`` is not compared."""
    assert actual.dtype == expected.dtype, (actual.dtype, expected.dtype)
    for name in actual.dtype.names:
        if name not in skip:
            np.testing.assert_array_equal(actual[name], expected[name], err_msg=f"{err_msg} {name}")


# --------------------------------------------------------------------------- #
# The fast path's compile progress (test_analytic_fast.py, test_analytic_numba_mechanisms.py)
# --------------------------------------------------------------------------- #

def compile_a_stand_in_entry_point(scope) -> None:
    """Compile, under ``analytic.fast``'s compile progress, a throwaway function named as ``scope``'s
    entry point (``kernel.shots``): the progress a cold compile shows, in milliseconds rather than
    tens of seconds (the caller reads it with ``capsys``)."""
    import numba

    from analytic import fast

    def shots(x):
        return x + 1.0

    shots.__qualname__ = fast.entry_point(scope).py_func.__qualname__
    with fast._compile_progress(True, scope):
        assert numba.njit(shots)(1.0) == 2.0


# --------------------------------------------------------------------------- #
# A sling and a pouch with mass
# --------------------------------------------------------------------------- #

#: The sling's and the pouch's masses of ``sling_designs``, kg: a 61 cm cord sling of about
#: 12 g and a leather pouch of about 6 g, light beside the 45.6 g golf ball, as built.
SLING_MASS, POUCH_MASS = 0.012, 0.006


def sling_designs() -> dict[str, Design]:
    """Table III machines whose sling and pouch have mass (``SLING_MASS``, ``POUCH_MASS``): each kind,
    a rolling frame, friction everywhere, the drag during the swing, and a sling as heavy as the ball."""
    table3 = load_design(DATA / "paper_table3.toml")
    losses = Losses(axle_friction=0.15, axle_radius=0.0064, hinge_friction=0.15, hinge_radius=0.005,
                    base_friction=0.3, base_static_friction=0.4)

    def heavy(design: Design, sling: float = SLING_MASS, pouch: float = POUCH_MASS) -> Design:
        return with_machine(design, sling_mass=sling, pouch_mass=pouch)

    return {"sling-hinged": heavy(table3), "sling-fixed": heavy(bolted(table3)),
            "sling-floating": heavy(load_design(TABLE3_FLOATING_FILE)),
            "sling-rolling": heavy(dataclasses.replace(table3, base=Base("rolling", 5.0))),
            "sling-lossy": heavy(dataclasses.replace(table3, losses=losses)),
            "sling-fixed-lossy-rolling": heavy(dataclasses.replace(bolted(table3), base=Base("rolling", 5.0),
                                                                   losses=Losses(axle_friction=0.15,
                                                                                 axle_radius=0.0064,
                                                                                 base_friction=0.3))),
            "sling-floating-lossy": heavy(dataclasses.replace(load_design(TABLE3_FLOATING_FILE),
                                                              losses=Losses(axle_friction=0.15, axle_radius=0.0064,
                                                                            guide_friction=0.2,
                                                                            track_friction=0.1))),
            "sling-swing-drag": heavy(with_projectile(table3, drag_during_swing=True)),
            "sling-pouch-only": heavy(table3, sling=0.0),
            "sling-as-heavy-as-the-ball": heavy(table3, sling=0.0456, pouch=0.0)}


#: Where the page's test clients say they reached the server: ``workbench.guard`` answers only
#: requests addressed to the loopback address and port they arrived at.
PAGE_URL = "http://127.0.0.1:8765"


def page_client():
    """A Starlette test client of the page's app, addressed as a browser on this machine would."""
    from starlette.testclient import TestClient

    from workbench.app import build_app

    return TestClient(build_app(), base_url=PAGE_URL, raise_server_exceptions=False)


class Stop(Exception):
    """What a caller's ``check`` raises to end a search (the workbench's is ``Cancelled``)."""


def stops_at(calls: int):
    """``(check, seen)``: a check that raises ``Stop`` at its ``calls``-th call, and the list it counts
    its calls in."""
    seen: list[None] = []

    def check() -> None:
        seen.append(None)
        if len(seen) == calls:
            raise Stop

    return check, seen
