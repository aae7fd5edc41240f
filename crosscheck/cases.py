"""The designs the cross-check runs: the paper's, ones that exercise every input, a seeded sample,
machines on wheels, and real machines with friction."""

from __future__ import annotations

import dataclasses
import math
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import analytic
from analytic.design import Base, BeamArm, Design, Losses
from analytic.design_file import default_design, load_design
from analytic.design_space import default_problem, sample_designs
from analytic.reference import simulate
from engine_model.build import SLING_MASS_FRACTION


@dataclass(frozen=True)
class Case:
    """One design to run through both models; ``group`` is paper, exercise, failure, sample, rolling,
    friction, stage-1-events, fixed, floating-arm, floating-friction, swing-drag, ideal-release, trough,
    target, floating-base-friction, sling-mass, as-built or file."""

    name: str
    design: Design
    group: str
    expected: str | None = None  # the status a failure case is known to end in


#: The sample alternates the problem file's arm (the default design's pine beam)
#: with this nearly massless one, a few grams.
LIGHT_ARM = BeamArm(width=0.005, depth=0.005, density=100.0)


def _variant(design: Design, name: str, *, machine=None, projectile=None, environment=None) -> Design:
    return dataclasses.replace(
        design, name=name,
        machine=dataclasses.replace(design.machine, **(machine or {})),
        projectile=dataclasses.replace(design.projectile, **(projectile or {})),
        environment=dataclasses.replace(design.environment, **(environment or {})))


def paper_cases() -> list[Case]:
    """Table III's optimum as published (43.4 deg) and at the prototype's measured 61 deg (section IV)."""
    table3 = default_design()
    return [Case("table3", table3, "paper"),
            Case("table3-61deg", _variant(table3, "table3-61deg", machine={"release_angle": math.radians(61.0)}), "paper")]


def exercise_cases() -> list[Case]:
    """Variants of Table III that each exercise one input (and one of each failure)."""
    t3 = default_design()
    deg = math.radians
    variants = {
        "cw-point-mass": dict(machine={"counterweight_inertia": 0.0}),
        "cw-large-inertia": dict(machine={"counterweight_inertia": 0.08}),
        "sling-rule": dict(machine={"release_rule": "sling", "release_angle": deg(-40.0)}),
        "sling-rule-late": dict(machine={"release_rule": "sling", "release_angle": deg(30.0)}),
        "downward-release": dict(machine={"release_angle": deg(-30.0)}),
        "very-late-release": dict(machine={"release_angle": deg(-75.0)}),
        "steep-release": dict(machine={"release_angle": deg(75.0)}),
        "no-drag": dict(projectile={"drag": "none"}),
        "constant-drag": dict(projectile={"drag": "constant", "drag_coefficient": 0.45}),
        "smooth-sphere": dict(projectile={"drag": "smooth-sphere"}),
        "tailwind": dict(environment={"wind_speed": 5.0}),
        "headwind": dict(environment={"wind_speed": -5.0}),
        "heavy-arm": dict(machine={"arm_mass": 1.2, "arm_inertia": 0.09}),
    }
    return [Case(name, _variant(t3, name, **changes), "exercise") for name, changes in variants.items()]


#: Valid designs known not to throw, one per failure, in the order the suite
#: runs them. Each is a design file, ``fails-<status>.toml``, whose header says
#: how it was found; the tests read the same files.
FAILURE_DESIGN_DIR = Path(analytic.__file__).with_name("data") / "designs"
FAILURE_STATUSES = ("never_fires", "no_landing", "never_lifts_off", "hits_base_before_release", "never_releases",
                    "short_of_target")


def failure_cases() -> list[Case]:
    """One design per named failure, each with the status it is known to end in."""
    cases = []
    for status in FAILURE_STATUSES:
        design = load_design(FAILURE_DESIGN_DIR / f"fails-{status}.toml")
        cases.append(Case(design.name, design, "failure", status))
    return cases


def sample_cases(count: int, seed: int) -> list[Case]:
    """``count`` designs drawn uniformly over the paper's Table II bounds (``analytic.design_space``),
    alternating the wooden and the light arm; kept whether they throw or fail."""
    problem = default_problem()
    designs = sample_designs(problem, count, seed, lambda i: f"sample-{seed}-{i:03d}-{('wooden', 'light')[i % 2]}",
                             arms=(problem.arm, LIGHT_ARM))
    return [Case(design.name, design, "sample") for design in designs]


#: Frame masses the paper's design rolls on, kg: from under a third of its
#: counterweight (6.5 kg), where the frame jumps most, to 15 times the whole
#: moving machine (6.9 kg), where it is nearly a fixed frame.
ROLLING_FRAME_MASSES = (2.0, 5.0, 20.0, 100.0)
#: Frame mass the sampled designs are put on wheels with, kg: about the counterweight's.
ROLLING_SAMPLE_FRAME_MASS = 10.0


