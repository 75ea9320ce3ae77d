"""Unwelded seams (docs/api.md): coincident vertices in pieces that move apart are named in a
warning; weld=True deforms the copies together and writes every copy back."""

import json
import subprocess
import sys

import numpy as np
import pytest

import edgedeform as ed
from _run import deformer

NX, NY = 9, 5


def grid():
    i, j = np.meshgrid(np.arange(NX), np.arange(NY))
    V = np.stack([i.ravel() / (NX - 1), j.ravel() / (NY - 1), np.zeros(NX * NY)], axis=1)
    F = []
    for b in range(NY - 1):
        for a in range(NX - 1):
            p, q, r, s = b * NX + a, b * NX + a + 1, (b + 1) * NX + a, (b + 1) * NX + a + 1
            F += [[p, q, s], [p, s, r]]
    return V, np.array(F)


def split_grid():
    """The grid cut along its middle column: the right half's faces use appended copies of
    that column's vertices, so the halves are separate pieces meeting at a seam."""
    V, F = grid()
    mid = NX // 2
    column = np.arange(NY) * NX + mid
    copy_of = {int(v): len(V) + k for k, v in enumerate(column)}
    right = (V[F, 0] > 0.5 + 1e-12).any(axis=1)
    F2 = F.copy()
    F2[right] = np.vectorize(lambda v: copy_of.get(int(v), int(v)))(F[right])
    return np.vstack([V, V[column]]), F2, column


def lift_setup(V):
    static = np.flatnonzero(V[:, 0] <= 0.0)
    handles = np.flatnonzero(V[:, 0] >= 1.0)
    targets = V[handles] + [0.0, 0.0, 0.4]
    return handles, static, targets


@pytest.mark.parametrize("domain", ["edge", "primal"])
def test_tearing_seam_is_named_in_a_warning(domain):
    V, F, column = split_grid()
    handles, static, targets = lift_setup(V)
    d = deformer(V, F, domain, 0.5, handles, static)
    r = d.solve(targets, max_iterations=20)
    X = np.asarray(r.positions)
    gap = np.linalg.norm(X[column] - X[len(V) - NY:], axis=1)
    assert gap.max() > 0.05  # the seam really opened
    seam = [w for w in r.warnings if w.startswith("unwelded seam")]
    assert len(seam) == 1, r.warnings
    assert seam[0].startswith(f"unwelded seam: {2 * NY} coincident vertices ({NY} shared positions, "
                              f"in 2 connected pieces) moved apart, by up to ")
    assert "weld=True" in seam[0]


def test_seam_that_stays_closed_gives_no_warning():
    """Control: the same split mesh moved rigidly as a whole keeps its copies together."""
    V, F, _ = split_grid()
    handles = np.flatnonzero((V[:, 0] <= 0.0) | (V[:, 0] >= 1.0))
    d = deformer(V, F, "edge", 0.5, handles)
    r = d.solve(V[handles] + [0.1, 0.2, 0.3], max_iterations=20)
    assert not [w for w in r.warnings if "seam" in w]


@pytest.mark.parametrize("domain", ["edge", "primal"])
def test_weld_deforms_copies_together_like_the_uncut_mesh(domain):
    V, F, column = split_grid()
    handles, static, targets = lift_setup(V)
    d = ed.Deformer(V, F, domain=domain, weld=True)
    assert d.welded_copies == NY and d.n_vertices == len(V)
    d.set_constraints(handles=handles, static=static)
    lam = np.full(len(V), 0.5)
    d.set_stiffness(lam)
    r = d.solve(targets, max_iterations=20)
    X = np.asarray(r.positions)
    assert X.shape == V.shape
    np.testing.assert_array_equal(X[column], X[len(V) - NY:])  # every copy written back
    assert not [w for w in r.warnings if "seam" in w]
    np.testing.assert_array_equal(X[handles], targets)
    # The welded solve is the solve of the uncut grid (whose vertices it numbers the same).
    G, FG = grid()
    h0, s0, t0 = lift_setup(G)
    ref = deformer(G, FG, domain, 0.5, h0, s0).solve(t0, max_iterations=20)
    np.testing.assert_allclose(X[:len(G)], np.asarray(ref.positions), rtol=0, atol=1e-12)
    # initial and energy take rows of the mesh as given
    again = d.solve(targets, max_iterations=3, initial=X)
    assert np.isfinite(d.energy(np.asarray(again.positions)))


