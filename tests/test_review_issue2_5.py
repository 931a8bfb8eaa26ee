"""Adversarial review of issues 2 (paper 000, sine press) and 5 (paper 003, swash plate).

Independent spot checks (direct geometric construction solved numerically, finite differences in
time with eps1 != 0) at parameter sets not used by the acceptance tests, and regression tests of
the defects the review found (each failed before its fix).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from linkwork.cli import main
from linkwork.errors import AssemblyError, ParameterError
from linkwork.models import crank_slider, sine
from linkwork.models import swashplate as sw

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

# --------------------------------------------------------------------------------------------
# independent constructions
# --------------------------------------------------------------------------------------------


def _crank_phi(t: float, phi0: float, w1: float, e1: float) -> float:
    return phi0 + w1 * t + 0.5 * e1 * t * t


def _slider_y(phi1: float, L1: float, L2: float, e: float, branch: int) -> float:
    """Y of the slider on the guide X = e: root of |C - B| = L2 on the branch's side of B."""
    bx, by = L1 * math.cos(phi1), L1 * math.sin(phi1)
    f = lambda y: (e - bx) ** 2 + (y - by) ** 2 - L2 * L2  # noqa: E731
    if branch == 1:
        return brentq(f, by, by + L2, xtol=1e-15, rtol=1e-15)
    return brentq(f, by - L2, by, xtol=1e-15, rtol=1e-15)


def _ram_x(phi1: float, L1: float, alpha: float) -> float:
    """x of the slot's crossing with y = 0: the point of the line through B along alpha."""
    bx, by = L1 * math.cos(phi1), L1 * math.sin(phi1)
    d = np.array([math.cos(alpha), math.sin(alpha)])
    # solve B + t d = (x, 0) as a 2x2 system
    _t, x = np.linalg.solve(np.array([[d[0], -1.0], [d[1], 0.0]]), np.array([-bx, -by]))
    return float(x)


def _time_derivs(fun, t: float, h: float = 1e-4) -> tuple[float, float]:
    f = [fun(t + k * h) for k in (-2, -1, 0, 1, 2)]
    v = (f[0] - 8 * f[1] + 8 * f[3] - f[4]) / (12 * h)
    a = (-f[0] + 16 * f[1] - 30 * f[2] + 16 * f[3] - f[4]) / (12 * h * h)
    return v, a


CS_REVIEW = [  # L1, lambda2, lambda_e, omega1, eps1, branch, phi0
    (0.037, 2.9, -1.3, 7.3, -41.0, 1, 2.61),
    (0.081, 3.3, 0.9, -15.0, 120.0, -1, 4.9),
    (0.012, 5.7, 0.0, 31.0, 7.5, 1, 0.05),
]


@pytest.mark.parametrize("L1,lam2,lame,w1,e1,branch,phi0", CS_REVIEW)
def test_crank_slider_against_construction_and_time_differences(L1, lam2, lame, w1, e1,
                                                                branch, phi0):
    L2, e = lam2 * L1, lame * L1
    res = crank_slider.offset_crank_slider(phi0, L1, lam2, lame, w1, e1, branch)
    y_ref = _slider_y(phi0, L1, L2, e, branch)
    assert float(res.Y_C) == pytest.approx(y_ref, rel=1e-12, abs=1e-15)
    # rod angle from +Y towards +X: atan2(X_C - X_B, Y_C - Y_B)
    phi2_ref = math.atan2(e - L1 * math.cos(phi0), y_ref - L1 * math.sin(phi0))
    assert math.remainder(float(res.phi2) - phi2_ref, 2 * math.pi) == pytest.approx(0, abs=1e-12)
    # motion in time with eps1 != 0: phi1(t) = phi0 + w1 t + e1 t^2 / 2, derivatives at t = 0
    v, a = _time_derivs(lambda t: _slider_y(_crank_phi(t, phi0, w1, e1), L1, L2, e, branch), 0.0,
                        h=1e-4 / abs(w1))
    assert float(res.V_C) == pytest.approx(v, rel=1e-7)
    assert float(res.a_C) == pytest.approx(a, rel=1e-5)

    def rod_angle(t):
        p = _crank_phi(t, phi0, w1, e1)
        return math.atan2(e - L1 * math.cos(p), _slider_y(p, L1, L2, e, branch) - L1 * math.sin(p))

    w2, e2 = _time_derivs(lambda t: np.unwrap([phi2_ref, rod_angle(t)])[1], 0.0, h=1e-4 / abs(w1))
    assert float(res.omega2) == pytest.approx(w2, rel=1e-7)
    assert float(res.eps2) == pytest.approx(e2, rel=1e-5)
    # pressure angle: acute angle between the rod and the guide, computed from the vectors
    rod = np.array([e - L1 * math.cos(phi0), y_ref - L1 * math.sin(phi0)])
    mu = math.acos(abs(rod[1]) / np.linalg.norm(rod))
    assert float(res.pressure_angle) == pytest.approx(mu, abs=1e-12)


