"""The smaller bench scripts on small inputs: the sample scenes, the pytest counts, the
same-positions check, the live-settle replay, the instruction counts and the region seam."""

import shutil
import types

import numpy as np
import pytest

from _bench import finite, load, run


def test_samples_one_scene_every_domain_and_lambda(tmp_path):
    out = tmp_path / "samples.json"
    run("bench_samples.py", "--scenes", "bar", "--json", out)
    rows = load(out)["rows"]
    assert {(r["domain"], r["lambda"]) for r in rows} == {
        (d, lam) for d in ("edge", "primal") for lam in (0.0, 0.25, 0.5, 0.75, 1.0)}
    for r in rows:
        assert r["scene"] == "bar" and r["finite"] and (r["converged"] or r["warned"])
        assert 0 < r["iterations"] <= 2000 and finite(r["distance_estimate"], r["bbox_ratio"])
    import bench_samples
    assert "| bar | 770 |" in bench_samples.markdown(load(out))


def test_counts_kept_and_rendered(tmp_path):
    counts = [{"test": "rigid", "mesh": "m.obj", "domain": "edge", "lambda": 1.0, "iterations": 45, "note": ""},
              {"test": "lift", "mesh": "m.obj", "domain": "primal", "lambda": 0.0, "iterations": None, "note": ""}]
    src, out = tmp_path / "counts.json", tmp_path / "kept.json"
    src.write_text(__import__("json").dumps(counts))
    run("counts_md.py", src, out)
    kept = load(out)
    assert kept["counts"] == counts and kept["machine"]["date"]
    import counts_md
    text = counts_md.markdown(kept)
    assert "| m.obj | 45 |" in text and "| m.obj | not conv. |" in text


def test_same_positions_agrees_with_itself_and_catches_a_change(tmp_path):
    saved = tmp_path / "saved.npz"
    run("same_positions.py", "save", saved, "--meshes", "spot_low_resolution.obj")
    out = run("same_positions.py", "compare", saved, "--meshes", "spot_low_resolution.obj")
    assert "largest relative difference" in out
    moved = dict(np.load(saved))
    key = sorted(moved)[0]
    moved[key] = moved[key] * (1 + 1e-6)
    np.savez(tmp_path / "moved.npz", **moved)
    with pytest.raises(AssertionError, match="over the limit"):
        run("same_positions.py", "compare", tmp_path / "moved.npz", "--meshes", "spot_low_resolution.obj")


def test_live_settle_replay_on_spot(tmp_path):
    out = tmp_path / "settle.json"
    run("bench_live_settle.py", "--mesh", "spot", "--lam", "0.5,1", "--drag-ticks", "5",
        "--methods", "auto,anderson", "--claims", "checked,unchecked", "--json", out)
    rows = load(out)["rows"]
    assert [(r["lambda"], r["method"], r["claims"]) for r in rows] == [
        (lam, m, c) for lam in (0.5, 1.0) for m in ("auto", "anderson") for c in ("checked", "unchecked")]
    assert [r["ran"] for r in rows] == ["anderson"] * 4 + ["lbfgs", "lbfgs", "anderson", "anderson"]
    for row in rows:
        assert row["mesh"] == "spot" and row["vertices"] == 829 and row["drag"]["ticks"] == 5
        s = row["settle"]
        assert s["converged"] and s["ticks"] > 0 and s["iterations"] > 0
        assert finite(s["core_ms"], s["wall_ms"], s["estimate"], s["distance"], s["longest_tick_ms"])
        assert s["distance"] < 2e-3
    checked, unchecked = rows[:2]
    # The add-on's policy checks the settle's claim; the old one never does.
    assert checked["settle"]["claim_checks"] >= 1
    assert unchecked["settle"]["claim_checks"] == 0
    import bench_live_settle
    assert "| spot | 829 | edge | 1 | auto (lbfgs) | checked |" in bench_live_settle.markdown(load(out))


