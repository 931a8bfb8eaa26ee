"""Force elements and load diagrams in planar files (``[[spring]]``, ``[[damper]]``, ``[[load]]``
of type ``slide`` and ``drag``, ``[load.diagram]``; docs/forces.md): read with their units into
the engine's loads, and every bad value refused with the file, the key as written and the limit.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from _sketches import paper001_drawing

from linkwork import io
from linkwork.cli import main
from linkwork.errors import FileFormatError, LinkworkError
from linkwork.planar import (
    BodyTorque,
    Damper,
    Drag,
    LoadDiagram,
    PointForce,
    SlideForce,
    Spring,
)

ROOT = Path(__file__).resolve().parents[2]
PRESS = ROOT / "examples" / "crank_press.toml"


def _file(tmp_path: Path, text: str, name: str = "m.toml") -> Path:
    f = tmp_path / name
    f.write_text(text)
    return f


def _press(tmp_path: Path, old: str = "", new: str = "", extra: str = "") -> Path:
    text = PRESS.read_text()
    if old:
        assert old in text, old
        text = text.replace(old, new)
    return _file(tmp_path, text + extra)


def test_press_example_loads_in_si():
    doc = io.load(PRESS)
    loads = doc.loads(doc.positions())
    assert doc.load_keys() == ["load.0", "spring.0"]
    drawing, spring = loads
    assert isinstance(drawing, SlideForce) and drawing.joint == "guide"
    assert drawing.name == "drawing"
    d = drawing.force
    assert isinstance(d, LoadDiagram)
    np.testing.assert_allclose(d.position, [-0.450, -0.446, -0.442, -0.438, -0.434, -0.430],
                               rtol=1e-15)
    np.testing.assert_allclose(d.value, [100e3, 150e3, 190e3, 200e3, 140e3, 0.0], rtol=1e-15)
    assert (d.over, d.when, d.outside, d.table_range) == ("guide", "decreasing", "zero",
                                                          (-0.450, -0.430))
    assert spring == Spring("frame", "K", "ram", "R", stiffness=5000.0, free_length=0.4,
                            preload=2500.0, name="counterbalance")


OTHER = """
[[load]]
type = "drag"
body = "rod"
point = [0.2, 0]
force = "40 N"
damping = "0.5 kN*s/m"
from_frame = true

[[load]]
name = "tilt"
type = "force"
body = "ram"
point = "R"
angle = "120 deg"
[load.diagram]
over = "driver"
table = [["200 deg", "1 kN"], ["260 deg", "3 kN"]]

[[load]]
type = "torque"
body = "crank"
[load.diagram]
table = [[0, "10 N*m"], ["1 turn", "-10 N*m"]]
when = "increasing"
outside = "error"

[[load]]
type = "slide"
joint = "guide"
force = "-2 kN"
phi_range = ["90 deg", "180 deg"]

[[damper]]
a = "frame"
point_a = [0.1, -0.6]
b = "ram"
point_b = "com"
damping = "3 N*s/mm"
"""


def test_every_kind_with_units(tmp_path):
    doc = io.load(_press(tmp_path, extra=OTHER))
    phi = np.radians([0.0, 100.0, 200.0])
    loads = doc.loads(phi)
    assert doc.load_keys() == ["load.0", "load.1", "load.2", "load.3", "load.4", "spring.0",
                               "damper.0"]
    drag, tilt, torque, slide = loads[1:5]
    assert drag == Drag("rod", (0.2, 0.0), 40.0, 500.0, True, "load.1")
    assert isinstance(tilt, PointForce) and tilt.name == "tilt"
    fx, fy = tilt.fx, tilt.fy
    assert isinstance(fx, LoadDiagram) and isinstance(fy, LoadDiagram)
    np.testing.assert_allclose(fx.position, np.radians([200.0, 260.0]), rtol=1e-15)
    np.testing.assert_allclose(fx.value, [1e3 * math.cos(math.radians(120)),
                                          3e3 * math.cos(math.radians(120))], rtol=1e-12)
    np.testing.assert_allclose(fy.value, [1e3 * math.sin(math.radians(120)),
                                          3e3 * math.sin(math.radians(120))], rtol=1e-12)
    assert isinstance(torque, BodyTorque) and isinstance(torque.mz, LoadDiagram)
    assert torque.mz.position == pytest.approx((0.0, 2 * math.pi), rel=1e-15)
    assert (torque.mz.when, torque.mz.outside) == ("increasing", "error")
    assert isinstance(slide, SlideForce)
    np.testing.assert_array_equal(slide.force, [0.0, -2e3, 0.0])  # over phi_range only
    assert loads[6] == Damper("frame", (0.1, -0.6), "ram", "com", 3000.0, "damper.0")


def test_a_linear_drivers_diagram_is_over_its_slide_in_metres(tmp_path):
    text = (ROOT / "tests" / "data" / "slider_driven_crank.toml").read_text()
    f = _file(tmp_path, text + """
