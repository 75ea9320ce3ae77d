"""Newton (acceleration="newton"): the analytic Jacobian, the assembled Newton matrix, the
fixed point it reaches, its claims, its lead-in and fallback, and its reproducibility
(docs/design.md §4, "Reaching the fixed point"; docs/decisions/0029)."""

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


def _interleaved(dX):
    return dX.reshape(-1)  # row 3 v + c: coordinate c of free vertex v


@pytest.mark.parametrize("domain", DOMAINS)
@pytest.mark.parametrize("lam", (0.0, 0.5, 1.0, "painted"))
def test_assembled_newton_matrix_equals_the_operator(domain, lam):
    """_newton_matrix_coo(X) is the K whose products _jacobian(..., newton_operator=True)
    gives, entry for entry; symmetric at lambda 1 only; and with projection 1 (the per-node
    positive model) positive definite there."""
    import scipy.sparse
    V, F = load(SPOT)
    h, s, t = lift(V)
    d = ed.Deformer(V, F, domain=domain)
    d.set_constraints(h, s)
    d.set_stiffness(np.linspace(0.0, 1.0, len(V)) if lam == "painted" else lam)
    X = d.solve(t, max_iterations=15, acceleration="none").positions
    rows, cols, vals, shape = d._newton_matrix_coo(X)
    K = scipy.sparse.csr_matrix((vals, (rows, cols)), shape=shape)
    nf = len(d.free_vertices)
    assert shape == (3 * nf, 3 * nf)
    dX = np.random.default_rng(7).standard_normal((nf, 3))
    want = _interleaved(d._jacobian(X, dX, True))
    assert np.linalg.norm(K @ _interleaved(dX) - want) <= 1e-12 * np.linalg.norm(want)
    asymmetry = abs(K - K.T).max()
    if lam == 1.0:
        assert asymmetry <= 1e-12 * abs(K).max()
        rows, cols, vals, shape = d._newton_matrix_coo(X, projection=1.0)
        model = scipy.sparse.csr_matrix((vals, (rows, cols)), shape=shape).toarray()
        assert np.linalg.eigvalsh(0.5 * (model + model.T)).min() > 0.0
    else:
        assert asymmetry > 1e-6 * abs(K).max()
    with pytest.raises(ValueError, match=r"projection must be in \[0, 1\]"):
        d._newton_matrix_coo(X, projection=1.5)


def test_newton_options_are_checked_and_named():
    d, V, F, t = _deformer(SPOT, "edge", 1.0)
    assert ed.NewtonOptions().lead_in == 100
    with pytest.raises(ValueError, match="lead_in must be at least 0, got -1"):
        ed.NewtonOptions(lead_in=-1)
    with pytest.raises(TypeError):
        d.solve(t, acceleration="newton", newton={"lead_in": 3})
    r = d.solve(t, acceleration="newton", newton=ed.NewtonOptions(lead_in=0), tolerance=1e-6, warm_start=False)
    assert r.converged and r.newton_steps > 0 and r.newton_factorizations >= r.newton_steps


def test_the_lead_in_is_anderson_and_counted_across_short_calls():
    """A solve that converges inside the lead-in takes no Newton step; calls of a few
    iterations each share one lead-in (live ticks), then Newton finishes."""
    d, V, F, t = _deformer(SPOT, "edge", 1.0)
    easy = d.solve(t, acceleration="newton", warm_start=False, tolerance=1e-2)
    assert easy.converged and easy.newton_steps == 0
    steps = iterations = 0
    for _ in range(100):
        r = d.solve(t * 1.01, max_iterations=5, acceleration="newton", newton=ed.NewtonOptions(lead_in=20),
                    tolerance=1e-8)
        iterations += r.iterations
        steps += r.newton_steps
        if r.converged:
            break
    assert r.converged and steps > 0 and iterations >= 20


@pytest.mark.parametrize("stiffness", (0.5, "painted"))
def test_below_lambda_1_newton_is_anderson(stiffness):
    """Newton steps are taken only where lambda = 1 on every term: below it the LU Newton lost
    to Anderson everywhere and failed on the koala (record 0029), so "newton" runs Anderson,
    bit for bit, and says so by taking no Newton step."""
    results = {}
    for method in ("newton", "anderson"):
        d, V, F, t = _deformer(DINO, "edge", 1.0)
        d.set_stiffness(np.linspace(0.5, 1.0, len(V)) if stiffness == "painted" else stiffness)
        results[method] = d.solve(t, acceleration=method, tolerance=1e-6, warm_start=False)
    newton, anderson = results["newton"], results["anderson"]
    assert newton.converged and newton.newton_steps == 0 and newton.newton_factorizations == 0
    assert np.array_equal(newton.positions, anderson.positions)
    assert newton.iterations == anderson.iterations


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
    """The same bits on any thread count, whatever keeps them so in this build (CHOLMOD's
    BLAS held to one thread, serial_blas.h; the split back-substitution's fixed order)."""
    code = (
        "import sys, numpy as np, edgedeform as ed\n"
        f"sys.path.insert(0, {os.path.dirname(os.path.abspath(__file__))!r})\n"
        "from _meshes import load, lift\n"
        + ("V, F = load('cgal_dino.off')\n" if mesh == "dino" else
           # a bumpy 140 x 140 grid: a factor large enough for the two-way split back-substitution
           "n = 140; x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))\n"
           "V = np.column_stack([x.ravel(), y.ravel(), 0.1 * np.sin(6 * x.ravel()) * np.cos(5 * y.ravel())])\n"
           "i = (np.arange(n - 1)[:, None] * n + np.arange(n - 1)[None, :]).ravel()\n"
           "F = np.vstack([np.column_stack([i, i + 1, i + n + 1]), np.column_stack([i, i + n + 1, i + n])])\n")
        + "h, s, t = lift(V)\n"
        # lambda 1: where Newton takes its steps (below it the solve is Anderson's)
        "d = ed.Deformer(V, F, domain='edge'); d.set_constraints(h, s); d.set_stiffness(1.0)\n"
        "o = ed.NewtonOptions(lead_in=10)\n"
        + ("r = d.solve(t, acceleration='newton', newton=o)\n" if mesh == "dino" else
           "r = d.solve(t, acceleration='newton', newton=o, max_iterations=40)\n") +
        "assert r.newton_steps > 0, r.newton_steps\n"
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
