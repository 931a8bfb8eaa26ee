"""The common base of linkwork's result objects.

A result is a frozen dataclass of NumPy arrays whose last axis runs over the positions of the
cycle (shape ``(..., n)``), plus scalars that describe the inputs. It knows the unit of each
field (class attribute ``units``) and exports itself to a dict, CSV, JSON and, where pandas is
installed, a DataFrame; it draws its family's default figure with ``.plot()``, which imports
:mod:`linkwork.plot` (and so matplotlib) only when called and returns one
:class:`linkwork.plot.Figure` for every family.
"""

from __future__ import annotations

import contextlib
import csv
import dataclasses
import functools
import json
import math
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from linkwork.errors import MissingExtraError, ParameterError
from linkwork.outputs import atomic_path

__all__ = ["CsvRows", "Result", "all_true", "atomic_path", "csv_rows", "json_array",
           "strict_json_values", "write_csv", "write_json"]


@functools.lru_cache(maxsize=64)
def all_true(shape: tuple[int, ...]) -> np.ndarray:
    """A read-only all-True boolean array of ``shape``, made once per shape.

    The ``valid`` mask of a result in which every position assembled: results are immutable,
    so one shared array serves them all (making it anew is 1 us, 3 % of a 360-position
    crank-slider).
    """
    arr = np.ones(shape, dtype=bool)
    arr.flags.writeable = False
    return arr


_TOO_LARGE = ("must be finite: an input is too large for double precision (check the "
              "magnitudes and units of speeds, lengths and loads)")


def _refuse_inf(name: str, values: Any) -> None:
    """Raise a :class:`ParameterError` naming ``name`` if ``values`` hold an infinity."""
    arr = np.asarray(values)
    if arr.dtype.kind in "fc" and np.isinf(arr).any():
        raise ParameterError(name, f"inf at {int(np.isinf(arr).sum())} of {arr.size} positions",
                             _TOO_LARGE)


def _cell(x: float) -> str:
    """A CSV cell: ``repr(float)``, or empty for NaN (a value undefined at that position)."""
    return "" if x != x else repr(x)


#: Rows of a CSV file formatted and written at a time (bounded memory for any length).
CSV_BLOCK_ROWS = 4096


class CsvRows:
    """Rows of a CSV table appended block by block to an open text file: the one formatting of
    every CSV file linkwork writes (header ``name [unit]``, values as ``repr(float)``, an empty
    cell for NaN, ``\\r\\n`` line ends as the csv module writes them).

    ``header`` maps each column name to its unit; :meth:`append` takes a block of rows as a
    mapping of the same names, in the same order, to equal-length arrays, and writes it
    :data:`CSV_BLOCK_ROWS` rows at a time (the text of a block is never in memory whole). A
    long cycle computed in chunks streams through it (:func:`csv_rows`).
    """

    def __init__(self, fh: Any, header: dict[str, str]) -> None:
        self._fh = fh
        self.names = tuple(header)
        self.rows = 0
        # as the csv module writes a lone empty cell
        self._empty = '""' if len(self.names) == 1 else ""
        csv.writer(fh).writerow([f"{k} [{u}]" for k, u in header.items()])

    def append(self, columns: dict[str, Any],
               progress: Callable[[int, int], None] | None = None) -> None:
        """Write one block of rows; ``progress(rows_done, rows)`` after every
        :data:`CSV_BLOCK_ROWS` rows of it. Infinite values are refused (naming the column)
        before anything of the block is written."""
        if tuple(columns) != self.names:
            raise ParameterError("columns", list(columns), f"must be the header's columns "
                                 f"{list(self.names)} in order")
        for name, values in columns.items():
            _refuse_inf(name, values)
        arrays = [np.asarray(v, dtype=float) for v in columns.values()]
        n = len(arrays[0]) if arrays else 0
        for name, a in zip(columns, arrays, strict=True):
            if a.shape != (n,):
                raise ParameterError(f"columns[{name!r}]", f"shape {a.shape}",
                                     f"must be one value per row, like the first column ({n})")
        table = np.column_stack(arrays) if arrays else np.empty((0, 0))
        for start in range(0, n, CSV_BLOCK_ROWS):
            rows = table[start:start + CSV_BLOCK_ROWS].tolist()  # Python floats: repr below
            # repr(float) is the shortest text that reads back the same double; NaN -> empty
            # (no other cell can contain "nan": infinities were refused above)
            self._fh.write("".join(",".join(map(repr, r)) + "\r\n" for r in rows)
                           .replace("nan", self._empty))
            if progress is not None:
                progress(min(start + CSV_BLOCK_ROWS, n), n)
        self.rows += n


