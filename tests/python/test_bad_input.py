"""Bad input: a ValueError/IndexError naming the problem, or a documented behaviour;
never a crash, and a failed call leaves the Deformer usable (docs/api.md "Errors")."""

import numpy as np
import pytest

import edgedeform as ed
from _meshes import PLANE, SPOT, diag, lift, load
from _run import deformer, max_dev


@pytest.fixture
def spot():
    V, F = load(SPOT)
    handles, static, targets = lift(V, amount=0.1)
    return V, F, handles, static, targets


# ---- construction -------------------------------------------------------------------

@pytest.mark.parametrize("make, exc, words", [
    (lambda V, F: (V[:, :2], F), ValueError, r"(?i)\bV\b|vert|position|shape"),
    (lambda V, F: (V.reshape(-1), F), ValueError, r"(?i)\bV\b|vert|position|shape"),
    (lambda V, F: (V, F[:, :2]), ValueError, r"(?i)\bF\b|face|triang|shape"),
    (lambda V, F: (V, np.hstack([F, F[:, :1]])), ValueError, r"(?i)\bF\b|face|triang|shape"),
    (lambda V, F: (np.where(np.arange(len(V))[:, None] == 7, np.nan, V), F), ValueError,
     r"(?i)nan|finite"),
    (lambda V, F: (np.where(np.arange(len(V))[:, None] == 7, np.inf, V), F), ValueError,
     r"(?i)inf|finite"),
    (lambda V, F: (V, np.where(F == 5, len(V), F)), IndexError, r"(?i)face|\bF\b|index|range"),
    (lambda V, F: (V, np.where(F == 5, -1, F)), IndexError, r"(?i)face|\bF\b|index|negative|range"),
], ids=["V_2cols", "V_flat", "F_2cols", "F_4cols", "V_nan", "V_inf",
        "F_out_of_range", "F_negative"])
def test_bad_mesh_rejected(make, exc, words):
    V, F = load(SPOT)
    V2, F2 = make(V, F)
    with pytest.raises(exc, match=words):
        ed.Deformer(V2, F2, domain="edge")


def test_bad_domain_rejected():
    V, F = load(SPOT)
    with pytest.raises(ValueError, match=r"(?i)domain"):
        ed.Deformer(V, F, domain="vertex")


@pytest.mark.parametrize("domain", ["edge", "primal"])
@pytest.mark.parametrize("make, words", [
    (lambda V: np.zeros_like(V) + [1.0, 2.0, 3.0],
     r"^the mesh is degenerate: all its 829 vertices are at one point \(1, 2, 3\)$"),
    (lambda V: np.outer(V[:, 0], [1.0, 0.0, 0.0]),
     r"^the mesh is degenerate: every face has zero area \(its vertices lie on one line\)$"),
    (lambda V: np.outer(V[:, 0], [1.0, 2.0, -0.5]) + 7.0,
     r"^the mesh is degenerate: every face has zero area"),
], ids=["one_point", "x_axis", "skew_line"])
def test_degenerate_whole_mesh_named(make, words, domain):
    """Not "CHOLMOD could not analyze the matrix (status -4)"."""
    V, F = load(SPOT)
    with pytest.raises(ValueError, match=words):
        ed.Deformer(make(V), F, domain=domain)


def test_huge_mesh_coordinates_rejected():
    V, F = load(SPOT)
    with pytest.raises(ValueError, match=r"^V\[\d+\] = .* too far to solve without overflow"):
        ed.Deformer(V * 1e200, F)


# ---- constraints and stiffness ------------------------------------------------------

def _usable_after(d, targets, before):
    """The failed call changed nothing: the same solve gives the same answer."""
    r = d.solve(targets, max_iterations=5, warm_start=False)
    assert max_dev(r.positions, before) <= 1e-12 * (1 + np.abs(before).max())


