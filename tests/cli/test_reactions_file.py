"""`linkwork reactions FILE.toml` end to end on the bundled example (a planar-engine file with a
[spatial] table), in-process."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("linkwork.planar.file")  # registers the engine's 'planar' schema

from linkwork.cli import main
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
