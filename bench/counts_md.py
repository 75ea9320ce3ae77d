#!/usr/bin/env python3
"""The iteration counts recorded by the pytest suite, kept as bench/results/counts.json for
bench/report.py (which renders them with markdown() below into docs/benchmarks.md).

    EDGEDEFORM_COUNTS_JSON=/tmp/counts.json PYTHONPATH=build/python \\
        /usr/bin/python3 -m pytest -q tests/python
    /usr/bin/python3 bench/counts_md.py /tmp/counts.json [bench/results/counts.json]
"""

import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from machine import machine_info  # noqa: E402

INTRO = """Measured by the pytest suite (`tests/python`, recorded with `EDGEDEFORM_COUNTS_JSON`), on
the test meshes in `tests/data`, with the solver's default acceleration.

**Rigid motion from the naive solve** (`test_rigid_convergence.py`): two handle groups (the
lowest and highest 10 % along the longest axis) moved by one rigid motion (30° about
(1, 2, 0.5), plus a shift), nothing static. Counted: iterations until every vertex is within
1e-6 × bounding-box diagonal of the rigidly moved rest shape (checked every 5 iterations, so
counts are multiples of 5; budget 3000).

{rigid}

**λ < 1 on moderate edits** (`test_energy.py`): iterations until `converged` (estimated
largest vertex distance to the fixed point below 1e-3 × diagonal), naive start, budget 400;
"not conv." = stopped at the budget with the warning. "lift": lowest 20 % of the height
static, top 10 % raised by 0.05 × diagonal; "bend": lowest 20 % along the longest axis
static, top 10 % rotated 15° about their centroid (the tests' own edits, smaller than
bench/edits.py's).

{moderate}
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


def markdown(result):
    counts = result["counts"]
    parts = []
    for edit in ("lift", "bend"):
        rows = [c for c in counts if c["test"].startswith(edit)]
        if rows:
            parts.append(f"{edit}:\n\n" + table(rows, "mesh"))
    rigid = [c for c in counts if c["test"].startswith("rigid")]
    return INTRO.format(rigid=table(rigid, "mesh"), moderate="\n\n".join(parts)).rstrip()


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    counts = json.loads(Path(argv[0]).read_text())
    out = Path(argv[1]) if len(argv) > 1 else HERE / "results" / "counts.json"
    out.write_text(json.dumps({"machine": machine_info(), "command": "EDGEDEFORM_COUNTS_JSON=... "
                               "pytest -q tests/python; bench/counts_md.py", "counts": counts},
                              indent=1))
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
