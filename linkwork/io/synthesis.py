"""The ``synthesis`` task file: what ``linkwork synthesize function|motion|path`` is asked.

Example (path generation, Kunjur and Krishnamurty's six points on a line)::

    type = "synthesis"
    name = "six points on a vertical line"

    [path]
    # linkage = "fourbar"                  # or "stephenson" / "watt": a six-bar's point P
    points = [["20 mm", "20 mm"], ["20 mm", "25 mm"], ["20 mm", "30 mm"],
              ["20 mm", "35 mm"], ["20 mm", "40 mm"], ["20 mm", "45 mm"]]
    # timing = ["30 deg", "45 deg", ...]   # crank angles from the frame line (optional)
    # free_start = true                    # with timing: only its advances prescribed
    closed = false
    constraints = ["grashof", "order"]
    min_transmission = "30 deg"            # optional
    bounds = { r1 = ["5 mm", "60 mm"], r2 = ["5 mm", "60 mm"], theta0 = ["0 deg", "360 deg"] }

    [search]                               # optional
    candidates = 65536
    refine = 24
    designs = 5
    seed = 0

    [objective]                            # optional: judged by forces as well
    kind = "pareto"                        # "sum_squares" (default), "weighted", "pareto"
    metrics = ["error", "peak_torque"]     # pareto
    weights = { error = 1, peak_torque = 1 }   # weighted
    omega1 = "100 rpm"                     # crank speed
    section = 1e-4                         # bar cross-section [m^2] (masses from lengths)
    density = 7850                         # [kg/m^3]
    masses = ["0.5 kg", "1.2 kg", "0.8 kg"]    # or given: crank, coupler, rocker
    force = ["0 N", "-50 N"]               # tool force on the coupler point

Function generation::

    [function]
    mechanism = "fourbar"                  # or "crank_slider"
    y = "log10(x)"                         # an expression of x (numpy functions), or a table:
    # x = [1, 2, 4, 10]  y = [0, 0.301, 0.602, 1]   (cubic spline through it)
    x_range = [1, 10]
    input = { start = "30 deg", span = "60 deg" }     # start optional: searched
    output = { start = "110 deg", span = "60 deg" }   # four-bar: rocker angles
    # stroke = "80 mm", datum = "150 mm"               # crank-slider: slide travel, datum
    frame = "100 mm"                       # four-bar frame length d

Motion generation::

    [motion]
    poses = [["0 mm", "0 mm", "0 deg"], ["20 mm", "10 mm", "15 deg"], ...]   # 3, 4 or 5
    fixed_pivots = [["-50 mm", 0], ["80 mm", 0]]    # 3 poses (or moving_pivots)
    pivot_region = [["-100 mm", "100 mm"], ["-80 mm", "0 mm"]]   # 4, 5 poses (optional)
    grashof = false
    min_transmission = "30 deg"

Plain numbers are SI (metres, radians); strings carry units. Unknown keys are errors.
"""

from __future__ import annotations

import ast
import math
from collections.abc import Callable
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import Field, model_validator
from pydantic_core import PydanticCustomError

from linkwork.io.toml import Angle, AngularVelocity, FileModel, Force, Length, Mass
from linkwork.synthesis.design import PARAMS
from linkwork.synthesis.forces import ForceModel, Objective
from linkwork.synthesis.sixbar import SIXBAR_PARAMS
from linkwork.units import to_si

__all__ = ["FunctionSection", "MotionSection", "ObjectiveSection", "PathSection",
           "SearchSection", "SynthesisFile", "expression"]

XY = tuple[Length, Length]
Pose = tuple[Length, Length, Angle]
PositiveInt = Annotated[int, Field(ge=1)]

#: Names an expression of ``[function] y`` may use (numpy's, vectorised over x).
FUNCTIONS: dict[str, Any] = {
    "sin": np.sin, "cos": np.cos, "tan": np.tan, "arcsin": np.arcsin, "arccos": np.arccos,
    "arctan": np.arctan, "sinh": np.sinh, "cosh": np.cosh, "tanh": np.tanh, "exp": np.exp,
    "log": np.log, "log10": np.log10, "log2": np.log2, "sqrt": np.sqrt, "abs": np.abs,
    "pi": math.pi, "e": math.e}

_NODES = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Call, ast.Name, ast.Load, ast.Constant,
          ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow, ast.USub, ast.UAdd, ast.Mod)


