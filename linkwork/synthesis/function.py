r"""Function generation: a four-bar (output rocker angle) or an offset crank-slider (output slide)
as a function of the crank angle.

A function ``y = f(x)`` on ``[x0, x1]`` is mapped linearly onto the crank's range ``phi =
phi_start + dphi (x - x0)/(x1 - x0)`` and the output's range: the rocker angle ``psi =
psi_start + dpsi (y - y0)/(y1 - y0)`` (four-bar), or the slide ``s = ds (y - y0)/(y1 - y0)``
measured from its position at ``phi_start`` (crank-slider). Angles follow
:mod:`linkwork.models.fourbar` (from the frame line O2 -> O4, counter-clockwise; ``psi`` is
Norton's theta4) and :mod:`linkwork.models.crank_slider` (paper 000: crank from +X, slide along
+Y on the line X = e).

Methods
-------
* **Freudenstein's equation** (Norton [1]_, Eq. (5.42)), linear in ``K1 = d/a``, ``K2 = d/c``,
  ``K3 = (a^2 - b^2 + c^2 + d^2)/(2 a c)``:
  ``K1 cos(psi) - K2 cos(phi) + K3 = cos(phi - psi)``; for the crank-slider the same idea:
  ``(Y - L1 sin phi)^2 + (e - L1 cos phi)^2 = L2^2`` is linear in ``2 L1``, ``2 e L1`` and
  ``L1^2 + e^2 - L2^2`` once the slide's datum ``Y0 = Y(phi_start)`` is fixed.
* **Three precision points at Chebyshev spacing** (Norton, Eq. (5.40);
  ``x_j = (x0 + x1)/2 - (x1 - x0)/2 cos((2j - 1) pi / 6)``): the linear system solved exactly.
* **Least squares over many points**: the linear equations in the least-squares sense
  (Freudenstein's design error), then SciPy's ``least_squares`` on the **structural error**
  (the output the linkage really gives minus the wanted one) over the link lengths.
* The **structural error** over the whole input range (dense) is reported for every design, on
  the assembly branch through which the linkage reaches the precision points; a design whose
  precision points lie on different branches (circuit defect) or that cannot be assembled
  somewhere in the range (a toggle inside it: branch defect) is rejected.

References
----------
.. [1] R. L. Norton, *Design of Machinery*, 5th ed., McGraw-Hill, 2012, Sec. 5.12-5.13.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar, Literal

import numpy as np

from linkwork.errors import InfeasibleError, ParameterError
from linkwork.models.crank_slider import offset_crank_slider
from linkwork.models.fourbar import fourbar
from linkwork.planar.model import Mechanism, crank_slider_mechanism, fourbar_mechanism
from linkwork.results import Result
from linkwork.synthesis.design import write_planar_toml

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = ["FunctionDesign", "FunctionResult", "chebyshev_spacing", "crank_slider_function",
           "fourbar_function"]

#: Input positions of the structural error over the range.
DENSE = 721


def chebyshev_spacing(x0: float, x1: float, n: int = 3) -> np.ndarray:
    """Chebyshev spacing of ``n`` precision points on ``[x0, x1]`` (Norton Eq. (5.40))."""
    j = np.arange(1, n + 1)
    return (x0 + x1) / 2 - (x1 - x0) / 2 * np.cos((2 * j - 1) * math.pi / (2 * n))


@dataclass(frozen=True)
class FunctionDesign:
    """One function generator and its structural error.

    ``kind``: ``"fourbar"`` (params ``a b c d`` [m], output psi [rad]) or ``"crank_slider"``
    (params ``L1 L2 e`` [m] and ``Y0`` the slide at the range start [m]). ``input``: dense crank
    angles over the range [rad]; ``wanted``, ``actual``: the output there (rad or m);
    ``structural_error = actual - wanted``; ``precision_inputs``: crank angles of the precision
    points (None for least squares); ``branch``: the assembly branch used.
    """

    kind: Literal["fourbar", "crank_slider"]
    method: str
    params: dict[str, float]
    branch: int
    input: np.ndarray
    wanted: np.ndarray
    actual: np.ndarray
    precision_inputs: np.ndarray | None

    @property
    def structural_error(self) -> np.ndarray:
        return self.actual - self.wanted

    @property
    def max_error(self) -> float:
        """Largest |structural error| over the range (rad or m)."""
        return float(np.max(np.abs(self.structural_error)))

    @property
    def rms_error(self) -> float:
        """RMS of the structural error over the range (rad or m)."""
        return float(np.sqrt(np.mean(self.structural_error ** 2)))

    def mechanism(self, omega1: float = 1.0) -> Mechanism:
        """The engine model: :func:`~linkwork.planar.model.fourbar_mechanism` (``phi1`` = the
        crank angle from the frame line) or :func:`~linkwork.planar.model.crank_slider_mechanism`
        with the guide along +Y (paper 000's slider; the engine's offset is ``-e``)."""
        p = self.params
        if self.kind == "fourbar":
            return fourbar_mechanism(p["a"], p["b"], p["c"], p["d"], omega1=omega1,
                                     branch=self.branch)
        return crank_slider_mechanism(p["L1"], p["L2"], -p["e"], guide_angle=math.pi / 2,
                                      omega1=omega1, branch=self.branch)

    def to_toml(self, path: str | Path, *, name: str | None = None, n: int = 361) -> Path:
        """A ``planar`` file of the design over its input range (``linkwork analyze`` reads it)."""
        p = ", ".join(f"{k} = {v!r}" for k, v in self.params.items())
        return write_planar_toml(
            self.mechanism(), path, name=name or f"{self.kind} function generator",
            start=float(self.input[0]), stop=float(self.input[-1]), n=n,
            comments=(f"A {self.kind} function generator synthesised by linkwork ({self.method}).",
                      f"parameters: {p}, branch = {self.branch}",
                      f"structural error: max {self.max_error!r}, RMS {self.rms_error!r} "
                      f"({'rad' if self.kind == 'fourbar' else 'm'})"))


@dataclass(frozen=True)
class FunctionResult(Result):
    """Function generators for one task, best (smallest max structural error) first."""

    kind: str
    designs: tuple[FunctionDesign, ...]
    x_range: tuple[float, float]
    input_range: tuple[float, float]
    output_range: tuple[float, float]

    units: ClassVar[dict[str, str]] = {"max_error": "", "rms_error": "", "rank": ""}
    position_field: ClassVar[str] = "rank"

    @property
    def rank(self) -> np.ndarray:
        return np.arange(1, len(self.designs) + 1)

    @property
    def best(self) -> FunctionDesign:
        return self.designs[0]

    def columns(self) -> dict[str, np.ndarray]:
        cols: dict[str, np.ndarray] = {"rank": self.rank}
        for k in self.designs[0].params:
            cols[k] = np.array([d.params[k] for d in self.designs])
        cols["branch"] = np.array([d.branch for d in self.designs], dtype=float)
        cols["max_error"] = np.array([d.max_error for d in self.designs])
        cols["rms_error"] = np.array([d.rms_error for d in self.designs])
        return cols

    def _unit_of(self, column: str) -> str:
        if column in ("max_error", "rms_error"):
            return "rad" if self.kind == "fourbar" else "m"
        return "m" if column in ("a", "b", "c", "d", "L1", "L2", "e", "Y0") else ""

    def scalars(self) -> dict[str, Any]:
        return {"kind": self.kind, "methods": [d.method for d in self.designs],
                "x_range": list(self.x_range), "input_range": list(self.input_range),
                "output_range": list(self.output_range)}

    def plot(self, ax: Any = None, **kw: Any) -> Figure:
        """The structural error of every design over the input range: 1 axes."""
        from linkwork.plot.synthesis import function_figure

        return function_figure(self, ax=ax, **kw)


def _check_task(f: Callable[[np.ndarray], Any], x_range: tuple[float, float],
                phi_range: tuple[float | None, float], n_points: int
                ) -> tuple[float, float, float, float]:
    x0, x1 = (float(v) for v in x_range)
    if not (math.isfinite(x0) and math.isfinite(x1)) or x1 == x0:
        raise ParameterError("x_range", x_range, "must be two different finite numbers")
    p0 = 0.0 if phi_range[0] is None else float(phi_range[0])
    dp = float(phi_range[1])
    if not (math.isfinite(p0) and math.isfinite(dp)) or dp == 0 or abs(dp) >= 2 * math.pi:
        raise ParameterError("phi_range", phi_range, "must be (start, span) [rad] with "
                             "0 < |span| < 2 pi")
    if n_points < 3:
        raise ParameterError("n_points", n_points, "too few: function generation needs at "
                             "least 3 precision points (3 unknowns of Freudenstein's equation)")
    y = np.asarray(f(np.array([x0, x1])), dtype=float)
    if y.shape != (2,) or not np.all(np.isfinite(y)) or y[0] == y[1]:
        raise ParameterError("f", y.tolist(), "must give finite, different values at the ends "
                             "of x_range (the output range maps y(x0) -> y(x1))")
    return x0, x1, p0, dp


def _fourbar_output(phi: np.ndarray, p: dict[str, float], branch: int) -> np.ndarray:
    r = fourbar(phi, p["a"], p["b"], p["c"], p["d"], branch=branch, on_failure="nan")
    return np.asarray(r.theta4)


def _unwrap_near(psi: np.ndarray, wanted: np.ndarray) -> np.ndarray:
    """``psi`` shifted by whole turns to lie nearest ``wanted`` (angles compared as angles)."""
    return wanted + np.mod(psi - wanted + math.pi, 2 * math.pi) - math.pi


def _fourbar_design(K: np.ndarray, d: float, method: str, phi: np.ndarray, wanted: np.ndarray,
                    prec: np.ndarray | None, prec_out: np.ndarray | None = None
                    ) -> FunctionDesign | str:
    """A design from Freudenstein's K1..K3, on the branch that reaches the precision points;
    else the defect (a string)."""
    K1, K2, K3 = (float(k) for k in K)
    if not (K1 > 0 and K2 > 0):
        return "negative link length (K1 or K2 <= 0)"
    a, c = d / K1, d / K2
    b2 = a * a + c * c + d * d - 2 * a * c * K3
    if not b2 > 0:
        return "no real coupler length (b^2 <= 0)"
    p = {"a": a, "b": math.sqrt(b2), "c": c, "d": d}
    best: FunctionDesign | str = "circuit defect: the precision points lie on different branches"
    for br in (1, -1):
        out = _fourbar_output(phi, p, br)
        if np.any(np.isnan(out)):
            best = "branch defect: the linkage cannot be assembled over the whole input range"
            continue
        out = _unwrap_near(out, wanted)
        if prec is not None and prec_out is not None:
            pr_out = _unwrap_near(_fourbar_output(prec, p, br), prec_out)
            if np.max(np.abs(pr_out - prec_out)) > 1e-6:
                continue
        cand = FunctionDesign("fourbar", method, p, br, phi, wanted, out, prec)
        if isinstance(best, str) or cand.max_error < best.max_error:
            best = cand
    return best


#: Start angles tried when ``phi_range`` or ``psi_range`` leaves its start free (None).
START_GRID = 36


def fourbar_function(f: Callable[[np.ndarray], Any], x_range: tuple[float, float],
                     phi_range: tuple[float | None, float],
                     psi_range: tuple[float | None, float], *, d: float = 1.0,
                     n_least_squares: int = 41, n_points: int = 3) -> FunctionResult:
    """Four-bars generating ``y = f(x)``: ``n_points`` (3) precision points at Chebyshev
    spacing, and least squares over ``n_least_squares`` points refined on the structural error.

    Parameters
    ----------
    f : callable
        The function, vectorised over an array of x.
    x_range : (x0, x1)
        The range of x.
    phi_range, psi_range : (start, span)
        Crank and rocker angles [rad] (from the frame line) that x0 and y0 = f(x0) map to, and
        the spans that x1 and f(x1) map to. A start given as None is searched (every
        360/:data:`START_GRID` deg) for the defect-free three-point design of smallest
        structural error.
    d : float
        Frame length [m] (the linkage scales with it).

    Returns
    -------
    FunctionResult
        The designs found (precision points, least squares), smallest max error first.

    Raises
    ------
    ParameterError
        Bad ranges, fewer than 3 precision points.
    InfeasibleError
        No defect-free design with positive link lengths; names the reason.
    """
    _, _, _, dp = _check_task(f, x_range, phi_range, n_points)
    ds = float(psi_range[1])
    if not math.isfinite(ds) or ds == 0:
        raise ParameterError("psi_range", psi_range, "must be (start, span) [rad], span != 0")
    if not d > 0:
        raise ParameterError("d", d, "must be > 0")
    grid = np.arange(START_GRID) * (2 * math.pi / START_GRID)
    p_starts = grid if phi_range[0] is None else [float(phi_range[0])]
    s_starts = grid if psi_range[0] is None else [float(psi_range[0])]
    best: FunctionResult | None = None
    reasons: list[str] = []
    for p0 in p_starts:
        for s0 in s_starts:
            try:
                r = _fourbar_function(f, x_range, (float(p0), dp), (float(s0), ds), d,
                                      n_least_squares, n_points,
                                      refine=len(p_starts) * len(s_starts) == 1)
            except InfeasibleError as exc:
                reasons.append(str(exc.closest))
                continue
            if best is None or r.best.max_error < best.best.max_error:
                best = r
    if best is None:
        raise InfeasibleError("a defect-free four-bar with positive link lengths for these "
                              "ranges", "; ".join(sorted(set(reasons))),
                              "change phi_range/psi_range (start angles or spans)")
    if len(p_starts) * len(s_starts) > 1:  # refine the best start found
        best = _fourbar_function(f, x_range, best.input_range, best.output_range, d,
                                 n_least_squares, n_points, refine=True)
    return best


def _fourbar_function(f: Callable[[np.ndarray], Any], x_range: tuple[float, float],
                      phi_range: tuple[float, float], psi_range: tuple[float, float],
                      d: float, n_least_squares: int, n_points: int, refine: bool
                      ) -> FunctionResult:
    x0, x1 = (float(v) for v in x_range)
    p0, dp = phi_range
    s0, ds = psi_range
    y0, y1 = (float(v) for v in np.asarray(f(np.array([x0, x1])), dtype=float))

    def phi_of(x: np.ndarray) -> np.ndarray:
        return p0 + dp * (x - x0) / (x1 - x0)

    def psi_of(x: np.ndarray) -> np.ndarray:
        return s0 + ds * (np.asarray(f(x), dtype=float) - y0) / (y1 - y0)

    xs = np.linspace(x0, x1, DENSE)
    phi, wanted = phi_of(xs), psi_of(xs)
    designs: list[FunctionDesign] = []
    reasons: list[str] = []

    def solve(x: np.ndarray) -> np.ndarray:
        ph, ps = phi_of(x), psi_of(x)
        A = np.c_[np.cos(ps), -np.cos(ph), np.ones_like(ph)]
        return np.linalg.lstsq(A, np.cos(ph - ps), rcond=None)[0]

    xp = chebyshev_spacing(x0, x1, n_points)
    des = _fourbar_design(solve(xp), d, f"Chebyshev precision points ({n_points})", phi, wanted,
                          phi_of(xp), psi_of(xp))
    (designs.append(des) if isinstance(des, FunctionDesign) else reasons.append(des))
    if refine or designs:
        xl = np.linspace(x0, x1, max(int(n_least_squares), 3))
        des = _fourbar_design(solve(xl), d, f"least squares ({len(xl)} points)", phi, wanted,
                              None)
        if isinstance(des, FunctionDesign):
            designs.append(des)
            if refine:
                ref = _refine_fourbar(des, xl, phi_of, psi_of)
                if ref is not None:
                    designs.append(ref)
        else:
            reasons.append(des)
    if not designs:
        raise InfeasibleError("a defect-free four-bar with positive link lengths for these "
                              "ranges", "; ".join(reasons),
                              "change phi_range/psi_range (start angles or spans)")
    designs.sort(key=lambda g: g.max_error)
    return FunctionResult(kind="fourbar", designs=tuple(designs), x_range=(x0, x1),
                          input_range=(p0, dp), output_range=(s0, ds))


def _refine_fourbar(des: FunctionDesign, xl: np.ndarray, phi_of: Callable[..., np.ndarray],
                    psi_of: Callable[..., np.ndarray]) -> FunctionDesign | None:
    """Least squares on the structural error at ``xl`` over (a, b, c), d fixed."""
    from scipy.optimize import least_squares

    d = des.params["d"]
    ph, ps = phi_of(xl), psi_of(xl)

    def res(v: np.ndarray) -> np.ndarray:
        p = {"a": v[0], "b": v[1], "c": v[2], "d": d}
        out = _fourbar_output(ph, p, des.branch)
        return np.where(np.isnan(out), math.pi, _unwrap_near(out, ps) - ps)

    v0 = np.array([des.params[k] for k in ("a", "b", "c")])
    sol = least_squares(res, v0, bounds=(1e-9 * d, np.inf), x_scale="jac", max_nfev=400)
    p = {"a": float(sol.x[0]), "b": float(sol.x[1]), "c": float(sol.x[2]), "d": d}
    out = _fourbar_output(des.input, p, des.branch)
    if np.any(np.isnan(out)):
        return None
    new = FunctionDesign("fourbar", f"least squares on the structural error ({len(xl)} points)",
                         p, des.branch, des.input, des.wanted,
                         _unwrap_near(out, des.wanted), None)
    return new if new.max_error < des.max_error or new.rms_error < des.rms_error else None


def _slider_output(phi: np.ndarray, p: dict[str, float], branch: int) -> np.ndarray:
    r = offset_crank_slider(phi, p["L1"], p["L2"] / p["L1"], p["e"] / p["L1"], branch=branch,
                            on_failure="nan")
    return np.asarray(r.Y_C) - p["Y0"]


def _slider_design(Y0: float, ph: np.ndarray, s: np.ndarray, method: str, phi: np.ndarray,
                   wanted: np.ndarray, prec: bool) -> FunctionDesign | str:
    """A crank-slider through the points ``(ph, s)`` (least squares beyond three); with
    ``prec`` they are precision points and must be met on the design's branch."""
    Y = Y0 + s
    A = np.c_[Y * np.sin(ph), np.cos(ph), -np.ones_like(ph)]
    K = np.linalg.lstsq(A, Y * Y, rcond=None)[0]
    L1 = K[0] / 2
    if not L1 > 0:
        return "negative crank length"
    e = K[1] / (2 * L1)
    L2sq = L1 * L1 + e * e - K[2]
    if not L2sq > 0:
        return "no real rod length"
    p = {"L1": float(L1), "L2": float(math.sqrt(L2sq)), "e": float(e), "Y0": float(Y0)}
    for br in (1, -1):
        out = _slider_output(phi, p, br)
        if np.any(np.isnan(out)):
            continue
        if prec and np.max(np.abs(_slider_output(ph, p, br) - s)) > 1e-6 * max(abs(Y0), L1):
            continue
        return FunctionDesign("crank_slider", method, p, br, phi, wanted, out,
                              ph if prec else None)
    return "circuit or branch defect"


