#!/usr/bin/env python3
"""Wall surface of a symmetric Weibel-type airway tree, generations 3 to 6, as an STL.

The tree: one G3 tube along +x from the inlet plane x = 0, bifurcating into two G4 tubes, each
bifurcating into two G5 tubes, each bifurcating into two G6 tubes that end in flat outlet caps:
seven bifurcations (one of generation 3, two of generation 4, four of generation 5), eight
outlets. Diameters and lengths are Weibel's model A (Weibel 1963, Table in Tu, Inthavong &
Ahmadi 2013, Table 3.2) scaled by `--scale` (default 6/5.6, so that G3 has the 6 mm of the
paper's bifurcation, paper §6.4). A tube's length is its centreline from its start (the inlet
plane, or its parent's branch point) to its own branch point (or outlet cap).

Each bifurcation is built like cases/bifurcation/geometry.py (whose functions it imports):

    parent      the parent tube ends flat at the branch point B
    joint       sphere of the parent radius R_p at B (tangent to the parent tube)
    daughters   tubes from B along cos θ e ± sin θ n, θ = 30° (bifurcation angle 60°), whose
                radius tapers from R_p at B to R_d over l_t = R_p + R_d by a smoothstep
                r(t) = R_d + (R_p − R_d)(1 − 3s² + 2s³), s = t/l_t: r′(0) = 0, so the joint sphere
                is tangent to them, and it stays inside them for t > 0 when l_t² ≥ 6 R_p (R_p − R_d)
                (checked below)
    carina      the two daughters joined by the polynomial smooth minimum of width
                k(z) = K (1 − (z/R_p)²)₊, K = 1.2 R_d (the bifurcation's 3.6 mm for R = 3 mm),
                z the height above the bifurcation plane

`planar`: every bifurcation in one plane (the x–y plane). `rotated`: each bifurcation plane is
turned by 90° about its parent tube's axis against its parent's plane (the physiological
arrangement): the normal n of a daughter's bifurcation is the binormal e × n of its parent's.

The surface is extracted by marching cubes on a grid of spacing `--spacing` and written as an
ASCII STL with the solids `wall` and `outlet1`..`outlet8` (the flat caps); the G3 tube runs past
x = 0, where snappyHexMesh cuts it with the background box (the inlet patch). The centrelines,
radii, carina apexes and the generation zones (`centrelines.json`, next to the STL) are what
the Rust scene's generation classifier reads (`studies::airway_tree`).

Usage: geometry.py OUT.stl --variant planar|rotated [--spacing M] [--scale S]
(prints the derived dimensions and the box of the mesh as key=value lines)
"""
import argparse
import json
import os
import sys

import numpy as np
from skimage.measure import marching_cubes

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bifurcation"))
from geometry import carina_width, smooth_min  # noqa: E402  (the bifurcation's own rules)

# Weibel (1963) model A, generations 3..6: diameter and length (m), before scaling.
WEIBEL_A = {3: (5.6e-3, 7.6e-3), 4: (4.5e-3, 12.7e-3), 5: (3.5e-3, 10.7e-3), 6: (2.8e-3, 9.0e-3)}
FIRST, LAST = 3, 6
THETA = np.deg2rad(30.0)  # parent to daughter axis (bifurcation angle 60°, as the bifurcation)
CARINA_K = 1.2  # carina blend width at the apex over the daughter radius (3.6 mm / 3 mm)
ZONE = 1.0  # a daughter tube begins this many daughter radii past the carina apex
PAST = 1.5e-3  # the surface runs this far past the inlet plane; margin of the box


def unit(v):
    return v / np.linalg.norm(v)