def rolling_cases(sample: int = 4, seed: int = 0) -> list[Case]:
    """The paper's design on frames from light to heavy (``ROLLING_FRAME_MASSES``) and the first
    ``sample`` designs of ``sample_cases(sample, seed)`` on a ``ROLLING_SAMPLE_FRAME_MASS`` frame."""
    table3 = default_design()
    designs = [dataclasses.replace(table3, name=f"table3-rolling-{mass:g}kg", base=Base("rolling", mass))
               for mass in ROLLING_FRAME_MASSES]
    designs += [dataclasses.replace(case.design, name=f"{case.name}-rolling",
                                    base=Base("rolling", ROLLING_SAMPLE_FRAME_MASS))
                for case in sample_cases(sample, seed)]
    return [Case(design.name, design, "rolling") for design in designs]


#: Realistic losses: a 12.8 mm steel axle in a greased wooden bearing
#: (Coulomb 0.15), a 10 mm hinge pin (0.15), the projectile's pouch on a wooden base (0.3).
REALISTIC_LOSSES = Losses(axle_friction=0.15, axle_radius=0.0064, hinge_friction=0.15, hinge_radius=0.005,
                          base_friction=0.3)
#: Each loss of ``REALISTIC_LOSSES`` alone, and all of them.
LOSS_VARIANTS = {
    "axle-friction": Losses(axle_friction=0.15, axle_radius=0.0064),
    "hinge-friction": Losses(hinge_friction=0.15, hinge_radius=0.005),
    "base-friction": Losses(base_friction=0.3),
    "all-losses": REALISTIC_LOSSES,
}
#: A machine its axle's friction holds at rest: Table III with a 0.3 kg
#: counterweight that only just outweighs the arm (gravity's torque about the
#: pivot at rest 0.0099 N m) on an axle of coefficient 0.3 (it holds up to
#: 0.3 x 6.4 mm x 5.94 N = 0.0114 N m). At 0.15 it would fire.
HELD_COUNTERWEIGHT_MASS = 0.3
HELD_AXLE = Losses(axle_friction=0.3, axle_radius=0.0064)


#: Static coefficients 1.3 times the kinetic ones of ``REALISTIC_LOSSES`` (dry wood on wood or a
#: plain bearing holds about a third more at rest than it gives sliding).
STATIC_FACTOR = 1.3
REALISTIC_STATIC_LOSSES = dataclasses.replace(
    REALISTIC_LOSSES, **{f"{name}_static_friction": STATIC_FACTOR * getattr(REALISTIC_LOSSES, f"{name}_friction")
                         for name in ("axle", "hinge", "base")})
#: A hinge that sticks at rest and again before release (a 20 cm pin), holding up to 1.3 times what it
#: gives slipping: the static coefficient changes when it breaks free and whether it sticks.
STICKING_STATIC_HINGE = Losses(hinge_friction=1.0, hinge_radius=0.1, hinge_static_friction=1.3)
#: ``HELD_AXLE``'s hold by static friction alone: the kinetic coefficient (0.15) would let it fire.
HELD_STATIC_AXLE = Losses(axle_friction=0.15, axle_radius=0.0064, axle_static_friction=0.3)


def friction_cases(sample: int = 3, seed: int = 0) -> list[Case]:
    """Each loss alone and all together on the paper's design (as published and at 61 deg: all losses),
    all losses on the first ``sample`` designs of ``sample_cases(sample, seed)`` (a light arm among them,
    whose engine arm carries ballast), the paper's point counterweight and its rolling frame with all losses,
    and a machine its axle's friction holds (``never_fires``); with static coefficients above the kinetic
    ones, the paper's design with all losses and with a sticking hinge, the first sampled design with all
    losses, and the held machine held by its static friction alone (``never_fires``)."""
    table3 = default_design()
    cases = [Case(f"table3-{name}", dataclasses.replace(table3, name=f"table3-{name}", losses=losses), "friction")
             for name, losses in LOSS_VARIANTS.items()]
    for case in paper_cases()[1:] + [c for c in exercise_cases() if c.name == "cw-point-mass"]:
        name = f"{case.name}-all-losses"
        cases.append(Case(name, dataclasses.replace(case.design, name=name, losses=REALISTIC_LOSSES), "friction"))
    name = f"table3-rolling-{ROLLING_SAMPLE_FRAME_MASS:g}kg-all-losses"
    cases.append(Case(name, dataclasses.replace(table3, name=name, base=Base("rolling", ROLLING_SAMPLE_FRAME_MASS),
                                                losses=REALISTIC_LOSSES), "friction"))
    for case in sample_cases(sample, seed):
        name = f"{case.name}-all-losses"
        cases.append(Case(name, dataclasses.replace(case.design, name=name, losses=REALISTIC_LOSSES), "friction"))
    held = _variant(table3, "table3-held-by-its-axle", machine={"counterweight_mass": HELD_COUNTERWEIGHT_MASS})
    cases.append(Case(held.name, dataclasses.replace(held, losses=HELD_AXLE), "friction", "never_fires"))
    static = [("table3-all-losses-static", table3, REALISTIC_STATIC_LOSSES),
              ("table3-sticking-hinge-static", table3, STICKING_STATIC_HINGE)]
    static += [(f"{case.name}-all-losses-static", case.design, REALISTIC_STATIC_LOSSES)
               for case in sample_cases(sample, seed)[:1]]
    for name, design, losses in static:
        cases.append(Case(name, dataclasses.replace(design, name=name, losses=losses), "friction"))
    name = "table3-held-by-static-friction"
    cases.append(Case(name, dataclasses.replace(held, name=name, losses=HELD_STATIC_AXLE), "friction", "never_fires"))
    return cases


