#!/usr/bin/env python3
"""Write system/blockMeshDict of a 90-degree bend of circular cross-section (cases/bend).

Usage: blockmesh.py OUT_FILE N_SQUARE N_RADIAL CELLS_PER_D [WALL_GRADING]

Geometry (SI): tube radius a = RADIUS, bend (centreline) radius R_o = CURVATURE_RATIO * a,
curvature ratio R_o/a = 5.6 as in Pui, Romay-Novas & Liu (1987). A straight entrance of
ENTRANCE_D diameters along +x ends at the origin, the bend turns the axis about the centre of
curvature (0, R_o, 0) to +y, and a straight exit of EXIT_D diameters follows.

The cross-section is an O-grid: a central square (N_SQUARE x N_SQUARE cells, half-width 0.5 a)
and four blocks between it and the wall (N_SQUARE along the wall, N_RADIAL towards it, cells
shrinking towards the wall by WALL_GRADING, the ratio of the innermost to the wall cell). The
wall is four circular arcs per section and every vertex is carried through the bend on a
circular arc about the centre of curvature, so the bend's wall is exact up to the faces'
planarity. Patches: inlet, outlet (patch) and wall_entrance, wall_bend, wall_exit (wall): the
bend's wall is a patch of its own, so deposition in the bend is counted apart from the
straight tubes.
"""
import math
import os
import sys

RADIUS = 2.5e-3
CURVATURE_RATIO = 5.6
# Straight entrance in diameters; BEND_ENTRANCE_D in the environment changes it (a check that
# the imposed profile has settled before the bend).
ENTRANCE_D = float(os.environ.get("BEND_ENTRANCE_D", "2"))
EXIT_D = 3.0
SQUARE = 0.5  # half-width of the central square, in radii


def main():
    out, n_sq, n_r, per_d = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
    grading = float(sys.argv[5]) if len(sys.argv) > 5 else 4.0
    a = RADIUS
    r_o = CURVATURE_RATIO * a
    d = 2.0 * a
    l_in, l_out = ENTRANCE_D * d, EXIT_D * d

    # Local cross-section coordinates (p, q): p along e_z, q along the outward normal (away
    # from the centre of curvature); p x q is the flow direction, so blocks listed
    # counterclockwise in (p, q) and extruded downstream have positive volume.
    s = SQUARE * a
    c = a / math.sqrt(2.0)
    local = [(-s, -s), (s, -s), (s, s), (-s, s), (-c, -c), (c, -c), (c, c), (-c, c)]
    # Midpoints of the wall arcs o0-o1, o1-o2, o2-o3, o3-o0 (at 270, 0, 90, 180 degrees).
    arc_mid = [(0.0, -a), (a, 0.0), (0.0, a), (-a, 0.0)]

    def point(phi, p, q, shift=0.0):
        """Section at bend angle phi (0: bend entry, pi/2: bend exit); `shift` moves it along
        the straight tube before (phi = 0, shift < 0) or after (phi = pi/2, shift > 0)."""
        centre = (r_o * math.sin(phi), r_o * (1.0 - math.cos(phi)), 0.0)
        tangent = (math.cos(phi), math.sin(phi), 0.0)
        outward = (math.sin(phi), -math.cos(phi), 0.0)
        return tuple(centre[i] + shift * tangent[i] + p * (1.0 if i == 2 else 0.0) + q * outward[i] for i in range(3))

    sections = [(0.0, -l_in), (0.0, 0.0), (0.5 * math.pi, 0.0), (0.5 * math.pi, l_out)]
    vertices = [point(phi, p, q, shift) for phi, shift in sections for p, q in local]

    lengths = [l_in, 0.5 * math.pi * r_o, l_out]
    n_axial = [max(1, round(per_d * length / d)) for length in lengths]

    def v(k, j):
        return 8 * k + j

    blocks, walls = [], [[], [], []]
    for seg in range(3):
        k0, k1 = seg, seg + 1
        n_ax = n_axial[seg]
        quad = [0, 1, 2, 3]
        blocks.append(
            "hex (%s) (%d %d %d) simpleGrading (1 1 1)"
            % (" ".join(str(v(k, j)) for k in (k0, k1) for j in quad), n_sq, n_sq, n_ax)
        )
        for j in range(4):
            o0, o1, c1, c0 = 4 + j, 4 + (j + 1) % 4, (j + 1) % 4, j
            ring = [o0, o1, c1, c0]
            blocks.append(
                "hex (%s) (%d %d %d) simpleGrading (1 %g 1)"
                % (" ".join(str(v(k, i)) for k in (k0, k1) for i in ring), n_sq, n_r, n_ax, grading)
            )
            walls[seg].append("(%d %d %d %d)" % (v(k0, o0), v(k0, o1), v(k1, o1), v(k1, o0)))

    edges = []
    for k, (phi, shift) in enumerate(sections):
        for j in range(4):
            mid = point(phi, *arc_mid[j], shift)
            edges.append("arc %d %d (%.12g %.12g %.12g)" % ((v(k, 4 + j), v(k, 4 + (j + 1) % 4)) + mid))
    for j in range(8):
        mid = point(0.25 * math.pi, *local[j])
        edges.append("arc %d %d (%.12g %.12g %.12g)" % ((v(1, j), v(2, j)) + mid))

    def end_faces(k):
        faces = ["(%d %d %d %d)" % (v(k, 0), v(k, 1), v(k, 2), v(k, 3))]
        for j in range(4):
            o0, o1, c1, c0 = 4 + j, 4 + (j + 1) % 4, (j + 1) % 4, j
            faces.append("(%d %d %d %d)" % (v(k, o0), v(k, o1), v(k, c1), v(k, c0)))
        return faces

    def patch(name, kind, faces):
        return "    %s\n    {\n        type %s;\n        faces\n        (\n%s\n        );\n    }\n" % (
            name,
            kind,
            "\n".join("            " + f for f in faces),
        )

    text = [
        "/* Written by cases/bend/blockmesh.py: do not edit. */",
        "FoamFile { version 2.0; format ascii; class dictionary; object blockMeshDict; }",
        "// a = %g m, R_o/a = %g, entrance %g D, exit %g D; cells: square %d, radial %d (grading %g), axial %s"
        % (a, CURVATURE_RATIO, ENTRANCE_D, EXIT_D, n_sq, n_r, grading, n_axial),
        "convertToMeters 1;",
        "vertices\n(\n%s\n);" % "\n".join("    (%.12g %.12g %.12g)" % p for p in vertices),
        "blocks\n(\n%s\n);" % "\n".join("    " + b for b in blocks),
        "edges\n(\n%s\n);" % "\n".join("    " + e for e in edges),
        "boundary\n(\n%s);"
        % "".join(
            [
                patch("inlet", "patch", end_faces(0)),
                patch("outlet", "patch", end_faces(3)),
                patch("wall_entrance", "wall", walls[0]),
                patch("wall_bend", "wall", walls[1]),
                patch("wall_exit", "wall", walls[2]),
            ]
        ),
        "mergePatchPairs ();",
    ]
    with open(out, "w") as f:
        f.write("\n".join(text) + "\n")
    cells = (n_sq * n_sq + 4 * n_sq * n_r) * sum(n_axial)
    print("blockmesh.py: %d cells (%d per section, axial %s)" % (cells, cells // sum(n_axial), n_axial))


if __name__ == "__main__":
    main()
