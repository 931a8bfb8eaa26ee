"""TOML files written from nested dicts, a crank-slider file builder, edits of the bundled examples
command-line runner, shared by the file and command tests."""

from __future__ import annotations

import json
from pathlib import Path

from linkwork.cli import main


def run_cli(args, capsys):
    """Exit code, stdout, stderr of the command line."""
    try:
        code = main(args)
    except SystemExit as exc:  # typer's standalone mode
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


def toml(doc, prefix=""):
    """A TOML text from nested dicts and lists (tables, arrays of tables, inline values)."""
    def val(v):
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, dict):
            return "{ " + ", ".join(f"{k} = {val(x)}" for k, x in v.items()) + " }"
        if isinstance(v, list | tuple):
            return "[" + ", ".join(val(x) for x in v) + "]"
        return repr(v)

    lines, later = [], []
    for k, v in doc.items():
        if isinstance(v, dict) and k in TABLES:
            later.append(f"\n[{prefix}{k}]\n" + toml(v, f"{prefix}{k}."))
        elif isinstance(v, list) and v and isinstance(v[0], dict):
            later += [f"\n[[{prefix}{k}]]\n" + toml(x, f"{prefix}{k}.") for x in v]
        else:
            lines.append(f"{k} = {val(v)}")
    return "\n".join(lines) + "".join(later) + "\n"


TABLES = {"frame", "driver", "analysis", "spatial", "balance", "joints"}


def link(name, start, end, length, mass, **kw):
    return dict(name=name, start=start, end=end, length=length, mass=mass, **kw)


def joint(name, kind, a, b, **kw):
    return dict(name=name, type=kind, a=a, b=b, **kw)


def slider_crank(guide, driver, analysis, **extra):
    """A crank-slider file: crank O-A 50 mm, rod A-B 200 mm, slider on the frame's guide G."""
    doc = {"type": "planar", "name": "crank-slider",
           "frame": {"points": {"O": [0, 0], "G": guide.pop("at", [0, 0])}},
           "body": [link("crank", "O", "A", "50 mm", "2 kg"),
                    link("rod", "A", "B", "200 mm", "3 kg"),
                    {"name": "slider", "points": {"B": [0, 0]}, "mass": "4 kg",
                     "inertia": "0.01 kg*m^2"}],
           "joint": [joint("O", "revolute", "frame", "crank"),
                     joint("A", "revolute", "crank", "rod"),
                     joint("B", "revolute", "rod", "slider"),
                     joint("G", "prismatic", "frame", "slider", through="G", point="B",
                           **guide)],
           "driver": driver, "analysis": analysis}
    doc.update(extra)
    return toml(doc)


LINEAR_SLIDER_CRANK = slider_crank(
    {}, {"type": "linear", "joint": "G", "v1": "1 m/s"},
    {"start": "160 mm", "stop": "240 mm", "n": 41, "branches": {"A": 1}})


EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def sine_press_with_friction(tmp_path: Path, angle: str = '"60 deg"') -> Path:
    """``examples/sine_press_planar.toml`` with friction at the crank bearing (f 0.05, journal
    30 mm), the ram's guide (f 0.10, a 200 mm block) and the slot (f 0.12, a sliding block),
    its slot at ``angle`` (TOML value)."""
    text = (EXAMPLES / "sine_press_planar.toml").read_text()
    text = text.replace('type = "revolute"\n', 'type = "revolute"\nfriction = 0.05\n'
                        'radius = "30 mm"\n', 1)
    text = text.replace('type = "prismatic"\n', 'type = "prismatic"\nfriction = 0.1\n'
                        'length = "200 mm"\n', 1)
    text = text.replace('type = "slot"\n', 'type = "slot"\nfriction = 0.12\n', 1)
    text = text.replace('angle = "60 deg"', f"angle = {angle}")
    f = tmp_path / "press.toml"
    f.write_text(text)
    return f


def edit_example_and_run(tmp_path, capsys, example: str, old: str, new: str,
                         cmd=("analyze",)) -> str:
    """Run a command on a bundled example with `old` replaced by `new`; one line, exit 2."""
    text = (EXAMPLES / example).read_text()
    assert old in text
    p = tmp_path / "mech.toml"
    p.write_text(text.replace(old, new, 1))
    rc = main([*cmd, str(p), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err and "mech.toml" in err, err
    return err
