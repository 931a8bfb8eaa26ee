"""studies.sine_press.analyze: paper 000's press of a file, against the closed forms called
directly."""

from pathlib import Path

import numpy as np

from linkwork import io
from linkwork.models import crank_slider, sine
from linkwork.models.variable_structure import VariableStructureMechanism
from linkwork.studies import sine_press as study_sine_press

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "sine_press.toml"


def test_study_equals_the_closed_forms_called_directly(capsys):
    doc = io.load(EXAMPLE)
    angles = np.radians([0.0, 45.0, 200.0])
    study = study_sine_press.analyze(doc, angles=angles)
    assert capsys.readouterr() == ("", "")  # a study prints nothing
    L1, w1, e1 = doc.crank.L1, doc.crank.speed, doc.crank.eps1
    idle, work = doc.idle, doc.working
    cs = crank_slider.offset_crank_slider(angles, L1, idle.lambda2, idle.lambda_e, w1, e1,
                                          idle.branch)
    np.testing.assert_array_equal(study.table_idle.Y_C, cs.Y_C)
    np.testing.assert_array_equal(study.table_working.X3,
                                  sine.inclined_slot(angles, L1, work.alpha, w1, e1).X3)
    phi = np.linspace(0.0, 2 * np.pi, doc.output.samples_per_revolution + 1)
    np.testing.assert_array_equal(study.working_cycle.V3,
                                  sine.inclined_slot(phi, L1, work.alpha, w1, e1).V3)
    s = study.summary
    assert s["idle"]["stroke_m"] == crank_slider.stroke(L1, idle.lambda2, idle.lambda_e)
    assert s["working"]["stroke_m"] == sine.stroke(L1, work.alpha)
    assert s["working"]["working_range_deg"] == list(
        np.degrees(sine.working_range(work.f_slot, work.f_guide)))
    mech = VariableStructureMechanism(L1=L1, lambda2=idle.lambda2, lambda_e=idle.lambda_e,
                                      alpha=work.alpha, branch=idle.branch, f_slot=work.f_slot,
                                      f_guide=work.f_guide)
    sched = mech.run(doc.segments(), w1, samples_per_revolution=360)
    np.testing.assert_array_equal(study.schedule.t, sched.t)
    assert s["schedule"]["duration_s"] == sched.t[-1]


def test_default_table_angles_are_every_30_degrees():
    study = study_sine_press.analyze(io.load(EXAMPLE))
    np.testing.assert_allclose(np.degrees(study.angles), np.arange(0, 360, 30), atol=1e-12)


def test_no_schedule_no_schedule_result(tmp_path):
    text = EXAMPLE.read_text()
    f = tmp_path / "p.toml"
    f.write_text(text[:text.index("[[schedule]]")] + text[text.index("[output]"):])
    study = study_sine_press.analyze(io.load(f))
    assert study.schedule is None and "schedule" not in study.summary
