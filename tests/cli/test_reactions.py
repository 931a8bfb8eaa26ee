"""The [spatial] table and the `linkwork reactions` report."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from _cli_files import LINEAR_SLIDER_CRANK, run_cli
from _fourbar_reference import INERTIA, M_EXT, MASS, OMEGA1
from rich.console import Console

from linkwork.cli.reactions import run
from linkwork.errors import FileFormatError, ParameterError
from linkwork.planar import BodyTorque, fourbar_mechanism
from linkwork.redundancy import Deviation, OutOfPlaneLoad, spatial_reactions
from linkwork.redundancy.spec import read_spatial

SPATIAL = {
    "k_bearing": "100 N/um",
    "positions": 72,
    "default": {"e": "30 mm", "z": "0 mm"},
    "heights": {"coupler": "30 mm"},
    "joints": {"A": {"e": "20 mm", "z": "30 mm"}, "B": {"z": "30 mm"},
               "O4": {"kind": "revolute", "e": "40 mm", "z": "-10 mm",
                      "stiffness": ["1e8 N/m", "1e8 N/m", "5e7 N/m", "10 kN*m/rad",
                                    "10 kN*m/rad", 0]}},
    "deviation": [{"joint": "O4", "body": "frame", "tx": "0.2 mrad", "dz": "10 um"}],
    "out_of_plane": [{"body": "coupler", "fz": "5 N"}],
    "tolerance": [{"joint": "O4", "body": "frame", "component": "ty", "limit": "0.3 mrad"},
                  {"joint": "B", "body": "rocker", "component": "dz", "limit": "20 um",
                   "distribution": "uniform"}],
}


def _mech():
    return fourbar_mechanism(0.1, 0.3, 0.2, 0.3, masses=tuple(MASS), inertias=tuple(INERTIA),
                   omega1=OMEGA1)


def test_spatial_table_units_and_defaults():
    spec = read_spatial("f.toml", {"spatial": SPATIAL})
    assert spec.k_bearing == pytest.approx(1e8)
    assert spec.joint_kwargs()["A"] == {"k_bearing": 1e8, "axial_ratio": 1.0, "e": 0.02,
                                        "z": 0.03}
    assert spec.joint_kwargs()["O4"]["stiffness"] == pytest.approx((1e8, 1e8, 5e7, 1e4, 1e4, 0))
    assert spec.deviation[0].tx == pytest.approx(2e-4)
    assert spec.deviation[0].dz == pytest.approx(1e-5)
    assert spec.tolerance[0].limit == pytest.approx(3e-4)
    assert spec.tolerance[1].limit == pytest.approx(2e-5)
    assert read_spatial("f.toml", {}).positions is None


@pytest.mark.parametrize(("patch", "key"), [
    ({"joints": {"A": {"e": "-3 mm"}}}, "spatial.joints.A.e"),
    ({"joints": {"A": {"length": "3 mm"}}}, "spatial.joints.A.length"),
    ({"joints": {"A": {"kind": "hinge"}}}, "spatial.joints.A.kind"),
    ({"deviation": [{"joint": "A", "body": "crank", "tx": "3 mm"}]}, "spatial.deviation.0.tx"),
    ({"tolerance": [{"joint": "A", "body": "crank", "component": "tx", "limit": "-1 mrad"}]},
     "spatial.tolerance.0.limit"),
    ({"joints": {"A": {"stiffness": [1, 2, 3]}}}, "spatial.joints.A.stiffness"),
])
def test_spatial_table_errors_name_the_key(patch, key):
    with pytest.raises(FileFormatError, match=key.replace(".", r"\.")):
        read_spatial("f.toml", {"spatial": patch})


def test_run_report_matches_library_and_writes_files(tmp_path):
    spec = read_spatial("f.toml", {"spatial": SPATIAL})
    console = Console(record=True, width=140)
    angles = np.radians([0.0, 90.0])
    out = run(_mech(), spec, out=tmp_path, angles=angles, console=console, gravity=(0.0, -9.81),
              loads=lambda phi: [BodyTorque("rocker", M_EXT)], tolerance_study=40, plots=True)
    # independent call of the library with the same data written as Python objects
    joints = {"O2": {"e": 0.03, "z": 0.0}, "A": {"e": 0.02, "z": 0.03},
              "B": {"e": 0.03, "z": 0.03},
              "O4": {"e": 0.04, "z": -0.01, "stiffness": (1e8, 1e8, 5e7, 1e4, 1e4, 0)}}
    ref = spatial_reactions(_mech(), angles, gravity=(0, -9.81),
                            loads=[BodyTorque("rocker", M_EXT)], joints=joints,
                            heights={"coupler": 0.03},
                            out_of_plane=[OutOfPlaneLoad("coupler", fz=5.0)],
                            deviations=[Deviation("O4", "frame", tx=2e-4, dz=1e-5)])
    assert np.allclose(out["table"].components(), ref.components(), rtol=1e-12, atol=1e-12)
    text = console.export_text()
    assert "q = W - W0 = 3" in text and "peaks over the cycle" in text
    assert f"{ref.fz[2, 1]:.4g}" in text
    names = {p.name for p in out["files"]}
    assert {"reactions.csv", "reactions.json", "reactions_peaks.json", "reactions_bending.png",
            "tolerance.json", "tolerance_samples.csv", "tolerance_bending_B.png"} <= names
    peaks = json.loads((tmp_path / "reactions_peaks.json").read_text())
    assert peaks["redundant_constraints"] == 3
    assert np.isclose(peaks["peaks"]["B"]["bending"], np.max(out["reactions"].bending()[2]))
    header = (tmp_path / "reactions.csv").read_text().splitlines()[0]
    assert header.startswith("phi1 [rad],fx_O2 [N]")
    # the study includes the file's systematic deviations (dz, tx of O4) as fixed means
    st = out["study"]
    assert np.allclose(st.draws[:, -2], 1e-5) and np.allclose(st.draws[:, -1], 2e-4)
    assert st.n_samples == 40


def test_run_tolerance_study_needs_tolerances(tmp_path):
    spec = read_spatial("f.toml", {"spatial": {"positions": 24}})
    with pytest.raises(ParameterError, match="tolerance"):
        run(_mech(), spec, out=tmp_path, angles=np.zeros(1), console=Console(),
            tolerance_study=10, plots=False)


ROOT = Path(__file__).resolve().parents[2]


def test_cli_reactions_linear_driver_by_default_tables_its_range(tmp_path, capsys):
    """Without --angles a linear-driver file failed ("0, 90, 180, 270 mm" leave the stroke);
    now it tables the positions every command tables: 12 over the file's [analysis] range."""
    f = tmp_path / "lin.toml"
    f.write_text(LINEAR_SLIDER_CRANK)
    code, text, err = run_cli(["reactions", str(f), "--out", str(tmp_path / "o"),
                               "--no-plots"], capsys)
    assert code == 0, err
    shown = [float(line.split("s1 = ")[1].split(" mm")[0])
             for line in text.splitlines() if "reactions at s1 = " in line]
    np.testing.assert_allclose(shown, np.linspace(160, 240, 12), rtol=1e-3)


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


