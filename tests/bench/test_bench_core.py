"""bench/bench_core.py on the 1k mesh: precompute, per-iteration parts and the incremental paths."""

from _bench import finite, load, run


def test_one_row_with_every_timing(tmp_path):
    out = tmp_path / "core.json"
    run("bench_core.py", "--sizes", "1k", "--domains", "edge", "--lambdas", "0.5", "--repeat", "1",
        "--max-iterations", "20", "--json", out)
    result = load(out)
    (row,) = result["rows"]
    assert (row["size"], row["domain"], row["lambda"], row["vertices"]) == ("1k", "edge", 0.5, 829)
    numbers = [v for k, v in row.items() if k.endswith("_ms") or k.endswith("_ms_per_it")]
    assert len(numbers) >= 6 and finite(*numbers) and all(v >= 0 for v in numbers)
    for key in ("precompute_ms", "ms_per_it", "stiffness_change_ms", "handle_add_ms",
                "handle_remove_ms", "fresh_factor_add_ms"):
        assert finite(row[key]) and row[key] > 0, key
    assert result["commands"] and result["build_info"]["solver"]
    import bench_core
    assert "| 1k | spot_low_resolution.obj | 829 | edge | 0.5 |" in bench_core.markdown(result)


def test_peak_memory_of_anderson_and_lbfgs(tmp_path):
    """--peak: one fresh process per method, each naming the method that ran (L-BFGS at
    lambda 1) and compared with Anderson's peak."""
    out = tmp_path / "core.json"
    run("bench_core.py", "--peak", "--sizes", "1k", "--domains", "edge", "--lambdas", "1",
        "--peak-methods", "anderson,lbfgs", "--json", out)
    anderson, lbfgs = load(out)["peak_memory"]
    assert (anderson["method"], lbfgs["method"]) == ("anderson", "lbfgs")
    assert (anderson["ran"], lbfgs["ran"]) == ("anderson", "lbfgs")
    assert finite(anderson["peak_mb"], lbfgs["peak_mb"]) and anderson["peak_mb"] > 0
    import bench_core
    assert "× Anderson's" in bench_core.targets([], load(out)["peak_memory"])
