"""Adversarial review of issues 3 (planar engine), 4 (balancing) and 6 (spatial reactions).

Mechanisms not used by the acceptance tests (an RPR inverted slider-crank with a load on the
guide, a Stephenson III six-bar with a ternary coupler, a pin-in-slot drive with an inclined
ram guide, an inclined offset crank-slider, a four-bar whose bodies' frames are not on their
links), each checked against positions written out here by plain trigonometry and time
derivatives by finite differences; plus the defects the review found, each with a test that
failed before its fix.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import linkwork.planar as pl
from linkwork import balancing as bal
from linkwork.cli import main
from linkwork.errors import ParameterError
from linkwork.planar.model import fourbar

ROOT = Path(__file__).resolve().parents[1]


def run_cli(args, capsys):
    """Exit code, stdout, stderr of the command line."""
    try:
        code = main(args)
    except SystemExit as exc:  # typer's standalone mode
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


# ---------------------------------------------------------------------------------------------
# defects


def test_force_balance_radius_for_an_unknown_link_is_named():
    """A radius keyed by a misspelt link was silently ignored (the default radius was used)."""
    mech = fourbar(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0), omega1=10.0)
    with pytest.raises(ParameterError) as err:
        bal.force_balance(mech, radii={"crnk": 0.05, "rocker": 0.1})
    assert "radii" in str(err.value) and "crnk" in str(err.value)
    assert "crank" in str(err.value)  # the links that do carry counterweights
    # the correctly spelt table is used as given
    fb = bal.force_balance(mech, radii={"crank": 0.05, "rocker": 0.1})
    assert [c.radius for c in fb.counterweights] == [0.05, 0.1]


def test_cli_balance_radius_for_an_unknown_link_one_line_exit_2(tmp_path, capsys):
    text = (ROOT / "examples" / "fourbar_paper001.toml").read_text()
    f = tmp_path / "m.toml"
    f.write_text(text + '\n[balance]\nradii = { crnk = "50 mm", rocker = "100 mm" }\n')
    code, _, err = run_cli(["balance", str(f), "--out", str(tmp_path / "o")], capsys)
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert "radii" in err and "crnk" in err


def toml(doc, prefix=""):
    """A TOML text from nested dicts and lists (tables, arrays of tables, inline values)."""
    def val(v):
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, dict):
            return "{ " + ", ".join(f"{k} = {val(x)}" for k, x in v.items()) + " }"
        if isinstance(v, list | tuple):
            return "[" + ", ".join(val(x) for x in v) + "]"
        return repr(v)

    lines, later = [], []
    for k, v in doc.items():
        if isinstance(v, dict) and k in TABLES:
            later.append(f"\n[{prefix}{k}]\n" + toml(v, f"{prefix}{k}."))
        elif isinstance(v, list) and v and isinstance(v[0], dict):
            later += [f"\n[[{prefix}{k}]]\n" + toml(x, f"{prefix}{k}.") for x in v]
        else:
            lines.append(f"{k} = {val(v)}")
    return "\n".join(lines) + "".join(later) + "\n"


TABLES = {"frame", "driver", "analysis", "spatial", "balance", "joints"}


def link(name, start, end, length, mass, **kw):
    return dict(name=name, start=start, end=end, length=length, mass=mass, **kw)


def joint(name, kind, a, b, **kw):
    return dict(name=name, type=kind, a=a, b=b, **kw)


def slider_crank(guide, driver, analysis, **extra):
    """A crank-slider file: crank O-A 50 mm, rod A-B 200 mm, slider on the frame's guide G."""
    doc = {"type": "planar", "name": "crank-slider",
           "frame": {"points": {"O": [0, 0], "G": guide.pop("at", [0, 0])}},
           "body": [link("crank", "O", "A", "50 mm", "2 kg"),
                    link("rod", "A", "B", "200 mm", "3 kg"),
                    {"name": "slider", "points": {"B": [0, 0]}, "mass": "4 kg",
                     "inertia": "0.01 kg*m^2"}],
           "joint": [joint("O", "revolute", "frame", "crank"),
                     joint("A", "revolute", "crank", "rod"),
                     joint("B", "revolute", "rod", "slider"),
                     joint("G", "prismatic", "frame", "slider", through="G", point="B",
                           **guide)],
           "driver": driver, "analysis": analysis}
    doc.update(extra)
    return toml(doc)


