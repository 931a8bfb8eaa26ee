"""Static (force) balancing by counterweights: closed forms for the four-bar and crank-slider.

A mechanism is force balanced when its total centre of mass is stationary, i.e. its shaking
force :math:`-\\sum m_i a_{S_i}` vanishes at every position and speed. Counterweights on links
hinged to the frame can do this when the total first moment of mass
:math:`\\sum m_i r_{S_i}` can be written, using the loop-closure equations, as a constant plus
terms that each rotate rigidly with one frame-hinged link ("method of linearly independent
vectors", Berkof and Lowen [1]_); each such term is then cancelled by a counterweight on that
link.

Complex notation: a point fixed to a link is given by its local coordinates as a complex number
:math:`p = \\xi + i\\eta`, with :math:`\\xi` along the link (from its first joint towards its
second) and :math:`\\eta` perpendicular, counter-clockwise. A counterweight is its local first
moment :math:`q = m_{cw}\\,\\rho_{cw}` (complex): static moment :math:`S = |q|` [kg·m] and angle
on the link :math:`\\arg q` [rad] from the link's line.

References
----------
.. [1] Berkof R. S., Lowen G. G. A new method for completely force balancing simple linkages.
   ASME J. Eng. Ind., 1969, 91(1), 21-26.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from linkwork.checks import require_finite, require_in_range, require_positive
from linkwork.errors import ParameterError
from linkwork.results import Result

if TYPE_CHECKING:
    from linkwork.plot import Figure

__all__ = [
    "Counterweight",
    "crank_slider_counterweight",
    "fourbar_counterweights",
    "fourbar_counterweights_point_masses",
    "statically_equivalent_masses",
]


@dataclass(frozen=True)
class Counterweight(Result):
    """A counterweight on a link, as a first moment of mass in the link's frame.

    Attributes
    ----------
    link : str
        Name of the link that carries it.
    static_moment : float
        :math:`S = m_{cw} r_{cw}` [kg·m], about the link's hinge with the frame.
    angle : float
        Direction of the counterweight's centre on the link [rad], from the link's line
        (first joint -> second joint; in the planar engine: the body's x axis),
        counter-clockwise; ``pi`` = on the extension beyond the hinge, opposite the link's
        other joint.
    radius : float or None
        Distance of the counterweight's centre from the hinge [m]; needed to turn S into a
        mass when the counterweight is added to a mechanism (the mass is ``S / radius``).
    inertia : float
        The counterweight's own centroidal moment of inertia [kg·m²] (0: a point mass).
    """

    link: str
    static_moment: float
    angle: float
    radius: float | None = None
    inertia: float = 0.0
    units: ClassVar[dict[str, str]] = {"static_moment": "kg*m", "angle": "rad", "radius": "m",
                                       "inertia": "kg*m**2"}
    position_field: ClassVar[str] = "static_moment"

    def __post_init__(self) -> None:
        require_positive("static_moment", self.static_moment, allow_zero=True)
        require_finite("angle", self.angle)
        if self.radius is not None:
            require_positive("radius", self.radius)
        require_positive("inertia", self.inertia, allow_zero=True)

    def with_radius(self, radius: float, inertia: float = 0.0) -> Counterweight:
        """The same static moment and angle at ``radius`` [m], with own inertia [kg·m²]."""
        return Counterweight(self.link, self.static_moment, self.angle, float(radius),
                             float(inertia))

    @property
    def first_moment(self) -> complex:
        """Local first moment :math:`q = S e^{i\\,angle}` [kg·m]."""
        return complex(self.static_moment * np.cos(self.angle),
                       self.static_moment * np.sin(self.angle))

    def mass(self, radius: float | None = None) -> float:
        """Counterweight mass [kg] for a centre at ``radius`` [m] (default: its own radius)."""
        if radius is None and self.radius is None:
            raise ParameterError(f"counterweight on {self.link}: radius", None,
                                 "must be given to turn the static moment into a mass")
        rr = self.radius if radius is None else radius
        assert rr is not None  # checked above
        r = float(require_positive("radius", rr))
        return self.static_moment / r

    @classmethod
    def from_first_moment(cls, link: str, q: complex, radius: float | None = None,
                          inertia: float = 0.0) -> Counterweight:
        """From a complex local first moment [kg·m]."""
        angle = float(np.angle(q)) if q != 0 else 0.0
        if angle <= -np.pi + 1e-15:  # keep angles in (-pi, pi]
            angle = float(np.pi)
        return cls(link, float(abs(q)), angle, radius, inertia)

    @classmethod
    def from_mass(cls, link: str, mass: float, radius: float, angle: float,
                  inertia: float = 0.0) -> Counterweight:
        """From a mass [kg] at ``radius`` [m] from the hinge and ``angle`` [rad] on the link."""
        m = float(require_positive("mass", mass, allow_zero=True))
        r = float(require_positive("radius", radius))
        return cls(link, m * r, float(require_finite("angle", angle)), r, inertia)

    def plot(self, ax: Any = None, **kw: Any) -> Figure:
        """The counterweight's first moment S drawn at its angle on the link: a
        :class:`linkwork.plot.Figure` with 1 axes."""
        from linkwork.plot.balancing import counterweights_figure

        return counterweights_figure((self,), ax=ax, **kw)


def fourbar_counterweights(l1: float, l2: float, l3: float, m1: float, s1: complex,
                           m2: float, s2: complex, m3: float, s3: complex,
                           ) -> tuple[Counterweight, Counterweight]:
    """Crank and rocker counterweights that fully force-balance a four-bar (Berkof-Lowen).

    Loop closure :math:`l_1 e^{i\\theta_1} + l_2 e^{i\\theta_2} = l_0 + l_3 e^{i\\theta_3}`
    eliminates the coupler's direction from the total first moment:

    .. math::

        \\sum m_k r_{S_k} = e^{i\\theta_1}\\left[m_1 s_1 + m_2 l_1 (1 - s_2/l_2)\\right]
            + e^{i\\theta_3}\\left[m_3 s_3 + m_2 s_2 l_3/l_2\\right] + \\text{const},

    so counterweights with local first moments

    .. math::

        q_1 = -\\left[m_1 s_1 + m_2 l_1 (1 - s_2/l_2)\\right], \\qquad
        q_3 = -\\left[m_3 s_3 + m_2 s_2 l_3 / l_2\\right]

    on the crank and the rocker make it stationary, for any coupler centre :math:`s_2` (also
    off the line AB) and independently of the frame length :math:`l_0` and of the assembly
    branch. For a coupler centre on AB this is the statically equivalent split of the coupler
    into :math:`m_2(1 - s_2/l_2)` at A and :math:`m_2 s_2/l_2` at B.

    Parameters
    ----------
    l1, l2, l3 : float
        Crank OA, coupler AB and rocker CB lengths [m].
    m1, m2, m3 : float
        Masses of crank, coupler, rocker [kg].
    s1, s2, s3 : complex
        Centres of mass in local coordinates [m]: crank from O along OA, coupler from A along
        AB, rocker from C along CB (imaginary part: perpendicular, counter-clockwise).

    Returns
    -------
    (Counterweight, Counterweight)
        On the crank (``"crank"``, angle from OA) and on the rocker (``"rocker"``, angle
        from CB).
    """
    L1, L2, L3 = (float(require_positive(n, v)) for n, v in (("l1", l1), ("l2", l2),
                                                               ("l3", l3)))
    M1, M2, M3 = (float(require_positive(n, v, allow_zero=True))
                  for n, v in (("m1", m1), ("m2", m2), ("m3", m3)))
    z1, z2, z3 = complex(s1), complex(s2), complex(s3)
    for n, z in (("s1", z1), ("s2", z2), ("s3", z3)):
        require_finite(n, [z.real, z.imag])
    q1 = -(M1 * z1 + M2 * L1 * (1.0 - z2 / L2))
    q3 = -(M3 * z3 + M2 * z2 * L3 / L2)
    return (Counterweight.from_first_moment("crank", q1),
            Counterweight.from_first_moment("rocker", q3))


def crank_slider_counterweight(l1: float, l2: float, m1: float, s1: complex, m2: float,
                               s2: complex, m3: float, fraction: float = 0.0) -> Counterweight:
    """Crank counterweight of a crank-slider: rotating masses plus a fraction of the reciprocating.

    With the rod's centre :math:`s_2` (from A along AB) the rod's first moment splits, exactly,
    into :math:`m_2(1 - s_2/l_2)` at the crank pin A (rotating) and :math:`m_2 s_2/l_2` at the
    slider B (reciprocating, with the slider mass :math:`m_3`):

    .. math::

        q_1 = -\\left[m_1 s_1 + m_2 l_1 (1 - s_2/l_2)\\right]
              - k\\,l_1 \\left(m_3 + m_2 s_2/l_2\\right).

    ``fraction`` k = 0 balances the rotating masses fully (the shaking force is then only the
    reciprocating one, along the guide); k = 1 cancels the first harmonic of the
    reciprocating force along the guide (centred crank-slider) but adds an equal rotating
    force across it. A counterweight on the crank cannot cancel the reciprocating force
    exactly: it is not a vector rotating with a frame-hinged link (it contains all
    harmonics of the slider motion), so full force balance by counterweights is impossible.

    Parameters
    ----------
    l1, l2 : float
        Crank OA and rod AB [m].
    m1, m2, m3 : float
        Crank, rod and slider masses [kg].
    s1, s2 : complex
        Crank centre from O along OA, rod centre from A along AB [m].
    fraction : float
        k in [0, 1]: share of the reciprocating mass (referred to the crank pin) balanced.

    Returns
    -------
    Counterweight
        On ``"crank"``, angle from OA.
    """
    L1, L2 = float(require_positive("l1", l1)), float(require_positive("l2", l2))
    M1, M2, M3 = (float(require_positive(n, v, allow_zero=True))
                  for n, v in (("m1", m1), ("m2", m2), ("m3", m3)))
    k = float(require_in_range("fraction", fraction, 0.0, 1.0))
    z1, z2 = complex(s1), complex(s2)
    if not (np.isfinite(z1) and np.isfinite(z2)):
        raise ParameterError("s1/s2", (z1, z2), "must be finite")
    q1 = -(M1 * z1 + M2 * L1 * (1.0 - z2 / L2)) - k * L1 * (M3 + M2 * z2 / L2)
    return Counterweight.from_first_moment("crank", q1)


def statically_equivalent_masses(mass: float, length: float, com: float
                                 ) -> tuple[float, float, float]:
    """Two point masses at a link's joints statically equivalent to the link.

    A link of mass m whose centre lies on its line at ``com`` = a from the first joint
    (length l = a + b) is replaced by :math:`m_1 = m b / l` at the first joint and
    :math:`m_2 = m a / l` at the second (same mass and first moment). Their inertia about the
    centre is :math:`m a b`; the link is then dynamically equivalent to the pair plus a
    massless "residual" body of inertia :math:`I_S - m a b` turning with it.

    Returns
    -------
    (m1, m2, correction)
        m1, m2 [kg] and :math:`-m a b` [kg·m²]: the residual inertia is
        ``I_S + correction``.
    """
    m = float(require_positive("mass", mass, allow_zero=True))
    L = float(require_positive("length", length))
    a = float(require_in_range("com", com, 0.0, L))
    return m * (L - a) / L, m * a / L, -m * a * (L - a)


def fourbar_counterweights_point_masses(l1: float, l2: float, l3: float, m1: float, s1: float,
                                        m2: float, s2: float, m3: float, s3: float,
                                        ) -> tuple[Counterweight, Counterweight]:
    """Four-bar force balance by statically equivalent point masses (centres on the links).

    The coupler is replaced by point masses at A and B (:func:`statically_equivalent_masses`);
    the crank counterweight balances the crank and the mass at A about O, the rocker
    counterweight the rocker and the mass at B about C. Only for centres on the link lines
    (real s1, s2, s3 measured from O, A, C); :func:`fourbar_counterweights` covers the general
    case and gives the same result here.
    """
    mA, mB, _ = statically_equivalent_masses(m2, l2, s2)
    S1 = float(require_positive("m1", m1, allow_zero=True)) * float(s1) + mA * float(l1)
    S3 = float(require_positive("m3", m3, allow_zero=True)) * float(s3) + mB * float(l3)
    return (Counterweight("crank", abs(S1), float(np.pi) if S1 >= 0 else 0.0),
            Counterweight("rocker", abs(S3), float(np.pi) if S3 >= 0 else 0.0))
