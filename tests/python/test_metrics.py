"""ed.metrics: quality of a deformed mesh against its rest shape (docs/api.md)."""

import numpy as np
import pytest

import edgedeform as ed
from _meshes import DINO, PLANE, SPOT, diag, edge_strain, load, rigid
from _reference import ClassicARAP

KEYS = {"handle_error", "mean_edge_strain", "max_edge_strain", "mean_dihedral_change",
        "arap_energy"}


def _normal_angles(V, F):
    """Angle between the two face normals of every interior edge (my own reference)."""
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n /= np.linalg.norm(n, axis=1)[:, None]
    E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    E.sort(axis=1)
    face = np.tile(np.arange(len(F)), 3)
    order = np.lexsort((E[:, 1], E[:, 0]))
    E, face = E[order], face[order]
    same = np.all(E[1:] == E[:-1], axis=1)
    f1, f2 = face[:-1][same], face[1:][same]
    c = np.clip(np.einsum("ij,ij->i", n[f1], n[f2]), -1.0, 1.0)
    return np.arccos(c)


@pytest.mark.parametrize("name", [SPOT, PLANE])
def test_identity_is_all_zero(name):
    V, F = load(name)
    m = ed.metrics(V, F, V.copy())
    assert KEYS <= set(m)
    for k in KEYS:
        assert m[k] == pytest.approx(0.0, abs=1e-12), k


@pytest.mark.parametrize("name", [SPOT, DINO])
def test_rigid_motion_changes_nothing(name):
    V, F = load(name)
    X = rigid(V, degrees=70.0)(V)
    m = ed.metrics(V, F, X)
    assert m["max_edge_strain"] <= 1e-12
    assert m["mean_dihedral_change"] <= 1e-7
    assert m["arap_energy"] <= 1e-20 * diag(V) ** 2 * len(V)


def test_uniform_scale_strain_and_angles():
    V, F = load(SPOT)
    c = V.mean(axis=0)
    m = ed.metrics(V, F, c + 2.0 * (V - c))
    assert m["mean_edge_strain"] == pytest.approx(1.0, rel=1e-12)
    assert m["max_edge_strain"] == pytest.approx(1.0, rel=1e-12)
    assert m["mean_dihedral_change"] <= 1e-7
    assert m["arap_energy"] > 0


def test_strain_and_arap_energy_match_own_computation():
    V, F = load(SPOT)
    X = V + 0.01 * diag(V) * np.random.default_rng(3).standard_normal(V.shape)
    m = ed.metrics(V, F, X)
    s, _ = edge_strain(V, X, F)
    assert m["mean_edge_strain"] == pytest.approx(s.mean(), rel=1e-10)
    assert m["max_edge_strain"] == pytest.approx(s.max(), rel=1e-10)
    ref = ClassicARAP(V, F, fixed=np.array([0]))
    assert m["arap_energy"] == pytest.approx(ref.energy(X), rel=1e-8)


def test_dihedral_change_of_a_bumped_plane():
    """Flat rest shape: every convention of dihedral angle gives |change| = the angle
    between the two face normals, which the test computes itself."""
    V, F = load(PLANE)
    r2 = (V[:, 0] ** 2 + V[:, 2] ** 2) / 0.3 ** 2
    X = V.copy()
    X[:, 1] += 0.2 * np.exp(-r2)                         # plane is y = 0
    m = ed.metrics(V, F, X)
    expect = _normal_angles(X, F)
    assert m["mean_dihedral_change"] == pytest.approx(expect.mean(), rel=1e-9)
    assert m["mean_dihedral_change"] > 0.01


def test_handle_error():
    V, F = load(SPOT)
    handles = np.array([3, 50, 400])
    targets = V[handles] + [[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.3, 0.4]]
    m = ed.metrics(V, F, V.copy(), handles=handles, targets=targets)
    assert m["handle_error"] == pytest.approx(0.5, rel=1e-12)
    X = V.copy()
    X[handles] = targets
    assert ed.metrics(V, F, X, handles=handles, targets=targets)["handle_error"] == 0.0


def test_metrics_bad_input():
    V, F = load(SPOT)
    with pytest.raises(ValueError):
        ed.metrics(V, F, V[:-1])
    X = V.copy()
    X[0, 0] = np.nan
    with pytest.raises(ValueError):
        ed.metrics(V, F, X)
    with pytest.raises((ValueError, IndexError)):
        ed.metrics(V, F, V, handles=np.array([0, 1]), targets=V[:3])
