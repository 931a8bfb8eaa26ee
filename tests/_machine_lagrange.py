"""Independent forward dynamics of a planar mechanism under a motor, for the machine tests.

Written here from the equations, sharing no code with linkwork's engine or its machine module:
every moving body has the coordinates q = (x_S, y_S, theta) of its centre of mass; the joints
are constraint equations Phi(q) = 0 written out below (revolute: two point coincidences;
prismatic: point on a line and a fixed relative angle; pin-in-slot: point on a line), with
their Jacobian Phi_q and the velocity-quadratic term gamma of Phi_q q'' = gamma derived by hand.
The equations of motion with Lagrange multipliers,

    [ M    Phi_q^T ] [ q'' ]   [ Q_e ]
    [ Phi_q   0    ] [ lam ] = [ gamma ],

with the motor torque (through an ideal gear of ratio i) on the crank's angle and the drive's
rotors as extra inertia of the crank, give the crank's acceleration; positions are solved by
Newton's method on Phi(q) = 0 with the crank angle prescribed (continued from the previous
position), velocities from Phi_q q' = 0 with the crank's speed prescribed. The crank's speed is
integrated over its angle, d omega/d phi = eps / omega, d t/d phi = 1/omega, by scipy's DOP853
(rtol 1e-12), and the periodic solution found by the secant method on omega(phi0 + 2 pi) =
omega(phi0). From linkwork only the mechanism's data (points, masses, inertias, joint
geometry) and, once, the engine's pose at the first position as Newton's starting guess (it picks
the assembly branch) are read.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from scipy.integrate import solve_ivp

from linkwork.planar import PinInSlot, Prismatic, Revolute, kinematics

ROT90 = np.array([[0.0, -1.0], [1.0, 0.0]])


def _A(th: float) -> np.ndarray:
    c, s = math.cos(th), math.sin(th)
    return np.array([[c, -s], [s, c]])


class Multibody:
    """The mechanism ``mech`` as a constrained multibody system (see the module docstring).

    ``torque(phi, omega) -> float``: the driving torque on the crank [N m] (motor through the
    gear); ``rotors``: extra inertia on the crank [kg m^2]; ``gravity`` (gx, gy);
    ``loads(phi) -> list of ("force", body, local point, fx, fy) or ("torque", body, mz)``.
    """

    def __init__(self, mech, torque: Callable[[float, float], float], *, rotors: float = 0.0,
                 gravity=(0.0, 0.0), loads=None) -> None:
        self.mech = mech
        self.names = [b.name for b in mech.bodies]
        self.idx = {n: k for k, n in enumerate(self.names)}
        self.nb = len(self.names)
        self.com = {b.name: np.array(b.com, float) for b in mech.bodies}
        self.com[mech.frame.name] = np.zeros(2)
        self.bodies = {b.name: b for b in mech.bodies}
        self.bodies[mech.frame.name] = mech.frame
        self.frame = mech.frame.name
        self.torque = torque
        self.gravity = np.asarray(gravity, float)
        self.loads = loads
        drv = mech.joint(mech.driver.joint)
        self.crank = drv.b if drv.a == self.frame else drv.a
        self.crank_sign = 1.0 if drv.b == self.crank else -1.0  # phi1 = theta_b - theta_a
        M = np.zeros(3 * self.nb)
        for k, n in enumerate(self.names):
            b = self.bodies[n]
            M[3 * k:3 * k + 3] = (b.mass, b.mass, b.inertia)
        M[3 * self.idx[self.crank] + 2] += rotors
        self.M = np.diag(M)
        self.joints = []
        for j in mech.joints:
            ba, bb = self.bodies[j.a], self.bodies[j.b]
            if isinstance(j, Revolute):
                pa = np.array(ba.point(j.point_a or j.name), float) - self.com[j.a]
                pb = np.array(bb.point(j.point_b or j.name), float) - self.com[j.b]
                self.joints.append(("R", j.a, j.b, pa, pb))
            else:
                thr = j.through if j.through is not None else j.name
                qa = np.array(ba.point(thr) if isinstance(thr, str) else thr, float) - self.com[j.a]
                pb = np.array(bb.point(j.point or j.name), float) - self.com[j.b]
                nu = np.array([-math.sin(j.angle), math.cos(j.angle)])
                rel = j.rel_angle if isinstance(j, Prismatic) else None
                assert isinstance(j, Prismatic | PinInSlot)
                self.joints.append(("L", j.a, j.b, qa, pb, nu, rel))
        self.q = None

    # -- body state helpers --------------------------------------------------------------
    def _pose(self, q, name):
        if name == self.frame:
            return np.zeros(2), 0.0
        k = self.idx[name]
        return q[3 * k:3 * k + 2], q[3 * k + 2]

    def _cols(self, name):
        return None if name == self.frame else 3 * self.idx[name]

    def constraints(self, q, qd=None):
        """Phi (m,), Phi_q (m, 3 nb) and, with velocities, gamma (m,); plain float arithmetic
        (the 2-vectors are tuples: numpy is slow on arrays of two)."""
        rows, jrows, gam = [], [], []
        n = 3 * self.nb

        def state(name):
            if name == self.frame:
                return None, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
            k = 3 * self.idx[name]
            if qd is None:
                return k, q[k], q[k + 1], q[k + 2], 0.0, 0.0, 0.0
            return k, q[k], q[k + 1], q[k + 2], qd[k], qd[k + 1], qd[k + 2]

        for jt in self.joints:
            ca, xa, ya, ta, vxa, vya, wa = state(jt[1])
            cb, xb, yb, tb, vxb, vyb, wb = state(jt[2])
            c_a, s_a = math.cos(ta), math.sin(ta)
            c_b, s_b = math.cos(tb), math.sin(tb)
            if jt[0] == "R":
                (pax, pay), (pbx, pby) = jt[3], jt[4]
                Apa = (c_a * pax - s_a * pay, s_a * pax + c_a * pay)  # A_a pa; B_a pa = rot90
                Apb = (c_b * pbx - s_b * pby, s_b * pbx + c_b * pby)
                rows += [xa + Apa[0] - xb - Apb[0], ya + Apa[1] - yb - Apb[1]]
                for comp in (0, 1):
                    row = np.zeros(n)
                    if ca is not None:
                        row[ca + comp] = 1.0
                        row[ca + 2] = -Apa[1] if comp == 0 else Apa[0]
                    if cb is not None:
                        row[cb + comp] = -1.0
                        row[cb + 2] = Apb[1] if comp == 0 else -Apb[0]
                    jrows.append(row)
                gam += [Apa[0] * wa**2 - Apb[0] * wb**2, Apa[1] * wa**2 - Apb[1] * wb**2]
            else:
                (qax, qay), (pbx, pby), (nux, nuy), rel = jt[3], jt[4], jt[5], jt[6]
                nx, ny = c_a * nux - s_a * nuy, s_a * nux + c_a * nuy       # A_a nu
                Bnx, Bny = -ny, nx                                           # B_a nu
                Aqa = (c_a * qax - s_a * qay, s_a * qax + c_a * qay)
                Apb = (c_b * pbx - s_b * pby, s_b * pbx + c_b * pby)
                Dx = xb + Apb[0] - xa - Aqa[0]
                Dy = yb + Apb[1] - ya - Aqa[1]
                rows.append(nx * Dx + ny * Dy)
                row = np.zeros(n)
                if cb is not None:
                    row[cb], row[cb + 1] = nx, ny
                    row[cb + 2] = nx * -Apb[1] + ny * Apb[0]
                if ca is not None:
                    row[ca], row[ca + 1] = -nx, -ny
                    row[ca + 2] = Bnx * Dx + Bny * Dy - (nx * -Aqa[1] + ny * Aqa[0])
                jrows.append(row)
                ndx, ndy = Bnx * wa, Bny * wa
                Ddx = vxb - Apb[1] * wb - vxa + Aqa[1] * wa
                Ddy = vyb + Apb[0] * wb - vya - Aqa[0] * wa
                quad = (-(nx * Dx + ny * Dy) * wa**2 + 2 * (ndx * Ddx + ndy * Ddy)
                        + nx * (-Apb[0] * wb**2 + Aqa[0] * wa**2)
                        + ny * (-Apb[1] * wb**2 + Aqa[1] * wa**2))
                gam.append(-quad)
                if rel is not None:
                    rows.append(tb - ta - rel)
                    row = np.zeros(n)
                    if cb is not None:
                        row[cb + 2] = 1.0
                    if ca is not None:
                        row[ca + 2] = -1.0
                    jrows.append(row)
                    gam.append(0.0)
        return np.array(rows), np.array(jrows), np.array(gam)

    def _drive_row(self):
        row = np.zeros(3 * self.nb)
        row[3 * self.idx[self.crank] + 2] = self.crank_sign
        return row

    def solve_positions(self, phi):
        q = self.q + self.dq * (phi - self.phi_last)  # first-order prediction
        row = self._drive_row()
        for _ in range(50):
            r, J, _ = self.constraints(q)
            r = np.append(r, row @ q - phi)
            step = np.linalg.solve(np.vstack((J, row)), -r)
            q += step
            if np.max(np.abs(step)) < 1e-13 * (1 + np.max(np.abs(q))):
                break
        r, _, _ = self.constraints(q)
        assert np.max(np.abs(r)) < 1e-12, r
        self.q = q
        self.phi_last = phi
        return q

    def start(self, phi0):
        """Newton's starting pose: the engine's at phi0 (only to pick the branch)."""
        kin = kinematics(self.mech, [phi0], 1.0, 0.0)
        q = np.zeros(3 * self.nb)
        for k, n in enumerate(self.names):
            i = kin.bodies.index(n)
            c = self.com[n]
            th = kin.theta[i, 0]
            q[3 * k:3 * k + 2] = (kin.x[i, 0], kin.y[i, 0]) + _A(th) @ c
            q[3 * k + 2] = th
        self.q = q
        self.dq = np.zeros_like(q)
        self.phi_last = phi0
        self.solve_positions(phi0)

    def accel(self, phi, omega):
        """The crank's acceleration at (phi, omega)."""
        q = self.solve_positions(phi)
        _, J, _ = self.constraints(q)
        row = self._drive_row()
        self.dq = np.linalg.solve(np.vstack((J, row)), np.append(np.zeros(J.shape[0]), 1.0))
        qd = self.dq * omega
        _, J, gam = self.constraints(q, qd)
        Qe = np.zeros(3 * self.nb)
        for k, n in enumerate(self.names):
            Qe[3 * k:3 * k + 2] += self.bodies[n].mass * self.gravity
        for ld in (self.loads(phi) if self.loads else []):
            k = 3 * self.idx[ld[1]]
            if ld[0] == "force":
                p = np.array(ld[2], float) - self.com[ld[1]]
                F = np.array([ld[3], ld[4]], float)
                Qe[k:k + 2] += F
                rp = _A(q[k + 2]) @ p
                Qe[k + 2] += rp[0] * F[1] - rp[1] * F[0]
            else:
                Qe[k + 2] += ld[2]
        Qe[3 * self.idx[self.crank] + 2] += self.crank_sign * self.torque(phi, omega)
        m = J.shape[0]
        K = np.block([[self.M, J.T], [J, np.zeros((m, m))]])
        sol = np.linalg.solve(K, np.concatenate((Qe, gam)))
        return self.crank_sign * sol[3 * self.idx[self.crank] + 2]

    def cycle(self, phi0, omega0, phis=None, rtol=1e-11):
        """omega and t over one revolution from (phi0, omega0); values at ``phis``."""
        self.start(phi0)

        def rhs(phi, y):
            eps = self.accel(phi, y[0])
            return [eps / y[0], 1.0 / y[0]]

        sol = solve_ivp(rhs, (phi0, phi0 + 2 * math.pi), [omega0, 0.0], method="DOP853",
                        rtol=rtol, atol=1e-14 * omega0, dense_output=True)
        assert sol.success
        end = sol.y[:, -1]
        vals = None if phis is None else sol.sol(phis)
        return end, vals

    def periodic(self, phi0, omega_guess, phis=None, tol=1e-11):
        """The periodic solution by the secant method on f(w) = omega(phi0 + 2 pi; w) - w from
        ``omega_guess`` (any start: the secant converges to this model's own cycle; a good one
        saves revolutions); returns omega0, the end state (omega, period) and the values at
        ``phis``."""
        w0 = omega_guess
        f0 = self.cycle(phi0, w0)[0][0] - w0
        w1 = w0 * (1 + 1e-5)
        run = self.cycle(phi0, w1, phis)
        f1 = run[0][0] - w1
        for _ in range(40):
            w2 = w1 - f1 * (w1 - w0) / (f1 - f0)
            w0, f0 = w1, f1
            w1 = w2
            run = self.cycle(phi0, w1, phis)
            f1 = run[0][0] - w1
            if abs(f1) < tol * abs(w1):
                break
        return w1, run[0], run[1]


def run_in_time(mb: Multibody, phi0: float, t_end: float, *, omega0: float = 0.0,
                factor=None, rtol: float = 1e-11):
    """The motion in time from (phi0, omega0), y = (phi, omega), DOP853; ``factor(t)`` scales
    the loads (the Multibody's ``loads`` and gravity untouched). Returns the dense solution."""
    mb.start(phi0)
    base = mb.loads

    def rhs(t, y):
        if factor is not None and base is not None:
            f = factor(t)
            mb.loads = lambda p: [(*ld[:-2], ld[-2] * f, ld[-1] * f) if ld[0] == "force"
                                  else (ld[0], ld[1], ld[2] * f) for ld in base(p)]
        eps = mb.accel(y[0], y[1])
        return [y[1], eps]

    sol = solve_ivp(rhs, (0.0, t_end), [phi0, omega0], method="DOP853", rtol=rtol,
                    atol=1e-13, dense_output=True)
    mb.loads = base
    assert sol.success
    return sol.sol
