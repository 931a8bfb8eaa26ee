"""Every linkwork file format, and the one registry of file types.

A file is a TOML document whose top-level ``type`` key says what it describes. Each type is a
pydantic class (a :class:`~linkwork.io.toml.FileModel`) in a module of this package:

* :class:`~linkwork.io.planar.PlanarFile` (``type = "planar"``): any planar linkage of the
  engine, with the optional ``[balance]`` and ``[spatial]`` sections;
* :class:`~linkwork.io.sine_press.SinePressFile` (``type = "sine_press"``): paper 000's press;
* :class:`~linkwork.io.swashplate.SwashplateFile` (``type = "swashplate"``): paper 003's drive;
* :class:`~linkwork.io.synthesis.SynthesisFile` (``type = "synthesis"``): a synthesis task
  (path, function or motion generation) for ``linkwork synthesize``.

:data:`FILE_TYPES` maps the ``type`` to the class; :func:`load` reads a file, picks the class and
returns the validated document. A new file type is a class in a new module here, added to
:data:`FILE_TYPES`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from linkwork.errors import FileFormatError
from linkwork.io.planar import PlanarFile
from linkwork.io.sine_press import SinePressFile
from linkwork.io.swashplate import SwashplateFile
from linkwork.io.synthesis import SynthesisFile
from linkwork.io.toml import FileModel, read_toml, validate

__all__ = ["FILE_TYPES", "FileModel", "PlanarFile", "SinePressFile", "SwashplateFile",
           "SynthesisFile", "load", "read_toml"]

#: File type (the file's top-level ``type`` key) -> its class.
FILE_TYPES: dict[str, type[FileModel]] = {
    "sine_press": SinePressFile,
    "planar": PlanarFile,
    "swashplate": SwashplateFile,
    "synthesis": SynthesisFile,
}


def load(path: str | Path, *, types: dict[str, type[FileModel]] | None = None) -> Any:
    """Read and validate a linkwork file; dispatch on its top-level ``type`` key.

    Parameters
    ----------
    path : str or Path
        The TOML file.
    types : dict, optional
        The file types accepted (default :data:`FILE_TYPES`).

    Raises
    ------
    FileFormatError
        The file is missing, unreadable, not TOML, of an unknown type or invalid; the message
        names the file and the key.
    """
    known = FILE_TYPES if types is None else types
    data = read_toml(path)
    kind = data.get("type")
    if kind is None:
        raise FileFormatError(str(path), "type", f"missing required key; one of {sorted(known)}")
    if kind not in known:
        raise FileFormatError(str(path), "type", f"unknown type {kind!r}; one of {sorted(known)}")
    cls = known[kind]
    if isinstance(cls, type) and issubclass(cls, FileModel):
        return cls.from_data(path, data)
    return validate(path, data, cls)  # a plain pydantic model (files.register_schema)
