"""Iteration counts measured by the tests, printed at the end of the run (and written
as JSON to $EDGEDEFORM_COUNTS_JSON when set) for docs/benchmarks.md."""

COUNTS = []


def record(test, mesh, domain, lam, iterations, note=""):
    COUNTS.append({"test": test, "mesh": mesh, "domain": domain, "lambda": lam,
                   "iterations": iterations, "note": note})
