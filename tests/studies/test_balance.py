"""studies.balance: paper 001's comparison of a planar file, against linkwork.balancing called
directly."""

from pathlib import Path

import numpy as np
import pytest

from linkwork import balancing, io
from linkwork.errors import ParameterError
from linkwork.studies import balance as study_balance

ROOT = Path(__file__).resolve().parents[2]
FOURBAR = ROOT / "examples" / "fourbar_paper001.toml"


def test_study_equals_compare_balancing_called_directly(capsys):
    doc = io.load(FOURBAR)
    study = study_balance.run(doc)
    assert capsys.readouterr() == ("", "")  # a study prints nothing
    comp = balancing.compare_balancing(doc.mechanism(), None, n=360,
                                       gravity=doc.analysis.gravity)
    for name in ("phi1", "M", "dM1", "dM2", "dM3"):
        np.testing.assert_array_equal(getattr(study.comparison, name), getattr(comp, name))
    assert (study.comparison.R2, study.comparison.R3) == (comp.R2, comp.R3)
    assert study.increases == comp.increases()
    h = comp.harmonics(4)
    assert list(study.harmonics) == list(h)
    for key, hv in h.items():
        np.testing.assert_array_equal(study.harmonics[key].amplitude, hv.amplitude)
    assert study.pareto is None and study.pareto_dict() == {}
    s = study.summary()
    assert s["R2"] == comp.R2 and s["summary"] == comp.summary()


def test_section_and_angles(tmp_path):
    f = tmp_path / "m.toml"
    f.write_text(FOURBAR.read_text() + '\n[balance]\nradii = { crank = "50 mm", rocker = '
                 '"100 mm" }\nangles = [0, 90, 180, 270]\nn = 72\n')
    doc = io.load(f)
    study = study_balance.run(doc, angles=[0.0, 45.0, 90.0, 135.0])
    comp = balancing.compare_balancing(doc.mechanism(), np.radians([0.0, 45.0, 90.0, 135.0]),
                                       radii={"crank": 0.05, "rocker": 0.1}, n=72,
                                       gravity=doc.analysis.gravity)
    np.testing.assert_array_equal(study.comparison.dM3, comp.dM3)
    assert [c.radius for c in study.comparison.counterweights] == pytest.approx([0.05, 0.1])
    assert study.section.angles == [0.0, 45.0, 90.0, 135.0]
    assert doc.balance.angles == [0.0, 90.0, 180.0, 270.0]  # the file's section is unchanged


def test_pareto_equals_pareto_set_called_directly():
    doc = io.load(FOURBAR)
    section = doc.balance.model_copy(update={"n": 36})
    study = study_balance.compare(doc.mechanism(), section, pareto=True)
    p = balancing.optimal.pareto_set(doc.mechanism(), static_radii=None, n=36)
    np.testing.assert_allclose(study.pareto.force_rms, p.force_rms, rtol=1e-9)
    assert study.pareto_dict()["dominated"] == p.dominated.tolist()


def test_a_linear_driver_is_refused_with_the_message_of_the_command():
    """As `linkwork balance` says it (the recorded output of tests/data/slider_driven_crank)."""
    doc = io.load(ROOT / "tests" / "data" / "slider_driven_crank.toml")
    with pytest.raises(ParameterError) as exc:
        study_balance.run(doc)
    assert str(exc.value) == ("driver = G is invalid: must be a crank turning about a frame "
                              "joint")
