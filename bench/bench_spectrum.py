#!/usr/bin/env python3
"""Why some solves converge slowly: the spectrum of the one-step map at its fixed point.

The local/global iteration x -> G(x) (one local step, then one global step) contracts the
error e along an eigenvector of G's Jacobian J (at the fixed point) by that eigenvalue per
iteration. Eigenvalues near 1 are modes that the plain iteration needs ~1/(1 - |mu|)
iterations per factor e to remove, and that Anderson (a window of 5 secants) can only cancel
a few at a time; an eigenvalue above 1 is a fixed point the plain iteration moves away from.

For each cell: the reference (a cold default solve, tolerance 1e-10, at most 6000
iterations), then Arnoldi with products J v taken by finite differences of the package's own
one-step map (`solve(..., max_iterations=1, initial=x, acceleration="none")`) at that point.
Reported: the largest Ritz moduli, how many exceed 0.99 / 0.999 / 1, and the Arnoldi residual
of the largest (how well that value is resolved). With --radius K, for the K largest: how
far Newton's linear model of G holds along that eigenvector v (max row |v| = diag): the
second difference |G(x + hv) + G(x - hv) - 2 G(x)| = c h^2 gives the model's error c h^2 / 2
at a step h, which equals the step's own term |(I - J) hv| = |1 - mu| h at h* = 2 |1 - mu| / c:
beyond h* (a fraction of the diagonal) a Newton step along that mode is mostly model error.
With --spread, the reference is also
computed in child processes with 1 and with 2 solver threads, and the two end points compared
(round-off differs between them, nothing else).

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_spectrum.py [--steps 100] [--spread]
        [--cells koala:lift:edge:1,head:lift:edge:0.5] [--radius 3]
        [--json bench/results/spectrum.json]
Writes bench/results/spectrum.json; bench/report.py puts the tables into docs/benchmarks_solver.md.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
from bench_convergence import SAMPLES  # noqa: E402
from edits import diagonal, edit, mesh_path as find_mesh  # noqa: E402
from machine import machine_info  # noqa: E402
from rotation_coordinates import RotationCoordinates, largest_row  # noqa: E402

DEFAULT_CELLS = ("spot:lift:edge:0.5,dino:lift:edge:0.5,head:lift:edge:1,head:lift:edge:0.5,"
                 "head:lift:edge:0,koala:lift:edge:1,koala:lift:edge:0.5")
REFERENCE_BUDGET = 6000
FD_STEP = 1e-5  # finite-difference step, / diag: far above round-off, far below the nonlinearity
# Steps of --radius's second differences, / diag: two, so the table shows c is a constant
# there (not round-off, not a kink of the fit).
RADIUS_STEPS = (1e-3, 3e-3)
# c counts as a constant when the two steps' values agree this well.
CONSTANT_CURVATURE = 0.2
# In rotation coordinates the larger step turns no term by more than this (radians): a
# term whose rotation its arcs barely determine turns thousands of radians per diagonal
# moved, and past pi the coordinates wrap.
ROTATION_TURN = 0.05


def mesh_path(name):
    """"koala" or a sample's short name (bench_convergence.SAMPLES)."""
    return find_mesh("koala.obj" if name == "koala" else SAMPLES[name])


def problem(ed, cell):
    from edgedeform.mesh_files import read_mesh
    name, edit_name, domain, lam = cell
    V, F = read_mesh(mesh_path(name))
    handles, static, targets = edit(V, edit_name)
    d = ed.Deformer(V, F, domain=domain)
    d.set_constraints(handles=handles, static=static)
    d.set_stiffness(lam)
    free = np.ones(len(V), bool)
    free[handles] = free[static] = False
    return d, targets, free, diagonal(V)


def reference(d, targets):
    r = d.solve(targets, max_iterations=REFERENCE_BUDGET, tolerance=1e-10, warm_start=False)
    return np.asarray(r.positions), r.iterations, float(r.residuals[-1]), bool(r.converged)


def one_step_map(d, targets):
    """G over full shapes: one plain step of the package from x (its own map, not a copy)."""
    def G(x):
        return np.asarray(d.solve(targets, max_iterations=1, tolerance=0.0, warm_start=False,
                                  initial=x, acceleration="none").positions)
    return G


