"""``linkwork analyze`` on planar-engine files: the cycle extremes, dead centres, mean torque and
power, the JSON's sign statements and the table titles, against hand computations (power
balance, written-out positions) and the library's own results."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from _planar_references import _crank_rod_slider_energy, _fourbar_paper001_torque, _fourbar_torque

from linkwork.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _analyze(example: str, out: Path, capsys: pytest.CaptureFixture[str], *extra: str
             ) -> tuple[str, dict]:
    assert main(["analyze", str(EXAMPLES / example), "--out", str(out), *extra]) == 0
    text = capsys.readouterr().out
    return text, json.loads((out / "planar.json").read_text())


def _sine_press_by_hand(phi: np.ndarray) -> dict[str, np.ndarray]:
    """examples/sine_press_planar.toml written out: crank L1 = 50 mm at 120 rpm, slot at 60 deg,
    ram 25 kg sliding along x (x up, g = -9.81 along x), crank 6 kg with its centre 10 mm out,
    8 kN along +x on the ram for 100 <= phi1 <= 150 deg."""
    L1, al, w, g, m_ram, m_crank = 0.05, np.radians(60.0), 4.0 * np.pi, -9.81, 25.0, 6.0
    # the slot line through B = L1 (cos, sin) at alpha crosses y = 0 at x_S
    v = w * L1 * (-np.sin(phi) - np.cos(phi) / np.tan(al))      # d x_S / dt
    a = w * w * L1 * (-np.cos(phi) + np.sin(phi) / np.tan(al))  # d2 x_S / dt2
    deg = np.degrees(phi)
    F = np.where((deg >= 100.0 - 1e-9) & (deg <= 150.0 + 1e-9), 8000.0, 0.0)
    v_crank_x = -0.01 * w * np.sin(phi)
    # power balance; the crank's kinetic energy is constant at constant omega1
    Q = (m_ram * v * a - (m_ram * g * v + m_crank * g * v_crank_x + F * v)) / w
    # the slot carries only a force normal to it: its x component balances the ram along x
    slot = np.abs(F + m_ram * g - m_ram * a) / np.sin(al)
    x32 = L1 * np.sin(phi) / np.sin(al)                        # pin to S along the slot
    return {"Q": Q, "slot": slot, "guide_couple": np.abs(x32) * slot}


def test_analyze_reports_cycle_extremes_of_torque_and_reactions(tmp_path, capsys):
    """The table at 30 deg steps missed the peaks an engineer sizes the motor and bearings
    for: the sine press's driving torque peaks at 335.9 N m at 100 deg (the table showed
    217.7 at 120), the ram guide's couple (499.5 N m) appeared nowhere but in the CSV."""
    text, data = _analyze("sine_press_planar.toml", tmp_path, capsys)
    phi = np.radians(np.linspace(0.0, 360.0, 361))
    ref = _sine_press_by_hand(phi)
    peaks = {p["name"]: p for p in data["peaks"]}
    assert data["positions_unit"] == "rad"
    i = int(np.argmax(ref["Q"]))
    assert peaks["Q max"]["value"] == pytest.approx(ref["Q"][i], rel=1e-7)
    assert peaks["Q max"]["phi1"] == pytest.approx(phi[i], abs=1e-12)
    assert peaks["Q max"]["unit"] == "N*m"
    assert np.degrees(phi[i]) == pytest.approx(100.0)  # at the start of the working load
    i = int(np.argmin(ref["Q"]))
    assert peaks["Q min"]["value"] == pytest.approx(ref["Q"][i], rel=1e-7)
    for name, key in (("|R slot|", "slot"), ("|M guide|", "guide_couple")):
        i = int(np.argmax(ref[key]))
        assert peaks[name]["value"] == pytest.approx(ref[key][i], rel=1e-7)
        assert peaks[name]["phi1"] == pytest.approx(phi[i], abs=1e-12)
    # printed: the quantity with its unit, the value and where
    line = next(ln for ln in text.splitlines() if "Q max [N·m]" in ln)
    assert f"{ref['Q'].max():.4g}" in line and "100.0" in line
    assert "|M guide| [N·m]" in text


