"""The harness of bench_soft_modes.py d3: accelerations of the local/global map written in
Python on the package's two halves of one step (Deformer._local_fit, _global_step) and its
energy, so that each variant is measured in the same terms: global steps (evaluations of G)
until the iterate is within 1e-3 of the diagonal of a reference, and steps rejected.

Variants (all start as the core does: one global step with R = I, s = 1):
- positions: Anderson on the free positions with the core's safeguard at λ 1 (an accelerated
  point is kept only if E does not rise; else the plain step, history restarted);
- damped: the same, but 1/2 and 1/4 of the way from the plain to the accelerated point are
  tried before the plain step;
- rotations: Anderson on the fitted rotations (in the Lie algebra about a base, rebased when a
  rotation turns past 2 radians) and scales, the map (R, s) -> fit(global(R, s)); a limb that
  swings moves on its arc, linearly in these coordinates;
- judged after a plain step: each accelerated point is followed by a plain step and kept when
  E after that step is below E of the plain step from the current point (record 0028's rule);
- lbfgs: L-BFGS on E with H0 = (2A)^-1 and the longer-step line search of
  native/src/strategies/quasi_newton.cpp (a direction that fails at alpha = 1 gives way to
  the plain step at once).
"""

import numpy as np
from scipy.spatial.transform import Rotation

from soft_modes import system_matrix

GOAL = 1e-3
REGULARIZATION = 1e-10


class Anderson:
    """Anderson mixing of a fixed-point map (as native/src/strategies/anderson.cpp)."""

    def __init__(self, window):
        self.window = window
        self.reset()

    def reset(self):
        self.dF, self.dG, self.last_f, self.last_g = [], [], None, None

    def step(self, x, g):
        f = g - x
        if self.last_f is not None:
            norm = np.linalg.norm(f - self.last_f)
            if norm > 0:
                self.dF.append((f - self.last_f) / norm)
                self.dG.append((g - self.last_g) / norm)
                del self.dF[:-self.window], self.dG[:-self.window]
        self.last_f, self.last_g = f, g
        if not self.dF:
            return g, False
        F = np.stack(self.dF, 1)
        theta = np.linalg.solve(F.T @ F + REGULARIZATION * np.eye(F.shape[1]), F.T @ f)
        return g - np.stack(self.dG, 1) @ theta, True


class Problem:
    """G and E on the free vertices of Deformer d whose handles sit on their targets."""

    def __init__(self, d, V, handles, targets, X_ref):
        self.d, self.free = d, np.asarray(d.free_vertices)
        self.X = np.array(V, dtype=float)
        self.X[handles] = targets
        self.X_ref, self.diag = X_ref, float(np.linalg.norm(np.ptp(V, axis=0)))
        self.global_steps = 0

    def full(self, y):
        X = self.X.copy()
        X[self.free] = y
        return X

    def fit(self, y):
        R, s = self.d._local_fit(self.full(y))
        return np.asarray(R), np.asarray(s)

    def energy(self, y):
        return float(self.d.energy(self.full(y)))

    def glob(self, R, s):
        self.global_steps += 1
        return np.asarray(self.d._global_step(self.X, R, s))

    def near(self, y):
        return np.linalg.norm(y - self.X_ref[self.free], axis=1).max() / self.diag < GOAL

    def cold(self):
        """The first iterate, as the core's cold start: the global step with R = I, s = 1."""
        T = len(self.fit(self.X[self.free])[1])
        return self.glob(np.tile(np.eye(3), (T, 1, 1)), np.ones(T))


def positions(P, window, budget, damping=()):
    aa, stats = Anderson(window), {"accepted": 0, "rejected": 0}
    y = P.cold()
    R, s = P.fit(y)
    E = P.energy(y)
    while P.global_steps < budget:
        g = P.glob(R, s)
        if P.near(g):
            return P.global_steps, stats
        nxt, ok = aa.step(y.ravel(), g.ravel())
        taken = False
        if ok:
            for beta in (1.0,) + tuple(damping):
                candidate = g + beta * (nxt.reshape(y.shape) - g)
                if P.energy(candidate) <= E:
                    y, taken = candidate, True
                    stats["accepted"] += 1
                    break
            if not taken:
                stats["rejected"] += 1
                aa.reset()
        if not taken:
            y = g
        R, s = P.fit(y)
        E = P.energy(y)
    return None, stats