@pytest.mark.parametrize("kwargs, exc, words", [
    (lambda h, s, n: dict(handles=np.array([], dtype=np.int64), static=s),
     ValueError, r"(?i)handle.*empty|empty.*handle|no handle"),
    (lambda h, s, n: dict(handles=np.append(h, n), static=s), IndexError,
     r"(?i)handle|range|index"),
    (lambda h, s, n: dict(handles=np.append(h, -1), static=s), IndexError,
     r"(?i)handle|negative|range|index"),
    (lambda h, s, n: dict(handles=h, static=np.append(s, n + 10)), IndexError,
     r"(?i)static|range|index"),
    (lambda h, s, n: dict(handles=h, static=np.append(s, -3)), IndexError,
     r"(?i)static|negative|range|index"),
    (lambda h, s, n: dict(handles=h, static=np.append(s, h[0])), ValueError,
     r"(?i)overlap|both|handle.*static|static.*handle"),
    (lambda h, s, n: dict(handles=h, static=s, roi=np.array([0, n])), IndexError,
     r"(?i)roi|region|range|index"),
    (lambda h, s, n: dict(handles=h.reshape(-1, 1).repeat(2, 1), static=s), ValueError,
     r"(?i)handle|shape|1-d|dimension"),
], ids=["empty_handles", "handle_out_of_range", "handle_negative", "static_out_of_range",
        "static_negative", "overlap", "roi_out_of_range", "handles_2d"])
def test_bad_constraints_rejected_and_deformer_usable(spot, kwargs, exc, words):
    V, F, handles, static, targets = spot
    d = deformer(V, F, "edge", 0.5, handles, static)
    before = np.asarray(d.solve(targets, max_iterations=5).positions).copy()
    with pytest.raises(exc, match=words):
        d.set_constraints(**kwargs(handles, static, len(V)))
        d.solve(targets, max_iterations=5)       # in case checks are deferred to solve
    _usable_after(d, targets, before)


@pytest.mark.parametrize("lam, words", [
    (-0.1, r"(?i)stiff|lambda|\[0, ?1\]|range"),
    (1.1, r"(?i)stiff|lambda|\[0, ?1\]|range"),
    (float("nan"), r"(?i)stiff|lambda|nan|finite"),
    ("array_bad_value", r"(?i)stiff|lambda|\[0, ?1\]|range"),
    ("array_wrong_length", r"(?i)stiff|lambda|shape|length|size"),
])
def test_bad_stiffness_rejected_and_deformer_usable(spot, lam, words):
    V, F, handles, static, targets = spot
    d = deformer(V, F, "primal", 0.5, handles, static)
    before = np.asarray(d.solve(targets, max_iterations=5).positions).copy()
    if lam == "array_bad_value":
        lam = np.full(len(V), 0.5)
        lam[3] = 1.5
    elif lam == "array_wrong_length":
        lam = np.full(len(V) - 1, 0.5)
    with pytest.raises(ValueError, match=words):
        d.set_stiffness(lam)
    _usable_after(d, targets, before)


@pytest.mark.parametrize("case, words", [
    ("targets_short", r"(?i)target|shape|handle"),
    ("targets_2cols", r"(?i)target|shape"),
    ("targets_nan", r"(?i)target|nan|finite"),
    ("targets_inf", r"(?i)target|inf|finite"),
    ("initial_shape", r"(?i)initial|shape"),
    ("initial_nan", r"(?i)initial|nan|finite"),
    ("targets_1e308", r"^targets\[2\] = \(1e\+308, .* too far to solve without overflow"),
    ("targets_1e200", r"^targets\[0\] = .* too far to solve without overflow"),
    ("initial_1e300", r"^initial\[3\] = .* too far to solve without overflow"),
])
def test_bad_solve_arguments_rejected_and_deformer_usable(spot, case, words):
    V, F, handles, static, targets = spot
    d = deformer(V, F, "edge", 1.0, handles, static)
    before = np.asarray(d.solve(targets, max_iterations=5).positions).copy()
    kw = dict(max_iterations=5)
    t = targets
    if case == "targets_short":
        t = targets[:-1]
    elif case == "targets_2cols":
        t = targets[:, :2]
    elif case == "targets_nan":
        t = targets.copy(); t[0, 1] = np.nan
    elif case == "targets_inf":
        t = targets.copy(); t[-1, 2] = -np.inf
    elif case == "initial_shape":
        kw["initial"] = V[:-1]
    elif case == "initial_nan":
        X0 = V.copy(); X0[10, 0] = np.nan
        kw["initial"] = X0
    elif case == "targets_1e308":  # finite, but its squared distances overflow (docs/api.md)
        t = targets.copy(); t[2, 0] = 1e308
    elif case == "targets_1e200":
        t = targets * 1e200
    elif case == "initial_1e300":
        X0 = V.copy(); X0[3, 1] = -1e300
        kw["initial"] = X0
    with pytest.raises(ValueError, match=words):
        d.solve(t, **kw)
    _usable_after(d, targets, before)


