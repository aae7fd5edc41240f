"""The paper's printed equations (8)-(43), checked: which are right, which are wrong, and the corrections.

These tests check the paper, not the code: they carry the ``paper`` mark
(``-m "not paper"`` leaves them out). Every equation the paper prints for
stage 1 (eqs. 8-13, 17-21), stage 2 (22-32), the release velocity (34-35) and
the flight (42-43) is transcribed as printed in ``tests/paper_equations.py``
and evaluated here at random states against the sympy Lagrangian of
``tests/sympy_model.py`` (the reference ``analytic.eom`` is held to in
``test_analytic_symbolic.py``). A printed equation that is right gets a test
that it agrees; one that is wrong gets a test that the printed form disagrees
and a test that the corrected form (written out below, next to its test)
agrees. Nothing of ``analytic`` is evaluated, so no change to the simulator can
make one fail: only a change to the transcription or to the reference can.

They are kept because the model departs from the printed paper wherever the
paper is wrong (``docs/derivation.md`` section 7 lists where and cites these
tests), and a reader comparing the code with the paper needs the proof that
the departure is the paper's error, not the code's.

Findings (equation numbers of Corie, Park & Standring, "Here Comes Trebuchet",
section II):

======  =====================================================================
eq.     verdict
======  =====================================================================
8-13    right (reading LAI as L_Al); 12 checked term by term, it is right
17, 18  right (Cramer's rule on eq. 7)
19      WRONG: the fraction bar of the second term spans ``cot(Aq+Sq) + LAI cos(Aq)``
        (a number plus a length); it must be
        ``(cot(Aq+Sq) + LAI cos(Aq) / (LS sin(Aq+Sq))) Aw^2`` as in eqs. 12, 21
20      WRONG: ``F_y < 0`` is false at the start (F_y = mP g > 0), so stage 1 would
        end at t = 0; stage 1 continues while ``F_y > 0`` (lift-off when F_y falls to 0)
21      WRONG: the bracket is multiplied by ``sin(Aq+Sq)``; it must be divided by it:
        printed F_y - mP g = sin^2(Aq+Sq) (N - mP g). Right only with the sling
        flat (sin(Aq+Sq) = -1), as at the start, so it errs as the sling rises
22      right (M23 = M32 = 0)
23-27   right
28      right up to typography: ``Ls`` is ``LS`` and ``LA1`` is ``LAl``
29, 30  right (``SIN`` read as sin)
31      WRONG three times: stray ``L`` for ``LW``; ``sin(Aq) + Wq`` for
        ``sin(Aq + Wq)``; the parenthesis closes too early, leaving
        ``LAs sin(Wq) Aw^2`` outside ``-LW mW (...)``. Correct: eq. 13,
        ``-LW mW (Grav sin(Aq+Wq) + LAs sin(Wq) Aw^2)``
32      right
34, 35  right
42, 43  right (quadratic drag on the wind-relative velocity)
======  =====================================================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest
import sympy as sp

import paper_equations as paper
from analytic.design_file import default_design
from analytic.parameters import Params
from paper_equations import PaperParams

pytestmark = pytest.mark.paper

#: Agreement asked of a right equation, relative to the natural size of the
#: quantity (largest matrix entry, force or acceleration scale): the paper's
#: algebra and the reference are the same function arranged differently, so
#: they differ by round-off (~1e-14); 1e-10 leaves margin for the 1/sin(Aq+Sq)
#: factors (|sin(Aq+Sq)| >= 0.2 in the samples).
AGREE_REL = 1e-10
#: A printed equation counts as wrong only if it misses by more than this
#: (relative, as above) at every sample: far above round-off, so a
#: disagreement cannot be numerical noise.
DISAGREE_REL = 1e-3

#: Seed of the random samples (fixed so a failure reproduces).
SEED = 1_854
#: Random samples per stage (plus the Table III machine).
N_SAMPLES = 8
#: Smallest |sin(Aq + Sq)| of a stage-1 sample: stage 1 in the paper divides by it.
MIN_SIN_BETA = 0.2
#: Smallest |cos(Aq + Sq)| of a sample used to show that eqs. (19) and (21) as
#: printed are wrong (both are right with the sling flat, cos(Aq + Sq) = 0, and
#: their error grows with |cos(Aq + Sq)|; 0.2 keeps it well above DISAGREE_REL).
MIN_COS_BETA = 0.2


def _table3() -> tuple[PaperParams, float]:
    """The default design in the paper's symbols, and its pivot height: Table III's lengths, the
    6.5 kg counterweight and 45.6 g ball (section III), g = 9.81 m/s^2 (Definitions), and the
    arm and counterweight assumed in analytic/data/paper_table3.toml (the paper gives neither)."""
    design = default_design()
    m = design.machine
    return PaperParams(LAl=m.arm_long, LAs=m.arm_short, LAcg=m.arm_cg, LS=m.sling_length,
                       LW=m.counterweight_link, mA=m.arm_mass, mW=m.counterweight_mass,
                       mP=design.projectile.mass, IA3=m.arm_inertia, IW3=m.counterweight_inertia,
                       Grav=design.environment.gravity), m.pivot_height


TABLE3, TABLE3_PIVOT_HEIGHT = _table3()


# --------------------------------------------------------------------------- #
# The reference, in the paper's symbols
# --------------------------------------------------------------------------- #

def in_model_symbols(P: PaperParams, h: float) -> Params:
    """The paper's machine as the sympy model reads it (a fixed frame; the numbers the
    equations of motion do not read stay NaN)."""
    rest = dict.fromkeys(Params._fields, math.nan)
    rest.update(La=P.LAl, Lb=P.LAs, d=P.LAcg, mA=P.mA, IA=P.IA3, mW=P.mW, Lw=P.LW, IW=P.IW3, Ls=P.LS,
                mP=P.mP, h=h, g=P.Grav, rolling=0.0, Mf=0.0, mS=0.0, mQ=0.0)   # the paper's sling is massless
    return Params(**rest)


def swing_truth(lagrangian, q, qd, P: PaperParams) -> dict:
    """Stage 2 at (q, q'): M (3, 3), f (3,), projectile velocity (2,) (the pivot height is not read)."""
    p = in_model_symbols(P, math.nan)
    return {"M": lagrangian.mass(p, q, qd)[:3, :3], "f": lagrangian.forcing(p, q, qd)[:3],
            "v": lagrangian.projectile(p, q, qd)[1]}


def slide_truth(lagrangian, theta, phi, dtheta, dphi, P: PaperParams, h: float, solve: bool = True) -> dict:
    """Stage 1 at (theta, phi, theta', phi') on the base y_P = -h (branch sin(theta+psi) < 0): the
    reduction that the paper's eq. (7) writes out, ``M_r`` (key ``m_r``) and ``r``, and with
    ``solve`` q'' and N (key ``normal``) from the 3-DOF system with the base's push as the
    constraint's multiplier (``sympy_model.Machine.base_reduction``)."""
    return lagrangian.base_reduction(in_model_symbols(P, h), theta, phi, dtheta, dphi, solve=solve)


# --------------------------------------------------------------------------- #
# Samples: random machines and states, plus Table III
# --------------------------------------------------------------------------- #

@dataclass(frozen=True)
class Sample:
    """One machine and state in the paper's symbols, with the reference values there."""

    P: PaperParams
    h: float
    q: tuple[float, float, float]    # Aq, Wq, Sq
    qd: tuple[float, float, float]   # Aw, Ww, Sw
    truth: dict

    @property
    def angles(self):
        return self.q

    @property
    def state(self):
        return (*self.q, *self.qd)


def random_machine(rng: np.random.Generator) -> tuple[PaperParams, float]:
    LAl = rng.uniform(0.8, 4.0)
    LAs = LAl * rng.uniform(0.15, 0.5)
    h = LAl * rng.uniform(0.4, 0.9)
    mA = math.exp(rng.uniform(math.log(0.3), math.log(50.0)))
    mW = math.exp(rng.uniform(math.log(5.0), math.log(2000.0)))
    return PaperParams(LAl=LAl, LAs=LAs, LAcg=rng.uniform(-LAs, LAl), LS=LAl * rng.uniform(0.5, 1.3),
                       LW=h * rng.uniform(0.2, 0.8), mA=mA, mW=mW,
                       mP=math.exp(rng.uniform(math.log(0.04), math.log(20.0))),
                       IA3=mA * (LAl + LAs) ** 2 / 12.0 * rng.uniform(0.5, 1.5),
                       IW3=mW * rng.uniform(0.0, 0.05), Grav=rng.uniform(1.0, 25.0)), h


def machines(rng):
    yield TABLE3, TABLE3_PIVOT_HEIGHT
    while True:
        yield random_machine(rng)


@pytest.fixture(scope="module")
def swing_samples(lagrangian) -> list[Sample]:
    rng = np.random.default_rng(SEED)
    out = []
    for P, h in machines(rng):
        q, qd = tuple(rng.uniform(-math.pi, math.pi, 3)), tuple(rng.normal(0.0, 4.0, 3))
        out.append(Sample(P, h, q, qd, swing_truth(lagrangian, q, qd, P)))
        if len(out) == N_SAMPLES + 1:
            return out


@pytest.fixture(scope="module")
def slide_samples(lagrangian) -> list[Sample]:
    """Projectile on the base; includes states where N < 0 (it should have lifted off)."""
    rng = np.random.default_rng(SEED + 1)
    out = []
    for P, h in machines(rng):
        while True:
            beta = rng.uniform(-math.pi, 0.0)
            cos_theta = (-h - P.LS * math.cos(beta)) / P.LAl
            if abs(math.sin(beta)) > MIN_SIN_BETA and abs(cos_theta) < 0.98:
                break
        theta = math.acos(cos_theta)
        phi, dtheta, dphi = rng.uniform(-math.pi, math.pi), *rng.normal(0.0, 3.0, 2)
        truth = slide_truth(lagrangian, theta, phi, dtheta, dphi, P, h)
        out.append(Sample(P, h, tuple(truth["q"]), tuple(truth["qd"]), truth))
        if len(out) == N_SAMPLES + 1:
            return out


def relative_errors(samples, evaluate):
    """[(|value - truth| / scale)] over the samples; ``evaluate(sample) -> (value, truth, scale)``."""
    errors = []
    for sample in samples:
        value, truth, scale = evaluate(sample)
        errors.append(abs(value - truth) / scale)
    return np.array(errors)


def assert_agrees(samples, evaluate, what):
    errors = relative_errors(samples, evaluate)
    worst = int(np.argmax(errors))
    value, truth, scale = evaluate(samples[worst])
    assert errors[worst] <= AGREE_REL, (
        f"{what}: paper {value!r} vs reference {truth!r} at sample {worst} "
        f"(relative error {errors[worst]:.3g} > {AGREE_REL:g}, scale {scale:.3g})")


def assert_disagrees(samples, evaluate, what):
    errors = relative_errors(samples, evaluate)
    best = int(np.argmin(errors))
    value, truth, scale = evaluate(samples[best])
    assert errors[best] > DISAGREE_REL, (
        f"{what} as printed matches the reference at sample {best}: paper {value!r} vs "
        f"reference {truth!r} (relative error {errors[best]:.3g} <= {DISAGREE_REL:g})")


# Natural scales: the largest entry of the matrix; the largest entry of the
# forcing, but at least the machine's weight times its size (so a forcing that
# happens to be small is not compared relative to almost nothing).

def m_scale(m) -> float:
    return float(np.max(np.abs(m)))


def r_scale(s: Sample, r) -> float:
    P = s.P
    return max(float(np.max(np.abs(r))), (P.mP + P.mW + P.mA) * P.Grav * (P.LAl + P.LS + P.LAs + P.LW))


def accel_scale(s: Sample) -> float:
    return max(1.0, float(np.max(np.square(s.qd))), float(np.max(np.abs(s.truth["qdd"]))))


# --------------------------------------------------------------------------- #
# Stage 1 (eqs. 7-21)
# --------------------------------------------------------------------------- #

SLIDE_MATRIX = {  # equation -> (printed function, (row, col) of M_r)
    "eq08_M11": (paper.eq08_M11, (0, 0)),
    "eq09_M12": (paper.eq09_M12, (0, 1)),
    "eq10_M21": (paper.eq10_M21, (1, 0)),
    "eq11_M22": (paper.eq11_M22, (1, 1)),
}


@pytest.mark.parametrize("equation", SLIDE_MATRIX, ids=list(SLIDE_MATRIX))
def test_stage1_mass_matrix_as_printed_agrees(slide_samples, equation):
    printed, (i, j) = SLIDE_MATRIX[equation]
    assert_agrees(slide_samples,
                  lambda s: (printed(*s.angles, s.P), s.truth["m_r"][i, j], m_scale(s.truth["m_r"])),
                  equation)


SLIDE_FORCING = {"eq12_r1": (paper.eq12_r1, 0), "eq13_r2": (paper.eq13_r2, 1)}


@pytest.mark.parametrize("equation", SLIDE_FORCING, ids=list(SLIDE_FORCING))
def test_stage1_forcing_as_printed_agrees(slide_samples, equation):
    printed, i = SLIDE_FORCING[equation]
    assert_agrees(slide_samples,
                  lambda s: (printed(*s.state, s.P), s.truth["r"][i], r_scale(s, s.truth["r"])),
                  equation)


EQ12_PARTS = {  # part of eq. (12) -> how to isolate it (parameters, rates scaled by)
    "eq12_gravity_terms": (lambda P: P, 0.0),
    "eq12_rate_terms": (lambda P: P._replace(Grav=0.0), 1.0),
    "eq12_arm_and_weight_terms": (lambda P: P._replace(mP=0.0), 1.0),
    "eq12_projectile_terms": (lambda P: P._replace(mA=0.0, mW=0.0, IA3=0.0, IW3=0.0), 1.0),
    "eq12_projectile_rate_terms": (lambda P: P._replace(mA=0.0, mW=0.0, IA3=0.0, IW3=0.0, Grav=0.0), 1.0),
}


@pytest.mark.parametrize("part", EQ12_PARTS, ids=list(EQ12_PARTS))
def test_eq12_r1_term_by_term_agrees(lagrangian, slide_samples, part):
    # r1 is linear in each mass and in Grav, and its rate terms are quadratic:
    # switching groups off isolates the printed terms a few at a time, so a
    # wrong term cannot hide behind another that compensates it in the total.
    modify, rate_factor = EQ12_PARTS[part]

    def evaluate(s):
        P = modify(s.P)
        theta, phi, _ = s.q
        truth = slide_truth(lagrangian, theta, phi, rate_factor * s.qd[0], rate_factor * s.qd[1], P, s.h, solve=False)
        value = paper.eq12_r1(*truth["q"], *truth["qd"], P)
        return value, truth["r"][0], r_scale(s, s.truth["r"])

    assert_agrees(slide_samples, evaluate, part)


SOLVE = {"eq17_Aw_dot": (paper.eq17_Aw_dot, 0), "eq18_Ww_dot": (paper.eq18_Ww_dot, 1)}


@pytest.mark.parametrize("equation", SOLVE, ids=list(SOLVE))
def test_stage1_solution_as_printed_agrees(slide_samples, equation):
    printed, i = SOLVE[equation]

    def from_reference_system(s):
        (m11, m12), (m21, m22) = s.truth["m_r"]
        return printed(m11, m12, m21, m22, *s.truth["r"]), s.truth["qdd"][i], accel_scale(s)

    def from_printed_system(s):  # the paper's chain (8)-(13) -> (17), (18)
        args = [f(*s.angles, s.P) for f in (paper.eq08_M11, paper.eq09_M12, paper.eq10_M21, paper.eq11_M22)]
        args += [paper.eq12_r1(*s.state, s.P), paper.eq13_r2(*s.state, s.P)]
        return printed(*args), s.truth["qdd"][i], accel_scale(s)

    assert_agrees(slide_samples, from_reference_system, f"{equation} on the reference M_r, r")
    assert_agrees(slide_samples, from_printed_system, f"{equation} on eqs. (8)-(13)")


def eq19_corrected(Aq, Sq, Aw, Sw, Aw_dot, P: PaperParams):
    """Eq. (19) with the second term as eqs. (12) and (21) write it."""
    LAl, LS = P.LAl, P.LS
    beta = Aq + Sq
    return (-math.cos(beta) * Sw * (Sw + 2 * Aw) / math.sin(beta)
            - (math.cos(beta) / math.sin(beta) + LAl * math.cos(Aq) / (LS * math.sin(beta))) * Aw**2
            - (LAl * math.sin(Aq) + LS * math.sin(beta)) * Aw_dot / (LS * math.sin(beta)))


def _eq19(function):
    def evaluate(s: Sample):
        Aq, _, Sq, Aw, _, Sw = s.state
        return function(Aq, Sq, Aw, Sw, s.truth["qdd"][0], s.P), s.truth["qdd"][2], accel_scale(s)
    return evaluate


def away_from_flat_sling(samples):
    """Samples with |cos(Aq + Sq)| > MIN_COS_BETA: eqs. (19) and (21) as printed
    are right when the sling lies flat (cos(Aq + Sq) = 0), so their errors show
    only away from it."""
    chosen = [s for s in samples if abs(math.cos(s.q[0] + s.q[2])) > MIN_COS_BETA]
    assert len(chosen) >= len(samples) // 2
    return chosen


def test_eq19_Sw_dot_as_printed_disagrees(slide_samples):
    assert_disagrees(away_from_flat_sling(slide_samples), _eq19(paper.eq19_Sw_dot), "eq19_Sw_dot")


def test_eq19_Sw_dot_as_printed_is_not_dimensionally_consistent(slide_samples):
    # Printed, the Aw^2 coefficient adds cot(Aq+Sq) (a number) to LAI cos(Aq) (a
    # length). An angular acceleration from angles, rates, Aw_dot and length
    # ratios cannot change when every length is doubled; the printed one does.
    s = slide_samples[1]
    Aq, _, Sq, Aw, _, Sw = s.state
    doubled = s.P._replace(LAl=2 * s.P.LAl, LS=2 * s.P.LS)
    Aw_dot = s.truth["qdd"][0]
    for function, consistent in ((eq19_corrected, True), (paper.eq19_Sw_dot, False)):
        same = math.isclose(function(Aq, Sq, Aw, Sw, Aw_dot, s.P), function(Aq, Sq, Aw, Sw, Aw_dot, doubled),
                            rel_tol=AGREE_REL)
        assert same == consistent, function.__name__


def test_eq19_Sw_dot_corrected_agrees(slide_samples):
    assert_agrees(slide_samples, _eq19(eq19_corrected), "eq19_Sw_dot corrected")


def eq21_corrected(Aq, Sq, Aw, Sw, Aw_dot, P: PaperParams):
    """Eq. (21) with the bracket divided by sin(Aq + Sq): the base's normal force on the projectile."""
    LAl, LS, beta = P.LAl, P.LS, Aq + Sq
    bracket = (LS * (math.cos(beta) * Sw * (Sw + 2 * Aw) / math.sin(beta)
                     + (math.cos(beta) / math.sin(beta) + LAl * math.cos(Aq) / (LS * math.sin(beta))) * Aw**2)
               - LAl * math.sin(Sq) * Aw**2 - LAl * (math.cos(Sq) - math.sin(Aq) / math.sin(beta)) * Aw_dot)
    return P.mP * (P.Grav + bracket / math.sin(beta))


def _eq21(function):
    def evaluate(s: Sample):
        Aq, _, Sq, Aw, _, Sw = s.state
        scale = max(abs(s.truth["normal"]), s.P.mP * s.P.Grav, s.P.mP * s.P.LAl * accel_scale(s))
        return function(Aq, Sq, Aw, Sw, s.truth["qdd"][0], s.P), s.truth["normal"], scale
    return evaluate


def test_eq21_F_y_as_printed_disagrees(slide_samples):
    # Relative to the dynamic part N - mP g (the printed Grav term is right), the
    # printed form is off by cos^2(Aq + Sq) >= MIN_COS_BETA^2, see the next test.
    def evaluate(s: Sample):
        value, truth, _ = _eq21(paper.eq21_F_y)(s)
        return value, truth, abs(truth - s.P.mP * s.P.Grav)

    assert_disagrees(away_from_flat_sling(slide_samples), evaluate, "eq21_F_y")


def test_eq21_F_y_as_printed_is_off_by_a_factor_sin_squared(slide_samples):
    # The error exactly: the printed bracket is multiplied by sin(Aq+Sq) where it
    # should be divided, so F_y - mP g = sin^2(Aq+Sq) (N - mP g).
    def evaluate(s: Sample):
        value, truth, scale = _eq21(paper.eq21_F_y)(s)
        weight = s.P.mP * s.P.Grav
        return value - weight, math.sin(s.q[0] + s.q[2]) ** 2 * (truth - weight), scale

    assert_agrees(slide_samples, evaluate, "eq21_F_y - mP Grav vs sin^2(Aq+Sq) (N - mP Grav)")


def test_eq21_F_y_corrected_is_the_normal_force(slide_samples):
    assert_agrees(slide_samples, _eq21(eq21_corrected), "eq21_F_y corrected")


def _start_at_rest(lagrangian):
    """Table III at rest before firing: tip on the base, weight plumb, sling flat forward."""
    P, h = TABLE3, TABLE3_PIVOT_HEIGHT
    theta = math.acos(-h / P.LAl)
    truth = slide_truth(lagrangian, theta, -theta, 0.0, 0.0, P, h)
    return Sample(P, h, tuple(truth["q"]), tuple(truth["qd"]), truth)


def test_eq21_printed_and_corrected_agree_only_with_the_sling_flat(lagrangian):
    # sin(Aq + Sq) = -1 at the start, where multiplying and dividing by it agree.
    s = _start_at_rest(lagrangian)
    assert math.sin(s.q[0] + s.q[2]) == pytest.approx(-1.0, abs=AGREE_REL)
    for function in (paper.eq21_F_y, eq21_corrected):
        value, truth, _ = _eq21(function)(s)
        assert value == pytest.approx(truth, rel=AGREE_REL)
        assert truth == pytest.approx(TABLE3.mP * TABLE3.Grav, rel=AGREE_REL)


def eq20_corrected(F_y) -> bool:
    """Stage 1 continues while the base pushes the projectile up."""
    return F_y > 0


def test_eq20_as_printed_ends_stage1_at_the_start(lagrangian):
    # At rest the base carries the projectile's weight, N = mP g > 0, yet the
    # printed condition F_y < 0 is already not satisfied: stage 1 would end at t = 0.
    s = _start_at_rest(lagrangian)
    F_y = paper.eq21_F_y(s.q[0], s.q[2], s.qd[0], s.qd[2], s.truth["qdd"][0], s.P)
    assert s.truth["normal"] > 0.0
    assert not paper.eq20_stage1_continues(F_y)
    assert eq20_corrected(F_y)


def test_eq20_corrected_continues_exactly_while_the_base_pushes(slide_samples):
    normals = [s.truth["normal"] for s in slide_samples]
    assert min(normals) < 0.0 < max(normals), "samples should include both pressed and lifting states"
    for s in slide_samples:
        F_y = eq21_corrected(s.q[0], s.q[2], s.qd[0], s.qd[2], s.truth["qdd"][0], s.P)
        assert eq20_corrected(F_y) == (s.truth["normal"] > 0.0)


# --------------------------------------------------------------------------- #
# Stage 2 (eqs. 22-32)
# --------------------------------------------------------------------------- #

def test_eq22_M23_and_M32_are_zero(lagrangian):
    # The weight link and the sling are not coupled inertially: exact zeros.
    for i, j in paper.EQ22_ZERO_ENTRIES:
        assert sp.simplify(lagrangian.symbols.mass[i - 1, j - 1]) == 0


SWING_MATRIX = {
    "eq23_M11": (paper.eq23_M11, (0, 0)),
    "eq24_M12": (paper.eq24_M12, (0, 1)),
    "eq25_M13": (paper.eq25_M13, (0, 2)),
    "eq26_M21": (paper.eq26_M21, (1, 0)),
    "eq27_M22": (paper.eq27_M22, (1, 1)),
    "eq29_M33": (paper.eq29_M33, (2, 2)),
}


@pytest.mark.parametrize("equation", SWING_MATRIX, ids=list(SWING_MATRIX))
def test_stage2_mass_matrix_as_printed_agrees(swing_samples, equation):
    printed, (i, j) = SWING_MATRIX[equation]
    assert_agrees(swing_samples,
                  lambda s: (printed(*s.angles, s.P), s.truth["M"][i, j], m_scale(s.truth["M"])),
                  equation)


def test_eq28_M31_agrees_reading_Ls_as_LS_and_LA1_as_LAl(swing_samples):
    assert_agrees(swing_samples,
                  lambda s: (paper.eq28_M31(*s.angles, s.P, Ls=s.P.LS, LA1=s.P.LAl),
                             s.truth["M"][2, 0], m_scale(s.truth["M"])),
                  "eq28_M31")


SWING_FORCING = {"eq30_r1": (paper.eq30_r1, 0), "eq32_r3": (paper.eq32_r3, 2)}


@pytest.mark.parametrize("equation", SWING_FORCING, ids=list(SWING_FORCING))
def test_stage2_forcing_as_printed_agrees(swing_samples, equation):
    printed, i = SWING_FORCING[equation]
    assert_agrees(swing_samples,
                  lambda s: (printed(*s.state, s.P), s.truth["f"][i], r_scale(s, s.truth["f"])),
                  equation)


def eq31_corrected(Aq, Wq, Sq, Aw, Ww, Sw, P: PaperParams):
    """Eq. (31) corrected; the same as eq. (13)."""
    return -P.LW * P.mW * (P.Grav * math.sin(Aq + Wq) + P.LAs * math.sin(Wq) * Aw**2)


def test_eq31_r2_as_printed_disagrees_reading_L_as_LW(swing_samples):
    assert_disagrees(swing_samples,
                     lambda s: (paper.eq31_r2(*s.state, s.P, L=s.P.LW), s.truth["f"][1],
                                r_scale(s, s.truth["f"])),
                     "eq31_r2")


def test_eq31_r2_as_printed_is_wrong_for_any_L(swing_samples):
    # r2 is linear in L; the L that fits one sample does not fit another.
    def fitted_L(s):
        base = paper.eq31_r2(*s.state, s.P, L=0.0)
        slope = paper.eq31_r2(*s.state, s.P, L=1.0) - base
        return (s.truth["f"][1] - base) / slope

    s0, s1 = swing_samples[0], swing_samples[1]
    L = fitted_L(s0)
    value = paper.eq31_r2(*s1.state, s1.P, L=L)
    assert abs(value - s1.truth["f"][1]) > DISAGREE_REL * r_scale(s1, s1.truth["f"])


def test_eq31_r2_as_printed_is_not_periodic_in_Wq(swing_samples):
    # The bare Wq added to Grav sin(Aq) makes r2 change when the weight turns a
    # full revolution, which leaves the machine exactly as it was.
    s = swing_samples[1]
    Aq, Wq, Sq, Aw, Ww, Sw = s.state
    turned = (Aq, Wq + 2 * math.pi, Sq, Aw, Ww, Sw)
    assert eq31_corrected(*turned, s.P) == pytest.approx(eq31_corrected(*s.state, s.P), rel=AGREE_REL)
    assert paper.eq31_r2(*turned, s.P, L=s.P.LW) != pytest.approx(paper.eq31_r2(*s.state, s.P, L=s.P.LW),
                                                                   rel=DISAGREE_REL)


def test_eq31_r2_corrected_agrees_and_equals_eq13(swing_samples):
    assert_agrees(swing_samples,
                  lambda s: (eq31_corrected(*s.state, s.P), s.truth["f"][1], r_scale(s, s.truth["f"])),
                  "eq31_r2 corrected")
    for s in swing_samples:
        assert eq31_corrected(*s.state, s.P) == paper.eq13_r2(*s.state, s.P)


# --------------------------------------------------------------------------- #
# Release velocity (eqs. 34-35) and flight (eqs. 42-43)
# --------------------------------------------------------------------------- #

RELEASE = {"eq34_vx": (paper.eq34_vx, 0), "eq35_vy": (paper.eq35_vy, 1)}


@pytest.mark.parametrize("equation", RELEASE, ids=list(RELEASE))
def test_release_velocity_as_printed_agrees(swing_samples, equation):
    printed, i = RELEASE[equation]

    def evaluate(s):
        Aq, _, Sq, Aw, _, Sw = s.state
        scale = (s.P.LAl + s.P.LS) * float(np.max(np.abs(s.qd)))
        return printed(Aq, Sq, Aw, Sw, s.P), s.truth["v"][i], scale

    assert_agrees(swing_samples, evaluate, equation)


def flight_samples():
    """(vx, vy, wind, rho, Cd, A_eff, mP, g): random flights, headwind and tailwind."""
    rng = np.random.default_rng(SEED + 2)
    return [(*rng.normal(0.0, 20.0, 2), rng.normal(0.0, 5.0), rng.uniform(0.5, 1.5),
             rng.uniform(0.1, 1.0), rng.uniform(1e-4, 1e-1), rng.uniform(0.01, 5.0), rng.uniform(1.0, 25.0))
            for _ in range(N_SAMPLES)]


def flight_acceleration(vx, vy, wind, rho, cd, area, mass, g):
    """Point mass under gravity and drag 1/2 rho Cd A |u| u against the air-relative velocity u."""
    u = np.array([vx - wind, vy])
    return np.array([0.0, -g]) - 0.5 * rho * cd * area * np.linalg.norm(u) * u / mass


@pytest.mark.parametrize("equation", ["eq42_x3_dot", "eq43_x4_dot"])
def test_flight_as_printed_agrees(equation):
    for vx, vy, wind, rho, cd, area, mass, g in flight_samples():
        truth = flight_acceleration(vx, vy, wind, rho, cd, area, mass, g)
        if equation == "eq42_x3_dot":
            value, expected = paper.eq42_x3_dot(vx, vy, rho, cd, area, wind, mass), truth[0]
        else:
            value, expected = paper.eq43_x4_dot(vx, vy, rho, cd, area, wind, mass, g), truth[1]
        assert value == pytest.approx(expected, rel=AGREE_REL, abs=AGREE_REL * float(np.max(np.abs(truth))))
