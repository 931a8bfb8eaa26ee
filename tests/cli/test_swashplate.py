"""`linkwork swashplate analyze/synthesize` in-process, the file schema, broken files."""

import json
import math
from pathlib import Path

import numpy as np
import pytest
from _cli_files import edit_example_and_run
from _swashplate_construction import ref_delta, ref_extremes, ref_max_on, ref_s

from linkwork.cli import main
from linkwork.models import swashplate as sw

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_analyze_example_4a_writes_outputs(tmp_path, capsys):
    rc = main(["swashplate", "analyze", str(EXAMPLES / "swashplate_4a.toml"), "--out",
               str(tmp_path), "--angles", "0,90,180"])
    out = capsys.readouterr().out
    assert rc == 0, out
    assert "stroke H" in out and "53.59 mm" in out
    for name in ("cycle.csv", "cycle.json", "characteristics.json", "kinematics.png",
                 "forces.csv", "forces.json", "forces.png"):
        assert (tmp_path / name).stat().st_size > 0, name
    data = json.loads((tmp_path / "characteristics.json").read_text())
    d = sw.scheme_4a(0.1, 0.2, math.radians(15))
    assert abs(data["H"] - 2 * 0.1 * math.tan(math.radians(15))) < 1e-12
    assert data["delta_allow_met"] is True and data["v_allow_met"] is True
    assert abs(data["omega"] - 50 * math.pi / 30) < 1e-12  # 600/min on 12 slides = 50 rpm
    rows = np.genfromtxt(tmp_path / "cycle.csv", delimiter=",", names=True)
    np.testing.assert_allclose(rows["s_m"], d.position(rows["phi_rad"]), atol=1e-15)


def test_generic_analyze_dispatches_swashplate(tmp_path, capsys):
    rc = main(["analyze", str(EXAMPLES / "swashplate_1.toml"), "--out", str(tmp_path)])
    assert rc == 0
    assert (tmp_path / "kinematics.png").exists()
    assert "forward / return stroke angle" in capsys.readouterr().out


GOOD = """
type = "swashplate"
scheme = "4b"
[geometry]
R = "100 mm"
r = "110 mm"
l = "220 mm"
alpha = "25 deg"
b = "15 mm"
"""


