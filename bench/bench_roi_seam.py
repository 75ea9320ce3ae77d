#!/usr/bin/env python3
"""The seam of a region picked by radius: does the shape kink where the region ends?

A region of interest (set_constraints(roi_radius=r)) keeps everything outside it at rest, so
at the region's border the deformed part meets the still part, and a kink can show there. For
each cell (mesh, λ, radius as a fraction of the bounding-box diagonal) the lift edit is
solved from a fresh Deformer to 1e-5 of the diagonal: on the whole mesh, and on the region
within r of the handle (Euclidean), once per falloff band. A band b (a fraction of r; 0 =
none) blends λ towards smooth near the border: λ · smoothstep(clamp((r − d) / (b r), 0, 1)),
d the vertex's distance from the nearest handle (computed here in numpy; the core has no
band: docs/decisions/0057-falloff-band-at-the-region-border.md). Reported:

- bend at the border: over the border edges (one end free, the other outside the region,
  neither a handle nor static), the largest change of the dihedral angle (degrees) from the
  rest shape, in the region's solve and in the whole mesh's solve at the same edges;
- the same over the outer half of the region (edges whose ends are free and at d >= r / 2,
  the same edges for every band): where a band lies, and where a kink it only moved
  inwards would show;
- the region's largest vertex distance from the whole mesh's solve, over the diagonal (all
  vertices, and the free ones only);
- the free vertices of each solve.

A bend the whole mesh does not show is the kink the region adds.

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_roi_seam.py \\
        [--cells dino:1,dino:0.5,spot11k:1,koala:1] [--radii 0.35,0.5] [--bands 0,0.25,0.5,1] \\
        [--out bench/results/roi_seam.json]

Prints a table and writes the JSON (the machine, its load, one row per cell, radius and
band); bench/report.py puts the table into docs/benchmarks.md.
"""

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from edits import MESH_FILES, diagonal, edit, mesh_path  # noqa: E402
from machine import machine_info  # noqa: E402

DEFAULT_CELLS = "dino:1,dino:0.5,spot11k:1,spot11k:0.5,koala:1,koala:0.5"
TOLERANCE = 1e-5
MAX_ITERATIONS = 6000


def interior_edges(F):
    """Edges shared by exactly two faces: (#e, 2) vertex pairs and (#e, 2) face ids."""
    key = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    faces = np.tile(np.arange(len(F)), 3)
    unique, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    by_edge = faces[np.argsort(inverse.reshape(-1), kind="stable")]
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    two = counts == 2
    return unique[two], np.column_stack([by_edge[starts[two]], by_edge[starts[two] + 1]])


def dihedral_degrees(X, F, edge_faces):
    """The angle between the normals of each edge's two faces, in degrees."""
    n = np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    cos = np.clip(np.einsum("ij,ij->i", n[edge_faces[:, 0]], n[edge_faces[:, 1]]), -1.0, 1.0)
    return np.degrees(np.arccos(cos))


def smoothstep(t):
    return t * t * (3.0 - 2.0 * t)


def band_lambda(V, handles, lam, radius, band):
    """λ blended towards smooth over the outer `band` (a fraction of the radius) of the region:
    λ · smoothstep(clamp((r − d) / (b r), 0, 1)), d the straight-line distance to the nearest
    handle (returned too). A band wider than 1 lowers λ already at the handles."""
    from scipy.spatial import cKDTree
    d, _ = cKDTree(V[np.asarray(handles)]).query(V)
    return lam * smoothstep(np.clip((radius - d) / (band * radius), 0.0, 1.0)), d


def solve(ed, V, F, handles, static, lam, targets, **region):
    d = ed.Deformer(V, F, domain="edge")
    d.set_constraints(handles, static, **region)
    d.set_stiffness(lam)
    start = time.perf_counter()
    r = d.solve(targets, tolerance=TOLERANCE, max_iterations=MAX_ITERATIONS)
    return r, time.perf_counter() - start, np.asarray(d.free_vertices)


