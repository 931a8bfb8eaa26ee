"""`linkwork swashplate analyze/synthesize` in-process, the file schema, broken files."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

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
