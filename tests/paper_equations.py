"""The paper's equations of motion transcribed exactly as printed, typos included (test helper, not a model).

Source: T. Corie, J. Park, D. Standring, "Here Comes Trebuchet - Optimizing the
Counterweight Trebuchet for Maximum Range", section II, eqs. (8)-(43)
(the project's copy: ``shared/seed/trebuchet-paper.md`` beside the repository). Each function is named after its
equation number and its body follows the printed text token by token, in the
paper's own symbols, so a reader can hold the two side by side. Nothing is
corrected here; ``tests/test_analytic_paper_errata.py`` holds the corrections
and the tests that show which printed forms are wrong.

Reading conventions (the only liberties taken):

* ``SIN`` (eqs. 30, 31) is read as ``sin``; juxtaposition is multiplication;
  ``a / b c`` in the one-line formulas is ``(a / b) * c`` (left to right), as
  in the MATLAB the paper's code was written in.
* ``LAI`` (stage 1, eqs. 8-21) is the nomenclature's ``L_Al`` (the paper also
  writes ``L_AI`` in Tables I and IV): a font confusion of l and I, read as
  ``LAl``.
* Symbols that the nomenclature does not define are not guessed: ``L`` in
  eq. (31) and ``Ls``, ``LA1`` in eq. (28) are arguments the caller must
  supply (the tests supply the readings ``L = LW``, ``Ls = LS``, ``LA1 = LAl``).
* Where the typeset fraction bars are ambiguous the docstring says so and the
  literal (typeset) reading is the one implemented.

Symbols: ``Aq, Wq, Sq`` arm, weight and sling angles; ``Aw, Ww, Sw`` their
rates; ``Aw_dot`` = the arm's angular acceleration (the paper's ``x4_dot``).
Their meaning matches ``analytic.eom``'s theta, phi, psi.
"""

from __future__ import annotations

from math import cos, sin, sqrt
from typing import NamedTuple


class PaperParams(NamedTuple):
    """The paper's parameter symbols (section I, Definitions)."""

    LAl: float   # pivot to projectile end of the arm ("long arm")
    LAs: float   # pivot to counterweight attachment ("short arm")
    LAcg: float  # pivot to arm centre of gravity
    LS: float    # sling
    LW: float    # weight rope
    mA: float
    mW: float
    mP: float
    IA3: float   # inertia of the arm (about its centre of gravity: eq. 23 adds mA LAcg^2)
    IW3: float   # inertia of the counterweight (about its centre)
    Grav: float


# --------------------------------------------------------------------------- #
# Stage 1: the projectile on the base, [M_2x2][Aw_dot, Ww_dot] = [r1, r2]  (eq. 7)
# --------------------------------------------------------------------------- #

def eq08_M11(Aq, Wq, Sq, P: PaperParams):
    """Eq. (8)."""
    LAI, LAs, LAcg, LW, mA, mW, mP, IA3, IW3 = P.LAl, P.LAs, P.LAcg, P.LW, P.mA, P.mW, P.mP, P.IA3, P.IW3
    return (-mP * LAI**2 * (-1 + 2 * sin(Aq) * cos(Sq) / sin(Aq + Sq))
            + IA3 + IW3 + mA * LAcg**2
            + mP * LAI**2 * sin(Aq)**2 / sin(Aq + Sq)**2
            + mW * (LAs**2 + LW**2 + 2 * LAs * LW * cos(Wq)))


def eq09_M12(Aq, Wq, Sq, P: PaperParams):
    """Eq. (9)."""
    return P.IW3 + P.LW * P.mW * (P.LW + P.LAs * cos(Wq))


def eq10_M21(Aq, Wq, Sq, P: PaperParams):
    """Eq. (10)."""
    return P.IW3 + P.LW * P.mW * (P.LW + P.LAs * cos(Wq))


def eq11_M22(Aq, Wq, Sq, P: PaperParams):
    """Eq. (11)."""
    return P.IW3 + P.mW * P.LW**2


