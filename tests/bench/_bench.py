"""Shared by the benchmark smoke tests: paths, and running a bench script as a user does."""

import json
import math
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BENCH = ROOT / "bench"
BUILD = Path(os.environ.get("EDGEDEFORM_BUILD_DIR", ROOT / "build"))
sys.path.insert(0, str(BENCH))


def run(script, *args, timeout=300, env=None):
    """Runs bench/<script> with this Python and the build's package; fails with its output."""
    full = dict(os.environ, OMP_NUM_THREADS="1", **(env or {}))
    proc = subprocess.run([sys.executable, str(BENCH / script), *map(str, args)],
                          capture_output=True, text=True, timeout=timeout, env=full)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return proc.stdout


def load(path):
    return json.loads(Path(path).read_text())


def finite(*values):
    """Every value is a real, finite number (not None, not NaN, not infinite)."""
    return all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
               for v in values)
