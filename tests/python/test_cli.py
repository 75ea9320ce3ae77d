"""python3 -m edgedeform deform ... (subprocess, as a user would run it)."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from edgedeform.mesh_files import read_mesh
from _meshes import DATA, PLANE, SPOT, diag, lift, load


def run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "edgedeform", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd, env=dict(os.environ),
                          timeout=120)


def write_constraints(path, handles, static, targets, roi=None, **extra):
    data = {"handles": [int(i) for i in handles], "static": [int(i) for i in static],
            "roi": None if roi is None else [int(i) for i in roi],
            "handle_targets": np.asarray(targets).tolist()}
    data.update(extra)
    path.write_text(json.dumps(data))
    return path


@pytest.fixture
def spot_job(tmp_path):
    V, F = load(SPOT)
    handles, static, targets = lift(V, amount=0.1)
    c = write_constraints(tmp_path / "c.json", handles, static, targets)
    return V, F, handles, static, targets, c


@pytest.mark.parametrize("domain", ["edge", "primal"])
def test_deform_writes_mesh_and_one_line_report(tmp_path, spot_job, domain):
    V, F, handles, static, targets, c = spot_job
    out = tmp_path / "out.obj"
    p = run("deform", DATA / SPOT, "--constraints", c, "--out", out, "--domain", domain,
            "--stiffness", "0.5", "--iterations", "30", "--tolerance", "1e-4")
    assert p.returncode == 0, p.stderr
    lines = p.stdout.strip().splitlines()
    assert len(lines) == 1
    rep = json.loads(lines[0])
    for key in ("vertices", "nodes", "domain", "factor_ms", "iterations", "ms_per_iteration",
                "energies", "converged"):
        assert key in rep, key
    assert rep["vertices"] == len(V) and rep["domain"] == domain
    n_edges = len(np.unique(np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]],
                                                    F[:, [2, 0]]]), 1), axis=0))
    assert rep["nodes"] == (n_edges if domain == "edge" else len(V))
    assert 1 <= rep["iterations"] <= 30 and len(rep["energies"]) == rep["iterations"]
    assert rep["factor_ms"] > 0 and rep["ms_per_iteration"] > 0
    X, F2 = read_mesh(out)
    np.testing.assert_array_equal(F2, F)
    np.testing.assert_array_equal(X[handles], targets)      # same vertex order
    np.testing.assert_array_equal(X[static], V[static])
    assert np.abs(X - V).max() > 0.01 * diag(V)


def test_deform_matches_python_api(tmp_path, spot_job):
    import edgedeform as ed
    V, F, handles, static, targets, c = spot_job
    lam = np.where(V[:, 0] > np.median(V[:, 0]), 1.0, 0.2)
    np.savetxt(tmp_path / "lam.txt", lam)
    out = tmp_path / "out.ply"
    p = run("deform", DATA / SPOT, "--constraints", c, "--out", out,
            "--stiffness-file", tmp_path / "lam.txt", "--iterations", "7", "--tolerance", "0")
    assert p.returncode == 0, p.stderr
    d = ed.Deformer(V, F, domain="edge")
    d.set_constraints(handles=handles, static=static, roi=None)
    d.set_stiffness(lam)
    r = d.solve(targets, max_iterations=7, tolerance=0.0)
    X, _ = read_mesh(out)
    np.testing.assert_allclose(X, r.positions, rtol=0, atol=1e-12 * diag(V))
    assert json.loads(p.stdout)["iterations"] == 7


def test_deform_off_with_roi(tmp_path):
    V, F = load(PLANE)
    roi = np.flatnonzero(V[:, 0] > 0)
    handles = roi[np.argsort(V[roi, 0])[-20:]]
    targets = V[handles] + [0.0, 0.2, 0.0]
    c = write_constraints(tmp_path / "c.json", handles, [], targets, roi=roi)
    out = tmp_path / "out.off"
    p = run("deform", DATA / PLANE, "--constraints", c, "--out", out)
    assert p.returncode == 0, p.stderr
    X, _ = read_mesh(out)
    outside = np.setdiff1d(np.arange(len(V)), roi)
    np.testing.assert_array_equal(X[outside], V[outside])
    np.testing.assert_array_equal(X[handles], targets)


@pytest.mark.parametrize("connected", [False, True])
def test_deform_with_roi_radius_is_the_api_with_it(tmp_path, connected):
    import edgedeform as ed
    V, F = load(PLANE)
    handles = np.argsort(V[:, 0])[-20:]
    targets = V[handles] + [0.0, 0.2, 0.0]
    radius = 0.3 * diag(V)
    c = write_constraints(tmp_path / "c.json", handles, [], targets)
    out = tmp_path / "out.off"
    p = run("deform", DATA / PLANE, "--constraints", c, "--out", out, "--roi-radius", str(radius),
            *(["--roi-connected"] if connected else []), "--iterations", "5", "--tolerance", "0")
    assert p.returncode == 0, p.stderr
    d = ed.Deformer(V, F)
    d.set_constraints(handles, roi_radius=radius, roi_connected=connected)
    r = d.solve(targets, max_iterations=5, tolerance=0.0)
    assert json.loads(p.stdout)["free_vertices"] == r.free_vertices < len(V) - len(handles)
    np.testing.assert_allclose(read_mesh(out)[0], r.positions, rtol=0, atol=1e-12 * diag(V))


def test_roi_radius_with_a_roi_is_an_error(tmp_path):
    V, F = load(PLANE)
    c = write_constraints(tmp_path / "c.json", [0], [], V[[0]], roi=np.arange(50))
    p = run("deform", DATA / PLANE, "--constraints", c, "--out", tmp_path / "o.off", "--roi-radius", "1")
    assert p.returncode == 1 and "roi and roi_radius both given" in p.stderr
    assert not (tmp_path / "o.off").exists()


BAD = {
    "missing_mesh": (lambda t, c: ["deform", t / "nope.obj", "--constraints", c,
                                   "--out", t / "o.obj"], "nope.obj"),
    "unsupported_mesh": (lambda t, c: ["deform", t / "c.json", "--constraints", c,
                                       "--out", t / "o.obj"], "unsupported"),
    "bad_out_ext": (lambda t, c: ["deform", DATA / SPOT, "--constraints", c,
                                  "--out", t / "o.stl"], "unsupported"),
    "missing_constraints": (lambda t, c: ["deform", DATA / SPOT, "--constraints",
                                          t / "none.json", "--out", t / "o.obj"], "none.json"),
    "stiffness_too_big": (lambda t, c: ["deform", DATA / SPOT, "--constraints", c,
                                        "--out", t / "o.obj", "--stiffness", "1.5"],
                          "stiffness"),
    "iterations_zero": (lambda t, c: ["deform", DATA / SPOT, "--constraints", c,
                                      "--out", t / "o.obj", "--iterations", "0"], "iterations"),
    "out_folder_missing": (lambda t, c: ["deform", DATA / SPOT, "--constraints", c,
                                         "--out", t / "no" / "o.obj"], "does not exist"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_arguments(tmp_path, spot_job, case):
    make, words = BAD[case]
    c = spot_job[-1]
    p = run(*make(tmp_path, c))
    assert p.returncode != 0
    assert words in p.stderr
    assert "Traceback" not in p.stderr and p.stdout == ""
    assert not list(tmp_path.rglob("o.*"))


CONSTRAINT_CASES = {
    "invalid_json": ("{handles: [1]", "invalid JSON"),
    "not_object": ("[1, 2, 3]", "object"),
    "no_handles": ({"static": [], "handle_targets": []}, "'handles' is missing"),
    "empty_handles": ({"handles": [], "handle_targets": []}, "empty"),
    "handle_out_of_range": ({"handles": [100000], "handle_targets": [[0, 0, 0]]},
                            "out of range"),
    "negative_static": ({"handles": [1], "static": [-1], "handle_targets": [[0, 0, 0]]},
                        "out of range"),
    "non_integer_index": ({"handles": [1.5], "handle_targets": [[0, 0, 0]]}, "integers"),
    "targets_count": ({"handles": [1, 2], "handle_targets": [[0, 0, 0]]},
                      "1 handle_targets for 2 handles"),
    "targets_shape": ({"handles": [1], "handle_targets": [[0, 0]]}, "[x, y, z]"),
    "targets_nan": ({"handles": [1], "handle_targets": [[0, "NaN", 0]]}, "handle_targets"),
    "overlap": ({"handles": [1, 2], "static": [2, 3], "handle_targets": [[0, 0, 0]] * 2},
                "both handle and static"),
    "unknown_key": ({"handles": [1], "handle_targets": [[0, 0, 0]], "statics": [2]},
                    "unknown key"),
}


@pytest.mark.parametrize("case", sorted(CONSTRAINT_CASES))
def test_bad_constraints_file(tmp_path, case):
    content, words = CONSTRAINT_CASES[case]
    c = tmp_path / "c.json"
    c.write_text(content if isinstance(content, str) else json.dumps(content))
    if case == "targets_nan":   # JSON has no NaN literal; Python's json writes one anyway
        c.write_text('{"handles": [1], "handle_targets": [[0, NaN, 0]]}')
    p = run("deform", DATA / SPOT, "--constraints", c, "--out", tmp_path / "o.obj")
    assert p.returncode != 0
    assert words in p.stderr, p.stderr
    assert "Traceback" not in p.stderr and p.stdout == ""
    assert not (tmp_path / "o.obj").exists()


def test_bad_stiffness_file(tmp_path, spot_job):
    V, *_, c = spot_job
    np.savetxt(tmp_path / "lam.txt", np.full(len(V) - 3, 0.5))
    p = run("deform", DATA / SPOT, "--constraints", c, "--out", tmp_path / "o.obj",
            "--stiffness-file", tmp_path / "lam.txt")
    assert p.returncode != 0 and "values for 829 vertices" in p.stderr
    assert not (tmp_path / "o.obj").exists()


def test_non_manifold_mesh_deforms(tmp_path):
    """A third triangle on an interior edge of the plane (a fin): deformed, not refused."""
    V, F = load(PLANE)
    a, b = F[0, 0], F[0, 1]
    V2 = np.vstack([V, V[[a, b]].mean(axis=0) + [0.0, 0.3, 0.0]])
    F2 = np.vstack([F, [[a, b, len(V)]]])
    mesh = tmp_path / "nm.obj"
    mesh.write_text(_obj_text(V2, F2))
    target = V2[0] + [0.0, 0.1, 0.0]
    c = write_constraints(tmp_path / "c.json", [0], [5], [target])
    p = run("deform", mesh, "--constraints", c, "--out", tmp_path / "o.obj")
    assert p.returncode == 0, p.stderr
    X, _ = read_mesh(tmp_path / "o.obj")
    assert np.allclose(X[0], target) and np.allclose(X[5], V2[5])
    assert np.abs(X[-1] - V2[-1]).max() > 0.0  # the fin's tip moved with its edge


def _obj_text(V, F):
    return ("".join(f"v {float(x)!r} {float(y)!r} {float(z)!r}\n" for x, y, z in V) +
            "".join(f"f {i + 1} {j + 1} {k + 1}\n" for i, j, k in F))


def test_degenerate_mesh_reports_core_error(tmp_path):
    """An error found by the core (not the CLI's own checks) is reported the same way, and
    names what is wrong with the mesh (not a CHOLMOD status)."""
    V, F = load(PLANE)
    mesh = tmp_path / "point.obj"
    mesh.write_text(_obj_text(np.zeros_like(V), F))
    c = write_constraints(tmp_path / "c.json", [0], [5], [[0.0, 0.1, 0.0]])
    p = run("deform", mesh, "--constraints", c, "--out", tmp_path / "o.obj")
    assert p.returncode == 1, p.stderr
    assert f"all its {len(V)} vertices are at one point" in p.stderr, p.stderr
    assert "CHOLMOD" not in p.stderr and "Traceback" not in p.stderr
    assert not (tmp_path / "o.obj").exists()


@pytest.mark.parametrize("value", [1e308, -1e200])
def test_overflowing_target_rejected_nothing_written(tmp_path, spot_job, value):
    V, F, handles, static, targets, _ = spot_job
    targets = targets.copy()
    targets[1, 2] = value
    c = write_constraints(tmp_path / "c.json", handles, static, targets)
    p = run("deform", DATA / SPOT, "--constraints", c, "--out", tmp_path / "o.obj")
    assert p.returncode == 1, p.stderr
    assert "targets[1]" in p.stderr and "overflow" in p.stderr, p.stderr
    assert not (tmp_path / "o.obj").exists()


def test_quads_uvs_and_normals_survive(tmp_path):
    """A quad mesh with vt/vn once came back triangulated and bare. Now every line but
    v and vn is unchanged, and the report says the normals were recomputed."""
    n = 6
    i, j = np.meshgrid(np.arange(n), np.arange(n))
    V = np.stack([i.ravel() / (n - 1), j.ravel() / (n - 1), np.zeros(n * n)], axis=1)
    lines = ["mtllib m.mtl\n", "o sheet\n"] + [f"v {float(x)!r} {float(y)!r} {float(z)!r}\n" for x, y, z in V]
    lines += [f"vt {float(x)!r} {float(y)!r}\n" for x, y, _ in V] + ["vn 0 0 1\n", "usemtl cloth\n"]
    lines += [f"f {a}/{a}/1 {a + 1}/{a + 1}/1 {a + n + 1}/{a + n + 1}/1 {a + n}/{a + n}/1\n"
              for a in (1 + b * n + c for b in range(n - 1) for c in range(n - 1))]
    src = tmp_path / "sheet.obj"
    src.write_text("".join(lines))
    handles = np.arange(n * n - n, n * n)  # the row at y = 1, lifted
    targets = V[handles] + [0.0, 0.0, 0.3]
    c = write_constraints(tmp_path / "c.json", handles, np.arange(n), targets)
    p = run("deform", src, "--constraints", c, "--out", tmp_path / "o.obj")
    assert p.returncode == 0, p.stderr
    report = json.loads(p.stdout)
    assert report["notes"] == ["normals (vn) recomputed from the deformed faces"]
    out = (tmp_path / "o.obj").read_text().splitlines(keepends=True)
    keep = [ln for ln in lines if ln.split()[0] not in ("v", "vn")]
    assert [ln for ln in out if ln.split()[0] not in ("v", "vn")] == keep
    X, _ = read_mesh(tmp_path / "o.obj")
    assert np.allclose(X[handles], targets)
    vn = [list(map(float, ln.split()[1:])) for ln in out if ln.startswith("vn ")]
    assert len(vn) == 1 and vn[0][1] < -0.05  # the sheet tilted towards -y as it lifted


def test_help_and_usage():
    p = run("--help")
    assert p.returncode == 0 and "deform" in p.stdout
    p = run("deform")
    assert p.returncode == 2 and "Traceback" not in p.stderr


def test_version_names_the_package_and_its_core():
    import edgedeform as ed
    p = run("--version")
    info = ed.build_info()
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith(f"edgedeform {info['version']} ({info['solver']}, "), p.stdout


def test_options_default_to_the_cores_solve_defaults():
    """The parser reads edgedeform.SOLVE_DEFAULTS and ACCELERATIONS: nothing restated."""
    import edgedeform as ed
    from edgedeform import cli
    args = cli._parser().parse_args(["deform", "m.obj", "--constraints", "c.json", "--out", "o.obj"])
    defaults = ed.SOLVE_DEFAULTS
    assert (args.iterations, args.tolerance, args.acceleration, args.anderson_window) == (
        defaults["max_iterations"], defaults["tolerance"], defaults["acceleration"],
        defaults["anderson_window"])
    choices = {a.dest: a.choices for a in cli._parser().commands["deform"]._actions}
    assert tuple(choices["acceleration"]) == ed.ACCELERATIONS
    text = run("deform", "--help").stdout
    assert f"(default {defaults['max_iterations']})" in text and "(default 0.001)" in text


def test_without_stiffness_the_deformers_own_default_applies():
    """--help says what a Deformer starts with; the command then sets no stiffness at all."""
    import edgedeform as ed
    V, F = load(PLANE)
    assert np.all(ed.Deformer(V, F).node_stiffness() == 0.5)
    assert "0.5 everywhere" in " ".join(run("deform", "--help").stdout.split())


def test_report_has_exactly_the_documented_fields(tmp_path, spot_job):
    """docs/api.md's report table is generated from cli.REPORT_FIELDS."""
    from edgedeform import cli
    *_, c = spot_job
    p = run("deform", DATA / SPOT, "--constraints", c, "--out", tmp_path / "o.obj", "--iterations", "3")
    assert p.returncode == 0, p.stderr
    assert list(json.loads(p.stdout)) == list(cli.REPORT_FIELDS)
