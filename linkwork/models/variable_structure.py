r"""The variable-structure sine press drive of paper 000 as one object, and its duty schedule.

The mechanism has one crank (length ``L1``, angle ``phi1`` from the right horizontal position,
counter-clockwise) shared by two structures (Fig. 5 in [1]_):

* **idle mode** -- an offset crank-slider (Fig. 1): crank 1, rod 2 (``L2 = lambda2 L1``) and
  its slider C in a guide parallel to ``AY`` at ``X = e = lambda_e L1``
  (:func:`linkwork.models.crank_slider.offset_crank_slider`);
* **working mode** -- a sine mechanism (Fig. 4): the block on the crank pin slides in a slot of
  the press slider (ram) inclined at ``alpha`` to the ram's motion
  (:func:`linkwork.models.sine.inclined_slot`); the stroke ``2 L1 / sin(alpha)`` is set by
  turning the slotted insert.

The mode and ``alpha`` are the state of the mechanism: :meth:`VariableStructureMechanism.switch`
returns the mechanism in another state.

What the output link is
-----------------------
The paper gives each structure's output without saying how they relate; linkwork makes it
explicit:

* **Output of the active structure** (``s, v, a`` of :class:`ScheduleResult`): in the idle mode
  the slider C of the crank-slider, coordinate ``Y_C`` along ``+Y`` from the line through the
  crank axis (Eq. (5) in [1]_); in the working mode the ram, coordinate ``X3`` from its
  ``phi1 = 0`` position, positive towards the crank axis (Eq. (19), corrected).  These are two
  different links with two different datums: ``s`` jumps at a switch by construction.
* **The press ram** (``ram_s, ram_v, ram_a``): driven only in the working mode (``X3``, ``V3``,
  ``a3``); in the idle mode it is disengaged and held at rest.  Every schedule segment is a
  whole number of crank revolutions starting at ``phi1 = 0 (mod 2 pi)``, where ``X3 = 0`` for any
  ``alpha``, so the ram is parked at ``X3 = 0`` and its position is continuous through every
  switch; its velocity jumps by ``omega1 L1 cot(alpha)`` at an engagement or disengagement
  (zero only at ``alpha = 90 deg``), which :attr:`ScheduleResult.switch_ram_dv` reports.

References
----------
.. [1] Toktakunov, Zh. Sh. Analytic determination of the kinematics of a variable-structure sine
   mechanism (paper 000 of the linkwork seed papers).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, Literal

import numpy as np
from numpy.typing import ArrayLike

from linkwork.checks import require_branch, require_finite, require_positive
from linkwork.errors import ParameterError
from linkwork.models import crank_slider, sine
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = [
    "BYTES_PER_SAMPLE",
    "IDLE",
    "MAX_SAMPLES",
    "MODES",
    "WORKING",
    "OutputMotion",
    "ScheduleResult",
    "Segment",
    "VariableStructureMechanism",
    "schedule_samples",
]

IDLE = "idle"
WORKING = "working"
MODES = (IDLE, WORKING)
Mode = Literal["idle", "working"]


@dataclass(frozen=True)
class OutputMotion:
    """Displacement ``s`` [m], velocity ``v`` [m/s], acceleration ``a`` [m/s^2] of an output link.

    ``link`` names the link and its coordinate (``"slider C: Y_C"`` or ``"ram: X3"``).
    """

    s: np.ndarray
    v: np.ndarray
    a: np.ndarray
    link: str


@dataclass(frozen=True)
class Segment:
    """One part of a duty schedule: ``revolutions`` crank turns in ``mode``.

    In the working mode one revolution is one working stroke (a full double stroke of the ram).
    ``alpha`` [rad] sets the slot angle for a working segment; ``None`` keeps the mechanism's
    current ``alpha``.
    """

    mode: str
    revolutions: int
    alpha: float | None = None

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ParameterError("mode", self.mode, f"must be one of {MODES}")
        if isinstance(self.revolutions, bool) or not isinstance(self.revolutions, int | np.integer):
            raise ParameterError("revolutions", self.revolutions, "must be a whole number")
        if self.revolutions < 1:
            raise ParameterError("revolutions", self.revolutions, "must be >= 1")


def _segment(entry: Segment | Sequence[Any]) -> Segment:
    if isinstance(entry, Segment):
        return entry
    if isinstance(entry, str) or not isinstance(entry, Sequence) or not 2 <= len(entry) <= 3:
        raise ParameterError("schedule entry", entry, "must be a Segment or a tuple "
                             "(mode, revolutions[, alpha]), e.g. ('working', 3, 1.05)")
    return Segment(*entry)


#: The most samples of :meth:`VariableStructureMechanism.run` (all segments): the twelve
#: per-sample arrays of the result and their segment pieces peak at about
#: :data:`BYTES_PER_SAMPLE` (tracemalloc over 10^5 samples: 165 B), 0.8 GB at the limit
#: (10^7 revolutions at 360 samples asked 26.8 GiB at once). Refused above it before any work.
MAX_SAMPLES = 5_000_000

#: Peak memory per sample of :meth:`VariableStructureMechanism.run` [bytes], rounded up.
BYTES_PER_SAMPLE = 170


def schedule_samples(revolutions: Iterable[int], samples_per_revolution: int) -> int:
    """Samples of a schedule of segments of ``revolutions`` crank turns each: a segment has
    ``revolutions * samples_per_revolution + 1`` (its switch instant twice)."""
    return sum(int(r) * int(samples_per_revolution) + 1 for r in revolutions)


@dataclass(frozen=True)
class ScheduleResult(Result):
    """Motion of the variable-structure mechanism over a duty schedule at constant crank speed.

    Per-sample arrays (shape ``(n,)``); the sample at a switch instant appears twice, once at the
    end of the old segment and once at the start of the new one (``switch`` True there).

    Attributes
    ----------
    t : time [s] from the start of the schedule.
    phi1 : crank angle [rad], unwrapped (``omega1 * t``).
    mode : 0 idle, 1 working.
    segment : index of the schedule segment.
    alpha : slot angle state [rad].
    s, v, a : output of the active structure [m, m/s, m/s^2] (idle: ``Y_C, V_C, a_C`` of the
        crank-slider's slider C; working: ``X3, V3, a3`` of the ram).
    ram_s, ram_v, ram_a : press ram [m, m/s, m/s^2]: ``X3, V3, a3`` when working, at rest at
        ``X3 = 0`` when idle.
    switch : True at the first sample of every segment after the first.
    switch_t, switch_phi1 : instants [s] and unwrapped crank angles [rad] of the switches.
    switch_to : the mode entered at each switch (0 idle, 1 working).
    switch_ram_dv : jump of the ram velocity at each switch [m/s] (after minus before).
    omega1 : crank speed [rad/s].
    """

    t: np.ndarray
    phi1: np.ndarray
    mode: np.ndarray
    segment: np.ndarray
    alpha: np.ndarray
    s: np.ndarray
    v: np.ndarray
    a: np.ndarray
    ram_s: np.ndarray
    ram_v: np.ndarray
    ram_a: np.ndarray
    switch: np.ndarray
    switch_t: np.ndarray
    switch_phi1: np.ndarray
    switch_to: np.ndarray
    switch_ram_dv: np.ndarray
    omega1: float

    position_field: ClassVar[str] = "t"
    units: ClassVar[dict[str, str]] = {
        "t": "s", "phi1": "rad", "mode": "0 idle / 1 working", "segment": "1", "alpha": "rad",
        "s": "m", "v": "m/s", "a": "m/s^2", "ram_s": "m", "ram_v": "m/s", "ram_a": "m/s^2",
        "switch": "1", "switch_t": "s", "switch_phi1": "rad", "switch_to": "0 idle / 1 working",
        "switch_ram_dv": "m/s", "omega1": "rad/s",
    }

    def to_dict(self) -> dict[str, Any]:
        """As :meth:`Result.to_dict`, plus the switch table under ``"switches"``."""
        data = super().to_dict()
        data["switches"] = [
            {"t": float(t), "phi1": float(p), "to": MODES[int(m)], "ram_dv": float(dv)}
            for t, p, m, dv in zip(self.switch_t, self.switch_phi1, self.switch_to,
                                   self.switch_ram_dv, strict=True)
        ]
        return data

    def plot(self, axes: Any = None, **kw: Any) -> Figure:
        """Output-link motion over the duty schedule, switches marked: a
        :class:`linkwork.plot.Figure` with 3 axes."""
        from linkwork.plot.sine import schedule_figure

        return schedule_figure(self, axes=axes, **kw)


@dataclass(frozen=True)
class VariableStructureMechanism:
    """The variable-structure sine mechanism: shared crank, two structures, state = mode, alpha.

    Parameters
    ----------
    L1 : float
        Crank length [m], > 0.
    lambda2 : float
        Relative rod length of the idle crank-slider [-], > ``|lambda_e| + 1``.
    lambda_e : float
        Relative guide offset of the idle crank-slider [-].
    alpha : float
        Slot angle of the working sine mechanism [rad]; must lie in the working range set by the
        friction coefficients (:func:`linkwork.models.sine.working_range`).
    mode : {"idle", "working"}
        The active structure.
    branch : {+1, -1}
        Assembly branch of the crank-slider.
    f_slot, f_guide : float
        Coulomb friction coefficients in the slot and in the ram guides [-] (default 0: any
        ``alpha`` in (0, pi)).
    """

    L1: float
    lambda2: float
    lambda_e: float
    alpha: float
    mode: str = IDLE
    branch: int = 1
    f_slot: float = 0.0
    f_guide: float = 0.0

    def __post_init__(self) -> None:
        require_positive("L1", self.L1)
        require_finite("lambda_e", self.lambda_e)
        crank_slider.stroke(self.L1, self.lambda2, self.lambda_e)  # checks lambda2
        require_branch(self.branch)
        if self.mode not in MODES:
            raise ParameterError("mode", self.mode, f"must be one of {MODES}")
        sine.check_alpha(self.alpha, self.f_slot, self.f_guide)

    def switch(self, mode: str | None = None, alpha: float | None = None
               ) -> VariableStructureMechanism:
        """Return the mechanism with another ``mode`` and/or slot angle ``alpha`` [rad]."""
        changes: dict[str, Any] = {}
        if mode is not None:
            changes["mode"] = mode
        if alpha is not None:
            changes["alpha"] = float(alpha)
        return dataclasses.replace(self, **changes)

    def kinematics(self, phi1: ArrayLike, omega1: ArrayLike = 1.0, eps1: ArrayLike = 0.0
                   ) -> crank_slider.CrankSliderResult | sine.InclinedSlotResult:
        """Full kinematics of the active structure at crank angles ``phi1`` [rad]."""
        if self.mode == IDLE:
            return crank_slider.offset_crank_slider(phi1, self.L1, self.lambda2, self.lambda_e,
                                                    omega1, eps1, self.branch)
        return sine.inclined_slot(phi1, self.L1, self.alpha, omega1, eps1)

    def output(self, phi1: ArrayLike, omega1: ArrayLike = 1.0, eps1: ArrayLike = 0.0
               ) -> OutputMotion:
        """Motion of the active structure's output link (see the module docstring)."""
        k = self.kinematics(phi1, omega1, eps1)
        if isinstance(k, crank_slider.CrankSliderResult):
            return OutputMotion(k.Y_C, k.V_C, k.a_C, "slider C: Y_C")
        return OutputMotion(k.X3, k.V3, k.a3, "ram: X3")

    def stroke(self) -> float:
        """Stroke [m] of the active structure's output link."""
        if self.mode == IDLE:
            return float(crank_slider.stroke(self.L1, self.lambda2, self.lambda_e))
        return float(sine.stroke(self.L1, self.alpha))

    def run(self, schedule: Iterable[Segment | Sequence[Any]], omega1: float,
            samples_per_revolution: int = 360) -> ScheduleResult:
        """Run a duty schedule at constant crank speed ``omega1`` [rad/s] from ``phi1 = 0``.

        Parameters
        ----------
        schedule : iterable of Segment or tuples ``(mode, revolutions[, alpha])``
            E.g. ``[("idle", 5), ("working", 3, np.radians(60))]``: 5 idle revolutions, then 3
            working strokes at ``alpha = 60 deg``.
        omega1 : float
            Crank speed [rad/s], > 0.
        samples_per_revolution : int
            Samples per crank revolution (>= 8); the schedule's samples in all
            (:func:`schedule_samples`) at most :data:`MAX_SAMPLES`.

        Returns
        -------
        ScheduleResult
        """
        w1 = float(require_positive("omega1", omega1))
        spr = samples_per_revolution
        if isinstance(spr, bool) or not isinstance(spr, int | np.integer) or spr < 8:
            raise ParameterError("samples_per_revolution", spr, "must be a whole number >= 8")
        segs = [_segment(s) for s in schedule]
        if not segs:
            raise ParameterError("schedule", "[]", "must have at least one segment")
        total = schedule_samples([s.revolutions for s in segs], spr)
        if total > MAX_SAMPLES:
            raise ParameterError(
                "schedule", f"{sum(int(s.revolutions) for s in segs)} revolutions x {spr} "
                f"samples", f"at most {MAX_SAMPLES} samples in all (got {total}): about "
                f"{BYTES_PER_SAMPLE} bytes each while running, "
                f"{total * BYTES_PER_SAMPLE / 2**30:.3g} GiB asked; run the schedule in parts "
                "or with fewer samples_per_revolution")
        state = self
        cols: dict[str, list[np.ndarray]] = {k: [] for k in (
            "phi1", "mode", "segment", "alpha", "s", "v", "a", "ram_s", "ram_v", "ram_a",
            "switch")}
        sw_t, sw_phi, sw_to, sw_dv = [], [], [], []
        start = 0.0
        prev_ram_v_end: float | None = None
        for i, seg in enumerate(segs):
            state = state.switch(seg.mode, seg.alpha)
            n = seg.revolutions * samples_per_revolution + 1
            phi = start + np.linspace(0.0, 2 * np.pi * seg.revolutions, n)
            out = state.output(phi, w1, 0.0)
            if state.mode == WORKING:
                ram = (out.s, out.v, out.a)
            else:
                zeros = np.zeros(n)
                ram = (zeros, zeros, zeros)
            m = MODES.index(state.mode)
            for key, val in (("phi1", phi), ("mode", np.full(n, m)), ("segment", np.full(n, i)),
                             ("alpha", np.full(n, state.alpha)), ("s", out.s), ("v", out.v),
                             ("a", out.a), ("ram_s", ram[0]), ("ram_v", ram[1]),
                             ("ram_a", ram[2])):
                cols[key].append(np.asarray(val, dtype=float))
            flag = np.zeros(n, dtype=bool)
            if i > 0:
                flag[0] = True
                sw_t.append(start / w1)
                sw_phi.append(start)
                sw_to.append(m)
                sw_dv.append(float(ram[1][0]) - (prev_ram_v_end or 0.0))
            cols["switch"].append(flag)
            prev_ram_v_end = float(ram[1][-1])
            start = float(phi[-1])
        arr = {k: np.concatenate(v) for k, v in cols.items()}
        return ScheduleResult(
            t=arr["phi1"] / w1, phi1=arr["phi1"], mode=arr["mode"].astype(int),
            segment=arr["segment"].astype(int), alpha=arr["alpha"], s=arr["s"], v=arr["v"],
            a=arr["a"], ram_s=arr["ram_s"], ram_v=arr["ram_v"], ram_a=arr["ram_a"],
            switch=arr["switch"], switch_t=np.asarray(sw_t, dtype=float),
            switch_phi1=np.asarray(sw_phi, dtype=float), switch_to=np.asarray(sw_to, dtype=int),
            switch_ram_dv=np.asarray(sw_dv, dtype=float), omega1=w1,
        )
