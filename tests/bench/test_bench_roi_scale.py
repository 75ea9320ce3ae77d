"""bench_roi_scale.py on the small Spot split once: the region's row and its cut-out's, the
same free vertices in both, the outside at rest, memory from fresh processes, the table;
and the midpoint split itself."""

import numpy as np

from _bench import finite, load, run


def test_region_against_its_cut_out(tmp_path):
    out = tmp_path / "roi_scale.json"
    run("bench_roi_scale.py", "--mesh", "spot_low_resolution.obj", "--splits", "1", "--radius", "0.3",
        "--repeat", "1", "--out", out)
    (row,) = load(out)["rows"]
    big, small = row["region"], row["cut_out"]
    assert big["free_vertices"] == small["free_vertices"] > 0
    assert big["vertices"] > small["vertices"] and row["outside_bit_equal"] and row["outside_checked_solves"] == 2 * (1 + 1) + 2 * 1  # (--repeat 1: two timed Deformers, two radius steps)
    for r in (big, small):
        assert finite(r["bind_ms"], r["ms_per_it"], r["tick_ms"], r["peak_mb"]) and r["peak_mb"] > r["loaded_mb"] > 0
    assert finite(big["radius_grow_ms"], big["radius_shrink_ms"])
    import bench_roi_scale
    assert "| bind (set_constraints + factor), ms |" in bench_roi_scale.markdown(load(out))


def test_split_in_four_keeps_the_surface():
    from subdivide import split_in_four
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    V2, F2 = split_in_four(V, F)
    assert len(V2) == 4 + 6 and len(F2) == 16
    assert np.allclose(V2[:4], V)
    area = lambda V, F: 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1).sum()
    assert np.isclose(area(V2, F2), area(V, F))
    edges = np.sort(np.vstack([F2[:, [0, 1]], F2[:, [1, 2]], F2[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert (counts == 2).all()   # still closed and manifold
