"""Acceptance check of issue 5 (swash-plate drive, paper 003), as its checker will run it.

Every expected value is computed here, independently of ``linkwork.models.swashplate``:

* the points by a direct 3-D construction: the slide point ``A = Rot_z(phi) (0, -R, 0) + z e_z``
  on its guide, the disk point ``B = (a, b, z1) + Rot_x(alpha) Rot_z(phi) (0, -r, 0)`` with the
  rotation matrices written out, the slide height ``z`` solved from ``|A - B| = l`` with
  :func:`scipy.optimize.brentq` along the guide (the slide beyond the disk point);
* the transfer functions by central finite differences of that construction;
* the stroke by dense sampling of it and bounded scalar minimisation around every sampled
  extreme (no ``s(pi) - s(0)``);
* the pressure angle from the 3-D rod vector (``atan2`` of its horizontal and axial parts) and
  from the paper's Eq. (5) as printed;
* the kinetostatics by a power balance (virtual work of the rod force on the disk point and of
  the guide reaction on the slide point, with velocities from finite differences) and, with
  friction, by the friction power ``mu N |v|`` (losses opposing the sliding).
"""

from __future__ import annotations

import functools
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
from _strategies import reals
from hypothesis import assume, given, settings
from scipy.optimize import brentq, minimize_scalar

from linkwork.cli import main
from linkwork.errors import AssemblyError, InfeasibleError, ParameterError
from linkwork.models import swashplate as sw
from linkwork.synthesis import swashplate as syn

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
DEG = math.pi / 180

# --------------------------------------------------------------------------------------------
# independent reference: direct 3-D construction
# --------------------------------------------------------------------------------------------