def test_fourbar_paper001_torque_extremes_against_the_power_balance(tmp_path, capsys):
    """Reference: hand computations of tests/_planar_references.py (power balance). Tolerance:
    atol=1e-5, abs=1e-5, abs=1e-12."""
    _text, data = _analyze("fourbar_paper001.toml", tmp_path, capsys)
    phi = np.radians(np.linspace(0.0, 360.0, 361))
    Q = _fourbar_paper001_torque(phi)
    np.testing.assert_allclose(data["columns"]["Q"], Q, atol=1e-5)
    peaks = {p["name"]: p for p in data["peaks"]}
    for name, i in (("Q max", int(np.argmax(Q))), ("Q min", int(np.argmin(Q)))):
        assert peaks[name]["value"] == pytest.approx(Q[i], abs=1e-5)
        assert peaks[name]["phi1"] == pytest.approx(phi[i], abs=1e-12)
    assert np.degrees(peaks["Q min"]["phi1"]) == pytest.approx(356.0)


LINEAR = Path(__file__).parents[1] / "data" / "slider_driven_crank.toml"


def _slider_driven_crank_force(s: np.ndarray) -> np.ndarray:
    """tests/data/slider_driven_crank.toml written out: slider B at (s, 0), crank O A = 0.1 m
    with A on the left of O -> B, rod 0.35 m; thin rods 1 and 2 kg, slider 3 kg; v1 = 0.5 m/s;
    -3 N m on the crank.
    Q v1 = dT/dt - P_loads, i.e. Q = dT/ds + 3 d theta_crank / ds."""
    r, l, v1 = 0.1, 0.35, 0.5

    def coords(s: np.ndarray) -> np.ndarray:
        x = (r * r - l * l + s * s) / (2 * s)             # A: circle O (r) with circle B (l)
        A = np.stack([x, np.sqrt(r * r - x * x)])
        B = np.stack([s, np.zeros_like(s)])
        th1 = np.arctan2(A[1], A[0])
        th2 = np.arctan2(B[1] - A[1], B[0] - A[0])
        return np.stack([*(A / 2), th1, *((A + B) / 2), th2, s])

    def energy(s: np.ndarray) -> np.ndarray:
        h = 1e-7
        return _crank_rod_slider_energy((coords(s + h) - coords(s - h)) / (2 * h) * v1, r, l)

    h = 1e-5
    dT = (energy(s + h) - energy(s - h)) / (2 * h)
    dth = (coords(s + h)[2] - coords(s - h)[2]) / (2 * h)
    return dT + 3.0 * dth


def test_analyze_angles_of_a_linear_driver_are_slide_positions_in_mm(tmp_path, capsys,
                                                                     monkeypatch):
    """--angles was silently ignored for a linear driver (the table stayed at 12 positions over
    [analysis]); it now gives slide positions in mm, as in `linkwork reactions`."""
    monkeypatch.setenv("COLUMNS", "250")
    f = LINEAR
    assert main(["analyze", str(f), "--out", str(tmp_path), "--angles", "300,350"]) == 0
    rows = [ln.split("│") for ln in capsys.readouterr().out.splitlines()
            if ln.startswith("│") and "quantity" not in ln]
    table = [r for r in rows if len(r) > 5]
    assert [float(r[1]) for r in table] == [300.0, 350.0]
    Q = _slider_driven_crank_force(np.array([0.300, 0.350]))
    np.testing.assert_allclose([float(r[2]) for r in table], Q, rtol=2e-4)  # printed to 4 digits
    # outside the range where it assembles: named with the unit it was read in
    assert main(["analyze", str(f), "--out", str(tmp_path), "--angles", "100"]) == 2
    err = capsys.readouterr().err
    assert "--angles = 100 mm" in err and len(err.strip().splitlines()) == 1


def test_dead_centres_say_which_coordinate_and_which_way(tmp_path, capsys):
    """The knuckle press printed 'ram max at 184.70 deg' where the ram is at its lowest (its
    guide points down, and the slide coordinate runs along it): the line now says what is
    extreme and which way. The positions: the ram's lowest point found here by a dense scan
    of the geometry written out; the rocker's extremes of paper 001's four-bar from the
    crank and coupler collinear (|OB| = 0.1 + 0.3 and 0.3 - 0.1)."""
    text, data = _analyze("loom_sixbar.toml", tmp_path, capsys)
    O, r, rod, upper, lower = np.array([0.61, -0.3]), 0.06, 0.55, 0.35, 0.35

    def ram_y(phi: np.ndarray) -> np.ndarray:
        A = O[:, None] + r * np.stack([np.cos(phi), np.sin(phi)])
        L = np.hypot(*A)                       # C at the origin
        x = (rod**2 - upper**2 + L * L) / (2 * L)
        u = -A / L                             # from A towards C
        K = A + x * u + np.sqrt(rod**2 - x * x) * np.stack([-u[1], u[0]])
        return K[1] - np.sqrt(lower**2 - K[0] ** 2)

    phi = np.radians(np.linspace(150.0, 220.0, 700001))
    lowest = np.degrees(phi[np.argmin(ram_y(phi))])
    assert f"ram slide max along G (towards -90 deg) at {lowest:.2f} deg" in text
    dc = next(d for d in data["dead_centres"] if d["body"] == "ram" and d["kind"] == "max")
    assert dc["of"] == "ram slide max along G (towards -90 deg)" and dc["joint"] == "G"
    assert np.degrees(dc["phi1"]) == pytest.approx(lowest, abs=1e-4)

    text, _ = _analyze("fourbar_paper001.toml", tmp_path, capsys)
    ext = np.degrees(np.arctan2(np.sqrt(0.4**2 - 0.35**2), 0.35))          # x_B = 0.35
    fold = 180.0 + np.degrees(np.arctan2(np.sqrt(0.2**2 - 0.15**2), 0.15))  # x_B = 0.15
    assert (f"  rocker angle min at {ext:.2f} deg\n  rocker angle max at {fold:.2f} deg\n"
            in text)


