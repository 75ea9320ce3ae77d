"""bench/bench_newton.py on one small cell: a row per method, each cold solve timed and
compared with the cell's reference."""

from _bench import finite, load, run

import edits  # noqa: E402


def test_one_cell_for_every_method(tmp_path):
    import edgedeform as ed
    out = tmp_path / "newton.json"
    run("bench_newton.py", "--meshes", "spot_low_resolution.obj", "--lambdas", "1", "--max-iterations", "600",
        "--newton-coarse", "20:0,20:4", "--out", out)
    result = load(out)
    rows = result["rows"]
    methods = edits.accelerations(ed)
    expected = [m for m in methods for _ in range(2 if m == "newton" else 1)]
    assert [r["method"] for r in rows] == expected
    assert [(r["coarse_patches"], r["coarse_blend"]) for r in rows if r["method"] == "newton"] == [(20, 0), (20, 4)]
    for r in rows:
        assert finite(r["wall_s"], r["distance_to_reference"], r["reference_residual"]) and r["wall_s"] > 0
        assert 0 < r["iterations"] <= 600
        assert r["reference_residual"] < 1e-9
        if r["converged"]:  # a claim is checked against the reference
            assert r["distance_to_reference"] <= 2e-3, r["method"]
    for newton in (r for r in rows if r["method"] == "newton"):
        assert newton["converged"] and newton["newton_steps"] > 0 and newton["krylov_iterations"] > 0
        assert newton["coarse_dimension"] > 0
    import bench_newton
    assert "| spot_low_resolution | lift | edge | 1 | newton (20:4) |" in bench_newton.markdown(result)
