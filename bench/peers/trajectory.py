"""How every iterative method is measured (the CGAL program does the same in C++).

A method offers precompute() (everything before the first iteration, including the
factorization; returns its own ms or None for "time me"), start() (back to the rest shape
with the handle targets set) and step(k) (k more iterations; returns the (n, 3) positions).

- precompute: median of `repeat` fresh precomputes;
- ms/it: wall time of step(block) / block, `repeat` times; also the process's CPU time
  (all its threads), which load from other processes hardly changes;
- reference: its own converged shape: one iteration at a time from the start until the
  estimated distance to the fixed point is <= ref_tol * diag, at most ref_iterations. The
  estimate is r * rate / (1 - rate), r = the largest vertex move of the last iteration,
  rate = the median ratio of the last five successive moves (a geometric tail);
- eps_iterations: from the start again, iterations until every vertex is within
  eps * diag of the reference; time to eps = precompute + eps_iterations * ms/it.
"""

import time

import numpy as np


def max_distance(a, b):
    return float(np.sqrt(np.max(np.sum((a - b) ** 2, axis=1))))


def distance_estimate(residuals, window=5):
    """Estimated distance to the fixed point (/ diag) from the last moves, or None while
    the tail does not look contracting."""
    if len(residuals) <= window or residuals[-1] <= 0:
        return 0.0 if residuals and residuals[-1] == 0 else None
    tail = np.asarray(residuals[-window - 1:])
    rate = float(np.median(tail[1:] / np.maximum(tail[:-1], 1e-300)))
    return residuals[-1] * rate / (1 - rate) if rate < 1 else None


def reference(method, rest, diag, ref_iterations, ref_tol):
    method.start()
    prev, residuals = rest, []
    for _ in range(ref_iterations):
        x = method.step(1)
        residuals.append(max_distance(x, prev) / diag)
        prev = x
        est = distance_estimate(residuals)
        if est is not None and est <= ref_tol:
            break
    return prev, residuals


def iterations_to(method, ref, diag, eps, budget):
    method.start()
    for it in range(1, budget + 1):
        if max_distance(method.step(1), ref) <= eps * diag:
            return it
    return None


def measure(method, rest, diag, ref_iterations=2000, ref_tol=1e-4, eps=1e-3, repeat=3, block=10):
    pre, pre_cpu = [], []
    for _ in range(repeat):
        c0, t0 = time.process_time(), time.perf_counter()
        own = method.precompute()
        pre.append(own if own is not None else (time.perf_counter() - t0) * 1e3)
        pre_cpu.append((time.process_time() - c0) * 1e3)
    out = {"precompute_ms": float(np.median(pre)), "precompute_ms_all": pre,
           "precompute_cpu_ms": float(np.median(pre_cpu))}
    ref, residuals = reference(method, rest, diag, ref_iterations, ref_tol)
    est = distance_estimate(residuals)
    out.update(ref_iterations=len(residuals), ref_error_estimate=est,
               ref_converged=bool(est is not None and est <= ref_tol),
               residual_tail=residuals[-10:], eps_iterations=None)
    if residuals:
        out["eps_iterations"] = iterations_to(method, ref, diag, eps, len(residuals))
    it_ms, it_cpu = [], []
    for _ in range(repeat):
        c0, t0 = time.process_time(), time.perf_counter()
        method.step(block)
        it_ms.append((time.perf_counter() - t0) * 1e3 / block)
        it_cpu.append((time.process_time() - c0) * 1e3 / block)
    out.update(ms_per_it=float(np.median(it_ms)), ms_per_it_all=it_ms,
               cpu_ms_per_it=float(np.median(it_cpu)))
    return out, ref