def test_reactions_of_several_drivers_table_the_path_and_write_each_drivers_columns(tmp_path,
                                                                                     capsys):
    """`linkwork reactions` on the excavator (three cylinders): one table per position along
    the drivers' path naming every driver's position, each driver's force in the captions and
    peaks; reactions.csv has phi1_<joint> [m] first and Q_<joint> [N] per driver, equal to
    linkwork.redundancy called directly on the file's path."""
    from linkwork import io
    from linkwork.redundancy import spatial_reactions as direct

    path = Path(__file__).resolve().parents[2] / "examples" / "excavator_boom.toml"
    code, out, err = run_cli(["reactions", str(path), "--out", str(tmp_path / "o"),
                              "--no-plots"], capsys)
    assert code == 0, err
    assert "path position 1/12: s1 boom_cyl = 1300 mm, s1 arm_cyl = 1450 mm, s1 bucket_cyl = " \
           "1300 mm" in " ".join(out.split())
    assert "driving force Q arm_cyl = " in out and "peak |Q bucket_cyl| = " in " ".join(
        out.split())
    head = (tmp_path / "o" / "reactions.csv").read_text().splitlines()[0].split(",")
    assert head[:3] == ["phi1_boom_cyl [m]", "phi1_arm_cyl [m]", "phi1_bucket_cyl [m]"]
    assert head[-3:] == ["Q_boom_cyl [N]", "Q_arm_cyl [N]", "Q_bucket_cyl [N]"]
    data = np.loadtxt(tmp_path / "o" / "reactions.csv", delimiter=",", skiprows=1)
    doc = io.load(path)
    phi = doc.positions()
    ref = direct(doc.mechanism(), phi, gravity=doc.analysis.gravity, loads=doc.loads(phi))
    np.testing.assert_allclose(data[:, :3].T, phi, rtol=1e-15)
    np.testing.assert_allclose(data[:, -3:].T, ref.Q, rtol=1e-12)
    peaks = json.loads((tmp_path / "o" / "reactions_peaks.json").read_text())
    assert peaks["units"]["Q"] == "N"
    assert peaks["peaks"]["driver"]["Q arm_cyl"] == pytest.approx(np.abs(ref.Q[1]).max())


def test_reactions_of_several_drivers_plot_each_drivers_load(tmp_path):
    """The bending figure of a two-crank file: the axes run along the path, one Q curve per
    driver labelled with its joint and unit."""
    from linkwork import io
    from linkwork.plot.redundancy import plot_bending
    from linkwork.redundancy import spatial_reactions as direct

    doc = io.load(Path(__file__).resolve().parents[1] / "data" / "drivers"
                  / "five_bar_two_cranks.toml")
    res = direct(doc.mechanism(), doc.positions(), gravity=doc.analysis.gravity)
    out = plot_bending(res)
    labels = [ln.get_label() for ln in out["Q_lines"]]
    assert labels == ["Q O1 [N·m]", "Q O2 [N·m]"]
    np.testing.assert_array_equal(out["Q_lines"][1].get_ydata(), res.Q[1])
    assert out["Q_lines"][0].get_xdata()[-1] == doc.positions().shape[1] - 1
