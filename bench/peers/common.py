"""Command line and output shared by the Python child programs."""

import argparse
import json


def child_args(description, extra=()):
    p = argparse.ArgumentParser(description=description)
    p.add_argument("problem", help="folder written by problem.write_problem")
    p.add_argument("--out", required=True, help="JSON result file")
    p.add_argument("--ref-iterations", type=int, default=2000)
    p.add_argument("--ref-tol", type=float, default=1e-4)
    p.add_argument("--eps", type=float, default=1e-3)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--block", type=int, default=10)
    for args, kwargs in extra:
        p.add_argument(*args, **kwargs)
    return p


def max_rss_mb():
    """Peak resident memory of this process so far (MB): VmHWM, the high-water mark of its
    own address space (getrusage's ru_maxrss also counts the parent's size at fork)."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024.0
    raise OSError("no VmHWM in /proc/self/status")


def write_result(path, result):
    result["vm_hwm_mb"] = max_rss_mb()
    with open(path, "w") as f:
        json.dump(result, f, indent=1)
