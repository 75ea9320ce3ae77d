#!/usr/bin/env python3
"""edgedeform against its peers: same meshes, same edits, one table of ratios.

Peers (each optional; a missing one is reported as skipped, with the reason):
CGAL Surface_mesh_deformation (ORIGINAL_ARAP, SPOKES_AND_RIMS; bench/cgal), libigl's ARAP
(Python bindings in build/peers-venv: spokes, spokes and rims) and Blender's Laplacian
Deform modifier (blender -b). bench/setup_peers.sh installs and builds them.

Ours: edge domain λ = 0.5 and primal domain λ = 1 (the ARAP energy with spokes, as CGAL's
ORIGINAL_ARAP and libigl's "spokes"). Edits "lift" and "twist" (bench/edits.py). Every
method runs in its own process (peak memory = that process's max RSS) and is measured the
same way (bench/peers/trajectory.py): precompute, ms per iteration, iterations and time to
within eps * diag of its own converged shape, and for ours one live update (a small drag,
one warm-started iteration, accelerated when the build has it) against a frame of Blender.

    bench/setup_peers.sh
    PYTHONPATH=build/python /usr/bin/python3 bench/bench_peers.py \
        [--sizes 4k,12k,50k,140k] [--edits lift,twist] [--peers edgedeform,cgal,libigl,blender]
        [--converge-sizes 4k,12k,50k] [--json bench/results/peers.json]

Prints a table, merges its rows into bench/results/peers.json and writes
bench/results/peers.png; bench/report.py puts the tables into docs/benchmarks.md.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))

from edits import EDITS, TWIST_DEGREES, accelerations, diagonal, mesh_path  # noqa: E402
from machine import machine_info  # noqa: E402
from peers.problem import write_problem  # noqa: E402
import peers_report  # noqa: E402

SIZES = {"4k": "cgal_dino.off", "12k": "spot.obj", "50k": "koala.obj",
         "140k": "nefertiti_loop1.ply"}
PEERS = ("edgedeform", "cgal", "libigl", "blender")
OURS = (("edge", 0.5), ("primal", 1.0))


def vm_hwm_mb(pid):
    """High-water mark of a live process's resident memory (MB), or None once it is gone."""
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        return None
    return None


def run_child(cmd, log, timeout, env=None):
    """Run one child to the end; returns (exit code, its peak RSS in MB, wall s).

    Peak RSS is the child's VmHWM, polled every 10 ms until it exits: the high-water mark
    of its own address space. (getrusage/wait4's ru_maxrss would not do: Linux carries the
    parent's RSS at fork over into the child's ru_maxrss, so every small child would
    report this Python process's size.)"""
    t0 = time.perf_counter()
    peak = 0.0
    with open(log, "w") as f:
        proc = subprocess.Popen([str(c) for c in cmd], stdout=f, stderr=subprocess.STDOUT,
                                env=env, stdin=subprocess.DEVNULL)
        while proc.poll() is None:
            peak = max(peak, vm_hwm_mb(proc.pid) or 0.0)
            if time.perf_counter() - t0 > timeout:
                proc.kill()
                proc.wait()
                f.write(f"\nbench_peers: killed after {timeout} s\n")
                break
            time.sleep(0.01)
    return proc.returncode, peak, time.perf_counter() - t0