def build(variant, scale):
    """Tubes (dicts) in depth-first order and bifurcations (dicts)."""
    dims = {g: (0.5 * d * scale, l * scale) for g, (d, l) in WEIBEL_A.items()}
    tubes, bifs = [], []

    def add(gen, start, direction, normal, parent, r_start):
        r, length = dims[gen]
        tube = {
            "id": len(tubes),
            "generation": gen,
            "parent": parent,
            "start": start,
            "end": start + length * direction,
            "direction": direction,
            "radius": r,
            "start_radius": r_start,
            "taper": 0.0 if parent is None else r_start + r,
            "children": [],
        }
        tubes.append(tube)
        if gen == LAST:
            return tube["id"]
        b = np.cross(direction, normal)
        bif = {"id": len(bifs), "generation": gen, "tube": tube["id"], "branch_point": tube["end"],
               "axis": direction, "normal": normal, "binormal": b}
        bifs.append(bif)
        for sign in (1.0, -1.0):
            d = np.cos(THETA) * direction + sign * np.sin(THETA) * normal
            if variant == "planar":
                # In-plane normal of the daughter, turned with it (only labels depend on its sign).
                n_child = unit(-sign * np.sin(THETA) * direction + np.cos(THETA) * normal) * sign
            else:
                n_child = b
            child = add(gen + 1, tube["end"], unit(d), unit(n_child), tube["id"], r)
            tube["children"].append(child)
        return tube["id"]

    start = np.array([0.0, 0.0, 0.0])
    add(FIRST, start, np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]), None, dims[FIRST][0])
    # The G3 tube runs past the inlet plane (cut there by the mesh's box).
    return tubes, bifs


def tube_radius(tube, t):
    if tube["parent"] is None:
        return np.full_like(t, tube["radius"])
    s = np.clip(t / tube["taper"], 0.0, 1.0)
    return tube["radius"] + (tube["start_radius"] - tube["radius"]) * (1.0 - 3 * s * s + 2 * s**3)


def tube_sdf(tube, p):
    """Approximate signed distance to a finite tube (p: (..., 3)); flat ends at both ends (the
    first tube starts PAST before the inlet plane)."""
    rel = p - tube["start"]
    t = rel @ tube["direction"]
    radial = np.sqrt(np.maximum(np.einsum("...i,...i->...", rel, rel) - t * t, 0.0))
    length = np.linalg.norm(tube["end"] - tube["start"])
    lo = -PAST if tube["parent"] is None else 0.0
    return np.maximum(np.maximum(radial - tube_radius(tube, t), lo - t), t - length)


def components(tubes, bifs):
    """(bounding box, function of points) whose minimum is the tree's signed distance."""
    out = []
    first = tubes[0]

    def box(ts, extra=0.0):
        pts = np.array([p for t in ts for p in (t["start"], t["end"])])
        r = max(max(t["radius"], t["start_radius"]) for t in ts) + extra
        lo = pts.min(axis=0) - r
        hi = pts.max(axis=0) + r
        return lo, hi

    lo, hi = box([first])
    lo[0] -= PAST
    out.append(((lo, hi), lambda p, t=first: tube_sdf(t, p)))
    for bif in bifs:
        parent = tubes[bif["tube"]]
        a, b = (tubes[c] for c in parent["children"])
        B = bif["branch_point"]
        rp = parent["radius"]
        out.append(((B - rp, B + rp), lambda p, B=B, rp=rp: np.linalg.norm(p - B, axis=-1) - rp))
        k_apex = CARINA_K * a["radius"]

        def blend(p, a=a, b=b, bif=bif, rp=rp, k_apex=k_apex):
            z = (p - bif["branch_point"]) @ bif["binormal"]
            return smooth_min(tube_sdf(a, p), tube_sdf(b, p), carina_width(k_apex, z, rp))

        out.append((box([a, b], 0.5 * k_apex), blend))
    return out


def sdf(parts, p):
    out = np.full(p.shape[:-1], np.inf)
    for _, f in parts:
        out = np.minimum(out, f(p))
    return out