def rot_z(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rot_x(t: float) -> np.ndarray:
    c, s = math.cos(t), math.sin(t)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def ref_points(phi, R, r, l, alpha, a=0.0, b=0.0, z1=0.0):
    """Slide point A and disk point B [m] at rotor angle phi (disk centre at height z1)."""
    B = np.array([a, b, z1]) + rot_x(alpha) @ rot_z(phi) @ np.array([0.0, -r, 0.0])
    Ah = rot_z(phi) @ np.array([0.0, -R, 0.0])
    dx, dy = Ah[0] - B[0], Ah[1] - B[1]
    horiz2 = dx * dx + dy * dy
    if horiz2 > l * l:
        raise ValueError("rod cannot reach")

    def f(z: float) -> float:
        return horiz2 + (z - B[2]) ** 2 - l * l

    z = brentq(f, B[2], B[2] + 1.01 * l, xtol=1e-16, rtol=1e-15, maxiter=200)
    return np.array([Ah[0], Ah[1], z]), B


@functools.lru_cache(maxsize=256)
def _ref_z0(*p):
    return ref_points(0.0, *p)[0][2]


def ref_s(phi, *p):
    """Slide position s(phi) = z_A(phi) - z_A(0) from the 3-D construction."""
    return ref_points(phi, *p)[0][2] - _ref_z0(*(float(x) for x in p))


def ref_delta(phi, *p):
    """Angle between the rod and the rotor axis from the 3-D rod vector."""
    A, B = ref_points(phi, *p)
    d = A - B
    return math.atan2(math.hypot(d[0], d[1]), d[2])


def eq5_printed(phi, R, r, l, alpha, a=0.0, b=0.0):
    """The paper's Eq. (5) as printed, solved for delta_z."""
    s2 = (((R - r) * math.sin(phi) - a) / l) ** 2 + \
        (((r * math.cos(alpha) - R) * math.cos(phi) - b) / l) ** 2
    return math.asin(math.sqrt(s2))


def fd1(f, x, h=1e-3):
    """Fourth-order central difference of f at x."""
    return (-f(x + 2 * h) + 8 * f(x + h) - 8 * f(x - h) + f(x - 2 * h)) / (12 * h)


def fd2(f, x, h=1e-2):
    """Fourth-order central second difference of f at x."""
    return (-f(x + 2 * h) + 16 * f(x + h) - 30 * f(x) + 16 * f(x - h) - f(x - 2 * h)) / (12 * h * h)


def ref_extremes(p, n=1440):
    """(phi_min, s_min, phi_max, s_max): dense sampling, then bounded minimisation around every
    sampled local extreme."""
    ph = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    s = np.array([ref_s(x, *p) for x in ph])
    step = ph[1]
    out = []
    for sign in (1.0, -1.0):  # maxima of sign * s
        v = sign * s
        peaks = np.flatnonzero((v >= np.roll(v, 1)) & (v >= np.roll(v, -1)))
        best = (-np.inf, 0.0)
        for i in peaks:
            res = minimize_scalar(lambda x, sg=sign: -sg * ref_s(x, *p), method="bounded",
                                  bounds=(ph[i] - step, ph[i] + step),
                                  options={"xatol": 1e-10})
            val = -res.fun
            if val > best[0]:
                best = (val, res.x % (2 * math.pi))
        out.append(best)
    (vmax, xmax), (vmin, xmin) = out
    return xmin, -vmin, xmax, vmax


def ref_max_on(f, lo, hi, n=400):
    """Max of f over [lo, hi]: dense sampling, then bounded refinement around the best."""
    x = np.linspace(lo, hi, n)
    v = np.array([f(t) for t in x])
    i = int(np.argmax(v))
    best = v[i]
    step = x[1] - x[0]
    res = minimize_scalar(lambda t: -f(t), method="bounded",
                          bounds=(max(lo, x[i] - step), min(hi, x[i] + step)),
                          options={"xatol": 1e-11})
    return max(best, -res.fun)


# designs (R, r, l, alpha, a, b) [m, rad]
S1_A = (0.1, 0.11, 0.15, 20 * DEG, 0.01, 0.02)
S1_B = (0.1, 0.09, 0.15, 20 * DEG, -0.03, -0.015)
S1_C = (0.1, 0.12, 0.18, 35 * DEG, 0.025, 0.005)
S4A_A = sw.scheme_4a(0.1, 0.15, 20 * DEG).params
S4A_B = sw.scheme_4a(0.1, 0.2, 30 * DEG).params
S4B_A = sw.scheme_4b(0.1, 0.11, 0.15, 20 * DEG, 0.02).params
S4B_B = sw.scheme_4b(0.1, 0.095, 0.15, 20 * DEG, -0.025).params
S2 = sw.scheme_2(0.1, 0.03, 0.25, 0.02).params
S3 = sw.scheme_3(0.1, 0.09, 0.2, 0.02, 0.03).params
#: a = 0 but two maxima per revolution: s(pi) - s(0) is wrong here too
NONUNI = (0.1, 0.05, 0.15, 20 * DEG, 0.0, -0.045)

DESIGNS = {"1a": S1_A, "1b": S1_B, "1c": S1_C, "4a_a": S4A_A, "4a_b": S4A_B, "4b_a": S4B_A,
           "4b_b": S4B_B, "2": S2, "3": S3}
PHIS = [0.0, 0.3, 1.0, math.pi / 2, 2.0, 3.0, math.pi, 3.5, 4.5, 5.5, 6.2, -0.7, 7.5]


# --------------------------------------------------------------------------------------------
# 1. exact kinematics against the 3-D construction
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", list(DESIGNS))
def test_position_and_pressure_angle_against_3d_construction(name):
    p = DESIGNS[name]
    ph = np.array(PHIS)
    s = sw.position(ph, *p)
    d = sw.pressure_angle(ph, *p)
    s_ref = np.array([ref_s(x, *p) for x in ph])
    d_ref = np.array([ref_delta(x, *p) for x in ph])
    d_eq5 = np.array([eq5_printed(x, *p) for x in ph])
    scale = np.max(np.abs(s_ref))
    np.testing.assert_allclose(s, s_ref, rtol=1e-9, atol=1e-9 * scale)
    np.testing.assert_allclose(d, d_ref, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(d, d_eq5, rtol=1e-9, atol=1e-12)
    assert sw.position(0.0, *p) == 0.0
    assert np.all(d >= 0)


@pytest.mark.parametrize("name", list(DESIGNS))
def test_transfer_functions_against_finite_differences(name):
    p = DESIGNS[name]
    ph = np.array(PHIS)
    pv = sw.first_transfer(ph, *p)
    pa = sw.second_transfer(ph, *p)
    pv_ref = np.array([fd1(lambda x: ref_s(x, *p), t) for t in ph])
    pa_ref = np.array([fd2(lambda x: ref_s(x, *p), t) for t in ph])
    np.testing.assert_allclose(pv, pv_ref, rtol=1e-7, atol=1e-9 * np.max(np.abs(pv_ref)))
    np.testing.assert_allclose(pa, pa_ref, rtol=1e-6, atol=1e-8 * np.max(np.abs(pa_ref)))


@settings(max_examples=20, deadline=None)
@given(r=reals(0.04, 0.16), l=reals(0.08, 0.5), alpha=reals(0.0, math.pi / 2),
       a=reals(-0.05, 0.05), b=reals(-0.05, 0.05), phi=reals(-7.0, 7.0))
def test_property_random_designs_against_3d_construction(r, l, alpha, a, b, phi):
    p = (0.1, r, l, alpha, a, b)
    # keep the rod clear of 90 deg to the axis everywhere (horizontal reach < 0.95 l)
    reach = max(math.hypot((0.1 - r) * math.sin(t) - a, (r * math.cos(alpha) - 0.1)
                           * math.cos(t) - b) for t in np.linspace(0, 2 * math.pi, 361))
    assume(reach < 0.95 * l)
    assert float(sw.position(phi, *p)) == pytest.approx(ref_s(phi, *p), abs=1e-13)
    assert float(sw.pressure_angle(phi, *p)) == pytest.approx(ref_delta(phi, *p), abs=1e-12)
    pv_ref = fd1(lambda x: ref_s(x, *p), phi)
    assert float(sw.first_transfer(phi, *p)) == pytest.approx(pv_ref, abs=1e-9 * l)
    _, smin, _, smax = ref_extremes(p, n=240)
    assert float(sw.stroke(*p)) == pytest.approx(smax - smin, rel=1e-9, abs=1e-13)


def test_broadcasting_designs_by_angles():
    ph = np.array(PHIS)
    P = np.array([S1_A, S4A_A, S4B_A])  # (3, 6)
    cols = [P[:, j:j + 1] for j in range(6)]
    s = sw.position(ph, *cols)
    assert s.shape == (3, len(PHIS))
    for i, p in enumerate((S1_A, S4A_A, S4B_A)):
        np.testing.assert_allclose(s[i], [ref_s(x, *p) for x in ph], atol=1e-12)
    H = sw.stroke(*cols)
    assert H.shape == (3, 1)


def test_finite_and_exact_where_the_pressure_angle_is_zero():
    # scheme 4a: delta_z = 0 at phi = 0 and pi (the paper's Eq. (10) is 0/0 there)
    p = S4A_A
    for t in (0.0, math.pi):
        assert ref_delta(t, *p) < 1e-7
        assert sw.pressure_angle(t, *p) == pytest.approx(0.0, abs=1e-15)
        pv = float(sw.first_transfer(t, *p))
        pa = float(sw.second_transfer(t, *p))
        assert math.isfinite(pv) and math.isfinite(pa)
        assert pv == pytest.approx(fd1(lambda x: ref_s(x, *p), t), abs=1e-10)
        assert pa == pytest.approx(fd2(lambda x: ref_s(x, *p), t), rel=1e-6)


@pytest.mark.parametrize("name", ["1a", "1b", "1c", "4a_a", "4b_a", "3", "nonuni"])
def test_stroke_from_true_extremes(name):
    p = NONUNI if name == "nonuni" else DESIGNS[name]
    _xmin, smin, _xmax, smax = ref_extremes(p)
    H_ref = smax - smin
    H = float(sw.stroke(*p))
    assert H == pytest.approx(H_ref, rel=1e-9)
    e = sw.extremes(*p)
    assert float(e["s_max"]) == pytest.approx(smax, rel=1e-9, abs=1e-12)
    assert float(e["s_min"]) == pytest.approx(smin, rel=1e-9, abs=1e-12)
    # angles of the extremes: flat there, so compare through the positions they give
    assert ref_s(float(e["phi_max"]), *p) == pytest.approx(smax, abs=1e-12)
    assert ref_s(float(e["phi_min"]), *p) == pytest.approx(smin, abs=1e-12)
    naive = ref_s(math.pi, *p) - ref_s(0.0, *p)
    if name in ("1a", "1b", "1c", "3", "nonuni"):
        assert abs(naive - H_ref) > 1e-6  # here s(pi) - s(0) is wrong; the stroke is right
    if name == "nonuni":
        assert not bool(sw.unimodal(*p))


# --------------------------------------------------------------------------------------------
# 2. harmonic form, relative units
# --------------------------------------------------------------------------------------------

def ref_harmonic(phi, R, r, l, alpha, a=0.0, b=0.0):
    """cos(delta) ~ 1 - sin^2(delta)/2 applied to the 3-D construction (horizontal rod part)."""
    def q(t):
        A, B = ref_points(t, R, r, l, alpha, a, b)
        return (A[0] - B[0]) ** 2 + (A[1] - B[1]) ** 2
    return r * math.sin(alpha) * (1 - math.cos(phi)) + (q(0.0) - q(phi)) / (2 * l)


@pytest.mark.parametrize("name", ["1a", "4a_a", "4b_a", "2"])
def test_harmonic_form_and_its_error(name):
    p = DESIGNS[name]
    ph = np.linspace(0, 2 * math.pi, sw.GRID, endpoint=False)
    approx = sw.position_harmonic(ph, *p)
    ref_h = np.array([ref_harmonic(t, *p) for t in ph])
    np.testing.assert_allclose(approx, ref_h, atol=1e-14)
    # Pi_v of the harmonic form = derivative of the harmonic position
    pv_h = sw.first_transfer_harmonic(ph[:20], *p)
    np.testing.assert_allclose(pv_h, [fd1(lambda x: ref_harmonic(x, *p), t) for t in ph[:20]],
                               atol=1e-11)
    err = approx - np.array([ref_s(t, *p) for t in ph])
    e = sw.harmonic_error(*p)
    assert float(e["max"]) == pytest.approx(np.max(np.abs(err)), rel=1e-6)
    assert float(e["rms"]) == pytest.approx(np.sqrt(np.mean(err ** 2)), rel=1e-6)
    assert float(e["relative_max"]) == pytest.approx(np.max(np.abs(err)) / float(sw.stroke(*p)),
                                                     rel=1e-6)


def test_relative_units_helper():
    R, r, l, al, a, b = S1_A
    rel = sw.relative(R, r=r, l=l, a=a, b=b, H=0.06)
    assert float(rel["r"]) == pytest.approx(r / R) and float(rel["H"]) == pytest.approx(0.6)
    ph = np.array(PHIS)
    s_rel = sw.position(ph, 1.0, rel["r"], rel["l"], al, rel["a"], rel["b"])
    np.testing.assert_allclose(s_rel, [ref_s(t, *S1_A) / R for t in ph], atol=1e-11)
    d = sw.Design(*S1_A).relative()
    assert d["l"] == pytest.approx(l / R)


# --------------------------------------------------------------------------------------------
# 3. characteristics
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["1a", "1b", "1c", "4b_a"])
def test_characteristics_against_reference(name):
    p = DESIGNS[name]
    _R, r, l, al, _a, _b = p
    c = sw.characteristics(*p)
    xmin, smin, xmax, smax = ref_extremes(p)
    assert float(c.H) == pytest.approx(smax - smin, rel=1e-9)
    phi_f = (xmax - xmin) % (2 * math.pi)
    # the extremes are flat: their angles are known to ~sqrt(eps) only
    assert float(c.phi_f) == pytest.approx(phi_f, abs=1e-6)
    assert float(c.phi_r) == pytest.approx(2 * math.pi - phi_f, abs=1e-6)
    df = ref_max_on(lambda t: ref_delta(t, *p), xmin, xmin + phi_f)
    dr = ref_max_on(lambda t: ref_delta(t, *p), xmax, xmax + 2 * math.pi - phi_f)
    assert float(c.delta_f) == pytest.approx(df, rel=1e-7)
    assert float(c.delta_r) == pytest.approx(dr, rel=1e-7)
    vmax = ref_max_on(lambda t: abs(fd1(lambda x: ref_s(x, *p), t)), 0.0, 2 * math.pi, n=720)
    assert float(c.Pi_v_max) == pytest.approx(vmax, rel=1e-7)
    assert float(c.L) == pytest.approx(2 * r * math.sin(al) + l, rel=1e-14)  # Eq. (13)
    # exact axial extent: lowest disk point (phi = 0) to the highest slide point
    zA0 = ref_points(0.0, *p)[0][2]
    zB_low = min(ref_points(t, *p)[1][2] for t in np.linspace(0, 2 * math.pi, 721))
    assert float(c.L_exact) == pytest.approx(zA0 + smax - zB_low, rel=1e-9)
    assert bool(c.unimodal)
    omega = 50 * math.pi / 30
    assert float(sw.max_slide_speed(*p, omega=omega)) == pytest.approx(omega * vmax, rel=1e-7)


def test_velocity_limit_from_productivity_eq3_eq14():
    # Eq. (3): [Pi_v] <= 30 u [v] / (pi Pi_T), Pi_T in pieces/min; u = 12, [v] = 0.35 m/s,
    # Pi_T = 600/min
    expected = 30 * 12 * 0.35 / (math.pi * 600)
    assert float(sw.allowed_first_transfer(0.35, 600 / 60, 12)) == pytest.approx(expected,
                                                                                 rel=1e-14)


def test_unimodality_against_dense_reference():
    for p, want in ((S1_A, True), (S4A_A, True), (NONUNI, False)):
        ph = np.linspace(0, 2 * math.pi, 720, endpoint=False)
        s = np.array([ref_s(t, *p) for t in ph])
        n_max = int(np.sum((s > np.roll(s, 1)) & (s >= np.roll(s, -1))))
        assert (n_max == 1) is want
        assert bool(sw.unimodal(*p)) is want
        assert bool(sw.characteristics(*p).unimodal) is want


# --------------------------------------------------------------------------------------------
# 4. scheme constructors
# --------------------------------------------------------------------------------------------

def test_scheme_constructors_fix_what_the_scheme_fixes():
    R = 0.1
    d1 = sw.scheme_1(R, 0.11, 0.15, 20 * DEG, 0.01, 0.02)
    assert d1.scheme == "1" and set(d1.free) == {"r", "l", "alpha", "a", "b"}
    d2 = sw.scheme_2(R, 0.03, 0.25, 0.02)
    assert (d2.alpha, d2.a) == (math.pi / 2, 0.0) and set(d2.free) == {"r", "l", "b"}
    d3 = sw.scheme_3(R, 0.09, 0.2, 0.02, 0.03)
    assert d3.alpha == 0.0 and set(d3.free) == {"r", "l", "a", "b"}
    d4a = sw.scheme_4a(R, 0.15, 20 * DEG)
    assert (d4a.a, d4a.b) == (0.0, 0.0) and set(d4a.free) == {"l", "alpha"}
    assert d4a.r * math.cos(d4a.alpha) == pytest.approx(R, rel=1e-15)
    d4b = sw.scheme_4b(R, 0.11, 0.15, 20 * DEG, 0.02)
    assert d4b.a == 0.0 and d4b.b == 0.02 and set(d4b.free) == {"r", "l", "alpha", "b"}
    # each constructor's design moves as the 3-D construction says, e.g. scheme 4a H = 2 R tan a
    _xmin, smin, _xmax, smax = ref_extremes(d4a.params, n=360)
    assert d4a.stroke() == pytest.approx(smax - smin, rel=1e-9)
    assert d4a.stroke() == pytest.approx(2 * R * math.tan(20 * DEG), rel=1e-12)
    for d in (d2, d3, d4b):
        assert float(d.position(2.0)) == pytest.approx(ref_s(2.0, *d.params), abs=1e-12)


@pytest.mark.parametrize("call, needle", [
    (lambda: sw.scheme_4a(0.1, 0.15, 0.0), "alpha"),
    (lambda: sw.scheme_4a(0.1, 0.15, math.pi / 2), "alpha"),
    (lambda: sw.scheme_4b(0.1, 0.11, 0.15, 20 * DEG, 0.0), "b"),
    (lambda: sw.scheme_3(0.1, 0.09, 0.2, 0.0, 0.0), "a, b"),
    (lambda: sw.scheme_1(0.1, -0.11, 0.15, 20 * DEG), "r"),
])
def test_scheme_constructors_reject_what_the_scheme_excludes(call, needle):
    with pytest.raises(ParameterError) as ei:
        call()
    assert str(ei.value).startswith(needle)


# --------------------------------------------------------------------------------------------
# 5. kinetostatics: power balance
# --------------------------------------------------------------------------------------------

def ref_slide_statics(phi, p, F, mu_eff):
    """Rod force S (compression +), lateral force N, and the virtual powers (at omega = 1) of
    the rod force on the disk point and of the guide reaction on the slide point.

    Axial equilibrium of the slide: S cos(delta) = F + friction, friction = mu_eff |N| opposing
    the slide's velocity ds/dphi (from a finite difference of the construction).
    """
    A, B = ref_points(phi, *p)
    e = (A - B) / p[2]
    cd, sd = e[2], math.hypot(e[0], e[1])
    v = fd1(lambda x: ref_s(x, *p), phi)
    # S cd = F + mu sd |S| sgn(v)  -> solve for both signs of S and keep the consistent one
    S = None
    for sgn_S in (1.0, -1.0):
        cand = F / (cd - mu_eff * sd * sgn_S * math.copysign(1.0, v))
        if cand * sgn_S >= 0:
            S = cand
            break
    assert S is not None

    def B_of(t):
        return ref_points(t, *p)[1]

    def Ah_of(t):
        A_ = ref_points(t, *p)[0]
        return np.array([A_[0], A_[1], 0.0])

    vB = np.array([fd1(lambda t, k=k: B_of(t)[k], phi) for k in range(3)])
    vAh = np.array([fd1(lambda t, k=k: Ah_of(t)[k], phi) for k in range(3)])
    P_disk = S * float(e @ vB)  # the disk pushes the rod at B with S e
    eh = np.array([e[0], e[1], 0.0])
    P_rotor = -S * float(eh @ vAh)  # the guide holds the slide against the rod's S e_h
    return S, S * sd, P_disk, P_rotor, v


LOAD_ANG = np.radians([0.0, 60.0, 120.0, 170.0, 180.0, 360.0])
LOAD_F = np.array([0.0, 0.0, 20e3, 20e3, 0.0, 0.0])


@pytest.mark.parametrize("name", ["1a", "4a_a", "4b_b"])
def test_kinetostatics_frictionless_power_balance(name):
    d = sw.Design(*DESIGNS[name])
    u = 6
    ph = np.linspace(0.0, 2 * math.pi, 73)
    f = sw.drive_forces(d, (LOAD_ANG, LOAD_F), u=u, phi=ph)
    sel = [3, 20, 27, 33, 40, 55]
    for i in sel:
        t = ph[i]
        F = float(np.interp(t % (2 * math.pi), LOAD_ANG, LOAD_F))
        S, _N, P_disk, P_rotor, v = ref_slide_statics(t, d.params, F, 0.0)
        assert float(f.F[i]) == pytest.approx(F, abs=1e-9)
        assert float(f.S[i]) == pytest.approx(S, rel=1e-9, abs=1e-9)
        assert float(f.M_disk[i]) == pytest.approx(P_disk, rel=1e-7, abs=1e-6)
        assert float(f.M_rotor[i]) == pytest.approx(P_rotor, rel=1e-7, abs=1e-6)
        assert float(f.M[i]) == pytest.approx(F * v, rel=1e-7, abs=1e-6)  # torque x omega = F v
        # all u slides, phase-shifted by 2 pi / u: M_total omega = sum F_k v_k
        tot = 0.0
        for k in range(u):
            tk = t + 2 * math.pi * k / u
            Fk = float(np.interp(tk % (2 * math.pi), LOAD_ANG, LOAD_F))
            tot += Fk * fd1(lambda x: ref_s(x, *d.params), tk)
        assert float(f.M_total[i]) == pytest.approx(tot, rel=1e-7, abs=1e-6)
    assert f.efficiency == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("guide", [None, (0.12, 0.04)])
def test_kinetostatics_with_friction_losses_and_efficiency(guide):
    d = sw.Design(*S1_A)
    rho = 6 * DEG
    mu = math.tan(rho)
    kw = {}
    if guide is not None:
        bg, e = guide
        kw = {"guide_length": bg, "overhang": e}
        # two bearing places bg apart, the joint e outside: moments about the far one give
        # N1 = N (bg + e) / bg at the near one, N2 = N1 - N = N e / bg at the far one
        mu_eff = mu * ((bg + e) / bg + e / bg)
    else:
        mu_eff = mu
    ph = np.linspace(0.0, 2 * math.pi, 145)
    # a load that resists part of the forward stroke and aids part of the return stroke
    ang = np.radians([0.0, 60.0, 120.0, 200.0, 260.0, 300.0, 360.0])
    Fs = np.array([0.0, 5e3, 10e3, 0.0, -4e3, 0.0, 0.0])
    f = sw.drive_forces(d, (ang, Fs), u=3, rho_guide=rho, phi=ph, **kw)
    f0 = sw.drive_forces(d, (ang, Fs), u=3, phi=ph)
    for i in (10, 30, 45, 74, 76, 90, 110, 120):  # 74, 76: the load aids the return stroke
        t = ph[i]
        F = float(np.interp(t, ang, Fs))
        S, N, _P_disk, _P_rotor, v = ref_slide_statics(t, d.params, F, mu_eff)
        assert float(f.S[i]) == pytest.approx(S, rel=1e-9, abs=1e-9)
        # power in = useful power + friction power (losses >= 0, whichever way power flows)
        loss = mu_eff * abs(N) * abs(v)
        assert float(f.M[i]) == pytest.approx(F * v + loss, rel=1e-7, abs=1e-6)
        assert float(f.M[i]) - float(f0.M[i]) >= -1e-9
    assert 0.0 < f.efficiency < 1.0
    assert f.work_input > f0.work_input > 0
    # instantaneous efficiency of one slide: one value per angle (was (u, n), garbage rows)
    assert f.eta_inst.shape == ph.shape
    i = 30
    F = float(np.interp(ph[i], ang, Fs))
    assert float(f.eta_inst[i]) == pytest.approx(F * fd1(lambda x: ref_s(x, *d.params), ph[i])
                                                 / float(f.M[i]), rel=1e-7)
    assert f0.efficiency == pytest.approx(1.0, abs=1e-9)


# --------------------------------------------------------------------------------------------
# 6. synthesis
# --------------------------------------------------------------------------------------------

def ref_check(design, req):
    """Independent check of a synthesised design against a request (3-D construction)."""
    p = design.params
    xmin, smin, xmax, smax = ref_extremes(p, n=720)
    H = smax - smin
    assert abs(H - req.H) <= req.H_tol * (1 + 1e-6) + 1e-12
    phi_f = (xmax - xmin) % (2 * math.pi)
    df = ref_max_on(lambda t: ref_delta(t, *p), xmin, xmin + phi_f, n=200)
    dr = ref_max_on(lambda t: ref_delta(t, *p), xmax, xmax + 2 * math.pi - phi_f, n=200)
    assert df <= req.delta_f * (1 + 1e-12) and dr <= req.delta_r * (1 + 1e-12)
    if req.Pi_v_max is not None:
        vmax = ref_max_on(lambda t: abs(fd1(lambda x: ref_s(x, *p), t)), 0, 2 * math.pi, n=360)
        assert vmax <= req.Pi_v_max * (1 + 1e-6)
    if req.point is not None:
        assert abs(ref_s(req.point[0], *p) - req.point[1]) <= req.point_tol * (1 + 1e-6)
    if req.phi_f is not None:
        dphi = abs((phi_f - req.phi_f + math.pi) % (2 * math.pi) - math.pi)
        assert dphi <= req.phi_f_tol * (1 + 1e-6)
    return H, df, dr, phi_f


def test_synthesis_known_answer_4a_at_least_as_good():
    known = sw.scheme_4a(0.1, 0.2, 15 * DEG)
    H = known.stroke()
    delta = float(np.max([ref_delta(t, *known.params) for t in (math.pi / 2, 3 * math.pi / 2)]))
    L_known = 2 * known.r * math.sin(known.alpha) + known.l
    req = syn.Request(scheme="4a", R=0.1, H=H, H_tol=1e-13, delta_f=delta, delta_r=delta)
    res = syn.synthesize(req, n_candidates=1024, n_best=3, n_refine=2)
    best = res.best
    assert best.scheme == "4a"
    ref_check(best, req)
    L = 2 * best.r * math.sin(best.alpha) + best.l
    # the optimum is the known design itself (alpha fixed by H, l by delta): "at least as good"
    # to 1e-11 (the rod-repair margin was 1e-9 relative: L came out 2e-10 m longer)
    assert L <= L_known * (1 + 1e-11)
    assert float(res.table["L"][0]) == pytest.approx(L, rel=1e-12)


def test_synthesis_every_option_scheme_1():
    # point, phi_f, velocity limit, separate pressure angles, torque objective with u slides.
    # (phi_f: with delta <= 10 deg and l <= 5 R the asymmetry is small; a differential-evolution
    # search over the bounds found at most phi_f = 181.07 deg)
    R = 0.1
    pv = float(sw.allowed_first_transfer(0.4, 600 / 60, 12))
    req = syn.Request(scheme="1", R=R, H=0.06, H_tol=3e-4, delta_f=10 * DEG, delta_r=12 * DEG,
                      Pi_v_max=pv, point=(math.pi / 2, 0.028), point_tol=5e-4,
                      phi_f=181 * DEG, phi_f_tol=0.5 * DEG, objective="torque", u=12)
    res = syn.synthesize(req, n_candidates=1024, n_best=2, n_refine=1)
    assert len(res.designs) >= 1
    for i, d in enumerate(res.designs):
        ref_check(d, req)
        assert float(res.table["s_point"][i]) == pytest.approx(ref_s(req.point[0], *d.params),
                                                              abs=1e-12)
    assert res.n_evaluated == 1024 and res.n_feasible >= 0
    # objective column = peak frictionless torque of 12 slides under 1 N on each forward stroke
    d = res.best
    c = d.characteristics()
    t = np.linspace(0, 2 * math.pi, 180, endpoint=False)

    def M_ref(x):  # 12 slides, 1 N against each forward stroke, torque = sum F Pi_v
        tk = x + 2 * math.pi * np.arange(12) / 12
        fwd = ((tk - float(c.phi_min)) % (2 * math.pi)) < float(c.phi_f)
        return sum(fd1(lambda y: ref_s(y, *d.params), tt) for tt in tk[fwd])

    # where the peak is (located with the model, then evaluated independently)
    tk = t[:, None] + 2 * math.pi * np.arange(12) / 12
    fwd = ((tk - float(c.phi_min)) % (2 * math.pi)) < float(c.phi_f)
    i = int(np.argmax(np.abs(np.sum(np.where(fwd, sw.first_transfer(tk, *d.params), 0), 1))))
    peak = abs(M_ref(t[i]))
    assert float(res.table["objective"][0]) * R == pytest.approx(peak, rel=1e-6)
    for j in (i - 1, (i + 1) % 180, (i + 45) % 180, (i + 90) % 180):
        assert abs(M_ref(t[j])) <= peak * (1 + 1e-9)


def test_synthesis_impossible_request_names_constraint_and_closest_value():
    # scheme 4a: H = 2 R tan(alpha), max delta = asin(R (1/cos(alpha) - 1) / l); with l <= 5 R
    # and delta <= 2 deg the largest stroke is 2 R tan(acos(1 / (1 + 5 sin 2deg)))
    R = 0.1
    req = syn.Request(scheme="4a", R=R, H=0.2, H_tol=1e-4, delta_f=2 * DEG, delta_r=2 * DEG)
    with pytest.raises(InfeasibleError) as ei:
        syn.synthesize(req, n_candidates=1024, n_refine=2)
    msg = str(ei.value)
    key = ei.value.key  # type: ignore[attr-defined]
    closest = ei.value.closest_value  # type: ignore[attr-defined]
    H_max = 2 * R * math.tan(math.acos(1 / (1 + 5 * math.sin(2 * DEG))))
    delta_min = math.asin(R * (1 / math.cos(math.atan(1.0)) - 1) / (5 * R))
    assert key in ("H", "delta_f", "delta_r")
    if key == "H":
        assert "stroke" in msg and closest == pytest.approx(H_max, rel=1e-3)
    else:
        assert "pressure angle" in msg and closest == pytest.approx(delta_min, rel=1e-3)
    assert "closest achievable" in msg


def test_synthesis_two_failing_limits_closest_value_meets_the_others():
    # phi_f = 200 deg is out of reach (with delta <= 10 deg, l <= 5 R a differential-evolution
    # search over the bounds, run separately, found at most phi_f = 181.07 deg), and
    # s(90 deg) = 25 mm cannot be met together with the others either. The closest phi_f was
    # taken from a candidate that violated the point and the pressure angles (181.8 deg, more
    # than any design meeting them reaches); now the point is named as failing too and the
    # closest value meets every other limit.
    pv = 0.4 / (50 * math.pi / 30)
    req = syn.Request(scheme="1", R=0.1, H=0.06, H_tol=3e-4, delta_f=10 * DEG,
                      delta_r=10 * DEG, Pi_v_max=pv, point=(math.pi / 2, 0.025),
                      point_tol=5e-4, phi_f=200 * DEG, phi_f_tol=2 * DEG)
    with pytest.raises(InfeasibleError) as ei:
        syn.synthesize(req, n_candidates=4096, n_refine=2)
    e = ei.value
    assert e.key == "phi_f"  # type: ignore[attr-defined]
    closest = e.closest_value  # type: ignore[attr-defined]
    assert 180 * DEG < closest <= 181.08 * DEG
    assert "s(90 deg) = 0.025 m" in str(e)


def test_feasible_region_map_agrees_with_independent_check():
    req = syn.Request(scheme="4b", R=0.1, H=0.06, H_tol=3e-4, delta_f=8 * DEG,
                      delta_r=8 * DEG)
    base = sw.scheme_4b(0.1, 0.105, 0.25, 16 * DEG, 0.01)
    reg = syn.feasible_region(req, base, "r", "l", n=12)
    assert reg.feasible.shape == (12, 12)
    assert reg.feasible.any() and not reg.feasible.all()
    # a few cells: rebuild the design (alpha re-solved for the stroke, as documented) and check
    # the pressure angle independently
    for j, i in ((2, 3), (6, 6), (9, 2), (11, 11), (0, 0)):
        r, l = reg.x[i] * 0.1, reg.y[j] * 0.1
        try:
            # solve alpha for the stroke by brentq on the reference stroke
            def g(al, r=r, l=l):
                _xmin, smin, _xmax, smax = ref_extremes((0.1, r, l, al, 0.0, 0.01), n=180)
                return smax - smin - 0.06
            al = brentq(g, 1 * DEG, 45 * DEG, xtol=1e-10)
            dmax = ref_max_on(lambda t, r=r, l=l, al=al: ref_delta(t, 0.1, r, l, al, 0.0, 0.01),
                              0.0, 2 * math.pi, n=180)
            ok = dmax <= 8 * DEG
        except ValueError:
            ok = False
        margin = abs(float(reg.violations["delta_f"][j, i]))
        if margin > 1e-4:  # away from the boundary the map must agree
            assert bool(reg.feasible[j, i]) is bool(ok), (r, l)


# --------------------------------------------------------------------------------------------
# failure policy
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, exc, needles", [
    ({"l": 0.01}, AssemblyError, ("rod cannot reach", "|sin(delta_z)| = 2.86799")),
    ({"alpha": 100 * DEG}, ParameterError, ("alpha", "100", "90")),
    ({"alpha": -1 * DEG}, ParameterError, ("alpha", "-1", "0")),
    ({"R": -0.1}, ParameterError, ("R", "-0.1", "> 0")),
    ({"l": 0.0}, ParameterError, ("l", "0")),
    ({"r": float("nan")}, ParameterError, ("r", "nan")),
    ({"a": float("inf")}, ParameterError, ("a", "inf")),
])
def test_bad_input_fails_clearly(kwargs, exc, needles):
    p = dict(zip(("R", "r", "l", "alpha", "a", "b"), S1_A, strict=True))
    p.update(kwargs)
    for fn in (sw.position, sw.pressure_angle, sw.first_transfer, sw.second_transfer):
        with pytest.raises(exc) as ei:
            fn(np.array([0.0, 1.0, 2.0]), **p)
        msg = str(ei.value)
        for n in needles:
            assert n in msg, msg
    with pytest.raises(exc):
        sw.stroke(**p)


