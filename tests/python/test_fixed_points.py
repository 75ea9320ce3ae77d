"""Shapes the energy cannot improve on: rest (zero displacement), rigid motions, and
(for lambda = 0) uniform scale. docs/design.md §3."""

import pytest

from _meshes import ALL, diag, lift, load, rigid, two_ends
from _run import deformer, max_dev

DOMAINS = ("edge", "primal")
LAMBDAS = (0.0, 0.5, 1.0)
REL = 1e-9  # "within 1e-9 relative": max coordinate error / bbox diagonal


@pytest.mark.parametrize("lam", LAMBDAS)
@pytest.mark.parametrize("domain", DOMAINS)
@pytest.mark.parametrize("name", ALL)
def test_zero_displacement_returns_rest(name, domain, lam):
    V, F = load(name)
    handles, static, _ = lift(V)
    d = deformer(V, F, domain, lam, handles, static)
    r = d.solve(V[handles], max_iterations=5)
    assert max_dev(r.positions, V) <= REL * diag(V)
    assert r.converged


@pytest.mark.parametrize("lam", LAMBDAS)
@pytest.mark.parametrize("domain", DOMAINS)
@pytest.mark.parametrize("name", ALL)
def test_rigid_motion_is_fixed_point(name, domain, lam):
    """Two handle groups at opposite ends moved by one rigid motion, nothing static:
    started at the moved rest shape, the solver stays there."""
    V, F = load(name)
    handles = two_ends(V)
    g = rigid(V, degrees=30.0)
    goal = g(V)
    d = deformer(V, F, domain, lam, handles)
    r = d.solve(goal[handles], max_iterations=5, tolerance=0.0, initial=goal)
    assert max_dev(r.positions, goal) <= REL * diag(V)
    # The moved rest shape has (numerically) zero energy.
    assert r.initial_energy is not None
    assert r.initial_energy <= 1e-18 * diag(V) ** 2 * len(V)


@pytest.mark.parametrize("domain", DOMAINS)
@pytest.mark.parametrize("name", ALL)
@pytest.mark.parametrize("factor", [1.5, 0.75])
def test_uniform_scale_is_fixed_point_for_lambda_0(name, domain, factor):
    V, F = load(name)
    handles = two_ends(V)
    c = V.mean(axis=0)
    goal = c + factor * (V - c)
    d = deformer(V, F, domain, 0.0, handles)
    r = d.solve(goal[handles], max_iterations=5, tolerance=0.0, initial=goal)
    assert max_dev(r.positions, goal) <= REL * diag(V)


@pytest.mark.parametrize("domain", DOMAINS)
def test_uniform_scale_is_not_fixed_point_for_lambda_1(domain):
    """Control for the test above: the 1-form term does penalise scale, so the same
    start must move when lambda = 1 (otherwise the scale test proves nothing)."""
    V, F = load("spot_low_resolution.obj")
    handles = two_ends(V)
    c = V.mean(axis=0)
    goal = c + 1.5 * (V - c)
    d = deformer(V, F, domain, 1.0, handles)
    r = d.solve(goal[handles], max_iterations=5, tolerance=0.0, initial=goal)
    assert max_dev(r.positions, goal) > 1e-4 * diag(V)
