"""The edgedeform demo (run inside Blender, background mode):

    blender -b --factory-startup --python-exit-code 1 --python demo/run_demo.py -- \
        [--out demo_out] [--samples dino plane ...] [--ci] [--cell 400x300]

For every sample of blend_samples/scenes.json: λ ∈ {0, 0.5, 1} in the edge and the primal
domain plus the painted stiffness (edge), each solved to convergence; then a comparison sheet
PNG, the metrics (metrics.json, metrics.md) and one .blend with every result side by side
(one Blender scene per sample). --ci: the smallest sample at low resolution.
"""
import argparse
import os
import sys
import time

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path[:0] = [HERE, os.path.join(REPO, "blend_samples")]
import addon_check  # noqa: E402
import deform       # noqa: E402
import regions      # noqa: E402
import render       # noqa: E402
import sheet        # noqa: E402
import tables       # noqa: E402

CI_SAMPLE = "bar"   # the smallest mesh (770 vertices), procedural


def import_edgedeform(module_path):
    try:
        import edgedeform
    except ImportError:
        sys.path.insert(0, module_path)
        import edgedeform
    return edgedeform


def clean(out):
    """Remove what an earlier run wrote, so that checks never pass on stale files."""
    import glob
    import shutil
    for pattern in ("metrics.json", "metrics.md", "*_sheet.png", "*_sheet_small.jpg",
                    "edgedeform_results.blend", "edgedeform_results.blend1"):
        for path in glob.glob(os.path.join(out, pattern)):
            os.remove(path)
    for sub in ("cells", "addon_check"):
        shutil.rmtree(os.path.join(out, sub), ignore_errors=True)


def parse(argv):
    ap = argparse.ArgumentParser(prog="run_demo.py", description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(REPO, "demo_out"))
    ap.add_argument("--samples", nargs="*", help="scene names (default: all)")
    ap.add_argument("--ci", action="store_true", help="smallest sample, 200x150 cells")
    ap.add_argument("--cell", default="400x300", help="cell size in pixels, WxH")
    ap.add_argument("--max-iterations", type=int, default=3000)
    ap.add_argument("--tolerance", type=float, default=1e-3,
                    help="estimated distance to the fixed point, fraction of the bbox diagonal")
    ap.add_argument("--repeat", type=int, default=3, help="timing: best of N solves")
    ap.add_argument("--module-path", default=os.path.join(REPO, "build", "python"),
                    help="folder holding the edgedeform package, if not importable")
    ap.add_argument("--samples-dir", default=None,
                    help="sample .blend files for the add-on check (default: make them in OUT)")
    ap.add_argument("--no-addon-check", action="store_true")
    ap.add_argument("--clean", action="store_true",
                    help="first delete this demo's earlier outputs in OUT (and only those)")
    args = ap.parse_args(argv)
    if args.ci:
        args.samples = args.samples or [CI_SAMPLE]
        args.cell = "200x150"
        args.repeat = 1
    return args


def main(argv):
    args = parse(argv)
    ed = import_edgedeform(args.module_path)
    width, height = (int(v) for v in args.cell.lower().split("x"))
    out = os.path.abspath(args.out)
    if args.clean:
        clean(out)
    cell_dir = os.path.join(out, "cells")
    os.makedirs(cell_dir, exist_ok=True)
    scenes = [s for s in regions.load_scenes() if not args.samples or s["name"] in args.samples]
    if not scenes:
        raise SystemExit("run_demo: no sample named %s" % args.samples)
    check = None if args.no_addon_check else addon_check.AddonCheck(
        args.samples_dir, out, args.module_path)

    doc = {"settings": {"max_iterations": args.max_iterations, "tolerance": args.tolerance,
                        "cell": [width, height], "warm_start": False,
                        "ms": "best of %d solves" % args.repeat},
           "edgedeform": dict(ed.build_info()), "samples": []}
    render.reset_scene("demo")
    first_scene = bpy.context.scene
    for scene_def in scenes:
        t0 = time.perf_counter()
        print("run_demo: %s" % scene_def["title"])
        V, F = regions.scene_mesh(scene_def)
        setup = regions.scene_setup(scene_def, V)
        cells = deform.run_cells(ed, V, F, setup, args.max_iterations, args.tolerance,
                                 args.repeat)
        materials = regions.material_regions(scene_def, V)
        free = np.ones(len(V), bool)
        free[setup["handle_index"]] = free[setup["static"]] = False
        painted = deform.painted_regions(V, F, cells, materials, free)

        sc, cameras = sheet.build(scene_def, V, F, setup, cells, width, height)
        images = sheet.render_cells(sc, cameras, cell_dir, scene_def["name"])
        sheet_path = os.path.join(out, "%s_sheet.png" % scene_def["name"])
        boxes = sheet.compose(images, sheet_path)
        small = sheet.small_copy(sheet_path, sheet_path.replace("_sheet.png", "_sheet_small.jpg"))

        sample = {"name": scene_def["name"], "title": scene_def["title"],
                  "mesh": scene_def["mesh"], "vertices": len(V), "faces": len(F),
                  "handle_vertices": len(setup["handle_index"]),
                  "static_vertices": len(setup["static"]),
                  "sheet": sheet_path, "sheet_small": small, "sheet_cells": boxes,
                  "cells": [{k: v for k, v in c.items() if k != "positions"} for c in cells],
                  "painted_regions": painted}
        if check is not None:
            sample["addon_check"] = check.run(scene_def, ed, V, F, setup)
            print("  add-on check:", sample["addon_check"])
        doc["samples"].append(sample)
        print("  sheet %s (%.1f s)" % (sheet_path, time.perf_counter() - t0))

    bpy.data.scenes.remove(first_scene)
    blend_path = os.path.join(out, "edgedeform_results.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend_path, compress=True)
    json_path, md_path = os.path.join(out, "metrics.json"), os.path.join(out, "metrics.md")
    tables.write(doc, json_path, md_path)

    print("\nrun_demo: outputs")
    for s in doc["samples"]:
        print("  sheet   %s" % s["sheet"])
    print("  metrics %s\n          %s" % (md_path, json_path))
    print("  results %s (one scene per sample)" % blend_path)
    failed = [s["name"] for s in doc["samples"]
              if s.get("addon_check") and not s["addon_check"]["ok"]]
    if failed:
        # The outputs stay written (they show what went wrong); the exit code says it did.
        raise SystemExit("run_demo: the add-on check failed for %s (see metrics.md)"
                         % ", ".join(failed))


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