#: A machine whose arm friction stops before the projectile leaves the base (stage 1's
#: ``arm_stalls``), ``never_lifts_off``: a design drawn over the paper's Table II bounds with a
#: 4.78 kg counterweight and heavy friction (a 36.6 mm axle at 0.48, a 11.9 mm hinge pin at 0.2,
#: the base at 1.09), found by sampling 6,000 such designs with the reference path (76 stalled;
#: numbers rounded). The stall comes 0.46 s after firing. On the paper's own geometry no
#: counterweight from 0.4 to 6.5 kg stalls with axle and base coefficients up to 0.5 and 1.0.
STALLING_MACHINE = dict(pivot_height=0.567, arm_long=0.579, arm_short=0.1354, arm_mass=0.232, arm_cg=0.2217,
                        arm_inertia=0.0099, counterweight_mass=4.78, counterweight_link=0.2456,
                        counterweight_inertia=0.00935, sling_length=0.2915, release_angle=-0.1093)
STALLING_LOSSES = Losses(axle_friction=0.48, axle_radius=0.0366, hinge_friction=0.2, hinge_radius=0.0119,
                         base_friction=1.09)
#: The sling, as a multiple of the long arm, with which the paper's design drags its projectile
#: back and then forward over the base before lift-off (stage 1's ``slide_reverses``). The
#: slide reverses where ``x_P(theta)`` is extreme, ``x_P cos(theta) = h sin(theta)`` with ``x_P``
#: the projectile's distance ahead of the pivot: only a sling long against the arm gets there
#: before the sling stands vertical (none of 400 designs drawn over Table II's bounds does).
REVERSING_SLING = 2.0


def stage1_event_cases() -> list[Case]:
    """Whole shots through stage 1's friction events: the sampled machine whose arm stalls
    (``STALLING_MACHINE``) and the paper's design with all of ``REALISTIC_LOSSES`` on a sling
    ``REVERSING_SLING`` times its long arm, whose slide reverses (it is thrown, 1.9 m)."""
    table3 = default_design()
    stalls = dataclasses.replace(_variant(table3, "sampled-arm-stalls", machine=STALLING_MACHINE),
                                 losses=STALLING_LOSSES)
    name = "table3-long-sling-all-losses"
    reverses = dataclasses.replace(
        _variant(table3, name, machine={"sling_length": REVERSING_SLING * table3.machine.arm_long}),
        losses=REALISTIC_LOSSES)
    return [Case(stalls.name, stalls, "stage-1-events", "never_lifts_off"), Case(name, reverses, "stage-1-events")]


#: The fixed group's sample: the first designs of ``sample_cases(FIXED_SAMPLE, seed)`` with their
#: counterweight bolted (a light arm among them).
FIXED_SAMPLE = 3
#: A large machine (``large_design``): a 3 m pine beam (0.10 m x 0.15 m, 450 kg/m^3: 20.25 kg,
#: its centre 0.75 m toward the long end, I = m L^2 / 12 = 15.19 kg m^2 about it) on an axle
#: 1.8 m over the base, split 3:1 (2.25 m long, 0.75 m short), with a 200 kg counterweight (a
#: cast-iron sphere of 7200 kg/m^3: radius 0.188 m, I = 2/5 m r^2 = 2.83 kg m^2), a 2.0 m
#: sling and a 2 kg stone 0.12 m across.
LARGE_MACHINE = dict(pivot_height=1.8, arm_long=2.25, arm_short=0.75, arm_mass=20.25, arm_cg=0.75,
                     arm_inertia=15.19, counterweight_mass=200.0, counterweight_inertia=2.83,
                     sling_length=2.0, release_angle=math.radians(45.0))
LARGE_PROJECTILE = dict(mass=2.0, diameter=0.12, drag="smooth-sphere")


def fixed_design(design: Design, name: str) -> Design:
    """``design`` with its counterweight bolted to the arm: kind ``"fixed"``, no link."""
    return _variant(design, name, machine={"kind": "fixed", "counterweight_link": 0.0})


def large_design(kind: str) -> Design:
    """``LARGE_MACHINE`` throwing ``LARGE_PROJECTILE``, a ``kind`` machine (``fixed``, ``floating-arm``; for ``hinged``
    the counterweight hangs on a 0.5 m link), as ``large-<kind>``."""
    link = 0.5 if kind == "hinged" else 0.0
    return _variant(default_design(), f"large-{kind}", machine={**LARGE_MACHINE, "kind": kind,
                                                                "counterweight_link": link},
                    projectile=LARGE_PROJECTILE)


#: A counterweight the paper's fixed machine cannot fire with, kg: its weight's torque about the
#: pivot at rest (0.2 kg at 0.2405 m: 0.048 kg m) is less than the arm's (0.306 kg at 0.230 m: 0.070 kg m).
FIXED_UNFIRED_COUNTERWEIGHT = 0.2
#: ``REALISTIC_LOSSES`` that a fixed machine has: it has no hinge.
FIXED_LOSSES = dataclasses.replace(REALISTIC_LOSSES, hinge_friction=0.0, hinge_radius=0.0)


