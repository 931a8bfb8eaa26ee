"""An independent four-bar (kinematics, planar kinetostatics, spatial loads) for the redundancy
tests, written from scratch here (not linkwork's four-bar or engine); its own checks are in
``tests/redundancy/test_fourbar_reference.py``.

The mechanism is the four-bar of paper 001 (used by paper 004's loom example): O = (0, 0),
C = (0.3, 0); OA = 0.1 m, AB = 0.3 m, BC = 0.2 m; centres of mass 0.05 m from O on the crank,
0.15 m from A on the coupler, 0.1 m from B on the rocker; m = 1, 3, 2 kg; I_S = 0.001, 0.0225,
0.00567 kg m²; omega1 = 10 rad/s; gravity -y; an external moment on the rocker.
"""

from __future__ import annotations

import numpy as np

from linkwork.redundancy import SpatialGeometry, SpatialJoint, SpatialModel, wrench_about_origin

L0, L1, L2, L3 = 0.3, 0.1, 0.3, 0.2
MASS = np.array([1.0, 3.0, 2.0])
INERTIA = np.array([0.001, 0.0225, 0.00567])
OMEGA1 = 10.0
G = 9.81
M_EXT = 4.0  # external moment on the rocker [N m]


def kinematics(phi1, omega1=OMEGA1, eps1=0.0):
    """Positions (A, B), link angles, angular velocities and accelerations (open branch)."""
    phi1 = np.asarray(phi1, float)
    a = L1 * np.stack([np.cos(phi1), np.sin(phi1)], -1)
    c = np.array([L0, 0.0])
    d = c - a
    dist = np.linalg.norm(d, axis=-1)
    # circle-circle intersection: B on circle (A, L2) and (C, L3), left of A->C (upper branch)
    along = (L2**2 - L3**2 + dist**2) / (2 * dist)
    h = np.sqrt(L2**2 - along**2)
    u = d / dist[:, None]
    perp = np.stack([-u[:, 1], u[:, 0]], -1)
    b = a + along[:, None] * u + h[:, None] * perp
    phi2 = np.arctan2(b[:, 1] - a[:, 1], b[:, 0] - a[:, 0])
    phi3 = np.arctan2(b[:, 1] - c[1], b[:, 0] - c[0])
    # velocities: d/dt (L1 e1 + L2 e2 - L3 e3) = 0
    def solve(rhs_x, rhs_y):
        # unknowns (w2, w3): -L2 s2 w2 + L3 s3 w3 = rhs_x ; L2 c2 w2 - L3 c3 w3 = rhs_y
        m = np.array([[-L2 * np.sin(phi2), L3 * np.sin(phi3)],
                      [L2 * np.cos(phi2), -L3 * np.cos(phi3)]]).transpose(2, 0, 1)
        return np.linalg.solve(m, np.stack([rhs_x, rhs_y], -1)[..., None])[..., 0]

    w = solve(L1 * np.sin(phi1) * omega1, -L1 * np.cos(phi1) * omega1)
    w2, w3 = w[:, 0], w[:, 1]
    rx = (L1 * np.sin(phi1) * eps1 + L1 * np.cos(phi1) * omega1**2
          + L2 * np.cos(phi2) * w2**2 - L3 * np.cos(phi3) * w3**2)
    ry = (-L1 * np.cos(phi1) * eps1 + L1 * np.sin(phi1) * omega1**2
          + L2 * np.sin(phi2) * w2**2 - L3 * np.sin(phi3) * w3**2)
    e = solve(rx, ry)
    return dict(A=a, B=b, C=np.broadcast_to(c, a.shape), O=np.zeros_like(a),
                phi=np.stack([phi1, phi2, phi3], -1),
                omega=np.stack([np.full_like(phi1, omega1), w2, w3], -1),
                eps=np.stack([np.full_like(phi1, eps1), e[:, 0], e[:, 1]], -1))


def _acc(p_ref, a_ref, w, e, r):
    """Acceleration of point r of a body rotating (w, e) whose point p_ref accelerates a_ref."""
    d = r - p_ref
    return a_ref + e[:, None] * np.stack([-d[:, 1], d[:, 0]], -1) - (w**2)[:, None] * d


