"""Independent references for paper 000's crank-slider and sine mechanism: the bare loop-closure
equations solved by a Newton iteration of our own (scipy ``fsolve`` for the real start),
velocities by the complex-step derivative of that solver in time and accelerations by a 4th-
order central difference of the complex-step velocities (truncation ~1e-12).  The crank moves as
``phi1(t) = phi10 + omega1 t + eps1 t^2 / 2``, so ``eps1 != 0`` is part of the reference.
``_close``: tolerance 1e-6 relative to the quantity (``RTOL``), with an absolute floor of 1e-9
of the quantity's scale (for values that pass through zero, e.g. velocities at a dead centre);
it records the largest deviation per quantity in ``DEV``."""

from __future__ import annotations

import math

import numpy as np

RTOL = 1e-6


DEV: dict[str, float] = {}


def _newton(residual, q0, t, iters=60):
    """Root of residual(q, t) = 0 near real q0; t may be complex (complex step).

    Real Newton iterations with a forward-difference Jacobian from q0, then the same (frozen)
    Jacobian on the complex problem, which converges to the complex root linearly.
    """
    qr = np.asarray(q0, dtype=float)
    n = len(qr)
    for _ in range(iters):
        r0 = np.real(residual(qr, t.real))
        jac = np.empty((n, n))
        for k in range(n):
            dq = np.zeros(n)
            dq[k] = 1e-7 * max(1.0, abs(qr[k]))
            jac[:, k] = (np.real(residual(qr + dq, t.real)) - r0) / dq[k]
        step = np.linalg.solve(jac, r0)
        qr = qr - step
        if np.all(np.abs(step) <= 1e-15 * (1 + np.abs(qr))):
            break
    q = qr.astype(complex)
    for _ in range(iters):
        q = q - np.linalg.solve(jac, residual(q, t))
    return q


def _motion(position, t0=0.0, hc=1e-30, hd=1e-3):
    """(value, d/dt, d2/dt2) of position(t) (complex-capable) at t0."""
    def vel(t):
        return np.imag(position(t + 1j * hc)) / hc
    x = np.real(position(t0 + 0j))
    v = vel(t0)
    a = (-vel(t0 + 2 * hd) + 8 * vel(t0 + hd) - 8 * vel(t0 - hd) + vel(t0 - 2 * hd)) / (12 * hd)
    return x, v, a


def _close(actual, expected, scale, name):
    actual = np.asarray(actual, dtype=float)
    expected = np.asarray(expected, dtype=float)
    err = np.abs(actual - expected)
    lim = RTOL * np.abs(expected) + 1e-9 * scale
    rel = float(np.max(err / np.maximum(np.abs(expected), 1e-9 * scale)))
    DEV[name] = max(DEV.get(name, 0.0), rel)
    assert np.all(err <= lim), (name, actual, expected, rel)
    return rel


def _cs_reference(L1, lam2, lame, w1, e1, branch, phi10):
    L2, e = lam2 * L1, lame * L1

    def phi(t):
        return phi10 + w1 * t + 0.5 * e1 * t * t

    # unknowns: rod angle psi = atan2(C - B) in the usual sense, slider Y_C
    def residual(q, t):
        ph = phi(t)
        return np.array([L1 * np.cos(ph) + L2 * np.cos(q[0]) - e,
                         L1 * np.sin(ph) + L2 * np.sin(q[0]) - q[1]])

    # start: the rod pointing up (branch +1) or down (branch -1) from the crank pin
    q0 = np.array([np.pi / 2 * branch, L1 * math.sin(phi10) + branch * L2])

    def position(t):
        q = _newton(residual, q0, np.asarray(t, dtype=complex))
        # phi2 as the paper defines it: from +Y towards +X -> pi/2 - psi
        return np.array([q[1], np.pi / 2 - q[0]])

    (yc, phi2), (vc, w2), (ac, e2) = _motion(position, hd=2e-3 / max(abs(w1), 1.0))
    return dict(Y_C=yc, phi2=phi2, V_C=vc, omega2=w2, a_C=ac, eps2=e2)


def _sine_reference(L1, alpha, w1, e1, phi10):
    def phi(t):
        return phi10 + w1 * t + 0.5 * e1 * t * t

    d = np.array([math.cos(alpha), math.sin(alpha)])

    # unknowns: xs = where the slot's line crosses the x axis (a point fixed in the ram), u =
    # block position along the slot from that point; B = (xs, 0) + u d
    def residual(q, t):
        ph = phi(t)
        return np.array([L1 * np.cos(ph) - q[0] - q[1] * d[0], L1 * np.sin(ph) - q[1] * d[1]])

    def solve(t):
        return _newton(residual, np.array([L1, 0.0]), np.asarray(t, dtype=complex))

    xs0 = _newton(lambda q, t: np.array([L1 - q[0] - q[1] * d[0], -q[1] * d[1]]),
                  np.array([L1, 0.0]), np.asarray(0j)).real[0]

    def position(t):
        q = solve(t)
        # X3: ram displacement from its phi1 = 0 position, towards the crank axis (-x)
        return np.array([xs0 - q[0], q[1]])

    (x3, x32), (v3, v32), (a3, a32) = _motion(position, hd=2e-3 / max(abs(w1), 1.0))
    return dict(X3=x3, X32=x32, V3=v3, V32=v32, a3=a3, a32=a32)
