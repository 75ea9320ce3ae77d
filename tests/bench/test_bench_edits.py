"""bench/edits.py: the edits do what their names say, the meshes are the originals."""

import hashlib
import re

import numpy as np
import pytest

from _bench import BENCH

import edits  # noqa: E402


def test_every_compressed_mesh_unpacks_to_the_file_its_sources_row_names():
    table = (BENCH / "meshes" / "SOURCES.md").read_text()
    packed = sorted(p.name[:-3] for p in (BENCH / "meshes").glob("*.xz"))
    assert packed, "no benchmark meshes in bench/meshes"
    for name in packed:
        row = next(line for line in table.splitlines() if line.startswith(f"| {name} |"))
        digest = re.findall(r"\| ([0-9a-f]{12}) \|$", row)[0]
        assert hashlib.sha256(edits.mesh_path(name).read_bytes()).hexdigest()[:12] == digest


def test_a_missing_mesh_is_a_clear_error():
    with pytest.raises(SystemExit, match="no_such.obj is in none of"):
        edits.mesh_path("no_such.obj")


def test_the_turns_rotate_the_handle_about_its_centroid_by_their_angle():
    from edgedeform.mesh_files import read_mesh
    V, _ = read_mesh(str(edits.mesh_path("cgal_dino.off")))
    for name, degrees, about in (("twist", edits.TWIST_DEGREES, 0), ("bend", edits.BEND_DEGREES, 1)):
        handles, static, targets, ax = edits.EDITS[name](V)
        axis = (ax + about) % 3
        before = V[handles] - V[handles].mean(axis=0)
        after = targets - targets.mean(axis=0)
        i, j = (axis + 1) % 3, (axis + 2) % 3
        angles = np.degrees(np.arctan2(after[:, j], after[:, i]) - np.arctan2(before[:, j], before[:, i]))
        spread = np.hypot(before[:, i], before[:, j]) > 1e-9 * edits.diagonal(V)
        angles = (angles[spread] + 180.0) % 360.0 - 180.0
        assert np.allclose(angles, degrees, atol=1e-9), name
        assert np.allclose(after[:, axis], before[:, axis])
        assert len(static) and not set(handles) & set(static)
    assert edits.TWIST_DEGREES == 90.0   # docs/decisions/0009-one-definition-per-edit.md


def test_lift_raises_the_handle_by_a_quarter_of_the_diagonal():
    from edgedeform.mesh_files import read_mesh
    V, _ = read_mesh(str(edits.mesh_path("spot_low_resolution.obj")))
    handles, _, targets, ax = edits.lift_edit(V)
    moved = targets - V[handles]
    assert np.allclose(moved[:, ax], 0.25 * edits.diagonal(V))
    assert np.allclose(np.delete(moved, ax, axis=1), 0.0)


def test_the_methods_are_the_builds_own():
    import edgedeform as ed
    methods = edits.accelerations(ed)
    assert "none" in methods and "anderson" in methods
    with pytest.raises(SystemExit, match="unknown method"):
        edits.method_list(ed, "anderson,no_such_method")
    assert edits.method_list(ed, "") == methods