@contextlib.contextmanager
def csv_rows(path: str | Path, header: dict[str, str]) -> Iterator[CsvRows]:
    """A CSV file written block by block (:class:`CsvRows`): beside ``path`` and renamed when
    the block completes (:func:`atomic_path`), so an error or interrupt leaves no partial
    file."""
    with atomic_path(Path(path)) as tmp, tmp.open("w", newline="") as fh:
        yield CsvRows(fh, header)


def write_csv(path: str | Path, columns: dict[str, tuple[Any, str]], *,
              progress: Callable[[int, int], None] | None = None) -> Path:
    """Write equal-length columns as CSV: header ``name [unit]``, values as ``repr(float)``.

    The one CSV writer of linkwork: every result and every command's table goes through it, so
    that all CSV files read the same way (full double precision, units in the header; a value
    smaller than round-off stays as computed: round-off there is data).  ``columns`` maps a
    column name to ``(values, unit)``.  Returns the path.

    An empty cell is a value undefined at that position: unassembled (a result computed with
    ``on_failure="nan"``), or 0/0 (e.g. the efficiency of a slide that carries no load); NaN in
    the arrays is written so, never as ``nan``.  An infinite value is refused before the file
    is opened (:class:`~linkwork.errors.ParameterError` naming the column): it means an input
    beyond double precision, not a result.

    Rows are formatted and written :data:`CSV_BLOCK_ROWS` at a time (the text of the whole file
    is never in memory); ``progress(rows_done, rows)`` is called after each block.  The file is
    written beside ``path`` and renamed when complete (:func:`atomic_path`): an interrupted
    write leaves no partial file. Rows that come in chunks: :func:`csv_rows`.
    """
    for name, (values, _) in columns.items():
        _refuse_inf(name, values)
    arrays = [np.asarray(v, dtype=float) for v, _ in columns.values()]
    n = len(arrays[0]) if arrays else 0
    for name, a in zip(columns, arrays, strict=True):
        if a.shape != (n,):
            raise ParameterError(f"columns[{name!r}]", f"shape {a.shape}",
                                 f"must be one value per row, like the first column ({n})")
    p = Path(path)
    with csv_rows(p, {k: u for k, (_, u) in columns.items()}) as out:
        out.append({k: a for k, a in zip(columns, arrays, strict=True)}, progress)
    return p


def _strict_item(value: Any, where: str) -> Any:
    if isinstance(value, dict | list | tuple):
        return strict_json_values(value, where)
    if isinstance(value, float):  # also numpy.float64
        if value != value:
            return None
        if math.isinf(value):
            raise ParameterError(where or "value", value, _TOO_LARGE)
    return value


def strict_json_values(data: Any, where: str = "") -> Any:
    """``data`` with every NaN replaced by ``None`` (JSON ``null``), for strict JSON.

    Dicts, lists and tuples are walked (tuples become lists, as JSON writes them); a float NaN
    (Python or NumPy double) becomes ``None``; an infinite float is refused with a
    :class:`~linkwork.errors.ParameterError` naming its key path (``where`` is the path of
    ``data``), since it means an input beyond double precision.  Everything else is returned
    as it is.
    """
    if isinstance(data, dict):
        return {k: _strict_item(v, f"{where}.{k}" if where else str(k))
                for k, v in data.items()}
    if isinstance(data, list | tuple):
        out = []
        for i, v in enumerate(data):
            if isinstance(v, float) and v == v and not math.isinf(v):
                out.append(v)  # the common case, without building the key path
            else:
                out.append(_strict_item(v, f"{where}[{i}]"))
        return out
    return _strict_item(data, where)


def json_array(values: Any) -> list[Any]:
    """An array as a JSON list: floats, with None (``null``) where a value is not finite (a
    value undefined at that position). Converted by NumPy, not element by element in Python
    (4.5x faster on the columns of a 20 000-position analysis)."""
    arr = np.asarray(values, dtype=float)
    out = arr.astype(object)
    out[~np.isfinite(arr)] = None
    return list(out.tolist())


