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
