"""Write docs/results.md from a demo run (plain Python):

    python3 demo/write_results_doc.py demo_out docs

Copies the downscaled sheets to docs/img/, embeds them with the metrics tables, and checks the
paper's claims against the measured numbers (claims.py). The hand-written reading of the
figures comes from demo/results_notes.md, which must be revised whenever the numbers change.
"""
import json
import os
import shutil
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import claims  # noqa: E402
import tables  # noqa: E402


def main(out, docs):
    with open(os.path.join(out, "metrics.json")) as f:
        doc = json.load(f)
    img_dir = os.path.join(docs, "img")
    os.makedirs(img_dir, exist_ok=True)
    notes_path = os.path.join(HERE, "results_notes.md")
    notes = open(notes_path).read().strip() if os.path.exists(notes_path) else ""
    info = doc["edgedeform"]
    parts = [
        "# Results: what the demo measures",
        "",
        "Produced by `scripts/demo.sh` (the demo: `demo/run_demo.py`; this page: "
        "`demo/write_results_doc.py`). Every number below is copied from the run's "
        "`metrics.json`; nothing is typed in by hand except the reading in the next section.",
        "",
        "Run settings: converged = estimated largest vertex distance to the fixed point below "
        "%g of the bounding-box diagonal (Anderson-accelerated), at most %d iterations, every "
        "cell started from the naive Laplacian (no warm start), ms = %s (factorization included) "
        "on a 2-core machine shared with other jobs, so timings are indicative only. Package: "
        "solver %s, OpenMP %s, %s." % (
            doc["settings"]["tolerance"], doc["settings"]["max_iterations"],
            doc["settings"].get("ms", "one solve"), info.get("solver"), info.get("openmp"),
            info.get("compiler")),
        "",
        "Sheet layout (like the paper's Figs. 1, 5, 8–10): top row (a) rest shape with the "
        "painted stiffness (blue λ=0, grey 0.5, orange 1; handles green, static red), then the "
        "edge domain at λ = 0, 0.5, 1; bottom row (e) the painted materials (edge domain), "
        "then the primal domain at λ = 0, 0.5, 1. One orthographic view and scale per sample.",
        "",
    ]
    if notes:
        parts += [notes, ""]
    parts += ["## The paper's claims, measured", ""]
    for title, fn in (("1. Edge domain vs primal at λ = 0 and λ = 1", claims.edge_vs_primal),
                      ("2. λ trades rigidity for smoothness monotonically", claims.monotonic),
                      ("3. Painted materials behave like the uniform result of each material",
                       claims.painted)):
        summary, table = fn(doc)
        parts += ["### " + title, "", summary, "", table, ""]
    parts += ["## Sheets and metrics per sample", ""]
    for s in doc["samples"]:
        name = s["name"]
        if s.get("sheet_small") and os.path.exists(s["sheet_small"]):
            dst = os.path.join(img_dir, "%s_sheet.jpg" % name)
            shutil.copyfile(s["sheet_small"], dst)
            parts += ["![%s](img/%s_sheet.jpg)" % (s["title"], name), ""]
        parts += [tables.sample_markdown(s), ""]
    path = os.path.join(docs, "results.md")
    with open(path, "w") as f:
        f.write("\n".join(parts))
    print("write_results_doc: wrote %s and %s" % (path, img_dir))


if __name__ == "__main__":
    main(*sys.argv[1:3])
