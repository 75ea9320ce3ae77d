"""bench/bench_spectrum.py: its largest Ritz modulus is the rate at which the plain iteration
really contracts near the fixed point (checked apart, by iterating), and it writes the fields
its Markdown table reads."""

import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench"))

import bench_spectrum  # noqa: E402

CELL = "spot:lift:edge:0.5"


def test_largest_modulus_is_the_observed_contraction(tmp_path):
    out = tmp_path / "spectrum.json"
    bench_spectrum.main(["--cells", CELL, "--steps", "40", "--json", str(out)])
    row = json.loads(out.read_text())["rows"][0]
    assert row["reference_converged"] and row["one_step_residual"] < 1e-9
    assert row["above_1"] == 0 and 0.5 < row["top"][0] < 1.0
    table = bench_spectrum.markdown({"machine": {"cpu": "x", "cores": 2, "load_1min": 0.0,
                                                 "date": "d"}, "steps": 40, "rows": [row]})
    assert f"| spot lift edge λ 0.5 | {row['free']:,} |" in table and f"{row['top'][0]:.4f}" in table

    # Perturb the fixed point and iterate plainly: the residual's asymptotic ratio per
    # iteration is the largest modulus of the map's Jacobian there.
    import edgedeform as ed
    name, edit_name, domain, lam = CELL.split(":")
    d, targets, free, dg = bench_spectrum.problem(ed, (name, edit_name, domain, float(lam)))
    X, *_ = bench_spectrum.reference(d, targets)
    start = X.copy()
    start[free] += 1e-4 * dg * np.random.default_rng(1).standard_normal((int(free.sum()), 3))
    r = d.solve(targets, max_iterations=300, tolerance=0.0, warm_start=False, initial=start,
                acceleration="none")
    res = np.asarray(r.residuals)
    rate = (res[-1] / res[-101]) ** (1.0 / 100)
    assert res[-1] > 1e-12  # still above round-off, so the ratio is the mode's
    assert abs(rate - row["top"][0]) < 0.01, (rate, row["top"])
