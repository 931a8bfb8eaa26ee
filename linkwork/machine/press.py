r"""Paper 000's variable-structure press as a machine: its two structures with masses and the
press force, for a duty schedule run with the real motor and flywheel.

:func:`press_modes` builds, from a :class:`~linkwork.models.variable_structure.
VariableStructureMechanism` (the paper's kinematics) and the masses the paper does not give,
one engine mechanism per structure, sharing the crank (one body, the same in both):

* **idle** -- the offset crank-slider (crank, rod ``L2 = lambda2 L1``, slider C on the guide
  ``X = e``, parallel to ``Y``; :func:`~linkwork.planar.model.crank_slider_mechanism`);
* **working** at a slot angle ``alpha`` -- the sine mechanism: the crank pin in the straight
  slot of the ram (inclined at ``alpha`` to the ram's line of motion ``x``), the ram in the
  frame's guide; the slot's block is lumped at the crank pin (its mass ``block_mass`` on the
  crank).

Frame and signs as ``docs/conventions.md`` (paper 000): crank angle ``phi1`` from ``+x``
counter-clockwise; ``X3`` the ram's travel towards the crank axis (``-x``). The press stands
with ``x`` vertical, up (the default gravity ``(-9.81, 0)``), so the ram descends with ``X3``
rising to its lowest point at ``phi1 = alpha + 90 deg``; the **press force** ``press_force``
[N] pushes the ram up (from the workpiece on the bed: ``from_frame``) over the last
``working_stroke`` [m] of its descent, ``phi1`` from ``alpha + arcsin(1 - w sin(alpha) / L1)``
to ``alpha + 90 deg`` (the force jumps there: breaks of the modes).

**The other structure is at rest** (the paper's engagement mechanisms: the ram is held while
idle, the crank-slider's rod and slider while working); at a switch the bodies of the new
structure are engaged by an impact (see :mod:`linkwork.machine.transient`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_number, require_pair
from linkwork.errors import ParameterError
from linkwork.machine.transient import Mode
from linkwork.models.sine import check_alpha
from linkwork.models.variable_structure import (
    IDLE,
    WORKING,
    Segment,
    VariableStructureMechanism,
)
from linkwork.planar import (
    Body,
    Crank,
    Mechanism,
    PinInSlot,
    PointForce,
    Prismatic,
    Revolute,
    crank_slider_mechanism,
)

__all__ = ["press_modes", "press_schedule", "working_phase"]


def _mass(name: str, value: Any) -> float:
    v = require_number(name, value)
    if v < 0:
        raise ParameterError(name, v, "must be >= 0")
    return v


def working_phase(L1: float, alpha: float, working_stroke: float) -> tuple[float, float]:
    """Crank angles [rad] where the press force starts and ends: the last ``working_stroke``
    [m] of the ram's descent, ``(alpha + arcsin(1 - w sin(alpha) / L1), alpha + pi / 2)``."""
    stroke = 2 * L1 / math.sin(alpha)
    if not 0.0 < working_stroke <= stroke:
        raise ParameterError("working_stroke", working_stroke, f"must lie in (0, {stroke:.6g}] "
                             f"m: the ram's stroke 2 L1 / sin(alpha) at alpha = "
                             f"{math.degrees(alpha):.4g} deg")
    return alpha + math.asin(1.0 - working_stroke * math.sin(alpha) / L1), alpha + math.pi / 2