def eq12_r1(Aq, Wq, Sq, Aw, Ww, Sw, P: PaperParams):
    """Eq. (12), its eight printed lines in order.

    Reading: the ``/ sin(Aq + Sq)`` that closes line 6 divides the whole
    product ``LAI mP sin(Aq) ( ... )`` that starts on line 5 (left to right).
    """
    Grav, LAcg, mA, LAI, LS, mP, mW, LAs, LW = (P.Grav, P.LAcg, P.mA, P.LAl, P.LS, P.mP, P.mW,
                                                P.LAs, P.LW)
    return (Grav * LAcg * mA * sin(Aq) + LAI * LS * mP
            * (sin(Sq) * (Aw + Sw)**2 + cos(Sq) * (cos(Aq + Sq)
               * Sw * (Sw + 2 * Aw) / sin(Aq + Sq)
               + (cos(Aq + Sq) / sin(Aq + Sq) + LAI * cos(Aq)
                  / (LS * sin(Aq + Sq))) * Aw**2))
            + LAI * mP * sin(Aq) * (LAI * sin(Sq) * Aw**2
                                    - LS * (cos(Aq + Sq) * Sw * (Sw + 2 * Aw) / sin(Aq + Sq)
                                            + (cos(Aq + Sq) / sin(Aq + Sq) + LAI * cos(Aq)
                                               / (LS * sin(Aq + Sq))) * Aw**2)) / sin(Aq + Sq)
            - Grav * mW * (LAs * sin(Aq) + LW
                           * sin(Aq + Wq)) - LAs * LW * mW * sin(Wq)
            * (Aw**2 - (Aw + Ww)**2))


def eq13_r2(Aq, Wq, Sq, Aw, Ww, Sw, P: PaperParams):
    """Eq. (13)."""
    return -P.LW * P.mW * (P.Grav * sin(Aq + Wq)
                           + P.LAs * sin(Wq) * Aw**2)


def eq17_Aw_dot(M11, M12, M21, M22, r1, r2):
    """Eq. (17): x4_dot."""
    return (r1 * M22 - r2 * M12) / (M11 * M22 - M12 * M21)


def eq18_Ww_dot(M11, M12, M21, M22, r1, r2):
    """Eq. (18): x5_dot."""
    return -(r1 * M21 - r2 * M11) / (M11 * M22 - M12 * M21)


def eq19_Sw_dot(Aq, Sq, Aw, Sw, Aw_dot, P: PaperParams):
    """Eq. (19): x6_dot, with the second term's fraction bar as typeset.

    Ambiguity: the typeset second term is
    ``\\frac{cos(Aq+Sq)/sin(Aq+Sq) + LAI cos(Aq)}{LS sin(Aq+Sq)} Aw^2``, i.e. the
    bar spans the whole sum; that literal reading is implemented here (eq. 12
    and eq. 21 write the same term as ``cot(Aq+Sq) + LAI cos(Aq)/(LS sin(Aq+Sq))``).
    """
    LAI, LS = P.LAl, P.LS
    return (-cos(Aq + Sq) * Sw * (Sw + 2 * Aw) / sin(Aq + Sq)
            - ((cos(Aq + Sq) / sin(Aq + Sq) + LAI * cos(Aq)) / (LS * sin(Aq + Sq))) * Aw**2
            - (LAI * sin(Aq) + LS * sin(Aq + Sq)) * Aw_dot / (LS * sin(Aq + Sq)))


def eq20_stage1_continues(F_y) -> bool:
    """Eq. (20): stage 1 runs while this holds and ends once it no longer does."""
    return F_y < 0


def eq21_F_y(Aq, Sq, Aw, Sw, Aw_dot, P: PaperParams):
    """Eq. (21), reading the ``\\left( \\right.`` line breaks as one bracket per pair.

    Literal reading: ``mP (Grav + [ LS (A) - LAI sin(Sq) Aw^2
    - LAI (cos(Sq) - sin(Aq)/sin(Aq+Sq)) Aw_dot ] sin(Aq+Sq))`` with
    ``A = cos(Aq+Sq) Sw (Sw + 2 Aw)/sin(Aq+Sq) + (cot(Aq+Sq) + LAI cos(Aq)/(LS sin(Aq+Sq))) Aw^2``;
    the bracket is *multiplied* by ``sin(Aq + Sq)`` (juxtaposition).
    """
    mP, Grav, LS, LAI = P.mP, P.Grav, P.LS, P.LAl
    return mP * (Grav
                 + ((LS * (cos(Aq + Sq) * Sw * (Sw + 2 * Aw) / sin(Aq + Sq)
                           + (cos(Aq + Sq) / sin(Aq + Sq) + LAI * cos(Aq) / (LS * sin(Aq + Sq))) * Aw**2)
                     - LAI * sin(Sq) * Aw**2 - LAI * (cos(Sq)
                                                      - sin(Aq) / sin(Aq + Sq)) * Aw_dot))
                 * sin(Aq + Sq))


# --------------------------------------------------------------------------- #
# Stage 2: three degrees of freedom, [M_3x3][Aw_dot, Ww_dot, Sw_dot] = r  (eq. 22)
# --------------------------------------------------------------------------- #

#: Eq. (22): the printed zero entries of the 3x3 matrix, as (row, column), 1-based.
EQ22_ZERO_ENTRIES = ((2, 3), (3, 2))


