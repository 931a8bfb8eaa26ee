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


def test_several_drivers_are_balanced_along_their_path(tmp_path, capsys):
    """A two-crank five-bar: the path study's counterweights are those of
    centre_of_mass_balance on the file's path; its shaking loads and each driver's Q before and
    after are the engine's on the unbalanced and balanced mechanisms (gravity and loads in Q);
    `linkwork balance` prints them, says what is not computed and why, and writes the path's
    columns and the summary. A crank cycle's [balance] keys are refused by name."""
    from linkwork.balancing.mechanism import centre_of_mass_balance, shaking_loads
    from linkwork.cli import main
    from linkwork.planar import inverse_dynamics, kinematics
    from linkwork.studies import balance as study_balance

    path = ROOT / "tests" / "data" / "drivers" / "five_bar_two_cranks.toml"
    doc = io.load(path)
    s = study_balance.run_path(doc)
    phi = doc.positions()
    fb = centre_of_mass_balance(kinematics(doc.mechanism(), phi))
    assert [c.static_moment for c in s.balance.counterweights] == pytest.approx(
        [c.static_moment for c in fb.counterweights], rel=1e-12)
    kb = kinematics(fb.mechanism, phi)
    np.testing.assert_allclose(s.after.fx, shaking_loads(kb).fx, rtol=0, atol=1e-12)
    d1 = inverse_dynamics(kb, gravity=doc.analysis.gravity, loads=doc.loads(phi))
    np.testing.assert_allclose(s.dynamics_after.Q, d1.Q, rtol=1e-12)
    assert s.table_positions.shape == (2, 12) and s.table_Q1.shape == (2, 12)
    d = s.to_dict()
    assert set(d["summary"]) >= {"Q O1 peak [N*m]", "frame joint O2 peak [N]"}
    assert "moved crank-counterweight axis" in d["not_computed"]
    code = main(["balance", str(path), "--out", str(tmp_path / "o")])
    out = capsys.readouterr().out
    assert code == 0 and "along their path" in out and "not computed:" in out
    head = (tmp_path / "o" / "balance_path.csv").read_text().splitlines()[0]
    assert head.startswith("phi1.O1 [rad],phi1.O2 [rad],Fx0 [N]") and "Q1.O2 [N*m]" in head
    assert (tmp_path / "o" / "balancing_path.png").stat().st_size > 0
    bad = tmp_path / "bad.toml"
    bad.write_text(path.read_text() + "\n[balance]\nangles = [0, 30]\n")
    with pytest.raises(ParameterError, match=r"balance\.angles .*crank cycle"):
        study_balance.run_path(io.load(bad))