def arnoldi(G, x, free, dg, steps, seed=0):
    """Ritz values of J = dG/dx at x (free coordinates, largest modulus first), the Arnoldi
    residual of each, and their Ritz vectors as columns (real parts)."""
    g0 = G(x)
    n = int(free.sum()) * 3
    Q = np.zeros((steps + 1, n))
    H = np.zeros((steps + 1, steps))
    q = np.random.default_rng(seed).standard_normal(n)
    Q[0] = q / np.linalg.norm(q)
    for k in range(steps):
        v = Q[k]
        eps = FD_STEP * dg / np.abs(v).max()
        y = x.copy()
        y[free] += (eps * v).reshape(-1, 3)
        w = (G(y) - g0)[free].ravel() / eps
        for _ in range(2):  # Gram-Schmidt twice: the basis stays orthogonal to round-off
            c = Q[:k + 1] @ w
            H[:k + 1, k] += c
            w -= c @ Q[:k + 1]
        H[k + 1, k] = np.linalg.norm(w)
        Q[k + 1] = w / H[k + 1, k]
    theta, S = np.linalg.eig(H[:steps, :steps])
    order = np.argsort(-np.abs(theta))
    resid = np.abs(H[steps, steps - 1] * S[steps - 1, :])
    vectors = (Q[:steps].T @ S[:, order]).real  # (a complex pair: a vector of its plane)
    return theta[order], resid[order], vectors


def curvature_and_radius(second_difference, steps, gap, size):
    """c at each step (|second difference| / h^2) and h* = 2 gap size / c, or None when c
    is not a constant over the steps (within CONSTANT_CURVATURE): then the steps are past
    a kink or a wrap, and c is no second derivative."""
    c = [second_difference(h) / h ** 2 for h in steps]
    constant = abs(c[0] / c[1] - 1.0) <= CONSTANT_CURVATURE if c[1] > 0 else False
    return c, (2.0 * gap * size / c[0] if constant else None)


def model_radius(G, x, free, dg, mu, v, coords):
    """Along v (free coordinates, scaled to max row |v| = dg): the second difference's
    constant c per step of RADIUS_STEPS and h* = 2 |1 - mu| / c (/ diag), see the docstring.
    The same in rotation coordinates (coords: rotation_coordinates.RotationCoordinates at
    x) along v's direction there, with steps that turn no term by more than ROTATION_TURN,
    and how much each term's rotation turns per diagonal moved along v (median, 99.9th
    percentile, largest)."""
    v = v.reshape(-1, 3)
    v = v * (dg / np.linalg.norm(v, axis=1).max())
    g0 = G(x)

    def in_positions(h):
        plus, minus = x.copy(), x.copy()
        plus[free] += h * v
        minus[free] -= h * v
        return largest_row((G(plus) + G(minus) - 2.0 * g0)[free]) / dg
    gap = float(abs(1.0 - mu))
    curvature, radius = curvature_and_radius(in_positions, RADIUS_STEPS, gap, 1.0)
    out = {"gap": gap, "curvature": curvature, "radius": radius}

    dz = coords.direction(free, v)   # per diagonal moved (max row of v = dg)
    z0 = coords.psi(np.zeros_like(dz))
    turn = np.linalg.norm(dz[:, :3], axis=1)
    largest = min(RADIUS_STEPS[-1], ROTATION_TURN / float(turn.max()))
    steps = (largest / 3.0, largest)
    curvature, radius = curvature_and_radius(
        lambda h: largest_row(coords.psi(h * dz) + coords.psi(-h * dz) - 2.0 * z0), steps, gap,
        largest_row(dz))
    out["rotations"] = {"steps": list(steps), "curvature": curvature, "radius": radius,
                        "turn_median": float(np.median(turn)),
                        "turn_999": float(np.quantile(turn, 0.999)), "turn_max": float(turn.max())}
    return out


def child_reference(cell_text, threads, out):
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    subprocess.run([sys.executable, __file__, "--reference-only", cell_text, "--out", out],
                   env=env, check=True)
    z = np.load(out)
    return z["X"], int(z["iterations"]), float(z["residual"])


