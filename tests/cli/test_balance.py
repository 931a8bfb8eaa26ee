"""``linkwork balance``: the runner on an engine mechanism, and the command's failure policy."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from _balancing_cases import paper_fourbar
from _cli_files import run_cli, sine_press_with_friction
from rich.console import Console

from linkwork.cli import main
from linkwork.cli.balance import BalanceSection, run_balance
from linkwork.planar.dynamics import inverse_dynamics
from linkwork.planar.kinematics import kinematics
from linkwork.planar.model import crank_slider_mechanism, fourbar_mechanism

DATA = Path(__file__).parents[1] / "data"
PAPER = dict(masses=(1.0, 3.0, 2.0), inertias=(1.0 * 0.1**2 / 12, 0.0225, 0.00567),
             coms=(0.05, 0.15, 0.1), omega1=10.0)


def test_run_balance_on_paper_fourbar(tmp_path):
    mech = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, **PAPER)
    con = Console(record=True, width=200)
    sec = BalanceSection(radii={"crank": 0.05, "rocker": 0.1})
    comp = run_balance(mech, sec, tmp_path, con)
    text = con.export_text()
    assert "R_j [%]" in text and f"{comp.R2:.1f}" in text
    assert "balancing raises" in text and "frame joint O4 peak" in text
    for name in ("balance_table.csv", "balance_table.json", "balance_cycle.csv",
                 "balance_summary.json", "balancing_moments.png", "balancing_force.png",
                 "balancing_torque.png"):
        assert (tmp_path / name).stat().st_size > 0, name
    summary = json.loads((tmp_path / "balance_summary.json").read_text())
    assert summary["full_force_balance"] is True
    assert summary["harmonics"]["dM2"]["amplitude"][0] < 1e-9
    assert [c["mass"] for c in summary["counterweights"]] == pytest.approx([4.0, 5.0])
    assert summary["axis_least_squares"] == pytest.approx([comp.x3, comp.y3])
    rows = (tmp_path / "balance_table.csv").read_text().splitlines()
    assert len(rows) == 13  # header + 12 positions
    assert float(rows[1].split(",")[0]) == 0.0


def test_run_balance_custom_angles_and_partial_balance(tmp_path):
    mech = crank_slider_mechanism(0.05, 0.2, masses=(1.0, 2.0, 3.0), omega1=10.0)
    con = Console(record=True, width=200)
    comp = run_balance(mech, BalanceSection(angles=[0, 45, 90, 135], n=72), tmp_path, con)
    np.testing.assert_allclose(np.degrees(comp.phi1), [0, 45, 90, 135])
    text = con.export_text()
    assert "PARTIAL" in text
    assert "slider" in text


def test_balance_pareto_option(tmp_path):
    mech = fourbar_mechanism(0.1, 0.3, 0.2, 0.3, **PAPER)
    run_balance(mech, BalanceSection(radii={"crank": 0.05, "rocker": 0.1}, n=72), tmp_path,
                Console(record=True), pareto=True)
    data = json.loads((tmp_path / "balance_pareto.json").read_text())
    assert len(data["weights"]) == 15
    assert (tmp_path / "balancing_pareto.png").stat().st_size > 0


def test_balance_cli_failures(tmp_path, capsys):
    assert main(["balance", str(tmp_path / "missing.toml")]) == 2
    assert "not found" in capsys.readouterr().err
    bad = tmp_path / "bad.toml"
    bad.write_text('type = "sine_press"\n')
    assert main(["balance", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "planar" in err and err.count("\n") == 1
    broken = tmp_path / "broken.toml"
    broken.write_text("type = = 'planar'\n")
    assert main(["balance", str(broken)]) == 2
    assert "invalid TOML" in capsys.readouterr().err


def test_balance_section_validation(tmp_path, capsys):
    pytest.importorskip("linkwork.planar.file")
    f = tmp_path / "p.toml"
    f.write_text((DATA / "balance_fourbar.toml").read_text() + "n = 3\n")
    assert main(["balance", str(f)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("linkwork: error:") and "balance.n" in err


def test_balance_command_on_file_matches_engine_model(tmp_path, capsys):
    pytest.importorskip("linkwork.planar.file")
    from linkwork.balancing import compare_balancing

    assert main(["balance", str(DATA / "balance_fourbar.toml"), "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "R_j" in out
    table = np.loadtxt(tmp_path / "balance_table.csv", delimiter=",", skiprows=1)
    ref = compare_balancing(fourbar_mechanism(0.1, 0.3, 0.2, 0.3, **PAPER), radii={"crank": 0.05,
                                                                         "rocker": 0.1})
    header = (tmp_path / "balance_table.csv").read_text().splitlines()[0].split(",")
    cols = [h.split(" [")[0] for h in header]
    for name in ("M", "dM1", "dM2", "dM3"):
        np.testing.assert_allclose(table[:, cols.index(name)], getattr(ref, name), atol=1e-9)


def test_balance_command_bad_balance_table(tmp_path, capsys):
    pytest.importorskip("linkwork.planar.file")
    text = (DATA / "balance_fourbar.toml").read_text()
    f = tmp_path / "bad.toml"
    f.write_text(text.replace('links = ["crank", "rocker"]', 'links = ["crank", "coupler"]'))
    assert main(["balance", str(f), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "coupler" in err and "hinged to the frame" in err and err.count("\n") == 1
    f.write_text(text.replace('radii = { crank = "50 mm"', 'radii = { crank = "50 kg"'))
    assert main(["balance", str(f), "--out", str(tmp_path)]) == 2
    assert "balance.radii" in capsys.readouterr().err
    assert main(["balance", str(DATA / "balance_fourbar.toml"), "--angles", "a,b"]) == 2
    assert "--angles" in capsys.readouterr().err


EXAMPLE = Path(__file__).parents[2] / "examples" / "fourbar_paper001.toml"


@pytest.mark.skipif(not EXAMPLE.exists(), reason="bundled example not present")
def test_balance_bundled_example(tmp_path, capsys):
    """The bundled paper-001 file has no [balance] table: the default radii (half the distance
    from the hinge to the link's far joint) are the paper's 50 and 100 mm -> 4 and 5 kg."""
    pytest.importorskip("linkwork.planar.file")
    assert main(["balance", str(EXAMPLE), "--out", str(tmp_path)]) == 0
    summary = json.loads((tmp_path / "balance_summary.json").read_text())
    assert [c["mass"] for c in summary["counterweights"]] == pytest.approx([4.0, 5.0])
    assert [c["static_moment"] for c in summary["counterweights"]] == pytest.approx([0.2, 0.5])
    assert summary["full_force_balance"] is True
    assert "R_j" in capsys.readouterr().out


def test_balance_command_with_file_loads(tmp_path, capsys):
    pytest.importorskip("linkwork.planar.file")
    text = (DATA / "balance_fourbar.toml").read_text()
    load = '\n[[load]]\ntype = "torque"\nbody = "rocker"\nmz = "-5 N*m"\n'
    f = tmp_path / "loaded.toml"
    f.write_text(text.replace("[balance]", load + "\n[balance]"))
    assert main(["balance", str(f), "--out", str(tmp_path)]) == 0
    assert "external loads enter the driving torque" in capsys.readouterr().out


def test_balance_angles_accept_units_and_name_bad_values(tmp_path, capsys):
    """[balance].angles: plain numbers are degrees, strings carry a unit ("30 deg" was refused
    as 'not a valid number'); non-finite and wrong-dimension values are named."""
    import json

    src = (DATA / "balance_fourbar.toml").read_text()
    old = "angles = [0, 30, 60, 90, 120, 150, 180, 210, 240, 270, 300, 330]"
    assert old in src

    def run(angles):
        p = tmp_path / "b.toml"
        p.write_text(src.replace(old, f"angles = {angles}"))
        rc = main(["balance", str(p), "--out", str(tmp_path / "o")])
        return rc, capsys.readouterr().err.strip()

    assert run('["30 deg", "1.5707963267948966 rad", 180]')[0] == 0
    table = json.loads((tmp_path / "o" / "balance_table.json").read_text())
    assert np.allclose(np.degrees(table["columns"]["phi1"]), [30.0, 90.0, 180.0], atol=1e-12)
    for bad, shown in [('["30 kg"]', "'30 kg'"), ("[nan]", "nan"), ('["1e400 deg"]', "1e400")]:
        rc, err = run(bad)
        assert rc == 2 and len(err.splitlines()) == 1 and "balance.angles" in err, err
        assert shown in err, err
    # beyond +-1e6 rad the table printed 300-digit angles (now refused as by analyze --angles)
    rc, err = run("[-1e300, 30]")
    assert rc == 2 and "balance.angles" in err and "must lie within" in err, err


def test_balance_cli_angles_beyond_float_precision_are_refused(tmp_path, capsys):
    """'balance --angles -1e300' passed the angle on and failed with an unrelated least-squares
    message; it is refused as in 'analyze' (the limit of crank angles, +-1e6 rad)."""
    rc = main(["balance", str(DATA / "balance_fourbar.toml"), "--angles=-1e300,30",
               "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and len(err.splitlines()) == 1, err
    assert "--angles = -1e+300" in err and "must lie within +-5.72958e+07 deg" in err, err


ROOT = Path(__file__).resolve().parents[2]


def test_cli_balance_radius_for_an_unknown_link_one_line_exit_2(tmp_path, capsys):
    text = (ROOT / "examples" / "fourbar_paper001.toml").read_text()
    f = tmp_path / "m.toml"
    f.write_text(text + '\n[balance]\nradii = { crnk = "50 mm", rocker = "100 mm" }\n')
    code, _, err = run_cli(["balance", str(f), "--out", str(tmp_path / "o")], capsys)
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert "radii" in err and "crnk" in err


def test_cli_balance_bundled_example(tmp_path, capsys):
    out = tmp_path / "o"
    assert main(["balance", str(EXAMPLE), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    for f in ("balance_table.csv", "balance_table.json", "balance_cycle.csv",
              "balance_summary.json", "balancing_moments.png", "balancing_force.png",
              "balancing_torque.png", "balancing_bearings.png"):
        assert (out / f).stat().st_size > 0
    assert "R_j" in text and "φ1 [deg]" in text
    assert "S = 0.2 kg·m" in text and "S = 0.5 kg·m" in text


def _write(tmp_path, text, name="m.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


BROKEN_BALANCE = {
    "unknown_key": "[balance]\nlinx = ['crank']\n",
    "radius_units": "[balance]\nradii = { crank = '50 kg' }\n",
    "radius_negative": "[balance]\nradii = { crank = '-50 mm' }\n",
    "radius_zero": "[balance]\nradii = '0 mm'\n",
    "not_hinged": "[balance]\nlinks = ['coupler']\n",
    "unknown_link": "[balance]\nlinks = ['crnak']\n",
    "no_crank": "[balance]\nlinks = ['rocker']\n",
    "n_small": "[balance]\nn = 5\n",
    "angles_text": "[balance]\nangles = ['a']\n",
    "angles_nan": "[balance]\nangles = [nan]\n",
    "balance_not_table": "balance = 3\n",
}


@pytest.mark.parametrize("case", sorted(BROKEN_BALANCE))
def test_cli_balance_broken_files_one_line_exit_2(tmp_path, capsys, case):
    text = EXAMPLE.read_text() + "\n" + BROKEN_BALANCE[case]
    f = _write(tmp_path, text)
    rc = main(["balance", str(f), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err


@pytest.mark.parametrize("args", [
    ["balance", "/nonexistent/x.toml"],
    ["balance", str(EXAMPLE), "--angles", "a,b"],
    ["balance", str(EXAMPLE), "--angles", ","],
    ["balance", str(EXAMPLE), "--bogus"],
])
def test_cli_balance_bad_arguments_one_line_exit_2(tmp_path, capsys, args):
    rc = main([*args, "--out", str(tmp_path / "o")] if "--bogus" not in args else args)
    err = capsys.readouterr().err
    assert rc == 2, err
    assert len(err.strip().splitlines()) == 1, err


@pytest.mark.parametrize("text", [
    "type = 'planar'\n[frame\n",                                     # invalid TOML
    "type = 'sine'\nname = 'x'\n",                                   # not a planar file
])
def test_cli_balance_broken_toml_one_line_exit_2(tmp_path, capsys, text):
    rc = main(["balance", str(_write(tmp_path, text)), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert len(err.strip().splitlines()) == 1, err


def test_cli_balance_wrong_units_in_the_mechanism(tmp_path, capsys):
    text = EXAMPLE.read_text().replace('mass = "3 kg"', 'mass = "3 m"')
    rc = main(["balance", str(_write(tmp_path, text)), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1, err
    assert "mass" in err


@pytest.mark.parametrize("radii, words", [
    ("{ crank = '50 kg' }", ["balance.radii", "crank", "length"]),
    ("'0 mm'", ["balance.radii", "> 0"]),
    ("{ crank = '-5 mm', rocker = 0.1 }", ["balance.radii", "crank", "> 0"]),
    ("true", ["balance.radii", "length"]),
])
def test_cli_balance_bad_radii_named_plainly(tmp_path, capsys, radii, words):
    """The error named pydantic's internal union types
    ('balance.radii.dict[str,function-before[convert(), float]].crank'), a zero radius was
    reported without the file or key ('radius = 0 is invalid'), 'true' was taken as 1 m."""
    text = EXAMPLE.read_text() + f"\n[balance]\nradii = {radii}\n"
    rc = main(["balance", str(_write(tmp_path, text)), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1, err
    assert "function-before" not in err and "dict[" not in err
    for w in words:
        assert w in err


@pytest.mark.parametrize("angles", ["90", "30,210"])
def test_cli_balance_table_positions_that_cannot_fit_the_axis(tmp_path, capsys, angles):
    """One table angle (or two half a turn apart) cannot determine (x, y): the error named
    'phi = 1 positions', a parameter the user never gave; now it names the positions."""
    rc = main(["balance", str(EXAMPLE), "--angles", angles, "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1, err
    assert "positions" in err and "phi =" not in err


def test_cli_cycle_csv_has_shaking_force_and_bearing_reactions(tmp_path, capsys):
    """balance_cycle.csv had only M, dM1..3, Q0, Q1: the shaking force before/after and the
    frame-bearing reactions (which the command reports as raised) were in no output file."""
    import csv

    out = tmp_path / "o"
    assert main(["balance", str(EXAMPLE), "--out", str(out)]) == 0
    capsys.readouterr()
    with (out / "balance_cycle.csv").open() as fh:
        rows = list(csv.reader(fh))
    head, data = rows[0], np.array(rows[1:], float)
    for col in ("Fx0 [N]", "Fy0 [N]", "Fx1 [N]", "Fy1 [N]", "R0_O [N]", "R1_C [N]", "R3_O [N]",
                "R3_O1 [N]", "Q1 [N*m]", "phi1 [rad]"):
        assert col in head, head
    # independent: the engine's shaking force and reaction at C of the unbalanced mechanism
    phi = data[:, head.index("phi1 [rad]")]
    mech = paper_fourbar()
    d = inverse_dynamics(kinematics(mech, phi), about=(0, 0))
    assert np.allclose(data[:, head.index("Fx0 [N]")], d.shaking_fx, rtol=1e-9, atol=1e-9)
    i = [j.name for j in mech.joints][3]  # O4 = C of the example
    assert np.allclose(data[:, head.index("R0_C [N]")], d.reaction_magnitude(i), rtol=1e-9)
    assert np.max(np.abs(data[:, head.index("Fx1 [N]")])) < 1e-9


def test_cli_balance_negative_mass_is_short_and_keyed(tmp_path, capsys):
    text = EXAMPLE.read_text().replace('mass = "3 kg"', 'mass = "-3 kg"')
    rc = main(["balance", str(_write(tmp_path, text)), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and len(err.strip().splitlines()) == 1
    assert "body.1.mass (coupler): -3 kg is invalid" in err and len(err) < 300


def test_cli_balance_linear_driver_refused_before_work_naming_file(tmp_path, capsys):
    from _cli_files import LINEAR_SLIDER_CRANK
    f = tmp_path / "lin.toml"
    f.write_text(LINEAR_SLIDER_CRANK)
    code, text, err = run_cli(["balance", str(f), "--out", str(tmp_path / "o")], capsys)
    assert code == 2 and text == "" and len(err.strip().splitlines()) == 1
    assert f"{f}: driver: linear driver on joint G is invalid: balancing (paper 001)" in err
    assert not (tmp_path / "o").exists() or not any((tmp_path / "o").iterdir())


def test_cli_balance_of_a_self_locking_file_names_its_friction(tmp_path, capsys):
    """The sine press with its slot at 12 deg self-locks at 151..206 and 283..357 deg with the
    file's friction (docs/friction.md): balancing, which compares the driving torque and the
    bearing loads over a full turn, stops with one line naming the file, the joints'
    coefficients and the ranges (it failed with 'moment = nan is invalid'), and writes
    nothing; at 60 deg the same file balances."""
    out = tmp_path / "out"
    path = sine_press_with_friction(tmp_path, '"12 deg"')
    code, _, err = run_cli(["balance", str(path), "--out", str(out)], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert f"{path}: joint friction: 0.05 (A), 0.1 (guide), 0.12 (slot) is invalid" in err
    assert "makes the mechanism self-lock at phi1 in [151, 206 deg], [283, 357 deg]" in err
    assert not list(out.glob("balanc*"))
    path = sine_press_with_friction(tmp_path)
    assert run_cli(["balance", str(path), "--out", str(out)], capsys)[0] == 0
