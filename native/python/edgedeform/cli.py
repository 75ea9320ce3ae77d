"""Command line for batch deformation outside Blender.

    python3 -m edgedeform deform MESH --constraints C.json --out OUT.obj [options]

(`python3 -m edgedeform deform --help` lists the options with the core's defaults.)

C.json: {"handles": [...], "static": [...], "roi": null or [...],
         "handle_targets": [[x, y, z], ...]}   (targets in the order of handles)

On success: writes OUT and prints one line of JSON. Only the positions change: OUT keeps
MESH's vertex order, faces (quads, n-gons), texture coordinates, colours, groups and
materials; normals are recomputed. The report's "notes" say what was recomputed, or what
OUT's format cannot carry when it differs from MESH's.
On bad input: one message on stderr, exit status 1, no output file, no traceback.
"""

import argparse
import json
import math
import os
import sys
import time

import numpy as np

from . import ACCELERATIONS, SOLVE_DEFAULTS, SOLVE_INT_RANGES, Deformer, build_info, mesh_files

EXIT_BAD_INPUT = 1

# The one-line JSON report, key by key in the order it is printed, with what each means
# (docs/api.md's table is generated from this; a test checks that the report has these keys).
REPORT_FIELDS = {
    "vertices": "mesh vertices",
    "nodes": "graph nodes: the mesh's edges in the edge domain, its vertices in the primal one",
    "domain": '"edge" or "primal"',
    "factor_ms": "assembly + factorization, ms",
    "iterations": "iterations taken",
    "ms_per_iteration": "their mean time (local step, right-hand side, back-substitution), ms",
    "energies": "per iteration, as `SolveResult.energies`",
    "residuals": "per iteration, as `SolveResult.residuals`",
    "converged": "as `SolveResult.converged`",
    "distance_estimate": "as `SolveResult.distance_estimate`; null when unknown",
    "acceleration": 'the method that ran, as `SolveResult.method` ("lbfgs", "anderson" or "none": '
                    '"auto" resolved)',
    "free_vertices": "vertices the solve could move",
    "wall_ms": "wall time of the solve: factorization and iterations, not reading or writing, ms",
    "warnings": "as `SolveResult.warnings` (not converged, vertices kept at rest, unwelded seams, ...)",
    "notes": "what the output file could not carry unchanged: recomputed normals, data another "
             "format has no place for",
    "welded_copies": "vertices `--weld` merged (0 without it)",
}


class InputError(ValueError):
    """Bad command-line input; the message is shown to the user as is."""


def _program_name():
    name = os.path.basename(sys.argv[0]) if sys.argv and sys.argv[0] else ""
    return "edgedeform" if name == "edgedeform" else "python3 -m edgedeform"


def _version():
    info = build_info()
    openmp = f"OpenMP {info['threads']} threads" if info["openmp"] else "no OpenMP"
    return (f"edgedeform {info['version']} ({info['solver']}, {openmp}, Python "
            f"{sys.version.split()[0]})")


def _int_in_range(option):
    """An argparse type: an integer inside the core's range for solve's `option`, else a
    usage error that names the command-line option and the range."""
    low, high = SOLVE_INT_RANGES[option]

    def parse(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"must be an integer in [{low}, {high}], got {text}")
        return value
    return parse


