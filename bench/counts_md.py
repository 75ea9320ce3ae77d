#!/usr/bin/env python3
"""Render the iteration counts recorded by the pytest suite into docs/benchmarks.md.

    EDGEDEFORM_COUNTS_JSON=/tmp/counts.json PYTHONPATH=build/python \\
        /usr/bin/python3 -m pytest -q tests/python
    /usr/bin/python3 bench/counts_md.py /tmp/counts.json docs/benchmarks.md
"""

import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from machine import machine_info  # noqa: E402
from md_section import replace_section  # noqa: E402

INTRO = """## Convergence counts

Measured by the pytest suite (`tests/python`, recorded with `EDGEDEFORM_COUNTS_JSON`), on
the test meshes in `tests/data`. Date: {date}.

**Rigid motion from the naive solve** (`test_rigid_convergence.py`): two handle groups (the
lowest and highest 10 % along the longest axis) moved by one rigid motion (30° about
(1, 2, 0.5), plus a shift), nothing static. Counted: local/global iterations until every
vertex is within 1e-6 × bounding-box diagonal of the rigidly moved rest shape (checked
every 5 iterations, so counts are multiples of 5; budget 3000). The solves use the defaults:
Anderson acceleration, and the warm-started chunks continue one accelerated iteration.

{rigid}

Not in the test: on the flat `cgal_plane.off` the primal domain with λ = 0 crawls (every
interior rest Laplacian is zero there, so only the boundary steers the rotation out of the
plane): still 2.5e-4 × diagonal away after 4000 iterations while the energy keeps falling.
With λ = 0.1 the same case reaches 1e-6 in about 1000 iterations.

**λ < 1 on moderate edits** (`test_energy.py`): iterations until `converged` (estimated
largest vertex distance to the fixed point below 1e-3 × diagonal, Anderson-accelerated),
naive start, budget 400; "not conv." = stopped at the budget with the warning (the primal
dinosaur at λ = 0, whose residual does not contract; an expected failure in the test). "lift": lowest 20 % of the height static, top 10 % raised by 0.05 ×
diagonal; "bend": lowest 20 % along the longest axis static, top 10 % rotated 15° about
their centroid. Height = z unless the mesh is flat in z (none of these is; the plane lies
in y = 0, so its "lift" along z is an in-plane stretch).

{moderate}

Beyond the tests (same edits, 30° bend, budget 200, old energy stopping rule): on the
dinosaur the primal domain with λ = 0 does not settle and inflates the mesh (bounding box 3× the rest,
mean edge strain 1.19) while E stays small; the edge domain and λ = 0.5 stay put (mean
strain ≤ 0.007). This is the paper's "λ = 0 gets fatter" (Fig. 6) taken to its limit by the
free scale s_i, not a crash; the add-on should not offer pure λ = 0 in the primal domain
without a warning.

### Per-vertex stiffness

λ = 1 on one half, 0 on the other, lift by 0.2 × diagonal (`test_stiffness.py`). With the
halves side by side (split at the median x) each half's mean edge strain lies in the range
spanned by the uniform λ = 0 and λ = 1 results, give or take 10 % of its width, on Spot (both
domains), three peaks (both domains) and the dinosaur (edge domain): the stiff half ends a
few per cent of the gap *below* the all-stiff strain, relieved by its soft neighbour. With
the halves stacked along the lift (in series) the soft half takes over the stretch and
exceeds the all-soft strain by about 0.6 of the gap on Spot and three peaks and by 3.4 gaps
on the flat plane. Side by side, too, the dinosaur in the primal domain breaks the rule
with a lift of 0.1 × diagonal: its soft half inflates as above (3.3 gaps over the all-soft
strain), and on the flat plane lifted out of its plane the soft half ends 0.3 gaps over
(edge domain); these cases are not in the test. So "between the uniform results" holds
only for side-by-side halves, outside primal λ = 0 inflation; the test checks exactly that.
"""


def table(rows, key):
    meshes = sorted({r["mesh"] for r in rows}, key=[r["mesh"] for r in rows].index)
    cols = sorted({(r["domain"], r["lambda"]) for r in rows},
                  key=lambda c: (c[0] != "edge", c[1]))
    lines = [f"| {key} | " + " | ".join(f"{d} λ={lam:g}" for d, lam in cols) + " |",
             "|---|" + "---|" * len(cols)]
    for m in meshes:
        cells = []
        for c in cols:
            hit = [r for r in rows if r["mesh"] == m and (r["domain"], r["lambda"]) == c]
            cells.append("—" if not hit else
                         ("not conv." if hit[0]["iterations"] is None else str(hit[0]["iterations"])))
        lines.append(f"| {m} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main():
    counts = json.loads(Path(sys.argv[1]).read_text())
    rigid = [c for c in counts if c["test"].startswith("rigid")]
    parts = []
    for edit in ("lift", "bend"):
        rows = [c for c in counts if c["test"].startswith(edit)]
        if rows:
            parts.append(f"{edit}:\n\n" + table(rows, "mesh"))
    body = INTRO.format(date=machine_info()["date"], rigid=table(rigid, "mesh"),
                        moderate="\n\n".join(parts))
    replace_section(sys.argv[2], "convergence-counts", body)
    print(f"updated {sys.argv[2]}")


if __name__ == "__main__":
    main()
