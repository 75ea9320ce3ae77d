"""The package surface of docs/api.md: build info, defaults, result fields, warm start."""

import numpy as np
import pytest

import edgedeform as ed
from _meshes import SPOT, diag, lift, load
from _run import deformer


def test_build_info():
    info = ed.build_info()
    assert info["solver"] in ("cholmod-supernodal", "eigen-simplicial-ldlt")
    assert isinstance(info["openmp"], bool) and info["threads"] >= 1
    for key in ("version", "eigen", "compiler"):
        assert isinstance(info[key], str) and info[key]
    assert issubclass(ed.FactorizationError, RuntimeError)


@pytest.mark.parametrize("domain", ["edge", "primal"])
def test_read_only_sizes_and_default_stiffness(domain):
    V, F = load(SPOT)
    d = ed.Deformer(V, F, domain=domain)
    assert (d.n_vertices, d.n_faces, d.domain) == (len(V), len(F), domain)
    assert np.all(np.asarray(d.node_stiffness()) == 0.5)       # before set_stiffness
    with pytest.raises(AttributeError):
        d.n_vertices = 3


def test_result_fields_and_factorization_reuse():
    V, F = load(SPOT)
    handles, static, targets = lift(V, amount=0.1)
    d = deformer(V, F, "edge", 0.5, handles, static)
    r = d.solve(targets, max_iterations=6, tolerance=0.0)
    assert r.iterations == 6 and len(r.energies) == 6
    assert r.initial_energy is None and r.converged is False
    assert r.factor_ms > 0 and r.local_ms > 0 and r.solve_ms > 0 and r.rhs_ms >= 0
    assert isinstance(r.warnings, list)
    assert r.free_vertices == len(V) - len(handles) - len(static)
    assert r.active_nodes <= d.n_nodes
    r2 = d.solve(targets + 0.01, max_iterations=2)
    assert r2.factor_ms == 0                      # same constraints and stiffness: reused
    d.set_stiffness(0.7)
    assert d.solve(targets, max_iterations=1).factor_ms > 0


@pytest.mark.parametrize("domain", ["edge", "primal"])
def test_warm_start_continues_the_iteration(domain):
    """Five iterations, then five more warm-started, equal ten in one call (the rigid-
    convergence test counts iterations this way)."""
    V, F = load(SPOT)
    handles, static, targets = lift(V, amount=0.2)
    a = deformer(V, F, domain, 0.5, handles, static)
    ra = a.solve(targets, max_iterations=10, tolerance=0.0, warm_start=False)
    b = deformer(V, F, domain, 0.5, handles, static)
    b.solve(targets, max_iterations=5, tolerance=0.0, warm_start=False)
    rb = b.solve(targets, max_iterations=5, tolerance=0.0, warm_start=True)
    np.testing.assert_allclose(rb.positions, ra.positions, rtol=0, atol=1e-12 * diag(V))
    np.testing.assert_allclose(rb.energies, ra.energies[5:], rtol=1e-10)
    # and warm_start=False really starts over
    rc = b.solve(targets, max_iterations=10, tolerance=0.0, warm_start=False)
    np.testing.assert_allclose(rc.positions, ra.positions, rtol=0, atol=1e-12 * diag(V))


@pytest.mark.parametrize("domain", ["edge", "primal"])
def test_cold_solve_does_not_depend_on_earlier_solves(domain):
    """warm_start=False gives bit-identical positions on a fresh Deformer and on one that
    has a long warm-started history (the add-on's solve() relies on it)."""
    V, F = load("cgal_plane.off")
    h = np.flatnonzero(V[:, 0] > 0.55)
    s = np.flatnonzero(V[:, 0] < -0.55)

    def turned(angle):
        c, si = np.cos(angle), np.sin(angle)
        R = np.array([[c, -si, 0], [si, c, 0], [0, 0, 1]])
        return V[h] @ R.T + [0, 0.1, 0]

    used = ed.Deformer(V, F, domain=domain)
    used.set_constraints(handles=h, static=s)
    for k in range(20):
        used.solve(turned(0.05 * k), max_iterations=2)
    fresh = ed.Deformer(V, F, domain=domain)
    fresh.set_constraints(handles=h, static=s)
    a = used.solve(turned(0.6), max_iterations=20, warm_start=False).positions
    b = fresh.solve(turned(0.6), max_iterations=20, warm_start=False).positions
    assert np.array_equal(a, b)
    assert np.abs(a - V).max() > 0.1  # it did deform


def test_threads_sharing_a_deformer_take_turns():
    """The GIL is released while solving: concurrent calls must not corrupt the solver."""
    import threading
    V, F = load(SPOT)
    handles, static, targets = lift(V)
    d = deformer(V, F, "edge", 0.5, handles, static)
    expected = d.solve(targets, max_iterations=5, warm_start=False).positions
    results, errors = [], []

    def work():
        try:
            for _ in range(5):
                results.append(d.solve(targets, max_iterations=5, warm_start=False).positions)
        except Exception as exc:  # pragma: no cover - reported below
            errors.append(exc)

    threads = [threading.Thread(target=work) for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    assert len(results) == 15
    assert all(np.array_equal(r, expected) for r in results)
