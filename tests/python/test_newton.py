"""Newton-Krylov (acceleration="newton"): the analytic Jacobian, the fixed point it reaches,
its claims, its safeguards and its degenerate coarse spaces (docs/design.md §4, "Reaching the
fixed point")."""

import os
import subprocess
import sys

import numpy as np
import pytest

import edgedeform as ed
from _meshes import ALL, DINO, PEAKS, PLANE, SPOT, diag, lift, load, rotation, up_axis

DOMAINS = ("edge", "primal")


def twist(V, degrees=60.0):
    """The top 10 % turned about the height axis through its centroid, the lowest 20 % static."""
    ax = up_axis(V)
    height = V[:, ax]
    static = np.flatnonzero(height <= np.quantile(height, 0.2))
    handles = np.flatnonzero(height >= np.quantile(height, 0.9))
    axis = np.zeros(3)
    axis[ax] = 1.0
    pivot = V[handles].mean(axis=0)
    return handles, static, (V[handles] - pivot) @ rotation(axis, degrees).T + pivot
LAMBDAS = (0.0, 0.5, 1.0)


def _deformer(name, domain, lam, edit=lift, **constraints):
    V, F = load(name)
    h, s, t = edit(V)
    d = ed.Deformer(V, F, domain=domain)
    d.set_constraints(h, s, **constraints)
    d.set_stiffness(lam)
    return d, V, F, t


def _reference(d, t):
    r = d.solve(t, max_iterations=20000, tolerance=1e-10, acceleration="anderson", warm_start=False)
    assert r.residuals[-1] < 1e-9, "the reference did not reach a residual of 1e-10"
    return r.positions


def _flat(dX):
    return dX.T.reshape(-1)


@pytest.mark.parametrize("domain", DOMAINS)
@pytest.mark.parametrize("lam", LAMBDAS + ("painted",))
def test_analytic_jacobian_matches_central_differences(domain, lam):
    V, F = load(SPOT)
    h, s, t = lift(V)
    d = ed.Deformer(V, F, domain=domain)
    d.set_constraints(h, s)
    d.set_stiffness(np.linspace(0.0, 1.0, len(V)) if lam == "painted" else lam)
    X = d.solve(t, max_iterations=15, acceleration="none").positions  # a deformed, unconverged point
    free = np.array(d.free_vertices)
    dX = np.random.default_rng(3).standard_normal((len(free), 3))
    J = d._jacobian(X, dX)
    eps = 1e-6 * diag(V)  # small against the shape, large against round-off (1e-16 diag)
    Xp, Xm = X.copy(), X.copy()
    Xp[free] += eps * dX
    Xm[free] -= eps * dX
    fd = (d._one_step(Xp) - d._one_step(Xm)) / (2 * eps)
    assert np.linalg.norm(J - fd) <= 1e-5 * np.linalg.norm(fd)


@pytest.mark.parametrize("domain", DOMAINS)
def test_local_fit_and_global_step_are_the_two_halves_of_one_step(domain):
    """_global_step(X, *_local_fit(X)) is G(X) bit for bit; other rotations give another
    shape; a wrong count or a non-finite rotation is refused with the count named."""
    d, V, F, t = _deformer(SPOT, domain, 0.5)
    X = d.solve(t, max_iterations=15, acceleration="none").positions
    R, scale = d._local_fit(X)
    assert R.shape == (len(scale), 3, 3) and np.abs(np.linalg.det(R) - 1).max() < 1e-9
    assert np.array_equal(d._global_step(X, R, scale), d._one_step(X))
    turned = R.copy()
    turned[:, :, [0, 1]] = turned[:, :, [1, 0]]   # (not rotations: the step must still follow)
    assert np.abs(d._global_step(X, turned, scale) - d._one_step(X)).max() > 1e-3 * diag(V)
    with pytest.raises(ValueError, match=f"expected {len(scale)} rotations"):
        d._global_step(X, R[:-1], scale[:-1])
    with pytest.raises(ValueError, match=f"expected {len(scale)} rotations and scales"):
        d._global_step(X, R, scale[:-1])
    with pytest.raises(ValueError, match="rotations must be a"):
        d._global_step(X, R[:, :2, :], scale)
    bad = R.copy()
    bad[3, 0, 0] = np.nan
    with pytest.raises(ValueError, match="finite"):
        d._global_step(X, bad, scale)


