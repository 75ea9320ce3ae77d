"""`pip install` of each built wheel, as a pipeline user does it, under NumPy 2 and 1.26.

    check_wheel.py WHEEL_DIR WORK_DIR MESH FIND_PYTHON

For each wheel (one per Python, scripts/build_wheel.sh) and each NumPy it must work with, a
fresh venv on that wheel's Python installs the wheel and NumPy from the package index:
- the newest NumPy (2.x: Blender 5.1+ and pip users), on every wheel;
- NumPy 1.26 (what Blender 4.2–5.0 bundle), where it exists (CPython <= 3.12).
In each, from a folder outside the checkout:
- `edgedeform` loads from the venv, with CHOLMOD from the wheel (auditwheel);
- per-iteration arrays: at lambda = 1 with plain local/global steps, `r.energies` and
  `r.residuals` hold one value per iteration, the energy never rises, and a solve stopped
  after k iterations reports exactly the first k values of a longer one (the NumPy-2 bug
  of pybind11 < 2.12 gave arrays whose elements all equalled the first);
- the mesh writers on NumPy scalars (writers_numpy_scalars.py);
- the CLI (`edgedeform` and `python -m edgedeform`) deforms MESH, writing OBJ, OFF and PLY,
  each read back by the CLI itself as the next input: the positions survive every trip.
FIND_PYTHON is scripts/find_python.sh (which interpreter is Python X.Y here).
"""

import glob
import json
import os
import shutil
import subprocess
import sys

wheel_dir, work, mesh, find_python = sys.argv[1], sys.argv[2], os.path.abspath(sys.argv[3]), \
    sys.argv[4]
here = os.path.dirname(os.path.abspath(__file__))
wheels = sorted(glob.glob(os.path.join(wheel_dir, "edgedeform-*.whl")))
assert wheels, "no wheel in " + wheel_dir
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}   # no build/python

SOLVE_CHECK = r"""
import numpy as np, edgedeform as ed, sys
from edgedeform import mesh_files
V, F = mesh_files.read_mesh(sys.argv[1])
x = V[:, 0]
span = x.max() - x.min()
h, s = np.flatnonzero(x > x.max() - 0.1 * span), np.flatnonzero(x < x.min() + 0.1 * span)
def solve(k):
    d = ed.Deformer(V, F)
    d.set_constraints(handles=h, static=s)
    d.set_stiffness(1.0)
    return d.solve(V[h] + [0, 0, 0.3], max_iterations=k, tolerance=0.0, acceleration="none",
                   warm_start=False)
long = solve(40)
E, R = np.asarray(long.energies), np.asarray(long.residuals)
assert long.iterations == 40 and E.shape == (40,) and R.shape == (40,), (long.iterations, E.shape, R.shape)
assert np.all(np.isfinite(E)) and np.all(np.isfinite(R)), (E, R)
assert np.all(np.diff(E) <= 1e-12 * E[0]), "energy rose at lambda = 1: %s" % E
assert E[-1] < 0.9 * E[0] and len(set(E.tolist())) > 30, "energies barely change: %s" % E
assert len(set(R.tolist())) > 30, "residuals barely change: %s" % R
for k in (1, 2, 7):
    short = solve(k)
    assert short.iterations == k and len(short.energies) == k and len(short.residuals) == k
    assert np.allclose(short.energies, E[:k], rtol=1e-12, atol=0), (k, short.energies, E[:k])
    assert np.allclose(short.residuals, R[:k], rtol=1e-12, atol=0), (k, short.residuals, R[:k])
print("numpy %s: energies %.6g -> %.6g over %d iterations, monotone; residuals %.3g -> %.3g"
      % (np.__version__, E[0], E[-1], len(E), R[0], R[-1]))
"""


def python_of(wheel):
    tag = os.path.basename(wheel).split("-")[2]          # cp311
    version = "%s.%s" % (tag[2], tag[3:])
    found = subprocess.run(["bash", find_python, version], capture_output=True, text=True)
    assert found.returncode == 0, "the %s wheel was built, but no Python %s is found now: %s" % (
        tag, version, found.stderr)
    return version, found.stdout.strip()


def numpy_specs(version):
    specs = [("newest", "numpy")]
    if tuple(int(x) for x in version.split(".")) <= (3, 12):   # 1.26 has no 3.13 build
        specs.append(("1.26", "numpy==1.26.*"))
    return specs


def run(*cmd, cwd=work):
    p = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True)
    assert p.returncode == 0, "%s failed (%d):\n%s\n%s" % (" ".join(cmd), p.returncode,
                                                         p.stdout, p.stderr)
    return p


def check_install(venv, python):
    site = run(python, "-c", "import edgedeform, os; print(os.path.realpath(edgedeform.__file__))")
    path = site.stdout.strip()
    assert path.startswith(os.path.realpath(venv)), path
    core, = glob.glob(os.path.join(os.path.dirname(path), "_core*.so"))
    ldd = run("ldd", core).stdout
    cholmod = [line for line in ldd.splitlines() if "libcholmod" in line]
    assert cholmod and all("edgedeform.libs" in line for line in cholmod), ldd


