"""``studies.planar.analyze`` of the crank press example (``examples/crank_press.toml``): a
drawing-force diagram over the ram's stroke, a preloaded counterbalance spring, friction.

References, written out here: the ram's slide ``s = r sin(phi) - sqrt(l^2 - r^2 cos^2(phi))``
(branch: the ram below the shaft) and its rate; the diagram interpolated by hand from the
file's table; the spring's length ``-s``, tension and energy; the work of the drawing force
over a stroke, the area under the table by the trapezoid rule (2920 J); the power balance
``Q omega1 = dT/dt - P_drawing - P_spring - P_gravity + sum P_friction`` with those hand
powers, to 1e-9 of the largest term.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from _mechanisms import kinetic_energy_rate

from linkwork import io
from linkwork.studies import planar as study_planar

PRESS = Path(__file__).resolve().parents[2] / "examples" / "crank_press.toml"
R, L_ROD, W = 0.05, 0.4, 2 * np.pi  # crank, rod [m]; 60 rpm [rad/s]
TABLE_S = np.array([-0.450, -0.446, -0.442, -0.438, -0.434, -0.430])
TABLE_F = np.array([100e3, 150e3, 190e3, 200e3, 140e3, 0.0])
K, L0, F0 = 5000.0, 0.4, 2500.0  # the counterbalance


def _ram(phi):
    """Slide s of the wrist pin B on the vertical guide (y of B) and ds/dphi."""
    root = np.sqrt(L_ROD**2 - (R * np.cos(phi)) ** 2)
    return R * np.sin(phi) - root, R * np.cos(phi) - R * R * np.cos(phi) * np.sin(phi) / root


def _drawing(phi):
    """The drawing force by hand: the table where the ram is inside it and moving down."""
    s, ds = _ram(phi)
    inside = (s >= TABLE_S[0] - 1e-12) & (s <= TABLE_S[-1] + 1e-12)
    return np.where(inside & (ds * W <= 1e-9 * W * 0.45), np.interp(s, TABLE_S, TABLE_F), 0.0)


@pytest.fixture(scope="module")
def study():
    return study_planar.analyze(io.load(PRESS))


def test_press_columns_against_hand_computations(study):
    phi = study.positions
    s, ds = _ram(phi)
    cols = study.dynamics_columns()
    F = _drawing(phi)
    np.testing.assert_allclose(cols["F_drawing"][0], F, rtol=0, atol=1e-9 * 200e3)
    assert np.count_nonzero(F) > 40  # 20 mm of a 100 mm stroke, the way down
    np.testing.assert_allclose(cols["P_drawing"][0], F * ds * W, rtol=0,
                               atol=1e-9 * 200e3 * R * W)
    L = -s
    np.testing.assert_allclose(cols["L_counterbalance"][0], L, rtol=0, atol=1e-12)
    np.testing.assert_allclose(cols["F_counterbalance"][0], F0 + K * (L - L0), rtol=0,
                               atol=1e-9 * F0)
    np.testing.assert_allclose(cols["V"][0], F0 * (L - L0) + 0.5 * K * (L - L0) ** 2, rtol=0,
                               atol=1e-12 * F0 * R)
    assert [cols[k][1] for k in ("F_drawing", "P_drawing", "L_counterbalance", "V")] == [
        "N", "W", "m", "J"]
    for k in ("F_drawing", "P_drawing", "F_counterbalance", "L_counterbalance",
              "P_counterbalance", "V"):
        assert k not in study.kinematics_columns()


def test_press_power_balance_with_friction(study):
    """Q omega1 = dT/dt - P_drawing - P_spring - P_gravity + sum P_friction, the drawing's
    and the spring's power written out here (F ds/dt; the spring pulls B's point R up with
    its tension, -T dL/dt = T ds/dt)."""
    kin, dyn = study.kinematics, study.dynamics
    phi = study.positions
    s, ds = _ram(phi)
    dT, pg = kinetic_energy_rate(study.mechanism, kin, (0.0, -9.81))
    p_draw = _drawing(phi) * ds * W
    p_spring = (F0 + K * (-s - L0)) * ds * W
    lhs = dyn.Q * W
    rhs = dT - p_draw - p_spring - pg + dyn.friction_power.sum(axis=0)
    scale = max(np.max(np.abs(lhs)), np.max(np.abs(p_draw)))
    assert np.max(np.abs(lhs - rhs)) <= 1e-9 * scale
    assert dyn.friction_power.sum() > 0


def test_work_of_the_drawing_is_the_area_under_its_table(tmp_path):
    """Over one stroke the drawing force takes from the mechanism the area under its table,
    sum (F_i + F_i+1) / 2 (s_i+1 - s_i) = 2920 J; sampled every 0.005 deg over the working
    part of the turn the trapezoid of the power over time agrees to 1e-6 (its error is
    second order in the step, the diagram having kinks between samples). The counterbalance
    does no work over the whole turn (1e-9 of its energy range)."""
    area = float(np.sum((TABLE_F[1:] + TABLE_F[:-1]) / 2 * np.diff(TABLE_S)))
    assert area == pytest.approx(2920.0, rel=1e-15)
    text = PRESS.read_text().replace('start = "0 deg"\nstop = "360 deg"\nn = 721',
                                     'start = "200 deg"\nstop = "280 deg"\nn = 16001')
    (tmp_path / "press.toml").write_text(text)
    fine = study_planar.analyze(io.load(tmp_path / "press.toml"))
    drawing = next(e for e in fine.loads if e["name"] == "drawing")
    assert drawing["work"] == pytest.approx(-area, rel=1e-6)
    whole = study_planar.analyze(io.load(PRESS))
    spring = next(e for e in whole.loads if e["name"] == "counterbalance")
    assert abs(spring["work"]) <= 1e-9 * K * (2 * R) ** 2
    assert spring["length"] == pytest.approx([L_ROD - R, L_ROD + R], rel=1e-12)
    assert (spring["min"], spring["max"]) == pytest.approx((F0 - K * R, F0 + K * R), rel=1e-12)


def test_summary_states_the_diagram_and_json_carries_it(study):
    drawing = next(e for e in study.loads if e["name"] == "drawing")
    assert drawing["diagram"] == {"over": "guide", "range": [-0.45, -0.43],
                                  "when": "decreasing", "outside": "zero"}
    assert drawing["kind"] == "slide" and drawing["unit"] == "N"
    assert drawing["max"] == pytest.approx(np.max(_drawing(study.positions)), rel=1e-12)
    data = study.to_dict()
    assert data["loads"] == study.loads
    assert "F_drawing" in data["columns"] and data["units"]["V"] == "J"


def test_files_without_force_elements_report_none():
    study = study_planar.analyze(io.load(PRESS.parent / "sine_press_planar.toml"))
    assert study.loads == [] and "loads" not in study.to_dict()
    assert not any(k.startswith(("F_", "P_", "L_")) or k == "V"
                   for k in study.dynamics_columns())
