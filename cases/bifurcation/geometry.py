#!/usr/bin/env python3
"""Wall surface of the symmetric airway bifurcation of paper §6.4 (Weibel generation 3) as an STL.

The fluid region is the zero sublevel set of a signed distance function (metres):

    parent      cylinder of radius R along +x, x <= x_b (it runs past the inlet plane x = 0)
    joint       sphere of radius R at the branch point B = (x_b, 0, 0)
    daughters   cylinders of radius R from B along (cos θ, ±sin θ, 0), θ = α/2 = 30°
    fluid       min(parent, joint, blend(daughter1, daughter2)) <= 0

The joint is tangent to all three cylinders, so the outer bend is a circular arc of radius R in
the bifurcation plane (the wall turns by θ over R θ). The two daughters are joined by the
polynomial smooth minimum of width k(z) = K (1 − (z/R)²)₊: it rounds the carina ridge, fully at
the apex (z = 0), where it moves the apex downstream by K/2, and not at all where the ridge ends
at the top and bottom of the junction (there the two daughter walls meet tangentially and any
blend would raise a bump). x_b is chosen so that the rounded carina apex lies at x = c L. The
surface is extracted by marching cubes on a grid of spacing `--spacing`; it runs past x = 0
and x = L, where snappyHexMesh cuts it with the background box (inlet and outlet patches).

Usage: geometry.py OUT.stl [--spacing M]    (prints the derived dimensions as key=value lines)
"""
import argparse
import struct

import numpy as np
from skimage.measure import marching_cubes

R = 3e-3  # airway radius (D = 6 mm, parent and daughters)
L = 0.04  # total length along the parent axis, inlet to outlet plane
ALPHA = np.deg2rad(60.0)  # bifurcation angle, between the daughter axes
THETA = ALPHA / 2  # angle between parent and daughter axes
CARINA = 0.77  # carina apex at x / L
K = 3.6e-3  # carina blend width at the apex (moves the apex by K/2 = 1.8 mm)

# The apex of the unblended carina is where the inner daughter walls meet on the x axis:
# x_b + R / sin θ; the blend moves it by K/2 (exact in the plane z = 0, where both walls are lines).
X_B = CARINA * L - R / np.sin(THETA) - K / 2
# Margins of the surface beyond the box cut by snappyHexMesh.
PAST = 1.5e-3


def sdf(x, y, z):
    parent = np.maximum(np.hypot(y, z) - R, x - X_B)
    joint = np.sqrt((x - X_B) ** 2 + y**2 + z**2) - R
    c, s = np.cos(THETA), np.sin(THETA)
    daughters = []
    for sign in (1.0, -1.0):
        t = (x - X_B) * c + y * sign * s  # coordinate along the daughter axis
        radial = np.sqrt(np.maximum((x - X_B) ** 2 + y**2 + z**2 - t**2, 0.0))
        daughters.append(np.maximum(radial - R, -t))
    a, b = daughters
    blend = smooth_min(a, b, carina_width(K, z, R))
    return np.minimum(np.minimum(parent, joint), blend)


def carina_width(k_apex, z, r):
    """Blend width of the carina at height z above the bifurcation plane: k_apex at the apex,
    tapered as (1 − (z/r)²)₊ to nothing where the two daughter walls meet tangentially (|z| = r
    at the branch point)."""
    return k_apex * np.clip(1.0 - (z / r) ** 2, 0.0, None)


def smooth_min(a, b, k):
    """Polynomial smooth minimum of a and b over the width k ≥ 0 (k = 0: the plain minimum):
    min(a, b) − h²/(4k) with h = (k − |a − b|)₊."""
    h = np.clip(k - np.abs(a - b), 0.0, None)
    return np.minimum(a, b) - np.where(k > 0, h * h / (4 * np.where(k > 0, k, 1.0)), 0.0)


def carina_radius():
    """Radius of curvature of the rounded carina apex in the bifurcation plane, from the wall
    x(y) = x_apex + y²/(2ρ) near the apex."""
    x = np.linspace(X_B, L, 400001)
    apex = x[np.argmax(sdf(x, 0 * x, 0 * x) > 0)]
    dy = 0.05 * R
    off = x[np.argmax(sdf(x, dy + 0 * x, 0 * x) > 0)]
    return dy * dy / (2 * (off - apex)), apex


def y_extent():
    """Largest |y| of the wall at the outlet plane x = L (outer wall of a daughter)."""
    return (L - X_B) * np.tan(THETA) + R / np.cos(THETA)


def write_stl(path, verts, faces):
    tri = verts[faces]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    with open(path, "wb") as f:
        f.write(b"pseudorigid airway bifurcation wall".ljust(80, b" "))
        f.write(struct.pack("<I", len(faces)))
        rec = np.zeros(len(faces), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
        rec["n"] = n
        rec["v"] = tri
        f.write(rec.tobytes())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--spacing", type=float, default=1e-4)
    args = ap.parse_args()
    h = args.spacing
    ymax = y_extent() + PAST
    xs = np.arange(-PAST, L + PAST + h / 2, h)
    ys = np.arange(-ymax, ymax + h / 2, h)
    zs = np.arange(-R - PAST, R + PAST + h / 2, h)
    x, y, z = np.meshgrid(xs, ys, zs, indexing="ij")
    verts, faces, _, _ = marching_cubes(sdf(x, y, z), level=0.0, spacing=(h, h, h))
    verts += np.array([xs[0], ys[0], zs[0]])
    write_stl(args.out, verts, faces)
    print(f"radius={R}")
    print(f"length={L}")
    print(f"branch_x={X_B:.6e}")
    rho, apex = carina_radius()
    print(f"carina_x={apex:.6e}")
    print(f"carina_radius={rho:.6e}")
    print(f"outlet_half_width={y_extent():.6e}")
    print(f"triangles={len(faces)}")


if __name__ == "__main__":
    main()
