"""Every input the reader fuzzers found (tests/fuzz/readers/findings) and every seed they
start from, through the fuzzers' own oracle (tests/fuzz/readers/oracle.py) in a process
whose address space is 512 MB (where the platform can limit it): refused with a MeshFormatError naming the file, or read as a
mesh that survives being written and read again in every format."""

import json
import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
READERS = HERE.parent / "fuzz" / "readers"
ADDRESS_SPACE = 512 << 20

CHILD = r"""
import json, sys, tempfile
from pathlib import Path
limit = int(sys.argv[1])
if sys.platform != "win32":   # Windows has no RLIMIT_AS: there only the outcomes are checked
    import resource
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
import oracle, seeds
inputs = [(p.name, p.suffix, p.read_bytes()) for p in sorted(Path(sys.argv[2]).glob("*/*"))]
for ext in (".obj", ".off", ".ply"):
    inputs += [(name + ext, ext, data) for name, data in sorted(seeds.seeds(ext).items())]
outcomes = {}
for name, ext, data in inputs:
    try:
        outcomes[name] = oracle.check(data, ext)
    except BaseException as exc:
        outcomes[name] = f"{type(exc).__name__}: {exc}"
print(json.dumps(outcomes))
"""


def test_findings_and_seeds_keep_the_oracle_under_512_mb():
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    env["PYTHONPATH"] = os.pathsep.join([str(READERS), str(HERE), env.get("PYTHONPATH", "")])
    proc = subprocess.run([sys.executable, "-c", CHILD, str(ADDRESS_SPACE), str(READERS / "findings")],
                          capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 0, proc.stderr
    outcomes = json.loads(proc.stdout)
    kept = {p.name for p in (READERS / "findings").glob("*/*")}
    assert kept <= set(outcomes) and len(kept) >= 3
    broken = {name: o for name, o in outcomes.items() if o not in ("read", "refused")}
    assert not broken, broken