def fixed_cases(sample: int = FIXED_SAMPLE, seed: int = 0) -> list[Case]:
    """The fixed (bolted counterweight) machines: the paper's (``data/paper_table3_fixed.toml``), with
    the axle's and the base's friction (``FIXED_LOSSES``) and on a ``ROLLING_SAMPLE_FRAME_MASS`` frame
    with them, released by the sling rule, the first ``sample`` designs of ``sample_cases(sample, seed)``
    with their counterweight bolted, the large machine (``large_design``), and the paper's on a
    counterweight too light to fire it (``never_fires``)."""
    paper = load_design(Path(analytic.__file__).with_name("data") / "paper_table3_fixed.toml")
    lossy = dataclasses.replace(paper, name=f"{paper.name}-all-losses", losses=FIXED_LOSSES)
    rolling = dataclasses.replace(lossy, name=f"{paper.name}-rolling-{ROLLING_SAMPLE_FRAME_MASS:g}kg-all-losses",
                                  base=Base("rolling", ROLLING_SAMPLE_FRAME_MASS))
    sling_rule = _variant(paper, f"{paper.name}-sling-rule", machine={"release_rule": "sling",
                                                                       "release_angle": math.radians(-40.0)})
    designs = [paper, lossy, rolling, sling_rule]
    designs += [fixed_design(case.design, f"{case.name}-fixed") for case in sample_cases(sample, seed)]
    designs.append(large_design("fixed"))
    unfired = _variant(paper, f"{paper.name}-never-fires", machine={"counterweight_mass": FIXED_UNFIRED_COUNTERWEIGHT})
    return [Case(design.name, design, "fixed") for design in designs] + [
        Case(unfired.name, unfired, "fixed", "never_fires")]


#: The floating-arm group's sample: the first designs of the seeded sample with the problem file's
#: (wooden) arm, their counterweight bolted on a floating arm. Not the light arm's: the engine holds a
#: floating axle on its track through a carriage carrying part of the arm's mass
#: (``engine_model.floating``), and a carriage of a gram or two under a 6.5 kg counterweight leaves
#: pymunk's solver unconverged (the arm's pivot on the carriage misses its target velocity by orders
#: of magnitude more than ``engine_model.diagnostics.RESIDUAL_LIMIT`` on ``sample-0-005-light``, even
#: at a quarter of the default step).
FLOATING_SAMPLE = 3


def floating_design(design: Design, name: str) -> Design:
    """``design`` as a floating arm: kind ``"floating-arm"``, the counterweight bolted (no link)."""
    return _variant(design, name, machine={"kind": "floating-arm", "counterweight_link": 0.0})


def floating_cases(sample: int = FLOATING_SAMPLE, seed: int = 0) -> list[Case]:
    """The floating-arm machines: the paper's (Table III's numbers, the counterweight bolted at the short
    end on its guide), the first ``sample`` wooden-armed designs of the seeded sample as floating arms
    (``FLOATING_SAMPLE``),
    and the large machine (``large_design``: a 3 m arm, 200 kg)."""
    designs = [floating_design(default_design(), "table3-floating-arm")]
    wooden = [case for case in sample_cases(2 * sample, seed) if "light" not in case.name][:sample]
    designs += [floating_design(case.design, f"{case.name}-floating-arm") for case in wooden]
    designs.append(large_design("floating-arm"))
    return [Case(design.name, design, "floating-arm") for design in designs]


#: A floating arm's slides with friction: the counterweight's guide and the axle's carriage on its
#: track, greased hardwood on hardwood (Coulomb 0.2); with the axle's of ``REALISTIC_LOSSES``, every
#: loss of its supports (the base's is ``floating_base_friction_cases``').
SLIDE_LOSSES = Losses(guide_friction=0.2, track_friction=0.2)
FLOATING_LOSSES = dataclasses.replace(SLIDE_LOSSES, axle_friction=REALISTIC_LOSSES.axle_friction,
                                      axle_radius=REALISTIC_LOSSES.axle_radius)
#: ``FLOATING_LOSSES`` with every static coefficient ``STATIC_FACTOR`` times its kinetic one.
FLOATING_STATIC_LOSSES = dataclasses.replace(
    FLOATING_LOSSES, **{f"{name}_static_friction": STATIC_FACTOR * getattr(FLOATING_LOSSES, f"{name}_friction")
                        for name in ("axle", "guide", "track")})
#: A track the paper's floating arm cannot move on: its friction holds the machine at rest from
#: 0.570 (at rest the guide must push 38.0 N to hold the arm against its 66.8 N weight on the track:
#: ``tests/test_engine_guide_track_friction.py``'s ``track_threshold``); 0.8 holds it.
HELD_TRACK = Losses(track_friction=0.8)


