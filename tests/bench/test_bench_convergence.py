"""bench/bench_convergence.py on one small cell: a row per cell with every method's count."""

from _bench import finite, load, run

import edits  # noqa: E402


def test_one_cell_for_every_method(tmp_path):
    import edgedeform as ed
    out = tmp_path / "convergence.json"
    run("bench_convergence.py", "--meshes", "spot", "--edits", "lift,twist", "--domains", "edge",
        "--lambdas", "0.5", "--budget", "400", "--json", out)
    result = load(out)
    assert [(r["mesh"], r["edit"]) for r in result["rows"]] == [("spot", "lift"), ("spot", "twist")]
    for r in result["rows"]:
        assert list(r["methods"]) == edits.accelerations(ed)
        for m, v in r["methods"].items():
            assert v["iterations"] is None or 0 < v["iterations"] <= 400, m
            assert finite(v["ms"]) and v["ms"] > 0, m
        # 829 vertices: Anderson gets there inside the budget. (The script steps one iteration
        # per call; at lambda < 1 Newton then takes plain steps, as a one-iteration call has
        # no room for a line-search trial: docs/api.md.)
        assert r["methods"]["anderson"]["iterations"]
        assert finite(r["default_distance"], r["reference_residual"]) and r["reference_residual"] < 1e-9
    assert set(result["summary"]["median_ratio_to_plain"]) == set(edits.accelerations(ed)) - {"none"}
    import bench_convergence
    table = bench_convergence.markdown(result)
    assert "| spot | twist | edge | 0.5 |" in table
