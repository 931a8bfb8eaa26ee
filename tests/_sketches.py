"""Drawings of mechanisms for the tests of the ``[sketch]`` table: the planar file text of a
mechanism given by world coordinates as drawn."""

from __future__ import annotations

import math

import numpy as np

from linkwork.planar import kinematics


def drawing_of(mech, phi):
    """World coordinates of every named point of ``mech`` at driver position ``phi``."""
    kin = kinematics(mech, [phi])
    pts = {p: tuple(map(float, v)) for p, v in mech.frame.points.items()}
    for b in mech.bodies:
        for p in b.points:
            pm = kin.point(b.name, p)
            pts[p] = (float(pm.x[0]), float(pm.y[0]))
    return pts


def paper001_drawing() -> str:
    """Paper 001's four-bar (examples/fourbar_paper001.toml) as its drawing at phi1 = 0:
    points by circle intersection, printed to 17 digits."""
    a, b, c, d = 0.1, 0.3, 0.2, 0.3
    A = np.array([a, 0.0])
    C = np.array([d, 0.0])
    dd = np.hypot(*(C - A))
    x = (b * b - c * c + dd * dd) / (2 * dd)
    h = math.sqrt(b * b - x * x)
    e = (C - A) / dd
    B = A + x * e + h * np.array([-e[1], e[0]])  # branch +1: left of A -> C
    u = (B - A) / b
    P = A + 0.15 * u + 0.1 * np.array([-u[1], u[0]])
    mid = (A + B) / 2

    def xy(p):
        return f"[{float(p[0])!r}, {float(p[1])!r}]"

    return f"""type = "planar"
name = "Four-bar of paper 001, drawn"

[sketch]
points = {{ O = [0, 0], C = [0.3, 0], A = {xy(A)}, B = {xy(B)}, P = {xy(P)} }}
ground = ["O", "C"]
links = {{ crank = ["O", "A"], coupler = ["A", "B", "P"], rocker = ["C", "B"] }}

[sketch.masses]
crank = {{ mass = "1 kg", inertia = "0.000833 kg*m^2" }}
coupler = {{ mass = "3 kg", com = {xy(mid)}, inertia = "0.0225 kg*m^2" }}
rocker = {{ mass = "2 kg", inertia = "0.00567 kg*m^2" }}

[driver]
joint = "O"
omega1 = "10 rad/s"

[analysis]
n = 361
about = [0, 0]
"""
