"""studies.planar.analyze: a planar file over its cycle as one result object, checked against
the engine's public functions called directly; the mechanism built and decomposed once."""

import contextlib
import sys
from pathlib import Path
from unittest import mock

import numpy as np
import pytest

import linkwork.planar.model
import linkwork.planar.structure
from linkwork import io, planar
from linkwork.balancing.loads import mean_over_range
from linkwork.cli import main
from linkwork.errors import ParameterError
from linkwork.studies import planar as study_planar

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples").glob("*.toml"))
PLANAR = [p for p in [*EXAMPLES, *(ROOT / "tests" / "data").glob("*.toml")]
          if io.read_toml(p)["type"] == "planar"]


@contextlib.contextmanager
def count_decompositions():
    """Count the structure analyses (Assur-group decompositions) run inside the block."""
    calls = mock.Mock(wraps=linkwork.planar.structure.analyse)
    with contextlib.ExitStack() as stack:
        for module in (linkwork.planar.structure, linkwork.planar.model):
            if hasattr(module, "analyse"):
                stack.enter_context(mock.patch.object(module, "analyse", calls))
        yield calls


@pytest.mark.parametrize("path", PLANAR, ids=lambda p: p.name)
def test_study_equals_the_engine_called_directly(path, capsys):
    doc = io.load(path)
    study = study_planar.analyze(doc)
    assert capsys.readouterr() == ("", "")  # a study prints nothing
    mech = doc.mechanism()
    phi = doc.positions()
    kin = planar.kinematics(mech, phi)
    dyn = planar.inverse_dynamics(kin, gravity=doc.analysis.gravity, loads=doc.loads(phi),
                                  about=doc.analysis.about)
    np.testing.assert_array_equal(study.kinematics.phi1, phi)
    for name in ("theta", "omega", "eps", "x", "y"):
        np.testing.assert_array_equal(getattr(study.kinematics, name), getattr(kin, name))
    for name in ("fx", "fy", "mz", "Q", "shaking_fx", "shaking_fy", "shaking_m", "T"):
        np.testing.assert_array_equal(getattr(study.dynamics, name), getattr(dyn, name))
    # the table: the default positions (tested below), solved on their own
    tphi = study_planar.default_table_positions(doc)
    np.testing.assert_array_equal(study.table_positions, tphi)
    tdyn = planar.inverse_dynamics(planar.kinematics(mech, tphi), gravity=doc.analysis.gravity,
                                   loads=doc.loads(tphi), about=doc.analysis.about)
    np.testing.assert_array_equal(study.table_dynamics.Q, tdyn.Q)
    assert study.dead_centres == planar.dead_centres(kin)
    trans = planar.transmission_angles(kin)
    assert list(study.transmission) == list(trans)
    for key, (mu, _) in trans.items():
        np.testing.assert_array_equal(study.transmission[key][0], mu)
        pk = next(p for p in study.peaks if p["name"] == f"μ {key} min")
        assert pk["value"] == np.nanmin(mu)
    q = {p["name"]: p for p in study.peaks}
    for name, (qd, _) in study_planar.driver_columns(mech, {"Q": dyn.Q}).items():
        label = name.replace(".", " ")  # several drivers: one entry per driver, "Q O1 max"
        assert q[f"{label} max"]["value"] == np.nanmax(qd)
        assert q[f"{label} min"]["value"] == np.nanmin(qd)
    if mech.n_drivers == 1:
        assert q["Q max"]["phi1"] == phi[np.nanargmax(dyn.Q)]
        assert study.means == {"Q_mean": mean_over_range(phi, dyn.Q),
                               "power_mean": mean_over_range(phi, dyn.power)}
    else:  # the drivers' positions at the extreme, and each driver's mean load
        k = int(np.nanargmax(dyn.Q[0]))
        assert q[f"Q {mech.drivers[0].joint} max"]["phi1"] == list(phi[:, k])
        assert study.means["Q_mean"] == {d.joint: mean_over_range(phi[i], dyn.Q[i])
                                         for i, d in enumerate(mech.drivers)}


def test_study_at_given_table_positions_and_outside_the_range():
    doc = io.load(ROOT / "examples" / "fourbar_paper001.toml")
    angles = np.radians([10.0, 200.0])
    study = study_planar.analyze(doc, angles=angles)
    direct = planar.kinematics(doc.mechanism(), angles)
    np.testing.assert_array_equal(study.table_kinematics.theta, direct.theta)
    doc = io.load(ROOT / "tests" / "data" / "slider_driven_crank.toml")
    with pytest.raises(ParameterError) as exc:  # slide positions beyond the stroke
        study_planar.analyze(doc, angles=np.array([5.0]))
    assert exc.value.parameter == "--angles"


