"""Several drivers in a planar file (``[[driver]]`` with start and stop each).

Reference: the engine called directly on the file's mechanism with the positions written out
here (each driver linear from its start to its stop over [analysis] n); the study's columns
must equal it (same numbers, 1e-12 of their scale). Bad files: one line naming the key.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from linkwork import io
from linkwork.cli import main
from linkwork.errors import FileFormatError
from linkwork.planar import inverse_dynamics, kinematics
from linkwork.studies import planar as study

FILE = Path(__file__).resolve().parents[1] / "data" / "drivers" / "five_bar_two_cranks.toml"


def test_two_crank_file_columns_are_the_engines():
    doc = io.load(FILE)
    phi = doc.positions()
    assert phi.shape == (2, 61)
    assert phi[:, 0] == pytest.approx(np.radians([76.0, 95.0]), abs=1e-15)
    assert phi[:, -1] == pytest.approx(np.radians([136.0, 65.0]), abs=1e-15)
    s = study.analyze(doc)
    kin = kinematics(doc.mechanism(), phi, [2 * np.pi, -np.pi], 0.0)
    dyn = inverse_dynamics(kin, gravity=(0.0, -9.81))
    cols = s.columns()
    for k, j in enumerate(("O1", "O2")):
        assert np.array_equal(cols[f"phi1.{j}"][0], phi[k])
        assert cols[f"omega1.{j}"] == (pytest.approx(kin.omega1[k]), "rad/s")
        assert np.max(np.abs(cols[f"Q.{j}"][0] - dyn.Q[k])) <= 1e-12 * np.max(np.abs(dyn.Q))
        assert cols[f"Q.{j}"][1] == "N*m"
    assert "phi1" not in cols and "Q" not in cols
    assert set(s.dynamics_columns()) >= {"phi1.O1", "phi1.O2", "Q.O1", "Q.O2", "R_P.x"}
    assert not {"Q.O1", "Q.O2"} & set(s.kinematics_columns())
    assert s.table_positions.shape == (2, 12)
    assert s.dead_centres == []
    d = s.to_dict()
    assert d["means"]["Q_mean"].keys() == {"O1", "O2"}
    assert d["positions_unit"] == "rad" and "Q.<driver joint>" in d["torque_sign"]
    peak = next(p for p in s.peaks if p["name"] == "Q O1 min")
    assert peak["position"] == 60 and peak["phi1"] == pytest.approx(list(phi[:, 60]))


@pytest.mark.parametrize(("change", "key", "words"), [
    (('start = "76 deg"\n', ""), "driver.0.start", "own start and stop"),
    (("n = 61", 'n = 61\nstart = "0 deg"'), "analysis.start", "each [[driver]]"),
    (("[[driver]]\njoint = \"O2\"", '[[driver]]\njoint = "O1"'), "sketch.drivers",
     "driven twice"),
])
def test_bad_several_driver_files(tmp_path, change, key, words):
    f = tmp_path / "bad.toml"
    f.write_text(FILE.read_text().replace(*change))
    with pytest.raises(FileFormatError, match=words.replace("[", r"\[")) as err:
        io.load(f)
    assert key in str(err.value)


@pytest.mark.parametrize(("args", "words"), [
    (["analyze", "--angles", "0,30"], "--angles = 0,30 is invalid: gives one driver's"),
    (["reactions", "--angles", "0,30"], "--angles = 0,30 is invalid: gives one driver's"),
    (["balance", "--pareto"], "--pareto = True is invalid: is for one crank's cycle"),
    (["balance", "--angles", "0,30"], "--angles = 0,30 is invalid: is for one crank's cycle"),
])
def test_commands_that_take_one_driver_say_so_in_one_line(tmp_path, capsys, args, words):
    code = main([args[0], str(FILE), *args[1:], "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and words in err