def run_cell(ed, cell_text, steps, spread, log, radius=0):
    name, edit_name, domain, lam = cell_text.split(":")
    cell = (name, edit_name, domain, float(lam))
    d, targets, free, dg = problem(ed, cell)
    t0 = time.time()
    X, its, res, conv = reference(d, targets)
    row = {"mesh": name, "edit": edit_name, "domain": domain, "lambda": float(lam),
           "free": int(free.sum()), "reference_iterations": its, "reference_residual": res,
           "reference_converged": conv, "reference_s": time.time() - t0, "steps": steps}

    G = one_step_map(d, targets)
    row["one_step_residual"] = float(np.abs(G(X) - X).max() / dg)
    theta, resid, vectors = arnoldi(G, X, free, dg, steps)
    mod = np.abs(theta)
    if radius:
        coords = RotationCoordinates(d, X)
        # One row per real mode or complex pair (the pair's second member repeats the first).
        modes = [i for i in range(len(theta)) if theta[i].imag >= 0][:radius]
        row["model_radius"] = [dict(model_radius(G, X, free, dg, theta[i], vectors[:, i], coords),
                                    modulus=float(mod[i]), arnoldi_residual=float(resid[i]))
                               for i in modes]
    row.update(top=[float(m) for m in mod[:8]], top_arnoldi_residual=float(resid[0]),
               above_099=int((mod > 0.99).sum()), above_0999=int((mod > 0.999).sum()),
               above_1=int((mod > 1.0 + 1e-4).sum()))
    if spread:
        with tempfile.TemporaryDirectory() as tmp:
            ends = [child_reference(cell_text, t, str(Path(tmp) / f"ref{t}.npz")) for t in (1, 2)]
        row["spread"] = {"threads_1": {"iterations": ends[0][1], "residual": ends[0][2]},
                         "threads_2": {"iterations": ends[1][1], "residual": ends[1][2]},
                         "distance": float(np.abs(ends[0][0] - ends[1][0]).max() / dg)}
    log(json.dumps(row))
    return row


def cell_label(r):
    return f"{r['mesh']} {r['edit']} {r['domain']} λ {r['lambda']:g}"


