"""Unit tests of the demo's NumPy parts (no Blender): regions, per-region metrics, PNG I/O,
the metrics tables, the package side of the add-on check."""
import json
import os
import sys

import numpy as np
import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path[:0] = [os.path.join(REPO, "demo"), os.path.join(REPO, "blend_samples")]
import addon_check  # noqa: E402
import deform   # noqa: E402
import png      # noqa: E402
import regions  # noqa: E402
import tables   # noqa: E402

SCENES = regions.load_scenes()


def test_png_roundtrip(tmp_path):
    rng = np.random.default_rng(1)
    img = rng.integers(0, 256, (17, 23, 3), dtype=np.uint8)
    png.write_png(str(tmp_path / "a.png"), img)
    assert np.array_equal(png.read_png(str(tmp_path / "a.png")), img)


def test_bar_is_closed_manifold():
    V, F = regions.make_bar()
    edges, faces = deform.mesh_edges(F)
    assert len(V) - len(edges) + len(F) == 2          # sphere-like: Euler characteristic 2
    assert (faces[:, 1] >= 0).all()                   # every edge has two faces


@pytest.mark.parametrize("scene", SCENES, ids=[s["name"] for s in SCENES])
def test_scene_regions(scene):
    V, F = regions.scene_mesh(scene)
    assert np.isclose(np.abs(V).max(), 1.0)
    setup = regions.scene_setup(scene, V)
    h, st = setup["handle_index"], setup["static"]
    assert len(h) > 0 and len(st) > 0
    assert not np.intersect1d(h, st).size, "handles and static vertices must not overlap"
    assert len(np.unique(h)) == len(h)
    assert setup["targets"].shape == (len(h), 3)
    assert np.abs(setup["targets"] - V[h]).max() > 0.1, "the edit must move the handles"
    lam = setup["stiffness"]
    assert set(np.unique(lam)) <= {0.0, 0.5, 1.0}
    assert len(np.unique(lam)) >= 2, "a painted scene has at least two materials"
    mats = regions.material_regions(scene, V)
    painted = np.zeros(len(V), bool)
    for m in mats.values():
        assert not (painted & m["mask"]).any(), "material regions must not overlap"
        painted |= m["mask"]
        assert np.all(lam[m["mask"]] == m["value"])
    assert painted.all()


def test_identity_edit_targets_rest():
    V, _ = regions.make_bar()
    scene = {"handles": [{"name": "h", "region": {"sphere": {"center": [4, 0, 0], "radius": 1}},
                          "edit": {}}],
             "static": {"box": {"min": [None, None, None], "max": [-3.5, None, None]}},
             "stiffness": {"default": 0.5}}
    s = regions.scene_setup(scene, V)
    assert np.allclose(s["targets"], V[s["handle_index"]])


def test_edit_is_rotation_about_pivot():
    M = regions.edit_matrix({"rotate": [[[0, 0, 1], 90]], "translate": [1, 0, 0]}, [2, 0, 0])
    assert np.allclose(M[:3, :3] @ [1, 0, 0], [0, 1, 0])
    assert np.allclose(M[:3, 3], [3, 0, 0])


def test_region_metrics_zero_for_rigid_motion_and_positive_for_bending():
    V, F = regions.make_bar()
    R = regions.rotation([1, 2, 3], 40)
    mask = np.ones(len(V), bool)
    m = deform.region_metrics(V, F, V @ R.T + 0.3, mask)
    assert m["mean_edge_strain"] < 1e-12 and m["mean_dihedral_change"] < 1e-6
    X = V.copy()
    X[:, 2] += 0.05 * V[:, 0] ** 2
    m = deform.region_metrics(V, F, X, mask)
    assert m["mean_edge_strain"] > 1e-4 and m["mean_dihedral_change"] > 1e-4


def _dino_problem():
    import edgedeform as ed
    scene = next(s for s in SCENES if s["name"] == "dino")
    V, F = regions.scene_mesh(scene)
    setup = regions.scene_setup(scene, V)
    d = ed.Deformer(V, F, domain="edge")
    d.set_constraints(handles=setup["handle_index"], static=setup["static"], roi=None)
    d.set_stiffness(setup["stiffness"])
    return ed, V, F, setup, d


def test_addon_check_accepts_a_fixed_point_that_repels_plain_steps():
    """The demo's dino check failed (5.8e-3 apart) while the add-on was right: its result was
    the package's own fixed point, which plain steps flee. The verdict must accept that point
    and still refuse a point that is not a fixed point."""
    ed, V, F, setup, d = _dino_problem()
    tol = addon_check.CHECK_TOLERANCE
    r = d.solve(setup["targets"], max_iterations=3000, tolerance=tol, warm_start=False)
    assert r.converged
    fixed = np.asarray(r.positions)
    diag = np.linalg.norm(V.max(axis=0) - V.min(axis=0))
    # Why plain steps cannot judge it: from this very point they walk far away.
    fled = d.solve(setup["targets"], initial=fixed, max_iterations=3000, tolerance=tol,
                   warm_start=False, acceleration="none")
    assert np.abs(np.asarray(fled.positions) - fixed).max() > 1e-3 * diag
    assert addon_check.package_verdict(ed, V, F, setup, fixed, tol)["ok"]

    free = np.ones(len(V), bool)
    free[setup["handle_index"]] = free[setup["static"]] = False
    nudged = fixed.copy()
    nudged[free] += 1e-3 * diag * np.random.default_rng(0).standard_normal((free.sum(), 3))
    verdict = addon_check.package_verdict(ed, V, F, setup, nudged, tol)
    assert not verdict["ok"] and verdict["max_difference"] > verdict["limit"]


def test_scenes_json_is_the_source():
    with open(regions.SCENES_JSON) as f:
        names = [s["name"] for s in json.load(f)["scenes"]]
    assert names == ["dino", "plane", "head", "spot", "bar"]


def _cell(key, converged, iterations, warnings=()):
    return {"key": key, "domain": "edge", "lambda": 0.0, "converged": converged,
            "iterations": iterations, "warnings": list(warnings), "handle_error": 0.0,
            "mean_edge_strain": 0.1, "max_edge_strain": 0.2, "mean_dihedral_change": 0.01,
            "arap_energy": 1.0, "ms": 3.0}


def test_tables_show_iterations_and_name_unconverged_cells():
    sample = {"title": "t", "vertices": 3, "faces": 1, "handle_vertices": 1,
              "static_vertices": 1,
              "cells": [_cell("edge_0", True, 12), _cell("primal_0", False, 3000, ["capped"]),
                        _cell("primal_1", False, 50)]}
    md = tables.sample_markdown(sample)
    assert "| edge_0 | edge | 0 |" in md and "| 12 |" in md and "| 3000 |" in md
    assert md.count("**no**") == 2
    assert ("Not converged: primal_0 (stopped after 3000 iterations, with the solver's warning); "
            "primal_1 (stopped after 50 iterations, **without a warning**).") in md
    sample["cells"] = sample["cells"][:1]
    assert "Not converged" not in tables.sample_markdown(sample)
