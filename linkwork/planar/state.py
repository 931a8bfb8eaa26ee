"""The solver's state: pose, velocity and acceleration of every body over a chunk of positions.

Body ``i`` holds arrays over the positions: origin ``X, Y`` [m], angle ``T`` [rad] with its cosine
``C`` and sine ``S``, origin velocity ``VX, VY`` [m/s], angular velocity ``W`` [rad/s], origin
acceleration ``AX, AY`` [m/s^2], angular acceleration ``E`` [rad/s^2]. The position solvers
(:mod:`~linkwork.planar.positions`) fill the poses group by group, the rate solvers
(:mod:`~linkwork.planar.rates`) the velocities and accelerations.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["Arr", "State", "Vec"]

Arr = np.ndarray
Vec = tuple[Arr, Arr]


class State:
    """Poses, velocities and accelerations of all bodies (lists indexed by body) over n
    positions, the positions that failed, and a cache of rotated local vectors."""

    def __init__(self, nb: int, n: int) -> None:
        z = np.zeros(n)
        self.n = n
        self.X = [z] * nb
        self.Y = [z] * nb
        self.T = [z] * nb
        self.C = [z + 1.0] * nb
        self.S = [z] * nb
        self.VX = [z] * nb
        self.VY = [z] * nb
        self.W = [z] * nb
        self.AX = [z] * nb
        self.AY = [z] * nb
        self.E = [z] * nb
        self.bad = np.zeros(n, dtype=bool)
        self.pos_bad = self.bad
        self.failed: dict[str, Arr] = {}  # group key -> positions where it does not close
        self.parallel = False  # set when two lines of the group being solved were parallel
        self.parallel_groups: set[str] = set()
        self._rot: dict[tuple[Any, ...], Any] = {}

    def set_angle(self, i: int, th: Arr, c: Arr | None = None, s: Arr | None = None) -> None:
        """Set body i's angle (with its cosine and sine when already known)."""
        self.T[i] = th
        self.C[i] = np.cos(th) if c is None else c
        self.S[i] = np.sin(th) if s is None else s
        if self._rot:
            self._rot = {k: v for k, v in self._rot.items() if k[0] != i}

    def rot(self, i: int, v: tuple[Any, Any]) -> Vec:
        """A local vector of body i in frame axes (cached per body and vector; the components
        are numbers, or arrays over the elements of a batch of designs)."""
        x, y = v
        if type(x) is not float or type(y) is not float:
            if isinstance(x, np.ndarray) or isinstance(y, np.ndarray):
                return self._rot_array(i, x, y)
            x, y = float(x), float(y)
        key = (i, x, y)
        hit = self._rot.get(key)
        if hit is not None:
            return hit
        c, s = self.C[i], self.S[i]
        if y == 0.0:
            out = (c * x, s * x)
        elif x == 0.0:
            out = (-s * y, c * y)
        else:
            out = (c * x - s * y, s * x + c * y)
        self._rot[key] = out
        return out

    def _rot_array(self, i: int, x: Any, y: Any) -> Vec:
        """:meth:`rot` of a vector that varies over the designs: cached by the arrays'
        identity (the cache holds them, so that no other array takes their place)."""
        key = (i, id(x), id(y))
        hit = self._rot.get(key)
        if hit is not None:
            return hit[0]
        c, s = self.C[i], self.S[i]
        out = (c * x - s * y, s * x + c * y)
        self._rot[key] = (out, x, y)
        return out

    def wpt(self, i: int, p: tuple[float, float]) -> Vec:
        rx, ry = self.rot(i, p)
        return self.X[i] + rx, self.Y[i] + ry

    def place(self, i: int, p: tuple[float, float], world: Vec) -> None:
        """Set the origin of body i so that its local point p is at ``world`` (angle known)."""
        rx, ry = self.rot(i, p)
        self.X[i] = world[0] - rx
        self.Y[i] = world[1] - ry

    def point_vel(self, i: int, p: tuple[float, float]) -> Vec:
        rx, ry = self.rot(i, p)
        return self.VX[i] - self.W[i] * ry, self.VY[i] + self.W[i] * rx

    def point_acc(self, i: int, p: tuple[float, float]) -> Vec:
        rx, ry = self.rot(i, p)
        w2 = self.W[i] ** 2
        return (self.AX[i] - self.E[i] * ry - w2 * rx, self.AY[i] + self.E[i] * rx - w2 * ry)