LINEAR_SLIDER_CRANK = slider_crank(
    {}, {"type": "linear", "joint": "G", "v1": "1 m/s"},
    {"start": "160 mm", "stop": "240 mm", "n": 41, "branches": {"A": 1}})


def test_cli_reactions_linear_driver_positions_in_mm_and_force_in_newtons(tmp_path, capsys):
    """With a linear driver the table said 'φ1 = 9.74 deg' for s1 = 170 mm and gave the
    driving force in N·m; the CSV/JSON said phi1 [rad] and Q [N*m]."""
    import csv

    from linkwork.files import load
    from linkwork.planar import inverse_dynamics, kinematics

    f = tmp_path / "lin.toml"
    f.write_text(LINEAR_SLIDER_CRANK)
    out = tmp_path / "o"
    code, text, err = run_cli(["reactions", str(f), "--out", str(out), "--angles", "170,200",
                               "--no-plots"], capsys)
    assert code == 0, err
    assert "s1 = 170 mm" in text and "s1 = 200 mm" in text
    assert "deg" not in text and "N·m" not in text.split("driving")[1].splitlines()[0]
    # the driving force against the planar engine at s1 = 0.17 m (v1 = 1 m/s)
    doc = load(f)
    kin = kinematics(doc.mechanism(), [0.17, 0.2])
    q = inverse_dynamics(kin).Q
    assert f"driving force Q = {q[0]:.4g} N" in text
    with (out / "reactions.csv").open() as fh:
        head = next(csv.reader(fh))
    assert head[0] == "phi1 [m]" and head[-1] == "Q [N]"
    units = json.loads((out / "reactions.json").read_text())["units"]
    assert units["phi1"] == "m" and units["Q"] == "N"
    assert json.loads((out / "reactions_peaks.json").read_text())["units"]["Q"] == "N"


def _linear_with_load(phi_range):
    return LINEAR_SLIDER_CRANK + toml({"load": [
        {"type": "force", "body": "slider", "point": "B", "fx": "-100 N",
         "phi_range": phi_range}]})


@pytest.mark.parametrize("phi_range", [["200 mm", "220 mm"], [0.2, 0.22]])
def test_load_range_of_a_linear_driver_is_a_slide_interval(tmp_path, phi_range):
    """For a linear driver '[[load]] phi_range' had to be an angle ('200 mm' was refused) and
    plain numbers were wrapped modulo 2 pi, so [0.22, 0.2] acted everywhere except between
    0.2 and 0.22 m."""
    from linkwork.files import load

    f = tmp_path / "lin.toml"
    f.write_text(_linear_with_load(phi_range))
    doc = load(f)
    s = doc.positions()
    fx = np.asarray(np.broadcast_to(doc.loads(s)[0].fx, s.shape))
    inside = (s >= 0.2 - 1e-12) & (s <= 0.22 + 1e-12)
    assert inside.sum() == 11  # 160..240 mm in 2 mm steps
    np.testing.assert_array_equal(fx, np.where(inside, -100.0, 0.0))


@pytest.mark.parametrize("phi_range, words", [
    (["220 mm", "200 mm"], ["load.0.phi_range", "220 mm"]),  # reversed: no wrap for slides
    ([0.22, 0.2], ["load.0.phi_range", "0.22", "> start"]),
    (["20 deg", "40 deg"], ["load.0.phi_range", "length"]),  # an angle for a slide
])
def test_bad_load_range_of_a_linear_driver_one_line_exit_2(tmp_path, capsys, phi_range, words):
    f = tmp_path / "lin.toml"
    f.write_text(_linear_with_load(phi_range))
    code, _, err = run_cli(["analyze", str(f), "--out", str(tmp_path / "o")], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    for w in words:
        assert w in err


def test_load_range_of_a_crank_must_be_an_angle(tmp_path, capsys):
    text = (ROOT / "examples" / "sine_press_planar.toml").read_text()
    f = tmp_path / "sp.toml"
    f.write_text(text.replace('phi_range = ["100 deg", "150 deg"]',
                              'phi_range = ["100 mm", "150 mm"]'))
    code, _, err = run_cli(["analyze", str(f), "--out", str(tmp_path / "o")], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "load.0.phi_range" in err and "angle" in err


# ---------------------------------------------------------------------------------------------
# physics spot checks on mechanisms the acceptance tests do not use

def _rot(t):
    return np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])