def floating_friction_cases(seed: int = 0) -> list[Case]:
    """Floating arms with friction on their guide and track: the paper's floating arm with the guide's
    alone, the track's alone, both, and ``FLOATING_LOSSES`` (the axle's too), with those
    at static coefficients ``STATIC_FACTOR`` above the kinetic ones, the first sampled floating arm and
    the large one with ``FLOATING_LOSSES``, and the paper's held at rest by its track (``never_fires``)."""
    paper = floating_cases(sample=1, seed=seed)
    table3, sampled, large = (case.design for case in paper)
    variants = [(table3, "guide-friction", Losses(guide_friction=SLIDE_LOSSES.guide_friction)),
                (table3, "track-friction", Losses(track_friction=SLIDE_LOSSES.track_friction)),
                (table3, "slide-friction", SLIDE_LOSSES), (table3, "all-losses", FLOATING_LOSSES),
                (table3, "all-losses-static", FLOATING_STATIC_LOSSES),
                (sampled, "all-losses", FLOATING_LOSSES), (large, "all-losses", FLOATING_LOSSES)]
    cases = [Case(f"{design.name}-{suffix}", dataclasses.replace(design, name=f"{design.name}-{suffix}",
                                                                 losses=losses), "floating-friction")
             for design, suffix, losses in variants]
    held = dataclasses.replace(table3, name=f"{table3.name}-held-by-its-track", losses=HELD_TRACK)
    return cases + [Case(held.name, held, "floating-friction", "never_fires")]


#: A floating arm's projectile on the base with ``REALISTIC_LOSSES``' base friction, and with every loss
#: of its supports (``FLOATING_LOSSES``), kinetic, and static ``STATIC_FACTOR`` times above.
FLOATING_BASE_LOSSES = dataclasses.replace(FLOATING_LOSSES, base_friction=REALISTIC_LOSSES.base_friction)
FLOATING_BASE_STATIC_LOSSES = dataclasses.replace(
    FLOATING_STATIC_LOSSES, base_friction=REALISTIC_LOSSES.base_friction,
    base_static_friction=STATIC_FACTOR * REALISTIC_LOSSES.base_friction)
#: A base that holds the paper's floating arm throwing a 1.5 kg stone through the flat sling: static
#: friction holds 11.8 N m against gravity's 7.8 N m at rest, the kinetic coefficient alone 5.9 N m
#: (``analytic.friction.rest_balance``, ``tests/test_crosscheck_floating_base_friction.py``).
HELD_BASE = Losses(base_friction=0.5, base_static_friction=1.0)
HELD_BASE_STONE = 1.5


def floating_base_friction_cases(seed: int = 0) -> list[Case]:
    """Floating arms with the base's friction on their projectile: the paper's floating arm with the
    base's alone, with its slides', with every loss (``FLOATING_BASE_LOSSES``) and with those static
    (``FLOATING_BASE_STATIC_LOSSES``), the first sampled floating arm with every loss, and the paper's
    throwing a stone its base holds at rest (``HELD_BASE``: it sticks, and never fires)."""
    table3, sampled, _ = (case.design for case in floating_cases(sample=1, seed=seed))
    base = Losses(base_friction=REALISTIC_LOSSES.base_friction)
    slides = dataclasses.replace(SLIDE_LOSSES, base_friction=base.base_friction)
    variants = [(table3, "base-friction", base), (table3, "base-and-slide-friction", slides),
                (table3, "every-loss", FLOATING_BASE_LOSSES),
                (table3, "every-loss-static", FLOATING_BASE_STATIC_LOSSES), (sampled, "every-loss", FLOATING_BASE_LOSSES)]
    cases = [Case(f"{design.name}-{suffix}", dataclasses.replace(design, name=f"{design.name}-{suffix}",
                                                                 losses=losses), "floating-base-friction")
             for design, suffix, losses in variants]
    held = _variant(table3, f"{table3.name}-held-by-its-base", projectile={"mass": HELD_BASE_STONE})
    held = dataclasses.replace(held, losses=HELD_BASE)
    return cases + [Case(held.name, held, "floating-base-friction", "never_fires")]


#: The wind of the drag-during-swing cases with wind, m/s: a strong headwind and a strong
#: tailwind (Beaufort 6, 10.8-13.8 m/s), so the drag at rest and slow in stage 1 is not negligible.
SWING_DRAG_WIND = 12.0


def swing_drag_cases() -> list[Case]:
    """The drag acting in stages 1-2 too (``projectile.drag_during_swing``): the paper's golf ball as
    published and at 61 deg, into a headwind and with a tailwind, with every loss, on the bolted
    machine, the large machine's dense ball, and the floating arm into the headwind with every loss it
    has (its axle's motion in the projectile's velocity, the drag in its guide's and track's normal
    forces)."""
    t3 = default_design()
    on = {"drag_during_swing": True}
    designs = [
        _variant(t3, "table3-swing-drag", projectile=on),
        _variant(t3, "table3-61deg-swing-drag", machine={"release_angle": math.radians(61.0)}, projectile=on),
        _variant(t3, "swing-drag-headwind", projectile=on, environment={"wind_speed": -SWING_DRAG_WIND}),
        _variant(t3, "swing-drag-tailwind", projectile=on, environment={"wind_speed": SWING_DRAG_WIND}),
        dataclasses.replace(_variant(t3, "swing-drag-all-losses", projectile=on), losses=REALISTIC_LOSSES),
        _variant(fixed_design(t3, "fixed-swing-drag"), "fixed-swing-drag", projectile=on),
        _variant(large_design("hinged"), "large-swing-drag", projectile=on),
        dataclasses.replace(_variant(floating_design(t3, "floating-swing-drag"), "floating-swing-drag-headwind",
                                     projectile=on, environment={"wind_speed": -SWING_DRAG_WIND}),
                            losses=FLOATING_LOSSES),
    ]
    return [Case(design.name, design, "swing-drag") for design in designs]