def eq23_M11(Aq, Wq, Sq, P: PaperParams):
    """Eq. (23)."""
    return (P.IA3 + P.IW3 + P.mA * P.LAcg**2
            + P.mP * (P.LAl**2 + P.LS**2 + 2 * P.LAl * P.LS * cos(Sq))
            + P.mW * (P.LAs**2 + P.LW**2 + 2 * P.LAs * P.LW * cos(Wq)))


def eq24_M12(Aq, Wq, Sq, P: PaperParams):
    """Eq. (24)."""
    return P.IW3 + P.LW * P.mW * (P.LW + P.LAs * cos(Wq))


def eq25_M13(Aq, Wq, Sq, P: PaperParams):
    """Eq. (25)."""
    return P.LS * P.mP * (P.LS + P.LAl * cos(Sq))


def eq26_M21(Aq, Wq, Sq, P: PaperParams):
    """Eq. (26)."""
    return P.IW3 + P.LW * P.mW * (P.LW + P.LAs * cos(Wq))


def eq27_M22(Aq, Wq, Sq, P: PaperParams):
    """Eq. (27)."""
    return P.IW3 + P.mW * P.LW**2


def eq28_M31(Aq, Wq, Sq, P: PaperParams, *, Ls, LA1):
    """Eq. (28) as printed, ``Ls mP (LS + LA1 cos(Sq))``.

    ``Ls`` (lower-case s) and ``LA1`` (digit one) are not in the nomenclature;
    the caller supplies them (the evident readings are ``LS`` and ``LAl``).
    """
    return Ls * P.mP * (P.LS + LA1 * cos(Sq))


def eq29_M33(Aq, Wq, Sq, P: PaperParams):
    """Eq. (29)."""
    return P.mP * P.LS**2


def eq30_r1(Aq, Wq, Sq, Aw, Ww, Sw, P: PaperParams):
    """Eq. (30) (``SIN`` read as ``sin``)."""
    Grav, LAcg, mA, mP, LAl, LS, mW, LAs, LW = (P.Grav, P.LAcg, P.mA, P.mP, P.LAl, P.LS, P.mW,
                                                P.LAs, P.LW)
    return (Grav * LAcg * mA * sin(Aq)
            + Grav * mP * (LAl * sin(Aq) + LS * sin(Aq + Sq))
            - Grav * mW * (LAs * sin(Aq) + LW * sin(Aq + Wq))
            - LAl * LS * mP * sin(Sq) * (Aw**2 - (Aw + Sw)**2)
            - LAs * LW * mW * sin(Wq) * (Aw**2 - (Aw + Ww)**2))


def eq31_r2(Aq, Wq, Sq, Aw, Ww, Sw, P: PaperParams, *, L):
    """Eq. (31) as printed, ``-L mW (Grav sin(Aq) + Wq) + LAs SIN(Wq) Aw^2``.

    ``L`` is not in the nomenclature; the caller supplies it. The parenthesis
    closes after ``Wq``, so ``LAs sin(Wq) Aw^2`` is a separate term, not
    multiplied by ``-L mW``; and ``Wq`` is added to ``sin(Aq)``, not inside it.
    """
    return -L * P.mW * (P.Grav * sin(Aq) + Wq) + P.LAs * sin(Wq) * Aw**2


def eq32_r3(Aq, Wq, Sq, Aw, Ww, Sw, P: PaperParams):
    """Eq. (32)."""
    return P.LS * P.mP * (P.Grav * sin(Aq + Sq) - P.LAl * sin(Sq) * Aw**2)


# --------------------------------------------------------------------------- #
# Release (eqs. 34-35) and flight (eqs. 42-43)
# --------------------------------------------------------------------------- #

def eq34_vx(Aq, Sq, Aw, Sw, P: PaperParams):
    """Eq. (34)."""
    return -P.LAl * Aw * cos(Aq) - P.LS * (Aw + Sw) * cos(Aq + Sq)


def eq35_vy(Aq, Sq, Aw, Sw, P: PaperParams):
    """Eq. (35)."""
    return -P.LAl * Aw * sin(Aq) - P.LS * (Aw + Sw) * sin(Aq + Sq)


def eq42_x3_dot(x3, x4, rho, Cd, Aeff, WS, mP):
    """Eq. (42): horizontal acceleration in flight."""
    return -rho * Cd * Aeff * (x3 - WS) / (2 * mP) * sqrt(x4**2 + (WS - x3)**2)


def eq43_x4_dot(x3, x4, rho, Cd, Aeff, WS, mP, Grav):
    """Eq. (43): vertical acceleration in flight."""
    return -Grav - rho * Cd * Aeff * x4 / (2 * mP) * sqrt(x4**2 + (WS - x3)**2)