def carina(parts, bif, daughter_radius):
    """Rounded apex (on the symmetry line of the bifurcation plane) and its radius of curvature
    in that plane, from the wall s(y) = s_apex + y²/(2ρ) near the apex."""
    B, e, n = bif["branch_point"], bif["axis"], bif["normal"]
    s = np.linspace(0.0, 4.0 * daughter_radius / np.sin(THETA), 400001)

    def first_wall(offset):
        p = B + s[:, None] * e + offset * n
        return s[np.argmax(sdf(parts, p) > 0)]

    apex = first_wall(0.0)
    dy = 0.05 * daughter_radius
    return B + apex * e, dy * dy / (2 * (first_wall(dy) - apex))


def clearance(tubes, samples=401):
    """Smallest wall-to-wall gap between tubes that do not touch by construction (neither one's
    parent nor a sibling of the other): centreline points at their local radii, sampled."""
    u = np.linspace(0.0, 1.0, samples)

    def sampled(t):
        length = np.linalg.norm(t["end"] - t["start"])
        return t["start"] + (u * length)[:, None] * t["direction"], tube_radius(t, u * length)

    gap = np.inf
    for i, a in enumerate(tubes):
        for b in tubes[i + 1:]:
            if a["parent"] == b["parent"] or b["parent"] == a["id"] or a["parent"] == b["id"]:
                continue
            (pa, ra), (pb, rb) = sampled(a), sampled(b)
            d = np.linalg.norm(pa[:, None, :] - pb[None, :, :], axis=-1) - ra[:, None] - rb[None, :]
            gap = min(gap, d.min())
    return gap


