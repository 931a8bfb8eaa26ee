"""Acceptance check of issue 2 (paper 000) as an external checker does it.

Every public quantity is compared, at 7 crank angles (some near dead centres), with reference
values computed here by an independent route: the bare loop-closure equations solved by a Newton
iteration of our own (scipy ``fsolve`` for the real start), velocities by the complex-step
derivative of that solver in time and accelerations by a 4th-order central difference of the
complex-step velocities (truncation ~1e-12).  The crank moves as
``phi1(t) = phi10 + omega1 t + eps1 t^2 / 2``, so ``eps1 != 0`` is part of the reference.
Tolerance: 1e-6 relative to the quantity, with an absolute floor of 1e-9 of the quantity's scale
(for values that pass through zero, e.g. velocities at a dead centre).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

from linkwork.errors import AssemblyError, LinkworkError, ParameterError
from linkwork.models import crank_slider as cs
from linkwork.models import sine
from linkwork.models.variable_structure import VariableStructureMechanism

RTOL = 1e-6
DEV: dict[str, float] = {}


# ------------------------------------------------------------------------------------------
# independent machinery: Newton on complex arguments, complex-step and 4th-order differences
# ------------------------------------------------------------------------------------------

def _newton(residual, q0, t, iters=60):
    """Root of residual(q, t) = 0 near real q0; t may be complex (complex step).

    Real Newton iterations with a forward-difference Jacobian from q0, then the same (frozen)
    Jacobian on the complex problem, which converges to the complex root linearly.
    """
    qr = np.asarray(q0, dtype=float)
    n = len(qr)
    for _ in range(iters):
        r0 = np.real(residual(qr, t.real))
        jac = np.empty((n, n))
        for k in range(n):
            dq = np.zeros(n)
            dq[k] = 1e-7 * max(1.0, abs(qr[k]))
            jac[:, k] = (np.real(residual(qr + dq, t.real)) - r0) / dq[k]
        step = np.linalg.solve(jac, r0)
        qr = qr - step
        if np.all(np.abs(step) <= 1e-15 * (1 + np.abs(qr))):
            break
    q = qr.astype(complex)
    for _ in range(iters):
        q = q - np.linalg.solve(jac, residual(q, t))
    return q


def _motion(position, t0=0.0, hc=1e-30, hd=1e-3):
    """(value, d/dt, d2/dt2) of position(t) (complex-capable) at t0."""
    def vel(t):
        return np.imag(position(t + 1j * hc)) / hc
    x = np.real(position(t0 + 0j))
    v = vel(t0)
    a = (-vel(t0 + 2 * hd) + 8 * vel(t0 + hd) - 8 * vel(t0 - hd) + vel(t0 - 2 * hd)) / (12 * hd)
    return x, v, a


def _close(actual, expected, scale, name):
    actual = np.asarray(actual, dtype=float)
    expected = np.asarray(expected, dtype=float)
    err = np.abs(actual - expected)
    lim = RTOL * np.abs(expected) + 1e-9 * scale
    rel = float(np.max(err / np.maximum(np.abs(expected), 1e-9 * scale)))
    DEV[name] = max(DEV.get(name, 0.0), rel)
    assert np.all(err <= lim), (name, actual, expected, rel)
    return rel


# ------------------------------------------------------------------------------------------
# offset crank-slider (idle mode)
# ------------------------------------------------------------------------------------------

CS_DESIGNS = [  # L1 [m], lambda2, lambda_e, omega1 [rad/s], eps1 [rad/s^2], branch
    (0.05, 4.0, 0.5, 12.566, 0.0, 1),
    (0.05, 4.0, 0.5, 12.566, 35.0, 1),
    (0.12, 2.6, -1.3, -7.0, -20.0, 1),
    (0.03, 3.0, 0.8, 20.0, 150.0, -1),
]


def _cs_reference(L1, lam2, lame, w1, e1, branch, phi10):
    L2, e = lam2 * L1, lame * L1

    def phi(t):
        return phi10 + w1 * t + 0.5 * e1 * t * t

    # unknowns: rod angle psi = atan2(C - B) in the usual sense, slider Y_C
    def residual(q, t):
        ph = phi(t)
        return np.array([L1 * np.cos(ph) + L2 * np.cos(q[0]) - e,
                         L1 * np.sin(ph) + L2 * np.sin(q[0]) - q[1]])

    # start: the rod pointing up (branch +1) or down (branch -1) from the crank pin
    q0 = np.array([np.pi / 2 * branch, L1 * math.sin(phi10) + branch * L2])

    def position(t):
        q = _newton(residual, q0, np.asarray(t, dtype=complex))
        # phi2 as the paper defines it: from +Y towards +X -> pi/2 - psi
        return np.array([q[1], np.pi / 2 - q[0]])

    (yc, phi2), (vc, w2), (ac, e2) = _motion(position, hd=2e-3 / max(abs(w1), 1.0))
    return dict(Y_C=yc, phi2=phi2, V_C=vc, omega2=w2, a_C=ac, eps2=e2)


def _near_dead_centres(lam2, lame, branch):
    # 7 angles: the two dead centres found numerically (+1e-4 rad) and 5 spread angles
    def yc(p, s):
        return s * (math.sin(p) + branch * math.sqrt(lam2**2 - (lame - math.cos(p))**2))
    tops = []
    for s in (1.0, -1.0):
        best = min((minimize_scalar(lambda p, s=s: -yc(p, s), bounds=(b0, b0 + 2.5),
                                    method="bounded", options={"xatol": 1e-12})
                    for b0 in np.linspace(-np.pi, np.pi, 5)), key=lambda r: r.fun)
        tops.append(best.x)
    return [tops[0] + 1e-4, tops[1] - 1e-4, 0.3, 1.7, 2.9, 4.1, 5.5]


@pytest.mark.parametrize("L1,lam2,lame,w1,e1,branch", CS_DESIGNS)
def test_offset_crank_slider_against_loop_equations(L1, lam2, lame, w1, e1, branch):
    angles = _near_dead_centres(lam2, lame, branch)
    res = cs.offset_crank_slider(np.array(angles), L1, lam2, lame, w1, e1, branch)
    for k, p in enumerate(angles):
        ref = _cs_reference(L1, lam2, lame, w1, e1, branch, p)
        L = L1
        w = max(abs(w1), 1.0)
        _close(res.Y_C[k], ref["Y_C"], L, "Y_C")
        # phi2 is an angle: compare modulo 2 pi
        d = math.remainder(res.phi2[k] - ref["phi2"], 2 * math.pi)
        assert abs(d) <= 1e-9, ("phi2", res.phi2[k], ref["phi2"])
        _close(res.V_C[k], ref["V_C"], L * w, "V_C")
        _close(res.omega2[k], ref["omega2"], w, "omega2")
        _close(res.a_C[k], ref["a_C"], L * (w * w + abs(e1)), "a_C")
        _close(res.eps2[k], ref["eps2"], w * w + abs(e1), "eps2")
        # transfer functions: the derivatives with respect to phi1 (omega1 = 1, eps1 = 0)
        r1 = _cs_reference(L1, lam2, lame, 1.0, 0.0, branch, p)
        _close(res.V_qC[k], r1["V_C"], L, "V_qC")
        _close(res.U21[k], r1["omega2"], 1.0, "U21")
        _close(res.eps_q2[k], r1["eps2"], 1.0, "eps_q2")
        _close(res.a_qC[k], r1["a_C"], L, "a_qC")
        # conventions: X_C = e, the '+' root for branch=+1 (slider above the pin)
        assert res.X_C[k] == pytest.approx(lame * L1, rel=1e-12)
        assert branch * (res.Y_C[k] - L1 * math.sin(p)) > 0
        # pressure angle: acute angle between rod (B->C) and guide (Y axis)
        bc = np.array([lame * L1 - L1 * math.cos(p), ref["Y_C"] - L1 * math.sin(p)])
        mu = math.acos(abs(bc[1]) / np.hypot(*bc))
        _close(res.pressure_angle[k], mu, 1.0, "pressure_angle")
        _close(cs.pressure_angle(p, lam2, lame), mu, 1.0, "pressure_angle()")


@pytest.mark.parametrize("L1,lam2,lame,w1,e1,branch", CS_DESIGNS)
def test_crank_slider_stroke_and_dead_centres_by_search(L1, lam2, lame, w1, e1, branch):
    def yc(p):
        return float(cs.offset_crank_slider(p, L1, lam2, lame, branch=branch).Y_C)
    # independent: maximise the slider position from the loop equations directly
    def y_ref(p):
        return _cs_reference(L1, lam2, lame, 1.0, 0.0, branch, p)["Y_C"]
    grid = np.linspace(0, 2 * np.pi, 721)
    ys = np.array([L1 * (math.sin(p) + branch * math.sqrt(lam2**2 - (lame - math.cos(p))**2))
                   for p in grid])
    out = {}
    for sgn, key in ((1.0, "top"), (-1.0, "bottom")):
        i = int(np.argmax(sgn * ys))
        r = minimize_scalar(lambda p, sgn=sgn: -sgn * y_ref(p),
                            bounds=(grid[i] - 0.02, grid[i] + 0.02),
                            method="bounded", options={"xatol": 1e-10})
        out[key] = (r.x % (2 * np.pi), y_ref(r.x))
    dc = cs.dead_centres(lam2, lame, branch)
    # the position is stationary there, so the angle is only determined to ~sqrt(eps)
    assert abs(math.remainder(float(dc.phi1_top) - out["top"][0], 2 * np.pi)) < 1e-5
    assert abs(math.remainder(float(dc.phi1_bottom) - out["bottom"][0], 2 * np.pi)) < 1e-5
    assert yc(float(dc.phi1_top)) == pytest.approx(out["top"][1], rel=1e-9)
    assert yc(float(dc.phi1_bottom)) == pytest.approx(out["bottom"][1], rel=1e-9)
    assert float(cs.stroke(L1, lam2, lame)) == pytest.approx(out["top"][1] - out["bottom"][1],
                                                           rel=1e-8)
    # max pressure angle by brute force
    mus = [math.asin(min(1.0, abs(lame - math.cos(p)) / lam2)) for p in grid]
    assert float(cs.max_pressure_angle(lam2, lame)) == pytest.approx(max(mus), rel=1e-6)


# ------------------------------------------------------------------------------------------
# inclined-slot sine mechanism (working mode)
# ------------------------------------------------------------------------------------------

SINE_DESIGNS = [  # L1, alpha, omega1, eps1
    (0.05, math.radians(90.0), 12.566, 0.0),
    (0.05, math.radians(60.0), 12.566, 40.0),
    (0.08, math.radians(127.0), -9.0, -15.0),
    (0.02, math.radians(25.0), 30.0, 200.0),
]


def _sine_reference(L1, alpha, w1, e1, phi10):
    def phi(t):
        return phi10 + w1 * t + 0.5 * e1 * t * t

    d = np.array([math.cos(alpha), math.sin(alpha)])

    # unknowns: xs = where the slot's line crosses the x axis (a point fixed in the ram), u =
    # block position along the slot from that point; B = (xs, 0) + u d
    def residual(q, t):
        ph = phi(t)
        return np.array([L1 * np.cos(ph) - q[0] - q[1] * d[0], L1 * np.sin(ph) - q[1] * d[1]])

    def solve(t):
        return _newton(residual, np.array([L1, 0.0]), np.asarray(t, dtype=complex))

    xs0 = _newton(lambda q, t: np.array([L1 - q[0] - q[1] * d[0], -q[1] * d[1]]),
                  np.array([L1, 0.0]), np.asarray(0j)).real[0]

    def position(t):
        q = solve(t)
        # X3: ram displacement from its phi1 = 0 position, towards the crank axis (-x)
        return np.array([xs0 - q[0], q[1]])

    (x3, x32), (v3, v32), (a3, a32) = _motion(position, hd=2e-3 / max(abs(w1), 1.0))
    return dict(X3=x3, X32=x32, V3=v3, V32=v32, a3=a3, a32=a32)


@pytest.mark.parametrize("L1,alpha,w1,e1", SINE_DESIGNS)
def test_inclined_slot_against_loop_equations(L1, alpha, w1, e1):
    ext = [alpha - np.pi / 2 + 1e-4, alpha + np.pi / 2 - 1e-4]
    angles = np.array([*ext, 0.0, 0.9, 2.2, 3.6, 5.1])
    res = sine.inclined_slot(angles, L1, alpha, w1, e1)
    r1 = sine.inclined_slot(angles, L1, alpha)
    w = max(abs(w1), 1.0)
    scale = L1 / math.sin(alpha)
    for k, p in enumerate(angles):
        ref = _sine_reference(L1, alpha, w1, e1, p)
        _close(res.X3[k], ref["X3"], scale, "X3")
        _close(res.X32[k], ref["X32"], scale, "X32")
        _close(res.V3[k], ref["V3"], scale * w, "V3")
        _close(res.V32[k], ref["V32"], scale * w, "V32")
        _close(res.a3[k], ref["a3"], scale * (w * w + abs(e1)), "a3")
        _close(res.a32[k], ref["a32"], scale * (w * w + abs(e1)), "a32")
        ref1 = _sine_reference(L1, alpha, 1.0, 0.0, p)
        _close(r1.U31[k], ref1["V3"], scale, "U31")
    # Eq. (14): X3 = L1 (1 - cos phi1) at alpha = 90 deg, X32 = L1 sin phi1
    r90 = sine.inclined_slot(angles, L1, np.pi / 2)
    np.testing.assert_allclose(r90.X3, L1 * (1 - np.cos(angles)), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(r90.X32, L1 * np.sin(angles), rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("L1,alpha,w1,e1", SINE_DESIGNS)
def test_sine_stroke_and_extremes_by_search(L1, alpha, w1, e1):
    def x3(p):
        return _sine_reference(L1, alpha, 1.0, 0.0, p)["X3"]
    grid = np.linspace(0, 2 * np.pi, 361)
    vals = np.array([L1 * (1 - math.cos(p) + math.sin(p) / math.tan(alpha)) for p in grid])
    found = {}
    for sgn, key in ((1.0, "max"), (-1.0, "min")):
        i = int(np.argmax(sgn * vals))
        r = minimize_scalar(lambda p, sgn=sgn: -sgn * x3(p),
                            bounds=(grid[i] - 0.03, grid[i] + 0.03),
                            method="bounded", options={"xatol": 1e-10})
        found[key] = (r.x % (2 * np.pi), x3(r.x))
    ex = sine.extreme_positions(alpha)
    assert abs(math.remainder(float(ex.phi1_max) - found["max"][0], 2 * np.pi)) < 1e-5
    assert abs(math.remainder(float(ex.phi1_min) - found["min"][0], 2 * np.pi)) < 1e-5
    H = found["max"][1] - found["min"][1]
    assert float(sine.stroke(L1, alpha)) == pytest.approx(H, rel=1e-9)
    lo, hi = sine.alpha_for_stroke(L1, H)
    for a_ in (float(lo), float(hi)):
        assert 0 < a_ < np.pi
        gridv = [_sine_reference(L1, a_, 1.0, 0.0, p)["X3"] for p in (a_ - np.pi / 2,
                                                                        a_ + np.pi / 2)]
        assert gridv[1] - gridv[0] == pytest.approx(H, rel=1e-9)
    assert min(abs(float(lo) - alpha), abs(float(hi) - alpha)) < 1e-9
    assert float(lo) + float(hi) == pytest.approx(np.pi, rel=1e-12)


def _slider_load(alpha, f1, f2, sigma):
    """Load P the ram carries against its motion (+x) for block normal force N = 1.

    Newton's law of the ram, written from scratch: unknowns N-direction fixed (N = 1), guide
    normal G, load P.  Block on slot: N n + sigma f1 N d (friction dragging the ram along the
    block's relative sliding direction sigma d), n the slot normal with n_x > 0; guide: G along
    y and friction -f2 |G| along x; load -P along x.
    """
    d = np.array([math.cos(alpha), math.sin(alpha)])
    n = np.array([math.sin(alpha), -math.cos(alpha)])
    fb = n + sigma * f1 * d
    G = -fb[1]
    return fb[0] - f2 * abs(G)


@pytest.mark.parametrize("f1,f2", [(0.12, 0.10), (0.3, 0.05), (0.0, 0.2), (0.5, 0.5)])
def test_working_range_from_ram_equilibrium(f1, f2):
    lo, hi = sine.working_range(f1, f2)

    def worst(a):
        return min(_slider_load(a, f1, f2, s) for s in (1.0, -1.0))
    a_lo = brentq(worst, 1e-6, np.pi / 2, xtol=1e-14)
    a_hi = brentq(worst, np.pi / 2, np.pi - 1e-6, xtol=1e-14)
    assert float(lo) == pytest.approx(a_lo, rel=1e-9)
    assert float(hi) == pytest.approx(a_hi, rel=1e-9)
    for a in np.linspace(float(lo) + 1e-3, float(hi) - 1e-3, 7):
        eta = worst(a) / math.sin(a)
        assert float(sine.force_ratio(a, f1, f2)) == pytest.approx(eta, rel=1e-9, abs=1e-12)
    sine.check_alpha(0.5 * (float(lo) + float(hi)), f1, f2)
    with pytest.raises(ParameterError, match="alpha"):
        sine.check_alpha(float(lo) * 0.99, f1, f2)


# ------------------------------------------------------------------------------------------
# variable structure: the duty schedule of the issue (5 idle revolutions, 3 strokes at 60 deg)
# ------------------------------------------------------------------------------------------

def test_duty_schedule_against_references():
    L1, lam2, lame, w1 = 0.05, 4.0, 0.5, 4 * np.pi
    m = VariableStructureMechanism(L1, lam2, lame, math.radians(60), f_slot=0.12, f_guide=0.1)
    res = m.run([("idle", 5), ("working", 3, math.radians(60))], w1, samples_per_revolution=72)
    T = 2 * np.pi / w1
    assert res.switch_t == pytest.approx([5 * T], rel=1e-12)
    assert list(res.switch_to) == [1]
    assert res.t[-1] == pytest.approx(8 * T, rel=1e-12)
    assert res.switch.sum() == 1
    # sample values at a few instants against the loop-equation references
    for k in (7, 100, 300, 359, 361 + 10, 361 + 130, len(res.t) - 5):
        p = float(res.phi1[k])
        if res.mode[k] == 0:
            ref = _cs_reference(L1, lam2, lame, w1, 0.0, 1, p)
            _close(res.s[k], ref["Y_C"], L1, "s idle")
            _close(res.v[k], ref["V_C"], L1 * w1, "v idle")
            _close(res.a[k], ref["a_C"], L1 * w1 * w1, "a idle")
            assert res.ram_s[k] == 0 and res.ram_v[k] == 0
        else:
            ref = _sine_reference(L1, math.radians(60), w1, 0.0, p)
            for a_, b_ in ((res.s[k], "X3"), (res.ram_s[k], "X3")):
                _close(a_, ref[b_], L1, b_)
            _close(res.v[k], ref["V3"], L1 * w1, "V3")
            _close(res.a[k], ref["a3"], L1 * w1 * w1, "a3")
    # ram velocity jump at engagement: V3(phi1 = 0) = omega1 L1 cot(alpha)
    assert res.switch_ram_dv[0] == pytest.approx(w1 * L1 / math.tan(math.radians(60)),
                                                 rel=1e-12)


# ------------------------------------------------------------------------------------------
# failure policy: clear errors naming parameter, value and limit; never NaN
# ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("call,words", [
    (lambda: cs.offset_crank_slider(np.linspace(0, 6, 50), 0.05, 1.2, 0.5), ["lambda2", "1.5"]),
    (lambda: cs.offset_crank_slider(0.3, -0.05, 4.0, 0.5), ["L1", "-0.05"]),
    (lambda: cs.offset_crank_slider(0.3, 0.05, -4.0, 0.5), ["lambda2", "-4"]),
    (lambda: cs.offset_crank_slider(np.nan, 0.05, 4.0, 0.5), ["phi1", "nan"]),
    (lambda: cs.offset_crank_slider(0.3, 0.05, np.nan, 0.5), ["lambda2", "nan"]),
    (lambda: cs.offset_crank_slider(0.3, 0.05, 4.0, np.inf), ["lambda_e", "inf"]),
    (lambda: cs.offset_crank_slider(0.3, 0.05, 4.0, 0.5, omega1=np.nan), ["omega1", "nan"]),
    (lambda: cs.offset_crank_slider(0.3, 0.05, 4.0, 0.5, branch=0), ["branch", "0"]),
    (lambda: cs.stroke(0.05, 1.4, 0.5), ["lambda2", "1.4", "1.5"]),
    (lambda: cs.dead_centres(1.4, 0.5), ["lambda2", "1.4", "1.5"]),
    (lambda: cs.max_pressure_angle(1.4, 0.5), ["lambda2", "1.4", "1.5"]),
    (lambda: sine.inclined_slot(0.3, 0.05, 0.0), ["alpha", "0"]),
    (lambda: sine.inclined_slot(0.3, 0.05, np.pi), ["alpha", "180"]),
    (lambda: sine.inclined_slot(0.3, 0.05, np.nan), ["alpha", "nan"]),
    (lambda: sine.inclined_slot(0.3, 0.0, 1.0), ["L1", "0"]),
    (lambda: sine.stroke(-1.0, 1.0), ["L1", "-1"]),
    (lambda: sine.alpha_for_stroke(0.05, 0.09), ["H", "0.09", "0.1"]),
    (lambda: sine.alpha_for_stroke(0.05, np.nan), ["H", "nan"]),
    (lambda: sine.alpha_for_stroke(0.05, -0.2), ["H", "-0.2"]),
    (lambda: sine.working_range(-0.1, 0.1), ["f_slot", "-0.1"]),
    (lambda: sine.working_range(np.nan, 0.1), ["f_slot", "nan"]),
    (lambda: sine.working_range(1.5, 1.0), ["f_slot", "1.5"]),
    (lambda: sine.check_alpha(math.radians(5), 0.12, 0.1), ["alpha", "5", "12.55", "167.4"]),
    (lambda: VariableStructureMechanism(0.05, 1.2, 0.5, 1.0), ["lambda2", "1.2", "1.5"]),
    (lambda: VariableStructureMechanism(0.05, 4.0, 0.5, math.radians(5), f_slot=0.12,
                                        f_guide=0.1), ["alpha", "5"]),
    (lambda: VariableStructureMechanism(0.05, 4.0, 0.5, 1.0).run([("idle", 0)], 1.0),
     ["revolutions", "0"]),
    (lambda: VariableStructureMechanism(0.05, 4.0, 0.5, 1.0).run([("boring", 1)], 1.0),
     ["mode", "boring"]),
    (lambda: VariableStructureMechanism(0.05, 4.0, 0.5, 1.0).run([("idle", 1)], np.nan),
     ["omega1", "nan"]),
    (lambda: VariableStructureMechanism(0.05, 4.0, 0.5, 1.0).run([("idle", 1)], -3.0),
     ["omega1", "-3"]),
    (lambda: VariableStructureMechanism(0.05, 4.0, 0.5, 1.0, f_slot=0.12, f_guide=0.1).run(
        [("working", 1, math.radians(5))], 1.0), ["alpha", "5"]),
])
def test_impossible_parameters_give_clear_errors(call, words):
    with pytest.raises(LinkworkError) as ei:
        call()
    msg = str(ei.value).lower()
    for w in words:
        assert w.lower() in msg, (w, msg)
    assert isinstance(ei.value, ValueError)


def test_assembly_error_lists_the_ranges():
    phi = np.linspace(0, 2 * np.pi, 361)
    with pytest.raises(AssemblyError) as ei:
        cs.offset_crank_slider(phi, 0.05, 1.4, 0.5)
    # the rod (1.4) cannot reach the guide where |0.5 - cos phi| >= 1.4: cos phi <= -0.9
    bad = np.degrees(phi[np.abs(0.5 - np.cos(phi)) >= 1.4])
    rng = ei.value.ranges
    assert rng, "no ranges in the AssemblyError"
    lo, hi = np.degrees(rng[0][0]), np.degrees(rng[-1][1])
    assert lo == pytest.approx(bad.min(), abs=1.01) and hi == pytest.approx(bad.max(), abs=1.01)
    msg = str(ei.value)
    assert "deg" in msg or "rad" in msg
    # on_failure="nan" gives NaN exactly there, with a mask
    r = cs.offset_crank_slider(phi, 0.05, 1.4, 0.5, on_failure="nan")
    assert np.array_equal(~r.valid, np.abs(0.5 - np.cos(phi)) >= 1.4)
    assert np.all(np.isfinite(r.Y_C[r.valid]))


# ------------------------------------------------------------------------------------------
# broken sine-press files to `linkwork analyze`: one line on stderr, exit code 2
# ------------------------------------------------------------------------------------------

SP_BROKEN = [
    ('L1 = "50 mm"', 'L1 = "50 mm', ["invalid toml"]),
    ('type = "sine_press"', 'type = "sine_pres"', ["type", "sine_pres"]),
    ('type = "sine_press"', '', ["type", "missing"]),
    ('L1 = "50 mm"', 'L1 = "100 kg"', ["crank.L1", "100 kg", "length"]),
    ('L1 = "50 mm"', 'L1 = "-50 mm"', ["crank.L1", "-50 mm"]),
    ('L1 = "50 mm"', '', ["crank.L1", "missing"]),
    ('L1 = "50 mm"', 'L1 = nan', ["crank.L1", "nan"]),
    ('L1 = "50 mm"', 'L1 = "fifty mm"', ["crank.L1", "fifty"]),
    ('speed = "120 rpm"', 'speed = "120 mm"', ["crank.speed", "120 mm"]),
    ('lambda2 = 4.0', 'lambda2 = 1.2', ["idle.lambda2", "1.2", "1.5"]),
    ('alpha = "60 deg"', 'alpha = "5 deg"', ["working.alpha", "5 deg", "12.55"]),
    ('alpha = "60 deg"', 'alpha = "200 deg"', ["working.alpha", "200"]),
    ('alpha = "60 deg"', 'alpha = 60', ["working.alpha", "3437.75 deg", "plain number",
                                        "radians"]),
    ('alpha = "45 deg"', 'alpha = "175 deg"', ["schedule", "175 deg", "167.4"]),
    ('lambda_e = 0.5', 'lambda_e = 0.5\nfoo = 1', ["idle.foo", "unknown key"]),
    ('branch = 1', 'branch = 0', ["idle.branch", "0"]),
    ('revolutions = 5', 'revolutions = 0', ["schedule.0.revolutions", "0"]),
    ('revolutions = 5', 'revolutions = 2.5', ["schedule.0.revolutions", "2.5"]),
    ('mode = "idle"', 'mode = "sleep"', ["schedule.0.mode", "sleep"]),
    ('f_slot = 0.12', 'f_slot = -0.12', ["working.f_slot", "-0.12"]),
    ('f_slot = 0.12', 'f_slot = 5.0', ["working.alpha", "84.4"]),
    ('samples_per_revolution = 360', 'samples_per_revolution = 3',
     ["output.samples_per_revolution", "3"]),
]


@pytest.mark.parametrize("old,new,words", SP_BROKEN)
def test_cli_broken_sine_press_files_one_line_exit_2(old, new, words, tmp_path, capsys):
    from pathlib import Path

    from linkwork.cli import main
    text = (Path(__file__).resolve().parents[1] / "examples" / "sine_press.toml").read_text()
    assert old in text
    p = tmp_path / "press.toml"
    p.write_text(text.replace(old, new, 1))
    rc = main(["analyze", str(p), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert rc == 2
    assert len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err and "press.toml" in err
    for w in words:
        assert w.lower() in err.lower(), (w, err)
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_cli_missing_file(tmp_path, capsys):
    from linkwork.cli import main
    assert main(["analyze", str(tmp_path / "none.toml")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "none.toml" in err


def test_cli_sine_press_outputs_match_the_functions(tmp_path, capsys, monkeypatch):
    """The CSV written by `linkwork analyze` carries the same numbers as the public functions
    (SI columns), for both modes, and the schedule switches at 5 T, 8 T, 10 T."""
    import csv
    import json
    from pathlib import Path

    from linkwork.cli import main
    monkeypatch.setenv("COLUMNS", "250")
    src = Path(__file__).resolve().parents[1] / "examples" / "sine_press.toml"
    out = tmp_path / "out"
    assert main(["analyze", str(src), "--out", str(out)]) == 0
    table = capsys.readouterr().out
    # the switch instants say which mode is entered (was "duration, switches: 6, 2.5 s, ...")
    assert "2.5 (→ working), 4 (→ idle), 5 (→ working)" in table
    with (out / "idle_cycle.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    phi = np.array([float(r["phi1 [rad]"]) for r in rows])
    w1 = 120 * 2 * np.pi / 60
    ref = cs.offset_crank_slider(phi, 0.05, 4.0, 0.5, w1)
    np.testing.assert_allclose([float(r["a_C [m/s^2]"]) for r in rows], ref.a_C, rtol=1e-12)
    with (out / "working_cycle.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    phi = np.array([float(r["phi1 [rad]"]) for r in rows])
    ref2 = sine.inclined_slot(phi, 0.05, math.radians(60), w1)
    np.testing.assert_allclose([float(r["X3 [m]"]) for r in rows], ref2.X3, rtol=1e-12,
                               atol=1e-15)
    data = json.loads((out / "schedule.json").read_text())
    T = 2 * np.pi / w1
    np.testing.assert_allclose([s["t"] for s in data["switches"]], [5 * T, 8 * T, 10 * T],
                               rtol=1e-12)
    for png in ("kinematics.png", "schedule.png", "working_range.png"):
        assert (out / png).stat().st_size > 10_000


def test_non_broadcasting_inputs_name_the_shapes():
    """Designs that do not broadcast against the angles gave NumPy's bare broadcast error."""
    with pytest.raises(ParameterError, match=r"shapes.*'L1': \(3,\)"):
        cs.offset_crank_slider([0.1, 0.2], [0.05, 0.06, 0.07], 4.0, 0.5)
    with pytest.raises(ParameterError, match=r"shapes.*'L1': \(3,\)"):
        sine.inclined_slot([0.1, 0.2], [0.05, 0.06, 0.07], 1.0)
    assert cs.offset_crank_slider([], 0.05, 4.0, 0.5).Y_C.shape == (0,)
    assert sine.inclined_slot([], 0.05, 1.0).X3.shape == (0,)


def test_zz_report_deviations():
    """Print the largest relative deviation per quantity (run with -s to see it)."""
    for k, v in sorted(DEV.items()):
        print(f"issue2 max rel. deviation {k:24s} {v:.2e}")
