"""Generate jansen_pylinkage.csv: the Jansen leg's joint paths computed by pylinkage 1.3.0 from
the published link lengths (Theo Jansen's 'holy numbers': a = 38, b = 41.5, c = 39.3,
d = 40.1, e = 55.8, f = 39.4, g = 36.7, h = 65.7, i = 49, j = 50, k = 61.9, l = 7.8, m = 15,
in mm), crank angle 0..355 deg every 5 deg counter-clockwise from +x.

Run by hand (pip install pylinkage==1.3.0); the test suite reads only the CSV. The circuit is
the one of the drawing (pyslvs's example "Jansen's linkage (Single)": C above, E below the
frame line), set through pylinkage's initial positions.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import pylinkage as pl

a, b, c, d, e, f, g, h, i, j, k, l, m = (38.0, 41.5, 39.3, 40.1, 55.8, 39.4, 36.7, 65.7, 49.0,
                                         50.0, 61.9, 7.8, 15.0)
#: approximate drawn points (pyslvs's example, rounded) to pick the circuit
GUESS = {"C": (-35.24, 33.61), "E": (-20.1, -42.79), "F": (-56.05, -35.42)}


def build(step: float) -> tuple[pl.Linkage, dict[str, object]]:
    O = pl.Ground(0.0, 0.0, name="O")
    B = pl.Ground(-a, -l, name="B")
    crank = pl.Crank(anchor=O, radius=m, angular_velocity=step, initial_angle=0.0, name="A")
    C = pl.RRRDyad(anchor1=crank.output, anchor2=B, distance1=j, distance2=b, x=GUESS["C"][0],
                   y=GUESS["C"][1], name="C")
    # D on the ternary link B-C-D: angle CBD from the triangle's sides b, d, e
    angle_d = math.acos((b * b + d * d - e * e) / (2 * b * d))
    D = pl.FixedDyad(anchor1=B, anchor2=C, distance=d, angle=angle_d, name="D")
    E = pl.RRRDyad(anchor1=crank.output, anchor2=B, distance1=k, distance2=c, x=GUESS["E"][0],
                   y=GUESS["E"][1], name="E")
    F = pl.RRRDyad(anchor1=D, anchor2=E, distance1=f, distance2=g, x=GUESS["F"][0],
                   y=GUESS["F"][1], name="F")
    # the foot G on the ternary link E-F-G: angle FEG from the sides g, i, h
    angle_g = math.acos((g * g + i * i - h * h) / (2 * g * i))
    G = pl.FixedDyad(anchor1=E, anchor2=F, distance=i, angle=angle_g, name="G")
    comps = [O, B, crank, C, D, E, F, G]
    return pl.Linkage(comps), {"A": crank, "C": C, "D": D, "E": E, "F": F, "G": G}


def main() -> None:
    n = 72
    lk, _ = build(2 * math.pi / n)
    rows = []
    for k_, coords in enumerate(lk.step(iterations=n)):  # each step turns the crank first
        rows.append([(k_ + 1) * 5.0 % 360.0, *(v for xy in coords for v in xy)])
    names = [cmp.name for cmp in lk.components]
    head = ["phi_deg"] + [f"{nm}.{ax}" for nm in names for ax in ("x", "y")]
    out = Path(__file__).with_name("jansen_pylinkage.csv")
    with out.open("w", newline="") as fh:
        fh.write("# Jansen leg by pylinkage 1.3.0 (tests/data/references/jansen_pylinkage.py), "
                 "lengths in mm, crank angle of A from +x [deg]\n")
        w = csv.writer(fh)
        w.writerow(head)
        for r in rows:
            w.writerow([f"{v:.17g}" for v in r])


if __name__ == "__main__":
    main()