class Peers:
    """Which peers this machine has, and how to start each child."""

    def __init__(self, args):
        self.args = args
        self.build = Path(args.build)
        self.skipped = {}
        self.env = dict(os.environ, PYTHONDONTWRITEBYTECODE="1", PYTHONPATH=os.pathsep.join(
            [str(self.build / "python"), str(HERE)]))

    def available(self, peer):
        reason = None
        if peer == "cgal" and not self.cgal_bin():
            reason = ("CGAL program not built (bench/setup_peers.sh builds it into "
                      "build/cgal-peer; or --cgal-bin)")
        elif peer == "libigl":
            py = self.venv_python()
            if not py.exists() or subprocess.run([str(py), "-c", "import igl"],
                                                 capture_output=True).returncode:
                reason = f"no libigl in {py.parent.parent} (bench/setup_peers.sh makes it)"
        elif peer == "blender" and not shutil.which(self.args.blender):
            reason = f"{self.args.blender} not found"
        if reason:
            self.skipped[peer] = reason
        return reason is None

    def cgal_bin(self):
        for c in ([self.args.cgal_bin] if self.args.cgal_bin else
                  [self.build / "cgal-peer" / "cgal_arap_bench",
                   self.build / "bench" / "cgal" / "cgal_arap_bench"]):
            if c and Path(c).is_file() and os.access(c, os.X_OK):
                return Path(c)
        return None

    def venv_python(self):
        return Path(self.args.venv or self.build / "peers-venv") / "bin" / "python"

    def commands(self, peer, folder, edit, ref_iterations, out):
        """[(method label, command, how its result comes back: 'file' or 'stdout',
        extra environment)]."""
        a = self.args
        common = ["--ref-iterations", ref_iterations, "--ref-tol", a.ref_tol, "--eps", a.eps,
                  "--repeat", a.repeat, "--block", a.block]
        if peer == "edgedeform":
            return [(f"edgedeform_{dom}_{lam:g}" + ("" if t == "default" else f"_t{t}"),
                     [sys.executable, "-m", "peers.run_edgedeform", folder, "--domain", dom,
                      "--stiffness", lam, "--acceleration", a.acceleration, "--out", out] + common, "file",
                     {} if t == "default" else {"OMP_NUM_THREADS": t})
                    for t in a.threads.split(",") for dom, lam in OURS]
        if peer == "cgal":
            return [(f"cgal_{name}", [self.cgal_bin(), folder / "mesh.off",
                                      folder / "constraints.txt", tag, ref_iterations,
                                      a.ref_tol, a.eps, a.repeat, a.block], "stdout", {})
                    for tag, name in (("arap", "original_arap"),
                                      ("spokes_and_rims", "spokes_and_rims"))]
        if peer == "libigl":
            return [(f"libigl_{e}", [self.venv_python(), "-m", "peers.run_libigl", folder,
                                     "--energy", e, "--out", out] + common, "file", {})
                    for e in ("spokes", "spokes_and_rims")]
        # Debian's Blender embeds the system Python, which finds its home through the
        # python3 on PATH: a pyenv there (as when ctest itself comes from pip) would hand it
        # another Python's standard library, without NumPy.
        path = os.pathsep.join(d for d in os.environ.get("PATH", "").split(os.pathsep)
                               if "/.pyenv/" not in d + "/")
        return [("blender_laplacian_deform",
                 [a.blender, "-b", "--factory-startup", "--python-exit-code", "1", "--python",
                  HERE / "peers" / "run_blender_ld.py", "--", folder, "--edit", edit,
                  "--out", out], "file", {"PATH": path})]


