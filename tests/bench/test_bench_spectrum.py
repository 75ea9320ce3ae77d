"""bench/bench_spectrum.py: its largest Ritz modulus is the rate at which the plain iteration
really contracts near the fixed point (checked apart, by iterating), and it writes the fields
its Markdown table reads."""

import json
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench"))

import bench_spectrum  # noqa: E402

CELL = "spot:lift:edge:0.5"


def fixed_point(steps=None):
    """CELL's deformer, free mask, diagonal, reference X and map G; with `steps`, also the
    slowest Arnoldi pair (mu, v), v scaled to a largest row of one diagonal."""
    import edgedeform as ed
    name, edit_name, domain, lam = CELL.split(":")
    d, targets, free, dg = bench_spectrum.problem(ed, (name, edit_name, domain, float(lam)))
    X, *_ = bench_spectrum.reference(d, targets)
    cell = SimpleNamespace(d=d, targets=targets, free=free, dg=dg, X=X,
                           G=bench_spectrum.one_step_map(d, targets))
    if steps:
        theta, _, vectors = bench_spectrum.arnoldi(cell.G, X, free, dg, steps)
        v = vectors[:, 0].reshape(-1, 3)
        cell.mu, cell.v = theta[0].real, v * (dg / np.linalg.norm(v, axis=1).max())
    return cell


def test_largest_modulus_is_the_observed_contraction(tmp_path):
    out = tmp_path / "spectrum.json"
    bench_spectrum.main(["--cells", CELL, "--steps", "40", "--json", str(out)])
    row = json.loads(out.read_text())["rows"][0]
    assert row["reference_converged"] and row["one_step_residual"] < 1e-9
    assert row["above_1"] == 0 and 0.5 < row["top"][0] < 1.0
    table = bench_spectrum.markdown({"machine": {"cpu": "x", "cores": 2, "load_1min": 0.0,
                                                 "date": "d"}, "steps": 40, "rows": [row]})
    assert f"| spot lift edge λ 0.5 | {row['free']:,} |" in table and f"{row['top'][0]:.4f}" in table

    # Perturb the fixed point and iterate plainly: the residual's asymptotic ratio per
    # iteration is the largest modulus of the map's Jacobian there.
    c = fixed_point()
    start = c.X.copy()
    start[c.free] += 1e-4 * c.dg * np.random.default_rng(1).standard_normal((int(c.free.sum()), 3))
    r = c.d.solve(c.targets, max_iterations=300, tolerance=0.0, warm_start=False, initial=start,
                acceleration="none")
    res = np.asarray(r.residuals)
    rate = (res[-1] / res[-101]) ** (1.0 / 100)
    assert res[-1] > 1e-12  # still above round-off, so the ratio is the mode's
    assert abs(rate - row["top"][0]) < 0.01, (rate, row["top"])


def test_model_radius_is_where_the_linear_model_fails(tmp_path):
    """--radius: c is a constant over its two steps (a second derivative, not noise), and
    the linear model's measured error along the slowest mode at h is c h^2 / 2 (so, at
    h*, the step's own term |1 - mu| h*), as the table says."""
    out = tmp_path / "spectrum.json"
    bench_spectrum.main(["--cells", CELL, "--steps", "40", "--radius", "2", "--json", str(out)])
    row = json.loads(out.read_text())["rows"][0]
    first = row["model_radius"][0]
    assert len(row["model_radius"]) == 2 and abs(first["modulus"] - row["top"][0]) < 1e-12
    c_small, c_large = first["curvature"]
    assert c_small > 0 and abs(c_large / c_small - 1) < 0.1, first["curvature"]
    assert first["radius"] > 0
    table = bench_spectrum.radius_markdown({"machine": {}, "steps": 40, "rows": [row]})
    assert f"| spot lift edge λ 0.5 | {first['modulus']:.4f} |" in table
    rotations = first["rotations"]
    assert abs(rotations["curvature"][1] / rotations["curvature"][0] - 1) < 0.1
    assert 0 < rotations["turn_median"] <= rotations["turn_999"] <= rotations["turn_max"]
    assert rotations["steps"][1] * rotations["turn_max"] <= bench_spectrum.ROTATION_TURN + 1e-12
    assert f"{rotations['radius']:.1e}" in table

    # Apart: the linearization's error along the slowest Ritz vector at h*/2, measured.
    c = fixed_point(steps=40)
    h = first["radius"] / 2
    moved = c.X.copy()
    moved[c.free] += h * c.v
    error = np.linalg.norm((c.G(moved) - c.G(c.X))[c.free] - h * c.mu * c.v, axis=1).max() / c.dg
    assert 0.5 < error / (c_small * h * h / 2) < 2.0, (error, c_small * h * h / 2)


def test_a_curvature_that_is_not_constant_gives_no_radius():
    """c from steps past a kink (here |x|: c halves when h triples) is no second derivative:
    no h*, and the table says '–'."""
    c, radius = bench_spectrum.curvature_and_radius(lambda h: 2 * h, (1e-3, 3e-3), 0.01, 1.0)
    assert radius is None and abs(c[0] / c[1] - 3) < 1e-9
    c, radius = bench_spectrum.curvature_and_radius(lambda h: 5 * h * h, (1e-3, 3e-3), 0.01, 1.0)
    assert abs(radius - 2 * 0.01 / 5) < 1e-15


def test_rotation_coordinates_carry_the_same_slow_mode():
    """bench/rotation_coordinates.py: exp and log invert each other; at the fixed point psi(0)
    is 0 to the reference's precision, and along the slowest position mode's direction
    there psi multiplies by the same eigenvalue mu (J_G and D_R A^-1 B share it)."""
    from rotation_coordinates import RotationCoordinates, exp_so3, largest_row, log_so3
    w = np.random.default_rng(2).normal(scale=0.5, size=(50, 3))
    R = exp_so3(w)
    assert np.abs(np.swapaxes(R, 1, 2) @ R - np.eye(3)).max() < 1e-12
    assert np.abs(np.linalg.det(R) - 1).max() < 1e-12 and np.abs(log_so3(R) - w).max() < 1e-10

    c = fixed_point(steps=40)
    coords = RotationCoordinates(c.d, c.X)
    z0 = coords.psi(np.zeros((len(coords.s), 4)))
    assert largest_row(z0) < 1e-7, largest_row(z0)
    dz = coords.direction(c.free, c.v)
    h = 1e-5
    image = (coords.psi(h * dz) - coords.psi(-h * dz)) / (2 * h)
    assert largest_row(image - c.mu * dz) < 1e-3 * largest_row(dz)
    assert largest_row(image - 0.9 * c.mu * dz) > 0.05 * largest_row(dz)  # (not any factor)