def expression(text: str) -> Callable[[np.ndarray], np.ndarray]:
    """A vectorised function of ``x`` from an arithmetic expression (``+ - * / ** %``,
    numbers, ``x`` and the names of :data:`FUNCTIONS`); anything else is a ValueError
    naming it (nothing is executed that is not arithmetic)."""
    tree = ast.parse(text, mode="eval")
    for node in ast.walk(tree):
        if not isinstance(node, _NODES):
            raise ValueError(f"{type(node).__name__} is not allowed in an expression of x")
        if isinstance(node, ast.Name) and node.id != "x" and node.id not in FUNCTIONS:
            raise ValueError(f"unknown name {node.id!r}; known: x, {', '.join(FUNCTIONS)}")
        if isinstance(node, ast.Call) and not (isinstance(node.func, ast.Name)
                                               and callable(FUNCTIONS.get(node.func.id))):
            raise ValueError("only the functions " + ", ".join(
                k for k, v in FUNCTIONS.items() if callable(v)) + " may be called")
    code = compile(tree, "<y>", "eval")

    def f(x: np.ndarray) -> np.ndarray:
        with np.errstate(all="ignore"):
            return np.asarray(eval(code, {"__builtins__": {}}, {**FUNCTIONS, "x": x}),
                              dtype=float) * np.ones_like(np.asarray(x, dtype=float))

    return f


def _bound_value(name: str, v: Any) -> float:
    kind = "angle" if name.startswith("theta") else "length"
    return to_si(v, kind, f"bounds.{name}")


def _default_constraints() -> list[Literal["grashof", "order"]]:
    return ["grashof", "order"]


class PathSection(FileModel):
    """``[path]``: the linkage, target points, optional timing, closed, constraints, bounds
    (the four-bar's parameters, or the six-bar's :data:`~linkwork.synthesis.sixbar.
    SIXBAR_PARAMS`)."""

    linkage: Literal["fourbar", "stephenson", "watt"] = "fourbar"
    points: list[XY]
    timing: list[Angle] | None = None
    free_start: bool = False
    closed: bool = False
    constraints: list[Literal["grashof", "order"]] = Field(default_factory=_default_constraints)
    min_transmission: Annotated[Angle, Field(gt=0, lt=math.pi / 2)] | None = None
    bounds: dict[str, tuple[Any, Any]] = Field(default_factory=dict)

    @model_validator(mode="after")
    def _check(self) -> PathSection:
        if self.free_start and self.timing is None:
            raise PydanticCustomError("free_start", "free_start needs timing (the crank's "
                                      "advances between the points)")
        known = (*PARAMS, "theta2") if self.linkage == "fourbar" else SIXBAR_PARAMS
        for k in self.bounds:
            if k not in known:
                raise PydanticCustomError("bounds", "bounds.{k}: unknown parameter of the "
                                          "{linkage}; known: {known}",
                                          {"k": k, "linkage": self.linkage,
                                           "known": ", ".join(known)})
        for k, v in self.bounds.items():
            for x in v:
                try:
                    _bound_value(k, x)
                except ValueError as exc:
                    raise PydanticCustomError("bounds", "bounds.{k}: {msg}",
                                              {"k": k, "msg": str(exc)}) from None
        return self

    def si_bounds(self) -> dict[str, tuple[float, float]]:
        return {k: (_bound_value(k, v[0]), _bound_value(k, v[1])) for k, v in self.bounds.items()}

    def constraint_tuple(self) -> tuple[Any, ...]:
        out: list[Any] = list(self.constraints)
        if self.min_transmission is not None:
            out.append(("transmission", self.min_transmission))
        return tuple(out)


class Range(FileModel):
    """``{ start = ..., span = ... }`` (start optional: searched)."""

    start: Angle | None = None
    span: Angle