def run_method(peers, label, cmd, mode, extra_env, folder, timeout):
    out = folder / f"{label}.json"
    log = folder / f"{label}.log"
    out.unlink(missing_ok=True)
    with tempfile.TemporaryDirectory() as blender_home:   # never the user's Blender folders
        env = dict(peers.env, BLENDER_USER_SCRIPTS=blender_home, BLENDER_USER_CONFIG=blender_home,
                   **extra_env)
        cmd = [out if c == "OUT" else c for c in cmd]
        code, rss, wall = run_child(cmd, log, timeout, env)
    text = log.read_text(errors="replace")
    try:
        if code != 0:
            raise ValueError(f"exit code {code}")
        if mode == "stdout":
            result = json.loads([ln for ln in text.splitlines() if ln.startswith("{")][-1])
        else:
            result = json.loads(out.read_text())
    except (ValueError, IndexError, OSError) as e:
        tail = "\n".join(text.splitlines()[-8:])
        return {"method": label, "error": f"{e}; log {log}:\n{tail}"}
    # the child's own last reading of its high-water mark, when it gave one, closes the gap
    # between the driver's last poll and its exit
    result.update(method=label, peak_rss_mb=max(rss, result.get("vm_hwm_mb") or 0.0), wall_s=wall)
    return result


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--sizes", default=",".join(SIZES), help="comma list of " + ",".join(SIZES))
    p.add_argument("--mesh", action="append", default=[],
                   help="a mesh file to use instead of --sizes (repeatable; label = file name)")
    p.add_argument("--meshes", default=None,
                   help="folder of the size table's meshes (default: bench/meshes and the test data)")
    p.add_argument("--edits", default="lift,twist")
    p.add_argument("--peers", default=",".join(PEERS))
    p.add_argument("--converge-sizes", default="4k,12k,50k",
                   help="sizes that also get a converged reference and time to eps "
                        "(others: precompute, ms/it, memory only); 'all' or 'none'")
    p.add_argument("--ref-iterations", type=int, default=2000,
                   help="budget of the converged reference, per method")
    p.add_argument("--ref-tol", type=float, default=1e-4,
                   help="reference: estimated distance to the fixed point, / diag")
    p.add_argument("--eps", type=float, default=1e-3, help="time to within eps * diag")
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--block", type=int, default=10, help="iterations per ms/it sample")
    p.add_argument("--threads", default="default",
                   help="comma list of OpenMP thread counts to run edgedeform with; 'default' = "
                        "the package's own choice, e.g. 'default,1' (the peers are single-threaded)")
    p.add_argument("--timeout", type=float, default=3600, help="seconds per child")
    p.add_argument("--acceleration", default="anderson",
                   help="ours: the accelerated method measured beside the plain one (any the build "
                        "accepts, e.g. anderson)")
    p.add_argument("--build", default=str(ROOT / "build"))
    p.add_argument("--cgal-bin", default=None)
    p.add_argument("--venv", default=None, help="venv with libigl (default build/peers-venv)")
    p.add_argument("--blender", default="blender")
    p.add_argument("--work", default=None, help="problem files and logs (default build/peers-work)")
    p.add_argument("--json", default=str(HERE / "results" / "peers.json"))
    p.add_argument("--plot", default=str(HERE / "results" / "peers.png"),
                   help="PNG plot ('' for none)")
    args = p.parse_args(argv)

    import edgedeform as ed
    from edgedeform.mesh_files import read_mesh
    if args.acceleration not in accelerations(ed):
        p.error(f"--acceleration {args.acceleration}: this build has {', '.join(accelerations(ed))}")

    if args.mesh:
        meshes = [(Path(m).name, Path(m)) for m in args.mesh]
    else:
        for s in args.sizes.split(","):
            if s not in SIZES:
                p.error(f"unknown size {s!r} (known: {', '.join(SIZES)})")
        meshes = [(s, mesh_path(SIZES[s], args.meshes)) for s in args.sizes.split(",")]
    for _, path in meshes:
        if not path.is_file():
            p.error(f"mesh {path} not found (--meshes sets the folder)")
    edits = args.edits.split(",")
    for e in edits:
        if e not in EDITS:
            p.error(f"unknown edit {e!r} (known: {', '.join(EDITS)})")
    converge = set(args.converge_sizes.split(",")) if args.converge_sizes not in ("all", "none") \
        else args.converge_sizes
    peers = Peers(args)
    wanted = [x for x in args.peers.split(",") if x]
    for x in wanted:
        if x not in PEERS:
            p.error(f"unknown peer {x!r} (known: {', '.join(PEERS)})")
    active = [x for x in wanted if peers.available(x)]
    for x, why in peers.skipped.items():
        print(f"skipped {x}: {why}", flush=True)

    out = Path(args.json)
    result = json.loads(out.read_text()) if out.exists() else {"rows": []}
    cmd = "bench/bench_peers.py " + " ".join(argv if argv is not None else sys.argv[1:])
    result.update(machine=machine_info(), build_info=dict(ed.build_info()),
                  settings={k: getattr(args, k) for k in
                            ("ref_iterations", "ref_tol", "eps", "repeat", "block", "acceleration")},
                  skipped=peers.skipped,
                  commands=[c for c in result.get("commands", []) if c != cmd] + [cmd])
    work = Path(args.work or Path(args.build) / "peers-work")
    for label, path in meshes:
        V, F = read_mesh(path)
        for edit in edits:
            handles, static, targets, ax = EDITS[edit](V)
            drag = np.zeros(3)
            drag[ax] = 0.005 * diagonal(V)          # a live drag: small moves of the handles
            folder = write_problem(work / f"{path.stem}-{edit}", V, F, handles, static, targets,
                                   drag, up_axis=ax, twist_degrees=TWIST_DEGREES)
            ref_its = args.ref_iterations if converge == "all" or (
                converge != "none" and label in converge) else 0
            for peer in active:
                for method, command, mode, env in peers.commands(peer, folder, edit, ref_its, "OUT"):
                    row = run_method(peers, method, command, mode, env, folder, args.timeout)
                    row.update(size=label, mesh=path.name, vertices=len(V), faces=len(F),
                               edit=edit, handles=len(handles), static=len(static),
                               load_1min=os.getloadavg()[0])
                    peers_report.derive(row, args.eps)
                    key = (label, edit, method)
                    result["rows"] = [r for r in result["rows"]
                                      if (r["size"], r["edit"], r["method"]) != key] + [row]
                    print(peers_report.one_line(row), flush=True)
                    out.parent.mkdir(parents=True, exist_ok=True)
                    out.write_text(json.dumps(result, indent=1))     # keep partial results
    result["ratios"] = peers_report.ratios(result["rows"])
    out.write_text(json.dumps(result, indent=1))
    print()
    print(peers_report.method_table(result["rows"]))
    print()
    print(peers_report.ratio_table(result["ratios"], peers_report.PER_ITERATION_RATIOS))
    print()
    print(peers_report.ratio_table(result["ratios"], peers_report.OTHER_RATIOS))
    if args.plot:
        try:
            peers_report.plot(result, args.plot)
            print(f"\nplot: {args.plot}")
        except ImportError as e:     # matplotlib comes with bench/setup_peers.sh
            print(f"\nno plot ({e}); bench/setup_peers.sh installs matplotlib")


if __name__ == "__main__":
    main()