def press_modes(press: VariableStructureMechanism, *, crank_mass: float, crank_inertia: float,
                rod_mass: float, slider_mass: float, ram_mass: float, press_force: float,
                working_stroke: float, crank_com: float = 0.0, rod_inertia: float | None = None,
                block_mass: float = 0.0, alphas: Iterable[float] = (),
                gravity: ArrayLike | None = (-9.81, 0.0)) -> dict[str, Mode]:
    """The press's structures as machine modes: ``"idle"`` and ``"working <alpha> deg"`` for
    the press's ``alpha`` and every angle of ``alphas`` [rad].

    Parameters
    ----------
    press : VariableStructureMechanism
        Dimensions (``L1``, ``lambda2``, ``lambda_e``, ``alpha``, branch, friction coefficients
        for the working range of ``alpha``).
    crank_mass, crank_inertia : float
        The crank's mass [kg] and centroidal inertia [kg m^2]; ``crank_com`` its centre of mass
        along the crank from the axis [m] (0: counterweighted).
    rod_mass, slider_mass : float
        The idle crank-slider's rod (a uniform rod unless ``rod_inertia`` [kg m^2] is given)
        and slider C [kg].
    ram_mass : float
        The ram with its upper die [kg].
    press_force, working_stroke : float
        The technological force [N] over the last ``working_stroke`` [m] of the descent.
    block_mass : float
        The slot's block, lumped at the crank pin [kg].
    gravity : (gx, gy) or None
        [m/s^2]; default: ``x`` up.
    """
    L1 = press.L1
    m1, j1 = _mass("crank_mass", crank_mass), _mass("crank_inertia", crank_inertia)
    mb = _mass("block_mass", block_mass)
    c1 = require_number("crank_com", crank_com)
    force = _mass("press_force", press_force)
    w = require_number("working_stroke", working_stroke)
    # the crank with the block at its pin: one body, the same in every mode
    m_tot = m1 + mb
    com = (m1 * c1 + mb * L1) / m_tot if m_tot > 0 else 0.0
    inertia = j1 + m1 * (c1 - com) ** 2 + mb * (L1 - com) ** 2
    e = press.lambda_e * L1
    idle = crank_slider_mechanism(L1, press.lambda2 * L1, -e, guide_angle=math.pi / 2,
                                  masses=(m_tot, _mass("rod_mass", rod_mass),
                                          _mass("slider_mass", slider_mass)),
                                  inertias=(inertia, rod_inertia), coms=(com, None),
                                  branch=press.branch)
    crank = idle.body("crank")
    g = None if gravity is None else require_pair("gravity", gravity)
    modes = {IDLE: Mode(IDLE, idle, (), g)}
    for a in (press.alpha, *alphas):
        check_alpha(a, press.f_slot, press.f_guide)
        start, end = working_phase(L1, a, w)
        name = f"{WORKING} {math.degrees(a):.4g} deg"
        ram = Body("ram", {"S": (0.0, 0.0)}, mass=_mass("ram_mass", ram_mass))
        mech = Mechanism(
            Body("frame", {"O": (0.0, 0.0)}), (crank, ram),
            (Revolute("O", "frame", "crank"),
             Prismatic("guide", "frame", "ram", angle=0.0, through="O", point="S"),
             PinInSlot("slot", "ram", "crank", angle=a, through="S", point="A")),
            Crank("O"))

        def loads(phi: np.ndarray, start: float = start, end: float = end
                  ) -> list[PointForce]:
            on = np.mod(np.asarray(phi) - start, 2 * np.pi) <= (end - start) + 1e-12
            return [PointForce("ram", "S", np.where(on, force, 0.0), 0.0, from_frame=True)]

        modes[name] = Mode(name, mech, loads, g, (start, end))
    return modes


def press_schedule(press: VariableStructureMechanism,
                   schedule: Iterable[Segment | Sequence[Any]], **masses: Any
                   ) -> tuple[dict[str, Mode], list[tuple[str, int]]]:
    """The modes and the machine schedule of a press duty schedule (segments ``(mode,
    revolutions[, alpha])`` as :meth:`VariableStructureMechanism.run` takes them; a working
    segment's ``alpha`` selects its mode). ``masses``: the keywords of :func:`press_modes`."""
    segs = [s if isinstance(s, Segment) else Segment(*s) for s in schedule]
    alphas = sorted({float(s.alpha) for s in segs if s.mode == WORKING and s.alpha is not None})
    modes = press_modes(press, alphas=alphas, **masses)
    out = []
    for s in segs:
        if s.mode == IDLE:
            out.append((IDLE, int(s.revolutions)))
        else:
            a = press.alpha if s.alpha is None else float(s.alpha)
            out.append((f"{WORKING} {math.degrees(a):.4g} deg", int(s.revolutions)))
    return modes, out
