"""studies.planar.analyze_chunked: a cycle analysed chunk by chunk (bounded memory) reports
what studies.planar.analyze reports of the whole cycle held at once -- extremes and their
positions, dead centres, table -- exactly, the means and friction losses (summed chunk by chunk)
to round-off, and streams the same per-position columns. Chunks of 37 positions put many
chunk boundaries inside every cycle (also inside dead-centre intervals and locked runs)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from _cli_files import sine_press_with_friction

from linkwork import io
from linkwork.errors import AssemblyError, ParameterError
from linkwork.results import csv_rows
from linkwork.studies import planar as study_planar

ROOT = Path(__file__).resolve().parents[2]
ALL_PLANAR = [p for p in [*sorted((ROOT / "examples").glob("*.toml")),
                          *sorted((ROOT / "tests" / "data").glob("*.toml"))]
              if io.read_toml(p)["type"] == "planar"]
#: one driver: what analyze_chunked takes (several drivers are refused, see below)
PLANAR = [p for p in ALL_PLANAR if io.load(p).mechanism().n_drivers == 1]
SEVERAL = [p for p in ALL_PLANAR if io.load(p).mechanism().n_drivers > 1]


def _friction_files(tmp_path):
    for sub in ("a", "b"):
        (tmp_path / sub).mkdir()
    return [sine_press_with_friction(tmp_path / "a"),           # runs freely
            sine_press_with_friction(tmp_path / "b", '"12 deg"')]  # self-locks over a range


def _compare(doc, chunk):
    whole = study_planar.analyze(doc)
    got: list[tuple[dict, dict]] = []
    summary = study_planar.analyze_chunked(doc, chunk=chunk,
                                           sink=lambda k, d: got.append((k, d)))
    assert summary.n == whole.kinematics.n and summary.chunk == chunk
    assert len(got) == -(-summary.n // chunk)
    # extremes and their positions: exactly (first position of a tie, as over the whole); a
    # Newton-solved group (continued from the drawing to each chunk's first position, as to the
    # whole cycle's) to its tolerance, 1e-12 of the length scale: values to 1e-9 relative
    newton = summary.mechanism.plan.newton
    if newton:
        assert [(p["name"], p["phi1"]) for p in summary.peaks] == [
            (p["name"], p["phi1"]) for p in whole.peaks]
        for a, b in zip(summary.peaks, whole.peaks, strict=True):
            assert abs(a["value"] - b["value"]) <= 1e-9 * max(abs(b["value"]), 1e-9), a["name"]
    else:
        assert summary.peaks == whole.peaks
    assert summary.dead_centres == whole.dead_centres
    assert summary.dead_centre_labels == whole.dead_centre_labels
    assert summary.branches == dict(whole.kinematics.branches)
    # means: trapezoid sums continued across chunks; round-off of the driving torque's scale
    q_scale = max(abs(p["value"]) for p in whole.peaks if p["name"].startswith("Q "))
    w_scale = q_scale * float(np.max(np.abs(whole.kinematics.omega1)))
    for key, scale in (("Q_mean", q_scale), ("power_mean", w_scale)):
        a, b = summary.means[key], whole.means[key]
        assert np.isnan(a) == np.isnan(b), key  # undefined where some position self-locks
        if not np.isnan(b):
            assert abs(a - b) <= 1e-12 * scale, key
    if whole.friction is None:
        assert summary.friction is None
    else:
        a, b = summary.friction, whole.friction
        for key in ("self_locking", "locked_positions", "newton_iterations"):
            assert a[key] == b[key], key
        work = abs(b["driving_work"] or 0.0) + sum(abs(v or 0.0) for v in b["losses"].values())
        for key in ("driving_work", "efficiency_cycle"):
            assert (a[key] is None) == (b[key] is None), key
            if b[key] is not None:
                assert abs(a[key] - b[key]) <= 1e-12 * max(work, 1.0), key
        for j, v in b["losses"].items():
            assert (a["losses"][j] is None) == (v is None)
            if v is not None:
                assert abs(a["losses"][j] - v) <= 1e-12 * work
    # the loads' extremes exactly, their work to round-off
    assert len(summary.loads) == len(whole.loads)
    for a, b in zip(summary.loads, whole.loads, strict=True):
        for key in set(b) - {"work"}:
            assert a[key] == b[key], (b["name"], key)
        assert (a["work"] is None) == (b["work"] is None)
        if b["work"] is not None:
            assert abs(a["work"] - b["work"]) <= 1e-12 * max(abs(b["work"]), w_scale, 1.0)
    np.testing.assert_array_equal(summary.table_dynamics.Q, whole.table_dynamics.Q)
    # the streamed columns: those of the whole cycle (by the joints' structure: a couple or
    # friction power that is zero throughout is a column of zeros here)
    kin_cols = {k: np.concatenate([c[0][k] for c in got]) for k in got[0][0]}
    dyn_cols = {k: np.concatenate([c[1][k] for c in got]) for k in got[0][1]}
    for mine, ref in ((kin_cols, whole.kinematics_columns()),
                      (dyn_cols, whole.dynamics_columns())):
        assert set(ref) <= set(mine)
        for k, (v, _) in ref.items():
            if newton:  # the group's Newton tolerance, 1e-12 of the length scale
                np.testing.assert_allclose(mine[k], v, rtol=1e-9, atol=1e-9 * np.nanmax(
                    np.abs(v), initial=1.0), err_msg=k)
            else:
                np.testing.assert_array_equal(mine[k], v, err_msg=k)
        for k in set(mine) - set(ref):
            assert not np.any(mine[k]), k
    return summary


@pytest.mark.parametrize("path", PLANAR, ids=lambda p: p.name)
def test_chunked_equals_the_whole_cycle(path):
    _compare(io.load(path), 37)


def test_chunked_with_friction_and_self_locking(tmp_path):
    for path in _friction_files(tmp_path):
        s = _compare(io.load(path), 37)
        assert s.friction is not None
    assert s.friction["self_locking"] and s.friction["efficiency_cycle"] is None


def test_one_chunk_and_chunks_of_two(tmp_path):
    doc = io.load(ROOT / "examples" / "fourbar_paper001.toml")
    _compare(doc, 2)
    _compare(doc, 10**6)


def test_chunked_csv_files_equal_the_whole_cycles(tmp_path):
    """Through csv_rows, the streamed planar_kinematics.csv is the text write_csv gives for
    the whole cycle (four-bar of paper 001: no couple, no friction, same columns)."""
    from linkwork.results import write_csv

    doc = io.load(ROOT / "examples" / "fourbar_paper001.toml")
    whole = study_planar.analyze(doc)
    ref = write_csv(tmp_path / "ref.csv", whole.kinematics_columns()).read_text()
    units = {k: u for k, (_, u) in whole.kinematics_columns().items()}
    with csv_rows(tmp_path / "chunked.csv", units) as out:
        study_planar.analyze_chunked(doc, chunk=50, sink=lambda k, d: out.append(k))
    assert (tmp_path / "chunked.csv").read_text() == ref


def test_given_positions_and_bad_input():
    doc = io.load(ROOT / "examples" / "fourbar_paper001.toml")
    phi = np.linspace(0.0, 4 * np.pi, 1001)  # two turns: any number of positions
    s = study_planar.analyze_chunked(doc, positions=phi, chunk=300)
    assert s.n == 1001 and s.first == 0.0 and s.last == 4 * np.pi
    assert len(s.dead_centres) == 2 * len(study_planar.analyze(doc).dead_centres)
    with pytest.raises(ParameterError, match="chunk"):
        study_planar.analyze_chunked(doc, chunk=1)
    with pytest.raises(ParameterError, match="positions"):
        study_planar.analyze_chunked(doc, positions=[0.0, np.nan])


@pytest.mark.parametrize("path", SEVERAL, ids=lambda p: p.name)
def test_several_drivers_are_refused_by_name(path):
    """A path of several drivers is analysed whole (analyze); the chunked study says so."""
    assert study_planar.analyze(io.load(path)).kinematics.phi1.ndim == 2
    with pytest.raises(ParameterError, match=r"drivers = [2-9].*must be 1.*analyze"):
        study_planar.analyze_chunked(io.load(path))


def test_unassembled_chunk_names_its_positions(tmp_path):
    """A position where the mechanism cannot be assembled stops the study at its chunk, naming
    the driver range and the positions of that chunk (paper 001's four-bar with a 250 mm crank
    does not turn fully)."""
    text = (ROOT / "examples" / "fourbar_paper001.toml").read_text()
    path = tmp_path / "short.toml"
    path.write_text(text.replace('length = "100 mm"', 'length = "250 mm"', 1))
    doc = io.load(path)
    phi = np.linspace(0.0, 2 * np.pi, 200)
    with pytest.raises(AssemblyError, match=r"positions \d+-\d+ of 200") as err:
        study_planar.analyze_chunked(doc, positions=phi, chunk=50)
    assert err.value.ranges and "cannot assemble at" in str(err.value)
