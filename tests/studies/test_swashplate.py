"""studies.swashplate: a swash-plate file analysed and designs synthesised, against
linkwork.models.swashplate and linkwork.synthesis.swashplate called directly."""

import math
from pathlib import Path

import numpy as np
import pytest

from linkwork import io
from linkwork.models import swashplate as sw
from linkwork.studies import swashplate as study_swashplate
from linkwork.synthesis import swashplate as syn

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples").glob("swashplate_*.toml"))


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_analysis_equals_the_model_called_directly(path, capsys):
    doc = io.load(path)
    angles = np.radians([0.0, 100.0, 250.0])
    study = study_swashplate.analyze(doc, angles=angles)
    assert capsys.readouterr() == ("", "")  # a study prints nothing
    d = doc.design()
    omega = doc.operation.omega
    table = sw.analyze(d, angles, omega=omega)
    for name in ("s", "delta_z", "Pi_v", "Pi_a", "v", "acc"):
        np.testing.assert_array_equal(getattr(study.table, name), getattr(table, name))
    c = sw.characteristics(*d.params)
    assert study.characteristics.H == pytest.approx(float(c.H), rel=1e-12)
    cycle = sw.analyze(d, np.linspace(0.0, 2 * math.pi, doc.output.samples), omega=omega)
    np.testing.assert_array_equal(study.cycle.s, cycle.s)
    err = sw.harmonic_error(*d.params)
    assert study.summary["harmonic_error_max"] == float(err["max"])
    if omega > 0:
        assert study.summary["v_max"] == omega * float(table.characteristics.Pi_v_max)
    if doc.operation.delta_allow is not None:
        assert study.summary["delta_allow_met"] == (
            max(float(c.delta_f), float(c.delta_r)) <= doc.operation.delta_allow)
    f = doc.drive_forces()
    assert (study.forces is None) == (f is None)
    if f is not None:
        np.testing.assert_allclose(study.forces.M_total, f.M_total, rtol=1e-12)
        assert study.summary["peak_rod_force"] == float(np.max(np.abs(f.S)))
    assert study.to_dict()["design"] == d.as_dict()


def test_synthesis_equals_synthesize_called_directly(capsys):
    req = syn.Request(scheme="1", R=0.1, H=0.06, H_tol=0.0003, delta_f=math.radians(10),
                      delta_r=math.radians(10))
    study = study_swashplate.synthesize(req, n_candidates=256, n_best=3, n_refine=1,
                                        region_n=8)
    assert capsys.readouterr() == ("", "")
    res = syn.synthesize(req, n_candidates=256, n_best=3, n_refine=1, seed=0)
    for key in ("r", "l", "alpha", "H", "L"):
        np.testing.assert_array_equal(study.result.table[key], res.table[key])
    names = list(req.free)[:2]
    assert study.region_names == (names[0], names[1])
    reg = syn.feasible_region(req, res.best, names[0], names[1], n=8)
    np.testing.assert_array_equal(study.region.feasible, reg.feasible)
