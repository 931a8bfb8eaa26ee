r"""Synthesised four-bar designs in the literature's parametrisation, and the result of a search.

A four-bar path generator is described as in the path-synthesis literature (Cabrera et al.
[1]_, Acharyya & Mandal [2]_): ``r1`` frame O2O4, ``r2`` crank O2A, ``r3`` coupler AB, ``r4``
rocker O4B, ``rcx``, ``rcy`` the coupler point P in the coupler's frame (origin A, x along
A -> B, y 90 deg counter-clockwise), ``x0``, ``y0`` the crank pivot O2, ``theta0`` the angle of
the frame line O2 -> O4 from the x axis and ``theta2`` the crank angles at the points, measured
from the frame line (so the crank's absolute angle is ``theta0 + theta2``). The assembly branch
(``branch``, +1: B on the left of the directed line A -> O4, as in
:func:`linkwork.models.fourbar.fourbar`) completes the description.

:class:`FourbarDesign` holds one design with its error and the numbers its checks found;
:meth:`FourbarDesign.mechanism` builds the engine model, :meth:`FourbarDesign.to_toml` writes a
``planar`` file that ``linkwork analyze`` reads. :class:`SynthesisResult` holds the designs of a
search, best first, with what the search did (candidates evaluated, rejected per defect, time).

References
----------
.. [1] J. A. Cabrera, A. Simon, M. Prado, "Optimal synthesis of mechanisms with genetic
   algorithms", Mechanism and Machine Theory 37 (2002) 1165-1177.
.. [2] S. K. Acharyya, M. Mandal, "Performance of EAs for four-bar linkage synthesis",
   Mechanism and Machine Theory 44 (2009) 1784-1794.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from linkwork.errors import ParameterError
from linkwork.outputs import atomic_path
from linkwork.planar.model import Body, Crank, Mechanism, Revolute, bar
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = ["PARAMS", "FourbarDesign", "LinkMasses", "SynthesisResult", "coupler_point",
           "design_columns", "run_range", "write_planar_toml"]

TWO_PI = 2.0 * math.pi

#: The literature's parameter names of a four-bar path generator (``theta2`` is a list).
PARAMS = ("r1", "r2", "r3", "r4", "rcx", "rcy", "x0", "y0", "theta0")


# ---------------------------------------------------------------------------------------------
# the closed form, vectorised over designs x crank angles
# ---------------------------------------------------------------------------------------------
def _loop(th2: Any, r1: Any, r2: Any, r3: Any, r4: Any, br: Any) -> tuple[Any, ...]:
    """The loop of a four-bar in the frame of the frame line (origin O2, x along O2 -> O4) at
    crank angles ``th2``: the crank pin ``A``, ``s = O4 - A``, the coupler vector ``u = B - A``
    and ``h2`` (>= 0 where it assembles): ``ax, ay, sx, sy, ux, uy, h2``.

    ``B = A + k s + h s_perp`` with ``k = (r3^2 - r4^2 + |s|^2) / (2 |s|^2)``,
    ``h = br sqrt(h2)``, ``h2 = r3^2/|s|^2 - k^2`` (the closed form of
    :func:`linkwork.models.fourbar.fourbar`)."""
    ax = r2 * np.cos(th2)
    ay = r2 * np.sin(th2)
    sx = r1 - ax
    sy = -ay
    f2 = sx * sx + sy * sy
    k = (r3 * r3 - r4 * r4 + f2) / (2.0 * f2)
    h2 = r3 * r3 / f2 - k * k
    h = br * np.sqrt(np.maximum(h2, 0.0))
    return ax, ay, sx, sy, k * sx - h * sy, k * sy + h * sx, h2


def _kernel(th2: Any, *geometry: Any) -> tuple[Any, Any, Any, Any]:
    """Coupler point (x, y) in the task's frame, ``h2`` (>= 0 where it assembles) and the
    cosine of the transmission angle at B, for crank angles ``th2`` from the frame line.

    The loop by :func:`_loop`, then ``P = A + (rcx e3 + rcy e3_perp)`` and the frame
    placement. ``geometry``: ``r1 r2 r3 r4 rcx rcy x0 y0 theta0`` and the branch ``br``.
    """
    r1, r2, r3, r4, rcx, rcy, x0, y0, t0, br = geometry
    ax, ay, sx, sy, ux, uy, h2 = _loop(th2, r1, r2, r3, r4, br)
    px = ax + (rcx * ux - rcy * uy) / r3
    py = ay + (rcx * uy + rcy * ux) / r3
    c0, s0 = np.cos(t0), np.sin(t0)
    # transmission angle ABO4: between B->A = -u and B->O4 = -(u - s)
    cos_mu = (ux * (ux - sx) + uy * (uy - sy)) / (r3 * r4)
    return x0 + c0 * px - s0 * py, y0 + s0 * px + c0 * py, h2, cos_mu


def _kernel_jacobian(th2: np.ndarray, *geometry: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact derivatives of the coupler point of :func:`_kernel` (one design, crank angles
    ``th2`` (n,)) with respect to ``r1 r2 r3 r4 rcx rcy x0 y0 theta0`` and the crank angle:
    ``dx, dy`` of shape (n, 10).

    By implicit differentiation of the loop closure ``|B - A| = r3``, ``|B - O4| = r4``:
    ``[u; w] dB = [r3 dr3 + u . dA; r4 dr4 + w . dO4]`` with ``u = B - A``, ``w = B - O4``
    (singular at a toggle, where the coupler point's derivatives are unbounded), then
    ``P = A + (rcx u + rcy u_perp) / r3`` and the frame placement. Finite differences fail
    near a toggle, where optima of the literature's problems often sit (the square root of
    the assembly condition changes faster than any fixed step resolves).
    """
    r1, r2, r3, r4, rcx, rcy, _x0, _y0, t0, br = geometry
    c, s = np.cos(th2), np.sin(th2)
    ax, ay, sx, sy, ux, uy, _ = _loop(th2, r1, r2, r3, r4, br)
    wx, wy = ux - sx, uy - sy
    det = ux * wy - uy * wx
    tiny = 1e-12 * r3 * r4
    det = np.where(np.abs(det) < tiny, np.where(det < 0, -tiny, tiny), det)
    n = len(th2)
    zero, one = np.zeros(n), np.ones(n)
    # columns: r1 r2 r3 r4 rcx rcy x0 y0 theta0 theta2
    dA = [(zero, zero), (c, s), (zero, zero), (zero, zero), (zero, zero), (zero, zero),
          (zero, zero), (zero, zero), (zero, zero), (-ay, ax)]
    dO4 = [(one, zero)] + [(zero, zero)] * 9
    dr3 = [zero, zero, one] + [zero] * 7
    dr4 = [zero, zero, zero, one] + [zero] * 6
    px_l = (rcx * ux - rcy * uy) / r3
    py_l = (rcx * uy + rcy * ux) / r3
    c0, s0 = math.cos(t0), math.sin(t0)
    dx = np.empty((n, 10))
    dy = np.empty((n, 10))
    for j in range(10):
        (dax, day), (dox, doy) = dA[j], dO4[j]
        b1 = r3 * dr3[j] + ux * dax + uy * day
        b2 = r4 * dr4[j] + wx * dox + wy * doy
        dbx = (wy * b1 - uy * b2) / det
        dby = (ux * b2 - wx * b1) / det
        dux, duy = dbx - dax, dby - day
        dpx = dax + (rcx * dux - rcy * duy) / r3 - px_l * dr3[j] / r3
        dpy = day + (rcx * duy + rcy * dux) / r3 - py_l * dr3[j] / r3
        if j == 4:
            dpx, dpy = dpx + ux / r3, dpy + uy / r3
        elif j == 5:
            dpx, dpy = dpx - uy / r3, dpy + ux / r3
        dx[:, j] = c0 * dpx - s0 * dpy
        dy[:, j] = s0 * dpx + c0 * dpy
    px, py = ax + px_l, ay + py_l
    dx[:, 6], dy[:, 6] = 1.0, 0.0
    dx[:, 7], dy[:, 7] = 0.0, 1.0
    dx[:, 8] = -(s0 * px + c0 * py)
    dy[:, 8] = c0 * px - s0 * py
    return dx, dy


