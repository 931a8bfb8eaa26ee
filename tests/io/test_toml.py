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