def test_analytic_jacobian_with_clamped_scales():
    # lambda 0 and a strong squash: some node scales sit on their lower bound (local_step.h)
    V, F = load(SPOT)
    h, s, t = lift(V, amount=-0.6)
    d = ed.Deformer(V, F, domain="primal")
    d.set_constraints(h, s)
    d.set_stiffness(0.0)
    X = d.solve(t, max_iterations=20, acceleration="none").positions
    free = np.array(d.free_vertices)
    dX = np.random.default_rng(4).standard_normal((len(free), 3))
    eps = 1e-7 * diag(V)
    Xp, Xm = X.copy(), X.copy()
    Xp[free] += eps * dX
    Xm[free] -= eps * dX
    fd = (d._one_step(Xp) - d._one_step(Xm)) / (2 * eps)
    assert np.linalg.norm(d._jacobian(X, dX) - fd) <= 1e-4 * np.linalg.norm(fd)


def test_newton_operator_is_symmetric_at_lambda_1():
    # K = A (I - J_G) is the energy's Hessian (halved) there
    d, V, F, t = _deformer(SPOT, "edge", 1.0)
    X = d.solve(t, max_iterations=30).positions
    rng = np.random.default_rng(5)
    u, v = rng.standard_normal((2, len(d.free_vertices), 3))
    Ku, Kv = d._jacobian(X, u, True), d._jacobian(X, v, True)
    assert np.sum(v * Ku) == pytest.approx(np.sum(u * Kv), rel=1e-9)
    d.set_stiffness(0.5)  # and not below lambda 1: G is not a gradient map
    Ku, Kv = d._jacobian(X, u, True), d._jacobian(X, v, True)
    assert abs(np.sum(v * Ku) - np.sum(u * Kv)) > 1e-6 * abs(np.sum(v * Ku))


@pytest.mark.parametrize("blend", (0, 3))
def test_coarse_operator_is_the_galerkin_product(blend):
    d, V, F, t = _deformer(SPOT, "edge", 0.5)
    X = d.solve(t, max_iterations=20).positions
    free = np.array(d.free_vertices)
    nf = len(free)
    ur, uc, uv, ushape = d._coarse_basis_coo(8, blend)
    U = np.zeros(ushape)
    np.add.at(U, (ur, uc), uv)
    assert U.shape[1] > 0
    KU = np.column_stack([_flat(d._jacobian(X, U[:, j].reshape(3, nf).T.copy(), True)) for j in range(U.shape[1])])
    dense = U.T @ KU
    cr, cc, cv, cshape = d._coarse_operator_coo(X, 8, blend)
    C = np.zeros(cshape)
    np.add.at(C, (cr, cc), cv)
    assert np.abs(C - dense).max() <= 1e-9 * np.abs(dense).max()


# The small test meshes in every cell; the dinosaur (3.9k vertices) where its reference is
# quick (its lambda 0 references take minutes).
CELLS = [(name, lam) for name in (PLANE, SPOT, PEAKS) for lam in LAMBDAS] + [(DINO, 0.5), (DINO, 1.0)]


@pytest.mark.parametrize("name,lam", CELLS)
@pytest.mark.parametrize("domain", DOMAINS)
@pytest.mark.parametrize("edit", (lift, twist), ids=("lift", "twist"))
def test_newton_reaches_the_plain_fixed_point(name, domain, lam, edit):
    d, V, F, t = _deformer(name, domain, lam, edit)
    tol = 1e-3
    r = d.solve(t, tolerance=tol, acceleration="newton", warm_start=False)
    if r.converged and lam == 0.0:
        # lambda = 0 has no single fixed point (plain and Anderson runs from the same start
        # end 1.7e-3 diag apart on the peaks twist): the claimed point must be one, i.e. a
        # plain step from it moves no vertex by more than the tolerance.
        moved = np.linalg.norm(d._one_step(r.positions) - r.positions[d.free_vertices], axis=1).max() / diag(V)
        assert moved <= tol, f"claimed converged but a plain step moves {moved:.1e}"
    elif r.converged:
        dist = np.linalg.norm(r.positions - _reference(d, t), axis=1).max() / diag(V)
        assert dist <= 2 * tol, f"claimed converged {r.distance_estimate:.1e} but {dist:.1e} away"
    else:  # never a silent wrong claim: it says why
        assert any("not converged" in w for w in r.warnings)
    assert len(r.energies) == len(r.residuals) == r.iterations
    if lam == 1.0:
        assert np.all(np.diff(r.energies) <= 1e-12 * abs(r.energies[0]))  # monotone: Armijo on E