def _parser(prog=None):
    """The parser; `.commands` holds each subcommand's own parser (docs/api.md's tables are
    made from them). The solve options' defaults and choices are the core's (SOLVE_DEFAULTS)."""
    solve = SOLVE_DEFAULTS
    p = argparse.ArgumentParser(
        # "edgedeform" when run as the console script, "python3 -m edgedeform" otherwise.
        prog=prog or _program_name(),
        description="Edge-based graph mesh deformation (batch).")
    p.add_argument("--version", action="version", version=_version(),
                   help="the package's version and how its core was built, then exit")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    d = sub.add_parser("deform", help="deform a mesh with handle/static constraints")
    d.add_argument("mesh", metavar="MESH", help="input mesh (.obj, .off, .ply)")
    d.add_argument("--constraints", required=True, metavar="C.json",
                   help='{"handles", "static", "roi", "handle_targets"}')
    d.add_argument("--out", required=True, metavar="OUT", help="output mesh (.obj, .off, .ply)")
    d.add_argument("--domain", choices=("edge", "primal"), default="edge",
                   help="graph nodes at the edges' midpoints (the paper's method) or at the vertices "
                        "(default %(default)s)")
    lam = d.add_mutually_exclusive_group()
    lam.add_argument("--stiffness", type=float, default=None, metavar="LAMBDA",
                     help="global stiffness in [0,1] (default: the Deformer's, 0.5 everywhere)")
    lam.add_argument("--stiffness-file", default=None, metavar="FILE",
                     help="one stiffness value per vertex, whitespace separated")
    d.add_argument("--iterations", type=_int_in_range("max_iterations"), default=solve["max_iterations"],
                   metavar="N",
                   help="most local/global iterations (default %(default)s)")
    d.add_argument("--tolerance", type=float, default=solve["tolerance"], metavar="T",
                   help="stop when the estimated largest vertex distance to the fixed point is "
                        "below T times the bounding-box diagonal (default %(default)g)")
    d.add_argument("--acceleration", choices=ACCELERATIONS, default=solve["acceleration"],
                   help="how the fixed point is reached (default %(default)s); every method reaches "
                        "the same shapes (help(edgedeform.Deformer.solve) says how each does)")
    d.add_argument("--anderson-window", type=_int_in_range("anderson_window"), default=solve["anderson_window"],
                   metavar="M",
                   help="how many past iterates Anderson acceleration combines (default %(default)s)")
    d.add_argument("--roi-radius", type=float, default=None, metavar="R",
                   help="instead of the constraints' roi: the vertices within R (mesh units) of a "
                        "handle, as Blender's proportional editing")
    d.add_argument("--roi-connected", action="store_true",
                   help="with --roi-radius: measure along the mesh edges (Blender's Connected Only)")
    d.add_argument("--weld", action="store_true",
                   help="solve with vertices that share a position welded (unwelded seams); "
                        "every copy gets the welded position")
    p.commands = {"deform": d}
    return p


def _index_list(data, key, n, required):
    value = data.get(key)
    if value is None:
        if required:
            raise InputError(f"constraints: '{key}' is missing")
        return None
    if not isinstance(value, list):
        raise InputError(f"constraints: '{key}' must be a list of vertex indices")
    for v in value:
        # bool is an int in Python; a true/false index is a mistake, not vertex 1/0
        if isinstance(v, bool) or not isinstance(v, int):
            raise InputError(f"constraints: '{key}' must hold integers, found {v!r}")
        if v < 0 or v >= n:
            raise InputError(f"constraints: '{key}' index {v} out of range [0, {n})")
    return np.asarray(value, dtype=np.int64).reshape(-1)