[[load]]
type = "torque"
body = "crank"
[load.diagram]
table = [["300 mm", "2 N*m"], ["400 mm", "4 N*m"]]
""")
    d = io.load(f).loads(np.zeros(1))[1].mz
    assert d.position == pytest.approx((0.3, 0.4), rel=1e-15)


@pytest.mark.parametrize(("old", "new", "extra", "match"), [
    ('stiffness = "5 N/mm"', 'stiffness = "-5 N/mm"', "",
     r"crank_press\.toml: spring\.0\.stiffness: -5 N/mm is invalid: must be >= 0$"),
    ('free_length = "400 mm"', 'free_length = "-400 mm"', "",
     r"spring\.0\.free_length: -400 mm is invalid: must be >= 0"),
    ('stiffness = "5 N/mm"', 'stiffness = "5 N"', "",
     r"spring\.0\.stiffness: .*must have the dimension of stiffness \(N/m\)"),
    ('free_length = "400 mm"\n', "", "", r"spring\.0\.free_length: missing required key"),
    ('point_b = "R"', 'point_b = "Z"', "",
     r"spring\.0\.point_b: Z is invalid: no such point of body 'ram'; known: \['B', 'R', 'com'\]"),
    ('b = "ram"\npoint_b = "R"', 'b = "frame"\npoint_b = "O"', "",
     r"spring\.0\.b: frame .*differ from a"),
    ('a = "frame"\npoint_a', 'a = "arm"\npoint_a', "", r"spring\.0\.a: arm .*no such body"),
    ('["-442 mm", "190 kN"]', '["-447 mm", "190 kN"]', "",
     r"load\.0\.diagram\.table\.2\.0: -447 mm is invalid: the table's positions must increase "
     r"strictly: it must be > -446 mm \(row 1\)"),
    ('["-446 mm", "150 kN"]', '["-446 mm", "150 mm"]', "",
     r"load\.0\.diagram\.table\.1\.1: 150 mm is invalid: must have the dimension of force"),
    ('over = "guide"', 'over = "A"', "",
     r"load\.0\.diagram\.over: A is invalid: must be a prismatic or pin-in-slot joint \(a slide "
     r"position\), or 'driver'; this joint is Revolute"),
    ('over = "guide"', 'over = "G2"', "", r"load\.0\.diagram\.over: G2 .*known: \['O', 'A'"),
    ('over = "guide"', 'over = "driver"', "",
     r"load\.0\.diagram\.table\.0\.0: -450 mm is invalid: must have the dimension of angle"),
    ('when = "decreasing"', 'when = "down"', "", r"load\.0\.diagram\.when: .*'decreasing'"),
    ('table = [', 'outside = "extrapolate"\ntable = [', "", r"load\.0\.diagram\.outside"),
    ('joint = "guide"\n\n[load', 'joint = "A"\n\n[load', "",
     r"load\.0\.joint: A is invalid: must be a prismatic or pin-in-slot joint \(a line to act "
     r"along\); this joint is Revolute"),
    ('joint = "guide"\n\n[load', 'joint = "guide"\nforce = "3 kN"\n\n[load', "",
     r"load\.0\.force: 3 kN is invalid: is not used with type = 'slide', which takes its value "
     r"from the diagram"),
    ('joint = "guide"\n\n[load', 'joint = "guide"\nphi_range = [0, 1]\n\n[load', "",
     r"load\.0\.phi_range: .*not used"),
    ('type = "slide"                 # along', 'type = "force"\nbody = "ram"  # along', "",
     r"load\.0\.joint: guide is invalid: is not used with type = 'force'"),
    ('joint = "guide"\n\n[load', '\n\n[load', "", r"load\.0\.joint: .*is required by type = "
     r"'slide'"),
    ("", "", '[[load]]\ntype = "drag"\nbody = "ram"\nforce = "-1 N"\n',
     r"load\.1\.force: -1 N is invalid: must be >= 0"),
    ("", "", '[[load]]\ntype = "drag"\nbody = "ram"\nmz = 1\n', r"load\.1\.mz: .*not used"),
    ("", "", '[[load]]\ntype = "drag"\nbody = "frame"\nforce = 1\n',
     r"load\.1\.body: frame is invalid: loads act on moving bodies"),
    ("", "", '[[load]]\ntype = "force"\nbody = "ram"\n[load.diagram]\n'
     'table = [[0, 1], [1, 2]]\n', r"load\.1\.angle: .*is required by a force given by a diagram"),
    ("", "", '[[load]]\ntype = "force"\nbody = "ram"\nangle = 1\n',
     r"load\.1\.angle: 1 is invalid: is the direction of a force given by a diagram"),
    ("", "", '[[load]]\ntype = "torque"\nbody = "crank"\n[load.diagram]\n'
     'table = [[0, 1], ["400 deg", 2]]\n',
     r"load\.1\.diagram\.position: 400 deg span is invalid: a crank-angle diagram spans at most "
     r"one turn"),
    ("", "", '[[load]]\ntype = "torque"\nbody = "crank"\n[load.diagram]\ntable = [[0, 1]]\n',
     r"load\.1\.diagram\.table: \[\[0, 1\]\] is invalid: a diagram needs at least 2 positions"),
    ("", "", '[[damper]]\na = "frame"\npoint_a = "K"\nb = "ram"\npoint_b = "B"\n'
     'damping = "-3 N*s/m"\n', r"damper\.0\.damping: -3 N\*s/m is invalid: must be >= 0"),
    ("", "", '[[damper]]\na = "frame"\npoint_a = "K"\nb = "ram"\npoint_b = "B"\n'
     'damping = "3 N/m"\n', r"damper\.0\.damping: .*dimension of damping \(N\*s/m\)"),
    ('name = "counterbalance"', 'name = "drawing"', "",
     r"spring\.0\.name: drawing is invalid: must be unique among the loads, springs and dampers "
     r"\(also load\.0\)"),
])
def test_bad_loads_are_named_by_their_key(tmp_path, old, new, extra, match):
    f = _press(tmp_path, old, new, extra)
    f = f.rename(tmp_path / "crank_press.toml")
    with pytest.raises(LinkworkError, match=match):
        io.load(f)
    assert main(["analyze", str(f), "--out", str(tmp_path / "out")]) == 2


def test_a_measured_curve_of_many_rows_reads_once_and_exactly(tmp_path):
    """A drawing force logged as 20 000 plain SI numbers (a measured curve): the diagram holds
    the table's numbers exactly, it is converted once (the file's check and every analysis
    share one LoadDiagram; it was converted three times, one value at a time, and a 10^6-row
    table took 77 s to analyse, 17 s now, most of it reading the TOML), and a bad row among
    them is named as one given with a unit would be (the first bad row in file order,
    strings and numbers alike)."""
    n = 20_000
    s = np.linspace(-0.450, -0.430, n)
    f = 1e5 + 1e5 * np.sin(np.arange(n) / 1e3)
    rows = [f"[{a!r}, {b!r}]" for a, b in zip(s.tolist(), f.tolist(), strict=True)]
    text = PRESS.read_text()
    i = text.index("table = [  ")
    j = text.index("]\n\n[[spring]]")

    def read(rows):
        return io.load(_file(tmp_path, text[:i] + f"table = [{','.join(rows)}" + text[j:]))

    doc = read(rows)
    drawing = doc.loads(doc.positions())[0].force
    np.testing.assert_array_equal(drawing.position, s)
    np.testing.assert_array_equal(drawing.value, f)
    assert doc.loads(doc.positions())[0].force is drawing
    bad = list(rows)
    bad[7] = f'["{float(s[7]) * 1e3!r} mm", "-1e13 N"]'
    bad[9] = f"[{float(s[9])!r}, nan]"
    with pytest.raises(LinkworkError, match=r"load\.0\.diagram\.table\.7\.1: -1e13 N is "
                       r"invalid: must lie within \+-1e\+12 N"):
        read(bad)
    bad[7] = rows[7]
    with pytest.raises(LinkworkError, match=r"load\.0\.diagram\.table\.9\.1: nan is invalid: "
                       "must be a finite number"):
        read(bad)

def test_errors_found_while_analysing_name_the_file_key(tmp_path, capsys):
    """A diagram that the analysis leaves with outside = "error", and a spring whose points
    meet at some position: one line naming the file and the key, exit code 2, nothing
    written; the same through the library call names the key too."""
    from linkwork.studies import planar as study_planar

    f = _press(tmp_path, 'when = "decreasing"', 'outside = "error"')
    capsys.readouterr()
    assert main(["analyze", str(f), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0
    assert err.startswith(f"linkwork: error: {f}: load.0.diagram.table: [-0.45, -0.43] m is "
                          "invalid: the analysis leaves this range of the diagram over the "
                          "slide of guide while the load acts, at phi1 in [-39.5, 219.5 deg]")
    assert not (tmp_path / "out" / "planar.json").exists()
    with pytest.raises(LinkworkError, match=r"^load\.0\.diagram\.table = "):
        study_planar.analyze(io.load(f))
    # the counterbalance anchored on the wrist pin's path: they meet at the bottom
    g = PRESS.read_text().replace('point_b = "R"', 'point_b = "B"').replace(
        'K = ["250 mm", 0]', 'K = [0, "-450 mm"]')
    f2 = _file(tmp_path, g, "meet.toml")
    for cmd in (["analyze"], ["balance"], ["reactions", "--no-plots"]):
        capsys.readouterr()
        assert main([*cmd, str(f2), "--out", str(tmp_path / "o2")]) == 2
        err = capsys.readouterr().err.strip()
        assert err.count("\n") == 0, err
        assert err.startswith(f"linkwork: error: {f2}: spring.0: counterbalance is invalid: "
                              "its points 'K' of 'frame' and 'B' of 'ram' coincide at phi1 in "
                              "270 deg, where the direction of its force is undefined"), err


def test_files_without_the_new_tables_read_as_before(tmp_path):
    """Every example without force elements: loads as PointForce/BodyTorque named load.<i>;
    an unknown load type is refused by its key."""
    for f in sorted((ROOT / "examples").glob("*.toml")):
        doc = io.load(f)
        if not isinstance(doc, io.PlanarFile) or doc.spring or doc.damper:
            continue
        for i, ld in enumerate(doc.loads(doc.positions())):
            if doc.load[i].type in ("force", "torque"):
                assert isinstance(ld, PointForce | BodyTorque) and ld.name == f"load.{i}"
    with pytest.raises(FileFormatError, match=r"load\.0\.type"):
        io.load(_press(tmp_path, 'type = "slide"', 'type = "spring"'))


SPRING_AND_DIAGRAM = """
[[spring]]
a = "frame"
point_a = "C"
b = "coupler"
point_b = "P"
stiffness = "1 N/mm"
free_length = "100 mm"
preload = "5 N"

[[load]]
type = "torque"
body = "rocker"
[load.diagram]
table = [["0 deg", "1 N*m"], ["180 deg", "3 N*m"]]
"""


def test_drawn_file_takes_the_same_elements(tmp_path):
    """A spring to the coupler point P and a couple diagram on the rocker, in paper 001's
    four-bar written in body frames and as its drawing (tests/io/test_planar_sketch.py):
    the same loads, driving torque and springs' energy, to 1e-9 of their scale."""
    from linkwork.studies import planar as study_planar

    body = _file(tmp_path, (ROOT / "examples" / "fourbar_paper001.toml").read_text()
                 + SPRING_AND_DIAGRAM, "body.toml")
    drawn = _file(tmp_path, paper001_drawing() + SPRING_AND_DIAGRAM, "drawn.toml")
    a, b = (study_planar.analyze(io.load(f)) for f in (body, drawn))
    ca, cb = a.dynamics_columns(), b.dynamics_columns()
    for key in ("F_spring.0", "L_spring.0", "M_load.0", "V", "Q"):
        scale = np.max(np.abs(ca[key][0]))
        assert scale > 0
        np.testing.assert_allclose(cb[key][0], ca[key][0], rtol=0, atol=1e-9 * scale)
