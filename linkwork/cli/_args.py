"""Arguments shared by the commands: table positions (``--angles``) and the output folder."""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

import numpy as np

from linkwork.errors import ParameterError
from linkwork.io.planar import MAX_ANGLE

__all__ = ["output_dir", "parse_angles", "parse_angles_deg"]


def parse_angles_deg(text: str, *, angles: bool = True) -> list[float]:
    """Parse a comma-separated list of crank angles in degrees (``"0,30,90"``); with
    ``angles=False`` any finite numbers (a linear driver's slide positions in mm)."""
    try:
        vals = [float(t) for t in text.split(",") if t.strip()]
    except ValueError:
        limit = "must be comma-separated numbers in degrees"
        raise ParameterError("--angles", text, limit) from None
    if not vals:
        raise ParameterError("--angles", text, "must list at least one angle")
    bad = [v for v in vals if not np.isfinite(v)]
    if bad:
        raise ParameterError("--angles", bad[0], "must be finite numbers in degrees")
    if angles:
        lim = math.degrees(MAX_ANGLE)
        far = [v for v in vals if abs(v) > lim]  # -1e300 was printed as a 300-digit angle
        if far:
            raise ParameterError("--angles", f"{far[0]:g}", f"must lie within +-{lim:.6g} deg "
                                 f"(+-{MAX_ANGLE:g} rad): beyond it the float spacing of "
                                 "angles exceeds 1e-10 rad")
    return vals


def parse_angles(text: str) -> np.ndarray:
    """Parse a comma-separated list of crank angles in degrees (``"0,30,90"``) to radians."""
    return np.radians(np.array(parse_angles_deg(text)))


def output_dir(out: Path) -> Path:
    """Create the output folder ``--out`` (with parents) and check that files can be written
    into it, before any work; else a ParameterError naming it: an existing file of that name,
    a folder that cannot be created, or one that cannot be written into (permissions,
    read-only disk: found before the study, not at its first file)."""
    try:
        out.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise ParameterError("--out", str(out), "must be a folder; a file of that name "
                             "exists") from None
    except OSError as exc:
        raise ParameterError("--out", str(out), f"cannot be created as a folder "
                             f"({exc.strerror or exc})") from None
    try:  # a real file, removed at once: os.access ignores read-only mounts
        with tempfile.TemporaryFile(dir=out, prefix=".linkwork-probe-"):
            pass
    except OSError as exc:
        raise ParameterError("--out", str(out), f"cannot be written into "
                             f"({exc.strerror or exc})") from None
    return out
