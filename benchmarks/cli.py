"""Wall time of ``linkwork`` commands split into start-up, imports, computation and output.

Each sample runs one command in a fresh interpreter (as a user does), in two steps:

1. a probe run (once per command) lists the modules the command imports, in the order it
   imports them (the lazy ones too: SciPy's optimisers, matplotlib, pint, Rich's progress);
2. a timed run imports them first (``imports``), then calls ``linkwork.cli.main(argv)``, in
   which every public function of ``linkwork.studies.*`` and ``linkwork.io.load`` is timed
   (``computation``: reading and validating the file, the study); the rest of ``main`` is
   ``output`` (argument parsing, tables, CSV/JSON, plots, the run record). ``start-up`` is the
   subprocess's wall time less those three: the interpreter starting and exiting.

The sum is the wall time a user waits; the same command is also run as the installed
``linkwork`` script (``total, script``) to check that the instrumented run takes as long.
Commands are sampled round-robin over ``--repeat`` rounds; every phase is printed as min /
median / max. Every run must exit 0 and write the same files (checked on each run).

Usage::

    .venv/bin/python benchmarks/cli.py [--repeat 5] [--markdown] [--json out.json]
"""

from __future__ import annotations

import argparse
import functools
import importlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

# the timed child imports nothing of its own beyond the standard library above (no NumPy
# before its ``imports`` phase): _common is imported by the parent only
sys.path.insert(0, str(Path(__file__).resolve().parent))

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"

#: (label, argv without --out); each writes into a fresh folder.
COMMANDS: list[tuple[str, list[str]]] = [
    ("--help", ["--help"]),
    ("analyze fourbar_paper001 (360 positions)", ["analyze", str(EX / "fourbar_paper001.toml")]),
    ("analyze loom_sixbar", ["analyze", str(EX / "loom_sixbar.toml")]),
    ("analyze sine_press", ["analyze", str(EX / "sine_press.toml")]),
    ("balance fourbar_paper001", ["balance", str(EX / "fourbar_paper001.toml")]),
    ("reactions loom_fourbar_spatial --tolerance-study 10000",
     ["reactions", str(EX / "loom_fourbar_spatial.toml"), "--tolerance-study", "10000"]),
    ("swashplate analyze swashplate_4a", ["swashplate", "analyze", str(EX / "swashplate_4a.toml")]),
    ("swashplate synthesize (2048 candidates)",
     ["swashplate", "synthesize", "-R", "100 mm", "-H", "60 mm", "--delta", "10 deg",
      "--candidates", "2048"]),
]

_PHASES = ("start-up", "imports", "computation", "output", "total")


def _child_probe(argv: list[str]) -> None:
    """Run the command; print the modules it imported, in order, as JSON."""
    before = set(sys.modules)
    from linkwork.cli import main

    try:
        main(argv)
    except SystemExit:
        pass
    mods = [m for m in sys.modules if m not in before and not m.startswith("__")]
    sys.stdout = sys.__stdout__
    print("\n" + json.dumps(mods))


def _child_timed(argv: list[str], module_list: str) -> None:
    """Import the modules listed in the JSON file ``module_list``, then run the command with
    its computation timed; print the phases as JSON."""
    t0 = time.perf_counter()
    with open(module_list) as fh:
        modules = json.load(fh)
    for m in modules:
        try:
            importlib.import_module(m)
        except Exception:
            pass
    from linkwork.cli import main

    spent = [0.0]
    depth = [0]

    def timed(fn: Any) -> Any:
        @functools.wraps(fn)
        def run(*a: Any, **k: Any) -> Any:
            depth[0] += 1
            t = time.perf_counter()
            try:
                return fn(*a, **k)
            finally:
                depth[0] -= 1
                if depth[0] == 0:
                    spent[0] += time.perf_counter() - t
        return run

    # only the modules the command imports (the probe's list): no extra import here
    targets = [(sys.modules["linkwork.io"], "load")] if "linkwork.io" in sys.modules else []
    for name in ("balance", "planar", "reactions", "sine_press", "swashplate"):
        mod = sys.modules.get(f"linkwork.studies.{name}")
        if mod is None:
            continue
        targets += [(mod, f) for f in getattr(mod, "__all__", ())
                    if callable(getattr(mod, f)) and not isinstance(getattr(mod, f), type)]
    for mod, f in targets:
        setattr(mod, f, timed(getattr(mod, f)))
    # the command modules bound some of these names at import: rebind them there too
    for m in list(sys.modules):
        if m.startswith("linkwork.cli"):
            cm = sys.modules[m]
            for mod, f in targets:
                obj = getattr(cm, f, None)
                if callable(obj) and getattr(obj, "__module__", None) == mod.__name__:
                    setattr(cm, f, getattr(mod, f))
    t1 = t2 = time.perf_counter()
    code = 0
    try:
        main(argv)
    except SystemExit as exc:
        code = int(exc.code or 0)
    t3 = time.perf_counter()
    sys.stdout = sys.__stdout__
    print("\n" + json.dumps({"imports": t1 - t0, "computation": spent[0],
                             "output": (t3 - t2) - spent[0], "code": code}))