def run_cell(ed, cell, radii, bands, log):
    from edgedeform.mesh_files import read_mesh
    name, lam = cell.split(":")
    lam = float(lam)
    V, F = read_mesh(mesh_path(MESH_FILES[name]))
    handles, static, targets = edit(V, "lift")
    dg = diagonal(V)
    whole, whole_s, whole_free = solve(ed, V, F, handles, static, lam, targets)
    edges, edge_faces = interior_edges(F)
    rest_angle = dihedral_degrees(V, F, edge_faces)
    whole_bend = np.abs(dihedral_degrees(whole.positions, F, edge_faces) - rest_angle)
    rows = []
    for fraction in radii:
        radius = fraction * dg
        for band in bands:
            stiffness, distance = band_lambda(V, handles, lam, radius, band) if band > 0 else (lam, None)
            r, wall, free = solve(ed, V, F, handles, static, stiffness, targets, roi_radius=radius)
            inside = np.zeros(len(V), bool)
            inside[free] = True
            outside = np.ones(len(V), bool)
            outside[free] = False
            outside[np.asarray(handles)] = False
            outside[np.asarray(static)] = False
            border = (inside[edges[:, 0]] & outside[edges[:, 1]]) | (inside[edges[:, 1]] & outside[edges[:, 0]])
            if distance is None:
                distance = band_lambda(V, handles, lam, radius, 1.0)[1]
            # The outer half of the region, the same edges for every band: where a band's blend
            # lies, and where a kink the band only moved inwards would show.
            outer = inside & (distance >= 0.5 * radius)
            near = outer[edges[:, 0]] & outer[edges[:, 1]]
            bend = np.abs(dihedral_degrees(r.positions, F, edge_faces) - rest_angle)
            gap = np.linalg.norm(r.positions - whole.positions, axis=1)
            row = {"mesh": name, "lambda": lam, "radius": fraction, "band": band, "vertices": len(V),
                   "free_region": int(len(free)), "free_whole": int(len(whole_free)),
                   "border_edges": int(border.sum()),
                   "border_bend_region_deg": float(bend[border].max()) if border.any() else 0.0,
                   "border_bend_whole_deg": float(whole_bend[border].max()) if border.any() else 0.0,
                   "outer_bend_region_deg": float(bend[near].max()) if near.any() else 0.0,
                   "outer_bend_whole_deg": float(whole_bend[near].max()) if near.any() else 0.0,
                   "largest_bend_whole_deg": float(whole_bend.max()),
                   "distance_to_whole": float(gap.max() / dg),
                   "distance_to_whole_in_region": float(gap[free].max() / dg),
                   "converged_region": bool(r.converged), "converged_whole": bool(whole.converged),
                   "iterations_region": int(r.iterations), "wall_region_s": wall, "wall_whole_s": whole_s}
            rows.append(row)
            log(row)
    return rows


def markdown(result):
    lines = ["| cell | radius / diag | band / radius | free: region / whole | border edges | "
             "bend at the border, region ° | same edges, whole mesh ° | outer half of the region: region ° / whole ° | "
             "region − whole in the region / diag | converged |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in result["rows"]:
        lines.append(f"| {r['mesh']} lift λ {r['lambda']:g} | {r['radius']:g} | {r.get('band', 0):g} | "
                     f"{r['free_region']:,} / {r['free_whole']:,} | {r['border_edges']:,} | "
                     f"{r['border_bend_region_deg']:.1f} | {r['border_bend_whole_deg']:.1f} | "
                     f"{r['outer_bend_region_deg']:.1f} / {r['outer_bend_whole_deg']:.1f} | "
                     f"{r['distance_to_whole_in_region']:.1e} | "
                     f"{'yes' if r['converged_region'] and r['converged_whole'] else 'no'} |")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cells", default=DEFAULT_CELLS)
    ap.add_argument("--radii", default="0.35,0.5", help="fractions of the bounding-box diagonal")
    ap.add_argument("--bands", default="0,0.25,0.5,1",
                    help="falloff bands as fractions of the radius (0 = no band)")
    ap.add_argument("--out", default=str(HERE / "results" / "roi_seam.json"))
    args = ap.parse_args(argv)
    import edgedeform as ed
    radii = [float(x) for x in args.radii.split(",")]
    bands = [float(x) for x in args.bands.split(",")]
    result = {"machine": machine_info(), "command": "bench/bench_roi_seam.py " + " ".join(argv or sys.argv[1:]),
              "rows": []}
    for cell in [c for c in args.cells.split(",") if c]:
        if cell.split(":")[0] not in MESH_FILES:
            raise SystemExit(f"unknown mesh in {cell!r}: choose from {', '.join(MESH_FILES)}")
        result["rows"] += run_cell(ed, cell, radii, bands, lambda row: print(json.dumps(row), flush=True))
    Path(args.out).write_text(json.dumps(result, indent=1) + "\n")
    print(markdown(result))


if __name__ == "__main__":
    main()