def test_mean_driving_torque_and_power_are_work_per_cycle(tmp_path, capsys):
    """The torque plot's 'mean' line was np.nanmean over 0..360 deg with the end repeating the
    start: for paper 001's four-bar (no loads, constant speed: no net work over a cycle, so
    the mean torque is 0) it drew -3.43/361 = -0.0095 N m, and nowhere said its value; the
    mean torque and mean driving power (motor sizing) were not reported at all."""
    from linkwork import files
    from linkwork.planar import inverse_dynamics, kinematics
    from linkwork.plot.planar import plot_driving_torque, plot_shaking

    _, data = _analyze("fourbar_paper001.toml", tmp_path, capsys)
    assert abs(data["means"]["Q_mean"]) < 1e-9 and abs(data["means"]["power_mean"]) < 1e-8
    doc = files.load(EXAMPLES / "fourbar_paper001.toml")
    kin = kinematics(doc.mechanism(), doc.positions())
    drawn = plot_driving_torque(inverse_dynamics(kin))["ax"]
    mean_line = next(ln for ln in drawn.get_lines() if ln.get_label().startswith("mean"))
    assert abs(mean_line.get_ydata()[0]) < 1e-9
    assert "N·m" in mean_line.get_label()
    # the shaking moment's reference point is labelled with its unit
    ax = plot_shaking(inverse_dynamics(kin, about=(0.1, -0.05)))["axes"][1]
    assert ax.get_lines()[0].get_label() == "M about (100, -50) mm"

    # the sine press: 8 kN over the ram's descent from 100 to 150 deg; the mean of the sampled
    # torque written out by hand (trapezoid over the same samples), and the exact work / 2 pi
    _, data = _analyze("sine_press_planar.toml", tmp_path, capsys)
    phi = np.radians(np.linspace(0.0, 360.0, 361))
    Q = _sine_press_by_hand(phi)["Q"]
    assert data["means"]["Q_mean"] == pytest.approx(np.trapezoid(Q, phi) / (2 * np.pi), rel=1e-8)
    assert data["means"]["power_mean"] == pytest.approx(data["means"]["Q_mean"] * 4 * np.pi)
    x_s = 0.05 * (np.cos(phi) - np.sin(phi) / np.tan(np.radians(60.0)))
    work = 8000.0 * (x_s[100] - x_s[150])
    assert data["means"]["Q_mean"] == pytest.approx(work / (2 * np.pi), rel=0.03)  # step load


def test_one_planar_file_serves_analyze_balance_and_reactions(tmp_path, capsys):
    """'linkwork analyze examples/loom_fourbar_spatial.toml' failed with 'spatial: unknown key'
    (and a file with a [balance] table likewise; 'balance' refused [spatial], 'reactions'
    refused [balance]): each command now leaves the other commands' tables alone. The loom
    four-bar's torque (gravity, 4 N m on the rocker) against the power balance by hand."""
    _, data = _analyze("loom_fourbar_spatial.toml", tmp_path / "a", capsys)
    phi = np.radians(np.arange(0.0, 360.0))
    Q = _fourbar_torque(phi, (0.001, 0.0225, 0.00567), gy=-9.81, mz_rocker=4.0)
    np.testing.assert_allclose(data["columns"]["Q"], Q, atol=1e-5 * np.abs(Q).max())
    both = tmp_path / "both.toml"
    both.write_text((EXAMPLES / "loom_fourbar_spatial.toml").read_text()
                    + "\n[balance]\nangles = [0, 90]\n")
    for command in ("analyze", "balance", "reactions"):
        assert main([command, str(both), "--out", str(tmp_path / command)]) == 0, command
    capsys.readouterr()
    typo = tmp_path / "typo.toml"
    typo.write_text((EXAMPLES / "loom_fourbar_spatial.toml").read_text()
                    .replace("[spatial]", "[spatail]").replace("[spatial.", "[spatail."))
    assert main(["analyze", str(typo), "--out", str(tmp_path / "t")]) == 2
    assert "spatail: unknown key" in capsys.readouterr().err


