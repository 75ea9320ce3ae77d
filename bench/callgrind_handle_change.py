#!/usr/bin/env python3
"""Instruction counts of a handle-set change against a fresh factorization (callgrind).

Wall clock on the shared machine is noise; callgrind's instruction counts are not. For each
mesh, one thread, edge domain, λ = 0.5, the core benchmark's lift edit, this runs the same
script under `valgrind --tool=callgrind` in four modes and reads the inclusive counts of
`Deformer::set_constraints` and `Deformer::ensure_factored` (callgrind_annotate):

- fresh:   construct, set_constraints(lift), set_stiffness(0.5), one iteration;
- add:     fresh, then the belt of bench_core.belt_group added as a handle group, one iteration;
- remove:  add, then the belt removed again, one iteration;
- final:   a fresh Deformer given the lift plus the belt directly, one iteration.

The cost of a change is the difference of two runs (add - fresh, remove - add); it is
reported against the fresh cost of the set it starts from and of the set it ends in.

    OMP_NUM_THREADS=1 PYTHONPATH=build/python /usr/bin/python3 bench/callgrind_handle_change.py \\
        [--meshes koala.obj,nefertiti_loop1.ply] [--json bench/results/callgrind_handle_change.json]

Instruction counts do not depend on the machine's load; the lead's wall-clock numbers come
from bench_core.py (its "handle add / remove" column).
"""

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from edits import lift_edit, mesh_path  # noqa: E402
from machine import machine_info  # noqa: E402

MODES = ("fresh", "add", "remove", "final")
FUNCTIONS = {"set_constraints": "edgedeform::Deformer::set_constraints(",
             "ensure_factored": "edgedeform::Deformer::ensure_factored("}


def workload(mesh, mode):
    """The profiled run (inside valgrind)."""
    import numpy as np

    import edgedeform as ed
    from bench_core import belt_group
    from edgedeform.mesh_files import read_mesh

    V, F = read_mesh(str(mesh_path(mesh)))
    handles, static, targets, ax = lift_edit(V)
    belt = belt_group(V, ax)
    belt = belt[~np.isin(belt, handles) & ~np.isin(belt, static)]
    more, more_targets = np.concatenate([handles, belt]), np.vstack([targets, V[belt]])
    d = ed.Deformer(V, F, domain="edge")
    d.set_stiffness(0.5)
    if mode == "final":
        d.set_constraints(handles=more, static=static)
        d.solve(more_targets, max_iterations=1)
        return
    d.set_constraints(handles=handles, static=static)
    d.solve(targets, max_iterations=1)
    if mode in ("add", "remove"):
        d.set_constraints(handles=more, static=static)
        d.solve(more_targets, max_iterations=1)
    if mode == "remove":
        d.set_constraints(handles=handles, static=static)
        d.solve(targets, max_iterations=1)


def inclusive_counts(out_file):
    text = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", str(out_file)],
                          check=True, capture_output=True, text=True).stdout
    counts = {}
    for line in text.splitlines():
        for key, name in FUNCTIONS.items():
            if name in line and key not in counts:
                counts[key] = int(re.match(r"\s*([\d,]+)", line).group(1).replace(",", ""))
    missing = set(FUNCTIONS) - set(counts)
    if missing:
        raise RuntimeError(f"{out_file}: no inclusive count for {sorted(missing)}")
    return counts


def profile(mesh, mode, folder):
    out_file = Path(folder) / f"callgrind.{mesh}.{mode}"
    env = dict(os.environ, OMP_NUM_THREADS="1")
    subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out_file}",
                    sys.executable, __file__, "--inner", mesh, mode],
                   check=True, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    counts = inclusive_counts(out_file)
    return counts["set_constraints"] + counts["ensure_factored"], counts


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--meshes", default="koala.obj")
    p.add_argument("--json", type=Path)
    p.add_argument("--skip-final", action="store_true", help="leave out the final set's fresh run (saves a run)")
    p.add_argument("--keep", type=Path, help="keep the callgrind outputs in this folder (for callgrind_annotate)")
    p.add_argument("--inner", nargs=2, metavar=("MESH", "MODE"), help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.inner:
        workload(*args.inner)
        return
    rows = []
    if args.keep:
        args.keep.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as scratch:
        folder = args.keep or scratch
        for mesh in args.meshes.split(","):
            total = {}
            for mode in MODES[:-1] if args.skip_final else MODES:
                total[mode], parts = profile(mesh, mode, folder)
                print(f"{mesh} {mode}: set_constraints {parts['set_constraints'] / 1e6:,.0f} M, "
                      f"ensure_factored {parts['ensure_factored'] / 1e6:,.0f} M", flush=True)
            add, remove = total["add"] - total["fresh"], total["remove"] - total["add"]
            row = {"mesh": mesh, "fresh_M": total["fresh"] / 1e6, "add_M": add / 1e6, "remove_M": remove / 1e6,
                   "add_vs_fresh": add / total["fresh"], "remove_vs_fresh": remove / total["fresh"]}
            final = ""
            if "final" in total:
                row.update(final_fresh_M=total["final"] / 1e6, add_vs_final_fresh=add / total["final"])
                final = (f" ({100 * row['add_vs_final_fresh']:.0f} % of the final set's fresh, "
                         f"{row['final_fresh_M']:,.0f} M)")
            rows.append(row)
            print(f"{mesh}: fresh {row['fresh_M']:,.0f} M; belt added {row['add_M']:,.0f} M = "
                  f"{100 * row['add_vs_fresh']:.0f} %{final}; removed {row['remove_M']:,.0f} M = "
                  f"{100 * row['remove_vs_fresh']:.0f} %", flush=True)
    if args.json:
        args.json.write_text(json.dumps({"machine": machine_info(), "unit": "millions of instructions (callgrind)",
                                         "command": "OMP_NUM_THREADS=1 bench/callgrind_handle_change.py "
                                         + " ".join(sys.argv[1:]), "rows": rows}, indent=2) + "\n")


def markdown(result):
    lines = ["One thread, edge domain, λ = 0.5, the core benchmark's lift; a belt (the 2 % band "
             "around 55 % of the height, bench_core.belt_group) added as a handle group, then "
             "removed. Counts of set_constraints + the next ensure_factored, in millions of "
             "instructions (callgrind: independent of the machine's load). Share = against the "
             "fresh constraint set's own count.", "",
             "| mesh | fresh set | belt added | share | belt removed | share | fresh lift + belt | added / that |",
             "|---|---|---|---|---|---|---|---|"]
    for r in result["rows"]:
        final = (f"{r['final_fresh_M']:,.0f} M | {100 * r['add_vs_final_fresh']:.0f} %"
                 if "final_fresh_M" in r else "– | –")
        lines.append(f"| {r['mesh']} | {r['fresh_M']:,.0f} M | {r['add_M']:,.0f} M | "
                     f"{100 * r['add_vs_fresh']:.0f} % | {r['remove_M']:,.0f} M | "
                     f"{100 * r['remove_vs_fresh']:.0f} % | {final} |")
    lines += ["", "Target: a handle group added or removed costs ≤ 30 % of a full factorization."]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