def crank_slider_function(f: Callable[[np.ndarray], Any], x_range: tuple[float, float],
                          phi_range: tuple[float, float], stroke: float, *,
                          datum: float | None = None, n_points: int = 3,
                          n_least_squares: int = 41) -> FunctionResult:
    """Offset crank-sliders whose slide ``s = Y_C - Y_C(phi_start)`` generates ``y = f(x)``
    (``stroke`` [m]: the slide travel from f(x0) to f(x1), signed).

    ``datum`` is the slide's position ``Y0`` at the range start, measured along +Y from the
    line through the crank axis normal to the guide [m]; None: chosen (a one-dimensional search)
    to minimise the structural error of the three-point design. Precision points at Chebyshev
    spacing and least squares as :func:`fourbar_function`.
    """
    from scipy.optimize import minimize_scalar

    x0, x1, p0, dp = _check_task(f, x_range, phi_range, n_points)
    if not (math.isfinite(stroke) and stroke != 0):
        raise ParameterError("stroke", stroke, "must be finite and != 0 [m]")
    y0, y1 = (float(v) for v in np.asarray(f(np.array([x0, x1])), dtype=float))

    def phi_of(x: np.ndarray) -> np.ndarray:
        return p0 + dp * (x - x0) / (x1 - x0)

    def s_of(x: np.ndarray) -> np.ndarray:
        return stroke * (np.asarray(f(x), dtype=float) - y0) / (y1 - y0)

    xs = np.linspace(x0, x1, DENSE)
    phi, wanted = phi_of(xs), s_of(xs)
    xp = chebyshev_spacing(x0, x1, n_points)
    xl = np.linspace(x0, x1, max(int(n_least_squares), 3))

    def error_of(Y0: float, x: np.ndarray, prec: bool) -> float:
        des = _slider_design(Y0, phi_of(x), s_of(x), "", phi, wanted, prec)
        return des.max_error if isinstance(des, FunctionDesign) else math.inf

    H = abs(stroke)
    designs: list[FunctionDesign] = []
    for x, label, prec in ((xp, f"Chebyshev precision points ({n_points})", True),
                           (xl, f"least squares ({len(xl)} points)", False)):
        if datum is None:
            grid = np.linspace(-6 * H, 6 * H, 241)
            errs = np.array([error_of(g, x, prec) for g in grid])
            if not np.isfinite(errs).any():
                continue
            g0 = float(grid[int(np.argmin(errs))])
            sol = minimize_scalar(lambda g, x=x, prec=prec: error_of(g, x, prec),
                                  bounds=(g0 - 0.05 * H, g0 + 0.05 * H), method="bounded")
            Y0 = float(sol.x) if sol.fun <= errs.min() else g0
        else:
            Y0 = float(datum)
        des = _slider_design(Y0, phi_of(x), s_of(x), label, phi, wanted, prec)
        if isinstance(des, FunctionDesign):
            designs.append(des)
    if not designs:
        raise InfeasibleError("a defect-free offset crank-slider for these ranges",
                              "none with a positive crank and a real rod",
                              "change phi_range, stroke or datum")
    designs.sort(key=lambda g: g.max_error)
    return FunctionResult(kind="crank_slider", designs=tuple(designs), x_range=(x0, x1),
                          input_range=(p0, dp), output_range=(0.0, float(stroke)))