class FunctionSection(FileModel):
    """``[function]``: the mechanism, the function (expression or table) and the ranges."""

    mechanism: Literal["fourbar", "crank_slider"] = "fourbar"
    y: str | list[float]
    x: list[float] | None = None
    x_range: tuple[float, float]
    input: Range
    output: Range | None = None
    stroke: Length | None = None
    datum: Length | None = None
    frame: Annotated[Length, Field(gt=0)] = 1.0
    points: Annotated[int, Field(ge=3, le=20)] = 3
    least_squares_points: Annotated[int, Field(ge=3, le=10_000)] = 41

    @model_validator(mode="after")
    def _check(self) -> FunctionSection:
        if isinstance(self.y, str):
            try:
                expression(self.y)
            except (SyntaxError, ValueError) as exc:
                raise PydanticCustomError("y", "y: {msg}", {"msg": str(exc)}) from None
        elif self.x is None or len(self.x) != len(self.y) or len(self.y) < 3:
            raise PydanticCustomError("y", "a table needs x and y of the same length (>= 3)")
        if self.mechanism == "fourbar" and self.output is None:
            raise PydanticCustomError("output", "the four-bar needs output = { start, span } "
                                      "(rocker angles)")
        if self.mechanism == "crank_slider" and self.stroke is None:
            raise PydanticCustomError("stroke", "the crank-slider needs stroke (slide travel)")
        return self

    def function(self) -> Callable[[np.ndarray], np.ndarray]:
        if isinstance(self.y, str):
            return expression(self.y)
        from scipy.interpolate import CubicSpline

        assert self.x is not None
        order = np.argsort(self.x)
        spline = CubicSpline(np.asarray(self.x)[order], np.asarray(self.y)[order])
        return lambda x: np.asarray(spline(x), dtype=float)


class MotionSection(FileModel):
    """``[motion]``: 3 to 5 poses, pivots or a pivot region, Grashof, transmission angle."""

    poses: list[Pose]
    fixed_pivots: list[XY] | None = None
    moving_pivots: list[XY] | None = None
    pivot_region: tuple[tuple[Length, Length], tuple[Length, Length]] | None = None
    grashof: bool = False
    min_transmission: Annotated[Angle, Field(gt=0, lt=math.pi / 2)] | None = None


class SearchSection(FileModel):
    """``[search]``: global sample, refinements, designs returned, seed."""

    candidates: Annotated[int, Field(ge=16, le=2**22)] = 2**16
    refine: Annotated[int, Field(ge=1, le=500)] = 24
    designs: Annotated[int, Field(ge=1, le=100)] = 5
    seed: int | None = 0


class ObjectiveSection(FileModel):
    """``[objective]``: the literature's error alone, or judged by forces as well."""

    kind: Literal["sum_squares", "weighted", "pareto"] = "sum_squares"
    weights: dict[str, float] = Field(default_factory=dict)
    metrics: list[str] = Field(default_factory=lambda: ["error", "peak_torque"])
    omega1: Annotated[AngularVelocity, Field(gt=0)] = 10.0
    section: Annotated[float, Field(gt=0, le=1.0)] = 1e-4
    density: Annotated[float, Field(gt=0, le=1e5)] = 7850.0
    masses: tuple[Mass, Mass, Mass] | None = None
    force: tuple[Force, Force] = (0.0, 0.0)

    def objective(self) -> Objective:
        model = ForceModel(masses=self.masses, density=self.density, section=self.section,
                           omega1=self.omega1, force=self.force)
        return Objective(kind=self.kind, weights=dict(self.weights),
                         metrics=tuple(self.metrics), forces=model)


class SynthesisFile(FileModel):
    """A synthesis task: one or more of ``[path]``, ``[function]``, ``[motion]``."""

    type: Literal["synthesis"]
    name: str = "synthesis task"
    path: PathSection | None = None
    function: FunctionSection | None = None
    motion: MotionSection | None = None
    search: SearchSection = SearchSection()
    objective: ObjectiveSection = ObjectiveSection()

    @model_validator(mode="after")
    def _one(self) -> SynthesisFile:
        if self.path is None and self.function is None and self.motion is None:
            raise PydanticCustomError("task", "needs a [path], [function] or [motion] section")
        if (self.path is not None and self.path.linkage != "fourbar"
                and self.objective.kind != "sum_squares"):
            raise PydanticCustomError("objective", "objective.kind = {kind!r}: judging by "
                                      "forces is for four-bars; a {linkage} six-bar is judged "
                                      "by the error alone", {"kind": self.objective.kind,
                                                             "linkage": self.path.linkage})
        try:
            self.objective.objective()
        except ValueError as exc:
            raise PydanticCustomError("objective", "objective: {msg}", {"msg": str(exc)}
                                      ) from None
        return self