#: The wind of the ideal-release cases with wind, m/s: a fresh tailwind (Beaufort 5).
IDEAL_RELEASE_WIND = 8.0


def ideal(design: Design, name: str) -> Design:
    """``design`` released by the ideal rule (no release angle), named ``name``."""
    return _variant(design, name, machine={"release_rule": "ideal", "release_angle": None})


def ideal_release_cases() -> list[Case]:
    """The ideal release (``machine.release_rule = "ideal"``) on each kind: the paper's machine in
    vacuum, with its golf ball's drag, and into a tailwind; the bolted machine and the floating arm
    with the drag."""
    t3 = default_design()
    vacuum = {"drag": "none"}
    designs = [
        ideal(_variant(t3, "", projectile=vacuum), "ideal-vacuum"),
        ideal(t3, "ideal-drag"),
        ideal(_variant(t3, "", environment={"wind_speed": IDEAL_RELEASE_WIND}), "ideal-tailwind"),
        ideal(fixed_design(t3, ""), "ideal-fixed"),
        ideal(_variant(fixed_design(t3, ""), "", projectile=vacuum), "ideal-fixed-vacuum"),
        ideal(floating_design(t3, ""), "ideal-floating"),
        ideal(_variant(floating_design(t3, ""), "", projectile=vacuum), "ideal-floating-vacuum"),
    ]
    return [Case(design.name, design, "ideal-release") for design in designs]


#: The raised trough of the trough group, as a fraction of the pivot's height over the base: on the
#: paper's machine (0.594 m) a trough 0.208 m up, its long arm resting 25 deg below the horizontal
#: instead of 38.
TROUGH_FRACTION = 0.35


def on_trough(design: Design, name: str, **base) -> Design:
    """``design`` (as ``name``) with its projectile on a trough ``TROUGH_FRACTION`` of its pivot height up,
    on a base with ``base``'s other fields (a rolling frame's ``mobility`` and ``mass``)."""
    trough = round(TROUGH_FRACTION * design.machine.pivot_height, 3)   # to the millimetre
    return dataclasses.replace(design, name=name, base=Base(**base, trough_height=trough))


def trough_cases() -> list[Case]:
    """The projectile on a raised trough (``base.trough_height``), each kind: the paper's hinged machine,
    its fixed one (``data/paper_table3_fixed.toml``) and its floating arm, each ideal and with every loss
    it has (the base's friction acting on the trough: ``REALISTIC_LOSSES``, ``FIXED_LOSSES``; the floating
    arm's ``FLOATING_LOSSES``), the hinged and the fixed one with them on a ``ROLLING_SAMPLE_FRAME_MASS``
    frame too (the trough on the frame), and the large machine of each kind (``large_design``)."""
    fixed = load_design(Path(analytic.__file__).with_name("data") / "paper_table3_fixed.toml")
    rolling = dict(mobility="rolling", mass=ROLLING_SAMPLE_FRAME_MASS)
    designs = []
    for design, losses in ((default_design(), REALISTIC_LOSSES), (fixed, FIXED_LOSSES),
                           (floating_design(default_design(), "table3-floating-arm"), FLOATING_LOSSES)):
        designs.append(on_trough(design, f"{design.name}-trough"))
        lossy = dataclasses.replace(design, losses=losses)
        designs.append(on_trough(lossy, f"{design.name}-trough-all-losses"))
        if design.machine.kind != "floating-arm":   # its axle already rides a track: it does not roll
            designs.append(on_trough(lossy, f"{design.name}-trough-rolling-{ROLLING_SAMPLE_FRAME_MASS:g}kg-all-losses",
                                     **rolling))
    designs += [on_trough(large_design(kind), f"large-{kind}-trough") for kind in ("hinged", "fixed", "floating-arm")]
    return [Case(design.name, design, "trough") for design in designs]


#: The target group's levels above the base, m (``environment.target_height``): a raised target the
#: paper's machines reach (their apexes are 13.8 m, the floating arm's 10.1 m), a pit, and a target
#: above every apex (``short_of_target``).
RAISED_TARGET, PIT_TARGET, OUT_OF_REACH_TARGET = 3.0, -5.0, 40.0
#: The downward release's target levels, m: below its release (1.79 m above the base, falling at
#: 13 m/s: it lands on the way down without rising) and above it (short at release).
BELOW_RELEASE_TARGET, ABOVE_RELEASE_TARGET = 1.0, 2.5


