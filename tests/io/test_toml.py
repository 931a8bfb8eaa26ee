"""Reading input files (io/toml.py): what is not a small TOML file is refused in one line."""

from __future__ import annotations

import os
import threading
from pathlib import Path

import pytest

from linkwork.errors import FileFormatError
from linkwork.io.toml import MAX_FILE_BYTES, read_toml

EXAMPLE = Path(__file__).parents[2] / "examples" / "fourbar_paper001.toml"


@pytest.mark.parametrize("opening", ["[", "{a="])
def test_nesting_deeper_than_the_parser_is_a_file_error(tmp_path: Path, opening: str) -> None:
    closing = "]" if opening == "[" else "}"
    f = tmp_path / "deep.toml"
    f.write_text("x = " + opening * 2000 + ("1" if opening != "[" else "") + closing * 2000)
    with pytest.raises(FileFormatError, match="nested too deeply"):
        read_toml(f)


def test_endless_device_is_refused_after_the_limit() -> None:
    if not Path("/dev/zero").exists():
        pytest.skip("no /dev/zero on this system")
    with pytest.raises(FileFormatError, match=f"larger than {MAX_FILE_BYTES // 2**20} MiB"):
        read_toml("/dev/zero")


def test_oversized_file_is_refused(tmp_path: Path) -> None:
    f = tmp_path / "big.toml"
    f.write_bytes(b"# " + b"x" * MAX_FILE_BYTES + b"\n")
    with pytest.raises(FileFormatError, match="limit of an input file"):
        read_toml(f)


def test_a_pipe_is_read_like_the_file(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)
    text = EXAMPLE.read_bytes()

    def feed() -> None:
        with open(fifo, "wb") as fh:
            fh.write(text)

    t = threading.Thread(target=feed)
    t.start()
    try:
        assert read_toml(fifo) == read_toml(EXAMPLE)
    finally:
        t.join(timeout=10)


def test_not_utf8_names_the_file(tmp_path: Path) -> None:
    f = tmp_path / "latin1.toml"
    f.write_bytes(b'name = "\xe9"\n')
    with pytest.raises(FileFormatError, match=r"latin1\.toml: cannot be read"):
        read_toml(f)


# --- errors as written: the value with its unit, the file, the dotted key, the limit ---------

EXAMPLES = Path(__file__).parents[2] / "examples"


@pytest.mark.parametrize(("example", "old", "new", "expected", "not_si"), [
    # planar file: a body's length, through the mechanism's own check (entry named)
    ("fourbar_paper001.toml", 'length = "100 mm"', 'length = "-100 mm"',
     "body.0.length (crank): -100 mm is invalid: must be > 0", "-0.1"),
    # the sanity layer: the limit also in the unit written
    ("fourbar_paper001.toml", 'C = ["300 mm", 0]', 'C = ["3e9 mm", 0]',
     "frame.points.C.0: 3e9 mm is invalid: must lie within +-1e+07 mm (10000 m)", "3e+06"),
    # a pydantic bound (Field(gt=0)) of a swash-plate file and of a sine press file
    ("swashplate_1.toml", 'R = "100 mm"', 'R = "-100 mm"',
     "geometry.R: -100 mm is invalid: must be > 0", "-0.1"),
    ("sine_press.toml", 'L1 = "50 mm"', 'L1 = "-50 mm"',
     "crank.L1: -50 mm is invalid: must be > 0", "-0.05"),
    ("sine_press.toml", 'speed = "120 rpm"', 'speed = "1e9 rpm"',
     "crank.speed: 1e9 rpm is invalid: must lie within +-9.5493e+06 rpm (1e+06 rad/s)",
     "1.04720e+08"),
    # [drive]: a motor's own check quoting another key of the entry, as written there
    ("loom_sixbar.toml", 'rated_speed = "1420 rpm"', 'rated_speed = "1600 rpm"',
     "drive.motor.0.rated_speed: 1600 rpm is invalid: must be < synchronous_speed = 1500 rpm",
     "167.5"),
    ("loom_sixbar.toml", 'inertia = "0.002 kg*m^2"', 'inertia = "-2 g*m^2"',
     "drive.gear.inertia: -2 g*m^2 is invalid: must be >= 0", "-0.002"),
    # [spatial]: worded as `linkwork reactions` words it, the same way
    ("loom_fourbar_spatial.toml", 'k_bearing = "100 N/um"', 'k_bearing = "-100 N/um"',
     "spatial.k_bearing: -100 N/um is invalid: must be > 0", "-1e+08"),
    ("crank_press.toml", 'stiffness = "5 N/mm"', 'stiffness = "-5 N/mm"',
     "spring.0.stiffness: -5 N/mm is invalid: must be >= 0", "-5000"),
])
def test_a_value_that_fails_a_check_is_shown_as_written(tmp_path: Path, example: str, old: str,
                                                        new: str, expected: str,
                                                        not_si: str) -> None:
    """Over four file types and the three kinds of check (the models' own, the sanity layer,
    pydantic's bounds): the file, the dotted key, the value as typed with its unit and the
    limit, never the SI value."""
    from linkwork import io

    text = (EXAMPLES / example).read_text()
    assert old in text
    p = tmp_path / example
    p.write_text(text.replace(old, new, 1))
    with pytest.raises(FileFormatError) as exc:
        io.load(p)
    msg = str(exc.value)
    assert msg.startswith(f"{p}: "), msg
    assert expected in msg, msg
    assert not_si not in msg, msg
