"""``studies.planar.analyze`` of a planar file with friction: the summary is the engine's
(losses, efficiency, self-locking), the columns with friction appear only with friction, and
the losses close the work balance over the cycle (driver's work = useful work + losses)."""


import numpy as np
import pytest
from _cli_files import EXAMPLES, sine_press_with_friction

from linkwork import io
from linkwork.planar import inverse_dynamics, kinematics
from linkwork.studies import planar as study_planar


def test_friction_summary_is_the_engines(tmp_path):
    doc = io.load(sine_press_with_friction(tmp_path))
    study = study_planar.analyze(doc)
    fr = study.friction
    assert fr is not None
    mech = doc.mechanism()
    phi = doc.positions()
    dyn = inverse_dynamics(kinematics(mech, phi), gravity=doc.analysis.gravity,
                           loads=doc.loads(phi), about=doc.analysis.about)
    assert fr["efficiency_cycle"] == dyn.efficiency_cycle
    assert list(fr["losses"].values()) == list(dyn.friction_losses)
    assert fr["self_locking"] == [] and fr["locked_positions"] == 0
    # the work balance over the closed cycle: driver's work = useful work + losses, where
    # the useful work is the frictionless driver's work (same motion, same loads)
    useful = np.trapezoid(dyn.Q_frictionless, phi)
    assert fr["driving_work"] == pytest.approx(useful + sum(fr["losses"].values()), rel=1e-6)
    assert fr["efficiency_cycle"] == pytest.approx(useful / fr["driving_work"], rel=1e-6)
    assert sum(fr["loss_share"].values()) == pytest.approx(1 - fr["efficiency_cycle"])
    cols = study.dynamics_columns()
    for key in ("Q_frictionless", "Pf_A", "Pf_guide", "Pf_slot", "efficiency", "locked"):
        assert key in cols
        assert key not in study.kinematics_columns()
    assert np.array_equal(cols["Pf_slot"][0], dyn.friction_power[2])
    assert study.to_dict()["friction"] == fr


def test_frictionless_file_has_no_friction_output():
    study = study_planar.analyze(io.load(EXAMPLES / "sine_press_planar.toml"))
    assert study.friction is None and "friction" not in study.to_dict()
    cols = study.dynamics_columns()
    assert not any(k.startswith("Pf_") or k in ("Q_frictionless", "efficiency", "locked")
                   for k in cols)


def test_self_locking_ranges_in_the_study(tmp_path):
    """Slot at 12 deg, below the friction angles' sum 12.55 deg (paper 000): locked runs."""
    study = study_planar.analyze(io.load(sine_press_with_friction(tmp_path, '"12 deg"')))
    fr = study.friction
    assert fr is not None and fr["locked_positions"] > 0
    assert fr["efficiency_cycle"] is None and fr["driving_work"] is None
    locked = study.dynamics.locked
    assert sum(int(np.sum((study.positions >= a) & (study.positions <= b)))
               for a, b in fr["self_locking"]) == int(locked.sum())
