#!/usr/bin/env python3
"""Every sample scene (blend_samples/scenes.json: its handles, static vertices and edits) x
domain x uniform lambda in {0, 0.25, 0.5, 0.75, 1}: a default cold solve (Anderson, tolerance
1e-3, at most 2000 iterations) must either report converged or stop with the "not converged"
warning, with finite positions. Prints one line per cell and writes
bench/results/samples_convergence.json.

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_samples.py
"""
import json
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "blend_samples"))

from machine import machine_info  # noqa: E402

import regions  # noqa: E402


def main():
    import edgedeform as ed
    rows = []
    for scene in regions.load_scenes():
        V, F = regions.scene_mesh(scene)
        setup = regions.scene_setup(scene, V)
        for domain in ("edge", "primal"):
            d = ed.Deformer(V, F, domain=domain)
            d.set_constraints(handles=setup["handle_index"], static=setup["static"])
            for lam in (0.0, 0.25, 0.5, 0.75, 1.0):
                d.set_stiffness(lam)
                t0 = time.perf_counter()
                r = d.solve(setup["targets"], warm_start=False)
                X = np.asarray(r.positions)
                row = {"scene": scene["name"], "vertices": len(V), "domain": domain,
                       "lambda": lam, "iterations": int(r.iterations),
                       "converged": bool(r.converged),
                       "warned": any("not converged" in w for w in r.warnings),
                       "distance_estimate": float(r.distance_estimate),
                       "finite": bool(np.isfinite(X).all()),
                       "bbox_ratio": float(np.ptp(X, 0).max() / np.ptp(V, 0).max()),
                       "seconds": time.perf_counter() - t0}
                rows.append(row)
                print(f"{row['scene']:6} {domain:6} {lam:4}: {row['iterations']:5} it "
                      f"{'converged' if row['converged'] else 'NOT converged'}"
                      f"{' (warned)' if row['warned'] else ''}  bbox x{row['bbox_ratio']:.2f}",
                      flush=True)
    ok = all(r["finite"] and (r["converged"] or r["warned"]) for r in rows)
    print(f"{sum(r['converged'] for r in rows)} of {len(rows)} converged; every other one "
          f"warned: {ok}")
    (HERE / "results").mkdir(exist_ok=True)
    (HERE / "results" / "samples_convergence.json").write_text(
        json.dumps({"machine": machine_info(), "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
