#!/usr/bin/env python3
"""planarPoiseuille's tracers against the closed form: a tracer at height y moves at the held
field's u(y) (one cell along the cyclic pair, so u does not depend on x), so after time t it is
at ((x0 + u t + h) mod 2h) - h with the period 2h = 0.2 m. Usage: periodic_check.py CASE_DIR
PSEUDORIGID [KIND] (KIND tracers by default). Prints the axial error (median, max, largest
relative to the travel) and the largest change of y."""
import csv, os, statistics, subprocess, sys

case, binary = sys.argv[1], sys.argv[2]
kind = sys.argv[3] if len(sys.argv) > 3 else "tracers"
h = 0.1
rows = list(csv.DictReader(open(os.path.join(case, f"out-{kind}", "results.csv"))))
pts, vel = os.path.join(case, "periodic-in.csv"), os.path.join(case, "periodic-u.csv")
with open(pts, "w") as f:
    f.write("x,y,z\n")
    f.writelines(f"{r['x0_1']},{r['x0_2']},0\n" for r in rows)
subprocess.run([binary, "probe", case, "latest", pts, vel], check=True, capture_output=True)
u = [float(r["u1"]) for r in csv.DictReader(open(vel))]
err, rel, dy, crossings = [], [], [], []
for r, ux in zip(rows, u):
    t, x0 = float(r["t"]), float(r["x0_1"])
    exact = (x0 + ux * t + h) % (2 * h) - h
    e = abs((float(r["x1"]) - exact + h) % (2 * h) - h)
    err.append(e)
    rel.append(e / (ux * t))
    dy.append(abs(float(r["x2"]) - float(r["x0_2"])))
    crossings.append(ux * t / (2 * h))
print(f"{len(rows)} {kind}, {min(crossings):.0f}-{max(crossings):.0f} crossings: axial error median "
      f"{statistics.median(err):.2e} m, max {max(err):.2e} m, relative max {max(rel):.2e}; |dy| max {max(dy):.1e} m")
