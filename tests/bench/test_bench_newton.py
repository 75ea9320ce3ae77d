"""bench/bench_newton.py on the small Spot: a row per method, cell and tolerance, each cold
solve timed and its claim checked against the cell's reference; the D1 variants run."""

from _bench import finite, load, run


def test_rows_for_every_method_cell_and_tolerance(tmp_path):
    out = tmp_path / "newton.json"
    run("bench_newton.py", "--cells", "spot:lift:1,spot:lift:primal:0.5", "--methods", "anderson,newton,d1-full,d1-lifted",
        "--tolerances", "1e-3,1e-5", "--max-iterations", "800", "--out", out)
    result = load(out)
    rows = result["rows"]
    # the d1 variants run at lambda 1 only: below it every method is Anderson (record 0029)
    expected = [(m, t) for m in ("anderson", "newton", "d1-full", "d1-lifted") for t in (1e-3, 1e-5)] + \
               [(m, t) for m in ("anderson", "newton") for t in (1e-3, 1e-5)]
    assert [(r["method"], r["tolerance"]) for r in rows] == expected
    assert {r["domain"] for r in rows[8:]} == {"primal"}
    for r in rows:
        assert finite(r["wall_s"], r["distance_to_reference"], r["reference_residual"], r["energy"]) and r["wall_s"] > 0
        assert 0 < r["iterations"] <= 800 and r["reference_residual"] < 1e-9
        if r["converged"]:  # a claim is checked against the reference
            assert r["distance_to_reference"] <= 2 * r["tolerance"], (r["method"], r["lambda"], r["tolerance"])
    d1 = [r for r in rows if r["method"].startswith("d1")]
    assert all(r["newton_steps"] > 0 and r["factorizations"] >= r["newton_steps"] for r in d1)
    assert all(r["newton_steps"] == 0 for r in rows if r["method"] == "anderson" or r["lambda"] < 1)
    below = [r for r in rows if r["lambda"] < 1]  # "newton" below lambda 1 is Anderson, step for step
    assert [r["iterations"] for r in below if r["method"] == "newton"] == \
           [r["iterations"] for r in below if r["method"] == "anderson"]
    import bench_newton
    table = bench_newton.markdown(result)
    assert "| spot lift edge λ 1 | 580 | d1-lifted | 1e-05 |" in table and "| 1.00 |" in table