SINE_REVIEW = [  # L1, alpha, omega1, eps1, phi0
    (0.043, math.radians(23.0), 9.1, -17.0, 1.2),
    (0.11, math.radians(151.0), -4.4, 33.0, 5.7),
    (0.02, math.radians(97.0), 50.0, 0.0, 3.3),
]


@pytest.mark.parametrize("L1,alpha,w1,e1,phi0", SINE_REVIEW)
def test_inclined_slot_against_construction_and_time_differences(L1, alpha, w1, e1, phi0):
    res = sine.inclined_slot(phi0, L1, alpha, w1, e1)
    x0 = _ram_x(0.0, L1, alpha)  # ram position at phi1 = 0 (X3 = 0 there)
    ram = lambda t: x0 - _ram_x(_crank_phi(t, phi0, w1, e1), L1, alpha)  # noqa: E731
    assert float(res.X3) == pytest.approx(ram(0.0), rel=1e-12, abs=1e-15)
    v, a = _time_derivs(ram, 0.0, h=1e-4 / abs(w1))
    assert float(res.V3) == pytest.approx(v, rel=1e-7)
    assert float(res.a3) == pytest.approx(a, rel=1e-5)
    # block in the slot: distance along d from the crossing point to the crank pin
    blk = lambda t: ((L1 * math.sin(_crank_phi(t, phi0, w1, e1)))  # noqa: E731
                     / math.sin(alpha))
    assert float(res.X32) == pytest.approx(blk(0.0), rel=1e-12, abs=1e-15)
    v, a = _time_derivs(blk, 0.0, h=1e-4 / abs(w1))
    assert float(res.V32) == pytest.approx(v, rel=1e-7)
    assert float(res.a32) == pytest.approx(a, rel=1e-5)
    # stroke and extremes by a dense scan of the construction
    grid = np.linspace(0.0, 2 * math.pi, 20001)
    xs = np.array([x0 - _ram_x(p, L1, alpha) for p in grid])
    assert float(sine.stroke(L1, alpha)) == pytest.approx(np.ptp(xs), rel=1e-7)
    ext = sine.extreme_positions(alpha)
    assert math.remainder(float(ext.phi1_max) - grid[np.argmax(xs)], 2 * math.pi) == \
        pytest.approx(0.0, abs=1e-3)
    assert math.remainder(float(ext.phi1_min) - grid[np.argmin(xs)], 2 * math.pi) == \
        pytest.approx(0.0, abs=1e-3)


def test_working_range_against_direct_statics():
    """Slider statics solved as a linear system: jamming exactly at alpha = rho1 + rho2."""
    f1, f2 = 0.17, 0.08

    def load_over_normal(alpha: float, sigma: float) -> float:
        # block pushes the slider with N along n = (sin a, -cos a) plus friction sigma f1 N d;
        # the guide reacts with Ny (normal) and friction -f2 |Ny| against +x motion; F the load.
        n = np.array([math.sin(alpha), -math.cos(alpha)])
        d = np.array([math.cos(alpha), math.sin(alpha)])
        push = n + sigma * f1 * d
        return push[0] - f2 * abs(push[1])

    lo, hi = sine.working_range(f1, f2)
    grid = np.linspace(1e-3, math.pi - 1e-3, 200001)
    worst = np.minimum(*[np.array([load_over_normal(a, s) for a in grid[::50]])
                         for s in (1.0, -1.0)])
    ok = grid[::50][worst > 0]
    assert ok.min() == pytest.approx(float(lo), abs=2e-3)
    assert ok.max() == pytest.approx(float(hi), abs=2e-3)


