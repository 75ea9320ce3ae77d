"""`pip install` of the built wheel gives `import edgedeform` and an `edgedeform` command that
is the same CLI as `python -m edgedeform`.

    check_wheel.py WHEEL_DIR WORK_DIR MESH

A fresh venv in WORK_DIR (with the system's site packages, so numpy comes from
Debian and nothing is downloaded) installs the wheel; from a folder outside the checkout,
the package must load from the venv and both commands must deform MESH identically.
"""

import glob
import json
import os
import shutil
import subprocess
import sys

wheel_dir, work, mesh = sys.argv[1], sys.argv[2], os.path.abspath(sys.argv[3])
wheel, = glob.glob(os.path.join(wheel_dir, "edgedeform-*.whl"))
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
venv = os.path.join(work, "venv")
subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", venv], check=True)
python = os.path.join(venv, "bin", "python")
env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}   # no build/python
subprocess.run([python, "-m", "pip", "install", "-q", "--no-deps", "--no-index", wheel],
               check=True, env=env)


def run(*cmd):
    return subprocess.run(cmd, cwd=work, env=env, capture_output=True, text=True, check=True)


site = run(python, "-c", "import edgedeform, os; print(os.path.realpath(edgedeform.__file__))")
assert site.stdout.strip().startswith(os.path.realpath(venv)), site.stdout
print("import edgedeform ->", site.stdout.strip())
# Self-contained (auditwheel): the module loads CHOLMOD from the wheel, not from the system.
core, = glob.glob(os.path.join(os.path.dirname(site.stdout.strip()), "_core*.so"))
ldd = run("ldd", core).stdout
cholmod = [line for line in ldd.splitlines() if "libcholmod" in line]
assert cholmod and all("edgedeform.libs" in line for line in cholmod), ldd

# A plane: the +x tenth lifted, the -x tenth static.
V = run(python, "-c", "import edgedeform.mesh_files as m, json, sys; "
        "print(json.dumps(m.read_mesh(sys.argv[1])[0].tolist()))", mesh)
V = json.loads(V.stdout)
xs = [v[0] for v in V]
lo, hi = min(xs), max(xs)
handles = [i for i, x in enumerate(xs) if x > hi - 0.1 * (hi - lo)]
static = [i for i, x in enumerate(xs) if x < lo + 0.1 * (hi - lo)]
constraints = os.path.join(work, "c.json")
with open(constraints, "w") as f:
    json.dump({"handles": handles, "static": static, "roi": None,
               "handle_targets": [[V[i][0], V[i][1], V[i][2] + 0.3] for i in handles]}, f)

outputs = []
for cmd in ([os.path.join(venv, "bin", "edgedeform")], [python, "-m", "edgedeform"]):
    out = os.path.join(work, "out_%d.obj" % len(outputs))
    report = run(*cmd, "deform", mesh, "--constraints", constraints,
                 "--out", out)
    outputs.append((json.loads(report.stdout.strip().splitlines()[-1]), open(out).read()))
    print(" ".join(os.path.basename(c) for c in cmd), "->", report.stdout.strip())
(r1, mesh1), (r2, mesh2) = outputs


def vertices(obj_text):
    return [[float(x) for x in line.split()[1:4]] for line in obj_text.splitlines()
            if line.startswith("v ")]


assert vertices(mesh1) == vertices(mesh2), "edgedeform and python -m edgedeform differ"
assert r1["iterations"] == r2["iterations"] and r1["energies"] == r2["energies"], (r1, r2)
out = vertices(mesh1)
assert len(out) == len(V)
assert max(abs(out[i][2] - V[i][2] - 0.3) for i in handles) < 1e-5, "handles on target"
assert max(abs(a - b) for i in static for a, b in zip(out[i], V[i])) < 1e-6, "static kept"
help1 = run(os.path.join(venv, "bin", "edgedeform"), "--help").stdout
help2 = run(python, "-m", "edgedeform", "--help").stdout
# The same program; each names itself the way it was run.
assert help1.startswith("usage: edgedeform ") and help2.startswith("usage: python3 -m edgedeform "), \
    (help1, help2)
assert help1.replace("usage: edgedeform", "usage: PROG") == \
    help2.replace("usage: python3 -m edgedeform", "usage: PROG") and "deform" in help1, (help1, help2)
print("wheel OK:", os.path.basename(wheel))