def coupler_point(theta2: ArrayLike, params: Mapping[str, Any], branch: int = 1
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The coupler point of a design at crank angles ``theta2`` from the frame line [rad].

    Returns ``x, y`` [m] in the task's frame (NaN where the linkage cannot be assembled on
    ``branch``) and ``valid``. ``params`` holds ``r1 r2 r3 r4 rcx rcy x0 y0 theta0`` (floats,
    or arrays broadcasting against ``theta2`` for many designs).
    """
    th = np.asarray(theta2, dtype=float)
    x, y, h2, _ = _kernel(th, *(np.asarray(params[k], dtype=float) for k in PARAMS), branch)
    ok = h2 >= 0
    return np.where(ok, x, np.nan), np.where(ok, y, np.nan), ok



def run_range(theta2: np.ndarray, checks: Mapping[str, Any], closed: bool, n: int
              ) -> np.ndarray:
    """Crank angles a design runs through (see :meth:`FourbarDesign.run_range`): a full turn
    from the first point when ``checks["crank_rotates"]`` or ``closed``, else from the first
    point to the last in the sense ``checks["direction"]`` (the angles are kept within a
    turn)."""
    t = np.asarray(theta2, dtype=float)
    s = float(checks.get("direction", 1.0 if len(t) < 2 or t[-1] >= t[0] else -1.0))
    if checks.get("crank_rotates", False) or closed:
        return t[0] + s * np.linspace(0.0, 2 * math.pi, n)
    total = float(np.sum(np.mod(s * np.diff(t), 2 * math.pi)))
    return t[0] + s * np.linspace(0.0, total, n)


@dataclass(frozen=True)
class LinkMasses:
    """Masses, centres of mass and centroidal inertias of crank, coupler, rocker.

    ``com`` points are in each link's own frame (origin O2, A, O4; x along the link) [m];
    ``mass`` [kg]; ``inertia`` [kg m^2].
    """

    mass: tuple[float, float, float]
    com: tuple[tuple[float, float], tuple[float, float], tuple[float, float]]
    inertia: tuple[float, float, float]


@dataclass(frozen=True)
class FourbarDesign:
    """One four-bar design: literature parameters, branch, its error and its checks.

    Attributes
    ----------
    params : dict
        ``r1 r2 r3 r4 rcx rcy x0 y0`` [m], ``theta0`` [rad] and ``theta2`` (list, [rad], one
        crank angle from the frame line per target point).
    branch : int
        Assembly branch, +1 or -1 (B left / right of A -> O4).
    error : float
        The literature's error: sum of squared distances between the coupler point and the
        target points [m^2].
    points : ndarray (n, 2)
        The target points [m].
    closed : bool
        Whether the task's path is closed (the points are reached cyclically).
    checks : dict
        What the defect checks measured: ``grashof`` (class), ``crank_rotates``,
        ``min_transmission_angle`` [rad] over the range the design runs, ``max_deviation``
        [m] (largest distance to a target point), ``engine_deviation`` [m] (the engine's
        coupler point against the closed form at the target angles).
    forces : dict
        Peak driving torque [N m], peak bearing load [N], RMS shaking force [N] re-solved by
        the engine (empty unless the search was judged by forces).
    masses : LinkMasses or None
        The masses the forces were computed with.
    omega1 : float
        Crank speed of the force evaluation and of the written file [rad/s].
    """

    params: Mapping[str, Any]
    branch: int
    error: float
    points: np.ndarray
    closed: bool = False
    checks: Mapping[str, Any] = field(default_factory=dict)
    forces: Mapping[str, float] = field(default_factory=dict)
    masses: LinkMasses | None = None
    omega1: float = 1.0

    # -- derived geometry ---------------------------------------------------------------------
    @property
    def theta2(self) -> np.ndarray:
        """Crank angles at the target points, from the frame line [rad]."""
        return np.asarray(self.params["theta2"], dtype=float)

    def pivots(self) -> tuple[np.ndarray, np.ndarray]:
        """The fixed pivots O2 and O4 in the task's frame [m]."""
        p = self.params
        o2 = np.array([p["x0"], p["y0"]], dtype=float)
        return o2, o2 + p["r1"] * np.array([math.cos(p["theta0"]), math.sin(p["theta0"])])

    def coupler_curve(self, n: int = 361) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Crank angles from the frame line [rad] over the range the design runs (a full turn
        when the crank rotates, else from the first to the last point), and the coupler point's
        x, y there [m] (NaN where it cannot be assembled)."""
        th = self.run_range(n)
        x, y, _ = coupler_point(th, self.params, self.branch)
        return th, x, y

    def joints_at(self, theta2: float) -> dict[str, np.ndarray]:
        """Positions of O2, A, B, O4 and P at the crank angle ``theta2`` from the frame line
        [rad], in the task's frame [m] (NaN where the linkage cannot be assembled)."""
        p = self.params
        o2, o4 = self.pivots()
        t = float(p["theta0"]) + float(theta2)
        a = o2 + float(p["r2"]) * np.array([math.cos(t), math.sin(t)])
        # B is the coupler point (r3, 0) of the coupler's frame
        bx, by, h2, _ = _kernel(np.array([float(theta2)]), *(float(p[k]) for k in PARAMS[:4]),
                                float(p["r3"]), 0.0, *(float(p[k]) for k in PARAMS[6:]),
                                self.branch)
        px, py, _ = coupler_point(np.array([float(theta2)]), p, self.branch)
        nan = h2[0] < 0
        b = np.array([np.nan, np.nan]) if nan else np.array([bx[0], by[0]])
        return {"O2": o2, "A": a, "B": b, "O4": o4, "P": np.array([px[0], py[0]])}

    def skeleton(self, theta2: float) -> tuple[list[np.ndarray], np.ndarray]:
        """The links at the crank angle ``theta2`` as polylines [m] (O2-A-B-O4 and the coupler
        triangle A-P-B) and the fixed pivots (O2, O4)."""
        j = self.joints_at(theta2)
        return ([np.array([j["O2"], j["A"], j["B"], j["O4"]]), np.array([j["A"], j["P"], j["B"]])],
                np.array([j["O2"], j["O4"]]))

    def run_range(self, n: int = 361) -> np.ndarray:
        """Crank angles from the frame line [rad] the design runs through: a full turn from the
        first point when the crank rotates fully, else from the first to the last point in
        the sense the points are reached (``checks["direction"]``; the angles themselves are
        kept within a turn)."""
        return run_range(self.theta2, self.checks, self.closed, n)

    # -- engine model and file ----------------------------------------------------------------
    def mechanism(self, masses: LinkMasses | None = None, omega1: float | None = None
                  ) -> Mechanism:
        """The design as an engine :class:`~linkwork.planar.model.Mechanism`.

        Frame points ``O2``, ``O4`` at their places in the task's frame; bodies ``crank``
        (O2 -> A), ``coupler`` (points A, B and the coupler point ``P``), ``rocker`` (O4 ->
        B); joints O2, A, B, O4; the driver is the crank at O2, so the engine's ``phi1`` is
        the crank's absolute angle ``theta0 + theta2``; branch key ``B``. ``masses`` default to
        the design's own (massless without them).
        """
        p = self.params
        o2, o4 = self.pivots()
        m = masses if masses is not None else self.masses
        mass = m.mass if m else (0.0, 0.0, 0.0)
        com = m.com if m else ((p["r2"] / 2, 0.0), (p["r3"] / 2, 0.0), (p["r4"] / 2, 0.0))
        inertia = m.inertia if m else (0.0, 0.0, 0.0)
        frame = Body("frame", {"O2": (float(o2[0]), float(o2[1])),
                               "O4": (float(o4[0]), float(o4[1]))})
        crank = bar("crank", "O2", "A", float(p["r2"]), mass=mass[0], com=com[0],
                    inertia=inertia[0])
        coupler = Body("coupler", {"A": (0.0, 0.0), "B": (float(p["r3"]), 0.0),
                                   "P": (float(p["rcx"]), float(p["rcy"]))},
                       mass=mass[1], com=com[1], inertia=inertia[1])
        rocker = bar("rocker", "O4", "B", float(p["r4"]), mass=mass[2], com=com[2],
                     inertia=inertia[2])
        joints = (Revolute("O2", "frame", "crank"), Revolute("A", "crank", "coupler"),
                  Revolute("B", "coupler", "rocker"), Revolute("O4", "frame", "rocker"))
        w = self.omega1 if omega1 is None else omega1
        return Mechanism(frame, (crank, coupler, rocker), joints, Crank("O2", w, 0.0),
                         {"B": int(self.branch)})

    def to_toml(self, path: str | Path, *, name: str | None = None, n: int = 361) -> Path:
        """Write the design as a ``planar`` file that ``linkwork analyze`` reads; return the path.

        Plain numbers are SI (m, rad, kg) at full precision; the ``[analysis]`` range is a full
        turn of the crank from the first point when it rotates fully, else the crank's range
        from the first to the last point (``n`` positions). Comments give the literature
        parameters, the crank angles at the points and the error.
        """
        p = self.params
        th = self.run_range(2) + float(p["theta0"])
        t2 = ", ".join(_num(v) for v in self.theta2)
        comments = (
            "A four-bar synthesised by linkwork (linkwork.synthesis); plain numbers are SI.",
            "literature parameters: " + ", ".join(f"{k} = {_num(p[k])}" for k in PARAMS)
            + f", branch = {int(self.branch)}",
            f"theta2 (crank angles from the frame line at the points) = [{t2}]",
            f"error (sum of squared distances to the targets) = {_num(self.error)} m^2")
        return write_planar_toml(self.mechanism(), path,
                                 name=name or "four-bar synthesised by linkwork",
                                 start=float(th[0]), stop=float(th[-1]), n=n,
                                 comments=comments)

    def summary(self) -> dict[str, Any]:
        """Parameters, branch, error, checks and forces as plain values (JSON-able)."""
        d: dict[str, Any] = {k: float(self.params[k]) for k in PARAMS}
        d["theta2"] = [float(v) for v in self.theta2]
        d["branch"] = int(self.branch)
        d["error"] = float(self.error)
        d.update({k: (float(v) if isinstance(v, float | np.floating) else v)
                  for k, v in self.checks.items()})
        d.update({k: float(v) for k, v in self.forces.items()})
        return d


