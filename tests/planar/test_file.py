"""The ``planar`` TOML file and ``linkwork analyze`` on the planar examples."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
from _cli_files import LINEAR_SLIDER_CRANK, run_cli, toml
from _fourbar_newton_euler import (
    ABOUT,
    COM,
    DESIGNS,
    F_COUPLER,
    GRAV,
    INERTIA,
    LOADS,
    M_EXT,
    MASS,
    P_COUPLER,
    _shaking_ref,
    check_reactions,
    close,
    fourbar_reference,
)

from linkwork import files
from linkwork.cli import main
from linkwork.errors import FileFormatError
from linkwork.planar import fourbar_mechanism, inverse_dynamics, kinematics

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_paper001_file_equals_builder():
    """The example file describes the paper-001 four-bar: same motion and torque as
    fourbar_mechanism()."""
    doc = files.load(EXAMPLES / "fourbar_paper001.toml")
    mech = doc.mechanism()
    phi = doc.positions()
    assert phi.shape == (361,) and phi[-1] == pytest.approx(2 * np.pi)
    k1 = kinematics(mech, phi)
    ref = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0),
                  inertias=(0.000833, 0.0225, 0.00567), omega1=10.0)
    k2 = kinematics(ref, phi)
    np.testing.assert_allclose(k1.omega, k2.omega, atol=1e-12)
    np.testing.assert_allclose(inverse_dynamics(k1).Q, inverse_dynamics(k2).Q, atol=1e-10)
    assert k1.omega1[0] == 10.0


def test_units_and_load_window(tmp_path):
    text = (EXAMPLES / "sine_press_planar.toml").read_text()
    doc = files.load(EXAMPLES / "sine_press_planar.toml")
    assert doc.driver.omega1 == pytest.approx(4 * np.pi)  # 120 rpm
    phi = np.radians([90.0, 100.0, 120.0, 150.0, 151.0])
    (load,) = doc.loads(phi)
    np.testing.assert_allclose(load.fx, [0.0, 8000.0, 8000.0, 8000.0, 0.0])
    assert "8 kN" in text


def test_unknown_key_and_bad_structure(tmp_path):
    src = (EXAMPLES / "fourbar_paper001.toml").read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(src.replace('mass = "1 kg"', 'mass = "1 kg"\ncolour = "red"'))
    with pytest.raises(FileFormatError, match=r"body\.0\.colour: unknown key"):
        files.load(bad)
    bad.write_text(src.replace('length = "100 mm"', 'length = "100 s"'))
    with pytest.raises(FileFormatError, match="length"):
        files.load(bad)
    # drop the rocker's frame joint: under-driven
    cut = src.replace('[[joint]]\nname = "C"\ntype = "revolute"\na = "frame"\nb = "rocker"\n', "")
    assert cut != src
    bad.write_text(cut)
    with pytest.raises(FileFormatError, match="under-driven"):
        files.load(bad)


@pytest.mark.parametrize("name", ["fourbar_paper001.toml", "loom_sixbar.toml",
                                  "sine_press_planar.toml"])
def test_cli_analyze_examples(name, tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "250")  # wide enough for every column header
    rc = main(["analyze", str(EXAMPLES / name), "--out", str(tmp_path), "--angles", "0,90,200"])
    out = capsys.readouterr().out
    assert rc == 0, out
    assert "mobility W = 1" in out and "Q [N" in out and "|R" in out
    with (tmp_path / "planar_dynamics.csv").open() as fh:
        rows = list(csv.reader(fh))
    header = rows[0]
    assert header[0] == "phi1 [rad]" and any(h.startswith("Q [") for h in header)
    data = json.loads((tmp_path / "planar.json").read_text())
    assert data["mobility"] == 1 and data["reaction_sign"].startswith("force exerted by")
    for png in ("planar_skeleton.png", "planar_driving_torque.png", "planar_reactions.png",
                "planar_shaking.png"):
        assert (tmp_path / png).stat().st_size > 1000
    # the CSV's torque column is the engine's
    doc = files.load(EXAMPLES / name)
    k = kinematics(doc.mechanism(), doc.positions())
    d = inverse_dynamics(k, gravity=doc.analysis.gravity, loads=doc.loads(doc.positions()),
                         about=doc.analysis.about)
    qcol = header.index(next(h for h in header if h.startswith("Q [")))
    np.testing.assert_allclose([float(r[qcol]) for r in rows[1:]], d.Q, rtol=1e-12, atol=1e-9)


def test_cli_cannot_assemble_one_line(tmp_path, capsys):
    src = (EXAMPLES / "fourbar_paper001.toml").read_text()
    f = tmp_path / "nb.toml"
    f.write_text(src.replace('length = "100 mm"', 'length = "250 mm"'))
    assert main(["analyze", str(f), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "cannot assemble at phi1 in [" in err


def test_sine_press_example_matches_paper000_closed_form():
    """The engine-built sine press of the example file = inclined_slot(L1 = 50 mm, 60 deg)."""
    from linkwork.models.sine import inclined_slot

    doc = files.load(EXAMPLES / "sine_press_planar.toml")
    phi = doc.positions()
    k = kinematics(doc.mechanism(), phi)
    cf = inclined_slot(phi, 0.05, np.radians(60.0), omega1=doc.driver.omega1)
    S = k.point("ram", "S")
    np.testing.assert_allclose(0.05 - S.x, cf.X3, atol=1e-12)
    np.testing.assert_allclose(-S.ax, cf.a3, atol=1e-9 * np.max(np.abs(cf.a3)))


def test_linear_driver_file_and_cli(tmp_path, capsys, monkeypatch):
    """A crank-slider driven by its slider (linear actuator): file, table, torque sign."""
    monkeypatch.setenv("COLUMNS", "250")
    f = tmp_path / "lin.toml"
    f.write_text("""