def write_ascii_stl(path, verts, faces, solids):
    """`solids`: list of (name, face mask)."""
    with open(path, "w") as f:
        for name, mask in solids:
            tri = verts[faces[mask]]
            n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
            n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
            f.write(f"solid {name}\n")
            rows = np.concatenate([n[:, None, :], tri], axis=1).reshape(-1, 12)
            for r in rows:
                f.write(
                    f"facet normal {r[0]:.6e} {r[1]:.6e} {r[2]:.6e}\nouter loop\n"
                    f"vertex {r[3]:.9e} {r[4]:.9e} {r[5]:.9e}\nvertex {r[6]:.9e} {r[7]:.9e} {r[8]:.9e}\n"
                    f"vertex {r[9]:.9e} {r[10]:.9e} {r[11]:.9e}\nendloop\nendfacet\n"
                )
            f.write(f"endsolid {name}\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--variant", choices=["planar", "rotated"], required=True)
    ap.add_argument("--spacing", type=float, default=1e-4)
    ap.add_argument("--scale", type=float, default=6.0 / 5.6)
    args = ap.parse_args()
    h = args.spacing
    tubes, bifs = build(args.variant, args.scale)
    for t in tubes[1:]:
        rp, rd = t["start_radius"], t["radius"]
        if t["taper"] ** 2 < 6 * rp * (rp - rd):
            sys.exit(f"taper {t['taper']} too short for radii {rp}, {rd}: the joint would show")
    gap = clearance(tubes)
    if gap <= 0.0:
        sys.exit(f"tubes overlap (wall gap {gap:.3e} m)")
    parts = components(tubes, bifs)

    # Carina apexes and the zones: a daughter tube begins ZONE daughter radii past the apex
    # (measured along its axis); before that the bifurcation zone of its parent's generation.
    for bif in bifs:
        parent = tubes[bif["tube"]]
        rd = tubes[parent["children"][0]]["radius"]
        apex, rho = carina(parts, bif, rd)
        bif["apex"], bif["apex_radius"] = apex, rho
        for c in parent["children"]:
            child = tubes[c]
            child["entry"] = float((apex - child["start"]) @ child["direction"] + ZONE * child["radius"])
    tubes[0]["entry"] = 0.0

    pts = np.array([p for t in tubes for p in (t["start"], t["end"])])
    rmax = max(t["start_radius"] for t in tubes)
    lo = pts.min(axis=0) - rmax - PAST
    hi = pts.max(axis=0) + rmax + PAST
    lo[0] = -PAST
    xs = np.arange(lo[0], hi[0] + h / 2, h)
    ys = np.arange(lo[1], hi[1] + h / 2, h)
    zs = np.arange(lo[2], hi[2] + h / 2, h)
    vol = np.full((len(xs), len(ys), len(zs)), np.float32(1.0))
    for (blo, bhi), f in parts:
        i0, i1 = (np.searchsorted(xs, blo[0] - 2 * h), np.searchsorted(xs, bhi[0] + 2 * h))
        j0, j1 = (np.searchsorted(ys, blo[1] - 2 * h), np.searchsorted(ys, bhi[1] + 2 * h))
        k0, k1 = (np.searchsorted(zs, blo[2] - 2 * h), np.searchsorted(zs, bhi[2] + 2 * h))
        for i in range(i0, i1, 32):  # slabs: bounded memory
            ie = min(i + 32, i1)
            x, y, z = np.meshgrid(xs[i:ie], ys[j0:j1], zs[k0:k1], indexing="ij")
            v = f(np.stack([x, y, z], axis=-1)).astype(np.float32)
            vol[i:ie, j0:j1, k0:k1] = np.minimum(vol[i:ie, j0:j1, k0:k1], v)
    verts, faces, _, _ = marching_cubes(vol, level=0.0, spacing=(h, h, h))
    verts = verts.astype(np.float64) + np.array([xs[0], ys[0], zs[0]])

    # Outlet caps: triangles whose three vertices lie on a terminal tube's end plane.
    outlets = [t for t in tubes if t["generation"] == LAST]
    taken = np.zeros(len(faces), dtype=bool)
    solids = []
    for k, t in enumerate(outlets, 1):
        rel = verts - t["end"]
        on = np.abs(rel @ t["direction"]) < 1e-3 * h
        near = np.linalg.norm(rel, axis=1) < t["radius"] + 2 * h
        mask = np.all((on & near)[faces], axis=1)
        if not mask.any():
            sys.exit(f"outlet {k}: no cap triangles found")
        taken |= mask
        solids.append((f"outlet{k}", mask))
        t["outlet"] = f"outlet{k}"
    write_ascii_stl(args.out, verts, faces, [("wall", ~taken)] + solids)

    desc = {
        "variant": args.variant,
        "scale": args.scale,
        "theta_deg": float(np.rad2deg(THETA)),
        "zone_radii": ZONE,
        "tubes": [
            {
                "id": t["id"],
                "generation": t["generation"],
                "parent": t["parent"],
                "start": t["start"].tolist(),
                "end": t["end"].tolist(),
                "radius": t["radius"],
                "start_radius": t["start_radius"],
                "entry": t["entry"],
                "outlet": t.get("outlet"),
            }
            for t in tubes
        ],
        "bifurcations": [
            {
                "generation": b["generation"],
                "tube": b["tube"],
                "branch_point": b["branch_point"].tolist(),
                "normal": b["normal"].tolist(),
                "apex": b["apex"].tolist(),
                "apex_radius": b["apex_radius"],
            }
            for b in bifs
        ],
    }
    with open(os.path.join(os.path.dirname(os.path.abspath(args.out)), "centrelines.json"), "w") as f:
        json.dump(desc, f, indent=1)
        f.write("\n")

    print(f"variant={args.variant}")
    print(f"scale={args.scale:.6f}")
    for g in range(FIRST, LAST + 1):
        r = next(t["radius"] for t in tubes if t["generation"] == g)
        length = next(np.linalg.norm(t["end"] - t["start"]) for t in tubes if t["generation"] == g)
        print(f"g{g}_diameter={2 * r:.6e} g{g}_length={length:.6e}")
    for b in bifs:
        print(f"bifurcation{b['id']}_g{b['generation']}_apex_radius={b['apex_radius']:.6e}")
    print(f"wall_gap_min={gap:.6e}")
    print(f"box_lo={lo[0]:.6e} {lo[1]:.6e} {lo[2]:.6e}")
    print(f"box_hi={hi[0]:.6e} {hi[1]:.6e} {hi[2]:.6e}")
    print(f"triangles={len(faces)}")


if __name__ == "__main__":
    main()