def _circles(P, rp, Q, rq, branch):
    """Intersection of circles (P, rp), (Q, rq); branch +1 on the left of P -> Q."""
    d = Q - P
    L = np.hypot(*d)
    a = (rp**2 - rq**2 + L**2) / (2 * L)
    ex = d / L
    return P + a * ex + branch * np.sqrt(rp**2 - a**2) * np.array([-ex[1], ex[0]])


def _angle(v):
    return np.arctan2(v[1], v[0])


def rpr_inverted_slider_crank():
    """Crank O2A 0.1 m, block on the crank pin sliding on a guide bar pivoted at O4; a force
    at the guide's tip T and a couple on the guide, both varying over the cycle."""

    O4 = np.array([0.05, -0.25])
    mech = pl.Mechanism(
        pl.Body("frame", {"O2": (0.0, 0.0), "O4": tuple(O4)}),
        (pl.bar("crank", "O2", "A", 0.1, mass=1.0),
         pl.Body("block", {"A": (0.0, 0.0)}, mass=0.5, inertia=1e-4),
         pl.bar("guide", "O4", "T", 0.6, mass=2.0)),
        (pl.Revolute("O2", "frame", "crank"), pl.Revolute("A", "crank", "block"),
         pl.Prismatic("P", "guide", "block", through="O4", point="A"),
         pl.Revolute("O4", "frame", "guide")), pl.Crank("O2"))

    def poses(p):
        A = 0.1 * np.array([np.cos(p), np.sin(p)])
        th = _angle(A - O4)
        return {"crank": (A / 2, p), "block": (A, th),
                "guide": (O4 + 0.3 * np.array([np.cos(th), np.sin(th)]), th)}

    def loads(ph):
        return [pl.PointForce("guide", "T", fx=10 * np.sin(ph), fy=-30.0),
                pl.BodyTorque("guide", mz=np.cos(ph))]
    return mech, poses, loads


def stephenson_sixbar():
    """Stephenson III: four-bar O2-A-B-O4 with a ternary coupler (A, B, C), dyad C-D-O6 on
    its coupler point C (branch -1: D right of C -> O6)."""

    O6, Cl, S3 = np.array([0.5, 0.35]), np.array([0.12, 0.1]), np.array([0.14, 0.03])
    mech = pl.Mechanism(
        pl.Body("frame", {"O2": (0.0, 0.0), "O4": (0.3, 0.0), "O6": tuple(O6)}),
        (pl.bar("crank", "O2", "A", 0.1, mass=1.0),
         pl.Body("coupler", {"A": (0.0, 0.0), "B": (0.3, 0.0), "C": tuple(Cl)}, mass=3.0,
              com=tuple(S3), inertia=0.03),
         pl.bar("rocker", "O4", "B", 0.25, mass=2.0), pl.bar("link5", "C", "D", 0.45, mass=1.5),
         pl.bar("link6", "O6", "D", 0.25, mass=1.2, com=0.05)),
        (pl.Revolute("O2", "frame", "crank"), pl.Revolute("A", "crank", "coupler"),
         pl.Revolute("B", "coupler", "rocker"), pl.Revolute("O4", "frame", "rocker"),
         pl.Revolute("C", "coupler", "link5"), pl.Revolute("D", "link5", "link6"),
         pl.Revolute("O6", "frame", "link6")), pl.Crank("O2"), {"B": 1, "D": -1})

    def poses(p):
        A, O4 = 0.1 * np.array([np.cos(p), np.sin(p)]), np.array([0.3, 0.0])
        B = _circles(A, 0.3, O4, 0.25, 1)
        t3, t4 = _angle(B - A), _angle(B - O4)
        C = A + _rot(t3) @ Cl
        D = _circles(C, 0.45, O6, 0.25, -1)
        t6 = _angle(D - O6)
        return {"crank": (A / 2, p), "coupler": (A + _rot(t3) @ S3, t3),
                "rocker": ((O4 + B) / 2, t4), "link5": ((C + D) / 2, _angle(D - C)),
                "link6": (O6 + 0.05 * np.array([np.cos(t6), np.sin(t6)]), t6)}

    def loads(ph):
        return [pl.PointForce("link6", "D", fx=50 * np.cos(2 * ph), fy=20.0),
                pl.PointForce("coupler", (0.05, 0.05), fx=-5.0, fy=np.sin(ph))]
    return mech, poses, loads


