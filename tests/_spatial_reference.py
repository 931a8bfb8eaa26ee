"""An independent spatial reaction solver for planar mechanisms of the engine, written from
the definitions (not from linkwork.redundancy): per position, the small displacements of every
moving body (translation of its origin point and rotation, 6 each) minimise the potential
energy of the joints' springs under the body loads, with every driver held rigid by a Lagrange
multiplier (the core holds it by a stiff spring instead).

Joint model (docs/conventions.md "Spatial reactions"): a joint j between a and b at
``p = (x, y, z)`` has the relative motion of b's point at p against a's, ``(t_b + r_b x p -
t_a - r_a x p, r_b - r_a)``, plus the misfit ``R(theta_b) d_b - R(theta_a) d_a`` of the
deviations; in the joint's local frame (global for a revolute; (d, n, z) for a prismatic
joint, d its slide direction; (n, t, z) for a gear mesh, n its line of action) its springs
act on the constrained components with stiffness ``k_b`` radial, ``axial_ratio k_b`` axial
and ``k_b e^2/12`` in tilt; the reaction on b is ``-K s``. The driving torque (force) of a
driver is the multiplier of its rigid row: the relative rotation about z (the relative
translation along d).

Body loads, from the mass properties and the engine's kinematics: ``m (g - a_S)`` at the
centre of mass lifted to the body's height, ``-I eps`` about z, and point forces
``(body, point, fx, fy)`` at the same height.
"""

from __future__ import annotations

import numpy as np

#: constrained local components of the kinds used here
KINDS = {"revolute": (0, 1, 2, 3, 4), "spherical": (0, 1, 2), "prismatic": (1, 2, 3, 4, 5),
         "spur": (0, 4), "crowned": (0,)}


def _skew(p):
    x, y, z = p
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def _rot6(a):
    c, s = np.cos(a), np.sin(a)
    r = np.zeros((6, 6))
    for o in (0, 3):
        r[o:o + 3, o:o + 3] = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
    return r


def stiffness(kind, e, kb, axial_ratio=1.0):
    """The six local stiffnesses of a joint (0 where free)."""
    kt = kb * e * e / 12.0
    full = {"revolute": [kb, kb, axial_ratio * kb, kt, kt, 0.0],
            "spherical": [kb, kb, axial_ratio * kb, 0.0, 0.0, 0.0],
            "prismatic": [0.0, kb, axial_ratio * kb, kt, kt, kt],
            "spur": [kb, 0.0, 0.0, 0.0, kt, 0.0],
            "crowned": [kb, 0.0, 0.0, 0.0, 0.0, 0.0]}[kind]
    return np.array(full)


def reactions(mech, kin, *, spec, frames, centres, heights=None, devs=(), gravity=(0.0, 0.0),
              forces=(), drivers=None):
    """Reactions (n_joints, 6, n) by a on b at the joint centres (global components) and the
    driving loads (n_drivers, n).

    ``spec``: joint name -> (kind, e, z, k_b); ``frames``: joint name -> its local x-axis
    angle per position (n,) (0 for a revolute); ``centres``: joint name -> (x, y) arrays of its
    centre; ``devs``: (joint, body, 6-vector) in the body's frame; ``forces``: (body, point,
    fx, fy); ``drivers``: joint names (default the mechanism's).
    """
    heights = dict(heights or {})
    bodies = [b.name for b in mech.bodies]
    nb = len(bodies)
    drivers = [d.joint for d in mech.drivers] if drivers is None else list(drivers)
    n = kin.theta.shape[1]
    out = np.zeros((len(mech.joints), 6, n))
    Q = np.zeros((len(drivers), n))
    g = np.asarray(gravity, float)
    for k in range(n):
        f = np.zeros(6 * nb)
        for i, b in enumerate(mech.bodies):
            c = kin.point(b.name, "com")
            p = np.array([c.x[k], c.y[k], heights.get(b.name, 0.0)])
            F = np.array([b.mass * (g[0] - c.ax[k]), b.mass * (g[1] - c.ay[k]), 0.0])
            M = np.array([0.0, 0.0, -b.inertia * kin.eps[kin.bodies.index(b.name)][k]])
            f[6 * i:6 * i + 3] += F
            f[6 * i + 3:6 * i + 6] += M + np.cross(p, F)
        for body, point, fx, fy in forces:
            q = kin.point(body, point)
            p = np.array([q.x[k], q.y[k], heights.get(body, 0.0)])
            F = np.array([fx, fy, 0.0])
            i = bodies.index(body)
            f[6 * i:6 * i + 3] += F
            f[6 * i + 3:6 * i + 6] += np.cross(p, F)
        K = np.zeros((6 * nb, 6 * nb))
        rows = []
        for j in mech.joints:
            kind, e, z, kb = spec[j.name]
            x, y = centres[j.name]
            p = np.array([x[k], y[k], z])
            # relative motion of b against a at p (global), 6 x 6nb
            B = np.zeros((6, 6 * nb))
            delta = np.zeros(6)
            for body, sign in ((j.a, -1.0), (j.b, 1.0)):
                dv = sum((np.asarray(d, float) for jn, bn, d in devs
                          if jn == j.name and bn == body), np.zeros(6))
                if body == mech.frame.name:
                    delta += sign * dv
                    continue
                i = bodies.index(body)
                delta += sign * _rot6(kin.angle(body)[k]) @ dv
                B[:3, 6 * i:6 * i + 3] += sign * np.eye(3)
                B[:3, 6 * i + 3:6 * i + 6] += -sign * _skew(p)
                B[3:, 6 * i + 3:6 * i + 6] += sign * np.eye(3)
            L = _rot6(frames[j.name][k]).T  # global -> local
            Bl, dl = L @ B, L @ delta
            kv = stiffness(kind, e, kb)
            K += Bl.T @ (kv[:, None] * Bl)
            f -= Bl.T @ (kv * dl)
            rows.append((Bl, dl, kv, L))
        G = np.zeros((len(drivers), 6 * nb))
        for m, name in enumerate(drivers):
            jj = [jt.name for jt in mech.joints].index(name)
            Bl = rows[jj][0]
            G[m] = Bl[5] if spec[name][0] != "prismatic" else Bl[0]
        kkt = np.block([[K, G.T], [G, np.zeros((len(drivers), len(drivers)))]])
        sol = np.linalg.solve(kkt, np.concatenate([f, np.zeros(len(drivers))]))
        u, lam = sol[:6 * nb], sol[6 * nb:]
        for jj, (Bl, dl, kv, L) in enumerate(rows):
            r_loc = -kv * (Bl @ u + dl)
            name = mech.joints[jj].name
            if name in drivers:  # the driver's load, carried by the joint too
                m = drivers.index(name)
                comp = 5 if spec[name][0] != "prismatic" else 0
                r_loc[comp] += -lam[m]
                Q[m, k] = -lam[m]
            out[jj, :, k] = L.T @ r_loc
    return out, Q