def test_cli_json_is_the_study(tmp_path, capsys):
    """planar.json of `linkwork analyze` holds the study's columns, peaks and means."""
    path = ROOT / "examples" / "loom_sixbar.toml"
    assert main(["analyze", str(path), "--out", str(tmp_path)]) == 0
    capsys.readouterr()
    import json

    data = json.loads((tmp_path / "planar.json").read_text())
    study = study_planar.analyze(io.load(path))
    assert data["peaks"] == study.peaks
    assert data["means"]["Q_mean"] == study.means["Q_mean"]
    for key, (values, unit) in study.columns().items():
        assert data["units"][key] == unit
        np.testing.assert_allclose(np.array(data["columns"][key], float), values,
                                   rtol=0, atol=0, equal_nan=True)


def test_analyze_builds_and_decomposes_the_mechanism_once(tmp_path, capsys):
    """`linkwork analyze` on a planar file decomposed the mechanism four times (the file's
    validator, the analyser, and once per solve of the cycle and of the table) before the
    studies; now once: the file builds it, the study reuses it. The kinematics is solved twice,
    for the cycle and for the table positions."""
    path = ROOT / "examples" / "fourbar_paper001.toml"
    kin = mock.Mock(wraps=planar.kinematics)
    with count_decompositions() as analyse, mock.patch.object(study_planar, "kinematics", kin):
        assert main(["analyze", str(path), "--out", str(tmp_path)]) == 0
    capsys.readouterr()
    assert analyse.call_count == 1
    assert kin.call_count == 2


def test_distinct_paths_alias():
    from linkwork.cli._planar import _distinct_paths

    assert _distinct_paths is study_planar.distinct_paths
    assert sys.modules["linkwork.cli._planar"].cycle_peaks is study_planar.cycle_peaks


def _with_range(path: Path, tmp_path: Path, start: str, stop: str) -> io.PlanarFile:
    text = path.read_text()
    data = io.read_toml(path)["analysis"]
    old = f'start = "{data["start"]}"\nstop = "{data["stop"]}"'
    assert old in text
    f = tmp_path / path.name
    f.write_text(text.replace(old, f'start = "{start}"\nstop = "{stop}"'))
    return io.load(f)


def test_default_table_positions_crank_every_30_deg_of_the_range(tmp_path):
    ex = ROOT / "examples" / "fourbar_paper001.toml"
    whole = study_planar.default_table_positions(io.load(ex))
    np.testing.assert_allclose(np.degrees(whole), np.arange(0, 360, 30), atol=1e-12)
    part = study_planar.default_table_positions(_with_range(ex, tmp_path, "20 deg", "200 deg"))
    np.testing.assert_allclose(np.degrees(part), np.arange(30, 181, 30), atol=1e-12)
    # a range holding fewer than 4 multiples of 30 deg: 12 positions over it, ends included
    small = study_planar.default_table_positions(_with_range(ex, tmp_path, "5 deg", "65 deg"))
    np.testing.assert_allclose(np.degrees(small), np.linspace(5, 65, 12), atol=1e-12)


def test_default_table_positions_linear_driver_over_its_range():
    doc = io.load(ROOT / "tests" / "data" / "slider_driven_crank.toml")
    phi = doc.positions()
    np.testing.assert_array_equal(study_planar.default_table_positions(doc),
                                  np.linspace(phi[0], phi[-1], 12))


@pytest.mark.parametrize("path", PLANAR, ids=lambda p: p.name)
def test_every_command_tables_the_same_default_positions(path):
    """analyze and reactions, on crank and linear drivers alike, table the same positions by
    default, and they lie where the file says the mechanism works."""
    from linkwork.studies import reactions as study_reactions
    doc = io.load(path)
    tphi = study_planar.default_table_positions(doc)
    phi = doc.positions()
    if phi.ndim == 2:  # several drivers: 12 positions along the path, each driver's ends
        np.testing.assert_array_equal(tphi[:, [0, -1]], phi[:, [0, -1]])
        assert tphi.shape == (phi.shape[0], 12)
        np.testing.assert_array_equal(study_planar.analyze(doc).table_positions, tphi)
        if all(j.spatial_family is not None for j in doc.mechanism().joints):
            np.testing.assert_array_equal(study_reactions.run(doc).table_positions, tphi)
        return
    assert phi[0] - 1e-12 <= tphi.min() and tphi.max() <= phi[-1] + 1e-12
    np.testing.assert_array_equal(study_planar.analyze(doc).table_positions, tphi)
    if all(j.spatial_family is not None for j in doc.mechanism().joints):
        # (the spatial reactions take no pin-in-slot joint)
        np.testing.assert_array_equal(study_reactions.run(doc).table_positions, tphi)