def test_energy_is_monotone_at_lambda_1_and_result_never_worse_than_its_start():
    d, V, F, t = _deformer(DINO, "edge", 1.0)
    for max_iterations in (3, 8, 20):
        r = d.solve(t, max_iterations=max_iterations, acceleration="newton", warm_start=False)
        assert np.all(np.diff(r.energies) <= 1e-12 * abs(r.energies[0]))
        assert r.energies[-1] == pytest.approx(d.energy(r.positions), rel=1e-9)


def test_one_krylov_product_still_gives_a_result_never_worse_than_the_best_iterate():
    # With one product per step the Newton direction is poor and line searches fail: the
    # solve falls back to plain steps and ends no worse than the best point it held.
    d, V, F, t = _deformer(PEAKS, "edge", 0.5, twist)
    r = d.solve(t, max_iterations=60, acceleration="newton", krylov_iterations=1, warm_start=False)
    assert np.isfinite(r.positions).all()
    assert r.iterations <= 60
    assert r.residuals[-1] <= 10 * min(r.residuals)
    assert r.converged or any("not converged" in w for w in r.warnings)


@pytest.mark.parametrize("blend", (0, 8))
@pytest.mark.parametrize("case", ("small_region", "roi", "components", "no_coarse"))
def test_degenerate_coarse_spaces_fall_back_cleanly(case, blend):
    V, F = load(SPOT)
    h, s, t = lift(V)
    roi = None
    if case == "small_region":  # 10 free vertices: fewer than 16 per patch, no coarse space
        free = np.setdiff1d(np.arange(len(V)), np.concatenate([h, s]))[:10]
        roi = np.concatenate([h, s, free])
    elif case == "roi":
        roi = np.flatnonzero(V[:, up_axis(V)] >= np.quantile(V[:, up_axis(V)], 0.5))
    elif case == "components":  # two copies side by side: two free components
        V = np.vstack([V, V + [2 * diag(V), 0.0, 0.0]])
        F = np.vstack([F, F + len(V) // 2])
        h, s, t = lift(V)
    d = ed.Deformer(V, F, domain="edge")
    d.set_constraints(h, s, roi)
    d.set_stiffness(0.5)
    r = d.solve(t, acceleration="newton", coarse_patches=0 if case == "no_coarse" else 400, coarse_blend=blend)
    assert np.isfinite(r.positions).all()
    if r.converged:
        assert np.linalg.norm(r.positions - _reference(d, t), axis=1).max() / diag(V) <= 2e-3
    else:
        assert any("not converged" in w for w in r.warnings)
    if case in ("small_region", "no_coarse"):
        assert r.coarse_dimension == 0 and r.coarse_factorizations == 0
    else:
        assert r.coarse_dimension > 0


@pytest.mark.parametrize("bad", (-1, 101))
def test_coarse_blend_out_of_range_is_refused_and_changes_nothing(bad):
    d, V, F, t = _deformer(SPOT, "edge", 0.5)
    before = d.solve(t, max_iterations=5, acceleration="newton").positions
    with pytest.raises(ValueError, match=r"coarse_blend must be in \[0, 100\]"):
        d.solve(t, max_iterations=5, acceleration="newton", coarse_blend=bad, warm_start=False)
    again = d.solve(t, max_iterations=5, acceleration="newton", warm_start=False).positions
    assert np.array_equal(before, again)  # the refused call left the Deformer as it was


def test_coarse_patches_never_hold_a_constrained_vertex():
    d, V, F, t = _deformer(SPOT, "edge", 1.0)
    ur, uc, uv, shape = d._coarse_basis_coo(50)
    nf = len(d.free_vertices)
    assert shape[0] == 3 * nf  # rows are free coordinates only
    assert len(np.unique(ur)) == 3 * nf  # every free vertex is in a patch


def test_live_settle_with_newton_reaches_the_cold_fixed_point():
    # a scripted drag (targets moving in steps, short calls) that then stands still
    d, V, F, t = _deformer(SPOT, "edge", 0.5)
    h = np.asarray(lift(V)[0])
    rest_t = V[h]
    for k in range(1, 6):
        d.solve(rest_t + (t - rest_t) * k / 5, max_iterations=3, acceleration="newton")
    r = None
    for _ in range(200):
        r = d.solve(t, max_iterations=3, acceleration="newton")
        if r.converged:
            break
    assert r.converged
    reference = _reference(d, t)
    assert np.linalg.norm(r.positions - reference, axis=1).max() / diag(V) <= 2e-3


@pytest.mark.parametrize("mesh", ("dino", "grid"))
def test_same_positions_with_1_2_and_4_threads(tmp_path, mesh):
    assert ed.build_info()["serial_blas_factor"], "the BLAS is not OpenBLAS: factors depend on the thread count"
    code = (
        "import sys, numpy as np, edgedeform as ed\n"
        f"sys.path.insert(0, {os.path.dirname(os.path.abspath(__file__))!r})\n"
        "from _meshes import load, lift\n"
        + ("V, F = load('cgal_dino.off')\n" if mesh == "dino" else
           # a bumpy 100 x 100 grid: a factor large enough for the two-way split back-substitution
           "n = 100; x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))\n"
           "V = np.column_stack([x.ravel(), y.ravel(), 0.1 * np.sin(6 * x.ravel()) * np.cos(5 * y.ravel())])\n"
           "i = (np.arange(n - 1)[:, None] * n + np.arange(n - 1)[None, :]).ravel()\n"
           "F = np.vstack([np.column_stack([i, i + 1, i + n + 1]), np.column_stack([i, i + n + 1, i + n])])\n")
        + "h, s, t = lift(V)\n"
        "d = ed.Deformer(V, F, domain='edge'); d.set_constraints(h, s); d.set_stiffness(0.5)\n"
        + ("r = d.solve(t, acceleration='newton')\n" if mesh == "dino" else
           "r = d.solve(t, acceleration='newton', max_iterations=40)\n") +
        "np.save(sys.argv[1], r.positions); print(d.factor_nonzeros)\n"
    )
    runs = []
    for threads in ("1", "2", "4"):
        out = tmp_path / f"p{threads}.npy"
        done = subprocess.run([sys.executable, "-c", code, str(out)], check=True, capture_output=True, text=True,
                              env=dict(os.environ, OMP_NUM_THREADS=threads))
        runs.append(np.load(out))
        if mesh == "grid":  # above the size where the back-substitution splits (supernodal_solve.h)
            assert float(done.stdout.split()[-1]) > 200000
    assert np.array_equal(runs[0], runs[1]) and np.array_equal(runs[0], runs[2])


@pytest.mark.parametrize("domain", DOMAINS)
def test_head_repelling_fixed_point_is_reached_or_reported(domain):
    # The head sample's lift at lambda 0.5 has a fixed point whose one-step map has an
    # eigenvalue of modulus 1.0074 (bench_spectrum.py): the plain iteration leaves it.
    # Newton either reaches a fixed point (a plain step from it moves less than the
    # tolerance) or says it did not; never a silent wrong claim.
    from pathlib import Path
    from edgedeform.mesh_files import read_mesh
    V, F = read_mesh(Path(__file__).resolve().parents[2] / "blend_samples" / "meshes" / "cgal_mannequin-devil.off")
    h, s, t = lift(V)
    d = ed.Deformer(V, F, domain=domain)
    d.set_constraints(h, s)
    d.set_stiffness(0.5)
    r = d.solve(t, acceleration="newton", max_iterations=400)
    assert np.isfinite(r.positions).all()
    if r.converged:
        moved = np.linalg.norm(d._one_step(r.positions) - r.positions[d.free_vertices], axis=1).max() / diag(V)
        assert moved <= 1e-3
        assert r.distance_estimate <= 1e-3
    else:
        assert any("not converged" in w for w in r.warnings)