def slot_drive():
    """Crank pin A in the slot of a rocker pivoted at O4 (RS group), rod T-E to a ram on a
    frame guide at 170 deg through (0, 0.4) with the ram's body turned by 0.3 rad; a press
    force on the ram over half the turn."""

    O4, G, gam = np.array([0.0, -0.3]), np.array([0.0, 0.4]), np.radians(170.0)
    u = np.array([np.cos(gam), np.sin(gam)])
    mech = pl.Mechanism(
        pl.Body("frame", {"O2": (0.0, 0.0), "O4": tuple(O4), "G": tuple(G)}),
        (pl.bar("crank", "O2", "A", 0.1, mass=1.0), pl.bar("rocker", "O4", "T", 0.6, mass=3.0),
         pl.bar("rod", "T", "E", 0.35, mass=1.0),
         pl.Body("ram", {"E": (0.0, 0.0)}, mass=4.0, com=(0.02, -0.01), inertia=0.02)),
        (pl.Revolute("O2", "frame", "crank"),
         pl.PinInSlot("S", "rocker", "crank", through="O4", point="A"),
         pl.Revolute("O4", "frame", "rocker"), pl.Revolute("T", "rocker", "rod"),
         pl.Revolute("E", "rod", "ram"),
         pl.Prismatic("G", "frame", "ram", angle=gam, through="G", point="E", rel_angle=0.3)),
        pl.Crank("O2"), {"S": 1, "E": 1})

    def poses(p):
        A = 0.1 * np.array([np.cos(p), np.sin(p)])
        th = _angle(A - O4)
        T = O4 + 0.6 * np.array([np.cos(th), np.sin(th)])
        b = (G - T) @ u
        s = -b + np.sqrt(b * b - ((G - T) @ (G - T) - 0.35**2))  # further along u
        E = G + s * u
        return {"crank": (A / 2, p), "rocker": ((O4 + T) / 2, th),
                "rod": ((T + E) / 2, _angle(E - T)),
                "ram": (E + _rot(0.3) @ np.array([0.02, -0.01]), 0.3)}

    def loads(ph):
        return [pl.PointForce("ram", "com", fx=np.where(np.sin(ph) > 0, -200.0, 0.0))]
    return mech, poses, loads


def _point_path(mech, poses, body, point):
    """World path phi -> position of a body point, from the written-out poses."""
    b = mech.body(body)
    local = np.array(b.point(point) if isinstance(point, str) else point) - np.array(b.com)

    def f(p):
        c, th = poses(p)[body]
        return c + _rot(th) @ local
    return f


def _rates(f, p, h=2e-3):
    """f, df/dphi, d2f/dphi2 by fourth-order central differences (angles unwrapped)."""
    v = [np.asarray(f(p + k * h), dtype=float) for k in (-2, -1, 0, 1, 2)]
    d1 = (v[0] - 8 * v[1] + 8 * v[3] - v[4]) / (12 * h)
    d2 = (-v[0] + 16 * v[1] - 30 * v[2] + 16 * v[3] - v[4]) / (12 * h * h)
    return v[2], d1, d2


