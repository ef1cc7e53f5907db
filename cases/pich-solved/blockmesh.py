#!/usr/bin/env python3
"""blockMeshDict of the Pich pipe: radius R = 1 along z in [0, L], L = 4, an O-grid of a
square core (N x N cells, half-side 0.45 R) and four blocks of N x N cells out to the circle
(arcs), 4N cells along z per unit radius... (NZ = 4 N). Usage: blockmesh.py N > blockMeshDict."""
import math
import sys

n = int(sys.argv[1])
nz = 4 * n
radius, length, a = 1.0, 4.0, 0.45
c = radius / math.sqrt(2.0)
section = [(-a, -a), (a, -a), (a, a), (-a, a), (-c, -c), (c, -c), (c, c), (-c, c)]
points = [(x, y, 0.0) for x, y in section] + [(x, y, length) for x, y in section]
blocks = [(0, 1, 2, 3), (4, 5, 1, 0), (5, 6, 2, 1), (6, 7, 3, 2), (7, 4, 0, 3)]
arcs = [(4, 5, (0, -radius)), (5, 6, (radius, 0)), (6, 7, (0, radius)), (7, 4, (-radius, 0))]
print("FoamFile { version 2.0; format ascii; class dictionary; object blockMeshDict; }")
print("convertToMeters 1;")
print("vertices (")
for p in points:
    print("    (%.17g %.17g %.17g)" % p)
print(");")
print("blocks (")
for b in blocks:
    ids = " ".join(str(i) for i in b + tuple(i + 8 for i in b))
    print(f"    hex ({ids}) ({n} {n} {nz}) simpleGrading (1 1 1)")
print(");")
print("edges (")
for i, j, (x, y) in arcs:
    for dz, z in ((0, 0.0), (8, length)):
        print(f"    arc {i + dz} {j + dz} ({x} {y} {z})")
print(");")
def faces(offset, flip):
    out = []
    for b in blocks:
        f = tuple(i + offset for i in b)
        out.append(tuple(reversed(f)) if flip else f)
    return out
print("boundary (")
print("    inlet { type patch; faces (" + " ".join("(%d %d %d %d)" % f for f in faces(0, True)) + "); }")
print("    outlet { type patch; faces (" + " ".join("(%d %d %d %d)" % f for f in faces(8, False)) + "); }")
wall = [(i, j, j + 8, i + 8) for i, j, _ in arcs]
print("    wall { type wall; faces (" + " ".join("(%d %d %d %d)" % f for f in wall) + "); }")
print(");")