def _json_lines(value: Any, level: int, where: str = "") -> Iterator[str]:
    """The pieces of strict, indented JSON text of ``value``: objects, and lists that start
    with an object or a list, one item per line; other lists (arrays of numbers) on one line
    by the C encoder.  NaN becomes null; an infinity is refused naming its key path."""
    if isinstance(value, dict) and value:
        pad = "\n" + " " * (level + 1)
        yield "{"
        for i, (k, v) in enumerate(value.items()):
            yield ("," if i else "") + pad + json.dumps(str(k)) + ": "
            yield from _json_lines(v, level + 1, f"{where}.{k}" if where else str(k))
        yield "\n" + " " * level + "}"
    elif isinstance(value, list | tuple) and value and isinstance(value[0], dict | list | tuple):
        pad = "\n" + " " * (level + 1)
        yield "["
        for i, v in enumerate(value):
            yield ("," if i else "") + pad
            yield from _json_lines(v, level + 1, f"{where}[{i}]")
        yield "\n" + " " * level + "]"
    elif isinstance(value, np.ndarray) and value.ndim == 1 and value.dtype.kind == "f":
        yield from _json_array_pieces(value, where)
    else:
        try:  # the common case: nothing to replace
            yield json.dumps(value, allow_nan=False)
        except ValueError:  # NaN (-> null) or an infinity (refused, naming where)
            yield json.dumps(strict_json_values(value, where), allow_nan=False)


def _json_array_pieces(values: np.ndarray, where: str) -> Iterator[str]:
    """A float array as the JSON text of the list :func:`json_array` makes of it (``[1.0,
    null, 2.5]``: the same text, as the C encoder writes a list), :data:`CSV_BLOCK_ROWS` values
    at a time: the list of Python floats (32 bytes a value) is never made."""
    inf = np.isinf(values)
    if inf.any():
        i = int(np.argmax(inf))
        raise ParameterError(f"{where}[{i}]", float(values[i]), _TOO_LARGE)
    yield "["
    for start in range(0, values.size, CSV_BLOCK_ROWS):
        block = values[start:start + CSV_BLOCK_ROWS].tolist()
        # repr(float) is json's float text; NaN -> null (no other value contains "nan")
        yield (", " if start else "") + ", ".join(map(repr, block)).replace("nan", "null")
    yield "]"


def write_json(path: str | Path, data: Any) -> Path:
    """Write ``data`` (JSON-able Python values) as indented, strict JSON; the one JSON writer.

    Strict: NaN (a value undefined at a position, see :func:`write_csv`) is written as
    ``null``, never as the bare ``NaN`` that strict parsers reject; an infinite value is
    refused (:func:`strict_json_values`) and leaves no file.  Objects are indented one
    key per line; a list of numbers (an array over the positions) is one line, encoded by
    Python's C encoder (the indenting encoder is pure Python: 1.8x slower on a 40 000-position
    analysis); a one-dimensional float NumPy array is written as that list would be, block by
    block, without making the list (NaN as null).  Written piece by piece beside ``path`` and
    renamed when complete (:func:`atomic_path`).  Returns the path.
    """
    p = Path(path)
    with atomic_path(p) as tmp, tmp.open("w") as fh:
        for piece in _json_lines(data, 0):  # an infinity raises here: no file is left
            fh.write(piece)
        fh.write("\n")
    return p