def test_live_settle_ticks_ask_for_the_method():
    """Each of a tick's solves names the row's method."""
    import bench_live_settle

    class Recording:
        def __init__(self):
            self.methods = []

        def solve(self, targets, acceleration, **options):
            self.methods.append(acceleration)
            return types.SimpleNamespace(
                positions=targets, converged=False, distance_estimate=1.0, iterations=1,
                local_ms=0.0, rhs_ms=0.0, solve_ms=0.0, claim_checks=0, refused_claims=0,
                method=acceleration)

    d = Recording()
    budget = bench_live_settle.settle.Settle(limit=10 ** 9)
    bench_live_settle.tick(d, np.zeros((1, 3)), budget, moving=True, method="none")
    bench_live_settle.tick(d, np.zeros((1, 3)), budget, method="none")
    assert d.methods and set(d.methods) == {"none"}


@pytest.mark.skipif(shutil.which("valgrind") is None, reason="valgrind is not installed")
def test_callgrind_handle_change_on_spot(tmp_path):
    out = tmp_path / "callgrind.json"
    run("callgrind_handle_change.py", "--meshes", "spot_low_resolution.obj", "--skip-final",
        "--json", out, timeout=900)
    (row,) = load(out)["rows"]
    assert row["mesh"] == "spot_low_resolution.obj"
    assert finite(row["fresh_M"], row["add_M"], row["remove_M"]) and row["fresh_M"] > 0
    assert 0 < row["add_vs_fresh"] < 1 and 0 < row["remove_vs_fresh"] < 1
    import callgrind_handle_change
    assert "| spot_low_resolution.obj |" in callgrind_handle_change.markdown(load(out))


def test_roi_seam_rows_and_the_bend_measure(tmp_path):
    """bench_roi_seam.py on the small Spot: a row per radius and band; a region that holds
    every free vertex matches the whole mesh, with or without a band (its λ is then unchanged
    wherever a vertex is); the dihedral measure is 0 at rest and sees a fold."""
    out = tmp_path / "seam.json"
    run("bench_roi_seam.py", "--cells", "spot:1", "--radii", "0.35,10", "--bands", "0,0.5", "--out", out)
    small, banded, everything, everything_banded = load(out)["rows"]
    assert [r["band"] for r in (small, banded, everything, everything_banded)] == [0, 0.5, 0, 0.5]
    assert small["free_region"] < small["free_whole"] and small["border_edges"] > 0
    assert small["converged_region"] and small["converged_whole"]
    assert finite(small["border_bend_region_deg"], small["distance_to_whole"]) and small["distance_to_whole"] > 1e-3
    assert banded["free_region"] == small["free_region"]
    assert banded["border_bend_region_deg"] != small["border_bend_region_deg"]
    for row in (everything, everything_banded):
        assert row["free_region"] == row["free_whole"] and row["border_edges"] == 0
        assert row["distance_to_whole"] < 1e-12
    import bench_roi_seam
    assert "| spot lift λ 1 | 0.35 | 0.5 |" in bench_roi_seam.markdown(load(out))
    # two triangles folded by 90 degrees about their shared edge
    F = np.array([[0, 1, 2], [1, 0, 3]])
    flat = np.array([[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0]], float)
    folded = flat.copy()
    folded[3] = [0.5, 0, 1]
    edges, faces = bench_roi_seam.interior_edges(F)
    assert edges.tolist() == [[0, 1]]
    assert bench_roi_seam.dihedral_degrees(flat, F, faces)[0] == pytest.approx(0.0, abs=1e-9)
    assert bench_roi_seam.dihedral_degrees(folded, F, faces)[0] == pytest.approx(90.0)


def test_roi_seam_band_profile():
    """The band's λ: unchanged up to r(1 − b) from the nearest handle, 0 from r on, strictly
    between inside the band and falling with the distance."""
    import bench_roi_seam
    V = np.array([[0, 0, 0], [0.4, 0, 0], [0.5, 0, 0], [0.75, 0, 0], [0.9, 0, 0], [1.0, 0, 0], [1.5, 0, 0]], float)
    lam, d = bench_roi_seam.band_lambda(V, [0], 0.8, 1.0, 0.5)
    assert d.tolist() == pytest.approx([0, 0.4, 0.5, 0.75, 0.9, 1.0, 1.5])
    assert lam[:3].tolist() == [0.8, 0.8, 0.8] and lam[5:].tolist() == [0.0, 0.0]
    assert 0.8 > lam[3] > lam[4] > 0.0
    assert lam[3] == pytest.approx(0.8 * 0.5 ** 2 * (3 - 2 * 0.5))
