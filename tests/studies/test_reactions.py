"""studies.reactions: the spatial reactions of a planar file with its [spatial] section, against
linkwork.redundancy called directly; the cycle's kinematics solved once."""

import contextlib
import sys
from pathlib import Path
from unittest import mock

import numpy as np
import pytest

from linkwork import io, planar
from linkwork import redundancy as rd
from linkwork.cli import main
from linkwork.errors import ParameterError
from linkwork.studies import planar as study_planar
from linkwork.studies import reactions as study_reactions

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "loom_fourbar_spatial.toml"


def _direct(doc, phi):
    spec = doc.spatial
    return rd.spatial_reactions(
        doc.mechanism(), phi, gravity=doc.analysis.gravity, loads=doc.loads(phi),
        joints=spec.joint_kwargs(), default=spec.default_kwargs(), heights=dict(spec.heights),
        out_of_plane=[rd.OutOfPlaneLoad(o.body, o.fz, o.mx, o.my) for o in spec.out_of_plane],
        deviations=[rd.Deviation(d.joint, d.body, d.dx, d.dy, d.dz, d.tx, d.ty, d.tz)
                    for d in spec.deviation])


@pytest.mark.parametrize("method", ["force", "displacement"])
def test_study_equals_spatial_reactions_called_directly(method, capsys):
    doc = io.load(EXAMPLE)
    angles = np.radians([0.0, 90.0, 180.0, 270.0])
    study = study_reactions.run(doc, angles=angles, method=method)
    assert capsys.readouterr() == ("", "")  # a study prints nothing
    cycle = doc.positions()
    if doc.spatial.positions:
        cycle = np.linspace(cycle[0], cycle[-1], doc.spatial.positions)
    ref = _direct(doc, cycle) if method == "force" else None
    if ref is not None:
        np.testing.assert_allclose(study.reactions.components(), ref.components(),
                                   rtol=1e-12, atol=1e-9)
        np.testing.assert_allclose(study.reactions.Q, ref.Q, rtol=1e-12, atol=1e-12)
        at = _direct(doc, angles)
        np.testing.assert_allclose(study.table.components(), at.components(), rtol=1e-12,
                                   atol=1e-9)
        assert study.peaks == ref.peaks()
    model = rd.spatial_model(doc.mechanism(), doc.spatial.joint_kwargs(),
                             doc.spatial.default_kwargs())
    geom = rd.geometry(doc.mechanism(), planar.kinematics(doc.mechanism(), cycle))
    count = rd.count_redundancy(model, geom, position=len(cycle) // 7)
    assert study.count.redundant == count.redundant
    assert study.count.summary() == count.summary()


def test_tolerance_study_needs_tolerances_and_names_the_option():
    text = EXAMPLE.read_text()
    doc = io.load(EXAMPLE)
    study = study_reactions.run(doc, angles=np.radians([0.0]))
    tol = study_reactions.tolerance(study, 40, seed=1, chunk_size=20)
    assert tol.n_samples == 40
    assert tol.joints == study.reactions.joints
    no_tol = doc.model_copy(update={"spatial": doc.spatial.model_copy(update={"tolerance": []})})
    with pytest.raises(ParameterError) as exc:
        study_reactions.tolerance(study_reactions.run(no_tol, angles=np.radians([0.0])), 5)
    assert exc.value.parameter == "--tolerance-study"
    assert "[[spatial.tolerance]]" in text


def test_reactions_solves_the_cycle_kinematics_once(tmp_path, capsys):
    """`linkwork reactions` solved the kinematics three times before the studies (twice over
    the cycle: inside spatial_reactions and again for the count and the tolerance study; once
    at the table positions) and decomposed the mechanism twice; now the cycle once, the table
    once, one decomposition."""
    kin = mock.Mock(wraps=planar.kinematics)
    analyse = mock.Mock(wraps=sys.modules["linkwork.planar.structure"].analyse)
    with contextlib.ExitStack() as stack:
        stack.enter_context(mock.patch.object(study_reactions, "kinematics", kin))
        for name in ("linkwork.planar.structure", "linkwork.planar.model"):
            if hasattr(sys.modules[name], "analyse"):
                stack.enter_context(mock.patch.object(sys.modules[name], "analyse", analyse))
        assert main(["reactions", str(EXAMPLE), "--out", str(tmp_path), "--no-plots",
                     "--tolerance-study", "20"]) == 0
    capsys.readouterr()
    assert kin.call_count == 2
    assert analyse.call_count == 1


DRIVERS = ROOT / "tests" / "data" / "drivers" / "five_bar_two_cranks.toml"


def _with_spatial(path, tmp_path, spatial):
    f = tmp_path / path.name
    f.write_text(path.read_text() + spatial)
    return io.load(f)


@pytest.mark.parametrize("path, spatial", [
    (DRIVERS, '\n[spatial]\npositions = 31\ndefault = { e = "25 mm" }\n'
              'joints.O2 = { z = "-10 mm", e = "40 mm" }\nheights = { l1 = "8 mm" }\n'
              '[[spatial.deviation]]\njoint = "P"\nbody = "l2"\ntx = "0.2 mrad"\n'),
    (ROOT / "examples" / "excavator_boom.toml",
     '\n[spatial]\ndefault = { e = "60 mm" }\njoints.E = { z = "30 mm" }\n'
     '[[spatial.deviation]]\njoint = "O"\nbody = "frame"\nty = "0.3 mrad"\n'),
], ids=["two cranks", "three cylinders"])
def test_several_drivers_study_equals_spatial_reactions_along_the_path(path, spatial, tmp_path):
    """A file of several drivers: the study's cycle is the drivers' path (resampled by [spatial]
    positions, each driver from its start to its stop), its table the 12 positions of every
    command along it; both equal linkwork.redundancy called directly with those positions."""
    doc = _with_spatial(path, tmp_path, spatial)
    study = study_reactions.run(doc)
    phi = doc.positions()
    cyc = (np.linspace(phi[:, 0], phi[:, -1], doc.spatial.positions, axis=1)
           if doc.spatial.positions else phi)
    np.testing.assert_array_equal(study.cycle, cyc)
    direct = _direct(doc, cyc)
    assert study.reactions.Q.shape == (2 if path == DRIVERS else 3, cyc.shape[1])
    np.testing.assert_allclose(study.reactions.components(), direct.components(), rtol=0,
                               atol=1e-12 * np.abs(direct.components()).max())
    np.testing.assert_allclose(study.reactions.Q, direct.Q, rtol=1e-12)
    tphi = study_planar.default_table_positions(doc)
    np.testing.assert_array_equal(study.table_positions, tphi)
    at = _direct(doc, tphi)
    np.testing.assert_allclose(study.table.components(), at.components(), rtol=0,
                               atol=1e-12 * np.abs(at.components()).max())
    assert study.linear_drivers == tuple(d.kind == "linear" for d in doc.mechanism().drivers)
    assert np.abs(study.reactions.my).max() > 0  # the deviation and heights load the joints
    peaks = study.peaks_dict()["peaks"]["driver"]
    for k, d in enumerate(doc.mechanism().drivers):
        assert peaks[f"Q {d.joint}"] == pytest.approx(np.abs(direct.Q[k]).max(), rel=1e-12)


def test_several_drivers_need_their_path():
    doc = io.load(DRIVERS)
    with pytest.raises(ParameterError, match=r"cycle .*path of the 2 drivers"):
        study_reactions.solve(doc.mechanism(), doc.spatial, angles=doc.positions()[:, :3])
    with pytest.raises(ParameterError, match=r"angles = shape \(3,\).*one row per driver"):
        study_reactions.solve(doc.mechanism(), doc.spatial, angles=[0.1, 0.2, 0.3],
                              cycle=doc.positions())