class Result:
    """Mixin for frozen dataclass results: export to dict / CSV / JSON / DataFrame, and plot.

    Subclasses are ``@dataclass(frozen=True)`` and set ``units`` (field name -> unit string) and
    optionally ``position_field`` (the name of the driver-position array, e.g. ``"phi1"``).
    Every family overrides :meth:`plot` with its default figure, importing its
    :mod:`linkwork.plot` module inside the method (plot modules never import results at run
    time, so there is no import circle). Exports go through :func:`write_csv` and
    :func:`write_json` only.
    """

    units: ClassVar[dict[str, str]] = {}
    position_field: ClassVar[str] = "phi1"

    @classmethod
    def _assemble(cls, fields: dict[str, Any]) -> Any:
        """Build the result from a dict of all its fields without the dataclass ``__init__``.

        The frozen dataclass ``__init__`` sets each field through ``object.__setattr__``
        (about 7 us for twenty fields, a fifth of a whole 360-position crank-slider
        evaluation); closed forms that are called in tight loops use this instead (1.3 us;
        the dict becomes the object's ``__dict__``, so the caller must not keep it).  Same
        object, same immutability; the field names are checked against the dataclass in the
        tests (``tests/models/test_crank_slider.py``,
        ``test_fast_assembled_result_is_the_dataclass_...``), not here.
        """
        obj = object.__new__(cls)
        object.__setattr__(obj, "__dict__", fields)
        return obj

    def _relabel_units(self, **units: str) -> None:
        """Give this result its own units for some fields (e.g. a linear driver: positions in
        m, driving force in N); exports (CSV header, JSON) use them."""
        object.__setattr__(self, "units", {**self.units, **units})

    def _fields(self) -> dict[str, Any]:
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}  # type: ignore[arg-type]

    def columns(self) -> dict[str, np.ndarray]:
        """Per-position arrays, flattened to 1-D columns (only 1-D-over-positions fields)."""
        pos = np.asarray(getattr(self, self.position_field))
        if pos.ndim == 0:  # a single position: everything is in scalars()
            return {}
        n = pos.shape[-1]
        cols: dict[str, np.ndarray] = {}
        for name, val in self._fields().items():
            arr = np.asarray(val)
            if arr.ndim >= 1 and arr.shape[-1] == n and arr.dtype.kind in "fcib":
                if arr.ndim == 1:
                    cols[name] = arr
                else:
                    flat = np.broadcast_to(arr, arr.shape).reshape(-1, n)
                    for i, row in enumerate(flat):
                        cols[f"{name}[{i}]"] = row
        return cols

    def scalars(self) -> dict[str, Any]:
        """Non-array fields and 0-d arrays, as plain Python values."""
        out: dict[str, Any] = {}
        for name, val in self._fields().items():
            arr = np.asarray(val) if not isinstance(val, str) else None
            if arr is None:
                out[name] = val
            elif arr.ndim == 0 and arr.dtype.kind in "fcib":
                out[name] = arr.item()
        return out

    def _check_no_overflow(self, cols: dict[str, np.ndarray]) -> None:
        """Refuse to write infinite values: they mean an input far beyond double precision
        (e.g. a crank speed of 1e200 rad/s squared into an acceleration), not a result.  NaN
        stays: a value undefined at a position (unassembled with ``on_failure="nan"``, or
        0/0), written as an empty CSV cell and JSON ``null``."""
        for k, v in cols.items():
            _refuse_inf(k, v)

    def to_dict(self) -> dict[str, Any]:
        """Everything as strict-JSON-able Python values, with units.

        A value undefined at a position (NaN in the arrays: unassembled, or 0/0) is ``None``
        (JSON ``null``), as :func:`write_json` writes it; an infinite value is refused
        (:class:`~linkwork.errors.ParameterError` naming the field).
        """
        data: dict[str, Any] = {"type": type(self).__name__, "units": dict(self.units)}
        data.update(self.scalars())
        cols = self.columns()
        self._check_no_overflow(cols)
        data["columns"] = {k: v.tolist() for k, v in cols.items()}
        return strict_json_values(data)

    def to_json(self, path: str | Path) -> Path:
        """Write :meth:`to_dict` as JSON; return the path."""
        return write_json(path, self.to_dict())

    def to_csv(self, path: str | Path) -> Path:
        """Write the per-position columns as CSV with a unit row in the header names (through
        :func:`write_csv`: a value undefined at a position is an empty cell)."""
        cols = self.columns() or {  # a single position: one row of its numbers
            k: np.atleast_1d(v) for k, v in self.scalars().items()
            if isinstance(v, int | float)}
        self._check_no_overflow(cols)
        return write_csv(path, {k: (v, self._unit_of(k)) for k, v in cols.items()})

    def _unit_of(self, column: str) -> str:
        """Unit of a CSV column: that of its field (``R[0]`` -> ``R``)."""
        return self.units.get(column.split("[")[0], "")

    def plot(self, **kwargs: Any) -> Any:
        """The default figure of this result family, a :class:`linkwork.plot.Figure`.

        Each result family overrides this (importing :mod:`linkwork.plot` lazily, since it
        imports matplotlib); keyword arguments go to the family's plotting function. (Typed
        ``Any`` here so that this base module does not refer to the plot layer above it.)
        """
        raise NotImplementedError(f"{type(self).__name__} has no default figure")

    def _scene(self) -> Any:
        """The drawing of the mechanism this result moves (a
        :class:`linkwork.plot.scene.Scene`), or None: results of a mechanism's motion
        override it, and then display themselves animated in a notebook."""
        return None

    def _repr_html_(self) -> str:
        """A notebook's display: the animated mechanism (if the result moves one) and a
        compact table of the fields (scalars, and the range of each per-position array); one
        self-contained HTML fragment (:func:`linkwork.plot.html.view_html`)."""
        from linkwork.plot.html import result_table, view_html

        return view_html(self._scene(), result_table(self))

    def to_frame(self) -> Any:
        """A pandas DataFrame of the per-position columns (requires pandas: ``pip install
        'linkwork[pandas]'``; without it a :class:`~linkwork.errors.MissingExtraError`, an
        ImportError)."""
        try:
            import pandas as pd  # optional dependency
        except ImportError:
            raise MissingExtraError("Result.to_frame()", "pandas",
                                    "pip install pandas (or 'linkwork[pandas]')") from None

        return pd.DataFrame(self.columns())