# ---- documented behaviours ----------------------------------------------------------

@pytest.mark.parametrize("lam", [0.0, 0.5, 1.0])
@pytest.mark.parametrize("domain", ["edge", "primal"])
def test_zero_area_triangles_give_finite_result(domain, lam):
    """Documented: degenerate triangles are accepted (cotangents floored) and the
    result stays finite with the constraints met."""
    V, F = load(PLANE)
    handles, static, targets = lift(V, amount=0.1)
    free = np.setdiff1d(np.arange(len(V)), np.concatenate([handles, static]))
    # collapse a free vertex onto a neighbour: its triangles with that neighbour get area 0
    v = free[len(free) // 2]
    t = np.flatnonzero((F == v).any(axis=1))[0]
    u = [x for x in F[t] if x != v][0]
    V[v] = V[u]
    # and one needle: a vertex moved onto the line through two others
    w = free[len(free) // 3]
    t2 = np.flatnonzero((F == w).any(axis=1))[0]
    a, b = [x for x in F[t2] if x != w]
    V[w] = 0.5 * (V[a] + V[b])
    d = deformer(V, F, domain, lam, handles, static)
    assert np.all(np.isfinite(np.asarray(d.weights())))
    r = d.solve(targets, max_iterations=10)
    X = np.asarray(r.positions)
    assert np.all(np.isfinite(X))
    assert np.all(np.isfinite(r.energies))
    assert np.array_equal(X[handles], targets)
    assert np.abs(X - V).max() < 10 * diag(V)      # finite and not blown up


@pytest.mark.parametrize("domain", ["edge", "primal"])
def test_unreferenced_vertices_stay_at_rest_with_warning(domain):
    V, F = load(SPOT)
    handles, static, targets = lift(V, amount=0.1)
    extra = np.array([[5.0, 5.0, 5.0], [-5.0, 1.0, 2.0]])
    V2 = np.vstack([V, extra])
    d = deformer(V2, F, domain, 0.5, handles, static)
    r = d.solve(targets, max_iterations=10)
    X = np.asarray(r.positions)
    assert X.shape == V2.shape
    assert np.array_equal(X[len(V):], extra)
    assert any(("unreferenced" in w.lower() or "not used by any face" in w.lower())
               for w in r.warnings), r.warnings
    # the rest of the mesh is solved exactly as without the extra vertices
    r0 = deformer(V, F, domain, 0.5, handles, static).solve(targets, max_iterations=10)
    np.testing.assert_allclose(X[:len(V)], r0.positions, rtol=0, atol=1e-9 * diag(V))


@pytest.mark.parametrize("domain", ["edge", "primal"])
def test_free_component_without_constraints_stays_at_rest_with_warning(domain):
    V, F = load(SPOT)
    handles, static, targets = lift(V, amount=0.1)
    # a second, shifted copy of the mesh that carries no constraint at all
    V2 = np.vstack([V, V + [3.0, 0.0, 0.0]])
    F2 = np.vstack([F, F + len(V)])
    d = deformer(V2, F2, domain, 0.5, handles, static)
    r = d.solve(targets, max_iterations=10)
    X = np.asarray(r.positions)
    assert np.all(np.isfinite(X))
    assert np.array_equal(X[len(V):], V2[len(V):])
    assert np.array_equal(X[handles], targets)
    assert len(r.warnings) >= 1 and any("component" in w.lower() for w in r.warnings), \
        r.warnings


def test_solve_result_is_a_copy():
    """Modifying a result must not corrupt the Deformer's warm start."""
    V, F = load(SPOT)
    handles, static, targets = lift(V, amount=0.1)
    d = deformer(V, F, "edge", 0.5, handles, static)
    r1 = d.solve(targets, max_iterations=5, tolerance=0.0)
    X1 = np.array(r1.positions)
    try:
        r1.positions[:] = 0.0
    except (ValueError, AttributeError, TypeError):
        pass                                        # read-only is fine too
    d2 = deformer(V, F, "edge", 0.5, handles, static)
    d2.solve(targets, max_iterations=5, tolerance=0.0)
    a = d.solve(targets, max_iterations=3, tolerance=0.0, warm_start=True)
    b = d2.solve(targets, max_iterations=3, tolerance=0.0, warm_start=True)
    np.testing.assert_array_equal(a.positions, b.positions)
    assert np.isfinite(X1).all()
