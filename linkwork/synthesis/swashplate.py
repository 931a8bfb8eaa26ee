r"""Dimensional synthesis of the swash-plate (inclined-disk) drive of rotor machines.

Given the rotor radius ``R`` and the technological requirements of paper [1]_ -- stroke ``H``
(with a tolerance), allowed pressure angles on the forward and the return stroke, a velocity
limit (directly as ``[Pi_v]`` or from the slide-speed limit and the productivity, Eqs. (1)-(3)),
optionally a point ``(phi_p, s_p)`` the position function must pass through and a wanted
forward-stroke angle ``phi_f`` -- :func:`synthesize` finds, for one scheme of the paper's table,
the parameters ``(r, l, alpha, a, b)`` that meet every limit and minimise the objective: the
axial size ``L = 2 r sin(alpha) + l`` (Eq. (13), default) or the peak drive torque.

Method
------
1. A scrambled Sobol sample of the scheme's free parameters (relative units, lengths over
   ``R``) within bounds is evaluated vectorised, in chunks of bounded memory, by
   :func:`linkwork.sweep.evaluate` (in-process, or on a dask cluster when ``client`` is given).
   Each candidate gets its exact characteristics (:mod:`linkwork.models.swashplate`) and one
   normalised violation per constraint.
2. The best feasible candidates (and, if none is feasible, the least violating ones) start a
   local SLSQP refinement (SciPy) of the objective under the same constraints.
3. Designs are ranked by the objective; a request nothing can meet raises
   :class:`~linkwork.errors.InfeasibleError` naming the constraint that fails and the closest
   value achieved for it (by a further SLSQP run that minimises that constraint's quantity
   subject to the others).

:func:`feasible_region` maps the feasible set over two chosen parameters around a design
(:func:`linkwork.plot.swashplate.plot_feasible_region` draws it).

References
----------
.. [1] V. A. Kryukov, V. V. Preis, "Theoretical foundations of the kinematic analysis and
   synthesis of the crank drive of the actuating devices of technological rotors" (in Russian),
   Izvestiya TulGU, 2012.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_finite, require_in_range, require_positive
from linkwork.errors import InfeasibleError, ParameterError
from linkwork.models import swashplate as sw
from linkwork.results import Result
from linkwork.sweep import Progress, evaluate

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = [
    "CONSTRAINTS",
    "DEFAULT_BOUNDS",
    "MAX_CANDIDATES",
    "MAX_REGION_N",
    "FeasibleRegion",
    "Request",
    "SynthesisResult",
    "check_candidates",
    "evaluate_candidates",
    "feasible_region",
    "synthesize",
]

DEG = math.pi / 180
PARAMS = ("r", "l", "alpha", "a", "b")

#: Default search bounds per scheme: relative lengths (over R) and alpha [rad].
DEFAULT_BOUNDS: dict[str, dict[str, tuple[float, float]]] = {
    "1": {"r": (0.5, 1.5), "l": (0.3, 5.0), "alpha": (1 * DEG, 45 * DEG), "a": (-0.4, 0.4),
          "b": (-0.4, 0.4)},
    "2": {"r": (0.02, 1.0), "l": (0.3, 5.0), "b": (-0.4, 0.4)},
    "3": {"r": (0.2, 1.5), "l": (0.3, 5.0), "a": (-0.5, 0.5), "b": (-0.5, 0.5)},
    "4a": {"l": (0.3, 5.0), "alpha": (1 * DEG, 60 * DEG)},
    "4b": {"r": (0.5, 1.5), "l": (0.3, 5.0), "alpha": (1 * DEG, 45 * DEG), "b": (-0.4, 0.4)},
}

#: Constraint keys and their descriptions (used in messages).
CONSTRAINTS: dict[str, str] = {
    "reach": "rod reaches the disk point at every rotor angle",
    "H": "stroke H",
    "delta_f": "max pressure angle on the forward stroke",
    "delta_r": "max pressure angle on the return stroke",
    "Pi_v": "max |Pi_v| (velocity limit)",
    "point": "position function through the given point",
    "phi_f": "forward-stroke angle phi_f",
    "unimodal": "unimodal position function",
}


@dataclass(frozen=True)
class Request:
    """A synthesis request (SI units, radians).

    Parameters
    ----------
    scheme : str
        ``"1"``, ``"2"``, ``"3"``, ``"4a"`` or ``"4b"``
        (:data:`linkwork.models.swashplate.SCHEMES`).
    R : float
        Rotor pitch radius [m].
    H : float
        Wanted stroke [m]; met within ``H_tol`` [m].
    delta_f, delta_r : float
        Allowed pressure angle on the forward / return stroke [rad] (paper: 5-10 deg).
    Pi_v_max : float, optional
        Allowed ``max |ds/dphi|`` [m/rad]; see
        :func:`linkwork.models.swashplate.allowed_first_transfer`.
    point : (float, float), optional
        ``(phi_p [rad], s_p [m])`` the position function must pass through within ``point_tol``.
    phi_f : float, optional
        Wanted forward-stroke angle [rad] within ``phi_f_tol``.
    unimodal : bool
        Require one maximum and one minimum per revolution (paper, requirement 3).
    objective : {"L", "torque"}
        Minimise the axial size ``2 r sin(alpha) + l`` or the peak drive torque of ``u`` slides
        under ``load`` (frictionless, ``M = sum F Pi_v``; default load: 1 N against the forward
        stroke of each slide, nothing on the return).
    bounds : dict, optional
        Search bounds per free parameter (relative lengths, alpha in rad); defaults
        :data:`DEFAULT_BOUNDS`.
    """

    scheme: str
    R: float
    H: float
    H_tol: float
    delta_f: float
    delta_r: float
    Pi_v_max: float | None = None
    point: tuple[float, float] | None = None
    point_tol: float = 0.0
    phi_f: float | None = None
    phi_f_tol: float = 1 * DEG
    unimodal: bool = True
    objective: Literal["L", "torque"] = "L"
    u: int = 1
    load: Callable[[np.ndarray], ArrayLike] | None = None
    bounds: dict[str, tuple[float, float]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.scheme not in sw.SCHEMES:
            raise ParameterError("scheme", self.scheme, f"must be one of {sorted(sw.SCHEMES)}")
        require_positive("R", self.R)
        require_positive("H", self.H)
        require_positive("H_tol", self.H_tol, allow_zero=True)
        for name in ("delta_f", "delta_r"):
            require_in_range(name, getattr(self, name), 0.0, math.pi / 2, lo_open=True,
                             unit="deg", scale=180 / math.pi)
        if self.Pi_v_max is not None:
            require_positive("Pi_v_max", self.Pi_v_max)
        if self.objective not in ("L", "torque"):
            raise ParameterError("objective", self.objective, "must be 'L' or 'torque'")
        if isinstance(self.u, bool) or int(self.u) != self.u or self.u < 1:
            raise ParameterError("u", self.u, "must be an integer >= 1")
        if self.point is not None:
            if len(self.point) != 2:
                raise ParameterError("point", self.point, "must be (phi_p [rad], s_p [m])")
            require_finite("point angle phi_p", self.point[0])
            require_finite("point position s_p", self.point[1])
        require_positive("point_tol", self.point_tol, allow_zero=True)
        require_positive("phi_f_tol", self.phi_f_tol, allow_zero=True)
        free = sw.SCHEMES[self.scheme].free
        for k, (lo, hi) in self.bounds.items():
            if k not in free:
                raise ParameterError("bounds", k, f"is not a free parameter of scheme "
                                     f"{self.scheme} ({', '.join(free)})")
            if not lo <= hi:
                raise ParameterError(f"bounds[{k}]", (lo, hi), "needs lower <= upper")
        if self.phi_f is not None:
            require_in_range("phi_f", self.phi_f, 0.0, 2 * math.pi, lo_open=True, hi_open=True,
                             unit="deg", scale=180 / math.pi)

    @property
    def free(self) -> tuple[str, ...]:
        return sw.SCHEMES[self.scheme].free

    def search_bounds(self) -> list[tuple[float, float]]:
        """Bounds of the free parameters in order (relative lengths, alpha [rad]).

        Defaults (:data:`DEFAULT_BOUNDS`) are narrowed where the pressure-angle limits make
        the rest hopeless: the rod's horizontal projection cannot exceed
        ``rho = l_max sin(max(delta_f, delta_r))``, so ``|a|, |b| <= rho`` and
        ``1 - 2 rho <= r <= (1 + 2 rho) / cos(alpha_max)`` (schemes 1, 4b). Bounds given in
        ``bounds`` are used as given.
        """
        base = dict(DEFAULT_BOUNDS[self.scheme])
        if self.scheme in ("1", "4b"):
            l_max = (self.bounds.get("l") or base["l"])[1]
            rho = l_max * math.sin(max(self.delta_f, self.delta_r))
            for k in ("a", "b"):
                if k in base:
                    base[k] = (max(base[k][0], -rho), min(base[k][1], rho))
            a_max = (self.bounds.get("alpha") or base["alpha"])[1]
            base["r"] = (max(base["r"][0], 1 - 2 * rho),
                         min(base["r"][1], (1 + 2 * rho) / math.cos(a_max)))
        base |= self.bounds
        return [base[k] for k in self.free]


def _full_params(req: Request, X: np.ndarray) -> tuple[np.ndarray, ...]:
    """Absolute (R, r, l, alpha, a, b) arrays from relative free parameters X (n, k)."""
    X = np.atleast_2d(np.asarray(X, dtype=float))
    n = X.shape[0]
    vals = dict(zip(req.free, X.T, strict=True))
    fixed = sw.SCHEMES[req.scheme].fixed
    R = req.R
    alpha = vals.get("alpha", np.full(n, fixed.get("alpha", 0.0)))
    if req.scheme == "4a":
        r = np.full(n, 1.0) / np.cos(alpha)
    else:
        r = vals["r"]
    out = (np.full(n, R), R * r, R * vals["l"], alpha,
           R * vals.get("a", np.full(n, fixed.get("a", 0.0))),
           R * vals.get("b", np.full(n, fixed.get("b", 0.0))))
    return out


def evaluate_candidates(X: np.ndarray, req: Request, n_grid: int = 120) -> dict[str, np.ndarray]:
    """Characteristics, objective and constraint violations of candidates ``X`` (n, k).

    ``X`` holds the scheme's free parameters in relative units (``req.free`` order). Returns
    arrays of shape (n,): the characteristics, ``objective``, one violation ``g_<key>`` per
    constraint of :data:`CONSTRAINTS` (<= 0 met; lengths over ``R``, angles in rad) and
    ``feasible``. Designs whose rod cannot reach get ``g_reach = 1`` and NaN characteristics.
    """
    P = tuple(np.asarray(p, dtype=float) for p in _full_params(req, X))
    R = req.R
    c = sw._characteristics(P, "nan", n_grid)
    reach_bad = np.isnan(c.H)
    out: dict[str, np.ndarray] = {
        "H": c.H, "delta_f": c.delta_f, "delta_r": c.delta_r, "Pi_v_max": c.Pi_v_max,
        "phi_f": c.phi_f, "phi_r": c.phi_r, "phi_min": c.phi_min, "phi_max": c.phi_max,
        "L": c.L, "L_exact": c.L_exact, "unimodal": c.unimodal,
        "r": P[1], "l": P[2], "alpha": P[3], "a": P[4], "b": P[5]}
    g: dict[str, np.ndarray] = {"reach": np.where(reach_bad, 1.0, -1.0)}
    g["H"] = (np.abs(c.H - req.H) - req.H_tol) / R
    g["delta_f"] = c.delta_f - req.delta_f
    g["delta_r"] = c.delta_r - req.delta_r
    if req.Pi_v_max is not None:
        g["Pi_v"] = (c.Pi_v_max - req.Pi_v_max) / R
    if req.point is not None:
        s_p = sw._kp(np.asarray(req.point[0], dtype=float), P, 0)["s"]
        out["s_point"] = s_p
        g["point"] = (np.abs(s_p - req.point[1]) - req.point_tol) / R
    if req.phi_f is not None:
        d = np.abs(np.mod(c.phi_f - req.phi_f + math.pi, 2 * math.pi) - math.pi)
        g["phi_f"] = d - req.phi_f_tol
    if req.unimodal:
        g["unimodal"] = np.where(c.unimodal, -1.0, 1.0)
    if req.objective == "L":
        obj = c.L / R
    else:
        obj = _peak_torque(P, c.phi_min, c.phi_f, req) / R
    out["objective"] = obj
    feasible = ~reach_bad
    for k, v in g.items():
        v = np.where(reach_bad & (k != "reach"), np.inf, v)
        g[k] = v
        out[f"g_{k}"] = v
        feasible &= v <= 0
    out["feasible"] = feasible
    return out


def _peak_torque(P: tuple[np.ndarray, ...], phi_min: np.ndarray, phi_f: np.ndarray,
                 req: Request, n: int = 180, smooth: float | None = None) -> np.ndarray:
    """Peak |sum over u slides of F(phi_k) Pi_v(phi_k)| [N m] over a revolution (frictionless).

    ``smooth=p`` returns the p-mean ``(mean |M|^p)^(1/p)`` instead of the maximum (a smooth
    lower bound used by the SLSQP refinement, where the place of the peak jumps).
    """
    u = int(req.u)
    ph = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    shifts = 2 * math.pi * np.arange(u) / u
    grid = ph[None, :, None] + shifts[None, None, :]  # (1, n, u)
    Pg = tuple(p[:, None, None] for p in P)
    s1 = sw._kp(grid, Pg, 1)["s1"]
    if req.load is None:
        start = phi_min[:, None, None]
        F = np.where(np.mod(grid - start, 2 * math.pi) < phi_f[:, None, None], 1.0, 0.0)
    else:
        F = np.broadcast_to(np.asarray(req.load(np.broadcast_to(grid, s1.shape)), float),
                            s1.shape)
    M = np.abs(np.sum(F * s1, axis=-1))
    peak = np.max(M, axis=-1)
    if smooth is None:
        return peak
    scale = np.where(peak > 0, peak, 1.0)[:, None]
    return np.mean((M / scale) ** smooth, axis=-1) ** (1.0 / smooth) * scale[:, 0]


def _chunk_eval(X: np.ndarray, req: Request, n_grid: int) -> dict[str, np.ndarray]:
    return evaluate_candidates(X, req, n_grid)


@dataclass(frozen=True)
class SynthesisResult(Result):
    """Ranked designs of a synthesis run (best first) with their characteristics.

    ``designs`` are :class:`~linkwork.models.swashplate.Design` objects; ``table`` holds one
    row per design (dict of arrays: parameters [m, rad], characteristics, ``objective``);
    ``n_evaluated``, ``n_feasible`` count the sampled candidates; ``candidates`` keeps the
    screened sample (relative parameters ``X`` and ``feasible``) for plots.
    """

    request: Request
    designs: tuple[sw.Design, ...]
    table: dict[str, np.ndarray]
    n_evaluated: int
    n_feasible: int
    candidates: dict[str, np.ndarray] = field(repr=False)

    units: ClassVar[dict[str, str]] = {
        "r": "m", "l": "m", "alpha": "rad", "a": "m", "b": "m", "H": "m", "phi_min": "rad",
        "phi_max": "rad", "delta_f": "rad",
        "delta_r": "rad", "Pi_v_max": "m/rad", "phi_f": "rad", "phi_r": "rad", "L": "m",
        "L_exact": "m", "objective": "1", "s_point": "m"}
    position_field: ClassVar[str] = "objective"

    def columns(self) -> dict[str, np.ndarray]:
        return {k: np.asarray(v) for k, v in self.table.items()}

    def scalars(self) -> dict[str, Any]:
        return {"scheme": self.request.scheme, "n_evaluated": self.n_evaluated,
                "n_feasible": self.n_feasible}

    @property
    def best(self) -> sw.Design:
        return self.designs[0]

    def plot(self, x_name: str | None = None, y_name: str | None = None, n: int = 60,
             ax: Any = None, **kw: Any) -> Figure:
        """The feasible region around the best design over two free parameters (default the
        first two of the scheme), the best design starred: a :class:`linkwork.plot.Figure`
        with 1 axes. Maps :func:`feasible_region` on an ``n`` x ``n`` grid first."""
        from linkwork.plot.swashplate import feasible_region_figure

        free = list(self.request.free)
        region = feasible_region(self.request, self.best, x_name or free[0],
                                 y_name or free[1], n=n)
        return feasible_region_figure(region, ax=ax, best=self.best, **kw)

    def at_bounds(self, i: int = 0, tol: float = 1e-4) -> list[tuple[str, str, float]]:
        """Free parameters of design ``i`` that lie on a bound of the search box.

        Returns ``(name, "lower" | "upper", bound)`` with the bound relative to R for lengths
        and in radians for alpha.  A design on a bound may be limited by the search box rather
        than by the request: a wider bound (``Request(bounds=...)``) may give a better one.
        """
        req = self.request
        out = []
        for name, (lo, hi) in zip(req.free, req.search_bounds(), strict=True):
            v = float(self.table[name][i]) / (1.0 if name == "alpha" else req.R)
            if v - lo <= tol * (hi - lo):
                out.append((name, "lower", lo))
            elif hi - v <= tol * (hi - lo):
                out.append((name, "upper", hi))
        return out


TABLE_KEYS = ("r", "l", "alpha", "a", "b", "H", "phi_min", "phi_max", "delta_f", "delta_r",
              "Pi_v_max", "phi_f", "phi_r", "L", "L_exact", "objective")


def _violation(m: dict[str, np.ndarray]) -> np.ndarray:
    tot = np.zeros_like(m["objective"], dtype=float)
    for k in CONSTRAINTS:
        if f"g_{k}" in m:
            tot = tot + np.maximum(np.nan_to_num(m[f"g_{k}"], nan=1e3, posinf=1e3), 0.0)
    return tot


#: Angles at which the refinement imposes the pointwise (smooth) pressure-angle and velocity
#: constraints; the limits are tightened by :data:`_MARGIN` to cover the gaps between them.
_N_SIP = 240
_MARGIN = 1e-3


def _smooth_constraints(X: np.ndarray, req: Request) -> tuple[np.ndarray, np.ndarray]:
    """Objective (n,) and smooth inequality constraints (n, m) >= 0 for candidates X (n, k).

    The pressure-angle and velocity limits are imposed pointwise on :data:`_N_SIP` angles
    (a discretised semi-infinite program: smooth in the parameters, unlike the maxima), the
    stroke, the point and ``phi_f`` as two-sided smooth inequalities. Lengths over R.
    """
    P = tuple(np.asarray(p, dtype=float) for p in _full_params(req, X))
    R = req.R
    e = sw._extremes(P, "nan", 120)
    phi_f = np.mod(e["phi_max"] - e["phi_min"], 2 * math.pi)
    ph = np.linspace(0.0, 2 * math.pi, _N_SIP, endpoint=False)
    k = sw._kp(ph[None, :], tuple(p[:, None] for p in P), 1)
    fwd = np.mod(ph[None, :] - e["phi_min"][:, None], 2 * math.pi) <= phi_f[:, None]
    lim = np.where(fwd, math.sin(req.delta_f), math.sin(req.delta_r)) * (1 - _MARGIN)
    lv = P[2][:, None]
    cons = [((lv * lim) ** 2 - k["q"]) / R**2]
    H = np.nan_to_num(e["s_max"] - e["s_min"], nan=0.0)
    tol = req.H_tol * (1 - _MARGIN)
    cons.append(np.stack([(H - req.H + tol) / R, (req.H + tol - H) / R], axis=1))
    if req.Pi_v_max is not None:
        cons.append(((req.Pi_v_max * (1 - _MARGIN)) ** 2 - k["s1"] ** 2) / R**2)
    if req.point is not None:
        sp = sw._kp(np.asarray(req.point[0], dtype=float), P, 0)["s"]
        ptol = req.point_tol * (1 - _MARGIN)
        cons.append(np.stack([(sp - req.point[1] + ptol) / R,
                              (req.point[1] + ptol - sp) / R], axis=1))
    if req.phi_f is not None:
        d = np.mod(phi_f - req.phi_f + math.pi, 2 * math.pi) - math.pi
        ftol = req.phi_f_tol * (1 - _MARGIN)
        cons.append(np.stack([d + ftol, ftol - d], axis=1))
    C = np.concatenate([np.atleast_2d(x.T).T if x.ndim == 2 else x[:, None] for x in cons],
                       axis=1)
    C = np.where(np.isfinite(C), C, -10.0)
    if req.objective == "L":
        obj = sw.axial_size(P[1], P[2], P[3]) / R
    else:
        obj = _peak_torque(P, e["phi_min"], phi_f, req, smooth=16.0) / R
    return np.where(np.isfinite(obj), obj, 1e3), C


class _Batch:
    """Objective, constraints and their forward-difference Jacobians at one point, from one
    vectorised evaluation of the point and its k neighbours (scaled coordinates z)."""

    def __init__(self, req: Request, lo: np.ndarray, scale: np.ndarray,
                 mode: str = "objective", h: float = 1e-7) -> None:
        self.req, self.lo, self.scale, self.mode, self.h = req, lo, scale, mode, h
        self.z: np.ndarray | None = None

    def at(self, z: np.ndarray) -> None:
        if self.z is not None and np.array_equal(z, self.z):
            return
        k = len(z)
        Z = np.vstack([z, z + self.h * np.eye(k)])
        obj, C = _smooth_constraints(self.lo + Z * self.scale, self.req)
        if self.mode == "violation":
            obj = np.sum(np.minimum(C, 0.0) ** 2, axis=1)
        self.z = np.array(z, dtype=float)
        self.f0, self.df = float(obj[0]), (obj[1:] - obj[0]) / self.h
        self.c0, self.dc = C[0], (C[1:] - C[0]).T / self.h

    def fun(self, z: np.ndarray) -> float:
        self.at(z)
        return self.f0

    def jac(self, z: np.ndarray) -> np.ndarray:
        self.at(z)
        return self.df

    def cfun(self, z: np.ndarray) -> np.ndarray:
        self.at(z)
        return self.c0

    def cjac(self, z: np.ndarray) -> np.ndarray:
        self.at(z)
        return self.dc


def _refine(x0: np.ndarray, req: Request, bounds: list[tuple[float, float]],
            target: str | None = None, maxiter: int = 60) -> np.ndarray:
    """SLSQP from x0 over the free parameters within ``bounds``.

    ``target=None``: minimise the objective subject to the smooth constraints of
    :func:`_smooth_constraints`; ``target="violation"``: minimise the squared constraint
    violations (bounds only); ``target=<constraint key>``: minimise that constraint's exact
    violation (from :func:`evaluate_candidates`) subject to the smooth form of all the others
    -- used to report the closest achievable value of a failing limit.
    """
    from scipy.optimize import minimize

    lo = np.array([b[0] for b in bounds])
    hi = np.array([b[1] for b in bounds])
    scale = np.where(hi > lo, hi - lo, 1.0)
    z0 = np.clip((np.asarray(x0) - lo) / scale, 0.0, 1.0)
    zb = [(0.0, 1.0)] * len(bounds)
    if target in (None, "violation"):
        ev = _Batch(req, lo, scale, "objective" if target is None else "violation")
        cons = ([{"type": "ineq", "fun": ev.cfun, "jac": ev.cjac}] if target is None else [])
        res = minimize(ev.fun, z0, jac=ev.jac, method="SLSQP", bounds=zb, constraints=cons,
                       options={"maxiter": maxiter, "ftol": 1e-12})
    else:
        relaxed = replace(req, **_relax(req, target))

        def g(z: np.ndarray) -> float:
            m = evaluate_candidates((lo + z * scale)[None, :], req, n_grid=sw.GRID // 2)
            v = float(m[f"g_{target}"][0])
            return v if math.isfinite(v) else 10.0

        ev = _Batch(relaxed, lo, scale)
        res = minimize(g, z0, method="SLSQP", bounds=zb,
                       constraints=[{"type": "ineq", "fun": ev.cfun, "jac": ev.cjac}],
                       options={"maxiter": maxiter, "ftol": 1e-10})
    return np.asarray(lo + np.clip(res.x, 0.0, 1.0) * scale)


def _relax(req: Request, key: str) -> dict[str, Any]:
    """Request fields that drop the constraint ``key`` (for the closest-value search)."""
    if key == "H":
        return {"H_tol": 1e3 * req.R}
    if key == "delta_f":
        return {"delta_f": math.pi / 2 - 1e-6}
    if key == "delta_r":
        return {"delta_r": math.pi / 2 - 1e-6}
    if key == "Pi_v":
        return {"Pi_v_max": None}
    if key == "point":
        return {"point": None}
    if key == "phi_f":
        return {"phi_f": None}
    if key == "unimodal":
        return {"unimodal": False}
    return {}


def _project(X: np.ndarray, req: Request, bounds: list[tuple[float, float]],
             iters: int = 6, lengthen_rod: bool = True) -> np.ndarray:
    """Repair candidates: lengthen too short rods and move each onto the wanted stroke.

    The rod's horizontal projection ``rho = l sin(delta_z)`` does not depend on ``l``, so the
    shortest rod meeting the pressure-angle limits is
    ``max(rho_f / sin[delta_f], rho_r / sin[delta_r])``; ``l`` is raised to it where shorter.
    The stroke is nearly ``2 r sin(alpha)`` (plus offset terms), so ``sin(alpha)`` (schemes 1,
    4b), ``tan(alpha)`` (4a, exact there), ``r`` (scheme 2) or the offset vector ``(a, b)``
    (scheme 3) is scaled by ``H / H(candidate)``. A few alternating passes, within the bounds.
    """
    X = np.array(X, dtype=float)
    free = list(req.free)
    lo = np.array([b[0] for b in bounds])
    hi = np.array([b[1] for b in bounds])
    jl = free.index("l")
    for _ in range(iters):
        P = tuple(np.asarray(p, dtype=float) for p in _full_params(req, X))
        c = sw._characteristics(P, "nan", 60)
        ok = np.isfinite(c.H)
        lv = P[2] / req.R
        l_min = np.maximum(lv * np.sin(c.delta_f) / math.sin(req.delta_f),
                           lv * np.sin(c.delta_r) / math.sin(req.delta_r)) * (1 + 1e-12)
        if lengthen_rod:
            X[:, jl] = np.where(ok, np.maximum(lv, l_min), X[:, jl])
        ratio = np.where(ok & (c.H > 0), req.H / np.where(ok & (c.H > 0), c.H, 1.0), 1.0)
        ratio = np.clip(ratio, 0.2, 5.0)
        if req.scheme in ("1", "4b"):
            j = free.index("alpha")
            X[:, j] = np.arcsin(np.clip(np.sin(X[:, j]) * ratio, 0.0, 1.0))
        elif req.scheme == "4a":
            j = free.index("alpha")
            X[:, j] = np.arctan(np.tan(X[:, j]) * ratio)
        elif req.scheme == "2":
            j = free.index("r")
            X[:, j] = X[:, j] * ratio
        else:
            for name in ("a", "b"):
                j = free.index(name)
                X[:, j] = X[:, j] * ratio
        X = np.clip(X, lo, hi)
    return X


def _screen(X: np.ndarray, req: Request, bounds: list[tuple[float, float]]
            ) -> dict[str, np.ndarray]:
    """One chunk of the search: repair (:func:`_project`), then evaluate (module level so that
    dask can pickle it)."""
    Xp = _project(X, req, bounds)
    m = evaluate_candidates(Xp, req, n_grid=120)
    m["X"] = Xp
    return m


#: The largest Sobol sample of :func:`synthesize`: 2^20 candidates. The screened sample and its
#: characteristics are kept (about 250 bytes per candidate measured: 0.26 GB at the limit) and
#: screening takes about 0.5 ms per candidate (some 10 minutes at the limit on one core); the
#: refinements, not a larger sample, find the optimum.
MAX_CANDIDATES = 2**20

#: The largest side of the grid of :func:`feasible_region` (n x n points, 10^6 at the limit).
MAX_REGION_N = 1000


def check_candidates(n_candidates: Any, parameter: str = "n_candidates") -> int:
    """``n_candidates`` as an int, or a :class:`~linkwork.errors.ParameterError` naming
    ``parameter``, the value and the limit: an integer from 1 to :data:`MAX_CANDIDATES`."""
    if isinstance(n_candidates, bool) or int(n_candidates) != n_candidates or n_candidates < 1:
        raise ParameterError(parameter, n_candidates, "must be an integer >= 1")
    if n_candidates > MAX_CANDIDATES:
        raise ParameterError(parameter, n_candidates, f"must be at most {MAX_CANDIDATES} "
                             "(2^20) candidates: the screened sample is kept (about 250 bytes "
                             "per candidate) and screened at about 0.5 ms per candidate, some "
                             "10 minutes at the limit; more --refine starts, not more "
                             "candidates, sharpen the optimum")
    return int(n_candidates)


def synthesize(req: Request, *, n_candidates: int = 16384, n_best: int = 5, n_refine: int = 4,
               chunk_size: int = 4096, seed: int = 0, client: Any = None,
               progress: Progress | None = None) -> SynthesisResult:
    """Find designs of scheme ``req.scheme`` meeting every limit of ``req``, best first.

    Parameters
    ----------
    req : Request
        What is wanted.
    n_candidates : int
        Size of the Sobol sample (rounded up to a power of two), at most
        :data:`MAX_CANDIDATES` (2^20).
    n_best : int
        Number of ranked designs returned (at most).
    n_refine : int
        Number of SLSQP refinements started from the best candidates.
    chunk_size, client, progress
        Passed to :func:`linkwork.sweep.evaluate` (memory per chunk, dask cluster, progress
        callback).
    seed : int
        Seed of the scrambled Sobol sample (results are reproducible).

    Returns
    -------
    SynthesisResult

    Raises
    ------
    InfeasibleError
        No design within the bounds meets every limit; names the constraint and the closest
        value achieved.
    """
    from scipy.stats import qmc

    check_candidates(n_candidates)
    for name, val, least in (("n_best", n_best, 1), ("n_refine", n_refine, 0)):
        if isinstance(val, bool) or int(val) != val or val < least:
            raise ParameterError(name, val, f"must be an integer >= {least}")
    bounds = req.search_bounds()
    k = len(bounds)
    lo = np.array([b[0] for b in bounds])
    hi = np.array([b[1] for b in bounds])
    m = max(4, math.ceil(math.log2(max(int(n_candidates), 2))))
    U = qmc.Sobol(k, scramble=True, seed=seed).random_base2(m)
    res = evaluate(functools.partial(_screen, req=req, bounds=bounds), lo + U * (hi - lo),
                   chunk_size=chunk_size, client=client, progress=progress)
    X = np.asarray(res["X"])
    feas = np.asarray(res["feasible"], dtype=bool)
    order = np.flatnonzero(feas)[_rank(res, feas)]
    pool = [X[order[: 4 * n_best]]]
    starts_x: list[np.ndarray] = []
    if feas.any():
        starts_x = [X[i] for i in _distinct(X, order, hi - lo, max(n_refine, 1))]
    # phase 1 from the least violating infeasible candidates (ranked by violation, then by
    # objective): reduce the violations, keep those that become feasible
    infeas = np.flatnonzero(~feas)
    n_phase1 = max(n_refine, 1) if not feas.any() else max(n_refine // 2, 1)
    if infeas.size:
        rank = np.lexsort((res["objective"][infeas], _violation(res)[infeas]))
        for i in _distinct(X, infeas[rank], hi - lo, n_phase1):
            x1 = _refine(X[i], req, bounds, target="violation")
            if evaluate_candidates(x1[None, :], req, sw.GRID // 2)["feasible"][0]:
                starts_x.append(x1)
                pool.append(x1[None, :])
    for x0 in starts_x:
        pool.append(_refine(x0, req, bounds)[None, :])
    Xp = np.unique(np.concatenate(pool), axis=0) if sum(len(p) for p in pool) else X[:0]
    mp = (evaluate_candidates(Xp, req, n_grid=sw.GRID) if len(Xp)
          else {"feasible": np.zeros(0, dtype=bool)})
    fp = np.asarray(mp["feasible"], dtype=bool)
    if not fp.any():
        raise _infeasible(req, X, res, bounds)
    idx = np.flatnonzero(fp)[_rank(mp, fp)]
    idx = _distinct(Xp, idx, hi - lo, n_best)
    designs = tuple(_design(req, Xp[i]) for i in idx)
    table = {key: np.asarray(mp[key])[idx] for key in TABLE_KEYS}
    if req.point is not None:  # the position at the requested point, to compare with s_p
        table["s_point"] = np.asarray(mp["s_point"])[idx]
    return SynthesisResult(request=req, designs=designs, table=table, n_evaluated=len(X),
                           n_feasible=int(feas.sum()),
                           candidates={"X": X, "feasible": feas,
                                       "objective": np.asarray(res["objective"])})


#: Objective values within this fraction of the best count as equal when ranking; the axial size
#: ``L`` decides between them (the peak-torque objective hardly depends on the rod length).
RANK_TIE = 1e-4


def _rank(m: dict[str, np.ndarray], mask: np.ndarray) -> np.ndarray:
    """Order of the ``mask``-ed designs: by objective, near-ties (:data:`RANK_TIE`) by ``L``."""
    obj = np.asarray(m["objective"])[mask]
    if obj.size == 0:
        return np.zeros(0, dtype=int)
    step = RANK_TIE * max(float(np.min(np.abs(obj))), 1e-300)
    return np.lexsort((np.asarray(m["L"])[mask], np.floor(obj / step)))


def _distinct(X: np.ndarray, idx: np.ndarray, span: np.ndarray, n: int) -> np.ndarray:
    """The first ``n`` of ``idx`` that differ from the ones kept by > 1e-3 of the bounds."""
    keep: list[int] = []
    for i in idx:
        if all(np.max(np.abs(X[i] - X[j]) / np.where(span > 0, span, 1.0)) > 1e-3
               for j in keep):
            keep.append(int(i))
        if len(keep) == n:
            break
    return np.array(keep, dtype=int)


def _design(req: Request, x: np.ndarray) -> sw.Design:
    R, r, l, al, a, b = (float(v[0]) for v in _full_params(req, x[None, :]))
    return sw.Design(R, r, l, al, a, b, scheme=req.scheme)


_QUANTITY = {"H": ("H", "m"), "delta_f": ("delta_f", "deg"), "delta_r": ("delta_r", "deg"),
             "Pi_v": ("Pi_v_max", "m/rad"), "point": ("s_point", "m"), "phi_f": ("phi_f", "deg"),
             "unimodal": ("unimodal", ""), "reach": ("H", "m")}


def _fmt_q(key: str, value: float) -> str:
    name, unit = _QUANTITY[key]
    if unit == "deg":
        return f"{name} = {math.degrees(value):.4g} deg"
    if unit == "":
        return f"{name} = {bool(value)}"
    return f"{name} = {value:.6g} {unit}"


def _limit_text(req: Request, key: str) -> str:
    if key == "H":
        return f"stroke H = {req.H:.6g} m +- {req.H_tol:.3g} m"
    if key == "delta_f":
        return f"max pressure angle on the forward stroke <= {math.degrees(req.delta_f):.4g} deg"
    if key == "delta_r":
        return f"max pressure angle on the return stroke <= {math.degrees(req.delta_r):.4g} deg"
    if key == "Pi_v":
        return f"max |Pi_v| <= {req.Pi_v_max:.6g} m/rad (velocity limit)"
    if key == "point":
        assert req.point is not None
        return (f"s({math.degrees(req.point[0]):.4g} deg) = {req.point[1]:.6g} m "
                f"+- {req.point_tol:.3g} m")
    if key == "phi_f":
        assert req.phi_f is not None
        return (f"forward-stroke angle phi_f = {math.degrees(req.phi_f):.4g} deg "
                f"+- {math.degrees(req.phi_f_tol):.3g} deg")
    return CONSTRAINTS[key]


def _infeasible(req: Request, X: np.ndarray, res: dict[str, np.ndarray],
                bounds: list[tuple[float, float]]) -> InfeasibleError:
    """Name the constraint that cannot be met and the closest value achieved for it."""
    keys = [k for k in CONSTRAINTS if f"g_{k}" in res]
    G = {k: np.asarray(res[f"g_{k}"]) for k in keys}
    ok = {k: G[k] <= 0 for k in keys}
    rates = {k: float(ok[k].mean()) for k in keys}

    def met_except(drop: set[str]) -> np.ndarray:
        m = np.ones(len(X), dtype=bool)
        for j in keys:
            if j not in drop:
                m &= ok[j]
        return m

    culprit = None
    also: list[str] = []  # further limits that fail too (dropped for the closest value)
    for k in keys:  # a single constraint whose removal makes the request feasible
        others = met_except({k})
        if others.any():
            culprit = k
            break
    if culprit is None:  # several fail together: the smallest pair whose removal helps
        pairs = [(k, j) for n, k in enumerate(keys) for j in keys[n + 1:]
                 if met_except({k, j}).any()]
        if pairs:
            k, j = min(pairs, key=lambda kj: rates[kj[0]] + rates[kj[1]])
            culprit, other = (k, j) if (rates[k], k) <= (rates[j], j) else (j, k)
            also = [other]
            others = met_except({k, j})
        else:  # no pair either: the one least often met on its own, others ignored
            culprit = min(rates, key=lambda k: (rates[k], float(np.nanmin(G[k]))))
            also = [k for k in keys if k != culprit and rates[k] < 1.0]
            others = np.ones(len(X), dtype=bool)
    gk = np.where(others, G[culprit], np.inf)
    i = int(np.argmin(gk)) if np.isfinite(gk).any() else int(np.argmin(G[culprit]))
    x_best = X[i]
    qkey = _QUANTITY[culprit][0]
    closest = float(np.asarray(res[qkey])[i]) if qkey in res else float("nan")
    if culprit not in ("unimodal", "reach"):
        rreq = req
        for j in also:
            rreq = replace(rreq, **_relax(rreq, j))
        try:
            xr = _refine(x_best, rreq, bounds, target=culprit)
            mr = evaluate_candidates(xr[None, :], rreq, n_grid=sw.GRID)
            others_ok = all(float(mr[f"g_{j}"][0]) <= 1e-9 for j in keys
                            if j != culprit and f"g_{j}" in mr)
            if others_ok and float(mr[f"g_{culprit}"][0]) < float(gk[i]):
                closest = float(mr[qkey][0])
        except (ValueError, ArithmeticError):  # keep the sampled value
            pass
    detail = (f"scheme {req.scheme}, {len(X)} candidates within the search bounds, none "
              "meets every limit")
    if also:
        detail += ("; these fail as well and are left out of the closest value: "
                   + ", ".join(_limit_text(req, j) for j in also))
    err = InfeasibleError(_limit_text(req, culprit), _fmt_q(culprit, closest), detail)
    err.key = culprit  # type: ignore[attr-defined]
    err.closest_value = closest  # type: ignore[attr-defined]
    return err


@dataclass(frozen=True)
class FeasibleRegion(Result):
    """Feasible set over two parameters, the others held at ``base`` (a design).

    ``x``, ``y``: grid values (relative lengths or alpha [rad]) of parameters ``x_name`` and
    ``y_name``; ``feasible`` (ny, nx) bool; ``objective`` (ny, nx); ``violations`` per
    constraint (ny, nx); ``base`` the design whose other parameters are kept.
    """

    x_name: str
    y_name: str
    x: np.ndarray
    y: np.ndarray
    feasible: np.ndarray
    objective: np.ndarray
    violations: dict[str, np.ndarray]
    base: sw.Design
    request: Request

    units: ClassVar[dict[str, str]] = {}
    position_field: ClassVar[str] = "x"

    def scalars(self) -> dict[str, Any]:
        return {"x_name": self.x_name, "y_name": self.y_name,
                "feasible_fraction": float(np.mean(self.feasible))}

    def plot(self, ax: Any = None, **kw: Any) -> Figure:
        """The feasible set over the two parameters with objective contours and the failing
        limits: a :class:`linkwork.plot.Figure` with 1 axes."""
        from linkwork.plot.swashplate import feasible_region_figure

        return feasible_region_figure(self, ax=ax, **kw)


def feasible_region(req: Request, base: sw.Design, x_name: str, y_name: str, *,
                    x_range: tuple[float, float] | None = None,
                    y_range: tuple[float, float] | None = None,
                    n: int = 60) -> FeasibleRegion:
    """Map which ``(x, y)`` values of two free parameters meet every limit of ``req``
    (``n`` x ``n`` points, ``n`` from 2 to :data:`MAX_REGION_N`).

    The other free parameters stay at their values in ``base``, except the scheme's stroke
    parameter (``alpha`` in schemes 1, 4a, 4b; ``r`` in 2; ``(a, b)`` in 3), which -- unless it
    is ``x`` or ``y`` -- is adjusted at each point to give the wanted stroke (otherwise the
    stroke equality leaves only a line in the map). Ranges default to the search bounds;
    lengths are relative (over ``R``), ``alpha`` in rad.
    """
    if isinstance(n, bool) or int(n) != n or not 2 <= n <= MAX_REGION_N:
        raise ParameterError("n", n, f"must be an integer from 2 to {MAX_REGION_N} (an n x n "
                             "grid of candidates, 10^6 at the limit)")
    free = list(req.free)
    for name in (x_name, y_name):
        if name not in free:
            raise ParameterError("parameter", name, f"must be a free parameter of scheme "
                                 f"{req.scheme}: {', '.join(free)}")
    if x_name == y_name:
        raise ParameterError("y_name", y_name, "must differ from x_name")
    bnd = dict(zip(free, req.search_bounds(), strict=True))
    xr = x_range or bnd[x_name]
    yr = y_range or bnd[y_name]
    xs = np.linspace(xr[0], xr[1], n)
    ys = np.linspace(yr[0], yr[1], n)
    rel = base.relative()
    x0 = np.array([rel[k] for k in free])
    XX, YY = np.meshgrid(xs, ys)
    X = np.tile(x0, (XX.size, 1))
    X[:, free.index(x_name)] = XX.ravel()
    X[:, free.index(y_name)] = YY.ravel()
    stroke_par = {"1": ("alpha",), "4a": ("alpha",), "4b": ("alpha",), "2": ("r",),
                  "3": ("a", "b")}[req.scheme]
    if not set(stroke_par) & {x_name, y_name}:
        X = _project(X, req, req.search_bounds(), lengthen_rod=False)
    m = evaluate(functools.partial(_chunk_eval, req=replace(req), n_grid=120), X,
                 chunk_size=4096)
    viol = {k: np.asarray(m[f"g_{k}"]).reshape(XX.shape) for k in CONSTRAINTS
            if f"g_{k}" in m}
    return FeasibleRegion(x_name=x_name, y_name=y_name, x=xs, y=ys,
                          feasible=np.asarray(m["feasible"]).reshape(XX.shape),
                          objective=np.asarray(m["objective"]).reshape(XX.shape),
                          violations=viol, base=base, request=req)
