"""The one CSV and JSON writer (linkwork.results): an undefined value (NaN) is an empty CSV cell
and JSON null, the JSON is strict, infinities are refused naming the column or key. Checked
with the standard library's readers, independent of the writers."""

import csv
import json
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

from linkwork.errors import ParameterError
from linkwork.results import Result, strict_json_values, write_csv, write_json


def _strict_loads(text):
    """json.loads that refuses NaN, Infinity and -Infinity (as strict parsers do)."""
    def refuse(name):
        raise ValueError(f"non-standard JSON constant {name}")
    return json.loads(text, parse_constant=refuse)


@dataclass(frozen=True)
class _Curve(Result):
    phi: np.ndarray
    ratio: np.ndarray
    mean: float

    units: ClassVar[dict[str, str]] = {"phi": "rad", "ratio": "", "mean": ""}
    position_field: ClassVar[str] = "phi"

    def plot(self, **kwargs):  # every Result family overrides it (tests/plot/test_figures.py)
        raise NotImplementedError("a writer test's result has no figure")


def test_write_csv_nan_is_an_empty_cell_and_numbers_stay_exact(tmp_path):
    x = np.array([0.1, 1.0 / 3.0, -2.5e-300, 7.0])
    y = np.array([1.0, np.nan, 0.0, np.nan])
    p = write_csv(tmp_path / "a.csv", {"x": (x, "m"), "y": (y, "")})
    with p.open(newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["x [m]", "y []"]
    assert [r[1] for r in rows[1:]] == ["1.0", "", "0.0", ""]
    assert [float(r[0]) for r in rows[1:]] == x.tolist()  # full precision, round trip
    assert "nan" not in p.read_text().lower()


def test_write_csv_refuses_inf_naming_the_column_before_writing(tmp_path):
    with pytest.raises(ParameterError, match=r"b = inf at 1 of 2 positions.*too large"):
        write_csv(tmp_path / "b.csv", {"a": ([1.0, 2.0], ""), "b": ([1.0, -np.inf], "N")})
    assert not (tmp_path / "b.csv").exists()


def test_write_json_is_strict_nan_becomes_null(tmp_path):
    data = {"a": float("nan"), "b": [1.0, np.float64("nan"), 2.5], "c": (np.nan, "text"),
            "d": {"e": [[np.nan, 1e-300]]}, "f": True, "g": None, "h": 3}
    p = write_json(tmp_path / "a.json", data)
    back = _strict_loads(p.read_text())
    assert back == {"a": None, "b": [1.0, None, 2.5], "c": [None, "text"],
                    "d": {"e": [[None, 1e-300]]}, "f": True, "g": None, "h": 3}
    assert "NaN" not in p.read_text()


@pytest.mark.parametrize(("data", "where"), [
    ({"a": {"b": [0.0, float("inf")]}}, r"a\.b\[1\]"),
    ({"q": -np.inf}, "q"),
    ([1.0, [2.0, float("-inf")]], r"\[1\]\[1\]"),
])
def test_write_json_refuses_inf_naming_its_key_before_writing(tmp_path, data, where):
    with pytest.raises(ParameterError, match=where + ".*too large"):
        write_json(tmp_path / "c.json", data)
    assert not (tmp_path / "c.json").exists()


def test_strict_json_values_leaves_the_input_alone_and_dumps_never_fail():
    data = {"x": [float("nan"), 1.0], "y": float("nan")}
    out = strict_json_values(data)
    assert math.isnan(data["x"][0]) and math.isnan(data["y"])  # not modified in place
    json.dumps(out, allow_nan=False)  # must not raise


def test_result_exports_undefined_values_as_empty_cells_and_null(tmp_path):
    r = _Curve(phi=np.array([0.0, 1.0, 2.0]), ratio=np.array([0.5, np.nan, 0.25]),
               mean=float("nan"))
    d = r.to_dict()
    assert d["columns"]["ratio"] == [0.5, None, 0.25] and d["mean"] is None
    json.dumps(d, allow_nan=False)
    back = _strict_loads(r.to_json(tmp_path / "r.json").read_text())
    assert back["columns"]["ratio"] == [0.5, None, 0.25] and back["mean"] is None
    with r.to_csv(tmp_path / "r.csv").open(newline="") as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["phi [rad]", "ratio []"]
    assert [row[1] for row in rows[1:]] == ["0.5", "", "0.25"]


def test_result_with_inf_is_refused_by_every_export(tmp_path):
    r = _Curve(phi=np.array([0.0, 1.0]), ratio=np.array([1.0, np.inf]), mean=1.0)
    for export in (r.to_dict, lambda: r.to_json(tmp_path / "r.json"),
                   lambda: r.to_csv(tmp_path / "r.csv")):
        with pytest.raises(ParameterError, match="ratio = inf at 1 of 2 positions"):
            export()
    assert not list(tmp_path.iterdir())


def _csv_module_reference(columns: dict) -> str:
    """The CSV text as the csv module writes it row by row, repr(float), NaN empty."""
    import csv
    import io
    fh = io.StringIO(newline="")
    w = csv.writer(fh)
    w.writerow([f"{k} [{u}]" for k, (_, u) in columns.items()])
    for row in zip(*(np.asarray(v, float) for v, _ in columns.values()), strict=True):
        w.writerow(["" if x != x else repr(float(x)) for x in row])
    return fh.getvalue()


@pytest.mark.parametrize("ncols", [1, 2, 7])
def test_block_csv_writer_is_the_csv_module_text(tmp_path, ncols, monkeypatch):
    import linkwork.results as results
    monkeypatch.setattr(results, "CSV_BLOCK_ROWS", 37)  # many blocks, a short last one
    rng = np.random.default_rng(5)
    n = 500
    cols = {}
    for i in range(ncols):
        v = rng.normal(size=n) * 10.0 ** rng.integers(-30, 30, size=n)
        v[::11] = np.nan
        v[::13] = -0.0
        v[::17] = 5e-324
        cols[f"c{i}"] = (v, "m")
    seen = []
    p = results.write_csv(tmp_path / "a.csv", cols, progress=lambda d, t: seen.append((d, t)))
    with open(p, newline="") as fh:
        assert fh.read() == _csv_module_reference(cols)
    assert seen[-1] == (n, n) and len(seen) == -(-n // 37)


def test_csv_rows_in_chunks_is_the_same_file_and_atomic(tmp_path, monkeypatch):
    """Rows appended in chunks of uneven sizes (a long cycle computed chunk by chunk) give the
    text of the csv module for the whole table; a chunk with other columns is refused naming
    them; an error inside the block leaves no file."""
    import linkwork.results as results
    monkeypatch.setattr(results, "CSV_BLOCK_ROWS", 10)
    rng = np.random.default_rng(6)
    x, y = rng.normal(size=103), rng.normal(size=103) * 1e-300
    y[5] = np.nan
    with results.csv_rows(tmp_path / "a.csv", {"x": "m", "y": "N"}) as out:
        for lo, hi in ((0, 1), (1, 40), (40, 41), (41, 103)):
            out.append({"x": x[lo:hi], "y": y[lo:hi]})
    assert out.rows == 103
    with open(tmp_path / "a.csv", newline="") as fh:
        assert fh.read() == _csv_module_reference({"x": (x, "m"), "y": (y, "N")})
    with pytest.raises(ParameterError, match="header's columns"), \
            results.csv_rows(tmp_path / "b.csv", {"x": "m", "y": "N"}) as out:
        out.append({"x": x[:3], "y": y[:3]})
        out.append({"y": y[:3], "x": x[:3]})
    with pytest.raises(ParameterError, match="y = inf at 1 of 3"), \
            results.csv_rows(tmp_path / "c.csv", {"x": "m", "y": "N"}) as out:
        out.append({"x": x[:3], "y": [1.0, np.inf, 2.0]})
    assert sorted(q.name for q in tmp_path.iterdir()) == ["a.csv"]


def test_json_writer_reads_back_as_the_strict_values(tmp_path):
    data = {"name": "four-bar", "units": {"x": "m"}, "empty": {}, "none": [],
            "x": [0.1, float("nan"), -0.0, 1e300], "nested": [{"a": [1, 2]}, {"b": "c"}],
            "ints": (1, 2, 3), "flag": True, "text": 'quote " and \\ backslash'}
    p = write_json(tmp_path / "a.json", data)
    expected = json.loads(json.dumps({**data, "x": [0.1, None, -0.0, 1e300],
                                      "ints": [1, 2, 3]}))
    assert json.loads(p.read_text()) == expected


@pytest.mark.parametrize("n", [0, 1, 5, 4096, 4097, 9000])
def test_json_arrays_are_the_text_of_their_lists(tmp_path, n):
    """A float array is written as the JSON of json_array's list of it, byte for byte (NaN as
    null, -0.0, subnormal, huge and integer-valued floats; across the writer's 4096-value
    blocks), so planar.json written from arrays is the file written from lists."""
    from linkwork.results import json_array

    rng = np.random.default_rng(7)
    a = rng.normal(size=n) * 10.0 ** rng.integers(-300, 300, size=n)
    specials = [np.nan, -0.0, 5e-324, 1.7976931348623157e308, 3.0, -np.nan]
    a[:min(n, len(specials))] = specials[:n]
    lists = write_json(tmp_path / "lists.json", {"c": {"x": json_array(a)}, "n": n})
    arrays = write_json(tmp_path / "arrays.json", {"c": {"x": a}, "n": n})
    assert arrays.read_text() == lists.read_text()
    back = json.loads(arrays.read_text())["c"]["x"]
    assert [None if math.isnan(v) else v for v in a.tolist()] == back


def test_json_array_with_inf_is_refused_naming_its_place(tmp_path):
    a = np.array([1.0, 2.0, np.inf])
    with pytest.raises(ParameterError, match=r"columns\.x\[2\]"):
        write_json(tmp_path / "a.json", {"columns": {"x": a}})
    assert not list(tmp_path.iterdir())