def _toml_str(s: str) -> str:
    return json.dumps(s)  # a TOML basic string is a JSON string (escapes included)


def _num(x: float) -> str:
    return repr(float(x))


def _pts(points: Mapping[str, Any]) -> str:
    return "{ " + ", ".join(f"{k} = [{_num(v[0])}, {_num(v[1])}]" for k, v in points.items()) \
        + " }"


def write_planar_toml(mech: Mechanism, path: str | Path, *, name: str, start: float,
                      stop: float, n: int = 361, comments: tuple[str, ...] = ()) -> Path:
    """Write an engine mechanism of revolute and prismatic joints with a crank driver as a
    ``planar`` file (SI plain numbers, full precision) that ``linkwork analyze`` reads.

    Every body is written as a general body with its named points, mass, centre of mass and
    inertia; the ``[analysis]`` range runs from ``start`` to ``stop`` [rad] of the driver
    (``stop < start``: written the other way round with the driver's speed negated, the same
    positions)."""
    w = mech.driver.omega1
    if stop < start:
        start, stop, w = stop, start, -w
    lines = [f"# {c}" for c in comments]
    lines += ['type = "planar"', f"name = {_toml_str(name)}", "", "[frame]",
              f"points = {_pts(mech.frame.points)}", ""]
    for b in mech.bodies:
        lines += ["[[body]]", f"name = {_toml_str(b.name)}", f"points = {_pts(b.points)}",
                  f"mass = {_num(b.mass)}", f"com = [{_num(b.com[0])}, {_num(b.com[1])}]",
                  f"inertia = {_num(b.inertia)}", ""]
    for j in mech.joints:
        lines += ["[[joint]]", f"name = {_toml_str(j.name)}"]
        if j.code == "R":
            lines += ['type = "revolute"', f"a = {_toml_str(j.a)}", f"b = {_toml_str(j.b)}"]
            pa, pb = getattr(j, "point_a", None), getattr(j, "point_b", None)
            if pa:
                lines.append(f"point_a = {_toml_str(pa)}")
            if pb:
                lines.append(f"point_b = {_toml_str(pb)}")
        else:
            qa, _, ang = mech.joint_geometry(j)
            lines += ['type = "prismatic"', f"a = {_toml_str(j.a)}", f"b = {_toml_str(j.b)}",
                      f"angle = {_num(ang)}", f"through = [{_num(qa[0])}, {_num(qa[1])}]",
                      f"point = {_toml_str(getattr(j, 'point', None) or j.name)}",
                      f"rel_angle = {_num(getattr(j, 'rel_angle', 0.0))}"]
        lines.append("")
    br = ", ".join(f"{k} = {int(v)}" for k, v in mech.branches.items())
    lines += ["[driver]", 'type = "crank"', f"joint = {_toml_str(mech.driver.joint)}",
              f"omega1 = {_num(w)}", "eps1 = 0", "", "[analysis]", f"start = {_num(start)}",
              f"stop = {_num(stop)}", f"n = {int(n)}", f"branches = {{ {br} }}", ""]
    out = Path(path)
    with atomic_path(out) as tmp:
        tmp.write_text("\n".join(lines), encoding="utf-8")
    return out