# --------------------------------------------------------------------------------------------
# swash plate: independent 3-D construction (rotation matrices, rod length solved by brentq)
# --------------------------------------------------------------------------------------------


def _sw_z(phi: float, R: float, r: float, l: float, alpha: float, a: float, b: float) -> float:
    ca, sa = math.cos(alpha), math.sin(alpha)
    rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    rz = np.array([[math.cos(phi), -math.sin(phi), 0], [math.sin(phi), math.cos(phi), 0],
                   [0, 0, 1]])
    B = np.array([a, b, 0.0]) + rx @ rz @ np.array([0.0, -r, 0.0])
    Axy = np.array([R * math.sin(phi), -R * math.cos(phi)])
    return brentq(lambda z: float(np.sum((np.r_[Axy, z] - B) ** 2) - l * l), B[2], B[2] + l,
                  xtol=1e-15, rtol=1e-15)


SW_REVIEW = [  # R, r, l, alpha, a, b (scheme 1 with both offsets, 4b, 2)
    (0.12, 0.093, 0.31, math.radians(27.0), -0.017, 0.023),
    (0.08, 0.1, 0.17, math.radians(11.0), 0.0, -0.012),
    (0.1, 0.045, 0.4, math.pi / 2, 0.0, 0.03),
]


@pytest.mark.parametrize("p", SW_REVIEW)
def test_swashplate_against_own_construction(p):
    phis = np.array([0.4, 1.9, 2.8, 4.1, 5.95])
    z0 = _sw_z(0.0, *p)
    s_ref = np.array([_sw_z(x, *p) - z0 for x in phis])
    np.testing.assert_allclose(sw.position(phis, *p), s_ref, rtol=1e-10, atol=1e-13)
    h = 1e-4
    d1 = np.array([(_sw_z(x - 2 * h, *p) - 8 * _sw_z(x - h, *p) + 8 * _sw_z(x + h, *p)
                    - _sw_z(x + 2 * h, *p)) / (12 * h) for x in phis])
    np.testing.assert_allclose(sw.first_transfer(phis, *p), d1, rtol=1e-7, atol=1e-11)
    h = 1e-3
    d2 = np.array([(-_sw_z(x - 2 * h, *p) + 16 * _sw_z(x - h, *p) - 30 * _sw_z(x, *p)
                    + 16 * _sw_z(x + h, *p) - _sw_z(x + 2 * h, *p)) / (12 * h * h)
                   for x in phis])
    np.testing.assert_allclose(sw.second_transfer(phis, *p), d2, rtol=1e-5, atol=1e-9)
    grid = np.linspace(0, 2 * math.pi, 4001)
    zs = np.array([_sw_z(x, *p) for x in grid])
    assert float(sw.stroke(*p)) == pytest.approx(np.ptp(zs), rel=1e-6)


# --------------------------------------------------------------------------------------------
# defects found by the review (each test failed before its fix)
# --------------------------------------------------------------------------------------------


