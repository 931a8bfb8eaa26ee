"""Compare two folders written by tools/record_outputs.sh: exit codes, and every CSV/JSON
number by column name (CSV) or key path (JSON) to rtol = atol = 1e-9.

Usage: python tools/compare_outputs.py BEFORE AFTER [--text]

With --text, what each command printed (stdout, stderr) must also be the same, once each
recording's folder name is replaced by OUT (tables, messages: a pure restructuring keeps them).
"""

from __future__ import annotations

import csv
import json
import math
import sys
from pathlib import Path

TOL = 1e-9


#: How a value undefined at a position is written: NaN before the strict outputs of issue 19, an
#: empty CSV cell / JSON null since; the same meaning, so equal here.
_UNDEFINED = {"nan", "", "None"}


def _close(a: str, b: str) -> bool:
    if a in _UNDEFINED or b in _UNDEFINED:
        return a in _UNDEFINED and b in _UNDEFINED
    try:
        x, y = float(a), float(b)
    except ValueError:
        return a == b
    if math.isnan(x) or math.isnan(y):
        return math.isnan(x) and math.isnan(y)
    return abs(x - y) <= TOL + TOL * max(abs(x), abs(y))


def _csv(p: Path) -> dict[str, list[str]]:
    with p.open(newline="") as fh:
        rows = list(csv.reader(row for row in fh if not row.startswith("#")))
    if not rows:
        return {}
    head, body = rows[0], rows[1:]
    return {h: [r[i] if i < len(r) else "" for r in body] for i, h in enumerate(head)}


def _flat(obj: object, path: str = "") -> dict[str, str]:
    if isinstance(obj, dict):
        out: dict[str, str] = {}
        for k, v in obj.items():
            out.update(_flat(v, f"{path}.{k}"))
        return out
    if isinstance(obj, list):
        out = {}
        for i, v in enumerate(obj):
            out.update(_flat(v, f"{path}[{i}]"))
        return out
    return {path: str(obj)}


def compare(before: Path, after: Path) -> list[str]:
    bad: list[str] = []
    for rc in sorted(before.glob("*.rc")):
        other = after / rc.name
        if not other.exists() or other.read_text() != rc.read_text():
            bad.append(f"{rc.stem}: exit code {rc.read_text().strip()} -> "
                       f"{other.read_text().strip() if other.exists() else 'missing'}")
    for f in sorted(before.rglob("*")):
        rel = f.relative_to(before)
        g = after / rel
        if f.suffix not in {".csv", ".json"} or f.name == "linkwork-run.json":
            continue  # linkwork-run.json records times and file dates of the run, not results
        if not g.exists():
            bad.append(f"{rel}: missing after")
            continue
        if f.suffix == ".csv":
            a, b = _csv(f), _csv(g)
            for col, vals in a.items():
                if col not in b:
                    bad.append(f"{rel}: column {col!r} missing after")
                    continue
                if len(vals) != len(b[col]):
                    bad.append(f"{rel}:{col}: {len(vals)} rows -> {len(b[col])}")
                    continue
                for i, (x, y) in enumerate(zip(vals, b[col], strict=True)):
                    if not _close(x, y):
                        bad.append(f"{rel}:{col}[{i}]: {x} -> {y}")
                        break
        else:
            fa = _flat(json.loads(f.read_text()))
            fb = _flat(json.loads(g.read_text()))
            for k, v in fa.items():
                if k not in fb:
                    bad.append(f"{rel}: key {k} missing after")
                elif not _close(v, fb[k]):
                    bad.append(f"{rel}{k}: {v} -> {fb[k]}")
    return bad


def compare_text(before: Path, after: Path) -> list[str]:
    bad = []
    for f in sorted([*before.glob("*.stdout"), *before.glob("*.stderr")]):
        g = after / f.name
        a = " ".join(f.read_text().replace(str(before), "OUT").split())
        b = " ".join(g.read_text().replace(str(after), "OUT").split()) if g.exists() else ""
        if a != b:
            bad.append(f"{f.name}: printed text differs")
    return bad


if __name__ == "__main__":
    diffs = compare(Path(sys.argv[1]), Path(sys.argv[2]))
    if "--text" in sys.argv[3:]:
        diffs += compare_text(Path(sys.argv[1]), Path(sys.argv[2]))
    print("\n".join(diffs[:200]) if diffs else "same numbers")
    sys.exit(1 if diffs else 0)