def _run(args: list[str]) -> tuple[float, str]:
    t = time.perf_counter()
    res = subprocess.run(args, capture_output=True, text=True, cwd=ROOT)
    wall = time.perf_counter() - t
    if res.returncode != 0:
        raise AssertionError(f"{' '.join(args)} exited {res.returncode}: {res.stderr[-500:]}")
    return wall, res.stdout


def _files(out: Path) -> list[str]:
    return sorted(p.name for p in out.iterdir()) if out.exists() else []


def run(repeat: int = 5, commands: list[tuple[str, list[str]]] | None = None
        ) -> dict[str, Any]:
    from _common import Spread

    cmds = commands or COMMANDS
    me = [sys.executable, str(Path(__file__).resolve())]
    script = str(Path(sys.executable).with_name("linkwork"))
    tmp = Path(tempfile.mkdtemp(prefix="linkwork-cli-bench-"))
    try:
        modules, expected = {}, {}
        for label, argv in cmds:
            out = tmp / "probe"
            shutil.rmtree(out, ignore_errors=True)
            full = argv if argv == ["--help"] else [*argv, "--out", str(out)]
            _, text = _run([*me, "--probe", json.dumps(full)])
            modules[label] = str(tmp / f"modules-{len(modules)}.json")
            Path(modules[label]).write_text(text.strip().splitlines()[-1])
            expected[label] = _files(out)
        phases: dict[str, dict[str, Spread]] = {
            label: {p: Spread() for p in (*_PHASES, "total, script")} for label, _ in cmds}
        for _ in range(repeat):
            for label, argv in cmds:
                out = tmp / "run"
                shutil.rmtree(out, ignore_errors=True)
                full = argv if argv == ["--help"] else [*argv, "--out", str(out)]
                wall, text = _run([*me, "--timed", json.dumps(full), modules[label]])
                got = json.loads(text.strip().splitlines()[-1])
                if got["code"] != 0 or _files(out) != expected[label]:
                    raise AssertionError(f"{label}: exit {got['code']}, files {_files(out)} "
                                         f"against {expected[label]}")
                ph = phases[label]
                for p in ("imports", "computation", "output"):
                    ph[p].samples.append(got[p])
                ph["start-up"].samples.append(
                    wall - got["imports"] - got["computation"] - got["output"])
                ph["total"].samples.append(wall)
                shutil.rmtree(out, ignore_errors=True)
                wall2, _ = _run([script, *full])
                ph["total, script"].samples.append(wall2)
                if _files(out) != expected[label]:
                    raise AssertionError(f"{label} (script): files {_files(out)}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return {"commands": {label: {p: sp.samples for p, sp in ph.items()}
                         for label, ph in phases.items()}}


def table(result: dict[str, Any], markdown: bool = False) -> str:
    from _common import Spread, fmt_spread

    cols = (*_PHASES, "total, script")
    lines = []
    if markdown:
        lines += ["| command | " + " | ".join(f"{c} [s]" for c in cols) + " |",
                  "|---|" + "---:|" * len(cols)]
    for label, ph in result["commands"].items():
        cells = [fmt_spread(Spread(ph[c]), "ratio") for c in cols]
        if markdown:
            lines.append(f"| {label} | " + " | ".join(cells) + " |")
        else:
            lines.append(label)
            lines += [f"    {c:14s} {cell} s" for c, cell in zip(cols, cells, strict=True)]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5, help="rounds")
    ap.add_argument("--markdown", action="store_true")
    ap.add_argument("--json", help="also write the samples to this JSON file")
    ap.add_argument("--probe", help=argparse.SUPPRESS)
    ap.add_argument("--timed", nargs=2, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.probe:
        _child_probe(json.loads(args.probe))
        return 0
    if args.timed:
        _child_timed(json.loads(args.timed[0]), args.timed[1])
        return 0

    from _common import finish, load

    os.environ.setdefault("MPLBACKEND", "Agg")
    t0, load0 = time.perf_counter(), load()
    result = run(args.repeat)
    finish(result, table(result, markdown=args.markdown),
           f"CLI phases, min / median / max over {args.repeat} rounds, a fresh process each",
           load0, t0, args.json)
    return 0


if __name__ == "__main__":
    sys.exit(main())
