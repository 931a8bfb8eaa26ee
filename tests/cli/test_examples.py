"""`linkwork examples [--copy DIR]`: the bundled example files (linkwork/cli/examples.py)."""

import tomllib
from pathlib import Path

import pytest

from linkwork.cli import examples as cli_examples
from linkwork.cli import main

ROOT = Path(__file__).resolve().parents[2]
CHECKOUT = sorted(p.name for p in (ROOT / "examples").glob("*.toml"))


def test_from_a_checkout_the_checkouts_examples_are_listed(capsys):
    assert cli_examples.examples_dir() == ROOT / "examples"
    assert main(["examples"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [ln.split()[0] for ln in lines[:-1]] == CHECKOUT
    for ln in lines[:-1]:
        name, kind, *desc = ln.split()
        text = (ROOT / "examples" / name).read_text()
        assert kind == tomllib.loads(text)["type"]
        assert " ".join(desc) == text.splitlines()[0].lstrip("# ").strip()
    assert "--copy DIR" in lines[-1]


def test_copy_copies_every_example_byte_for_byte(tmp_path, capsys):
    dest = tmp_path / "a" / "ex"
    assert main(["examples", "--copy", str(dest)]) == 0
    assert sorted(p.name for p in dest.iterdir()) == CHECKOUT
    for name in CHECKOUT:
        assert (dest / name).read_bytes() == (ROOT / "examples" / name).read_bytes()
    assert capsys.readouterr().out == f"copied {len(CHECKOUT)} examples into {dest}\n"


def test_copy_never_overwrites_and_copies_nothing_then(tmp_path, capsys):
    (tmp_path / CHECKOUT[-1]).write_text("mine")
    assert main(["examples", "--copy", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "would overwrite" in err and CHECKOUT[-1] in err
    assert [p.name for p in tmp_path.iterdir()] == [CHECKOUT[-1]]
    assert (tmp_path / CHECKOUT[-1]).read_text() == "mine"


def test_copy_onto_a_file_is_one_line(tmp_path, capsys):
    (tmp_path / "f").write_text("")
    assert main(["examples", "--copy", str(tmp_path / "f")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "must be a folder" in err


def test_an_installed_package_uses_its_bundled_folder(tmp_path, monkeypatch):
    """Inside a wheel the examples are linkwork/examples (pyproject's force-include)."""
    pkg = tmp_path / "linkwork"
    (pkg / "examples").mkdir(parents=True)
    (pkg / "examples" / "only.toml").write_text("# Only one.\ntype = 'planar'\n")
    monkeypatch.setattr(cli_examples.resources, "files", lambda name: pkg)
    assert cli_examples.examples_dir() == pkg / "examples"
    assert [(e.name, e.type, e.description) for e in cli_examples.bundled()] == [
        ("only.toml", "planar", "Only one.")]


@pytest.mark.parametrize("arg", ["fourbar_paper001.toml", "examples/sine_press.toml"])
def test_a_missing_file_named_like_an_example_says_how_to_get_it(arg, tmp_path, monkeypatch,
                                                                  capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["analyze", arg]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "file not found" in err
    assert "linkwork examples --copy examples" in err


def test_other_missing_files_get_no_hint(tmp_path, capsys):
    assert main(["analyze", str(tmp_path / "mine.toml")]) == 2
    assert "bundled" not in capsys.readouterr().err


def test_pyproject_puts_the_examples_into_the_wheel():
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())
    force = meta["tool"]["hatch"]["build"]["targets"]["wheel"]["force-include"]
    assert force == {"examples": "linkwork/examples"}