@pytest.mark.parametrize("builder", [rpr_inverted_slider_crank, stephenson_sixbar, slot_drive])
def test_power_balance_and_momentum_against_written_out_positions(builder):
    """Q omega1 = dT/dt - P(loads, gravity); F_sh = F_ext + sum m g - dp/dt;
    M_sh,P = M_P(ext, gravity) - dH_P/dt: p, H, T and the powers from positions written out
    here by trigonometry, time derivatives by finite differences; variable omega1, eps1 != 0,
    gravity pointing 200 deg from +x."""
    from linkwork.planar import BodyTorque, inverse_dynamics, kinematics

    mech, poses, loads = builder()
    phi = np.radians(np.arange(3.0, 360.0, 15.0))
    w, e = 6.0 + np.cos(phi), -4.0 + 3 * np.sin(2 * phi)
    g = 9.81 * np.array([np.cos(np.radians(200)), np.sin(np.radians(200))])
    P = np.array([0.1, 0.2])
    kin = kinematics(mech, phi, w, e)
    lds = loads(phi)
    dyn = inverse_dynamics(kin, gravity=tuple(g), loads=lds, about=tuple(P))
    names = [b.name for b in mech.bodies]
    m = np.array([mech.body(n).mass for n in names])
    J = np.array([mech.body(n).inertia for n in names])
    for k, p in enumerate(phi):
        def q(x):
            d = poses(x)
            return np.array([[*d[n][0], d[n][1]] for n in names])
        q0, d1, d2 = _rates(q, p)
        v, a = d1 * w[k], d2 * w[k] ** 2 + d1 * e[k]
        # engine positions and accelerations of the centres
        for i, n in enumerate(names):
            c = kin.point(n, "com")
            assert np.hypot(c.x[k] - q0[i, 0], c.y[k] - q0[i, 1]) < 1e-12
            assert np.hypot(c.ax[k] - a[i, 0], c.ay[k] - a[i, 1]) < 1e-6 * (1 + abs(a).max())
        # power of the loads and gravity, resultant and moment about P
        power = float(np.sum(m * (v[:, :2] @ g)))
        F = m.sum() * g
        MP = float(np.sum(m * ((q0[:, 0] - P[0]) * g[1] - (q0[:, 1] - P[1]) * g[0])))
        for ld in lds:
            if isinstance(ld, BodyTorque):
                mz = float(np.broadcast_to(ld.mz, phi.shape)[k])
                power += mz * v[names.index(ld.body), 2]
                MP += mz
                continue
            f = np.array([np.broadcast_to(ld.fx, phi.shape)[k],
                          np.broadcast_to(ld.fy, phi.shape)[k]], dtype=float)
            r, dr, _ = _rates(_point_path(mech, poses, ld.body, ld.point), p)
            power += float(f @ dr) * w[k]
            F = F + f
            MP += (r[0] - P[0]) * f[1] - (r[1] - P[1]) * f[0]
        # dT/dt = sum m v.a + J omega eps
        dT = float(np.sum(m * np.sum(v[:, :2] * a[:, :2], 1)) + np.sum(J * v[:, 2] * a[:, 2]))
        scale = abs(dT) + abs(power) + 1.0
        assert abs(dyn.Q[k] * w[k] - (dT - power)) < 1e-6 * scale
        dp = (m[:, None] * a[:, :2]).sum(0)
        Fsh = F - dp
        assert np.hypot(dyn.shaking_fx[k] - Fsh[0], dyn.shaking_fy[k] - Fsh[1]) < (
            1e-6 * (1 + np.abs(dp).max() + np.abs(F).max()))
        dH = float(np.sum(m * ((q0[:, 0] - P[0]) * a[:, 1] - (q0[:, 1] - P[1]) * a[:, 0]))
                   + np.sum(J * a[:, 2]))
        assert abs(dyn.shaking_m[k] - (MP - dH)) < 1e-6 * (1 + abs(MP) + abs(dH))


def test_inclined_offset_crank_slider_rotating_balance_leaves_only_the_guide_force():
    """Crank-slider with a guide at 35 deg and 30 mm offset, crank centre off its line: after
    crank_slider_balance(k) only the reciprocating mass m3 + m2 s2/l2 (slider acceleration a_B
    from its position written out here) and the over-balance k of it rotating with the crank
    remain: across the guide -k r w^2 m_rec sin(phi - gamma) (0 for k = 0, to 1e-9 of the
    unbalanced force)."""
    from linkwork.planar import inverse_dynamics, kinematics
    from linkwork.planar.model import crank_slider

    r, l, ecc, gam, w = 0.05, 0.2, 0.03, np.radians(35.0), 30.0
    m = crank_slider(r, l, ecc, guide_angle=gam, masses=(2.0, 3.0, 4.0),
                     coms=((0.02, 0.01), 0.08), omega1=w)
    u, nrm = np.array([np.cos(gam), np.sin(gam)]), np.array([-np.sin(gam), np.cos(gam)])
    phi = bal.cycle(72)
    F0 = inverse_dynamics(kinematics(m, phi)).shaking_fx
    m_rec = 4.0 + 3.0 * 0.08 / l

    def slide(p):  # slider position along the guide, B = ecc n + s u, |B - A| = l
        A = r * np.array([np.cos(p), np.sin(p)])
        b = (ecc * nrm - A) @ u
        return -b + np.sqrt(b * b - ((ecc * nrm - A) @ (ecc * nrm - A) - l * l))

    aB = np.array([_rates(slide, p)[2] * w**2 for p in phi])
    for k in (0.0, 0.5, 1.0):
        d = inverse_dynamics(kinematics(bal.crank_slider_balance(m, k, radius=0.04), phi))
        F = np.stack([d.shaking_fx, d.shaking_fy], -1)
        # the counterweight's extra first moment -k l1 m_rec e^(i phi) adds the rotating force
        # -k r w^2 m_rec e^(i phi): across the guide it is all there is
        across_expected = -k * r * w**2 * m_rec * np.sin(phi - gam)
        assert np.max(np.abs(F @ nrm - across_expected)) <= 1e-9 * np.max(np.abs(F0))
        along_expected = -m_rec * aB - k * r * w**2 * m_rec * np.cos(phi - gam)
        assert np.max(np.abs(F @ u - along_expected)) <= 1e-5 * np.max(np.abs(F0))


