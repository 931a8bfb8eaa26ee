"""Generate stephenson3_slvs.csv: the Stephenson III six-bar of examples/stephenson3_sixbar.toml
(pyslvs's example drawing, coordinates read as mm) solved by SolveSpace's geometric constraint
solver (the ``slvs`` 3.3 wheel on PyPI: SolveSpace's libslvs wrapped with Cython), an outside
program with its own Newton solver.

The sketch: the frame pivots O, D, F and the crank pin A are fixed (A placed at the crank angle
on the circle about O of the drawn radius |OA|); B, C, E are free points held by the drawn
lengths |AB|, |BC|, |CE|, |BE| (the rigid ternary link), |DC| and |FE|. Starting from the drawing
(crank at its drawn angle), the crank turns a full turn counter-clockwise in steps of 1 deg and
then back, each solve started from the previous solution (the same assembly as drawn). Written:
every 5 deg of the crank angle from +x, [mm] with 17 digits. Run by hand (pip install slvs==3.3);
the test suite reads only the CSV.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import slvs

#: the drawing (mm): pyslvs's example "Stephenson III"
P = {"O": (0.25, -0.625), "A": (15.375, 41.125), "B": (61.375, 95.125), "C": (102.875, 84.375),
     "D": (117.125, 23.375), "E": (134.625, 119.875), "F": (138.875, 33.125)}
LINKS = [("A", "B"), ("B", "C"), ("C", "E"), ("B", "E"), ("D", "C"), ("F", "E")]


def length(a: str, b: str) -> float:
    return math.dist(P[a], P[b])


def solve(phi: float, start: dict[str, tuple[float, float]]) -> dict[str, tuple[float, float]]:
    """B, C, E for the crank at ``phi`` [rad], Newton (SolveSpace) from ``start``."""
    slvs.clear_sketch()
    g1, g2 = 1, 2
    wp = slvs.add_base_2d(g1)
    r = length("O", "A")
    fixed = {k: P[k] for k in "ODF"}
    fixed["A"] = (P["O"][0] + r * math.cos(phi), P["O"][1] + r * math.sin(phi))
    ent = {k: slvs.add_point_2d(g1, x, y, wp) for k, (x, y) in fixed.items()}
    for k in "BCE":
        ent[k] = slvs.add_point_2d(g2, *start[k], wp)
    for a, b in LINKS:
        slvs.distance(g2, ent[a], ent[b], length(a, b), wp)
    res = slvs.solve_sketch(g2, False)
    if res["result"] != slvs.ResultFlag.OKAY:
        raise RuntimeError(f"SolveSpace did not solve at {math.degrees(phi)} deg: {res}")
    return {k: (slvs.get_param_value(ent[k]["param"][0]),
                slvs.get_param_value(ent[k]["param"][1])) for k in "BCE"}


def main() -> None:
    drawn = math.atan2(P["A"][1] - P["O"][1], P["A"][0] - P["O"][0])
    start = {k: P[k] for k in "BCE"}
    # continue from the drawn angle to the next multiple of 5 deg, then a full turn by 1 deg
    first = math.ceil(math.degrees(drawn) / 5.0) * 5.0
    path = [math.radians(d) for d in
            [math.degrees(drawn) + (first - math.degrees(drawn)) * s / 10 for s in range(11)]]
    for p in path:
        start = solve(p, start)
    rows = {}
    for step in range(361):
        deg = first + step
        start = solve(math.radians(deg), start)
        if round(deg) % 5 == 0:
            rows.setdefault(round(deg) % 360, (deg % 360, start))
    out = Path(__file__).with_name("stephenson3_slvs.csv")
    with out.open("w", newline="") as fh:
        fh.write("# Stephenson III six-bar by SolveSpace (slvs 3.3; tests/data/references/"
                 "stephenson3_slvs.py), mm, crank angle of A about O from +x [deg]\n")
        w = csv.writer(fh)
        w.writerow(["phi_deg", "B.x", "B.y", "C.x", "C.y", "E.x", "E.y"])
        for key in sorted(rows):
            deg, pts = rows[key]
            w.writerow([f"{deg:.17g}", *(f"{v:.17g}" for k in "BCE" for v in pts[k])])


if __name__ == "__main__":
    main()