def constraints_for(python, folder):
    """A plane: the +x tenth lifted by 0.3, the -x tenth static."""
    V = json.loads(run(python, "-c", "import edgedeform.mesh_files as m, json, sys; "
                       "print(json.dumps(m.read_mesh(sys.argv[1])[0].tolist()))", mesh).stdout)
    xs = [v[0] for v in V]
    lo, hi = min(xs), max(xs)
    handles = [i for i, x in enumerate(xs) if x > hi - 0.1 * (hi - lo)]
    static = [i for i, x in enumerate(xs) if x < lo + 0.1 * (hi - lo)]
    path = os.path.join(folder, "c.json")
    with open(path, "w") as f:
        json.dump({"handles": handles, "static": static, "roi": None,
                   "handle_targets": [[V[i][0], V[i][1], V[i][2] + 0.3] for i in handles]}, f)
    return V, handles, static, path


def read_back(python, path):
    return json.loads(run(python, "-c", "import edgedeform.mesh_files as m, json, sys; "
                          "print(json.dumps(m.read_mesh(sys.argv[1])[0].tolist()))",
                          path).stdout)


def check_report(report):
    n = report["iterations"]
    E, R = report["energies"], report["residuals"]
    assert n >= 2 and len(E) == n and len(R) == n, report
    assert len(set(E)) > 1 and len(set(R)) > 1, "identical per-iteration values: %s" % report
    assert all(b <= a * (1 + 1e-12) for a, b in zip(E, E[1:])), "energy rose at lambda = 1: %s" % E


def check_cli(venv, python, folder):
    V, handles, static, constraints = constraints_for(python, folder)
    cli = [os.path.join(venv, "bin", "edgedeform")]
    args = ["--constraints", constraints, "--stiffness", "1", "--acceleration", "none"]
    # The mesh through every format: OFF -> OBJ -> PLY -> OFF, each output the next input.
    # From the second trip on the mesh is at rest with its targets met: nothing moves.
    source, first = mesh, None
    for i, ext in enumerate(("obj", "ply", "off")):
        out = os.path.join(folder, "trip%d.%s" % (i, ext))
        report = json.loads(run(*cli, "deform", source, *args, "--out", out)
                            .stdout.strip().splitlines()[-1])
        X = read_back(python, out)
        assert len(X) == len(V), (ext, len(X))
        if first is None:
            check_report(report)
            assert max(abs(X[i][2] - V[i][2] - 0.3) for i in handles) < 1e-5, "handles on target"
            assert max(abs(a - b) for i in static for a, b in zip(X[i], V[i])) < 1e-6, "static"
            first = X
        else:
            drift = max(abs(a - b) for p, q in zip(X, first) for a, b in zip(p, q))
            assert drift < 1e-6, "%s: positions moved by %g on a trip through %s" % (
                ext, drift, os.path.basename(source))
        source = out
    # `edgedeform` and `python -m edgedeform`: the same program, the same result.
    outputs = []
    for cmd in (cli, [python, "-m", "edgedeform"]):
        out = os.path.join(folder, "same_%d.obj" % len(outputs))
        report = json.loads(run(*cmd, "deform", mesh, *args, "--out", out)
                            .stdout.strip().splitlines()[-1])
        outputs.append((report, read_back(python, out)))
    (r1, x1), (r2, x2) = outputs
    assert x1 == x2 and r1["energies"] == r2["energies"], "edgedeform and python -m edgedeform differ"
    help1 = run(cli[0], "--help").stdout
    help2 = run(python, "-m", "edgedeform", "--help").stdout
    assert help1.startswith("usage: edgedeform ") and help2.startswith("usage: python3 -m edgedeform "), \
        (help1, help2)
    assert help1.replace("usage: edgedeform", "usage: PROG") == \
        help2.replace("usage: python3 -m edgedeform", "usage: PROG") and "deform" in help1


for wheel in wheels:
    version, base_python = python_of(wheel)
    for label, spec in numpy_specs(version):
        folder = os.path.join(work, "py%s-numpy-%s" % (version, label))
        os.makedirs(folder)
        venv = os.path.join(folder, "venv")
        run(base_python, "-m", "venv", venv)
        python = os.path.join(venv, "bin", "python")
        run(python, "-m", "pip", "install", "-q", "--no-cache-dir", wheel, spec)
        numpy = run(python, "-c", "import numpy; print(numpy.__version__)").stdout.strip()
        if label == "newest":
            assert int(numpy.split(".")[0]) >= 2, "the newest NumPy installed is " + numpy
        else:
            assert numpy.startswith("1.26."), numpy
        check_install(venv, python)
        print(run(python, "-c", SOLVE_CHECK, mesh, cwd=folder).stdout.strip())
        print(run(python, os.path.join(here, "writers_numpy_scalars.py"), cwd=folder)
              .stdout.strip().splitlines()[-1])
        check_cli(venv, python, folder)
        print("wheel OK: %s with NumPy %s (Python %s)" % (os.path.basename(wheel), numpy, version),
              flush=True)
