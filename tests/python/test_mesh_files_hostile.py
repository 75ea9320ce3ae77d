"""Hostile mesh files (tests/python/_hostile_files.py): each refused with MeshFormatError
naming the file, the format, the line or row and the problem, before anything of a declared
size is allocated; valid files with a byte-order mark or a comment that says "end_header"
read as the same mesh without them."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from edgedeform.mesh_files import MeshFormatError, read_mesh, read_mesh_file
from _hostile_files import BOM, HOSTILE, LARGE, VALID

HERE = Path(__file__).resolve().parent
ADDRESS_SPACE = 512 << 20      # the readers run under this limit (RLIMIT_AS)
PEAK_ABOVE_INTERPRETER = 100 << 20


def _write(tmp_path, name, ext, data):
    path = tmp_path / (name + ext)
    path.write_bytes(data)
    return path


@pytest.mark.parametrize("name", sorted(HOSTILE))
def test_hostile_file_refused_with_file_line_and_problem(tmp_path, name):
    ext, data, words = HOSTILE[name]
    path = _write(tmp_path, name, ext, data)
    with pytest.raises(MeshFormatError) as refused:
        read_mesh(path)
    message = str(refused.value)
    assert message.startswith(f"{path}: "), message
    assert words in message, message


@pytest.mark.parametrize("name", sorted(VALID))
def test_valid_file_with_an_oddity_reads_as_without_it(tmp_path, name):
    ext, data, plain = VALID[name]
    V, F = read_mesh(_write(tmp_path, name, ext, data))
    V0, F0 = read_mesh(_write(tmp_path, "plain", ext, plain))
    assert np.array_equal(V, V0) and np.array_equal(F, F0)
    assert len(V) == 3 and F.tolist() == [[0, 1, 2]]


@pytest.mark.parametrize("ext", [".obj", ".off", ".ply"])
def test_a_byte_order_mark_is_written_back(tmp_path, ext):
    name = {".obj": "obj_with_bom", ".off": "off_with_bom", ".ply": "ply_with_bom"}[ext]
    _, data, plain = VALID[name]
    mesh = read_mesh_file(_write(tmp_path, name, ext, data))
    out = tmp_path / ("out" + ext)
    mesh.write(out, mesh.vertices)
    assert out.read_bytes().startswith(BOM)
    assert read_mesh(out)[0].tolist() == mesh.vertices.tolist()


CHILD = r"""
import json, os, sys, time
limit = int(sys.argv[1])
if sys.platform != "win32":   # Windows has no RLIMIT_AS: there only the outcomes are checked
    import resource
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
from edgedeform.mesh_files import MeshFormatError, read_mesh

def peak_resident():
    # VmHWM, this process's own high-water mark (ru_maxrss keeps the parent's across exec);
    # None where there is no /proc (Windows, macOS)
    if not os.path.exists("/proc/self/status"):
        return None
    with open("/proc/self/status") as fh:
        return next(int(l.split()[1]) * 1024 for l in fh if l.startswith("VmHWM:"))

base = peak_resident()
report = {}
for path in sys.argv[2:]:
    t0 = time.perf_counter()
    try:
        read_mesh(path)
        outcome = "read"
    except MeshFormatError:
        outcome = "refused"
    except BaseException as exc:
        outcome = type(exc).__name__
    report[path] = [outcome, time.perf_counter() - t0]
peak = peak_resident()
print(json.dumps({"files": report, "peak_above_interpreter": None if base is None else peak - base}))
"""


def refuse_under_limit(tmp_path):
    """Every hostile file, the large ones too, read in one process whose address space is
    ADDRESS_SPACE."""
    paths = [str(_write(tmp_path, name, ext, data)) for name, (ext, data, _) in HOSTILE.items()]
    paths += [str(_write(tmp_path, name, ext, make())) for name, (ext, make) in LARGE.items()]
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    proc = subprocess.run([sys.executable, "-c", CHILD, str(ADDRESS_SPACE)] + paths,
                          capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


def test_hostile_files_refused_in_512_mb_within_100_mb(tmp_path):
    """Never by MemoryError: under a 512 MB address space every file is refused by name, and
    the process's peak resident memory grows by at most 100 MB over the interpreter's (the
    30 MB files included: their bytes and their text are most of it)."""
    report = refuse_under_limit(tmp_path)
    outcomes = {Path(p).stem: o for p, (o, _) in report["files"].items()}
    assert outcomes == {name: "refused" for name in list(HOSTILE) + list(LARGE)}
    if sys.platform.startswith("linux"):   # the limit and the peak are Linux's to measure
        assert report["peak_above_interpreter"] <= PEAK_ABOVE_INTERPRETER, report


@pytest.mark.timing
def test_each_hostile_file_refused_within_a_second(tmp_path):
    report = refuse_under_limit(tmp_path)
    assert all(o == "refused" for o, _ in report["files"].values()), report
    slow = {Path(p).stem: s for p, (_, s) in report["files"].items() if s > 1.0}
    assert not slow
