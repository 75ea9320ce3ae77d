#!/usr/bin/env python3
"""Every sample scene (blend_samples/scenes.json: its handles, static vertices and edits) x
domain x uniform lambda in {0, 0.25, 0.5, 0.75, 1}: a default cold solve (Anderson, tolerance
1e-3, at most 2000 iterations) must either report converged or stop with the "not converged"
warning, with finite positions. Prints one line per cell and writes
bench/results/samples_convergence.json (bench/report.py renders it with markdown()).

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_samples.py [--scenes dino,bar]
        [--json PATH]
"""
import argparse
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


LAMBDAS = (0.0, 0.25, 0.5, 0.75, 1.0)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", default="", help="comma list of scene names (default: all)")
    ap.add_argument("--json", default=str(HERE / "results" / "samples_convergence.json"))
    args = ap.parse_args(argv)
    import edgedeform as ed
    wanted = [x for x in args.scenes.split(",") if x]
    rows = []
    for scene in regions.load_scenes():
        if wanted and scene["name"] not in wanted:
            continue
        V, F = regions.scene_mesh(scene)
        setup = regions.scene_setup(scene, V)
        for domain in ("edge", "primal"):
            d = ed.Deformer(V, F, domain=domain)
            d.set_constraints(handles=setup["handle_index"], static=setup["static"])
            for lam in LAMBDAS:
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
    out = Path(args.json)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps({"machine": machine_info(), "build_info": ed.build_info(),
                               "command": "bench/bench_samples.py " + " ".join(argv or sys.argv[1:]),
                               "rows": rows}, indent=1))


def markdown(result):
    rows = result["rows"]
    cols = [(d, lam) for d in ("edge", "primal") for lam in LAMBDAS]
    lines = ["Every sample scene of blend_samples/scenes.json with its own handles, static "
             "vertices and edit; a default cold solve (tolerance 1e-3, at most 2000 "
             "iterations). Cell: iterations, then ✓ converged or ✗ stopped with the "
             "'not converged' warning.", "",
             "| scene | vertices | " + " | ".join(f"{d} λ={lam:g}" for d, lam in cols) + " |",
             "|---" * (2 + len(cols)) + "|"]
    for scene in dict.fromkeys(r["scene"] for r in rows):
        mine = {(r["domain"], r["lambda"]): r for r in rows if r["scene"] == scene}
        cells = []
        for c in cols:
            r = mine.get(c)
            cells.append("–" if r is None else
                         f"{r['iterations']} {'✓' if r['converged'] else '✗' if r['warned'] else '?'}")
        n = next(r["vertices"] for r in rows if r["scene"] == scene)
        lines.append(f"| {scene} | {n:,} | " + " | ".join(cells) + " |")
    good = sum(r["converged"] for r in rows)
    lines += ["", f"{good} of {len(rows)} converged; every other one warned: "
              f"{'yes' if all(r['finite'] and (r['converged'] or r['warned']) for r in rows) else '**no**'}."]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