def test_weld_checks_copies_against_each_other():
    V, F, column = split_grid()
    copy = len(V) - NY
    d = ed.Deformer(V, F, weld=True)
    with pytest.raises(ValueError, match=rf"vertices \[{column[0]}\] are welded copies of both"):
        d.set_constraints(handles=[column[0]], static=[copy])
    d.set_constraints(handles=[column[0], copy], static=[0])
    with pytest.raises(ValueError, match=rf"handles {column[0]} and {copy} are copies of one welded "
                                         r"vertex but have different targets"):
        d.solve([[0.5, 0.0, 0.1], [0.5, 0.0, 0.2]])
    r = d.solve([[0.5, 0.0, 0.1], [0.5, 0.0, 0.1]], max_iterations=5)
    assert np.array_equal(np.asarray(r.positions)[[column[0], copy]], [[0.5, 0.0, 0.1]] * 2)
    with pytest.raises(ValueError, match=r"targets has shape \(1, 3\)"):
        d.solve([[0.5, 0.0, 0.1]])
    with pytest.raises(ValueError, match=r"initial has shape"):
        d.solve([[0.5, 0.0, 0.1]] * 2, initial=V[:-1])


def test_weld_stiffness_is_the_mean_of_the_copies():
    V, F, column = split_grid()
    d = ed.Deformer(V, F, weld=True)
    lam = np.full(len(V), 0.5)
    lam[column[0]], lam[len(V) - NY] = 0.2, 0.6
    d.set_stiffness(lam)
    # The welded mesh numbers vertices by their first copy: column[0] keeps its index, with
    # lambda (0.2 + 0.6) / 2 = 0.4; each edge node at it averages that with a 0.5.
    touching = [value for (a, b), value in zip(d.node_vertices(), d.node_stiffness())
                if column[0] in (a, b)]
    assert len(touching) == 4 and np.allclose(touching, 0.45, rtol=0, atol=1e-15)


def test_cli_warns_without_weld_and_welds_with_it(tmp_path):
    V, F, column = split_grid()
    mesh = tmp_path / "split.obj"
    mesh.write_text("".join(f"v {float(x)!r} {float(y)!r} {float(z)!r}\n" for x, y, z in V) +
                    "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F))
    handles, static, targets = lift_setup(V)
    c = tmp_path / "c.json"
    c.write_text(json.dumps({"handles": handles.tolist(), "static": static.tolist(),
                             "handle_targets": targets.tolist()}))

    def run(*extra):
        out = tmp_path / "out.obj"
        p = subprocess.run([sys.executable, "-m", "edgedeform", "deform", str(mesh), "--constraints",
                            str(c), "--out", str(out), *extra], capture_output=True, text=True,
                           timeout=120)
        assert p.returncode == 0, p.stderr
        X = np.array([ln.split()[1:4] for ln in out.read_text().splitlines() if ln.startswith("v ")],
                     dtype=float)
        return p, json.loads(p.stdout), X

    p, report, X = run()
    assert "edgedeform: warning: unwelded seam: 10 coincident vertices" in p.stderr
    assert report["welded_copies"] == 0 and np.abs(X[column] - X[len(V) - NY:]).max() > 0.05
    p, report, X = run("--weld")
    assert "seam" not in p.stderr and report["welded_copies"] == NY
    np.testing.assert_array_equal(X[column], X[len(V) - NY:])