def _cli(tmp_path, capsys, example: str, old: str, new: str, cmd=("analyze",)) -> str:
    text = (EXAMPLES / example).read_text()
    assert old in text
    p = tmp_path / "mech.toml"
    p.write_text(text.replace(old, new, 1))
    rc = main([*cmd, str(p), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err and "mech.toml" in err, err
    return err


def test_drive_forces_jamming_with_several_slides_names_the_angles():
    # the two-point guide with rho = 60 deg jams where tan(delta_z) >= 1 / (k tan rho); with
    # u > 1 slides the error used to crash in angle_ranges (a (u, n) array of angles).
    d = sw.scheme_1(0.1, 0.07, 0.25, math.radians(20.0), 0.02, 0.0)
    with pytest.raises(AssemblyError, match="jams") as exc:
        sw.drive_forces(d, 1000.0, u=12, rho_guide=math.radians(80.0), guide_length=0.12,
                        overhang=0.04, n=361)
    # the jam ranges are angles of a slide over one revolution, in [0, 360] deg
    for lo, hi in exc.value.ranges:
        assert 0.0 <= lo <= hi <= 2 * math.pi + 1e-12


def test_cli_swashplate_jamming_load_one_line(tmp_path, capsys):
    err = _cli(tmp_path, capsys, "swashplate_4a.toml", 'rho_guide = "5 deg"',
               'rho_guide = "89 deg"', cmd=("swashplate", "analyze"))
    assert "jams" in err


@pytest.mark.parametrize("example,old,new,words", [
    # a geometry value the scheme constructor rejects: the key and, for a plain alpha, the hint
    ("swashplate_4a.toml", 'alpha = "15 deg"', 'alpha = 15', ["geometry.alpha", "859.4",
                                                              "(0, 90) deg", "radians"]),
    ("swashplate_4a.toml", 'alpha = "15 deg"', 'alpha = "0 deg"', ["geometry.alpha", "(0, 90)"]),
    # the rod cannot reach: said at load time, with the file name
    ("swashplate_4a.toml", 'alpha = "15 deg"', 'alpha = "89.9 deg"', ["geometry", "cannot reach"]),
    ("swashplate_1.toml", 'b = "0 mm"', 'b = "1000 mm"', ["geometry", "cannot reach"]),
    # non-finite numbers: named with their key (they used to lose the file and the key)
    ("swashplate_4a.toml", 'R = "100 mm"', 'R = inf', ["geometry.R", "finite"]),
    ("swashplate_4a.toml", 'l = "200 mm"', 'l = inf', ["geometry.l", "finite"]),
    ("swashplate_1.toml", 'a = "20 mm"', 'a = nan', ["geometry.a", "finite"]),
    ("swashplate_1.toml", 'speed = "50 rpm"', 'speed = inf', ["operation.speed", "finite"]),
    ("swashplate_4a.toml", 'productivity = "600 1/min"', 'productivity = inf',
     ["operation.productivity", "finite"]),
    ("swashplate_4a.toml", 'forces = ["0 kN", "0 kN", "20 kN"', 'forces = [0, 0, nan',
     ["load.forces.2", "finite"]),
    ("swashplate_4a.toml", 'guide_length = "120 mm"', 'guide_length = inf',
     ["load.guide_length", "finite"]),
])
def test_cli_swashplate_file_errors_name_file_and_key(example, old, new, words, tmp_path,
                                                      capsys):
    err = _cli(tmp_path, capsys, example, old, new, cmd=("swashplate", "analyze"))
    for w in words:
        assert w.lower() in err.lower(), (w, err)


@pytest.mark.parametrize("old,new,key", [
    ('L1 = "50 mm"', 'L1 = inf', "crank.L1"),
    ('speed = "120 rpm"', 'speed = inf', "crank.speed"),
    ('eps1 = "0 rad/s^2"', 'eps1 = nan', "crank.eps1"),
    ('lambda2 = 4.0', 'lambda2 = inf', "idle.lambda2"),
    ('lambda_e = 0.5', 'lambda_e = inf', "idle.lambda_e"),
    ('lambda_e = 0.5', 'lambda_e = nan', "idle.lambda_e"),
    ('f_slot = 0.12', 'f_slot = inf', "working.f_slot"),
    ('alpha = "45 deg"', 'alpha = nan', "schedule.3.alpha"),
])
def test_cli_sine_press_non_finite_values_name_file_and_key(old, new, key, tmp_path, capsys):
    # they used to reach the models: 'omega1 = inf is invalid' without file or key, or
    # 'lambda2 = 4 must be > |lambda_e| + 1 = inf', or f_slot = inf blamed on working.alpha
    err = _cli(tmp_path, capsys, "sine_press.toml", old, new)
    assert f"{key}:" in err and "finite" in err, err


def test_branch_array_is_named():
    from linkwork.models.variable_structure import VariableStructureMechanism
    with pytest.raises(ParameterError, match="branch"):
        crank_slider.offset_crank_slider(0.3, 0.05, 4.0, 0.5, branch=np.array([1, -1]))
    with pytest.raises(ParameterError, match="branch"):
        crank_slider.dead_centres(4.0, 0.5, branch=np.array([1, -1]))
    with pytest.raises(ParameterError, match="branch"):
        VariableStructureMechanism(0.05, 4.0, 0.5, 1.0, branch=np.array([1, -1]))
    # a scalar branch still works, as a numpy integer too
    res = crank_slider.offset_crank_slider(0.3, 0.05, 4.0, 0.5, branch=np.int64(-1))
    assert float(res.Y_C) < 0


def test_alpha_for_stroke_shape_mismatch_is_named():
    with pytest.raises(ParameterError, match=r"shapes.*L1.*H"):
        sine.alpha_for_stroke(np.full(2, 0.05), np.full(3, 0.2))
    lo, hi = sine.alpha_for_stroke(np.array([[0.05], [0.04]]), np.array([0.2, 0.1]))
    np.testing.assert_allclose(2 * np.array([[0.05], [0.04]]) / np.sin(lo), [[0.2, 0.1]] * 2)
    np.testing.assert_allclose(lo + hi, np.pi)


@pytest.mark.parametrize("schedule,spr,needle", [
    ([("idle", 1)], 10.5, "samples_per_revolution"),
    ([("idle", 1)], "360", "samples_per_revolution"),
    ([("idle",)], 36, "schedule entry"),
    (["idle"], 36, "schedule entry"),
    ([("working", 1, 1.0, 2)], 36, "schedule entry"),
])
def test_run_malformed_schedule_is_named(schedule, spr, needle):
    from linkwork.models.variable_structure import VariableStructureMechanism
    mech = VariableStructureMechanism(0.05, 4.0, 0.5, 1.0)
    with pytest.raises(ParameterError, match=needle):  # were TypeErrors from Python internals
        mech.run(schedule, 10.0, samples_per_revolution=spr)


def test_swashplate_shape_mismatch_and_sample_count_are_named():
    with pytest.raises(ParameterError, match="shapes"):  # was numpy's raw broadcast ValueError
        sw.position(np.zeros(3), 0.1, np.full(4, 0.07), 0.25, 0.3)
    with pytest.raises(ParameterError, match="shapes"):
        sw.stroke(0.1, np.full(4, 0.07), np.full(3, 0.25), 0.3)
    d = sw.scheme_1(0.1, 0.07, 0.25, 0.35, 0.02, 0.0)
    with pytest.raises(ParameterError, match="n = 0"):  # was an IndexError
        sw.drive_forces(d, 1000.0, n=0)
    with pytest.raises(ParameterError, match="phi"):  # one angle: the cycle integrals are 0/0
        sw.drive_forces(d, 1000.0, phi=[0.3])
    # designs (m, 1) against angles (n,) still broadcast
    s = sw.position(np.linspace(0, 6, 5), 0.1, np.array([[0.07], [0.09]]), 0.25, 0.3)
    assert s.shape == (2, 5)


@pytest.mark.parametrize("argv,words", [
    # a plain number is radians: 8 -> 458 deg; the error named only 'delta_f', a field of the
    # Request the user never typed, without the hint
    (["--delta", "8"], ["delta_f = 458.366 deg", "(0, 90]", "--delta '8'", "radians"]),
    (["--delta-r", "0 deg"], ["delta_r = 0 deg", "--delta-r '0 deg'", "(0, 90]"]),
    (["-R", "-100 mm"], ["R = -0.1", "--rotor-radius '-100 mm'", "> 0"]),
    (["-H", "0 mm"], ["--stroke '0 mm'", "> 0"]),
    (["--stroke-tol", "-1 mm"], ["--stroke-tol '-1 mm'", ">= 0"]),
    (["--phi-f", "400 deg"], ["--phi-f '400 deg'", "(0, 360)"]),
])
def test_cli_synthesize_errors_name_the_option_as_typed(argv, words, tmp_path, capsys):
    base = {"-R": "100 mm", "-H": "60 mm"}
    for k, v in zip(argv[::2], argv[1::2], strict=True):
        base[k] = v
    args = [x for kv in base.items() for x in kv]
    rc = main(["swashplate", "synthesize", *args, "--candidates", "64", "--refine", "0",
               "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1, err
    for w in words:
        assert w in err, (w, err)


@pytest.mark.parametrize("example,old,new,words,cmd", [
    # pint reads the radian as dimensionless: "2 Hz" passed as 2 rad/s (an engineer means
    # 2 rev/s = 12.57 rad/s), "600 rpm" as a productivity of 62.8 /s (meant: 10 /s)
    ("sine_press.toml", 'speed = "120 rpm"', 'speed = "2 Hz"', ["crank.speed", "2 Hz", "rpm"],
     ("analyze",)),
    ("swashplate_1.toml", 'speed = "50 rpm"', 'speed = "0.8 Hz"', ["operation.speed", "Hz"],
     ("swashplate", "analyze")),
    ("swashplate_4a.toml", 'productivity = "600 1/min"', 'productivity = "600 rpm"',
     ["operation.productivity", "angle unit", "1/min"], ("swashplate", "analyze")),
])
def test_cli_angle_unit_traps_are_refused(example, old, new, words, cmd, tmp_path, capsys):
    err = _cli(tmp_path, capsys, example, old, new, cmd=cmd)
    for w in words:
        assert w in err, (w, err)


def test_unit_conversions_keep_their_angle():
    from linkwork.units import to_si
    # independent values: 1 rev = 2 pi rad
    assert to_si("120 rpm", "angular_velocity") == pytest.approx(120 * 2 * math.pi / 60)
    assert to_si("2 rps", "angular_velocity") == pytest.approx(4 * math.pi)
    assert to_si("720 deg/s", "angular_velocity") == pytest.approx(4 * math.pi)
    assert to_si("2 1/s", "angular_velocity") == 2.0  # SI: omega in 1/s is rad/s
    assert to_si("600 1/min", "frequency") == pytest.approx(10.0)
    assert to_si("10 Hz", "frequency") == 10.0
    assert to_si("0.5", "angle") == 0.5
    with pytest.raises(ParameterError, match="ambiguous"):
        to_si("2 Hz", "angular_velocity", "speed")
    with pytest.raises(ParameterError, match="angle unit"):
        to_si("600 rpm", "frequency", "productivity")


@pytest.mark.parametrize("lam2,lame,branch", [(2.9, -1.3, 1), (3.3, 0.9, -1), (2.05, 1.0, -1)])
def test_crank_slider_characteristics_against_a_dense_scan(lam2, lame, branch):
    L1 = 0.037
    grid = np.linspace(0.0, 2 * math.pi, 200001)
    ys = np.array([_slider_y(p, L1, lam2 * L1, lame * L1, branch) for p in grid[::10]])
    g = grid[::10]
    assert float(crank_slider.stroke(L1, lam2, lame)) == pytest.approx(np.ptp(ys), rel=1e-8)
    top, bottom = crank_slider.dead_centres(lam2, lame, branch)
    assert math.remainder(float(top) - g[np.argmax(ys)], 2 * math.pi) == pytest.approx(0, abs=4e-4)
    assert math.remainder(float(bottom) - g[np.argmin(ys)], 2 * math.pi) == pytest.approx(
        0, abs=4e-4)
    mu = np.arcsin(np.abs(lame - np.cos(g)) / lam2)
    assert float(crank_slider.max_pressure_angle(lam2, lame)) == pytest.approx(mu.max(), abs=1e-9)


def test_cli_swashplate_without_speed_shows_no_zero_slide_speeds(tmp_path, capsys):
    text = (EXAMPLES / "swashplate_1.toml").read_text()
    assert 'speed = "50 rpm"' in text
    p = tmp_path / "mech.toml"
    p.write_text(text.replace('speed = "50 rpm"', "", 1))
    assert main(["swashplate", "analyze", str(p), "--out", str(tmp_path / "o"),
                 "--angles", "90"]) == 0
    out = capsys.readouterr().out
    # the slide moves at 90 deg (Pi_v = 23.9 mm/rad): a speed of 0.0000 m/s was printed
    assert "slide v" not in out and "slide speeds omitted" in out
