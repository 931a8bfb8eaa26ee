"""`linkwork analyze` on sine_press files, in-process through linkwork.cli.main."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
from _cli_files import edit_example_and_run
from _paper000_geometry import crank_slider_positions, slot_positions

from linkwork import files
from linkwork.cli import main
from linkwork.models import crank_slider as cs
from linkwork.models import sine

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "sine_press.toml"

BASE = """
type = "sine_press"
name = "test press"
[crank]
L1 = "{L1}"
speed = "{speed}"
[idle]
lambda2 = {lambda2}
lambda_e = 0.5
[working]
alpha = "{alpha}"
f_slot = 0.1
f_guide = 0.1
{extra}
"""


def _write(tmp_path, L1="50 mm", speed="120 rpm", lambda2="4.0", alpha="60 deg", extra=""):
    f = tmp_path / "press.toml"
    f.write_text(BASE.format(L1=L1, speed=speed, lambda2=lambda2, alpha=alpha, extra=extra))
    return f


def _fail(capsys, args):
    rc = main(args)
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err
    return err


def _read_csv(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    names = [h.split(" [")[0] for h in rows[0]]
    return {n: [float(r[i]) for r in rows[1:]] for i, n in enumerate(names)}


def test_example_runs_and_writes_everything(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["analyze", str(EXAMPLE), "--out", str(out), "--angles", "0,45,90"]) == 0
    text = capsys.readouterr().out
    assert "Y_C" in text and "X3" in text and "jamming" in text
    for name in ("idle_cycle.csv", "idle_cycle.json", "working_cycle.csv",
                 "working_cycle.json", "schedule.csv", "schedule.json", "summary.json",
                 "kinematics.png", "schedule.png", "working_range.png"):
        p = out / name
        assert p.is_file() and p.stat().st_size > 0, name
    for png in out.glob("*.png"):
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    summary = json.loads((out / "summary.json").read_text())
    assert summary["working"]["stroke_m"] == pytest.approx(0.1 / math.sin(math.radians(60)))
    assert [s["t"] for s in summary["schedule"]["switches"]] == pytest.approx([2.5, 4.0, 5.0])


def test_example_cycle_csv_matches_independent_construction(tmp_path, capsys):
    """Reference: the geometric construction of tests/_paper000_geometry.py. Tolerance:
    rel=1e-12, abs=1e-14."""
    out = tmp_path / "out"
    assert main(["analyze", str(EXAMPLE), "--out", str(out)]) == 0
    capsys.readouterr()
    idle = _read_csv(out / "idle_cycle.csv")
    work = _read_csv(out / "working_cycle.csv")
    assert len(idle["phi1"]) == 361
    for k in (0, 37, 90, 200, 333):
        p = idle["phi1"][k]
        g = crank_slider_positions(p, 0.05, 4.0, 0.5)
        assert idle["Y_C"][k] == pytest.approx(g["Y_C"], rel=1e-12)
        x3 = slot_positions(0.0, 0.05, math.radians(60))["x_P"] - slot_positions(
            p, 0.05, math.radians(60))["x_P"]
        assert work["X3"][k] == pytest.approx(x3, abs=1e-14)
        # 120 rpm: V3 = omega1 * U31
        assert work["V3"][k] == pytest.approx(4 * math.pi * work["U31"][k], rel=1e-12)
    data = json.loads((out / "working_cycle.json").read_text())
    assert data["units"]["a3"] == "m/s^2" and len(data["columns"]["a3"]) == 361


def test_units_and_plain_si_are_equivalent(tmp_path, capsys):
    a = files.load(_write(tmp_path, L1="50 mm", speed="120 rpm", alpha="60 deg"))
    f = tmp_path / "si.toml"
    f.write_text(BASE.format(L1="0.05 m", speed="12.566370614359172 rad/s", lambda2="4.0",
                             alpha="1.0471975511965976 rad", extra=""))
    b = files.load(f)
    assert a.crank.L1 == pytest.approx(b.crank.L1) == pytest.approx(0.05)
    assert a.crank.speed == pytest.approx(b.crank.speed) == pytest.approx(4 * math.pi)
    assert a.working.alpha == pytest.approx(b.working.alpha)


@pytest.mark.parametrize("kw,needles", [
    ({"L1": "-50 mm"}, ["crank.L1", "-50 mm is invalid: must be > 0"]),
    ({"L1": "50 kg"}, ["crank.L1", "dimension"]),
    ({"speed": "0 rpm"}, ["crank.speed"]),
    ({"lambda2": "1.2"}, ["idle.lambda2", "|lambda_e| + 1 = 1.5"]),
    ({"alpha": "5 deg"}, ["working.alpha", "working range"]),
    ({"alpha": "178 deg"}, ["working.alpha", "jams"]),
    ({"extra": "colour = 'red'"}, ["colour", "unknown key"]),
    ({"extra": "[[schedule]]\nmode = 'idle'\nstrokes = 3"}, ["schedule.0", "revolutions"]),
    ({"extra": "[[schedule]]\nmode = 'working'\nstrokes = 0"}, ["schedule.0.strokes"]),
    ({"extra": "[[schedule]]\nmode = 'working'\nstrokes = 2\nalpha = '3 deg'"},
     ["schedule.0.alpha", "working range"]),
    ({"extra": "[[schedule]]\nmode = 'dance'\nrevolutions = 2"}, ["schedule.0.mode"]),
    ({"extra": "[output]\nsamples_per_revolution = 2"}, ["output.samples_per_revolution"]),
])
def test_bad_files_one_line_exit_2(tmp_path, capsys, kw, needles):
    f = _write(tmp_path, **kw)
    err = _fail(capsys, ["analyze", str(f), "--out", str(tmp_path / "o")])
    assert str(f) in err
    for n in needles:
        assert n in err, (n, err)


def test_missing_section(tmp_path, capsys):
    f = tmp_path / "p.toml"
    f.write_text('type = "sine_press"\n[crank]\nL1 = "50 mm"\nspeed = "120 rpm"\n'
                 '[idle]\nlambda2 = 4\n')
    err = _fail(capsys, ["analyze", str(f)])
    assert "working" in err and "missing required key" in err


def test_invalid_toml_and_missing_file(tmp_path, capsys):
    f = tmp_path / "p.toml"
    f.write_text('type = "sine_press"\n[crank\n')
    assert "invalid TOML" in _fail(capsys, ["analyze", str(f)])
    assert "file not found" in _fail(capsys, ["analyze", str(tmp_path / "none.toml")])


def test_bad_angles_option(tmp_path, capsys):
    err = _fail(capsys, ["analyze", str(EXAMPLE), "--out", str(tmp_path / "o"), "--angles",
                         "ten"])
    assert "--angles" in err


@pytest.mark.parametrize("cmd,file", [("analyze", EXAMPLE),
                                      ("balance", EXAMPLE.parent / "fourbar_paper001.toml"),
                                      ("reactions", EXAMPLE.parent / "loom_fourbar_spatial.toml")])
@pytest.mark.parametrize("text,value", [("1e400", "inf"), ("0,nan", "nan"), ("-inf", "-inf")])
def test_non_finite_angles_are_named(cmd, file, text, value, tmp_path, capsys):
    err = _fail(capsys, [cmd, str(file), "--out", str(tmp_path / "o"), "--angles", text])
    assert f"--angles = {value} is invalid: must be finite numbers in degrees" in err


SP_BROKEN = [
    ('L1 = "50 mm"', 'L1 = "50 mm', ["invalid toml"]),
    ('type = "sine_press"', 'type = "sine_pres"', ["type", "sine_pres"]),
    ('type = "sine_press"', '', ["type", "missing"]),
    ('L1 = "50 mm"', 'L1 = "100 kg"', ["crank.L1", "100 kg", "length"]),
    ('L1 = "50 mm"', 'L1 = "-50 mm"', ["crank.L1", "-50 mm"]),
    ('L1 = "50 mm"', '', ["crank.L1", "missing"]),
    ('L1 = "50 mm"', 'L1 = nan', ["crank.L1", "nan"]),
    ('L1 = "50 mm"', 'L1 = "fifty mm"', ["crank.L1", "fifty"]),
    ('speed = "120 rpm"', 'speed = "120 mm"', ["crank.speed", "120 mm"]),
    ('lambda2 = 4.0', 'lambda2 = 1.2', ["idle.lambda2", "1.2", "1.5"]),
    ('alpha = "60 deg"', 'alpha = "5 deg"', ["working.alpha", "5 deg", "12.55"]),
    ('alpha = "60 deg"', 'alpha = "200 deg"', ["working.alpha", "200"]),
    ('alpha = "60 deg"', 'alpha = 60', ["working.alpha", "3437.75 deg", "plain number",
                                        "radians"]),
    ('alpha = "45 deg"', 'alpha = "175 deg"', ["schedule", "175 deg", "167.4"]),
    ('lambda_e = 0.5', 'lambda_e = 0.5\nfoo = 1', ["idle.foo", "unknown key"]),
    ('branch = 1', 'branch = 0', ["idle.branch", "0"]),
    ('revolutions = 5', 'revolutions = 0', ["schedule.0.revolutions", "0"]),
    ('revolutions = 5', 'revolutions = 2.5', ["schedule.0.revolutions", "2.5"]),
    ('mode = "idle"', 'mode = "sleep"', ["schedule.0.mode", "sleep"]),
    ('f_slot = 0.12', 'f_slot = -0.12', ["working.f_slot", "-0.12"]),
    ('f_slot = 0.12', 'f_slot = 5.0', ["working.alpha", "84.4"]),
    ('samples_per_revolution = 360', 'samples_per_revolution = 3',
     ["output.samples_per_revolution", "3"]),
]


@pytest.mark.parametrize("old,new,words", SP_BROKEN)
def test_cli_broken_sine_press_files_one_line_exit_2(old, new, words, tmp_path, capsys):
    from pathlib import Path

    from linkwork.cli import main
    text = (Path(__file__).resolve().parents[2] / "examples" / "sine_press.toml").read_text()
    assert old in text
    p = tmp_path / "press.toml"
    p.write_text(text.replace(old, new, 1))
    rc = main(["analyze", str(p), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert rc == 2
    assert len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err and "press.toml" in err
    for w in words:
        assert w.lower() in err.lower(), (w, err)
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_cli_missing_file(tmp_path, capsys):
    from linkwork.cli import main
    assert main(["analyze", str(tmp_path / "none.toml")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "none.toml" in err


def test_cli_sine_press_outputs_match_the_functions(tmp_path, capsys, monkeypatch):
    """The CSV written by `linkwork analyze` carries the same numbers as the public functions
    (SI columns), for both modes, and the schedule switches at 5 T, 8 T, 10 T."""
    import csv
    import json
    from pathlib import Path

    from linkwork.cli import main
    monkeypatch.setenv("COLUMNS", "250")
    src = Path(__file__).resolve().parents[2] / "examples" / "sine_press.toml"
    out = tmp_path / "out"
    assert main(["analyze", str(src), "--out", str(out)]) == 0
    table = capsys.readouterr().out
    # the switch instants say which mode is entered (was "duration, switches: 6, 2.5 s, ...")
    assert "2.5 (→ working), 4 (→ idle), 5 (→ working)" in table
    with (out / "idle_cycle.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    phi = np.array([float(r["phi1 [rad]"]) for r in rows])
    w1 = 120 * 2 * np.pi / 60
    ref = cs.offset_crank_slider(phi, 0.05, 4.0, 0.5, w1)
    np.testing.assert_allclose([float(r["a_C [m/s^2]"]) for r in rows], ref.a_C, rtol=1e-12)
    with (out / "working_cycle.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    phi = np.array([float(r["phi1 [rad]"]) for r in rows])
    ref2 = sine.inclined_slot(phi, 0.05, math.radians(60), w1)
    np.testing.assert_allclose([float(r["X3 [m]"]) for r in rows], ref2.X3, rtol=1e-12,
                               atol=1e-15)
    data = json.loads((out / "schedule.json").read_text())
    T = 2 * np.pi / w1
    np.testing.assert_allclose([s["t"] for s in data["switches"]], [5 * T, 8 * T, 10 * T],
                               rtol=1e-12)
    for png in ("kinematics.png", "schedule.png", "working_range.png"):
        assert (out / png).stat().st_size > 10_000


@pytest.mark.parametrize("old,new,key", [
    ('L1 = "50 mm"', 'L1 = inf', "crank.L1"),
    ('speed = "120 rpm"', 'speed = inf', "crank.speed"),
    ('eps1 = "0 rad/s^2"', 'eps1 = nan', "crank.eps1"),
    ('lambda2 = 4.0', 'lambda2 = inf', "idle.lambda2"),
    ('lambda_e = 0.5', 'lambda_e = inf', "idle.lambda_e"),
    ('lambda_e = 0.5', 'lambda_e = nan', "idle.lambda_e"),
    ('f_slot = 0.12', 'f_slot = inf', "working.f_slot"),
    ('alpha = "45 deg"', 'alpha = nan', "schedule.3.alpha"),
])
def test_cli_sine_press_non_finite_values_name_file_and_key(old, new, key, tmp_path, capsys):
    # they used to reach the models: 'omega1 = inf is invalid' without file or key, or
    # 'lambda2 = 4 must be > |lambda_e| + 1 = inf', or f_slot = inf blamed on working.alpha
    err = edit_example_and_run(tmp_path, capsys, "sine_press.toml", old, new)
    assert f"{key}:" in err and "finite" in err, err