def test_force_balance_of_a_fourbar_whose_body_frames_are_off_the_links():
    """Bodies given by arbitrary local points (origins off the hinges, x axes not along the
    links), frame not along x: full force balance, the shaking force of the balanced
    mechanism <= 1e-9 of the unbalanced one under a varying crank speed with eps1 != 0."""
    from linkwork.planar import Body, Crank, Mechanism, Revolute, inverse_dynamics, kinematics

    m = Mechanism(
        Body("ground", {"P": (0.1, 0.2), "Q": (0.35, 0.05)}),
        (Body("crank", {"P": (0.01, 0.02), "A": (0.06, 0.1)}, mass=1.2, com=(0.0, 0.05),
              inertia=0.002),
         Body("coupler", {"A": (0.0, 0.0), "B": (-0.05, 0.3)}, mass=2.5, com=(0.03, 0.12),
              inertia=0.02),
         Body("rocker", {"B": (0.1, -0.2), "Q": (0.0, 0.0)}, mass=1.7, com=(0.07, -0.05),
              inertia=0.01)),
        (Revolute("P", "ground", "crank"), Revolute("A", "crank", "coupler"),
         Revolute("B", "rocker", "coupler"), Revolute("Q", "rocker", "ground")),
        Crank("P", omega1=12.0))
    fb = bal.force_balance(m)
    assert fb.full and fb.reason == ""
    phi = bal.cycle(360)
    w, e = 12 * (1 + 0.3 * np.cos(phi)), 5.0 * np.sin(phi)
    before = inverse_dynamics(kinematics(m, phi, w, e))
    after = inverse_dynamics(kinematics(fb.mechanism, phi, w, e))
    f0 = np.hypot(before.shaking_fx, before.shaking_fy).max()
    assert f0 > 10.0
    assert np.hypot(after.shaking_fx, after.shaking_fy).max() <= 1e-9 * f0


@pytest.mark.parametrize("case", ["slider", "stephenson"])
def test_spatial_inplane_reactions_equal_planar_with_deviations(case):
    """Deviations (tilts, axial offsets), out-of-plane loads, centres of mass and joints at
    different heights, a prismatic joint in space: the in-plane reaction components and Q
    equal the planar engine's inverse dynamics; both formulations agree; each body's z force
    balance holds with the out-of-plane load; the deviations do produce out-of-plane parts."""
    from linkwork.planar import PointForce, inverse_dynamics, kinematics
    from linkwork.planar.model import crank_slider
    from linkwork.redundancy import Deviation, OutOfPlaneLoad, spatial_reactions

    if case == "slider":
        mech = crank_slider(0.05, 0.2, 0.03, guide_angle=np.radians(35.0),
                            masses=(2.0, 3.0, 4.0), coms=((0.02, 0.01), 0.08), omega1=30.0)
        joints = {"G": {"kind": "prismatic", "e": 0.06, "z": 0.005},
                  "A": {"e": 0.02, "z": 0.01}}
        devs = [Deviation("B", "rod", tx=3e-4), Deviation("G", "frame", dz=1e-5, tz=2e-4)]
        loads = [PointForce("slider", "B", fx=-500.0)]
        op = [OutOfPlaneLoad("slider", fz=20.0, mx=0.5)]
    else:
        mech, _, lfun = stephenson_sixbar()
        joints = {"D": {"e": 0.04, "z": -0.01}, "O6": {"e": 0.05, "z": 0.02}}
        devs = [Deviation("O6", "frame", tx=2e-4, ty=-1e-4),
                Deviation("C", "link5", dz=2e-5)]
        loads = lfun(np.radians(np.arange(0.0, 360.0, 10.0)))
        op = [OutOfPlaneLoad("link5", fz=-7.0, my=0.3)]
    phi = np.radians(np.arange(0.0, 360.0, 10.0))
    w, e = 8.0 + np.sin(phi), 2.0
    g = (3.0, -9.0)
    kw = dict(omega1=w, eps1=e, gravity=g, loads=loads, joints=joints,
              default={"e": 0.03, "k_bearing": 5e7}, heights={mech.bodies[1].name: 0.015},
              out_of_plane=op, deviations=devs)
    res = spatial_reactions(mech, phi, **kw)
    dis = spatial_reactions(mech, phi, method="displacement", **kw)
    dyn = inverse_dynamics(kinematics(mech, phi, w, e), gravity=g, loads=loads)
    scale = np.abs(dyn.fx).max()
    for k, name in enumerate(dyn.joints):
        j = res.joints.index(name)
        assert np.max(np.abs(res.fx[j] - dyn.fx[k])) <= 1e-9 * scale
        assert np.max(np.abs(res.fy[j] - dyn.fy[k])) <= 1e-9 * scale
    assert np.max(np.abs(res.Q - dyn.Q)) <= 1e-9 * np.abs(dyn.Q).max()
    for c in ("fx", "fy", "fz", "mx", "my", "mz"):
        a, b = getattr(res, c), getattr(dis, c)
        assert np.max(np.abs(a - b)) <= 1e-9 * max(np.abs(a).max(), 1e-300) + 1e-9
    # z equilibrium of every moving body: sum of joint fz on it + its out-of-plane load = 0
    fz_ext = {o.body: o.fz for o in op}
    for b in mech.bodies:
        total = np.zeros(phi.size) + fz_ext.get(b.name, 0.0)
        for j in mech.joints:
            i = res.joints.index(j.name)
            total += res.fz[i] * ((j.b == b.name) - (j.a == b.name))
        assert np.max(np.abs(total)) <= 1e-9 * (1.0 + np.abs(res.fz).max())
    assert np.abs(res.bending()).max() > 1e-3  # the deviations and heights do matter