def target_cases() -> list[Case]:
    """The target above and below the base (``environment.target_height``) on each kind: the paper's
    hinged, fixed and floating-arm machines at ``RAISED_TARGET``, over a ``PIT_TARGET`` and short of an
    ``OUT_OF_REACH_TARGET`` (``short_of_target``); and the paper's design released 30 deg downward,
    which never rises: onto a target below its release and short of one above it."""
    table3 = default_design()
    fixed = load_design(Path(analytic.__file__).with_name("data") / "paper_table3_fixed.toml")
    machines = (table3, fixed, floating_design(table3, "table3-floating-arm"))
    cases = []
    for machine in machines:
        for suffix, height, expected in (("raised-target", RAISED_TARGET, None), ("pit", PIT_TARGET, None),
                                         ("short-of-target", OUT_OF_REACH_TARGET, "short_of_target")):
            name = f"{machine.name}-{suffix}"
            cases.append(Case(name, _variant(machine, name, environment={"target_height": height}), "target",
                              expected))
    downward = {"release_angle": math.radians(-30.0)}
    for suffix, height, expected in (("onto-lower-target", BELOW_RELEASE_TARGET, None),
                                     ("short-of-target", ABOVE_RELEASE_TARGET, "short_of_target")):
        name = f"downward-release-{suffix}"
        cases.append(Case(name, _variant(table3, name, machine=downward, environment={"target_height": height}),
                          "target", expected))
    return cases


#: A sling with mass and a pouch on the paper's machine, kg: a cord sling of 10 g and a leather pouch
#: of 10 g, a fifth and a quarter of its 45.6 g golf ball.
SLING_MASS = 0.01
POUCH_MASS = 0.01


def sling_mass_cases() -> list[Case]:
    """A sling with mass (``SLING_MASS``), a pouch (``POUCH_MASS``) and both, on the paper's machine of each
    kind (hinged, fixed, floating arm); with both, every loss each kind has (``REALISTIC_LOSSES``,
    ``FIXED_LOSSES``, ``FLOATING_LOSSES``), the drag during the swing, and a rolling frame."""
    t3 = default_design()
    kinds = {"table3": t3, "table3-fixed": fixed_design(t3, "table3-fixed"),
             "table3-floating-arm": floating_design(t3, "table3-floating-arm")}
    losses = [REALISTIC_LOSSES, FIXED_LOSSES, FLOATING_LOSSES]
    weights = {"sling-mass": {"sling_mass": SLING_MASS}, "pouch": {"pouch_mass": POUCH_MASS},
               "sling-and-pouch": {"sling_mass": SLING_MASS, "pouch_mass": POUCH_MASS}}
    designs = [_variant(design, f"{kind}-{suffix}", machine=masses)
               for kind, design in kinds.items() for suffix, masses in weights.items()]
    both = weights["sling-and-pouch"]
    designs += [dataclasses.replace(_variant(design, f"{kind}-sling-and-pouch-all-losses", machine=both),
                                    losses=lossy) for (kind, design), lossy in zip(kinds.items(), losses, strict=True)]
    designs.append(_variant(t3, "table3-sling-and-pouch-swing-drag", machine=both,
                            projectile={"drag_during_swing": True}))
    name = f"table3-sling-and-pouch-rolling-{ROLLING_SAMPLE_FRAME_MASS:g}kg"
    designs.append(dataclasses.replace(_variant(t3, name, machine=both), base=Base("rolling", ROLLING_SAMPLE_FRAME_MASS)))
    return [Case(design.name, design, "sling-mass") for design in designs]


#: The as-built draw (``as_built_cases``): the sling's and the pouch's mass each up to this fraction
#: of the projectile's (a sling with mass at least the engine's ``SLING_MASS_FRACTION`` of what it
#: carries, below which its solver does not converge), a trough up to this fraction of the pivot's height.
AS_BUILT_MASS_FRACTION = 0.3
AS_BUILT_TROUGH_FRACTION = 0.6
#: How often a part of the as-built draw is left off (a massless sling, no pouch, no trough, the target at
#: the base's level), how often the design is released by the ideal rule, and how often it has every loss
#: its kind has (``REALISTIC_LOSSES``, ``FIXED_LOSSES``, ``FLOATING_BASE_LOSSES``: the floating arm's base
#: friction among them).
AS_BUILT_NONE_CHANCE = 0.25
AS_BUILT_IDEAL_CHANCE = 0.25
AS_BUILT_LOSSES_CHANCE = 0.5
#: The target's level, as a fraction of the apex of the design's shot at the base's level: from a pit
#: this deep to near the apex; ``AS_BUILT_ABOVE_CHANCE`` of the targets lie above the apex instead, by
#: up to ``AS_BUILT_ABOVE`` of it (those not under the ideal rule, whose release does not depend on the
#: target, are ``short_of_target``).
AS_BUILT_PIT, AS_BUILT_NEAR_APEX = -0.5, 0.95
AS_BUILT_ABOVE_CHANCE, AS_BUILT_ABOVE = 0.15, 0.5
#: The stream the as-built parts are drawn from, beside ``sample_cases``' (whose draws it leaves alone).
AS_BUILT_STREAM = 1
#: The kinds in turn: the wooden-armed designs of the sample are each kind, the light-armed ones hinged
#: or fixed (a floating arm's carriage of a gram or two leaves the engine unconverged:
#: ``FLOATING_SAMPLE``).
AS_BUILT_KINDS = {"wooden": ("hinged", "fixed", "floating-arm"), "light": ("hinged", "fixed")}
_AS_BUILT_LOSSES = {"hinged": REALISTIC_LOSSES, "fixed": FIXED_LOSSES, "floating-arm": FLOATING_BASE_LOSSES}


