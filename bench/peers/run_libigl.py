"""libigl's ARAP (Python bindings, igl.arap_precomputation + igl.arap_solve) on one
benchmark problem (child of bench/bench_peers.py; runs in the venv of bench/setup_peers.sh).

Handles and static vertices are both in b (static ones at rest); one arap_solve with
max_iter = k runs k iterations from the positions it is given, starting with a rotation
fit, so the first iteration from the rest shape is the naive Laplacian solve.

    build/peers-venv/bin/python -m peers.run_libigl PROBLEM --energy spokes --out r.json
"""

import igl
import numpy as np

from peers.common import child_args, max_rss_mb, write_result
from peers.problem import load_problem
from peers.trajectory import measure

ENERGIES = {"spokes": igl.ARAP_ENERGY_TYPE_SPOKES,
            "spokes_and_rims": igl.ARAP_ENERGY_TYPE_SPOKES_AND_RIMS}


class LibiglArap:
    def __init__(self, p, energy):
        self.V = np.ascontiguousarray(p["V"], dtype=np.float64)
        self.F = np.ascontiguousarray(p["F"], dtype=np.int64)
        self.b = np.ascontiguousarray(np.concatenate([p["handles"], p["static"]]), dtype=np.int32)
        self.bc = np.ascontiguousarray(np.vstack([p["targets"], p["V"][p["static"]]]))
        self.energy = ENERGIES[energy]
        self.data, self.U = None, None

    def precompute(self):
        self.data = None
        data = igl.ARAPData()
        data.energy = self.energy
        data.max_iter = 1
        igl.arap_precomputation(self.V, self.F, 3, self.b, data)
        self.data = data
        return None

    def start(self):
        self.U = self.V.copy()

    def step(self, k):
        self.data.max_iter = k
        self.U = igl.arap_solve(self.bc, self.data, self.U)
        return self.U


def main():
    args = child_args(__doc__.split("\n\n")[0], [
        (("--energy",), {"choices": list(ENERGIES), "required": True})]).parse_args()
    base_rss = max_rss_mb()
    p = load_problem(args.problem)
    out, _ = measure(LibiglArap(p, args.energy), p["V"], p["diag"], args.ref_iterations,
                     args.ref_tol, args.eps, args.repeat, args.block)
    from importlib.metadata import version
    out.update(method=f"libigl_{args.energy}", vertices=len(p["V"]),
               version=f"libigl {version('libigl')}", base_rss_mb=base_rss)
    write_result(args.out, out)


if __name__ == "__main__":
    main()
