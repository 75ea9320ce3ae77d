"""edgedeform on one benchmark problem (child of bench/bench_peers.py).

Runs against whatever the built package offers: when Deformer.solve accepts an
`acceleration` argument, the plain iteration is measured with acceleration="none" and the
accelerated one (--acceleration, "anderson" unless another method the build accepts is
named, e.g. "anderson") is measured too (iterations to eps from cold solves, and the live
update); otherwise only the plain iteration exists and is measured.

    PYTHONPATH=build/python:bench /usr/bin/python3 -m peers.run_edgedeform PROBLEM \
        --domain edge --stiffness 0.5 --out result.json
"""

import os
import time

import numpy as np

import edgedeform as ed

from peers.common import child_args, max_rss_mb, write_result
from peers.problem import load_problem
from peers.trajectory import max_distance, measure


def has_acceleration():
    """Whether this build's solve() takes `acceleration`: the native method's pybind11
    signature says so (a Python subclass may wrap it with *args, **kwargs)."""
    return any("acceleration" in (getattr(cls.__dict__.get("solve"), "__doc__", None) or "")
               for cls in ed.Deformer.__mro__)


class EdgeDeform:
    def __init__(self, p, domain, stiffness, acceleration):
        self.p, self.domain, self.stiffness = p, domain, stiffness
        self.extra = {"acceleration": acceleration} if acceleration else {}
        self.d, self.started = None, False

    def precompute(self):
        self.d = None
        t0 = time.perf_counter()
        d = ed.Deformer(self.p["V"], self.p["F"], domain=self.domain)
        d.set_constraints(handles=self.p["handles"], static=self.p["static"], roi=None)
        d.set_stiffness(self.stiffness)
        construct_ms = (time.perf_counter() - t0) * 1e3
        r = d.solve(self.p["targets"], max_iterations=1, tolerance=0.0, warm_start=False,
                    **self.extra)
        self.d = d
        return construct_ms + float(r.factor_ms)   # the one iteration is not precompute

    def start(self):
        self.started = False

    def step(self, k, targets=None):
        r = self.d.solve(self.p["targets"] if targets is None else targets, max_iterations=k,
                         tolerance=0.0, warm_start=self.started, **self.extra)
        self.started = True
        return r.positions


def accelerated_eps(p, domain, stiffness, ref, eps, budget, method):
    """Fewest iterations of a cold accelerated solve that land within eps * diag of the
    reference, and that solve's wall time (median of 3 cold solves of that length).

    Found in one pass: a cold solve of one iteration, continued one iteration per call
    (warm solves with unchanged targets continue the same accelerated iteration, so the
    k-th call's shape is that of a cold solve of k iterations). The earlier doubling and
    bisection over cold solves cost about four times as many iterations, which at 50k
    made this the longest part of the benchmark."""
    m = EdgeDeform(p, domain, stiffness, method)
    m.precompute()
    found = None
    for k in range(1, budget + 1):
        x = m.d.solve(p["targets"], max_iterations=1, tolerance=0.0, warm_start=k > 1,
                      acceleration=method).positions
        if max_distance(x, ref) <= eps * p["diag"]:
            found = k
            break
    if found is None:
        return None, None

    def cold_solve_ms():
        t0 = time.perf_counter()
        m.d.solve(p["targets"], max_iterations=found, tolerance=0.0, warm_start=False,
                  acceleration=method)
        return (time.perf_counter() - t0) * 1e3

    return found, float(np.median([cold_solve_ms() for _ in range(3)]))


def live_update_ms(method, p, updates=20):
    """One live update: the handles dragged a little, one warm-started iteration."""
    times = []
    for k in range(1, updates + 4):
        t0 = time.perf_counter()
        method.step(1, targets=p["targets"] + k * p["drag"])
        if k > 3:
            times.append((time.perf_counter() - t0) * 1e3)
    return float(np.median(times))


def main():
    args = child_args(__doc__.split("\n\n")[0], [
        (("--domain",), {"choices": ["edge", "primal"], "required": True}),
        (("--stiffness",), {"type": float, "required": True}),
        (("--acceleration",), {"default": "anderson",
                               "help": "the accelerated method measured beside the plain one"})]).parse_args()
    base_rss = max_rss_mb()
    p = load_problem(args.problem)
    has_acc = has_acceleration()
    plain = EdgeDeform(p, args.domain, args.stiffness, "none" if has_acc else None)
    out, ref = measure(plain, p["V"], p["diag"], args.ref_iterations, args.ref_tol, args.eps,
                       args.repeat, args.block)
    info = dict(ed.build_info())
    out.update(method=f"edgedeform_{args.domain}_{args.stiffness:g}", domain=args.domain,
               stiffness=args.stiffness, vertices=len(p["V"]), nodes=int(plain.d.n_nodes),
               version=f"edgedeform {getattr(ed, '__version__', '?')}",
               solver=str(info.get("solver", "?")),
               threads=int(os.environ.get("OMP_NUM_THREADS") or info.get("threads") or 0),
               acceleration_available=has_acc, base_rss_mb=base_rss)
    if has_acc:
        fast = EdgeDeform(p, args.domain, args.stiffness, args.acceleration)
        fast.precompute()
        out["live_update_ms"] = live_update_ms(fast, p)
        if out["ref_iterations"]:
            k, ms = accelerated_eps(p, args.domain, args.stiffness, ref, args.eps,
                                    out["ref_iterations"], args.acceleration)
            out.update(acc_eps_iterations=k, acc_solve_to_eps_ms=ms)
    else:
        out["live_update_ms"] = live_update_ms(plain, p)
    out["live_update_acceleration"] = args.acceleration if has_acc else "none (not in this build)"
    write_result(args.out, out)


if __name__ == "__main__":
    main()