@dataclass(frozen=True)
class SynthesisResult(Result):
    """The designs of a synthesis search, best first, and what the search did.

    Attributes
    ----------
    designs : tuple of FourbarDesign
        Defect-free designs, best first (by ``error``, or by the weighted objective; for a
        Pareto objective, the non-dominated designs by error).
    points : ndarray (n, 2)
        Target points [m].
    timing : ndarray (n,) or None
        Prescribed crank angles [rad], None when free.
    closed : bool
        Whether the path is closed.
    constraints : tuple of str
        The constraints the designs meet.
    n_evaluated : int
        Candidates evaluated in the global search.
    rejected : dict
        Candidates and refined designs rejected, per defect (``assembly``, ``grashof``,
        ``order``, ``branch``, ``circuit``, ``transmission``, ``bounds``).
    n_refined : int
        Local refinements run.
    n_residual_evaluations : int
        Evaluations of the residuals in the refinements (finite-difference ones included).
    time : float
        Wall time of the search [s] (``time_global`` of it in the global search).
    objective : str
        ``"sum_squares"``, ``"weighted"`` or ``"pareto"``.
    pareto : tuple of int
        Indices (into ``designs``) of the Pareto set of accuracy against dynamics (empty
        unless the objective was Pareto).
    scales : dict
        What each metric was measured against when judged by forces (``error`` [m^2]: n
        (0.01 L)^2; ``peak_torque`` [N m], ``peak_bearing``, ``rms_shaking`` [N]: their
        medians over the screened candidates); empty for the literature's objective.
    """

    designs: tuple[FourbarDesign, ...]
    points: np.ndarray
    timing: np.ndarray | None
    closed: bool
    constraints: tuple[str, ...]
    n_evaluated: int
    rejected: Mapping[str, int]
    n_refined: int
    n_residual_evaluations: int
    time: float
    time_global: float
    objective: str = "sum_squares"
    pareto: tuple[int, ...] = ()
    scales: Mapping[str, float] = field(default_factory=dict)

    units: ClassVar[dict[str, str]] = {
        "r1": "m", "r2": "m", "r3": "m", "r4": "m", "rcx": "m", "rcy": "m", "x0": "m",
        "y0": "m", "theta0": "rad", "branch": "", "error": "m^2", "max_deviation": "m",
        "min_transmission_angle": "rad", "peak_torque": "N*m", "peak_bearing": "N",
        "rms_shaking": "N", "rank": ""}
    position_field: ClassVar[str] = "rank"

    @property
    def best(self) -> FourbarDesign:
        """The first design."""
        return self.designs[0]

    @property
    def rank(self) -> np.ndarray:
        return np.arange(1, len(self.designs) + 1)

    @property
    def candidates_per_second(self) -> float:
        """Candidates evaluated per second of the global search."""
        return self.n_evaluated / self.time_global if self.time_global > 0 else math.inf

    def columns(self) -> dict[str, np.ndarray]:
        return design_columns(self, (*PARAMS, "branch", "error"))

    def _unit_of(self, column: str) -> str:
        return "rad" if column.startswith("theta2_") else self.units.get(column, "")

    def scalars(self) -> dict[str, Any]:
        return {"n_points": len(self.points), "closed": self.closed,
                "timing": self.timing is not None, "constraints": list(self.constraints),
                "n_evaluated": self.n_evaluated, "rejected": dict(self.rejected),
                "n_refined": self.n_refined,
                "n_residual_evaluations": self.n_residual_evaluations, "time": self.time,
                "time_global": self.time_global, "objective": self.objective,
                "pareto": list(self.pareto), "scales": dict(self.scales),
                "points": [[float(x), float(y)] for x, y in self.points]}

    def to_dict(self) -> dict[str, Any]:
        d = super().to_dict()
        d["designs"] = [x.summary() for x in self.designs]
        return d

    def plot(self, ax: Any = None, n_designs: int = 1, **kw: Any) -> Figure:
        """The coupler curves of the first ``n_designs`` designs against the target points: a
        :class:`linkwork.plot.Figure` with 1 axes."""
        from linkwork.plot.synthesis import path_figure

        return path_figure(self, ax=ax, n_designs=n_designs, **kw)


