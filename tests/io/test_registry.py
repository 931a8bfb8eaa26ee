"""linkwork.io: one registry of file classes, one loader, the old module paths as shims."""

from pathlib import Path

import pytest

import linkwork.cli
from linkwork import files, io
from linkwork.errors import FileFormatError
from linkwork.io.planar import PlanarFile
from linkwork.io.sine_press import SinePressFile
from linkwork.io.swashplate import SwashplateFile
from linkwork.io.synthesis import SynthesisFile
from linkwork.io.toml import read_toml

ROOT = Path(__file__).resolve().parents[2]
FILES = sorted([*(ROOT / "examples").glob("*.toml"), *(ROOT / "tests" / "data").glob("*.toml")])


def test_registry_maps_every_type_to_its_class():
    assert io.FILE_TYPES == {"planar": PlanarFile, "sine_press": SinePressFile,
                             "swashplate": SwashplateFile, "synthesis": SynthesisFile}
    assert files.schemas() == io.FILE_TYPES  # the deprecated accessor reads the same registry


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_every_bundled_file_loads_as_the_class_of_its_type(path):
    """Every file of examples/ and tests/data/ loads unchanged, as the class its ``type``
    names, and the deprecated linkwork.files.load gives the same document."""
    doc = io.load(path)
    assert type(doc) is io.FILE_TYPES[read_toml(path)["type"]]
    assert files.load(path) == doc


@pytest.mark.parametrize("text, problem", [
    ("name = 'x'\n", "type: missing required key; one of ['planar', 'sine_press', "
                     "'swashplate', 'synthesis']"),
    ("type = 'loom'\n", "type: unknown type 'loom'; one of ['planar', 'sine_press', "
                        "'swashplate', 'synthesis']"),
])
def test_unknown_or_missing_type_names_the_registered_types(tmp_path, text, problem):
    f = tmp_path / "m.toml"
    f.write_text(text)
    with pytest.raises(FileFormatError) as exc:
        io.load(f)
    assert str(exc.value) == f"{f}: {problem}"


def test_old_module_paths_are_shims_of_io():
    import linkwork.planar.file as planar_file
    import linkwork.redundancy.spec as spec
    import linkwork.sine_press_file as sine_press_file
    import linkwork.swashplate_file as swashplate_file
    from linkwork.cli.balance import BalanceSection

    assert planar_file.PlanarFile is PlanarFile
    assert sine_press_file.SinePressFile is SinePressFile
    assert swashplate_file.SwashplateFile is SwashplateFile
    assert spec.SpatialSpec is io.planar.SpatialSpec
    assert spec.read_spatial is io.planar.read_spatial
    assert BalanceSection is io.planar.BalanceSection
    assert files.FileModel is io.FileModel


def test_commands_are_found_through_modules_not_strings():
    assert all(hasattr(m, "register") for m in linkwork.cli.COMMAND_MODULES)
    assert not any(isinstance(m, str) for m in linkwork.cli.COMMAND_MODULES)
    from linkwork.cli.analyze import ANALYZERS

    assert set(ANALYZERS) == set(io.FILE_TYPES.values())
    assert all(callable(fn) for fn in ANALYZERS.values())


def test_a_plain_pydantic_model_registered_the_old_way_loads(tmp_path):
    """files.register_schema (deprecated) adds a class to io.FILE_TYPES; io.load validates a
    plain pydantic model too, with the file and key in its errors."""
    from pydantic import BaseModel

    class Gear(BaseModel):
        type: str
        teeth: int

    try:
        assert files.register_schema("gear")(Gear) is Gear
        assert io.FILE_TYPES["gear"] is Gear
        f = tmp_path / "g.toml"
        f.write_text("type = 'gear'\nteeth = 20\n")
        assert io.load(f) == Gear(type="gear", teeth=20)
        f.write_text("type = 'gear'\nteeth = 'many'\n")
        with pytest.raises(FileFormatError) as exc:
            io.load(f)
        assert exc.value.key == "teeth"
    finally:
        io.FILE_TYPES.pop("gear", None)
