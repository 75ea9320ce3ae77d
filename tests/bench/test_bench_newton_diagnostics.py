"""bench/bench_newton_diagnostics.py on a small mesh: its JSON has the rows the docs table
reads, with finite values in the ranges they must lie in, and the checks it runs on itself
(Ritz residuals, the A identity, the probed Hessian against K products and against K built
column by column, chunked Anderson against one uncut run) hold."""

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench"))

import bench_newton_diagnostics as diag  # noqa: E402

CELL = "spot_low_resolution.obj:lift:edge"
EIGENVALUES = 12


def finite(x):
    return isinstance(x, (int, float)) and math.isfinite(x)


def test_json_rows_and_ranges(tmp_path):
    out = tmp_path / "diag.json"
    diag.main(["--cells", CELL, "--eigenvalues", str(EIGENVALUES), "--patches", "30,100,30:4",
               "--safeguard-iterations", "200", "--monotone-iterations", "100",
               "--json", str(out), "--png", str(tmp_path / "diag.png")])
    result = json.loads(out.read_text())
    assert all(finite(x) for x in result["load_start"] + result["load_end"])
    (row,) = result["rows"]
    assert (row["mesh"], row["edit"], row["domain"]) == ("spot_low_resolution.obj", "lift", "edge")
    assert 0 < row["free"] < row["vertices"]

    ref = row["reference"]
    assert ref["converged"] and ref["residual"] < 1e-8 and ref["one_step_residual"] < 1e-8
    assert row["a_identity_error"] < 1e-10

    s = row["spectrum"]
    mod = np.asarray(s["moduli"])
    assert s["found"] == EIGENVALUES == len(mod) and np.isfinite(mod).all()
    assert (np.diff(mod) <= 1e-12).all()                 # largest first
    assert 0.5 < mod[0] < 1.0 and s["above_1"] == 0      # a stable minimum: contracting
    assert s["above_0.9"] == int((mod > 0.9).sum()) >= s["above_0.99"] >= s["above_0.999"]
    assert max(s["ritz_residuals"][:5]) < 1e-6          # the leading pairs are resolved
    part, share = np.asarray(s["participation"]), np.asarray(s["top1pct_share"])
    assert len(part) == len(share) == EIGENVALUES
    assert ((part > 0) & (part <= 1 + 1e-12)).all() and ((share > 0) & (share <= 1 + 1e-12)).all()

    assert [(c["patches_requested"], c["blend"]) for c in row["capture"]] == [(30, 0), (100, 0), (30, 4)]
    # Blending the same patches removes their jumps: less of each soft mode is missed in A's norm.
    assert row["capture"][2]["A_top10_median"] < row["capture"][0]["A_top10_median"]
    for c in row["capture"]:
        assert 0 < c["rank"] <= c["basis_columns"]
        assert c["coarse_operator_check"] < 1e-10      # the core's U^T K U is what we project with
        for norm in ("euclidean", "A", "K"):
            f = np.asarray(c["miss"][norm])
            assert len(f) == EIGENVALUES and np.isfinite(f).all()
            assert ((f >= 0) & (f <= 1 + 1e-9)).all(), (norm, f)
            assert c[f"{norm}_top10_median"] <= c[f"{norm}_top10_max"] <= 1 + 1e-9

    for sg, lam in zip(row["safeguard"], (0.5, 1.0)):
        assert sg["lambda"] == lam and len(sg["chunks"]) == 2
        assert all(0 <= ch["rejected"] + ch["accelerated"] <= ch["iterations"] for ch in sg["chunks"])
        assert sg["chunked_vs_whole"] == 0.0
        assert (sg["whole_run_rejected"], sg["whole_run_accelerated"]) == (sg["rejected"], sg["accelerated"])

    m = row["monotonicity"]
    assert m["lambda"] == 0.5 and m["energies"] == m["iterations"] == 100
    assert 0 <= m["increases"] <= m["energies"] - 1 and finite(m["largest_relative_increase"])
    assert (m["increases"] == 0) == (m["largest_relative_increase"] == 0.0)

    h = row["hessian"]
    assert h["size"] == 3 * row["free"]
    assert h["probe_check"] < 1e-12 and h["dense_check"] < 1e-12
    assert h["asymmetry"] < 1e-10                        # the Hessian at lambda = 1
    for f in (h["K_superlu"], h["A_superlu"]):
        assert f["seconds"] > 0 and f["factor_nonzeros"] > 0
    assert h["K_superlu"]["factor_nonzeros"] >= h["nonzeros"]

    table = diag.table(result)
    assert f"| spot_low_resolution.obj lift edge λ 1 | {ref['iterations']}, " in table
    assert f"{mod[0]:.4f}" in table


@pytest.mark.parametrize("blend", (0, 4))
def test_projections_keep_the_coarse_space_and_shrink_the_rest(blend):
    """The miss fractions are of real projections: 0 for a vector of the space, in (0, 1]
    for a random one, in each of the three norms."""
    import edgedeform as ed
    p = diag.load_cell(ed, CELL)
    X, _ = diag.reference(p, "anderson")
    nf = len(p["free"])
    A3, _ = diag.system_matrix(p["d"], p["free"])
    space = diag.CoarseSpace(p["d"], X, A3, 30, blend)

    def K(W):
        return np.column_stack([diag.to_flat(p["d"]._jacobian(X, diag.to_points(W[:, c], nf), True))
                                for c in range(W.shape[1])])

    inside = space.U @ (space.T[:, :3] @ np.array([[1.0], [-2.0], [0.5]]))
    outside = np.random.default_rng(3).standard_normal((3 * nf, 1))
    assert space.miss_euclidean(inside) < 1e-12
    assert space.miss_A(inside) < 1e-10
    assert space.miss_K(inside, K(inside)) < 1e-5        # sqrt of a difference of squares
    for miss in (space.miss_euclidean(outside), space.miss_A(outside), space.miss_K(outside, K(outside))):
        assert 0.05 < miss <= 1.0