def load_constraints(path, n):
    """Parse and check C.json against a mesh of n vertices."""
    try:
        with open(path, "r", encoding="utf-8") as fh:
            data = json.load(fh)
    except FileNotFoundError:
        raise InputError(f"constraints: {path}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"constraints: {path}: {exc}") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"constraints: {path}: invalid JSON ({exc})") from None
    if not isinstance(data, dict):
        raise InputError("constraints: top level must be a JSON object")
    unknown = set(data) - {"handles", "static", "roi", "handle_targets"}
    if unknown:
        raise InputError(f"constraints: unknown key(s) {sorted(unknown)}")
    handles = _index_list(data, "handles", n, required=True)
    if handles.size == 0:
        raise InputError("constraints: 'handles' is empty")
    static = _index_list(data, "static", n, required=False)
    static = np.zeros(0, dtype=np.int64) if static is None else static
    roi = _index_list(data, "roi", n, required=False)
    targets = data.get("handle_targets")
    if targets is None:
        raise InputError("constraints: 'handle_targets' is missing")
    try:
        T = np.array(targets, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError("constraints: 'handle_targets' must be a list of [x, y, z]") from None
    if T.ndim != 2 or T.shape[1] != 3:
        raise InputError(f"constraints: 'handle_targets' must be a list of [x, y, z], "
                         f"got shape {T.shape}")
    if len(T) != len(handles):
        raise InputError(f"constraints: {len(T)} handle_targets for {len(handles)} handles")
    if not np.all(np.isfinite(T)):
        raise InputError("constraints: 'handle_targets' contains NaN or inf")
    overlap = np.intersect1d(handles, static)
    if overlap.size:
        raise InputError(f"constraints: vertices {overlap[:5].tolist()} are both handle and static")
    return handles, static, roi, T


def load_stiffness(args, n):
    if args.stiffness_file is not None:
        try:
            lam = np.loadtxt(args.stiffness_file, dtype=np.float64, ndmin=1).reshape(-1)
        except (OSError, ValueError) as exc:
            raise InputError(f"stiffness file: {args.stiffness_file}: {exc}") from None
        if lam.shape != (n,):
            raise InputError(f"stiffness file: {lam.size} values for {n} vertices")
    elif args.stiffness is None:
        return None  # the Deformer's own default
    else:
        lam = float(args.stiffness)
    arr = np.atleast_1d(lam)
    if not np.all(np.isfinite(arr)) or arr.min() < 0.0 or arr.max() > 1.0:
        raise InputError("stiffness must lie in [0, 1] (and be finite)")
    return lam


def deform(args):
    if not math.isfinite(args.tolerance) or args.tolerance < 0:
        raise InputError("--tolerance must be a finite number >= 0")
    mesh_files.check_extension(args.out)  # fail before any work if OUT has an unknown extension
    mesh = mesh_files.read_mesh_file(args.mesh)
    V, F = mesh.vertices, mesh.triangles
    handles, static, roi, targets = load_constraints(args.constraints, len(V))
    lam = load_stiffness(args, len(V))

    d = Deformer(V, F, domain=args.domain, weld=args.weld)
    d.set_constraints(handles=handles, static=static, roi=roi, roi_radius=args.roi_radius,
                      roi_connected=args.roi_connected)
    if lam is not None:
        d.set_stiffness(lam)
    t0 = time.perf_counter()
    r = d.solve(targets, max_iterations=args.iterations, tolerance=args.tolerance,
                acceleration=args.acceleration, anderson_window=args.anderson_window)
    wall_ms = (time.perf_counter() - t0) * 1e3
    X = np.asarray(r.positions)
    if not np.all(np.isfinite(X)):
        raise InputError("the solve produced non-finite positions; nothing written")
    notes = mesh.write(args.out, X)

    its = int(r.iterations)
    loop_ms = float(r.local_ms + r.rhs_ms + r.solve_ms)
    report = {
        "vertices": int(d.n_vertices),
        "nodes": int(d.n_nodes),
        "domain": d.domain,
        "factor_ms": round(float(r.factor_ms), 3),
        "iterations": its,
        "ms_per_iteration": round(loop_ms / its, 3) if its else 0.0,
        "energies": [float(e) for e in r.energies],
        "residuals": [float(e) for e in r.residuals],
        "converged": bool(r.converged),
        "distance_estimate": (float(r.distance_estimate)
                              if math.isfinite(r.distance_estimate) else None),
        "acceleration": r.method,
        "free_vertices": int(r.free_vertices),
        "wall_ms": round(wall_ms, 3),
        "warnings": list(r.warnings),
        "notes": notes,
        "welded_copies": int(d.welded_copies),
    }
    return report


def main(argv=None):
    args = _parser().parse_args(argv)  # usage errors: argparse prints and exits 2
    try:
        report = deform(args)
    except KeyboardInterrupt:
        print("edgedeform: interrupted", file=sys.stderr)
        return 130
    except (InputError, ValueError, IndexError, OSError, RuntimeError) as exc:
        # Core errors (ValueError/IndexError/FactorizationError) name the problem already.
        print(f"edgedeform: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except Exception as exc:  # anything else still must not dump a traceback on users
        print(f"edgedeform: internal error: {type(exc).__name__}: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    for w in report["warnings"]:
        print(f"edgedeform: warning: {w}", file=sys.stderr)
    print(json.dumps(report, separators=(",", ":")))
    return 0