def test_assembly_error_names_the_group_that_cannot_close():
    """A six-bar whose second dyad cannot close over part of the cycle: the error listed only
    the driver ranges, not which of the two dyads fails (the user cannot tell which link to
    lengthen)."""
    from linkwork.errors import AssemblyError

    mech, _, _ = stephenson_sixbar()
    short = tuple(pl.bar("link5", "C", "D", 0.3, mass=1.5) if b.name == "link5" else b
                  for b in mech.bodies)  # |C O6| reaches 0.635 m > 0.3 + 0.25
    broken = pl.Mechanism(mech.frame, short, mech.joints, mech.driver, mech.branches)
    with pytest.raises(AssemblyError) as err:
        pl.kinematics(broken, np.radians(np.arange(0.0, 360.0, 10.0)))
    msg = str(err.value)
    assert "RRR(link5, link6)" in msg and "C, D, O6" in msg
    assert "coupler, rocker" not in msg  # the four-bar loop itself closes everywhere
    # NaN mode: the first dyad's bodies are assembled where only the second fails
    kin = pl.kinematics(broken, np.radians(np.arange(0.0, 360.0, 10.0)), on_fail="nan")
    assert (~kin.assembled).any() and kin.assembled.any()


SPATIAL_FOURBAR = (ROOT / "examples" / "loom_fourbar_spatial.toml").read_text()


@pytest.mark.parametrize("old, new, key", [
    ('tx = "0.2 mrad"', "tx = 30", "spatial.deviation.0.tx"),        # 30 rad, meant 30 urad?
    ('ty = "-0.1 mrad"', 'ty = "-10 deg"', "spatial.deviation.1.ty"),
    ('limit = "0.3 mrad"', 'limit = 0.3', "spatial.tolerance.0.limit"),  # 0.3 rad
])
def test_tilt_deviations_beyond_first_order_theory_are_named(tmp_path, capsys, old, new, key):
    """Tilts are small rotations in a first-order theory; a plain number is radians, so
    'tx = 30' (30 rad) ran silently and gave reactions 1e5 times those of 0.3 mrad."""
    f = tmp_path / "s.toml"
    assert old in SPATIAL_FOURBAR
    f.write_text(SPATIAL_FOURBAR.replace(old, new, 1))
    code, _, err = run_cli(["reactions", str(f), "--out", str(tmp_path / "o"), "--no-plots",
                            "--tolerance-study", "2"], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert key in err and "0.1 rad" in err


def test_tilt_deviations_beyond_first_order_theory_are_named_in_the_api():
    from linkwork.redundancy import Deviation, Tolerance, spatial_reactions

    mech = fourbar(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0), omega1=10.0)
    with pytest.raises(ParameterError, match="tx"):
        spatial_reactions(mech, [0.0, 1.0], deviations=[Deviation("O4", "frame", tx=0.5)])
    with pytest.raises(ParameterError, match="ty"):
        Tolerance("O4", "a", "ty", 0.05, "uniform", mean=0.08)
    # small ones are fine
    spatial_reactions(mech, [0.0, 1.0], deviations=[Deviation("O4", "frame", tx=0.01)])


