#!/usr/bin/env python3
"""Sum OpenFOAM's face flux phi over every patch of a case at a time (ASCII fields, .gz too).

Usage: flux.py CASE TIME  -> lines `patch type net outflow`: the net flux (outflow positive)
and the sum over the faces with outflow (a freestream patch has both), for every patch with
faces; `empty` patches are left out. Reads constant/polyMesh/boundary for the types."""
import gzip, os, re, sys

def read(path):
    for p in (path, path + ".gz"):
        if os.path.exists(p):
            op = gzip.open if p.endswith(".gz") else open
            with op(p, "rt") as f:
                return f.read()
    raise FileNotFoundError(path)

def strip_comments(s):
    s = re.sub(r"/\*.*?\*/", "", s, flags=re.S)
    return re.sub(r"//[^\n]*", "", s)

def blocks(s):
    """Top-level `name { ... }` entries of a dictionary body."""
    out, i = {}, 0
    tok = re.compile(r"\s*([A-Za-z0-9_\-\.:\"\(\)]+)\s*\{")
    while True:
        m = tok.search(s, i)
        if not m:
            return out
        depth, j = 1, m.end()
        while depth:
            c = s[j]
            depth += c == "{"
            depth -= c == "}"
            j += 1
        out[m.group(1).strip('"')] = s[m.end():j - 1]
        i = j

case, time = sys.argv[1], sys.argv[2]
bnd = strip_comments(read(os.path.join(case, "constant/polyMesh/boundary")))
body = bnd[bnd.index("(", bnd.index("FoamFile") + 10) + 1:] if "FoamFile" in bnd else bnd
patches = blocks(body[body.index("}") + 1:] if "FoamFile" in body[:200] else body)
patches = {k: v for k, v in blocks(bnd).items() if k != "FoamFile"}
phi = strip_comments(read(os.path.join(case, time, "phi")))
bf = blocks(phi[phi.index("boundaryField"):].split("{", 1)[1])
for name, d in patches.items():
    ptype = re.search(r"\btype\s+(\w+)", d).group(1)
    n = int(re.search(r"nFaces\s+(\d+)", d).group(1))
    if ptype == "empty" or n == 0:
        continue
    f = bf.get(name, "")
    m = re.search(r"value\s+nonuniform\s+List<scalar>\s*(\d+)\s*\((.*?)\)", f, re.S)
    if m:
        values = [float(x) for x in m.group(2).split()]
    else:
        m = re.search(r"value\s+uniform\s+([-+0-9.eE]+)", f)
        values = [float(m.group(1)) if m else float("nan")] * n
    print(f"{name} {ptype} {sum(values):.9g} {sum(v for v in values if v > 0):.9g}")
