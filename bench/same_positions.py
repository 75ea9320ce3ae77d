#!/usr/bin/env python3
"""Do two builds give the same positions? For changes that must not move the fixed point
(a faster local step, a new parallel loop): run `save` with one build's package on the
path, `compare` with the other's.

    PYTHONPATH=<old build>/python python3 bench/same_positions.py save /tmp/old.npz
    PYTHONPATH=build/python python3 bench/same_positions.py compare /tmp/old.npz

Cases: three small meshes x both domains x λ in {0, 0.5, 1} x each acceleration method
both builds accept (--methods; "none" is the plain iteration), the core benchmark's lift; 30 iterations from a cold start, then 10 more warm
(tolerance 0, so both builds run the same count). Prints the largest difference per case,
relative to the largest coordinate, and exits 1 when one exceeds --limit.
Plain iterations repeat round-off differences without amplifying them; Anderson's least
squares can amplify them where the iteration barely contracts (primal λ = 0 on the dino:
scaling the targets by 1 + 1e-15 already moves main's result by 7e-10).
"""

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from edits import lift_edit, mesh_path, method_list  # noqa: E402

MESHES = ("spot_low_resolution.obj", "cgal_dino.off", "blub_fish.obj")


def positions(methods, meshes=MESHES):
    import edgedeform as ed
    from edgedeform.mesh_files import read_mesh
    out = {}
    for mesh in meshes:
        V, F = read_mesh(str(mesh_path(mesh)))
        handles, static, targets, _ = lift_edit(V)
        for domain in ("edge", "primal"):
            for lam in (0.0, 0.5, 1.0):
                for acceleration in methods:
                    d = ed.Deformer(V, F, domain=domain)
                    d.set_constraints(handles=handles, static=static)
                    d.set_stiffness(lam)
                    cold = d.solve(targets, max_iterations=30, tolerance=0.0, acceleration=acceleration)
                    warm = d.solve(targets, max_iterations=10, tolerance=0.0, acceleration=acceleration)
                    out[f"{mesh}|{domain}|{lam}|{acceleration}"] = np.stack([cold.positions, warm.positions])
    return out


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("action", choices=("save", "compare"))
    p.add_argument("file", help=".npz written by save, read by compare")
    p.add_argument("--limit", type=float, default=1e-9, help="largest relative difference allowed")
    p.add_argument("--methods", default="", help="comma list (default: every method this build accepts)")
    p.add_argument("--meshes", default=",".join(MESHES), help="comma list of mesh files")
    args = p.parse_args(argv)
    import edgedeform as ed
    current = positions(method_list(ed, args.methods), args.meshes.split(","))
    if args.action == "save":
        np.savez(args.file, **current)
        print(f"saved {len(current)} cases to {args.file}")
        return 0
    reference = np.load(args.file)
    worst = {}
    for key, value in current.items():
        if key not in reference:   # a method the saving build did not have
            print(f"{key:45s} not in {args.file}")
            continue
        ref = reference[key]
        diff = float(np.abs(value - ref).max() / np.abs(ref).max())
        acceleration = key.rsplit("|", 1)[1]
        worst[acceleration] = max(worst.get(acceleration, 0.0), diff)
        print(f"{key:45s} {diff:.2e}{'  over the limit' if diff > args.limit else ''}")
    if not worst:
        print(f"no case of this build is in {args.file}")
        return 1
    print("largest relative difference: " + ", ".join(f"{m} {v:.2e}" for m, v in worst.items()))
    return 1 if max(worst.values()) > args.limit else 0


if __name__ == "__main__":
    sys.exit(main())
