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