def rotations(P, window, budget, rebase=2.0):
    aa, stats = Anderson(window), {"accepted": 0, "rejected": 0}
    y = P.cold()
    current = P.fit(y)
    E = P.energy(y)
    base = Rotation.from_matrix(current[0])

    def coords(R, s):
        return np.concatenate([(Rotation.from_matrix(R) * base.inv()).as_rotvec().ravel(), s])

    u, pending, fallback = coords(*current), False, None
    while P.global_steps < budget:
        y = P.glob(*current)
        if P.near(y):
            return P.global_steps, stats
        fitted = P.fit(y)
        E_new = P.energy(y)
        if pending and not E_new <= E:  # the accelerated rotations raised E: their plain step instead
            stats["rejected"] += 1
            aa.reset()
            current, pending = fallback, False
            u = coords(*current)
            continue
        stats["accepted"] += pending
        E, fallback = E_new, fitted
        g = coords(*fitted)
        nxt, pending = aa.step(u, g)
        if pending:
            T = len(fitted[1])
            current = ((Rotation.from_rotvec(nxt[:3 * T].reshape(T, 3)) * base).as_matrix(),
                       np.clip(nxt[3 * T:], 0.25, 4.0))
            u = nxt
        else:
            current, u = fitted, g
        if not pending and np.abs(u[:-len(fitted[1])]).max() > rebase:
            base = Rotation.from_matrix(current[0])
            aa.reset()
            u = coords(*current)
    return None, stats


def judged_after_plain_step(P, window, budget):
    aa, stats = Anderson(window), {"accepted": 0, "rejected": 0}
    y = P.cold()
    R, s = P.fit(y)
    while P.global_steps < budget:
        g = P.glob(R, s)
        if P.near(g):
            return P.global_steps, stats
        fitted_g = P.fit(g)
        E_g = P.energy(g)
        nxt, ok = aa.step(y.ravel(), g.ravel())
        if ok:
            nxt = nxt.reshape(y.shape)
            after = P.glob(*P.fit(nxt))
            if P.near(after):
                return P.global_steps, stats
            aa.step(nxt.ravel(), after.ravel())  # the accelerated point's own pair
            if P.energy(after) <= E_g:
                stats["accepted"] += 1
                y = after
                R, s = P.fit(y)
                continue
            stats["rejected"] += 1
        y, (R, s) = g, fitted_g
    return None, stats


def lbfgs(P, window, budget, longest=64.0, armijo=1e-4):
    A = system_matrix(P.d, 1.0)
    stats = {"accepted": 0, "rejected": 0, "line_search_fits": 0}
    y = P.cold()
    R, s = P.fit(y)
    E = P.energy(y)
    F = P.glob(R, s) - y
    grad = -2.0 * (A @ F)
    pairs = []   # (s, y, H0 y)
    while P.global_steps < budget:
        if P.near(y + F):
            return P.global_steps, stats
        q, alphas = -grad.copy(), []
        for sv, yv, hy in reversed(pairs):
            a = np.sum(sv * q) / np.sum(yv * sv)
            alphas.append(a)
            q -= a * yv
        d = F.copy()
        for a, (_, _, hy) in zip(alphas, reversed(pairs)):
            d -= a * hy
        if pairs:
            d *= np.sum(pairs[-1][0] * pairs[-1][1]) / np.sum(pairs[-1][1] * pairs[-1][2])
        for a, (sv, yv, _) in zip(reversed(alphas), pairs):
            d += (a - np.sum(yv * d) / np.sum(yv * sv)) * sv
        slope = float(np.sum(grad * d))
        alpha, trial = 1.0, None
        if slope < 0:
            e = P.energy(y + d)
            if e <= E + armijo * slope:
                trial = e
                while True:   # longer while the parabola's minimum lies twice as far and E falls
                    c = (trial - E - slope * alpha) / alpha ** 2
                    longer = min(-slope / (2 * c) if c > 0 else np.inf, longest)
                    if not longer >= 2 * alpha:
                        break
                    stats["line_search_fits"] += 1
                    e2 = P.energy(y + longer * d)
                    if not e2 < trial:
                        break
                    alpha, trial = longer, e2
        if trial is None:   # the plain step; the pairs no longer help
            stats["rejected"] += 1
            pairs, step = [], F
        else:
            stats["accepted"] += 1
            step = alpha * d
        y_new = y + step
        R, s = P.fit(y_new)
        E = P.energy(y_new)
        F_new = P.glob(R, s) - y_new
        grad_new = -2.0 * (A @ F_new)
        sv, yv = y_new - y, grad_new - grad
        if np.sum(sv * yv) > 1e-10 * np.linalg.norm(sv) * np.linalg.norm(yv):
            pairs = (pairs + [(sv, yv, F - F_new)])[-window:]
        y, F, grad = y_new, F_new, grad_new
    return None, stats


VARIANTS = {"positions": positions, "damped": lambda P, w, b: positions(P, w, b, damping=(0.5, 0.25)),
            "rotations": rotations, "judged after a plain step": judged_after_plain_step, "lbfgs": lbfgs}


def run(variant, d, V, handles, targets, X_ref, window, budget):
    """(global steps to GOAL or None, the variant's counts)."""
    P = Problem(d, V, handles, targets, X_ref)
    return VARIANTS[variant](P, window, budget)