@pytest.mark.parametrize("text, needle", [
    (GOOD.replace('b = "15 mm"', 'b = "15 mm"\na = "1 mm"'), "geometry.a: scheme 4b fixes it"),
    (GOOD.replace('b = "15 mm"', ''), "geometry.b: missing"),
    (GOOD.replace('l = "220 mm"', 'l = "100 kg"'), "geometry.l"),
    (GOOD.replace('l = "220 mm"', 'l = "1 mm"'), "rod cannot reach"),
    (GOOD.replace('scheme = "4b"', 'scheme = "7"'), "scheme"),
    (GOOD.replace('alpha = "25 deg"', 'alpha = "95 deg"'), "alpha"),
    (GOOD + '[load]\nangles = ["0 deg"]\nforces = ["1 kN"]\n', "load"),
    (GOOD + "[operation]\nspeed = '10 rpm'\nproductivity = '100 1/min'\n", "not both"),
    (GOOD.replace("[geometry]", "[geometry]\nfoo = 1"), "unknown key"),
])
def test_broken_files_one_line_exit_2(tmp_path, capsys, text, needle):
    f = tmp_path / "bad.toml"
    f.write_text(text)
    rc = main(["swashplate", "analyze", str(f), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2
    assert err.count("\n") == 1 and "Traceback" not in err
    assert needle in err, err


def test_analyze_rejects_other_file_types(tmp_path, capsys):
    f = tmp_path / "x.toml"
    f.write_text((EXAMPLES / "sine_press.toml").read_text())
    assert main(["swashplate", "analyze", str(f), "--out", str(tmp_path)]) == 2
    assert "expected 'swashplate'" in capsys.readouterr().err


def test_synthesize_small_run(tmp_path, capsys):
    rc = main(["swashplate", "synthesize", "-R", "100 mm", "-H", "50 mm", "--scheme", "4a",
               "--delta", "3 deg", "--candidates", "128", "--refine", "1", "--best", "3",
               "--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert rc == 0, out
    for name in ("synthesis.csv", "synthesis.json", "feasible_region.png"):
        assert (tmp_path / name).stat().st_size > 0
    rows = np.genfromtxt(tmp_path / "synthesis.csv", delimiter=",", names=True)
    r, l, al = float(np.atleast_1d(rows["r_m"])[0]), float(np.atleast_1d(rows["l_m"])[0]), \
        float(np.atleast_1d(rows["alpha_rad"])[0])
    c = sw.characteristics(0.1, r, l, al)
    assert abs(c.H - 0.05) <= 0.005 * 0.05 + 1e-12 and c.delta_f <= math.radians(3) + 1e-12
    # piped output: the ranked table is printed whole (no column cut to an ellipsis)
    assert "max Πv [mm/rad]" in out and "…" not in out


def test_synthesize_impossible_and_bad_options(tmp_path, capsys):
    rc = main(["swashplate", "synthesize", "-R", "100 mm", "-H", "50 mm", "--scheme", "2",
               "--delta", "3 deg", "--candidates", "64", "--refine", "1", "--out",
               str(tmp_path)])
    err = capsys.readouterr().err
    assert rc == 2 and "cannot satisfy max pressure angle" in err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert main(["swashplate", "synthesize", "-R", "100 mm", "-H", "50 mm", "--map",
                 "a,zz"]) == 2
    assert "--map" in capsys.readouterr().err
    assert main(["swashplate", "synthesize", "-R", "100 kg", "-H", "50 mm"]) == 2
    assert "--rotor-radius" in capsys.readouterr().err
    assert main(["swashplate", "synthesize", "-R", "100 mm", "-H", "50 mm", "--v-allow",
                 "0.3 m/s"]) == 2
    assert "needs --productivity" in capsys.readouterr().err


def test_cycle_files_without_rotor_speed_have_no_zero_speed_columns(tmp_path):
    """Without a rotor speed the slide speed is unknown: cycle.csv/json leave v and acc out
    (they were columns of zeros beside Pi_v = 23.9 mm/rad); with a speed they are v = Pi_v w."""
    import csv
    import json
    import re

    from linkwork.cli import main
    src = (Path(__file__).resolve().parents[2] / "examples" / "swashplate_1.toml").read_text()
    no_speed = re.sub(r"(?m)^speed = .*$\n", "", src, count=1)
    assert no_speed != src
    for text, out in ((no_speed, tmp_path / "a"), (src, tmp_path / "b")):
        p = tmp_path / f"{out.name}.toml"
        p.write_text(text)
        assert main(["swashplate", "analyze", str(p), "--out", str(out)]) == 0
    head = next(csv.reader((tmp_path / "a" / "cycle.csv").read_text().splitlines()))
    assert not any(h.startswith(("v ", "acc ")) for h in head) and "Pi_v [m/rad]" in head
    assert not {"v", "acc"} & set(json.loads((tmp_path / "a" / "cycle.json").read_text())
                                  ["columns"])
    rows = list(csv.DictReader((tmp_path / "b" / "cycle.csv").read_text().splitlines()))
    w = json.loads((tmp_path / "b" / "cycle.json").read_text())["omega"]
    assert w > 0
    for r in rows[::40]:
        assert float(r["v [m/s]"]) == pytest.approx(float(r["Pi_v [m/rad]"]) * w, rel=1e-12)


def test_cli_swashplate_jamming_load_one_line(tmp_path, capsys):
    err = edit_example_and_run(tmp_path, capsys, "swashplate_4a.toml", 'rho_guide = "5 deg"',
               'rho_guide = "89 deg"', cmd=("swashplate", "analyze"))
    assert "jams" in err


@pytest.mark.parametrize("example,old,new,words", [
    # a geometry value the scheme constructor rejects: the key and, for a plain alpha, the hint
    ("swashplate_4a.toml", 'alpha = "15 deg"', 'alpha = 15', ["geometry.alpha", "859.4",
                                                              "(0, 90) deg", "radians"]),
    ("swashplate_4a.toml", 'alpha = "15 deg"', 'alpha = "0 deg"', ["geometry.alpha", "(0, 90)"]),
    # the rod cannot reach: said at load time, with the file name
    ("swashplate_4a.toml", 'alpha = "15 deg"', 'alpha = "89.9 deg"', ["geometry", "cannot reach"]),
    ("swashplate_1.toml", 'b = "0 mm"', 'b = "1000 mm"', ["geometry", "cannot reach"]),
    # non-finite numbers: named with their key (they used to lose the file and the key)
    ("swashplate_4a.toml", 'R = "100 mm"', 'R = inf', ["geometry.R", "finite"]),
    ("swashplate_4a.toml", 'l = "200 mm"', 'l = inf', ["geometry.l", "finite"]),
    ("swashplate_1.toml", 'a = "20 mm"', 'a = nan', ["geometry.a", "finite"]),
    ("swashplate_1.toml", 'speed = "50 rpm"', 'speed = inf', ["operation.speed", "finite"]),
    ("swashplate_4a.toml", 'productivity = "600 1/min"', 'productivity = inf',
     ["operation.productivity", "finite"]),
    ("swashplate_4a.toml", 'forces = ["0 kN", "0 kN", "20 kN"', 'forces = [0, 0, nan',
     ["load.forces.2", "finite"]),
    ("swashplate_4a.toml", 'guide_length = "120 mm"', 'guide_length = inf',
     ["load.guide_length", "finite"]),
])
def test_cli_swashplate_file_errors_name_file_and_key(example, old, new, words, tmp_path,
                                                      capsys):
    err = edit_example_and_run(tmp_path, capsys, example, old, new, cmd=("swashplate", "analyze"))
    for w in words:
        assert w.lower() in err.lower(), (w, err)


@pytest.mark.parametrize("argv,words", [
    # a plain number is radians: 8 -> 458 deg; the error named only 'delta_f', a field of the
    # Request the user never typed, without the hint
    (["--delta", "8"], ["--delta = 8 is invalid", "(0, 90]", "delta_f = 458.366 deg",
                        "radians"]),
    (["--delta-r", "0 deg"], ["--delta-r = 0 deg is invalid", "(0, 90]"]),
    # as typed, with its unit: the SI value (R = -0.1) was shown first
    (["-R", "-100 mm"], ["--rotor-radius = -100 mm is invalid", "> 0"]),
    (["-H", "0 mm"], ["--stroke = 0 mm is invalid", "> 0"]),
    (["--stroke-tol", "-1 mm"], ["--stroke-tol = -1 mm is invalid", ">= 0"]),
    (["--phi-f", "400 deg"], ["--phi-f = 400 deg is invalid", "(0, 360)"]),
])
def test_cli_synthesize_errors_name_the_option_as_typed(argv, words, tmp_path, capsys):
    base = {"-R": "100 mm", "-H": "60 mm"}
    for k, v in zip(argv[::2], argv[1::2], strict=True):
        base[k] = v
    args = [x for kv in base.items() for x in kv]
    rc = main(["swashplate", "synthesize", *args, "--candidates", "64", "--refine", "0",
               "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1, err
    for w in words:
        assert w in err, (w, err)
    assert "-0.1" not in err and "0.001" not in err  # never the SI value of what was typed


def test_cli_swashplate_without_speed_shows_no_zero_slide_speeds(tmp_path, capsys):
    text = (EXAMPLES / "swashplate_1.toml").read_text()
    assert 'speed = "50 rpm"' in text
    p = tmp_path / "mech.toml"
    p.write_text(text.replace('speed = "50 rpm"', "", 1))
    assert main(["swashplate", "analyze", str(p), "--out", str(tmp_path / "o"),
                 "--angles", "90"]) == 0
    out = capsys.readouterr().out
    # the slide moves at 90 deg (Pi_v = 23.9 mm/rad): a speed of 0.0000 m/s was printed
    assert "slide v" not in out and "slide speeds omitted" in out


DEG = math.pi / 180


EX4A = ["swashplate", "analyze", str(EXAMPLES / "swashplate_4a.toml")]


SYN = ["swashplate", "synthesize", "-R", "100 mm", "-H", "50 mm", "--candidates", "64"]


@pytest.mark.parametrize("argv", [
    ["swashplate", "synthesize", "-R", "100 mm", "-H", "50 kg"],
    [*SYN[:-2], "--scheme", "7"],
    [*SYN, "--map", "alpha,alpha"],
    [*SYN, "--map", "alpha"],
    [*SYN, "--map", "q,l"],
    [*SYN, "--delta", "95 deg"],
    [*SYN, "--delta", "-5 deg"],
    [*SYN, "--point", "90 deg"],
    [*SYN, "--point", "90 deg,20 kg"],
    [*SYN, "--phi-f", "400 deg"],
    [*SYN, "--v-allow", "0.3 m/s"],
    [*SYN, "--speed", "50 rpm", "--productivity", "600 1/min"],
    [*SYN, "--objective", "cost"],
    [*SYN, "--positions", "0"],
    [*SYN, "--stroke-tol", "-1 mm"],
    [*SYN, "--candidates", "abc"],
    [*SYN, "--bogus"],
    [*SYN, "--delta-f", "0 deg"],
    [*SYN, "--delta-r", "0 deg"],
    [*SYN, "--positions", "0", "--productivity", "600 1/min"],
    [*SYN, "--positions", "0", "--productivity", "600 1/min", "--v-allow", "0.3 m/s"],
    [*SYN, "--best", "0"],
    [*SYN, "--candidates", "0"],
    [*SYN, "--refine", "-1"],
    [*SYN, "--speed", "0 rpm", "--v-allow", "0.3 m/s"],
    [*SYN, "--speed", "-5 rpm"],
    [*SYN, "--productivity", "0 1/min"],
    [*SYN, "--point", "90 deg,25 mm", "--point-tol", "-1 mm"],
    [*SYN, "--phi-f", "185 deg", "--phi-f-tol", "-1 deg"],
    [*SYN, "--point", "90 deg,nan mm"],
    ["swashplate", "synthesize", "-R", "100 mm"],
    [*EX4A, "--angles", "0,x"],
    ["swashplate", "analyze", "/nonexistent/file.toml"],
])
def test_cli_bad_options_one_line_exit_2(argv, capsys, tmp_path):
    rc = main([*argv, "--out", str(tmp_path)] if "--bogus" not in argv else argv)
    cap = capsys.readouterr()
    assert rc == 2, cap.out + cap.err
    assert cap.err.count("\n") == 1 and cap.err.strip(), repr(cap.err)
    assert "Traceback" not in cap.err + cap.out


@pytest.mark.parametrize("extra, needle", [
    (["--delta-f", "0 deg"], "--delta-f = 0 deg"),  # was silently replaced by --delta
    (["--delta-r", "0 deg"], "--delta-r = 0 deg"),
    (["--positions", "0", "--productivity", "600 1/min"], "--positions = 0"),  # was a traceback
    (["--best", "0"], "--best = 0"),  # listed every design
    (["--speed", "0 rpm", "--v-allow", "0.3 m/s"], "--speed = 0 rpm"),
    (["--point", "90 deg,25 mm", "--point-tol", "-1 mm"], "--point-tol = -1 mm"),
    (["--point", "90 deg,nan mm"], "point position s_p = nan"),
])
def test_cli_bad_values_named(extra, needle, capsys, tmp_path):
    assert main([*SYN, *extra, "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert needle in err, err


@pytest.mark.parametrize("text", [
    "this is not toml = = =",
    'type = "swashplate"\nscheme = "4a"\n[geometry]\nR = "100 mm"\nl = "200 mm"\n',
    'type = "swashplate"\nscheme = "4a"\n[geometry]\nR = "100 mm"\nl = "200 mm"\n'
    'alpha = "15 deg"\n[operation]\npositions = 0\n',
    'type = "swashplate"\nscheme = "4a"\n[geometry]\nR = "-100 mm"\nl = "200 mm"\n'
    'alpha = "15 deg"\n',
    'type = "swashplate"\nscheme = "4a"\n[geometry]\nR = "100 mm"\nl = "200 mm"\n'
    'alpha = "15 deg"\n[load]\nforce = "5 kN"\nrho_guide = "89.9 deg"\n',
    'type = "swashplate"\nscheme = "1"\n[geometry]\nR = "100 mm"\nl = "20 mm"\nr = "50 mm"\n'
    'alpha = "15 deg"\na = "30 mm"\n',
])
def test_cli_broken_files_one_line_exit_2(text, capsys, tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text(text)
    rc = main(["swashplate", "analyze", str(f), "--out", str(tmp_path / "o")])
    cap = capsys.readouterr()
    assert rc == 2, cap.out + cap.err
    assert cap.err.count("\n") == 1 and cap.err.strip(), repr(cap.err)
    assert "Traceback" not in cap.err


def test_example_scheme_1_is_asymmetric_as_its_comment_says(tmp_path, capsys):
    # the example claims a lower pressure angle on the forward than on the return stroke, and a
    # stroke different from s(pi) - s(0); it had r = R, for which the offset a changes nothing
    text = (EXAMPLES / "swashplate_1.toml").read_text()
    assert main(["swashplate", "analyze", str(EXAMPLES / "swashplate_1.toml"), "--out",
                 str(tmp_path)]) == 0
    capsys.readouterr()
    data = json.loads((tmp_path / "characteristics.json").read_text())
    p = tuple(data["design"][k] for k in ("R", "r", "l", "alpha", "a", "b"))
    xmin, smin, xmax, smax = ref_extremes(p, n=720)
    phi_f = (xmax - xmin) % (2 * math.pi)
    df = ref_max_on(lambda t: ref_delta(t, *p), xmin, xmin + phi_f)
    dr = ref_max_on(lambda t: ref_delta(t, *p), xmax, xmax + 2 * math.pi - phi_f)
    assert dr - df > 1.5 * DEG
    assert f"{math.degrees(df):.3g} deg against {math.degrees(dr):.4g} deg" in text
    assert f"{(smax - smin) * 1e3:.4g} mm" in text
    assert f"{(ref_s(math.pi, *p) - ref_s(0.0, *p)) * 1e3:.4g} mm" in text
    assert f"({math.degrees(phi_f):.4g} deg)" in text


def test_cli_analyze_and_synthesize_run(capsys, tmp_path):
    assert main([*EX4A, "--out", str(tmp_path / "a")]) == 0
    out = capsys.readouterr().out
    assert "53.59 mm" in out and "1.011 / 1.011 deg" in out
    # the acceleration column must not read like the offset a of the title ("a = 0 mm")
    assert "slide acc. [m/s²]" in out and "a [m/s²]" not in out.replace("acc. [m/s²]", "")
    rc = main(["swashplate", "synthesize", "-R", "100 mm", "-H", "53.59 mm", "--scheme", "4a",
               "--delta", "1.1 deg", "--candidates", "256", "--refine", "1", "--best", "2",
               "--out", str(tmp_path / "s")])
    cap = capsys.readouterr()
    assert rc == 0, cap.err
    assert (tmp_path / "s" / "feasible_region.png").stat().st_size > 0
    rows = np.genfromtxt(tmp_path / "s" / "synthesis.csv", delimiter=",", names=True)
    assert rows.size >= 1
