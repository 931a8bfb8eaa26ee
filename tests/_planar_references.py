"""Driving torques and energies of the bundled planar examples computed by hand (power balance,
written-out positions), shared by the ``linkwork analyze`` tests and the docs examples tests."""

from __future__ import annotations

import numpy as np


def _fourbar_torque(phi: np.ndarray, inertia: tuple[float, float, float], gy: float = 0.0,
                    fy_B: float = 0.0, mz_rocker: float = 0.0) -> np.ndarray:
    """Paper 001's four-bar (O at 0, C at 0.3 m on +x; 0.1/0.3/0.2 m; 1/3/2 kg at the
    midpoints; 10 rad/s; B on the left of A -> C) with gravity ``gy`` along y, a force ``fy_B``
    at B and a torque ``mz_rocker`` on the rocker: Q omega1 = dT/dt - P_loads, with T and the
    loads' power from finite differences of the positions written out here."""
    a, b, c, d, w = 0.1, 0.3, 0.2, 0.3, 10.0
    m = np.array([1.0, 3.0, 2.0])

    def coords(p: np.ndarray) -> np.ndarray:
        A = np.stack([a * np.cos(p), a * np.sin(p)])
        C = np.array([[d], [0.0]])
        AC = C - A
        L = np.hypot(*AC)
        x = (b * b - c * c + L * L) / (2 * L)
        u = AC / L
        B = A + x * u + np.sqrt(b * b - x * x) * np.stack([-u[1], u[0]])  # left of A -> C
        th2 = np.unwrap(np.arctan2(B[1] - A[1], B[0] - A[0]))
        th3 = np.unwrap(np.arctan2(B[1] - C[1], B[0] - C[0]))
        return np.stack([*(A / 2), p, *((A + B) / 2), th2, *((B + C) / 2), th3, B[1]])

    def rates(p: np.ndarray, h: float = 1e-6) -> np.ndarray:
        return (coords(p + h) - coords(p - h)) / (2 * h) * w

    def energy(p: np.ndarray) -> np.ndarray:
        qd = rates(p)
        return sum(0.5 * (m[k] * (qd[3 * k] ** 2 + qd[3 * k + 1] ** 2)
                          + inertia[k] * qd[3 * k + 2] ** 2) for k in range(3))

    h = 1e-4
    qd = rates(phi)
    power = gy * sum(m[k] * qd[3 * k + 1] for k in range(3)) + fy_B * qd[9] + mz_rocker * qd[8]
    return (energy(phi + h) - energy(phi - h)) / (2 * h) - power / w


def _fourbar_paper001_torque(phi: np.ndarray) -> np.ndarray:
    """examples/fourbar_paper001.toml: the inertias of its file, no gravity, no loads."""
    return _fourbar_torque(phi, (0.000833, 0.0225, 0.00567))


def _crank_rod_slider_energy(qd: np.ndarray, r: float, l: float) -> np.ndarray:
    """Kinetic energy [J] of a crank r and rod l (thin rods of 1 and 2 kg) and a 3 kg slider
    from the rates of (crank centre x, y, angle, rod centre x, y, angle, slider x)."""
    return (0.5 * (1.0 * (qd[0] ** 2 + qd[1] ** 2) + 1.0 * r * r / 12 * qd[2] ** 2)
            + 0.5 * (2.0 * (qd[3] ** 2 + qd[4] ** 2) + 2.0 * l * l / 12 * qd[5] ** 2)
            + 0.5 * 3.0 * qd[6] ** 2)