def as_built_cases(count: int, seed: int) -> list[Case]:
    """``count`` machines as built, drawn at random: the designs of ``sample_cases(count, seed)`` (the same
    geometry and arm), each of a kind in turn (``AS_BUILT_KINDS``), with a sling and a pouch of mass, a
    raised trough and a target's level drawn from their own stream (``AS_BUILT_*``), sometimes released by
    the ideal rule and sometimes with every loss of their kind.

    The target's level is a fraction of the apex of the design's shot at the base's level, released at the
    sample's angle even where the ideal rule releases it (the reference path's summary: the ideal rule's
    search costs seconds there; of the pivot's height where it does not throw). Seeded like the sample: the
    first k of any count are the same, and the sample's own draws are unchanged.
    """
    rng = np.random.default_rng([seed, AS_BUILT_STREAM])
    draws = rng.uniform(0.0, 1.0, size=(count, 10)).tolist()   # floats, not numpy's
    cases, kinds = [], {arm: 0 for arm in AS_BUILT_KINDS}
    for case, u in zip(sample_cases(count, seed), draws, strict=True):
        arm = case.name.rsplit("-", 1)[1]
        kind = AS_BUILT_KINDS[arm][kinds[arm] % len(AS_BUILT_KINDS[arm])]
        kinds[arm] += 1
        design = {"hinged": case.design, "fixed": fixed_design(case.design, ""),
                  "floating-arm": floating_design(case.design, "")}[kind]

        def part(none: float, value: float) -> float:
            return 0.0 if none < AS_BUILT_NONE_CHANCE else value

        m, most = design.machine, AS_BUILT_MASS_FRACTION * design.projectile.mass
        pouch = part(u[2], u[3] * most)
        lightest = SLING_MASS_FRACTION * (design.projectile.mass + pouch)   # the engine's lightest sling
        masses = {"sling_mass": part(u[0], lightest + u[1] * (most - lightest)), "pouch_mass": pouch}
        ideal_rule = u[6] < AS_BUILT_IDEAL_CHANCE
        lossy = u[7] < AS_BUILT_LOSSES_CHANCE
        name = (case.name.replace("sample-", "as-built-", 1) + f"-{kind}" + ("-ideal" if ideal_rule else "")
                + ("-all-losses" if lossy else ""))
        design = dataclasses.replace(
            _variant(design, name, machine=masses),
            base=dataclasses.replace(design.base, trough_height=part(u[4], u[5] * AS_BUILT_TROUGH_FRACTION
                                                                    * m.pivot_height)),
            losses=_AS_BUILT_LOSSES[kind] if lossy else design.losses)
        shot = simulate(design, histories=False, loads=False)
        if ideal_rule:
            design = ideal(design, name)
        scale = shot.apex_height if shot.ok else m.pivot_height
        above = u[8] >= 1.0 - AS_BUILT_ABOVE_CHANCE
        fraction = (1.0 + u[9] * AS_BUILT_ABOVE if above
                    else part(u[8], AS_BUILT_PIT + u[9] * (AS_BUILT_NEAR_APEX - AS_BUILT_PIT)))
        design = _variant(design, name, environment={"target_height": float(fraction * scale)})
        expected = "short_of_target" if above and shot.ok and not ideal_rule else None
        cases.append(Case(name, design, "as-built", expected))
    return cases


def file_cases(paths: list[str]) -> list[Case]:
    """Designs from the user's TOML files, each named by its own name, or by its file (the stem) where
    that name is the built-in default's or more than one file's: twelve files made from the default
    design are twelve rows a reader tells apart."""
    designs = [load_design(path) for path in paths]
    names = Counter(design.name for design in designs)
    default_name = default_design().name
    return [Case(Path(path).stem if design.name == default_name or names[design.name] > 1 else design.name,
                 design, "file")
            for path, design in zip(paths, designs, strict=True)]


def default_suite(sample: int = 24, seed: int = 0) -> list[Case]:
    """The suite ``python -m crosscheck`` runs with no design files."""
    return (paper_cases() + exercise_cases() + failure_cases() + sample_cases(sample, seed) + rolling_cases()
            + friction_cases() + stage1_event_cases() + fixed_cases(seed=seed) + floating_cases(seed=seed)
            + floating_friction_cases(seed=seed) + swing_drag_cases() + ideal_release_cases() + sling_mass_cases()
            + trough_cases() + target_cases() + floating_base_friction_cases(seed=seed))


#: The quick suite's cases, by name: the paper's design as published, at 61 deg
#: and with every loss, and one known failure. No rolling frame: its engine
#: steps the machine on through the whole flight (4-5 s a design, where these
#: take 0.5-1 s); the default suite has nine.
QUICK_CASES = ("table3", "table3-61deg", "table3-all-losses", "fails-no_landing")


def quick_suite() -> list[Case]:
    """The few designs ``make run`` checks in seconds (``QUICK_CASES``), no sampled one."""
    cases = {case.name: case for case in paper_cases() + failure_cases() + friction_cases(sample=0)}
    return [cases[name] for name in QUICK_CASES]

