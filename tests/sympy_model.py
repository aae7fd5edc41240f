"""The machine as a sympy Lagrangian: the one independent reference that every symbolic test holds
``analytic.eom``, ``analytic.friction`` and ``analytic.stages`` to (test helper, not a model).

Built from nothing but the geometry in ``analytic.design``'s module docstring; no function of
``analytic`` is used to build it. Coordinates ``q = (theta, phi, psi, X)``: the arm, the
counterweight's link relative to the arm, the sling relative to the arm, and the frame's
displacement X (the pivot is at ``(X, 0)``, the base at ``y = -h``). On a fixed frame X is held
at 0 and only the first three coordinates move; on a rolling one the frame of mass ``Mf`` is a
fourth body. ``machine("fixed")`` is the bolted counterweight's (``docs/derivation.md`` section 11):
the counterweight's centre at ``Lb`` on the arm's short side and its spin the arm's, so phi appears
nowhere (its row and column of M are 0 and it is not solved for). ``machine("floating-arm")``
(section 12): the axle at ``(X - Lb sin theta, 0)`` on its track, the counterweight bolted to the
short end, which puts it at ``(X, -Lb cos theta)`` on its guide; no phi either, and X is the guide's
place (the machine's frame is not rolled: ``p.rolling`` 0). From the parts' positions:

* velocities and accelerations by differentiation, ``T`` and ``V``, and Lagrange's equations in
  mass-matrix form ``M(q) q'' = f(q, q')`` with ``f = -(dM/dt) q' + dT/dq - dV/dq``;
* the base constraint ``y_P + h = 0`` (stage 1) as ``J q'' = -J' q'`` with its multiplier, the
  base's push N on the projectile (positive up): ``M q'' = f + Q + J^T N``;
* the friction's generalised forces ``Q = dP/dq'`` from the virtual power of the axle's and the
  hinge's torques and the base's force on the projectile,
  ``P = ta (w_arm - w_frame) + th (w_link - w_arm) + F (x_P' - X')`` (``docs/derivation.md`` 10.1);
* a force on the projectile (the air's drag during the swing) as ``Q = (d r_P / dq)^T F``;
* the joint forces from Newton's law for each body, with the accelerations sympy differentiates:
  the hinge's on the counterweight ``mW (a_W + g)``, the sling's on the projectile and the pouch
  ``(mP + mQ) (a_P + g) - (F, N)``, the axle's on the arm ``mA (a_A + g)`` plus the hinge's and
  the tip's, which is the sling's plus ``mS (a_S + g)`` for the sling's own mass (S its centre);
* the sling (section 14): a uniform rod of mass ``mS`` from the tip to the projectile, and the pouch,
  a point of mass ``mQ`` at the projectile.

The derivation runs once per process (``machine()``, cached: about two seconds); every numerical
function then takes a ``Params`` (only the machine's numbers and ``rolling`` are read) and a state
of three coordinates (a fixed frame's: X = X' = 0 is added) or four.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import sympy as sp

from analytic.parameters import Params

#: The numbers the Lagrangian reads, in ``Params``' names and the order its functions take them.
NUMBERS = ("La", "Lb", "d", "mA", "IA", "mW", "Lw", "IW", "Ls", "mP", "h", "g", "Mf", "mS", "mQ")


def numbers(p: Params) -> tuple[float, ...]:
    """The Lagrangian's numbers of ``p`` (a fixed frame's mass is never read: 0)."""
    return tuple(getattr(p, name) if name != "Mf" or p.rolling else 0.0 for name in NUMBERS)


def _four(values) -> np.ndarray:
    """A state's coordinates (or rates) with X: a fixed frame's three get X = 0."""
    values = np.asarray(values, dtype=float)
    return values if values.size == 4 else np.append(values, 0.0)


class Symbols:
    """The symbols of the derivation, and the expressions derived from them."""

    def __init__(self, kind: str = "hinged") -> None:
        self.q = sp.symbols("theta phi psi X", real=True)
        self.qd = sp.symbols("dtheta dphi dpsi dX", real=True)
        self.qdd = sp.symbols("ddtheta ddphi ddpsi ddX", real=True)
        self.prm = sp.symbols(NUMBERS, real=True)
        self.torques = sp.symbols("ta th F", real=True)   # axle, hinge, base's friction force
        self.normal = sp.Symbol("N", real=True)
        La, Lb, d, mA, IA, mW, Lw, IW, Ls, mP, h, g, Mf, mS, mQ = self.prm
        theta, phi, psi, x = self.q
        qv, qdv, qddv = sp.Matrix(self.q), sp.Matrix(self.qd), sp.Matrix(self.qdd)

        along_arm = sp.Matrix([-sp.sin(theta), sp.cos(theta)])
        # The axle: on a floating arm it rides the track y = 0, at x_A = -Lb sin(theta) (derivation 12.1).
        pivot = sp.Matrix([x - Lb * sp.sin(theta), 0]) if kind == "floating-arm" else sp.Matrix([x, 0])
        self.pivot = pivot
        self.arm = pivot + d * along_arm
        if kind == "fixed":   # bolted on the arm's axis, turning with the arm (derivation 11.1)
            self.weight = pivot - Lb * along_arm
        elif kind == "floating-arm":   # on the short end, held to the guide x = 0 (so x = X here)
            self.weight = pivot - Lb * along_arm
        else:
            self.weight = pivot - Lb * along_arm + Lw * sp.Matrix([sp.sin(theta + phi), -sp.cos(theta + phi)])
        self.sling_unit = sp.Matrix([-sp.sin(theta + psi), sp.cos(theta + psi)])   # tip -> projectile
        self.projectile = pivot + La * along_arm + Ls * self.sling_unit
        # The sling: a uniform rod of mass mS from the tip to the projectile, turning at theta' + psi';
        # the pouch: a point of mass mQ at the projectile (docs/derivation.md section 14).
        self.sling_centre = pivot + La * along_arm + Ls / 2 * self.sling_unit

        def velocity(r):
            return r.jacobian(qv) * qdv

        def acceleration(r):
            v = velocity(r)
            return v.jacobian(qdv) * qddv + v.jacobian(qv) * qdv

        def half_m_v2(m, r):
            v = velocity(r)
            return m * v.dot(v) / 2

        w_arm, dx = self.qd[0], self.qd[3]
        w_link = self.qd[0] + self.qd[1] if kind == "hinged" else w_arm
        self.kinetic_machine = (Mf * dx**2 / 2 + half_m_v2(mA, self.arm) + IA * w_arm**2 / 2
                                + half_m_v2(mW, self.weight) + IW * w_link**2 / 2)
        self.kinetic_projectile = half_m_v2(mP, self.projectile)
        w_sling = self.qd[0] + self.qd[2]
        self.kinetic_sling = (half_m_v2(mS, self.sling_centre) + mS * Ls**2 / 12 * w_sling**2 / 2
                              + half_m_v2(mQ, self.projectile))
        self.potential_machine = g * (mA * self.arm[1] + mW * self.weight[1])
        self.potential_projectile = g * mP * self.projectile[1]
        self.potential_sling = g * (mS * self.sling_centre[1] + mQ * self.projectile[1])
        kinetic = self.kinetic_machine + self.kinetic_projectile + self.kinetic_sling
        potential = self.potential_machine + self.potential_projectile + self.potential_sling

        momentum = sp.Matrix([kinetic]).jacobian(qdv).T                 # dT/dq'
        self.mass = momentum.jacobian(qdv)
        self.forcing = (-momentum.jacobian(qv) * qdv + sp.Matrix([kinetic]).jacobian(qv).T
                        - sp.Matrix([potential]).jacobian(qv).T)
        self.horizontal_momentum = momentum[3]
        self.horizontal_moment = (mA * (self.arm[0] - x) + mW * (self.weight[0] - x) + mP * (self.projectile[0] - x)
                                  + mS * (self.sling_centre[0] - x) + mQ * (self.projectile[0] - x))
        energy = kinetic + potential
        self.power = (sp.Matrix([energy]).jacobian(qv) * qdv + sp.Matrix([energy]).jacobian(qdv) * qddv)[0]

        y_p = self.projectile[1]
        self.base_jacobian = sp.Matrix([y_p]).jacobian(qv)
        self.base_jdot_qd = (qdv.T * sp.hessian(y_p, self.q) * qdv)[0]

        ta, th, fb = self.torques   # the frame does not turn: the axle's torque acts on w_arm alone
        virtual_power = ta * w_arm + th * (w_link - w_arm) + fb * (velocity(self.projectile)[0] - dx)
        self.generalised = sp.Matrix([virtual_power]).jacobian(qdv).T

        up = sp.Matrix([0, g])
        self.hinge = mW * (acceleration(self.weight) + up)
        # The sling pulls the projectile and the pouch; the arm's tip pulls the sling, whose own mass
        # takes mS (a_S + g) of that pull.
        self.sling = (mP + mQ) * (acceleration(self.projectile) + up) - sp.Matrix([fb, self.normal])
        self.tip = self.sling + mS * (acceleration(self.sling_centre) + up)
        self.axle = mA * (acceleration(self.arm) + up) + self.hinge + self.tip
        self.momentum_rate = (mA * acceleration(self.arm) + mW * acceleration(self.weight)
                              + (mP + mQ) * acceleration(self.projectile) + mS * acceleration(self.sling_centre))


class Machine:
    """The Lagrangian's functions, lambdified, and the systems solved from them.

    Every method takes ``p`` (``Params``) and states of three coordinates or four (see the module
    docstring); arrays are float, of shape ``(4,)`` for a state's coordinates unless said.
    """

    def __init__(self, kind: str = "hinged") -> None:
        s = self.symbols = Symbols(kind)
        # The coordinates that move: a fixed machine has no phi (its M's phi row and column are 0).
        self.free = (0, 1, 2, 3) if kind == "hinged" else (0, 2, 3)
        state = (s.q, s.qd, s.prm)
        with_accelerations = (s.q, s.qd, s.qdd, s.prm)

        def compiled(args, expression):
            return sp.lambdify(args, expression, "numpy", cse=True)

        self._mass = compiled(state, s.mass)
        self._forcing = compiled(state, s.forcing)
        self._energies = compiled(state, [s.kinetic_machine + s.kinetic_sling, s.kinetic_projectile,
                                          s.potential_machine + s.potential_sling, s.potential_projectile])
        self._sling_energies = compiled(state, [s.kinetic_sling, s.potential_sling])
        self._projectile = compiled(state, [s.projectile, s.projectile.jacobian(s.q) * sp.Matrix(s.qd)])
        self._projectile_jacobian = compiled(state, s.projectile.jacobian(s.q))
        self._momentum = compiled(state, s.horizontal_momentum)
        self._moment = compiled(state, s.horizontal_moment)
        self._jacobian = compiled(state, s.base_jacobian)
        self._jdot_qd = compiled(state, s.base_jdot_qd)
        self._power = compiled(with_accelerations, s.power)
        self._momentum_rate = compiled(with_accelerations, s.momentum_rate)
        self._generalised = compiled((s.q, s.qd, s.torques, s.prm), s.generalised)
        self._slides = compiled(state, [s.weight.jacobian(s.q), s.pivot.jacobian(s.q)])
        self._forces = compiled((s.q, s.qd, s.qdd, s.torques[2], s.normal, s.prm), [s.axle, s.hinge, s.sling])
        self._tip = compiled((s.q, s.qd, s.qdd, s.torques[2], s.normal, s.prm), s.tip)

    # -- the Lagrangian's terms ------------------------------------------------ #
    def mass(self, p, q, qd=(0.0, 0.0, 0.0)) -> np.ndarray:
        """M(q), (4, 4)."""
        return np.asarray(self._mass(_four(q), _four(qd), numbers(p)), dtype=float)

    def forcing(self, p, q, qd) -> np.ndarray:
        """f(q, q')."""
        return np.asarray(self._forcing(_four(q), _four(qd), numbers(p)), dtype=float).ravel()

    def energies(self, p, q, qd) -> np.ndarray:
        """(T of the machine with its frame, T of the projectile, V of the machine, V of the projectile), (4,);
        the machine's with the sling's and the pouch's."""
        return np.array(self._energies(_four(q), _four(qd), numbers(p)), dtype=float)

    def sling_energies(self, p, q, qd) -> np.ndarray:
        """(T, V) of the sling and the pouch, (2,)."""
        return np.array(self._sling_energies(_four(q), _four(qd), numbers(p)), dtype=float)

    def tip_force(self, p, q, qd, qdd, base_force=0.0, normal=0.0) -> np.ndarray:
        """The arm tip's force on the sling, (2,): the sling's pull on the projectile and the pouch plus
        what its own mass takes."""
        return np.asarray(self._tip(_four(q), _four(qd), _four(qdd), base_force, normal, numbers(p)),
                          dtype=float).ravel()

    def projectile(self, p, q, qd) -> tuple[np.ndarray, np.ndarray]:
        """The projectile's position and velocity on the ground, (2,) each."""
        position, velocity = self._projectile(_four(q), _four(qd), numbers(p))
        return np.asarray(position, dtype=float).ravel(), np.asarray(velocity, dtype=float).ravel()

    def power(self, p, q, qd, qdd) -> float:
        """dE/dt of the whole machine's energy T + V."""
        return float(self._power(_four(q), _four(qd), _four(qdd), numbers(p)))

    def momentum(self, p, q, qd) -> float:
        """The horizontal momentum dT/dX'."""
        return float(self._momentum(_four(q), _four(qd), numbers(p)))

    def moment(self, p, q) -> float:
        """sum m (x - X) over the arm, the counterweight, the projectile, the sling and the pouch."""
        return float(self._moment(_four(q), np.zeros(4), numbers(p)))

    def momentum_rate(self, p, q, qd, qdd) -> np.ndarray:
        """sum m a over the moving parts (the frame's X'' included), (2,)."""
        return np.asarray(self._momentum_rate(_four(q), _four(qd), _four(qdd), numbers(p)), dtype=float).ravel()

    def base_jacobian(self, p, q) -> np.ndarray:
        """J = d y_P / dq."""
        return np.asarray(self._jacobian(_four(q), np.zeros(4), numbers(p)), dtype=float).ravel()

    def generalised(self, p, q, qd, axle_torque, hinge_torque, base_force) -> np.ndarray:
        """Q, the friction's generalised forces."""
        return np.asarray(self._generalised(_four(q), _four(qd), (axle_torque, hinge_torque, base_force),
                                            numbers(p)), dtype=float).ravel()

    def slides(self, p, q, qd, guide_friction, track_friction) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """A floating arm's guide and track: the generalised force (4,) of a vertical force on the
        counterweight and a horizontal one on the axle, by virtual work, ``J_W^T (0, fg) + J_A^T (ft, 0)``,
        and the counterweight's and the axle's velocities, (2,) each."""
        weight, pivot = (np.asarray(j, dtype=float) for j in self._slides(_four(q), _four(qd), numbers(p)))
        generalised = weight.T @ np.array([0.0, guide_friction]) + pivot.T @ np.array([track_friction, 0.0])
        return generalised, weight @ _four(qd), pivot @ _four(qd)

    def force_on_projectile(self, p, q, force) -> np.ndarray:
        """Q of a force ``(Fx, Fy)`` on the projectile: its virtual work, ``(d r_P / dq)^T F``, (4,)."""
        jacobian = np.asarray(self._projectile_jacobian(_four(q), np.zeros(4), numbers(p)), dtype=float)
        return jacobian.T @ np.asarray(force, dtype=float)

    def joint_forces(self, p, q, qd, qdd, base_force=0.0, normal=0.0):
        """Newton's law for each body: the axle's force on the arm, the hinge's on the counterweight,
        the sling's on the projectile, (2,) each."""
        forces = self._forces(_four(q), _four(qd), _four(qdd), base_force, normal, numbers(p))
        return tuple(np.asarray(f, dtype=float).ravel() for f in forces)

    def sling(self, p, q, qd, qdd, normal=0.0) -> tuple[float, float]:
        """The sling's tension (its pull on the projectile towards the tip) and the sling force's
        component across the sling (zero for the massless sling the Lagrangian assumes)."""
        force = self.joint_forces(p, q, qd, qdd, 0.0, normal)[2]
        beta = q[0] + q[2]
        along, across = np.array([-math.sin(beta), math.cos(beta)]), np.array([-math.cos(beta), -math.sin(beta)])
        return -float(force @ along), float(force @ across)

    # -- the systems ----------------------------------------------------------- #
    def accelerations(self, p, q, qd) -> np.ndarray:
        """q'' of the free swing (stage 2): ``M q'' = f`` (on a fixed frame, its first three rows, X'' = 0)."""
        rows = self.rows(p)
        m, f = self.mass(p, q, qd)[np.ix_(rows, rows)], self.forcing(p, q, qd)[rows]
        return self._spread(rows, np.linalg.solve(m, f))

    def rows(self, p) -> list[int]:
        """The coordinates solved for: the free ones, X only on a rolling frame."""
        return [i for i in self.free if i < 3 or p.rolling]

    @staticmethod
    def _spread(rows, values) -> np.ndarray:
        """``values`` of the coordinates ``rows`` as a state of four, 0 elsewhere."""
        out = np.zeros(4)
        out[rows] = values
        return out

    def on_base(self, p, q, qd) -> tuple[np.ndarray, float]:
        """q'' and the base's push N with the projectile held on the base (stage 1):
        ``[[M, -J^T], [J, 0]] [q'', N] = [f, -J' q']``."""
        rows = self.rows(p)
        q, qd, prm = _four(q), _four(qd), numbers(p)
        m, f = self.mass(p, q, qd)[np.ix_(rows, rows)], self.forcing(p, q, qd)[rows]
        jac = self.base_jacobian(p, q)[rows]
        system = np.block([[m, -jac[:, None]], [jac[None, :], np.zeros((1, 1))]])
        solution = np.linalg.solve(system, np.append(f, -float(self._jdot_qd(q, qd, prm))))
        return self._spread(rows, solution[:-1]), float(solution[-1])

    def zero_momentum_rate(self, p, q, qd3) -> float:
        """The X' that makes the horizontal momentum zero, given (theta', phi', psi')."""
        at_rest = self.momentum(p, q, (*qd3, 0.0))
        return -at_rest / (self.momentum(p, q, (*qd3, 1.0)) - at_rest)

    def frame_acceleration(self, p, q, qd, qdd3) -> float:
        """X'' from the Lagrangian's X row, given (theta'', phi'', psi'')."""
        m, f = self.mass(p, q, qd), self.forcing(p, q, qd)
        return float((f[3] - m[3, :3] @ np.asarray(qdd3, dtype=float)) / m[3, 3])

    @staticmethod
    def base_angle(p, theta: float) -> float:
        """psi with the projectile on the base, branch sin(theta + psi) < 0, by atan2 (not arccos)."""
        cos_beta = -(p.h + p.La * math.cos(theta)) / p.Ls
        return math.atan2(-math.sqrt(1.0 - cos_beta**2), cos_beta) - theta

    def base_reduction(self, p, theta, phi, dtheta, dphi, solve=True) -> dict:
        """Stage 1 on a fixed frame as the paper's eq. (7) reduces it, with psi(theta) substituted:
        ``psi' = s theta'``, ``psi'' = s theta'' + c``, ``B = [[1, 0], [0, 1], [s, 0]]``,
        ``M_r = B^T M B``, ``r = B^T (f - M [0, 0, c])``. A dict of q, qd, s, c, jac, m, f, m_r, r
        (three coordinates) and, with ``solve``, q'' (3,) and N from ``on_base`` (not from M_r)."""
        psi = self.base_angle(p, theta)
        q = np.array([theta, phi, psi])
        jac = self.base_jacobian(p, q)[:3]
        s = -jac[0] / jac[2]                 # J B = 0 (J[1] = 0)
        qd = np.array([dtheta, dphi, s * dtheta])
        m, f = self.mass(p, q, qd)[:3, :3], self.forcing(p, q, qd)[:3]
        c = -float(self._jdot_qd(_four(q), _four(qd), numbers(p))) / jac[2]   # J (B [theta'', phi''] + [0, 0, c]) = -J' q'
        b = np.array([[1.0, 0.0], [0.0, 1.0], [s, 0.0]])
        out = {"q": q, "qd": qd, "s": s, "c": c, "jac": jac, "m": m, "f": f,
               "m_r": b.T @ m @ b, "r": b.T @ (f - m @ np.array([0.0, 0.0, c]))}
        if solve:
            qdd, out["normal"] = self.on_base(p, q, qd)
            out["qdd"] = qdd[:3]
        return out


@lru_cache(maxsize=3)
def machine(kind: str = "hinged") -> Machine:
    """The Lagrangian of a ``kind`` machine (``"hinged"``, ``"fixed"`` or ``"floating-arm"``), derived and
    lambdified once per process."""
    return Machine(kind)
