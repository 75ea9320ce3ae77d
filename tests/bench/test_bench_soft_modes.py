"""The solver's benchmarks on Spot 829: bench_solver (the methods against a reference) and the
soft-mode diagnostics D1-D3 of bench_soft_modes (record 0070), each as a user runs it, the
JSON checked for its rows and numbers that mean something."""

import importlib.util

import numpy as np

from _bench import finite, load, run


def test_solver_table_rows_per_method_and_the_rule_auto_follows(tmp_path):
    out = tmp_path / "solver.json"
    run("bench_solver.py", "--cells", "spot:lift:1,spot:lift:0.5", "--methods", "anderson,auto",
        "--json", out)
    rows = load(out)["rows"]
    # Below λ 1 auto runs Anderson bit for bit: its row is Anderson's and is not repeated.
    assert [(r["lambda"], r["method"], r["ran"]) for r in rows] == [
        (1.0, "anderson", "anderson"), (1.0, "auto", "lbfgs"), (0.5, "anderson", "anderson")]
    for r in rows:
        assert r["converged"] and r["claim_within_2_tolerance"], r
        assert finite(r["distance_to_reference"], r["energy"], r["wall_s"])
        assert r["distance_to_reference"] <= 2e-3
    # The plot needs matplotlib (bench/setup_peers.sh installs it); without it, no file.
    has_matplotlib = importlib.util.find_spec("matplotlib") is not None
    assert (tmp_path / "solver.png").exists() == has_matplotlib
    if has_matplotlib:
        assert (tmp_path / "solver.png").stat().st_size > 10_000
    import bench_solver
    assert "| spot lift λ 1 | 580 | auto (lbfgs) |" in bench_solver.markdown(load(out))


def test_d1_the_largest_eigenvalue_at_two_resolutions(tmp_path):
    out = tmp_path / "d1.json"
    run("bench_soft_modes.py", "d1", "--shapes", "spot", "--levels", "2", "--p1", "2", "--json", out)
    result = load(out)
    rows, apart = result["rows"], result["apart"]
    assert [r["mesh"] for r in rows] == ["spot 829", "spot split once"]
    # Splitting into four keeps the surface and quadruples the faces: about 4x the vertices.
    assert 3.5 < rows[1]["vertices"] / rows[0]["vertices"] < 4.5
    for r in rows:
        assert 0.9 < r["mu"] < 1.0 and r["products"] > 0 and r["reference_residual"] < 1e-6
        assert np.isclose(r["one_minus_mu_times_free"], (1 - r["mu"]) * r["free"])
    # The finer mesh bends more easily: its slowest mode is slower.
    assert rows[1]["mu"] > rows[0]["mu"]
    assert len(apart) == 1 and 0 < apart[0]["distance"] < 0.5


def test_d2_shares_lie_between_0_and_1_and_grow_with_p(tmp_path):
    out = tmp_path / "d2.json"
    run("bench_soft_modes.py", "d2", "--cells", "spot:lift", "--p", "25", "--json", out)
    rows = load(out)["rows"]
    assert [r["iterate"] for r in rows] == ["cold Anderson, 100 iterations",
                                           "Live (Anderson) when the mouse stops"]
    for r in rows:
        shares = [r["share_solution_modes"][p] for p in ("10", "25")]
        assert all(0.0 <= s <= 1.0 + 1e-9 for s in shares) and shares[0] <= shares[1] + 1e-9, r
        assert finite(r["distance"], *r["mu_at_iterate"])


def test_d3_every_variant_runs_and_lbfgs_reaches_the_reference(tmp_path):
    out = tmp_path / "d3.json"
    run("bench_soft_modes.py", "d3", "--cells", "spot:lift", "--budget", "400", "--json", out)
    rows = load(out)["rows"]
    assert [(r["variant"], r["window"]) for r in rows] == [
        ("positions", 5), ("damped", 5), ("rotations", 5), ("rotations", 20),
        ("judged after a plain step", 5), ("lbfgs", 5)]
    by_variant = {(r["variant"], r["window"]): r for r in rows}
    assert 0 < by_variant[("lbfgs", 5)]["global_steps"] <= 400
    assert 0 < by_variant[("positions", 5)]["global_steps"] <= 400
