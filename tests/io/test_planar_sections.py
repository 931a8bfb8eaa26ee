"""The planar file's optional [balance] and [spatial] tables: sections of one PlanarFile model,
read once, worded as the commands that use them worded them before."""

from pathlib import Path

import pytest

from linkwork import io
from linkwork.errors import FileFormatError
from linkwork.io.planar import BalanceSection, PlanarFile, SpatialSpec, read_spatial
from linkwork.io.toml import read_toml

ROOT = Path(__file__).resolve().parents[2]
SPATIAL = ROOT / "examples" / "loom_fourbar_spatial.toml"
FOURBAR = ROOT / "examples" / "fourbar_paper001.toml"


def test_spatial_section_equals_the_table_read_on_its_own():
    """The [spatial] section of the loaded file equals the table validated alone by
    read_spatial (the reader `linkwork reactions` used before)."""
    doc = io.load(SPATIAL)
    assert isinstance(doc, PlanarFile)
    assert doc.spatial == read_spatial(SPATIAL, read_toml(SPATIAL))
    assert doc.spatial.tolerance  # the example lists tolerances: the section is not a default
    assert doc.balance == BalanceSection()


def test_missing_sections_give_the_defaults():
    doc = io.load(FOURBAR)
    assert doc.balance == BalanceSection()
    assert doc.spatial == SpatialSpec() == read_spatial(FOURBAR, {})


def test_balance_section_values(tmp_path):
    f = tmp_path / "m.toml"
    f.write_text(FOURBAR.read_text() + '\n[balance]\nradii = { crank = "50 mm", rocker = 0.1 }'
                 '\nangles = [0, "90 deg", "3.14159 rad"]\nn = 72\n')
    doc = io.load(f)
    assert doc.balance.radii == {"crank": pytest.approx(0.05), "rocker": 0.1}
    assert doc.balance.angles == pytest.approx([0.0, 90.0, 179.9998], abs=1e-4)
    assert doc.balance.n == 72
    assert doc.balance == BalanceSection(radii={"crank": 0.05, "rocker": 0.1},
                                         angles=doc.balance.angles, n=72)


@pytest.mark.parametrize("extra", [
    "[spatial]\nstiff = 1\n",
    "[spatial.joints.A]\ne = '30 kg'\n",
    "[spatial.joints.A]\nstiffness = [1e8, 1e8]\n",
    "[[spatial.tolerance]]\njoint = 'C'\nbody = 'frame'\ncomponent = 'tx'\nlimit = '1 mm'\n",
])
def test_spatial_errors_are_worded_as_read_spatial_words_them(tmp_path, extra):
    text = SPATIAL.read_text()
    text = text[:text.index("\n[spatial]\n") + 1] + extra
    f = tmp_path / "m.toml"
    f.write_text(text)
    with pytest.raises(FileFormatError) as alone:
        read_spatial(f, read_toml(f))
    with pytest.raises(FileFormatError) as loaded:
        io.load(f)
    assert str(loaded.value) == str(alone.value)


@pytest.mark.parametrize("extra, key", [
    ("spatial = 3\n", "spatial"),
    ("balance = 3\n", "balance"),
])
def test_a_section_that_is_not_a_table(tmp_path, extra, key):
    f = tmp_path / "m.toml"
    f.write_text(extra + FOURBAR.read_text())
    with pytest.raises(FileFormatError) as exc:
        io.load(f)
    assert str(exc.value) == f"{f}: {key}: must be a table"


def test_spatial_names_are_checked_against_the_mechanism(tmp_path):
    f = tmp_path / "m.toml"
    f.write_text(FOURBAR.read_text() + "\n[spatial.joints.Z]\ne = '30 mm'\n")
    with pytest.raises(FileFormatError) as exc:
        io.load(f)
    assert exc.value.key == "spatial.joints.Z"
    assert "no joint 'Z'" in exc.value.problem


def test_the_mechanism_is_built_once():
    """The file's Mechanism (and so its cached structure decomposition) is the one built when
    the file was validated; a copy with other bodies builds its own."""
    doc = io.load(FOURBAR)
    mech = doc.mechanism()
    assert doc.mechanism() is mech
    assert mech.structure is doc.mechanism().structure
    other = doc.model_copy(update={"body": list(doc.body)})
    assert other.mechanism() is not mech
    assert other.mechanism().joints == mech.joints
