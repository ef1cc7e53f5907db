#!/usr/bin/env python3
"""pipeCyclic's inlet swirl without codedFixedValue: u = 2 Cf ^ e_x with u_x = 1, i.e.
(1, 2 z, -2 y) at each inlet face centre (read from writeCellCentres' TIME/C), written into
TIME/U as a fixedValue list. Usage: swirl.py TIME (in the case directory)."""
import re, sys
t = sys.argv[1]
c = open(f"{t}/C").read()
blk = c[c.index("inlet", c.index("boundaryField")):]
m = re.search(r"nonuniform\s+List<vector>\s*(\d+)\s*\((.*?)\n\)", blk, re.S)
pts = re.findall(r"\(([^()]*)\)", m.group(2))
vals = []
for p in pts:
    x, y, z = map(float, p.split())
    vals.append(f"(1 {2 * z:.12g} {-2 * y:.12g})")
u = open(f"{t}/U").read()
start = u.index("inlet", u.index("boundaryField"))
open_ = u.index("{", start)
depth, j = 1, open_ + 1
while depth:
    depth += u[j] == "{"
    depth -= u[j] == "}"
    j += 1
entry = ("inlet\n    {\n        type fixedValue;\n        value nonuniform List<vector> %d\n(\n%s\n);\n    }"
         % (len(vals), "\n".join(vals)))
open(f"{t}/U", "w").write(u[:start] + entry + u[j:])
print(f"swirl.py: {len(vals)} inlet faces")