@pytest.mark.parametrize("kw, words", [
    (dict(start="O", end="O"), ["crank.end", "O", "start"]),
    (dict(start="O", end="A", points={"A": (0.2, 0.0)}), ["crank.points.A", "length"]),
])
def test_bar_with_inconsistent_end_points_is_named(kw, words):
    """bar() silently overwrote: start == end kept one point at (length, 0) (the pivot moved to
    the far end), and a 'points' entry named like an end replaced it (length 0.1 m, A at 0.2)."""
    with pytest.raises(ParameterError) as err:
        pl.bar("crank", length=0.1, **kw)
    for w in words:
        assert w in str(err.value)


def test_file_straight_link_with_a_point_redefining_its_end_one_line_exit_2(tmp_path, capsys):
    text = (ROOT / "examples" / "fourbar_paper001.toml").read_text()
    old = 'name = "coupler"\n'
    assert old in text
    f = tmp_path / "m.toml"
    f.write_text(text.replace(old, old + 'points = { B = ["250 mm", 0] }\n', 1))
    code, _, err = run_cli(["analyze", str(f), "--out", str(tmp_path / "o")], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "coupler.points.B" in err


def test_comparison_of_a_mechanism_without_shaking_moment_reports_no_round_off():
    """Only the crank has mass (an eccentric on a shaft driving massless links): the shaking
    moment about O is zero at constant speed, yet the comparison reported R2 = 29.4 % and
    'balancing raises: shaking moment peak static 4.7e-17 vs unbalanced 2.8e-17 (+69.4 %)'."""
    mech = fourbar(0.1, 0.3, 0.2, 0.3, masses=(1.0, 0.0, 0.0), omega1=10.0)
    comp = bal.compare_balancing(mech)
    # hand: the crank's centre turns about O at 0.05 m: inertia force m r w^2 = 5 N through O
    assert comp.summary()["shaking force peak [N]"]["unbalanced"] == pytest.approx(5.0)
    assert np.max(np.abs(comp.M)) < 1e-12 and np.max(np.abs(comp.dM1)) < 1e-12
    assert comp.R2 == 0.0 and comp.R3 == 0.0
    assert not [m for m in comp.increases() if "moment" in m or "torque" in m]


def _rocking_crank_file(tmp_path):
    """Paper 001's four-bar with a 250 mm crank (non-Grashof: the crank only rocks), analysed
    over 20..128 deg where it assembles."""
    text = (ROOT / "examples" / "fourbar_paper001.toml").read_text()
    for old, new in (('length = "100 mm"', 'length = "250 mm"'),
                     ('start = "0 deg"', 'start = "20 deg"'),
                     ('stop = "360 deg"', 'stop = "128 deg"')):
        assert old in text
        text = text.replace(old, new, 1)
    f = tmp_path / "rock.toml"
    f.write_text(text)
    return f


@pytest.mark.parametrize("command, words", [
    (["analyze"], ["--angles", "0, 30"]),             # the default table angles
    (["reactions", "--no-plots"], ["--angles", "0, 90"]),
    (["balance"], ["full turn", "[analysis]"]),
])
def test_partial_cycle_mechanism_errors_name_what_to_change(tmp_path, capsys, command, words):
    """The file's range assembles, but the table's default angles (analyze, reactions) or the
    full turn balancing needs do not: the errors only said 'cannot be assembled at 4 of 12
    driver positions', naming neither --angles nor the full turn."""
    f = _rocking_crank_file(tmp_path)
    code, _, err = run_cli([command[0], str(f), "--out", str(tmp_path / "o"), *command[1:]],
                           capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    for w in words:
        assert w in err
    # within the range the table works
    if command[0] != "balance":
        code, _, err = run_cli([command[0], str(f), "--out", str(tmp_path / "o"),
                                *command[1:], "--angles", "30,60,90"], capsys)
        assert code == 0, err
