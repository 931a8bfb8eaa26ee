"""`linkwork synthesize function|motion|path TASK.toml` in-process: outputs, design files that
`linkwork analyze` reads back, the task file schema, bad input (one line, exit 2)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from linkwork import io
from linkwork.cli import main
from linkwork.planar.kinematics import kinematics
from linkwork.synthesis.design import coupler_point

PLANT = dict(r1=0.04, r2=0.01, r3=0.035, r4=0.03, rcx=0.015, rcy=0.012, x0=0.005, y0=-0.003,
             theta0=0.3)


def _write(tmp_path, text, name="task.toml"):
    f = tmp_path / name
    f.write_text(text)
    return f


def _points():
    th = np.linspace(0.2, 5.5, 7)
    x, y, _ = coupler_point(th, PLANT, 1)
    return th, np.c_[x, y]


def test_path_task_writes_designs_that_analyze_reads(tmp_path, capsys):
    th, pts = _points()
    pl = ", ".join(f'["{float(x) * 1e3!r} mm", "{float(y) * 1e3!r} mm"]' for x, y in pts)
    tim = ", ".join(f"{float(t)!r}" for t in th)
    f = _write(tmp_path, f'type = "synthesis"\nname = "planted"\n[path]\npoints = [{pl}]\n'
                         f'timing = [{tim}]\n[search]\ncandidates = 4096\nrefine = 6\n'
                         'designs = 2\n[objective]\nkind = "pareto"\n')
    out = tmp_path / "out"
    rc = main(["synthesize", "path", str(f), "--out", str(out)])
    text = capsys.readouterr().out
    assert rc == 0, text
    for name in ("synthesis.csv", "synthesis.json", "design_1.toml", "path.png", "pareto.png"):
        assert (out / name).stat().st_size > 0, name
    data = json.loads((out / "synthesis.json").read_text())
    assert data["kind"] == "path" and data["result"]["designs"][0]["error"] < 1e-20
    doc = io.load(out / "design_1.toml")
    p = data["result"]["designs"][0]
    kin = kinematics(doc.mechanism(), np.asarray(p["theta2"]) + p["theta0"])
    P = kin.point("coupler", "P")
    assert np.allclose(P.x, pts[:, 0], atol=1e-12) and np.allclose(P.y, pts[:, 1], atol=1e-12)
    assert main(["analyze", str(out / "design_1.toml"), "--out", str(tmp_path / "a")]) == 0


def test_function_task(tmp_path, capsys):
    f = _write(tmp_path, 'type = "synthesis"\n[function]\ny = "log10(x)"\nx_range = [1, 10]\n'
                         'input = { start = "30 deg", span = "60 deg" }\n'
                         'output = { start = "110 deg", span = "60 deg" }\nframe = "100 mm"\n')
    out = tmp_path / "out"
    assert main(["synthesize", "function", str(f), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "Chebyshev precision points" in text
    assert (out / "function.png").exists() and (out / "design_1.toml").exists()
    assert main(["analyze", str(out / "design_1.toml"), "--out", str(tmp_path / "a")]) == 0


def test_motion_task_three_poses(tmp_path, capsys):
    from linkwork.synthesis.design import FourbarDesign

    fb = FourbarDesign(params=dict(PLANT, theta2=[0.0]), branch=1, error=0.0,
                       points=np.zeros((1, 2)))
    kin = kinematics(fb.mechanism(), np.array([0.5, 1.5, 2.5]) + PLANT["theta0"])
    P = kin.point("coupler", "P")
    poses = ", ".join(f"[{float(x)!r}, {float(y)!r}, {float(t)!r}]"
                      for x, y, t in zip(P.x, P.y, kin.angle("coupler"), strict=True))
    o2, o4 = fb.pivots()
    f = _write(tmp_path, f'type = "synthesis"\n[motion]\nposes = [{poses}]\n'
                         f"fixed_pivots = [[{float(o2[0])!r}, {float(o2[1])!r}], "
                         f"[{float(o4[0])!r}, {float(o4[1])!r}]]\n")
    out = tmp_path / "out"
    assert main(["synthesize", "motion", str(f), "--out", str(out)]) == 0
    assert (out / "motion.png").exists()
    assert "four-bars through 3 poses" in capsys.readouterr().out.replace("\n", " ")


def test_sixbar_path_task_writes_designs_that_analyze_reads(tmp_path, capsys):
    """[path] linkage = "stephenson": the planted six-bar of tests/synthesis/test_sixbar.py in
    mm, bounds +-50 % around it, timing: the ranked table, the files, a design file that
    linkwork analyze reads and whose coupler point passes through the targets."""
    from linkwork.synthesis import sixbar as S

    p = dict(r1=40, r2=10, r3=35, r4=30, x0=0, y0=0, theta0=0, cx=15, cy=15, r5=35, r6=30,
             x6=40, y6=40, px=10, py=5)
    th = np.linspace(0.3, 5.0, 8)
    x, y, _ = S.sixbar_point(th, np.array([[p[k] * 1e-3 for k in S.SIXBAR_PARAMS]]),
                             [(1, 1)], "stephenson")
    pl = ", ".join(f'["{float(a) * 1e3!r} mm", "{float(b) * 1e3!r} mm"]'
                   for a, b in zip(x[0], y[0], strict=True))
    lims = {k: (0.5 * v, 1.5 * v) if k[0] == "r" else (v - 20, v + 20) for k, v in p.items()}
    bounds = ", ".join(f'{k} = ["{lo} mm", "{hi} mm"]' for k, (lo, hi) in lims.items()
                       if k != "theta0")
    f = _write(tmp_path, f'type = "synthesis"\nname = "six"\n[path]\nlinkage = "stephenson"\n'
                         f'points = [{pl}]\ntiming = [{", ".join(repr(float(t)) for t in th)}]\n'
                         f'constraints = ["order"]\nbounds = {{ {bounds}, theta0 = ["0 deg", '
                         '"360 deg"] }\n[search]\ncandidates = 8192\nrefine = 6\ndesigns = 2\n')
    out = tmp_path / "out"
    rc = main(["synthesize", "path", str(f), "--out", str(out)])
    text = capsys.readouterr().out
    assert rc == 0, text
    assert "stephenson six-bars" in text.replace("\n", " ")
    data = json.loads((out / "synthesis.json").read_text())
    d = data["result"]["designs"][0]
    assert data["result"]["linkage"] == "stephenson" and d["error"] < 1e-20
    for name in ("synthesis.csv", "design_1.toml", "path.png"):
        assert (out / name).stat().st_size > 0, name
    doc = io.load(out / "design_1.toml")
    P = kinematics(doc.mechanism(), np.asarray(d["theta2"]) + d["theta0"]).point("link5", "P")
    assert np.allclose(P.x, x[0], atol=1e-12) and np.allclose(P.y, y[0], atol=1e-12)
    assert main(["analyze", str(out / "design_1.toml"), "--out", str(tmp_path / "a")]) == 0


@pytest.mark.parametrize(("body", "needle"), [
    ('[path]\nlinkage = "watt"\npoints = [[0, 0], [1, 1], [2, 0]]\nbounds = { rcx = [1, 2] }\n',
     "bounds.rcx"),
    ('[path]\nlinkage = "watt"\npoints = [[0, 0], [1, 1], [2, 0]]\n[objective]\n'
     'kind = "pareto"\n', "judging by forces is for four-bars"),
    ('[path]\nlinkage = "klann"\npoints = [[0, 0], [1, 1], [2, 0]]\n', "linkage"),
    ('[function]\ny = "__import__(1)"\nx_range = [1, 2]\ninput = { span = 1 }\n'
     'output = { span = 1 }\n', "y:"),
    ('[path]\npoints = [[0, 0], [1, 1], [2, 0]]\nbounds = { crank = [1, 2] }\n', "bounds.crank"),
    ('[path]\npoints = [[0, 0], [1, 1], [2, 0]]\nbounds = { r1 = ["1 kg", 2] }\n', "bounds.r1"),
    ('[motion]\nposes = [[0, 0, 0], [1, 1, 1]]\n', "too few"),
])
def test_bad_tasks_give_one_line(tmp_path, capsys, body, needle):
    kind = body.split("]")[0].strip("[")
    f = _write(tmp_path, 'type = "synthesis"\n' + body)
    rc = main(["synthesize", kind, str(f), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and needle in err[0], err


def test_missing_section_and_wrong_file_type(tmp_path, capsys):
    f = _write(tmp_path, 'type = "synthesis"\n[path]\npoints = [[0, 0], [1, 1], [2, 0]]\n')
    assert main(["synthesize", "motion", str(f), "--out", str(tmp_path / "o")]) == 2
    assert "[motion]" in capsys.readouterr().err
    g = _write(tmp_path, 'type = "planar"\n', "p.toml")
    assert main(["synthesize", "path", str(g), "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err.count("\n") == 1


def test_impossible_constraint_names_the_closest_value(tmp_path, capsys):
    _, pts = _points()
    pl = ", ".join(f"[{float(x)!r}, {float(y)!r}]" for x, y in pts)
    f = _write(tmp_path, f'type = "synthesis"\n[path]\npoints = [{pl}]\n'
                         'min_transmission = "89.5 deg"\n[search]\ncandidates = 1024\nrefine = 2\n')
    assert main(["synthesize", "path", str(f), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "transmission angle >= 89.5 deg" in err and "closest achievable" in err


def test_analyze_of_a_task_file_names_the_synthesize_command(tmp_path, capsys):
    f = _write(tmp_path, 'type = "synthesis"\n[path]\npoints = [[0, 0], [1, 1], [2, 0]]\n')
    assert main(["analyze", str(f), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "linkwork synthesize path FILE" in err and not (tmp_path / "o").exists()