def loads(phi1, omega1=OMEGA1, eps1=0.0, m_ext=M_EXT, gravity=G):
    """In-plane loads: force on each body at its centre of mass, and moment about z.

    Returns (centres (n, 3, 2), forces (n, 3, 2), moments (n, 3)): gravity + d'Alembert inertia
    forces and moments + the external moment ``m_ext`` on the rocker.
    """
    k = kinematics(phi1, omega1, eps1)
    a, b, c = k["A"], k["B"], k["C"]
    w, e = k["omega"], k["eps"]
    g1 = 0.5 * a
    g2 = a + 0.5 * (b - a)
    g3 = b + 0.5 * (c - b)
    acc_a = _acc(np.zeros_like(a), np.zeros_like(a), w[:, 0], e[:, 0], a)
    acc = np.stack([
        _acc(np.zeros_like(a), np.zeros_like(a), w[:, 0], e[:, 0], g1),
        _acc(a, acc_a, w[:, 1], e[:, 1], g2),
        _acc(c, np.zeros_like(a), w[:, 2], e[:, 2], g3)], 1)
    centres = np.stack([g1, g2, g3], 1)
    forces = -MASS[None, :, None] * acc
    forces[..., 1] -= MASS * gravity
    moments = -INERTIA[None, :] * e
    moments[:, 2] += m_ext
    return centres, forces, moments


def planar_reactions(phi1, **kw):
    """Planar kinetostatics by one 9x9 solve per position (written independently).

    Unknowns: R_O, R_A, R_B, R_C (x, y; each on body b from body a: O ground->crank,
    A crank->coupler, B coupler->rocker, C ground->rocker) and Q on the crank.
    Returns (R (n, 4, 2), Q (n,)).
    """
    k = kinematics(phi1, kw.get("omega1", OMEGA1), kw.get("eps1", 0.0))
    centres, forces, moments = loads(phi1, **kw)
    n = len(np.atleast_1d(phi1))
    pts = [k["O"], k["A"], k["B"], k["C"]]
    conn = [(-1, 0), (0, 1), (1, 2), (-1, 2)]
    r_out = np.zeros((n, 4, 2))
    q = np.zeros(n)
    for i in range(n):
        m = np.zeros((9, 9))
        rhs = np.zeros(9)
        for jj, (ja, jb) in enumerate(conn):
            x, y = pts[jj][i]
            for body, sgn in ((jb, 1.0), (ja, -1.0)):
                if body < 0:
                    continue
                r0 = 3 * body
                m[r0, 2 * jj] += sgn
                m[r0 + 1, 2 * jj + 1] += sgn
                m[r0 + 2, 2 * jj] += -sgn * y
                m[r0 + 2, 2 * jj + 1] += sgn * x
        m[2, 8] = 1.0
        for body in range(3):
            fx, fy = forces[i, body]
            gx, gy = centres[i, body]
            rhs[3 * body:3 * body + 3] = -np.array([fx, fy, gx * fy - gy * fx + moments[i, body]])
        sol = np.linalg.solve(m, rhs)
        r_out[i] = sol[:8].reshape(4, 2)
        q[i] = sol[8]
    return r_out, q


def spatial_model(e=(0.03, 0.03, 0.03, 0.03), z=(0.0, 0.02, 0.02, 0.0), k_bearing=1e8,
                  kinds=("revolute",) * 4, stiffness=None, axial_ratio=1.0):
    """The four-bar as a SpatialModel: bodies crank, coupler, rocker; joints O, A, B, C."""
    conn = [("O", "ground", "crank"), ("A", "crank", "coupler"), ("B", "coupler", "rocker"),
            ("C", "ground", "rocker")]
    joints = tuple(
        SpatialJoint(name, a, b, kind=kinds[i], e=e[i], z=z[i], k_bearing=k_bearing,
                     axial_ratio=axial_ratio,
                     stiffness=None if stiffness is None else tuple(stiffness[i]))
        for i, (name, a, b) in enumerate(conn))
    return SpatialModel(("crank", "coupler", "rocker"), joints, "O")


def geometry(phi1):
    """SpatialGeometry of the four-bar at crank angles phi1."""
    k = kinematics(phi1)
    pts = np.stack([k["O"], k["A"], k["B"], k["C"]], 1)
    return SpatialGeometry(pts, k["phi"])


def wrenches(phi1, z_g=(0.0, 0.0, 0.0), out_of_plane=None, **kw):
    """Body wrenches about the origin; centres of mass at heights z_g; optional extra
    out-of-plane loads (n or 1, 3, 3) = (fz, mx, my) per body."""
    centres, forces, moments = loads(phi1, **kw)
    n = centres.shape[0]
    zg = np.broadcast_to(np.asarray(z_g, float), (n, 3))
    p3 = np.concatenate([centres, zg[..., None]], -1)
    f3 = np.concatenate([forces, np.zeros((n, 3, 1))], -1)
    m3 = np.zeros((n, 3, 3))
    m3[..., 2] = moments
    if out_of_plane is not None:
        oop = np.broadcast_to(np.asarray(out_of_plane, float), (n, 3, 3))
        f3[..., 2] += oop[..., 0]
        m3[..., 0] += oop[..., 1]
        m3[..., 1] += oop[..., 2]
    return wrench_about_origin(f3, m3, p3)