def test_json_states_the_torque_and_shaking_signs(tmp_path, capsys):
    """planar.json stated the reactions' sign but not the driving torque's nor the shaking
    loads' (a reader of the JSON alone could not tell motor torque from load torque). The
    statement must agree with the numbers: while the sine press's 8 kN resists the ram, the
    motor supplies power (Q omega1 > 0 by the power balance written out here)."""
    _, data = _analyze("sine_press_planar.toml", tmp_path, capsys)
    assert data["torque_sign"].startswith("Q: torque on body 'crank' of driver joint 'A'")
    assert "counter-clockwise +" in data["torque_sign"]
    assert "on the frame" in data["shaking_sign"] and "(0, 0) m" in data["shaking_sign"]
    phi = np.radians(np.linspace(0.0, 360.0, 361))
    Q = _sine_press_by_hand(phi)["Q"]
    got = np.asarray(data["columns"]["Q"])
    assert Q[120] > 100.0 and np.sign(got[120]) == 1.0
    np.testing.assert_allclose(got, Q, rtol=1e-7, atol=1e-6)


def test_extremes_include_the_worst_transmission_angle(tmp_path, capsys):
    """The smallest transmission angle over the cycle (the classic design check, e.g. mu >= 40
    deg) and where it occurs were not reported. Paper 001's four-bar: cos mu = (b^2 + c^2 -
    |AC|^2) / (2 b c) is largest at the shortest |AC| = d - a (crank towards C, phi1 = 0):
    mu_min = arccos(0.75) = 41.41 deg. The sine press: mu = alpha = 60 deg throughout."""
    text, data = _analyze("fourbar_paper001.toml", tmp_path, capsys)
    pk = next(p for p in data["peaks"] if p["name"] == "μ B min")
    assert pk["unit"] == "rad"
    assert pk["value"] == pytest.approx(np.arccos(0.75), abs=1e-12)
    assert np.cos(pk["phi1"]) == pytest.approx(1.0)
    assert f"{np.degrees(np.arccos(0.75)):.4g}" in next(
        ln for ln in text.splitlines() if "μ B min [deg]" in ln)
    _, data = _analyze("sine_press_planar.toml", tmp_path, capsys)
    pk = next(p for p in data["peaks"] if p["name"] == "μ slot min")
    assert pk["value"] == pytest.approx(np.radians(60.0), abs=1e-12)


def test_table_title_names_driving_force_and_the_moment_reference(tmp_path, capsys,
                                                                   monkeypatch):
    """The table's title said 'driving torque' for a linear driver (whose Q is a force in N)
    and 'shaking' without the point its moment column M_sh is taken about. The point printed
    must be the one the numbers use: moving it from O to P changes M by -(P x F_sh)."""
    monkeypatch.setenv("COLUMNS", "250")
    assert main(["analyze", str(LINEAR), "--out", str(tmp_path / "lin")]) == 0
    assert "driving force, joint reactions" in capsys.readouterr().out
    _, at_o = _analyze("fourbar_paper001.toml", tmp_path / "o", capsys)
    moved = tmp_path / "moved.toml"
    moved.write_text((EXAMPLES / "fourbar_paper001.toml").read_text().replace(
        "about = [0, 0]", 'about = ["300 mm", "-20 mm"]'))
    assert main(["analyze", str(moved), "--out", str(tmp_path / "p")]) == 0
    text = capsys.readouterr().out
    assert "driving torque, joint reactions" in text and "about (300, -20) mm" in text
    at_p = json.loads((tmp_path / "p" / "planar.json").read_text())["columns"]
    c = at_o["columns"]
    fx, fy = np.asarray(c["shaking_fx"]), np.asarray(c["shaking_fy"])
    expected = np.asarray(c["shaking_m"]) - (0.3 * fy - (-0.02) * fx)
    np.testing.assert_allclose(at_p["shaking_m"], expected, atol=1e-12)
