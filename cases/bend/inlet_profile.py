#!/usr/bin/env python3
"""Write 0/U of cases/bend with the developed (Poiseuille) profile on the inlet.

Usage: inlet_profile.py CASE_DIR MEAN_VELOCITY RADIUS

Reads the inlet's face centres from CASE_DIR/0/C (`postProcess -func writeCellCentres`) and
writes u = 2 U (1 - r^2/a^2) e_x there, r the face centre's distance from the axis (the x axis).
A fixed nonuniform value needs no compiled code (codedFixedValue would need a compiler and
OpenFOAM's headers at run time).
"""
import re
import sys

case, mean, radius = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
text = open(case + "/0/C").read()
block = re.search(r"\binlet\b\s*\{(.*?)\}", text, re.S).group(1)
body = re.search(r"nonuniform\s+List<vector>\s*(\d+)\s*\((.*)\)\s*;", block, re.S)
count = int(body.group(1))
centres = [tuple(map(float, t)) for t in re.findall(r"\(\s*(\S+)\s+(\S+)\s+(\S+)\s*\)", body.group(2))]
assert len(centres) == count, (len(centres), count)
values = []
for x, y, z in centres:
    u = max(0.0, 2.0 * mean * (1.0 - (y * y + z * z) / (radius * radius)))
    values.append("(%.12g 0 0)" % u)
template = open(case + "/0/U").read()
inlet = "inlet\n    {\n        type fixedValue;\n        value nonuniform List<vector> %d\n(\n%s\n);\n    }" % (
    count,
    "\n".join(values),
)
out = re.sub(r"inlet\s*\{[^}]*\}", lambda _: inlet, template, count=1)
open(case + "/0/U", "w").write(out)
print("inlet_profile.py: %d inlet faces, centreline %.6g m/s" % (count, max(float(v[1:].split()[0]) for v in values)))