def design_columns(res: Any, keys: tuple[str, ...]) -> dict[str, np.ndarray]:
    """The table of a synthesis result's designs: rank, ``keys`` of each design's summary,
    what the checks measured, the forces when judged by them, the crank angles at the
    points."""
    ds = res.designs
    cols: dict[str, np.ndarray] = {"rank": np.arange(1, len(ds) + 1)}
    for k in keys:
        cols[k] = np.array([d.summary()[k] for d in ds], dtype=float)
    for k in ("max_deviation", "min_transmission_angle"):
        cols[k] = np.array([float(d.checks.get(k, math.nan)) for d in ds])
    for k in ("peak_torque", "peak_bearing", "rms_shaking"):
        if any(k in getattr(d, "forces", {}) for d in ds):
            cols[k] = np.array([float(d.forces.get(k, math.nan)) for d in ds])
    for i in range(len(res.points)):
        cols[f"theta2_{i + 1}"] = np.array([float(d.theta2[i]) for d in ds])
    return cols


def check_design_params(params: Mapping[str, Any], n: int) -> None:
    """A ParameterError naming the first missing or invalid literature parameter."""
    for k in PARAMS:
        if k not in params:
            raise ParameterError("params", k, f"missing; needs {', '.join(PARAMS)}, theta2")
    for k in ("r1", "r2", "r3", "r4"):
        if not float(params[k]) > 0:
            raise ParameterError(k, params[k], "must be > 0")
    if len(np.atleast_1d(params["theta2"])) != n:
        raise ParameterError("theta2", params["theta2"], f"must hold {n} crank angles")