def markdown(result):
    lines = [  # the date, machine and load head the page's section (bench/report.py)
        f"Arnoldi with {result['steps']} finite-difference products of the package's one-step map G "
        "at the reference (a cold default solve run to tolerance 1e-10, at most 6000 iterations); "
        "|μ| = the largest Ritz moduli of G's Jacobian there. A mode with |μ| contracts by |μ| per "
        "plain iteration (|μ| = 0.999: about 2,300 iterations per factor 10); |μ| > 1: the plain "
        "iteration leaves that point. Counts are of the Ritz values found in those steps, so "
        "they are lower bounds. 'spread' = the distance between the references computed with 1 "
        "and with 2 solver threads (round-off is all that differs).",
        "",
        "| cell | free vertices | reference its (residual) | G residual there | largest moduli | "
        "Arnoldi residual of the largest | moduli > 0.99 | > 0.999 | > 1 | spread / diag |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in result["rows"]:
        sp = r.get("spread")
        spread = (f"{sp['distance']:.1e} (residuals {sp['threads_1']['residual']:.0e} / "
                  f"{sp['threads_2']['residual']:.0e})" if sp else "–")
        ref = (f"{r['reference_iterations']} ({r['reference_residual']:.0e}"
               f"{'' if r['reference_converged'] else ', not conv.'})")
        lines.append(
            f"| {cell_label(r)} | {r['free']:,} | {ref} | {r['one_step_residual']:.0e} | "
            f"{', '.join(f'{t:.4f}' for t in r['top'][:4])} | {r['top_arnoldi_residual']:.0e} | "
            f"{r['above_099']} | {r['above_0999']} | {r['above_1']} | {spread} |")
    return "\n".join(lines)


def radius_markdown(result):
    """The --radius table (docs/benchmarks_solver.md has it as a section of its own)."""
    def radius(value):
        return "–" if value is None else f"{value:.1e}"

    def constants(values):
        return " / ".join(f"{c:.2g}" for c in values)
    lines = []
    radius_rows = [r for r in result["rows"] if r.get("model_radius")]
    if radius_rows:
        lines += [
            f"Arnoldi with {result['steps']} products at each cell's reference, as in the "
            "spectrum section (one row per real mode or complex pair). How far Newton's linear "
            "model of G holds along the slowest modes (`--radius`): for each of the largest "
            "Ritz pairs (μ, v), v scaled to a largest vertex displacement of one diagonal, c "
            "from the second difference |G(x+hv) + G(x−hv) − 2G(x)| = c h² at h = "
            + " and ".join(f"{h:g}" for h in RADIUS_STEPS) + " of the diagonal; h* = 2|1 − μ|/c "
            "is the step (/ diag) beyond which the model's error c h²/2 exceeds the step's own "
            "term |1 − μ| h: farther out, a Newton step along that mode is mostly model error. "
            f"h* is '–' where the two c differ by more than {CONSTANT_CURVATURE:.0%} (not a "
            "second derivative at these steps: a kink of the fit).",
            "",
            "In rotation coordinates (the per-term rotations and scales a Newton method on the "
            "rotations would step in, `bench/rotation_coordinates.py`): the same measure along "
            "v's direction there, in the largest term's norm, with steps h/3 and h chosen so that "
            f"no term turns by more than {ROTATION_TURN:g} rad; 'turn' = how far each term's "
            "rotation turns (radians) per diagonal moved along v: median / 99.9th percentile / "
            "largest (a large one is a node whose rotation its arcs barely determine).",
            "",
            "| cell | modulus | Arnoldi residual | distance of μ from 1 | c at the two steps | "
            "h* / diag | rotations: steps h/3, h | rotations: c | rotations: h* / diag | "
            "turn per diagonal |",
            "|---|---|---|---|---|---|---|---|---|---|",
        ]
        for r in radius_rows:
            for m in r["model_radius"]:
                rot = m["rotations"]
                lines.append(
                    f"| {cell_label(r)} | {m['modulus']:.4f} | {m['arnoldi_residual']:.0e} | "
                    f"{m['gap']:.1e} | {constants(m['curvature'])} | {radius(m['radius'])} | "
                    f"{' / '.join(f'{h:.1e}' for h in rot['steps'])} | {constants(rot['curvature'])} | "
                    f"{radius(rot['radius'])} | "
                    f"{rot['turn_median']:.2g} / {rot['turn_999']:.2g} / {rot['turn_max']:.2g} |")
    return "\n".join(lines) if lines else "No cell of this run was measured with --radius."


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cells", default=DEFAULT_CELLS, help="mesh:edit:domain:lambda,...")
    ap.add_argument("--steps", type=int, default=100, help="Arnoldi steps per cell")
    ap.add_argument("--radius", type=int, default=0,
                    help="for this many of the largest Ritz pairs, how far Newton's model holds")
    ap.add_argument("--spread", action="store_true",
                    help="also compare references computed with 1 and 2 solver threads")
    ap.add_argument("--json", default=str(HERE / "results" / "spectrum.json"))
    ap.add_argument("--reference-only", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--out", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    import edgedeform as ed
    if args.reference_only:  # child of --spread: one reference, with this process's threads
        name, edit_name, domain, lam = args.reference_only.split(":")
        d, targets, _, _ = problem(ed, (name, edit_name, domain, float(lam)))
        X, its, res, _ = reference(d, targets)
        np.savez(args.out, X=X, iterations=its, residual=res)
        return
    result = {"machine": machine_info(), "steps": args.steps, "rows": [],
              "command": "bench/bench_spectrum.py " + " ".join(argv or sys.argv[1:])}
    for cell_text in args.cells.split(","):
        result["rows"].append(run_cell(ed, cell_text, args.steps, args.spread,
                                       lambda s: print(s, flush=True), args.radius))
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    Path(args.json).write_text(json.dumps(result, indent=1))
    print(markdown(result))
    print(radius_markdown(result))


if __name__ == "__main__":
    main()
