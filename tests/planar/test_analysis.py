"""Structure analysis, per-position driver speed, dead centres, transmission angles, plots."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from _mechanisms import m_rpr, m_triad

from linkwork.errors import ParameterError
from linkwork.models import fourbar as fb
from linkwork.planar import (
    analyse,
    crank_slider_mechanism,
    dead_centres,
    fourbar_mechanism,
    inverse_dynamics,
    kinematics,
    kinetic_energy,
    mobility,
    transmission_angles,
)
from linkwork.planar import crank_slider_mechanism as engine_crank_slider
from linkwork.planar import fourbar_mechanism as engine_fourbar


def test_structure_classes_orders():
    s = fourbar_mechanism(0.1, 0.3, 0.2, 0.3).structure
    assert (s.n_bodies, s.n_lower, s.n_higher, s.mobility) == (3, 4, 0, 1)
    assert [(g.kind, g.cls, g.order) for g in s.groups] == [("driver", 1, 1), ("RRR", 2, 2)]
    assert s.groups[1].joints == ("A", "B", "O4") and s.groups[1].key == "B"
    mech, _, _ = m_triad()
    g = mech.structure.groups[-1]
    assert (g.kind, g.cls, g.order) == ("newton", 3, 3)
    assert set(g.bodies) == {"l1", "l2", "l3", "tern"}
    assert mobility(mech) == 1
    assert mech.structure.formula() == "I(crank) -> III newton(l1, l2, l3, tern)"
    mech, _, _ = m_rpr()
    assert mech.structure.groups[-1].kind == "RPR"


def test_per_position_driver_speed():
    """omega1, eps1 given per position = the same positions analysed one by one."""
    m = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1, 3, 2))
    phi = np.linspace(0, 2 * np.pi, 9)
    w = 5 + np.sin(phi)
    e = np.cos(phi) * 3
    k = kinematics(m, phi, omega1=w, eps1=e)
    d = inverse_dynamics(k)
    for i in range(phi.size):
        ki = kinematics(m, phi[i:i + 1], omega1=w[i], eps1=e[i])
        np.testing.assert_allclose(k.eps[:, i], ki.eps[:, 0], rtol=1e-13, atol=1e-13)
        np.testing.assert_allclose(d.Q[i], inverse_dynamics(ki).Q[0], rtol=1e-12)


def test_fourbar_dead_centres_are_crank_coupler_collinear():
    a, b, c, d = 0.1, 0.3, 0.2, 0.3
    phi = np.linspace(0, 2 * np.pi, 7201)
    dcs = dead_centres(kinematics(fourbar_mechanism(a, b, c, d), phi))
    assert [x.body for x in dcs] == ["rocker", "rocker"]
    # independent: |A - O4| = b + a (extended) and b - a (folded) -> law of cosines on O2 O4 B
    found = sorted(x.phi1 for x in dcs)
    refs = []
    for L in (b + a, b - a):
        # B at distance c from O4 and L from O2, on the branch +1 side (y > 0)
        xb = (L**2 - c**2 + d**2) / (2 * d)
        yb = np.sqrt(L**2 - xb**2)
        ang = np.arctan2(yb, xb)
        refs.append(ang if L == b + a else np.mod(ang + np.pi, 2 * np.pi))
    np.testing.assert_allclose(found, sorted(refs), atol=1e-6)


def test_crank_slider_dead_centres_and_pressure_angle():
    r, l, e = 0.1, 0.3, 0.03
    phi = np.linspace(0, 2 * np.pi, 3601)
    k = kinematics(crank_slider_mechanism(r, l, e), phi)
    dcs = dead_centres(k)
    np.testing.assert_allclose([x.phi1 for x in dcs],
                               [np.arcsin(e / (l + r)), np.pi + np.arcsin(e / (l - r))],
                               atol=1e-7)
    mu, delta = transmission_angles(k)["B"]
    # independent: the rod's angle to the guide, sin(delta) = |e - r sin phi| / l
    np.testing.assert_allclose(np.sin(delta), np.abs(e - r * np.sin(phi)) / l, atol=1e-12)
    np.testing.assert_allclose(mu + delta, np.pi / 2)


def test_fourbar_transmission_angle_cosine_law():
    a, b, c, d = 0.1, 0.3, 0.2, 0.3
    phi = np.linspace(0, 2 * np.pi, 361)
    mu, _ = transmission_angles(kinematics(fourbar_mechanism(a, b, c, d), phi))["B"]
    f2 = a**2 + d**2 - 2 * a * d * np.cos(phi)  # |A - O4|^2
    cos_mu = (b**2 + c**2 - f2) / (2 * b * c)
    np.testing.assert_allclose(mu, np.arcsin(np.abs(np.sin(np.arccos(cos_mu)))), atol=1e-9)
    # extremes (Norton): at phi = 0 and pi
    assert np.degrees(mu.min()) == pytest.approx(np.degrees(np.arccos(
        (b**2 + c**2 - (d - a) ** 2) / (2 * b * c))), abs=1e-6)


def test_plots_return_what_they_drew(tmp_path):
    from linkwork.plot import planar as pp
    from linkwork.plot import pyplot, save

    m = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1, 3, 2))
    k = kinematics(m, np.linspace(0, 2 * np.pi, 73))
    d = inverse_dynamics(k)
    out = pp.plot_skeleton(k, [0, 10], paths=[("coupler", "B")])
    assert len(out["lines"]) == 6 and len(out["paths"]) == 1
    np.testing.assert_allclose(out["paths"][0].get_xdata(), k.point("coupler", "B").x * 1e3)
    r = pp.plot_driving_torque(d)
    np.testing.assert_allclose(r["line"].get_ydata(), d.Q)
    r = pp.plot_reactions(d, ["O2", "B"])
    np.testing.assert_allclose(r["lines"][1].get_ydata(), d.reaction_magnitude("B"))
    r = pp.plot_shaking(d)
    np.testing.assert_allclose(r["lines"][2].get_ydata(), d.shaking_m)
    assert save(r["axes"][0].figure, tmp_path / "s.png").stat().st_size > 1000
    pyplot().close("all")


def test_result_exports(tmp_path):
    k = kinematics(fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1, 3, 2)), np.linspace(0, 1, 5))
    d = inverse_dynamics(k)
    data = d.to_dict()
    assert data["units"]["Q"] == "N*m" and len(data["columns"]["Q"]) == 5
    assert k.to_csv(tmp_path / "k.csv").read_text().startswith("phi1 [rad]")


def test_newton_group_long_arrays_match_continuation():
    """Batched Newton (n > 100) = the one-by-one continuation; closure holds."""
    mech, phi, _ = m_triad()
    long = np.linspace(phi[0], phi[-1], 301)
    k_long = kinematics(mech, long)
    k_seq = kinematics(mech, long[:100])
    np.testing.assert_allclose(k_long.theta[:, :100], k_seq.theta, atol=1e-10)
    np.testing.assert_allclose(k_long.eps[:, :100], k_seq.eps, rtol=1e-8, atol=1e-8)
    P = k_long.point("l3", "P3")
    Q = k_long.point("tern", "P3")
    np.testing.assert_allclose(P.x, Q.x, atol=1e-12)
    np.testing.assert_allclose(P.vy, Q.vy, atol=1e-10)


def test_plots_of_large_forces_are_in_kN():
    """The knuckle press's bearings carry up to 299 kN: its reaction plot read '3.0' under a
    '1e5' offset; now kN. Its driving torque (1.2 kN m peak) and weight-dominated shaking
    force (1.7 kN) stay in N m and N: the prefix changes only from 10 units on."""
    from linkwork import files
    from linkwork.planar import inverse_dynamics, kinematics
    from linkwork.plot import planar as pp
    from linkwork.plot import pyplot

    doc = files.load(Path(__file__).resolve().parents[2] / "examples" / "loom_sixbar.toml")
    kin = kinematics(doc.mechanism(), doc.positions())
    d = inverse_dynamics(kin, gravity=doc.analysis.gravity, loads=doc.loads(kin.phi1))
    r = pp.plot_reactions(d, ["R", "O"])
    assert r["ax"].get_ylabel() == "|R| [kN]"
    np.testing.assert_allclose(r["lines"][0].get_ydata() * 1e3, d.reaction_magnitude("R"))
    assert 290 < r["lines"][0].get_ydata().max() < 300
    t = pp.plot_driving_torque(d)
    assert t["ax"].get_ylabel() == "driving torque Q [N·m]"
    np.testing.assert_allclose(t["line"].get_ydata(), d.Q)
    s = pp.plot_shaking(d)
    assert s["axes"][0].get_ylabel() == "shaking force [N]"
    pyplot().close("all")


def test_result_helpers_name_a_wrong_argument():
    """AttributeError ('str' object has no attribute 'mechanism' / 'bodies') before."""
    for f in (transmission_angles, dead_centres, kinetic_energy):
        with pytest.raises(ParameterError, match=r"^kin = k is invalid: must be the Kinematics"):
            f("k")
    with pytest.raises(ParameterError, match=r"^mech = m is invalid: must be a Mechanism"):
        analyse("m")  # type: ignore[arg-type]


@pytest.mark.parametrize("branch", [1, -1])
def test_engine_dead_centres_are_exact(branch):
    """The engine's dead centres were linearly interpolated between samples (6e-6 rad off at
    1 deg sampling); they must agree with the closed forms' limit positions."""
    from linkwork.models import crank_slider as cs
    from linkwork.planar import dead_centres
    lim = fb.limit_positions(0.1, 0.3, 0.2, 0.3, branch)
    kin = kinematics(engine_fourbar(0.1, 0.3, 0.2, 0.3, branch=branch),
                     np.linspace(0, 2 * np.pi, 361))
    got = sorted(d.phi1 for d in dead_centres(kin))
    want = sorted(float(np.mod(x, 2 * np.pi)) for x in (lim.phi1_rocker_extended,
                                                        lim.phi1_rocker_folded))
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-10)
    # crank-slider with the guide along +y at x = e (paper 000's idle mode)
    mech = engine_crank_slider(0.05, 0.2, -0.025, guide_angle=math.radians(90), branch=branch)
    kin = kinematics(mech, np.linspace(0, 2 * np.pi, 361))
    dc = cs.dead_centres(4.0, 0.5, branch)
    got = {d.kind: d.phi1 for d in dead_centres(kin)}
    np.testing.assert_allclose([got["max"], got["min"]],
                               [float(dc.phi1_top), float(dc.phi1_bottom)], rtol=0, atol=1e-10)


@pytest.mark.parametrize("branch", [1, -1])
def test_engine_transmission_angle_full_precision(branch):
    """mu from the law of cosines (closed form) and the engine's mu, delta agree to 1e-14 over
    the cycle; the engine's arccos lost half the digits near mu = 90 deg (1.5e-8 rad)."""
    phi = np.linspace(0, 2 * np.pi, 37)
    kin = kinematics(engine_fourbar(0.1, 0.3, 0.2, 0.3, branch=branch), phi)
    from linkwork.planar import transmission_angles
    mu, delta = transmission_angles(kin)["B"]
    # independent: angle at B between B->A and B->O4, from the engine's own points
    A = kin.point("coupler", "A")
    B = kin.point("coupler", "B")
    ux, uy = A.x - B.x, A.y - B.y
    vx, vy = 0.3 - B.x, -B.y
    ang = np.arctan2(np.abs(ux * vy - uy * vx), ux * vx + uy * vy)
    ref = np.minimum(ang, np.pi - ang)
    np.testing.assert_allclose(mu, ref, rtol=0, atol=1e-14)
    np.testing.assert_allclose(delta, np.pi / 2 - ref, rtol=0, atol=1e-14)