type = "planar"
name = "slider-driven crank"
[frame]
points = { O = [0, 0], G = [0, 0] }
[[body]]
name = "crank"
start = "O"
end = "A"
length = "100 mm"
mass = 1
[[body]]
name = "rod"
start = "A"
end = "B"
length = "350 mm"
mass = 2
[[body]]
name = "slider"
points = { B = [0, 0] }
mass = 3
[[joint]]
name = "O"
type = "revolute"
a = "frame"
b = "crank"
[[joint]]
name = "A"
type = "revolute"
a = "crank"
b = "rod"
[[joint]]
name = "B"
type = "revolute"
a = "rod"
b = "slider"
[[joint]]
name = "G"
type = "prismatic"
a = "frame"
b = "slider"
through = "G"
point = "B"
[driver]
type = "linear"
joint = "G"
v1 = "0.5 m/s"
[analysis]
start = "270 mm"
stop = "430 mm"
n = 41
branches = { A = 1 }
[[load]]
type = "torque"
body = "crank"
mz = "-3 N*m"
""")
    doc = files.load(f)
    k = kinematics(doc.mechanism(), doc.positions())
    d = inverse_dynamics(k, loads=doc.loads(doc.positions()))
    # statics-dominated check by power: Q v1 = dT/dt + 3 omega_crank
    dT = np.zeros(k.n)
    for b in doc.mechanism().bodies:
        i = doc.mechanism().index[b.name]
        c = k.point(b.name, "com")
        dT += b.mass * (c.vx * c.ax + c.vy * c.ay) + b.inertia * k.omega[i] * k.eps[i]
    np.testing.assert_allclose(d.Q * 0.5, dT + 3.0 * k.omega[1], atol=1e-9)
    assert main(["analyze", str(f), "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "s1 [mm]" in out and "Q [N]" in out


def planar_file(design, branch, rpm, eps):
    """The four-bar of the kinetostatic tests as a planar file, lengths in mm, loads in kN."""
    a, b, c, d = design
    lines = ['type = "planar"', "[frame]",
             f'points = {{ O2 = [0, 0], O4 = ["{1e3 * d} mm", 0] }}']
    for i, (name, start, end, length) in enumerate(
            (("crank", "O2", "A", a), ("coupler", "A", "B", b), ("rocker", "O4", "B", c))):
        lines += ["[[body]]", f'name = "{name}"', f'start = "{start}"', f'end = "{end}"',
                  f'length = "{1e3 * length} mm"', f'mass = "{MASS[i]} kg"',
                  f'inertia = "{INERTIA[i]} kg*m^2"',
                  f'com = ["{1e3 * COM[i][0]} mm", "{1e3 * COM[i][1]} mm"]']
    for name, ja, jb in (("O2", "frame", "crank"), ("A", "crank", "coupler"),
                         ("B", "coupler", "rocker"), ("O4", "frame", "rocker")):
        lines += ["[[joint]]", f'name = "{name}"', 'type = "revolute"', f'a = "{ja}"',
                  f'b = "{jb}"']
    lines += ["[driver]", 'joint = "O2"', f'omega1 = "{rpm} rpm"', f'eps1 = "{eps} rad/s^2"',
              "[analysis]", 'start = "0 deg"', 'stop = "360 deg"', "n = 25",
              f"branches = {{ B = {branch} }}",
              f'gravity = ["{GRAV[0]} m/s^2", "{GRAV[1]} m/s^2"]',
              f'about = ["{1e3 * ABOUT[0]} mm", "{1e3 * ABOUT[1]} mm"]',
              "[[load]]", 'type = "force"', 'body = "coupler"',
              f'point = ["{1e3 * P_COUPLER[0]} mm", "{1e3 * P_COUPLER[1]} mm"]',
              f'fx = "{1e-3 * F_COUPLER[0]} kN"', f'fy = "{1e-3 * F_COUPLER[1]} kN"',
              "[[load]]", 'type = "torque"', 'body = "rocker"', f'mz = "{M_EXT[2]} N*m"']
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("branch", [+1, -1])
def test_planar_file_and_cli_against_newton_euler(tmp_path, branch):
    """End to end: a file with units (mm, rpm, kN), oblique gravity, a force at a coupler
    point, a couple on the rocker and eps1 != 0, run by ``linkwork analyze``; the CSV columns
    against the reference."""
    import csv

    from linkwork.cli import main

    design = DESIGNS["general"]
    rpm, eps = 75.0, -18.0
    path = tmp_path / "fourbar.toml"
    path.write_text(planar_file(design, branch, rpm, eps))
    assert main(["analyze", str(path), "--out", str(tmp_path / "out")]) == 0
    with (tmp_path / "out" / "planar_dynamics.csv").open() as fh:
        rows = list(csv.reader(fh))
    cols = {h.split(" [")[0]: np.array([float(r[k]) for r in rows[1:]])
            for k, h in enumerate(rows[0])}
    t2 = np.linspace(0.0, 2 * np.pi, 25)
    close(cols["phi1"], t2, 1.0)
    # only the coupler force and the rocker couple act in the file
    loads = {"force": ((0.0, 0.0), F_COUPLER, (0.0, 0.0)), "point": LOADS["point"],
             "moment": (0.0, 0.0, M_EXT[2])}
    ref = fourbar_reference(design, branch, t2, (rpm * np.pi / 30, eps), loads)
    scale = check_reactions([(cols[f"R_{j}.x"], cols[f"R_{j}.y"]) for j in ("O2", "A", "B", "O4")],
                            cols["Q"], ref["x"])
    sf, sm = _shaking_ref(ref, ABOUT)
    close(cols["shaking_fx"], sf[0], scale)
    close(cols["shaking_fy"], sf[1], scale)
    close(cols["shaking_m"], sm)
    close(cols["T"], ref["T"])


# -- files on the command line ------------------------------------------------------------------
def _cli(tmp_path, capsys, text: str) -> str:
    f = tmp_path / "m.toml"
    f.write_text(text)
    rc = main(["analyze", str(f), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1, err
    return err


def _replace(src: str, old: str, new: str) -> str:
    assert old in src
    return src.replace(old, new, 1)


FOURBAR = (EXAMPLES / "fourbar_paper001.toml").read_text()


SIXBAR = (EXAMPLES / "loom_sixbar.toml").read_text()


LOAD = '\n[[load]]\ntype = "{}"\nbody = "rocker"\n{}\n'


@pytest.mark.parametrize("text, words", [
    # a huge length: was a traceback (OverflowError in the rate solve) and exit code 1; the
    # files' sanity layer names it before any computation
    (_replace(FOURBAR, 'length = "100 mm"', "length = 1e300"),
     "length: 1e+300 is invalid: must lie within +-10000 m, far beyond any machine mechanism"),
    # keys of another type of load, joint or driver were ignored silently (exit 0, no load
    # applied, the joint's default points used, the linear driver at its default 1 m/s)
    (FOURBAR + LOAD.format("force", 'mz = "10 N*m"'),
     "load.0.mz: 10 N*m is invalid: is not used with type = 'force'"),
    (FOURBAR + LOAD.format("torque", 'fx = "10 N"'),
     "load.0.fx: 10 N is invalid: is not used with type = 'torque'"),
    (_replace(FOURBAR, 'a = "crank"\nb = "coupler"', 'a = "crank"\nb = "coupler"\npoint = "B"'),
     "joint.1.point: B is invalid: is not used with type = 'revolute', which takes point_a"),
    (_replace(_replace(SIXBAR, 'through = "G"', 'through = "G"\nrel_angle = 0.1'),
              'type = "prismatic"', 'type = "slot"'),
     "joint.6.rel_angle: 0.1 is invalid: is not used with type = 'slot'"),
    (_replace(FOURBAR, "eps1 = 0", 'eps1 = 0\nv1 = "2 m/s"'),
     "driver.v1: 2 m/s is invalid: is not used with type = 'crank', which takes omega1 and eps1"),
    # a NaN end of the load range switched the load off everywhere (exit 0)
    (FOURBAR + LOAD.format("force", 'fy = "10 N"\nphi_range = [nan, "20 deg"]'),
     "load.0.phi_range: nan is invalid: must be finite"),
    # 1e300 rad: exit 0 with dead centres printed as 300-digit angles
    (_replace(FOURBAR, 'stop = "360 deg"', "stop = 1e300"),
     "analysis.stop: 1e+300 is invalid: must lie within +-1e+06 rad"),
    # a revolute's missing point: the joint was not named ('frame.points: Z is invalid')
    (_replace(FOURBAR, 'name = "C"\ntype = "revolute"', 'name = "C"\ntype = "revolute"\n'
              'point_a = "Z"'), "joint.3.point_a (C): Z is invalid: no such point of body 'frame'"),
    # a union (point name or [x, y]) reported its string member: 'Input should be a valid
    # string (got [nan, 0])'; now the member that reads [x, y] says what is wrong
    (_replace(SIXBAR, 'through = "G"', "through = [nan, 0]"),
     "joint.6.through.0: must be a finite number (got nan)"),
])
def test_cli_described_wrongly_one_line_exit_2(tmp_path, capsys, text, words):
    assert words in _cli(tmp_path, capsys, text)


def test_cli_load_keys_of_its_own_type_still_work(tmp_path, capsys):
    """For comparison: the same loads with their own keys run (exit 0)."""
    f = tmp_path / "ok.toml"
    f.write_text(FOURBAR + LOAD.format("force", 'fy = "10 N"\nphi_range = ["10 deg", "20 deg"]')
                 + LOAD.format("torque", 'mz = "1 N*m"'))
    assert main(["analyze", str(f), "--out", str(tmp_path / "out")]) == 0
    capsys.readouterr()


def test_cli_table_angles_beyond_float_precision_are_refused(tmp_path, capsys):
    """--angles -1e300 printed a 300-digit crank angle with 'results' for it (exit 0)."""
    rc = main(["analyze", str(EXAMPLES / "fourbar_paper001.toml"), "--out", str(tmp_path),
               "--angles", "-1e300"])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1
    assert "--angles = -1e+300 is invalid: must lie within +-5.72958e+07 deg" in err


ROOT = Path(__file__).resolve().parents[2]


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


def test_file_straight_link_with_a_point_redefining_its_end_one_line_exit_2(tmp_path, capsys):
    text = (ROOT / "examples" / "fourbar_paper001.toml").read_text()
    old = 'points = { P = '  # the coupler's named points (its coupler point P)
    assert old in text
    f = tmp_path / "m.toml"
    f.write_text(text.replace(old, 'points = { B = ["250 mm", 0], P = ', 1))
    code, _, err = run_cli(["analyze", str(f), "--out", str(tmp_path / "o")], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert 'body.1.points.B (coupler): ["250 mm", 0] is invalid' in err


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


@pytest.mark.parametrize("command", [["analyze"], ["reactions", "--no-plots"]])
def test_partial_cycle_mechanism_tables_inside_its_range(tmp_path, capsys, command):
    """The file's range (20..128 deg) assembles but a full turn does not: the default table
    positions are the multiples of 30 deg inside the range (30, 60, 90, 120), so the command
    works; table angles outside the range are refused naming --angles and the positions."""
    f = _rocking_crank_file(tmp_path)
    code, out, err = run_cli([command[0], str(f), "--out", str(tmp_path / "o"), *command[1:]],
                             capsys)
    assert code == 0, err
    if command[0] == "analyze":  # the table's rows
        assert "120.0" in out and "150.0" not in out.split("extreme")[0]
    code, _, err = run_cli([command[0], str(f), "--out", str(tmp_path / "o2"), *command[1:],
                            "--angles", "0,30"], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert "--angles" in err and "0, 30" in err


def test_partial_cycle_balance_names_the_full_turn(tmp_path, capsys):
    """Balancing needs a full turn, which the rocking crank does not make: the error names the
    full turn and the file's [analysis] range instead of only 'cannot be assembled at 4 of 12
    driver positions'."""
    f = _rocking_crank_file(tmp_path)
    code, _, err = run_cli(["balance", str(f), "--out", str(tmp_path / "o")], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert "full turn" in err and "[analysis]" in err


def _variant(tmp_path, example, old, new, name="case.toml"):
    from pathlib import Path
    text = (Path(__file__).resolve().parents[2] / "examples" / example).read_text()
    assert old in text, old
    p = tmp_path / name
    p.write_text(text.replace(old, new, 1))
    return p


PLANAR_BROKEN = [
    ("fourbar_paper001.toml", 'length = "100 mm"', 'length = "100 kg"', ["body.0.length", "kg"]),
    ("fourbar_paper001.toml", 'length = "100 mm"', 'length = "-100 mm"', ["body.0.length (crank)",
                                                                          "-100 mm is invalid"]),
    ("fourbar_paper001.toml", 'b = "crank"', 'b = "krank"', ["krank"]),
    ("fourbar_paper001.toml", 'joint = "O"\nomega1', 'joint = "O9"\nomega1', ["O9"]),
    ("fourbar_paper001.toml", 'type = "revolute"', 'type = "ball"', ["joint.0.type", "ball"]),
    ("fourbar_paper001.toml", 'type = "planar"', 'type = "planer"', ["type", "planer"]),
    ("fourbar_paper001.toml", 'branches = { B = 1 }', 'branches = { Z = 1 }', ["branches",
                                                                               "Z"]),
    ("fourbar_paper001.toml", 'n = 361', 'n = 0', ["analysis.n"]),
    ("fourbar_paper001.toml", 'omega1 = "10 rad/s"', 'omega1 = "10 m"', ["driver.omega1"]),
    ("fourbar_paper001.toml", 'length = "300 mm"\nmass = "3 kg"',
     'length = "30 mm"\nmass = "3 kg"', ["assembled", "deg"]),
    ("fourbar_paper001.toml", "[driver]",
     '[[joint]]\nname = "X"\ntype = "revolute"\na = "frame"\nb = "coupler"\npoint_a = "C"\n'
     'point_b = "B"\n\n[driver]', ["locked", "[[joint]] as written is invalid"]),
    ("fourbar_paper001.toml", 'about = [0, 0]',
     'about = [0, 0]\n\n[[load]]\ntype = "force"\nbody = "rokker"\npoint = "B"\nfx = 1\nfy = 0',
     ["load.0.body", "rokker"]),
    ("fourbar_paper001.toml", 'about = [0, 0]',
     'about = [0, 0]\n\n[[load]]\ntype = "force"\nbody = "rocker"\npoint = "Z"\nfx = 1\nfy = 0',
     ["load.0.point", "Z", "rocker"]),
    ("fourbar_paper001.toml", 'about = [0, 0]',
     'about = [0, 0]\n\n[[load]]\ntype = "torque"\nbody = "frame"\nmz = 1',
     ["load.0.body", "frame"]),
    ("fourbar_paper001.toml", 'name = "crank"', 'name = "crank"\ncolour = "red"', ["colour"]),
    ("sine_press_planar.toml", 'angle = "60 deg"', 'angle = "60 mm"', ["joint.2.angle"]),
    ("loom_sixbar.toml", 'type = "planar"', 'type = "planar"\n[oops', ["TOML"]),
]


@pytest.mark.parametrize("example,old,new,words", PLANAR_BROKEN)
def test_cli_broken_planar_files_one_line_exit_2(example, old, new, words, tmp_path, capsys):
    from linkwork.cli import main
    p = _variant(tmp_path, example, old, new)
    rc = main(["analyze", str(p), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert rc == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    for w in words:
        assert w.lower() in err.lower(), (w, err)


def test_cli_missing_file_and_directory(tmp_path, capsys):
    from linkwork.cli import main
    for path in (tmp_path / "nope.toml", tmp_path):
        rc = main(["analyze", str(path)])
        err = capsys.readouterr().err
        assert rc == 2 and len(err.strip().splitlines()) == 1, err


@pytest.mark.parametrize("old,new", [('length = "100 mm"', 'length = "-100 mm"'),
                                     ('b = "crank"', 'b = "krank"')])
def test_cli_model_level_errors_are_short_and_keyed(old, new, tmp_path, capsys):
    from linkwork.cli import main
    p = _variant(tmp_path, "fourbar_paper001.toml", old, new)
    assert main(["analyze", str(p)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err) < 300 and "{'type'" not in err, err


@pytest.mark.parametrize("example", ["fourbar_paper001.toml", "loom_sixbar.toml",
                                     "sine_press_planar.toml"])
def test_cli_examples_write_reactions_and_torque(example, tmp_path, capsys, monkeypatch):
    import csv
    import json
    from pathlib import Path

    from linkwork.cli import main
    from linkwork.files import load
    monkeypatch.setenv("COLUMNS", "250")
    src = Path(__file__).resolve().parents[2] / "examples" / example
    out = tmp_path / "out"
    assert main(["analyze", str(src), "--out", str(out)]) == 0
    table = capsys.readouterr().out
    assert "Q [N·m]" in table and "|R" in table
    with (out / "planar_dynamics.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    doc = load(src)
    mech = doc.mechanism()
    for j in mech.joints:
        assert f"R_{j.name}.x [N]" in rows[0] and f"R_{j.name}.y [N]" in rows[0]
    assert "Q [N*m]" in rows[0]
    data = json.loads((out / "planar.json").read_text())
    assert "Q" in data["columns"]
    for png in ("planar_driving_torque.png", "planar_reactions.png", "planar_shaking.png"):
        assert (out / png).stat().st_size > 10_000
    # the CSV's numbers are the engine's, recomputed here from the file
    phi = doc.positions()
    kin = kinematics(mech, phi)
    dyn = inverse_dynamics(kin, gravity=doc.analysis.gravity, loads=doc.loads(phi),
                           about=doc.analysis.about)
    q_csv = np.array([float(r["Q [N*m]"]) for r in rows])
    np.testing.assert_allclose(q_csv, dyn.Q, rtol=1e-12, atol=1e-12)