def test_nan_angle_fails_clearly():
    with pytest.raises(ParameterError, match="phi"):
        sw.position(np.array([0.0, np.nan]), *S1_A)


def test_rod_that_cannot_reach_lists_the_angles():
    with pytest.raises(AssemblyError) as ei:
        sw.position(np.linspace(0, 2 * math.pi, 73), 0.1, 0.05, 0.06, 20 * DEG, 0.0, -0.045)
    assert ei.value.ranges  # the rotor-angle ranges where it fails


EX4A = ["swashplate", "analyze", str(EXAMPLES / "swashplate_4a.toml")]
SYN = ["swashplate", "synthesize", "-R", "100 mm", "-H", "50 mm", "--candidates", "64"]


@pytest.mark.parametrize("argv", [
    ["swashplate", "synthesize", "-R", "100 mm", "-H", "50 kg"],
    [*SYN[:-2], "--scheme", "7"],
    [*SYN, "--map", "alpha,alpha"],
    [*SYN, "--map", "alpha"],
    [*SYN, "--map", "q,l"],
    [*SYN, "--delta", "95 deg"],
    [*SYN, "--delta", "-5 deg"],
    [*SYN, "--point", "90 deg"],
    [*SYN, "--point", "90 deg,20 kg"],
    [*SYN, "--phi-f", "400 deg"],
    [*SYN, "--v-allow", "0.3 m/s"],
    [*SYN, "--speed", "50 rpm", "--productivity", "600 1/min"],
    [*SYN, "--objective", "cost"],
    [*SYN, "--positions", "0"],
    [*SYN, "--stroke-tol", "-1 mm"],
    [*SYN, "--candidates", "abc"],
    [*SYN, "--bogus"],
    [*SYN, "--delta-f", "0 deg"],
    [*SYN, "--delta-r", "0 deg"],
    [*SYN, "--positions", "0", "--productivity", "600 1/min"],
    [*SYN, "--positions", "0", "--productivity", "600 1/min", "--v-allow", "0.3 m/s"],
    [*SYN, "--best", "0"],
    [*SYN, "--candidates", "0"],
    [*SYN, "--refine", "-1"],
    [*SYN, "--speed", "0 rpm", "--v-allow", "0.3 m/s"],
    [*SYN, "--speed", "-5 rpm"],
    [*SYN, "--productivity", "0 1/min"],
    [*SYN, "--point", "90 deg,25 mm", "--point-tol", "-1 mm"],
    [*SYN, "--phi-f", "185 deg", "--phi-f-tol", "-1 deg"],
    [*SYN, "--point", "90 deg,nan mm"],
    ["swashplate", "synthesize", "-R", "100 mm"],
    [*EX4A, "--angles", "0,x"],
    ["swashplate", "analyze", "/nonexistent/file.toml"],
])
def test_cli_bad_options_one_line_exit_2(argv, capsys, tmp_path):
    rc = main([*argv, "--out", str(tmp_path)] if "--bogus" not in argv else argv)
    cap = capsys.readouterr()
    assert rc == 2, cap.out + cap.err
    assert cap.err.count("\n") == 1 and cap.err.strip(), repr(cap.err)
    assert "Traceback" not in cap.err + cap.out


