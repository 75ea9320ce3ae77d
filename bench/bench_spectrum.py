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
at a step h, which equals the step's own term |(I - J) hv| = |1 - mu| h at h* = 2 |1 - mu| / c.
That compares the whole second-order term with the step; a Newton step multiplies only its
part along the soft modes by 1/(1 - mu) (docs/decisions/0028-soft-part-of-newton-model.md).
With --radius K --split, the modes come from the 50 largest eigenpairs of the analytic J
(ARPACK), each second difference is split into its part along their span and the rest
(SoftSplit, bench/soft_split.py), and exact Newton steps are taken along the slowest mode
(newton_steps). With --spread, the reference is also computed in child processes with 1 and
with 2 solver threads, and the two end points compared (round-off differs between them,
nothing else).

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_spectrum.py [--steps 100] [--spread]
        [--cells koala:lift:edge:1,head:lift:edge:0.5,spot.obj:lift:edge:1] [--radius 3]
        [--split [50]] [--json bench/results/spectrum.json]
Writes bench/results/spectrum.json (--radius 3: newton_radius.json; --split:
newton_soft_split.json, as the page's commands say); bench/report.py puts the tables into
docs/benchmarks_solver.md.
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
from soft_split import (NewtonSolve, SOFT_COUNT, SOLVE_TOLERANCE, SoftProjection,  # noqa: E402
                        projection_at, soft_eigenpairs)

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
# --split's Newton steps start this far along the slowest mode (/ diag: three decades across
# record 0026's h*, 1.4e-4 on the koala, 9e-3 on the 829-vertex Spot), straight or after
# this many plain steps (which remove the stiff error a straight step puts on a turning part).
NEWTON_FROM = (3e-4, 3e-3, 1e-2, 3e-2)
VALLEY_STEPS = 20
LINE_SEARCH_HALVINGS = 6   # at lambda = 1: step lengths 1 ... 1/64 tried on the energy


def mesh_path(name):
    """"koala", a sample's short name (bench_convergence.SAMPLES: "spot" is the 829-vertex
    sample) or a benchmark mesh's file name as the other scripts take it ("spot.obj": the
    11.5k Spot of bench/meshes)."""
    if name == "koala":
        return find_mesh("koala.obj")
    return find_mesh(SAMPLES[name] if name in SAMPLES else name)


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


def second_difference(G, x, free, v, h, g0):
    """G(x + hv) + G(x - hv) - 2 G(x) over the free rows (v: (#free, 3), g0 = G(x))."""
    plus, minus = x.copy(), x.copy()
    plus[free] += h * v
    minus[free] -= h * v
    return (G(plus) + G(minus) - 2.0 * g0)[free]


def model_radius(G, x, free, dg, mu, v, coords, split=None, compare=False):
    """Along v (free coordinates, scaled to max row |v| = dg): the second difference's
    constant c per step of RADIUS_STEPS and h* = 2 |1 - mu| / c (/ diag), see the docstring.
    The same in rotation coordinates (coords: rotation_coordinates.RotationCoordinates at
    x) along v's direction there, with steps that turn no term by more than ROTATION_TURN,
    and how much each term's rotation turns per diagonal moved along v (median, 99.9th
    percentile, largest). With split (a SoftSplit), also the second differences' soft and
    other parts (--split; compare: also the least-squares split's, SoftSplit.of_differences)."""
    v = v.reshape(-1, 3)
    v = v * (dg / np.linalg.norm(v, axis=1).max())
    g0 = G(x)
    differences = {h: second_difference(G, x, free, v, h, g0) for h in RADIUS_STEPS}
    gap = float(abs(1.0 - mu))
    curvature, radius = curvature_and_radius(lambda h: largest_row(differences[h]) / dg,
                                             RADIUS_STEPS, gap, 1.0)
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
    if split is not None:
        out["split"] = split.of_differences(differences, gap, dg, compare=compare)
    return out


class SoftSplit:
    """--split at the reference X: the soft modes (the `count` largest eigenpairs of the
    analytic J_G, soft_split.soft_eigenpairs), the A-orthogonal projection onto them
    (soft_split.projection_at; spectral at lambda = 1) and (I - J)^-1 (soft_split.NewtonSolve).
    of_differences splits a mode's second differences."""

    def __init__(self, d, X, free, lam, count, log):
        if not np.array_equal(np.asarray(d.free_vertices), np.flatnonzero(free)):
            raise SystemExit("Deformer.free_vertices is not the free mask's order")
        self.mu, self.vectors, spectrum = soft_eigenpairs(d, X, count, log)
        self.projection, basis, chosen = projection_at(d, X, lam, self.vectors)
        self.least_squares = SoftProjection(basis)
        self.solve = NewtonSolve(d, X, self.projection)
        mod = np.abs(self.mu)
        self.residuals = spectrum["ritz_residuals"]
        self.summary = dict(chosen, count=len(self.mu), rank=self.projection.rank,
                            largest=float(mod[0]), smallest=float(mod[-1]),
                            ritz_residual_max=float(max(spectrum["ritz_residuals"])),
                            products=spectrum["products"], seconds=spectrum["seconds"])

    def modes(self, count):
        """Indices of the `count` largest real modes or complex pairs (one index a pair)."""
        return [i for i in range(len(self.mu)) if self.mu[i].imag >= 0][:count]

    def amplified(self, s, projection, dg, h):
        """|(I - J)^-1 P s|, |(I - J)^-1 (s - P s)| and |(I - J)^-1 s| / (dg h^2) for the split
        of `projection`, the commutator |(I - J)^-1 P s - P (I - J)^-1 s| / |(I - J)^-1 s|
        (0 for a spectral split), and the solves' statistics."""
        soft, rest = projection.split(s)
        (a_soft, soft_stats), (a_rest, rest_stats) = self.solve(soft), self.solve(rest)
        whole = a_soft + a_rest

        def constant(a):
            return largest_row(a) / dg / h ** 2
        return {"soft": constant(a_soft), "rest": constant(a_rest), "whole": constant(whole),
                "radius": 2.0 / constant(whole),
                "commutator": largest_row(a_soft - projection.soft(whole)) / largest_row(whole),
                "solve_iterations": max(soft_stats["iterations"], rest_stats["iterations"]),
                "solve_residual": max(soft_stats["residual"], rest_stats["residual"])}

    def of_differences(self, differences, gap, dg, compare=False):
        """For second differences s(h) (RADIUS_STEPS) along a mode with |1 - mu| = gap: the
        constants (/ diag, largest row, like c) of the soft part P s and of the rest at each
        step, h*_soft = 2 gap / c_soft, the share of s in the soft part (A norm), and at the
        first step the amplified figures (amplified()): a Newton step from x* + hv leaves the
        error -1/2 (I - J)^-1 s(h) to second order, smaller than h while
        h < 2 / c_amplified ('radius'). With compare, also the amplified figures of the
        Euclidean least-squares split."""
        parts = {h: self.projection.split(s) for h, s in differences.items()}
        inner = self.projection.inner
        out = {"soft_share": [inner(parts[h][0], parts[h][0]) / inner(s, s)
                              for h, s in differences.items()]}
        for k, (name, scale) in enumerate((("soft", gap), ("rest", gap))):
            c, radius = curvature_and_radius(lambda h: largest_row(parts[h][k]) / dg,
                                             RADIUS_STEPS, scale, 1.0)
            out[name] = {"curvature": c, "radius": radius}
        h = RADIUS_STEPS[0]
        out["amplified"] = self.amplified(differences[h], self.projection, dg, h)
        if compare:
            out["least_squares"] = self.amplified(differences[h], self.least_squares, dg, h)
        return out


def energy_line_search(d, X, free, dg, x0, delta, after_plain):
    """At lambda = 1, from x0 along the Newton step delta: E - E* (E* = E(X)) before, after
    the full step and after the plain step that follows it (after_plain); the first step
    length of 1, 1/2, ... 1/2^LINE_SEARCH_HALVINGS that lowers E (0: none) and the distance
    to X (/ diag) there."""
    def energy(x):
        return float(d.energy(x))

    def moved(alpha):
        x = x0.copy()
        x[free] += alpha * delta
        return x
    star, e0 = energy(X), energy(x0)
    out = {"energy_before": e0 - star, "energy_after": energy(moved(1.0)) - star,
           "energy_after_plain": energy(after_plain) - star, "accepted_step": 0.0,
           "after_accepted": largest_row((x0 - X)[free]) / dg}
    for k in range(LINE_SEARCH_HALVINGS + 1):
        x = moved(0.5 ** k)
        if energy(x) < e0:
            out.update(accepted_step=0.5 ** k, after_accepted=largest_row((x - X)[free]) / dg)
            break
    return out


def newton_steps(d, G, X, free, dg, v, lam, projection, log):
    """One exact Newton step (I - J(x0)) delta = -(x0 - G(x0)), solved by GMRES (soft_split)
    from x0 = x* + h v (v the slowest mode, max row one diagonal; h per NEWTON_FROM) and from
    x0 = G^VALLEY_STEPS(x* + h v) (the stiff error a straight step along a turning part puts
    on it removed by plain steps: near the valley floor, where iterates are). Per start:
    the distances (/ diag, largest row) to x* before, after the full step, and after one plain
    step more; the soft part of the error before and after the step; at lambda = 1, what a
    line search on the energy does with the step (energy_line_search)."""
    v = v.reshape(-1, 3) * (dg / np.linalg.norm(v.reshape(-1, 3), axis=1).max())
    rows = []
    for start in ("line", "valley"):
        for h in NEWTON_FROM:
            x0 = X.copy()
            x0[free] += h * v
            for _ in range(VALLEY_STEPS if start == "valley" else 0):
                x0 = G(x0)
            g0 = G(x0)
            delta, stats = NewtonSolve(d, x0, projection)((g0 - x0)[free])
            x1 = x0.copy()
            x1[free] += delta
            error = (x1 - X)[free]
            row = {"start": start, "h": h, "before": largest_row((x0 - X)[free]) / dg,
                   "before_soft": largest_row(projection.soft((x0 - X)[free])) / dg,
                   "after": largest_row(error) / dg,
                   "after_soft": largest_row(projection.soft(error)) / dg,
                   "after_plain": largest_row((G(x1) - X)[free]) / dg,
                   "solve_iterations": stats["iterations"], "solve_residual": stats["residual"]}
            if lam == 1.0:
                row.update(energy_line_search(d, X, free, dg, x0, delta, G(x1)))
            log(json.dumps(row))
            rows.append(row)
    return rows


def child_reference(cell_text, threads, out):
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    subprocess.run([sys.executable, __file__, "--reference-only", cell_text, "--out", out],
                   env=env, check=True)
    z = np.load(out)
    return z["X"], int(z["iterations"]), float(z["residual"])


def run_cell(ed, cell_text, steps, spread, log, radius=0, split=0):
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
    if radius and split:
        # The modes and the soft subspace from ARPACK's converged eigenpairs (SoftSplit).
        coords = RotationCoordinates(d, X)
        t_split = time.time()
        soft = SoftSplit(d, X, free, float(lam), split, log)
        row["soft"] = soft.summary
        row["model_radius"] = []
        for k, i in enumerate(soft.modes(radius)):
            m = model_radius(G, X, free, dg, soft.mu[i], soft.vectors[i].real, coords, soft,
                             compare=k == 0)
            row["model_radius"].append(dict(m, modulus=float(abs(soft.mu[i])),
                                            arnoldi_residual=float(soft.residuals[i])))
            log(json.dumps(row["model_radius"][-1]))
        row["newton_steps"] = newton_steps(d, G, X, free, dg, soft.vectors[0].real, float(lam),
                                           soft.projection, log)
        row["split_s"] = time.time() - t_split
    elif radius:
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


def radius_text(value):
    return "–" if value is None else f"{value:.1e}"


def constants(values):
    return " / ".join(f"{c:.2g}" for c in values)


def radius_markdown(result):
    """The --radius table (docs/benchmarks_solver.md has it as a section of its own)."""
    radius = radius_text
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


def split_markdown(result):
    """The --split tables (docs/benchmarks_solver.md: "Which part of the second-order term
    limits a Newton step?")."""
    rows = [r for r in result["rows"] if r.get("soft")]
    if not rows:
        return "No cell of this run was measured with --split."
    steps = " and ".join(f"{h:g}" for h in RADIUS_STEPS)
    lines = [
        "The soft subspace at each cell's reference (x*): the largest eigenpairs of the "
        "analytic J_G (ARPACK; 'residual' = the largest |Jv − μv| / |v| among them), spanned by "
        "their real and imaginary parts. A second difference s is split A-orthogonally "
        "(P s: its part along the soft subspace): at λ = 1, J = A⁻¹D with A, D symmetric is "
        "self-adjoint in the A inner product, so P is the spectral projector onto those modes; "
        "at λ < 1 it is not quite ('asymmetry' = |⟨u, Jw⟩_A − ⟨Ju, w⟩_A| / (|Ju|_A |w|_A) on "
        "random u, w). A = the global step's matrix, checked against the core's K v = A(I − J)v "
        "('A check').",
        "",
        "| cell | eigenpairs (rank) | moduli, largest – smallest | residual | A check | "
        "asymmetry | products, s |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        s = r["soft"]
        lines.append(f"| {cell_label(r)} | {s['count']} ({s['rank']}) | {s['largest']:.5f} – "
                     f"{s['smallest']:.4f} | {s['ritz_residual_max']:.0e} | "
                     f"{s['a_identity_error']:.0e} | {s['asymmetry']:.0e} | "
                     f"{s['products']:,}, {s['seconds']:.0f} |")
    lines += [
        "",
        "Along each of the slowest eigenvectors v (max row |v| = one diagonal): the second "
        f"difference s(h) = G(x*+hv) + G(x*−hv) − 2G(x*) at h = {steps} of the diagonal, whole "
        "(c, as record 0026), its soft part P s (c_soft) and the rest s − P s (c_rest), each "
        "|·| / h² (largest vertex row, / diag; the same at both steps: a true second "
        "derivative). h* = 2(1 − μ)/c, h*_soft = 2(1 − μ)/c_soft. 'soft share' = |P s|²_A / "
        "|s|²_A. Amplified: a Newton step from x* + hv leaves the error −½ (I − J)⁻¹ s(h) to "
        "second order, so |(I − J)⁻¹ P s| / h² and |(I − J)⁻¹ (s − P s)| / h² (GMRES on the "
        f"analytic J to {SOLVE_TOLERANCE:g}, first step) are that error's soft and other "
        "constants, and "
        "2 / |(I − J)⁻¹ s| h² (whole) is how far along v a Newton step still shrinks the "
        "error, to second order. 'commutator' = |(I − J)⁻¹ P s − P (I − J)⁻¹ s| / |(I − J)⁻¹ s| "
        "(0 for a spectral split).",
        "",
        "| cell | modulus | 1 − μ | c | c_soft | c_rest | soft share | h* / diag | "
        "h*_soft / diag | h*_soft / h* | amplified: soft / rest | 2 / amplified / diag | "
        "commutator |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        for m in r["model_radius"]:
            sp = m["split"]
            ratio = (f"{sp['soft']['radius'] / m['radius']:.0f}"
                     if sp["soft"]["radius"] and m["radius"] else "–")
            lines.append(
                f"| {cell_label(r)} | {m['modulus']:.5f} | {m['gap']:.1e} | "
                f"{constants(m['curvature'])} | {constants(sp['soft']['curvature'])} | "
                f"{constants(sp['rest']['curvature'])} | {sp['soft_share'][0]:.1e} | "
                f"{radius_text(m['radius'])} | {radius_text(sp['soft']['radius'])} | {ratio} | "
                f"{sp['amplified']['soft']:.2g} / {sp['amplified']['rest']:.2g} | "
                f"{radius_text(sp['amplified']['radius'])} | {sp['amplified']['commutator']:.0e} |")
    lines += [
        "",
        "The same amplified constants with a Euclidean least-squares split instead (slowest "
        f"mode, h = {RADIUS_STEPS[0]:g}): not spectral, its parts cancel.",
        "",
        "| cell | amplified: soft / rest / whole | commutator |",
        "|---|---|---|",
    ]
    for r in rows:
        ls = r["model_radius"][0]["split"]["least_squares"]
        lines.append(f"| {cell_label(r)} | {ls['soft']:.2g} / {ls['rest']:.2g} / {ls['whole']:.2g} "
                     f"| {ls['commutator']:.1f} |")
    lines += [
        "",
        "One exact Newton step (I − J(x₀)) δ = −(x₀ − G(x₀)) (GMRES on the analytic J at x₀, "
        f"to {SOLVE_TOLERANCE:g}) along the slowest eigenvector: from x₀ = x* + hv ('line'), "
        f"or that point after {VALLEY_STEPS} plain steps ('valley': the stiff error a straight step along a "
        "turning part adds is gone, as near the iterates). Distances to x* / diag (largest "
        "row; in brackets the error's soft part P): before, after the full step, and after "
        "one plain step more. At λ = 1: E − E* before, after the full step and after the plain "
        f"step that follows it; the first of 1, ½, … 1/{2 ** LINE_SEARCH_HALVINGS} that "
        "lowers E ('step kept') and the distance there.",
        "",
        "| cell | start | h / diag | before (soft part) | after the step (soft part) | after a "
        "plain step more | E − E*: before → after → after the plain step | step kept: "
        "distance | GMRES iterations |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        for n in r["newton_steps"]:
            energy, kept = "–", "–"
            if "energy_before" in n:
                energy = (f"{n['energy_before']:.1e} → {n['energy_after']:.1e} → "
                          f"{n['energy_after_plain']:.1e}")
                kept = f"{n['accepted_step']:g}: {n['after_accepted']:.1e}"
            lines.append(
                f"| {cell_label(r)} | {n['start']} | {n['h']:g} | {n['before']:.1e} "
                f"({n['before_soft']:.1e}) | {n['after']:.1e} ({n['after_soft']:.1e}) | "
                f"{n['after_plain']:.1e} | {energy} | {kept} | {n['solve_iterations']} |")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cells", default=DEFAULT_CELLS, help="mesh:edit:domain:lambda,...")
    ap.add_argument("--steps", type=int, default=100, help="Arnoldi steps per cell")
    ap.add_argument("--radius", type=int, default=0,
                    help="for this many of the largest Ritz pairs, how far Newton's model holds")
    ap.add_argument("--split", type=int, nargs="?", const=SOFT_COUNT, default=0,
                    help="with --radius: take the modes from this many (default "
                         f"{SOFT_COUNT}) eigenpairs of the analytic J_G, split each second "
                         "difference into its part along their span and the rest, and take "
                         "exact Newton steps along the slowest (see SoftSplit)")
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
    Path(args.json).parent.mkdir(parents=True, exist_ok=True)
    for cell_text in args.cells.split(","):
        result["rows"].append(run_cell(ed, cell_text, args.steps, args.spread,
                                       lambda s: print(s, flush=True), args.radius, args.split))
        Path(args.json).write_text(json.dumps(result, indent=1))  # after each cell: a long
        # run that is stopped keeps the cells it finished
    print(markdown(result))
    print(radius_markdown(result))
    if args.split:
        print(split_markdown(result))


if __name__ == "__main__":
    main()
