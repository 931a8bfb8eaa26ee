"""`linkwork reactions FILE.toml` end to end on the bundled example (a planar-engine file with a
[spatial] table), in-process."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("linkwork.planar.file")  # registers the engine's 'planar' schema


from linkwork import redundancy as rd
from linkwork.cli import main
from linkwork.cli.reactions import load_problem
from linkwork.planar import BodyTorque, kinematics
from linkwork.redundancy import Deviation, spatial_reactions

EXAMPLE = str(Path(__file__).resolve().parents[2] / "examples" / "loom_fourbar_spatial.toml")


def _expected(phi):
    from linkwork import files

    raw = files.read_toml(EXAMPLE)
    doc = files.validate(EXAMPLE, {k: v for k, v in raw.items() if k != "spatial"},
                         files.schemas()["planar"])
    mech = doc.mechanism()
    joints = {"O": {"e": 0.03, "z": 0.0}, "A": {"e": 0.03, "z": 0.03},
              "B": {"e": 0.03, "z": 0.03}, "C": {"e": 0.03, "z": -0.03}}
    devs = [Deviation("C", "frame", tx=2e-4), Deviation("A", "crank", ty=-1e-4),
            Deviation("B", "rocker", dz=2e-5)]
    return mech, spatial_reactions(mech, phi, gravity=(0, -9.81),
                                   loads=[BodyTorque("rocker", 4.0)], joints=joints,
                                   heights={"coupler": 0.03}, deviations=devs)


def test_cli_reactions_example(tmp_path, capsys):
    rc = main(["reactions", EXAMPLE, "--out", str(tmp_path), "--angles", "0,90", "--no-plots"])
    out = capsys.readouterr().out
    assert rc == 0
    assert "q = W - W0 = 3" in out
    mech, ref = _expected(np.radians([0.0, 90.0]))
    assert f"{ref.mx[2, 1]:.4g}" in out and f"{ref.Q[1]:.4g}" in out
    data = json.loads((tmp_path / "reactions.json").read_text())
    phi = np.asarray(data["columns"]["phi1"])
    _, full = _expected(phi)
    assert np.allclose(data["columns"]["fz_B"], full.fz[2], rtol=1e-10, atol=1e-10)
    assert np.allclose(data["columns"]["Q"], full.Q, rtol=1e-10, atol=1e-10)
    assert len(phi) == 360 and kinematics(mech, phi).n == 360


def test_cli_reactions_tolerance_study(tmp_path, capsys):
    rc = main(["reactions", EXAMPLE, "--out", str(tmp_path), "--tolerance-study", "200",
               "--angles", "0"])
    assert rc == 0
    data = json.loads((tmp_path / "tolerance.json").read_text())
    assert data["n_samples"] == 200
    assert data["percentiles"]["B"]["bending"]["p95"] >= data["percentiles"]["B"]["bending"][
        "p50"]
    assert (tmp_path / "tolerance_bending_B.png").exists()
    assert (tmp_path / "reactions_bending.png").exists()


def test_cli_reactions_bad_spatial_key_one_line(tmp_path, capsys):
    text = Path(EXAMPLE).read_text().replace('[spatial.joints.A]\ne = "30 mm"',
                                        '[spatial.joints.A]\ne = "-30 mm"')
    f = tmp_path / "bad.toml"
    f.write_text(text)
    assert main(["reactions", str(f), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "spatial.joints.A.e" in err and err.count("\n") == 1
    assert main(["reactions", EXAMPLE, "--method", "magic"]) == 2


ROOT = Path(__file__).resolve().parents[2]


SPATIAL_EXAMPLE = ROOT / "examples" / "loom_fourbar_spatial.toml"


def test_cli_reactions_bundled_example_with_tolerance_study(tmp_path, capsys):
    out = tmp_path / "o"
    rc = main(["reactions", str(SPATIAL_EXAMPLE), "--out", str(out), "--tolerance-study", "200",
               "--no-plots"])
    text = capsys.readouterr().out
    assert rc == 0
    assert "q = W - W0 = 3" in text
    for f in ("reactions.csv", "reactions.json", "reactions_peaks.json", "tolerance.json",
              "tolerance_samples.csv"):
        assert (out / f).stat().st_size > 0
    # the CSV equals a direct solve of the file's problem
    import csv

    with (out / "reactions.csv").open() as fh:
        rows = list(csv.reader(fh))
    head = rows[0]
    data = np.array(rows[1:], float)
    mech, kw, spec = load_problem(SPATIAL_EXAMPLE)
    from linkwork.cli.reactions import _model_inputs

    r = rd.spatial_reactions(mech, kw["cycle"], gravity=kw["gravity"],
                             loads=kw["loads"](kw["cycle"]), **_model_inputs(mech, spec))
    assert np.allclose(data[:, head.index("mx_B [N*m]")], r.mx[2], rtol=1e-12, atol=1e-15)
    assert np.allclose(data[:, head.index("Q [N*m]")], r.Q, rtol=1e-12, atol=1e-15)


def _write(tmp_path, text):
    p = tmp_path / "m.toml"
    p.write_text(text)
    return p


BROKEN = {
    "unknown_spatial_key": ("[spatial]\nstiff = 1\n", "spatial.stiff"),
    "unknown_joint": ("[spatial.joints.Z]\ne = '30 mm'\n", "spatial.joints.Z"),
    "e_units": ("[spatial.joints.A]\ne = '30 kg'\n", "spatial.joints.A.e"),
    "e_negative": ("[spatial.joints.A]\ne = '-30 mm'\n", "spatial.joints.A.e"),
    "kind": ("[spatial.joints.A]\nkind = 'ball'\n", "spatial.joints.A.kind"),
    "kind_family": ("[spatial.joints.A]\nkind = 'prismatic'\n", "A.kind"),
    "stiffness_zero": ("[spatial.joints.A]\nstiffness = [1e8, 1e8, 0, 7e3, 7e3, 0]\n",
                       "A.stiffness"),
    "stiffness_len": ("[spatial.joints.A]\nstiffness = [1e8, 1e8]\n",
                      "spatial.joints.A.stiffness"),
    "stiffness_units": ("[spatial.joints.A]\nstiffness = ['1 kg', 1e8, 1e8, 7e3, 7e3, 0]\n",
                        "spatial.joints.A.stiffness"),
    "k_units": ("[spatial]\nk_bearing = '100 mm'\n", "spatial.k_bearing"),
    "k_zero": ("[spatial]\nk_bearing = 0\n", "spatial.k_bearing"),
    "positions": ("[spatial]\npositions = 3\n", "spatial.positions"),
    "dev_missing_joint": ("[[spatial.deviation]]\nbody = 'frame'\ntx = '1 mrad'\n",
                          "spatial.deviation.0.joint"),
    "dev_unknown_joint": ("[[spatial.deviation]]\njoint = 'Z'\nbody = 'frame'\n",
                          "spatial.deviation.0.joint"),
    "dev_wrong_body": ("[[spatial.deviation]]\njoint = 'A'\nbody = 'frame'\n",
                       "spatial.deviation.0.body"),
    "dev_units": ("[[spatial.deviation]]\njoint = 'C'\nbody = 'frame'\ntx = '1 mm'\n",
                  "spatial.deviation.0.tx"),
    "heights_body": ("[spatial]\nheights = { nope = '1 mm' }\n", "spatial.heights.nope"),
    "oop_body": ("[[spatial.out_of_plane]]\nbody = 'nope'\nfz = '1 N'\n",
                 "spatial.out_of_plane.0.body"),
    "tol_limit": ("[[spatial.tolerance]]\njoint = 'C'\nbody = 'frame'\ncomponent = 'tx'\n"
                  "limit = '-1 mrad'\n", "spatial.tolerance.0.limit"),
    "tol_component": ("[[spatial.tolerance]]\njoint = 'C'\nbody = 'frame'\n"
                      "component = 'zz'\nlimit = '1 mrad'\n", "spatial.tolerance.0.component"),
    "tol_units": ("[[spatial.tolerance]]\njoint = 'C'\nbody = 'frame'\ncomponent = 'tx'\n"
                  "limit = '1 mm'\n", "spatial.tolerance.0.limit"),
    "tol_joint": ("[[spatial.tolerance]]\njoint = 'Z'\nbody = 'frame'\ncomponent = 'tx'\n"
                  "limit = '1 mrad'\n", "spatial.tolerance.0.joint"),
    "tol_body": ("[[spatial.tolerance]]\njoint = 'A'\nbody = 'frame'\ncomponent = 'tx'\n"
                 "limit = '1 mrad'\n", "spatial.tolerance.0.body"),
    "spatial_not_table": ("spatial = 3\n", "spatial"),
}


@pytest.mark.parametrize("case", sorted(BROKEN))
def test_cli_reactions_broken_files_one_line_exit_2(tmp_path, capsys, case):
    """The mechanism of the example with only the broken [spatial] data."""
    extra, word = BROKEN[case]
    text = SPATIAL_EXAMPLE.read_text()
    text = text[:text.index("\n[spatial]\n") + 1] + extra
    if case == "spatial_not_table":  # a top-level key must come before the first table
        text = extra + text[:-len(extra)]
    rc = main(["reactions", str(_write(tmp_path, text)), "--out", str(tmp_path / "o"),
               "--no-plots", "--tolerance-study", "5"])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert len(err.strip().splitlines()) == 1, err
    assert word in err, err


@pytest.mark.parametrize("args, word", [
    (["--tolerance-study", "0"], "--tolerance-study"),
    (["--tolerance-study", "-5"], "--tolerance-study"),
    (["--tolerance-study", "x"], "tolerance-study"),
    (["--method", "fem"], "--method"),
    (["--chunk-size", "0"], "chunk"),
    (["--seed", "-1"], "seed"),
    (["--seed", "-1", "--tolerance-study", "5"], "seed"),
    (["--angles", "a,b"], "angle"),
])
def test_cli_reactions_bad_options_one_line_exit_2(tmp_path, capsys, args, word):
    rc = main(["reactions", str(SPATIAL_EXAMPLE), "--out", str(tmp_path / "o"), "--no-plots",
               *args])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert len(err.strip().splitlines()) == 1, err
    assert word in err, err


def test_cli_tolerance_study_without_tolerances(tmp_path, capsys):
    text = SPATIAL_EXAMPLE.read_text()
    text = text[:text.index("[[spatial.tolerance]]")]
    rc = main(["reactions", str(_write(tmp_path, text)), "--out", str(tmp_path / "o"),
               "--no-plots", "--tolerance-study", "10"])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1, err
    assert "tolerance" in err


def test_cli_reactions_says_that_it_leaves_friction_out(tmp_path, capsys):
    """The crank press has friction in its four joints; the spatial reactions (paper 004) are
    frictionless, so their driving torque is the frictionless one (peak 6777 N·m against
    analyze's 8116 N·m): the command says so in one note naming the joints; the frictionless
    loom example prints no such note."""
    press = Path(EXAMPLE).parent / "crank_press.toml"
    assert main(["reactions", str(press), "--out", str(tmp_path / "a"), "--no-plots"]) == 0
    out = capsys.readouterr().out
    assert ("note: the spatial reactions are frictionless (paper 004's equations): the "
            "friction of joints O, A, B, guide is not used here (linkwork analyze includes "
            "it)") in out
    assert main(["reactions", EXAMPLE, "--out", str(tmp_path / "b"), "--no-plots"]) == 0
    assert "friction" not in capsys.readouterr().out.split("\nwritten")[0]