@pytest.mark.parametrize("extra, needle", [
    (["--delta-f", "0 deg"], "delta_f = 0 deg"),  # was silently replaced by --delta
    (["--delta-r", "0 deg"], "delta_r = 0 deg"),
    (["--positions", "0", "--productivity", "600 1/min"], "--positions = 0"),  # was a traceback
    (["--best", "0"], "--best = 0"),  # listed every design
    (["--speed", "0 rpm", "--v-allow", "0.3 m/s"], "--speed = 0 rpm"),
    (["--point", "90 deg,25 mm", "--point-tol", "-1 mm"], "point_tol = -0.001"),
    (["--point", "90 deg,nan mm"], "point position s_p = nan"),
])
def test_cli_bad_values_named(extra, needle, capsys, tmp_path):
    assert main([*SYN, *extra, "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert needle in err, err


@pytest.mark.parametrize("kwargs, needle", [
    ({"u": 2.5}, "u = 2.5"),
    ({"point": (math.pi / 2, float("nan"))}, "s_p = nan"),
    ({"point": (float("inf"), 0.02)}, "phi_p = inf"),
    ({"point_tol": -1e-3}, "point_tol"),
    ({"phi_f_tol": -0.01}, "phi_f_tol"),
])
def test_request_rejects_bad_values(kwargs, needle):
    base = {"scheme": "4a", "R": 0.1, "H": 0.05, "H_tol": 1e-4, "delta_f": 0.1, "delta_r": 0.1}
    with pytest.raises(ParameterError, match=re.escape(needle)):
        syn.Request(**(base | kwargs))


@pytest.mark.parametrize("kwargs", [{"n_best": 0}, {"n_candidates": 0}, {"n_refine": -1}])
def test_synthesize_rejects_bad_counts(kwargs):
    req = syn.Request(scheme="4a", R=0.1, H=0.05, H_tol=1e-4, delta_f=0.1, delta_r=0.1)
    with pytest.raises(ParameterError, match=next(iter(kwargs))):
        syn.synthesize(req, **kwargs)


def test_drive_forces_rejects_fractional_slide_count():
    with pytest.raises(ParameterError, match=re.escape("u = 2.5")):  # was silently truncated to 2
        sw.drive_forces(sw.scheme_4a(0.1, 0.2, 0.2), 1000.0, u=2.5)


def test_harmonic_error_of_a_slide_that_does_not_move():
    # alpha = 0, a = b = 0: H = 0 and the harmonic form is exact; no 0/0 (a RuntimeWarning,
    # an error under pytest) and no NaN
    e = sw.harmonic_error(0.1, 0.09, 0.2, 0.0)
    assert float(e["max"]) == 0.0 and float(e["relative_max"]) == 0.0


def test_feasible_region_plot_names_each_limit_and_says_when_empty():
    from linkwork.plot import pyplot
    from linkwork.plot.swashplate import plot_feasible_region

    req = syn.Request(scheme="4b", R=0.1, H=0.06, H_tol=3e-4, delta_f=8 * DEG,
                      delta_r=8 * DEG, point=(math.pi / 2, 0.03), point_tol=1e-3)
    base = sw.scheme_4b(0.1, 0.105, 0.25, 16 * DEG, 0.01)
    reg = syn.feasible_region(req, base, "r", "l", n=12)
    ax = plot_feasible_region(reg, best=base)
    labels = [h.get_label() for h in ax.get_legend().legend_handles]
    assert "limit: δz on the forward stroke" in labels and "best design" in labels
    empty = syn.FeasibleRegion(**{**reg.__dict__, "feasible": np.zeros_like(reg.feasible)})
    ax2 = plot_feasible_region(empty)
    assert "no feasible grid point" in ax2.get_title()
    pyplot().close("all")


@pytest.mark.parametrize("text", [
    "this is not toml = = =",
    'type = "swashplate"\nscheme = "4a"\n[geometry]\nR = "100 mm"\nl = "200 mm"\n',
    'type = "swashplate"\nscheme = "4a"\n[geometry]\nR = "100 mm"\nl = "200 mm"\n'
    'alpha = "15 deg"\n[operation]\npositions = 0\n',
    'type = "swashplate"\nscheme = "4a"\n[geometry]\nR = "-100 mm"\nl = "200 mm"\n'
    'alpha = "15 deg"\n',
    'type = "swashplate"\nscheme = "4a"\n[geometry]\nR = "100 mm"\nl = "200 mm"\n'
    'alpha = "15 deg"\n[load]\nforce = "5 kN"\nrho_guide = "89.9 deg"\n',
    'type = "swashplate"\nscheme = "1"\n[geometry]\nR = "100 mm"\nl = "20 mm"\nr = "50 mm"\n'
    'alpha = "15 deg"\na = "30 mm"\n',
])
def test_cli_broken_files_one_line_exit_2(text, capsys, tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text(text)
    rc = main(["swashplate", "analyze", str(f), "--out", str(tmp_path / "o")])
    cap = capsys.readouterr()
    assert rc == 2, cap.out + cap.err
    assert cap.err.count("\n") == 1 and cap.err.strip(), repr(cap.err)
    assert "Traceback" not in cap.err


def test_example_scheme_1_is_asymmetric_as_its_comment_says(tmp_path, capsys):
    # the example claims a lower pressure angle on the forward than on the return stroke, and a
    # stroke different from s(pi) - s(0); it had r = R, for which the offset a changes nothing
    text = (EXAMPLES / "swashplate_1.toml").read_text()
    assert main(["swashplate", "analyze", str(EXAMPLES / "swashplate_1.toml"), "--out",
                 str(tmp_path)]) == 0
    capsys.readouterr()
    data = json.loads((tmp_path / "characteristics.json").read_text())
    p = tuple(data["design"][k] for k in ("R", "r", "l", "alpha", "a", "b"))
    xmin, smin, xmax, smax = ref_extremes(p, n=720)
    phi_f = (xmax - xmin) % (2 * math.pi)
    df = ref_max_on(lambda t: ref_delta(t, *p), xmin, xmin + phi_f)
    dr = ref_max_on(lambda t: ref_delta(t, *p), xmax, xmax + 2 * math.pi - phi_f)
    assert dr - df > 1.5 * DEG
    assert f"{math.degrees(df):.3g} deg against {math.degrees(dr):.4g} deg" in text
    assert f"{(smax - smin) * 1e3:.4g} mm" in text
    assert f"{(ref_s(math.pi, *p) - ref_s(0.0, *p)) * 1e3:.4g} mm" in text
    assert f"({math.degrees(phi_f):.4g} deg)" in text


def test_cli_analyze_and_synthesize_run(capsys, tmp_path):
    assert main([*EX4A, "--out", str(tmp_path / "a")]) == 0
    out = capsys.readouterr().out
    assert "53.59 mm" in out and "1.011 / 1.011 deg" in out
    # the acceleration column must not read like the offset a of the title ("a = 0 mm")
    assert "slide acc. [m/s²]" in out and "a [m/s²]" not in out.replace("acc. [m/s²]", "")
    rc = main(["swashplate", "synthesize", "-R", "100 mm", "-H", "53.59 mm", "--scheme", "4a",
               "--delta", "1.1 deg", "--candidates", "256", "--refine", "1", "--best", "2",
               "--out", str(tmp_path / "s")])
    cap = capsys.readouterr()
    assert rc == 0, cap.err
    assert (tmp_path / "s" / "feasible_region.png").stat().st_size > 0
    rows = np.genfromtxt(tmp_path / "s" / "synthesis.csv", delimiter=",", names=True)
    assert rows.size >= 1
