"""Hostile arguments to the API and the command line (docs/robustness.md): an integer out of range is
a ValueError naming the argument and its range (a usage error naming the option in the CLI,
never "internal error"); a wrong type is a short TypeError naming the argument, not a
listing of every argument; a radius that frees nothing is a NoFreeVertexError that suggests a
larger radius only where one helps; a file the CLI cannot read or write is named."""

import os
import re
import sys

import numpy as np
import pytest

import edgedeform as ed
from _meshes import DATA, PLANE, SPOT, lift, load
from test_cli import run, write_constraints

INT_MAX = 2**31 - 1


@pytest.fixture(scope="module")
def spot():
    V, F = load(SPOT)
    handles, static, targets = lift(V, amount=0.1)
    d = ed.Deformer(V, F)
    d.set_constraints(handles=handles, static=static)
    return d, targets, handles, static


@pytest.mark.parametrize("kwargs, words", [
    ({"max_iterations": 10**20},
     f"max_iterations must be an integer in [1, {INT_MAX}], got 100000000000000000000"),
    ({"max_iterations": 0}, f"max_iterations must be an integer in [1, {INT_MAX}], got 0"),
    ({"max_iterations": -2**63}, f"max_iterations must be an integer in [1, {INT_MAX}], got {-2**63}"),
    ({"anderson_window": 10**20}, "anderson_window must be an integer in [1, 50], got 100000000000000000000"),
    ({"anderson_window": 51}, "anderson_window must be an integer in [1, 50], got 51"),
])
def test_integer_out_of_range_names_argument_and_range(spot, kwargs, words):
    d, targets, *_ = spot
    with pytest.raises(ValueError) as err:
        d.solve(targets, **kwargs)
    assert str(err.value) == words


def test_integer_like_arguments_still_accepted(spot):
    d, targets, *_ = spot
    r = d.solve(targets, max_iterations=np.int64(3), anderson_window=np.int32(4), tolerance=0)
    assert r.iterations == 3


@pytest.mark.parametrize("call, words", [
    (lambda d, t, h, s: d.solve(t, max_iterations=True), "max_iterations must be an int, got bool"),
    (lambda d, t, h, s: d.solve(t, tolerance="0.1"), "tolerance must be a float, got str"),
    (lambda d, t, h, s: d.set_constraints(handles=h, static=s, roi_radius="1.0"),
     "roi_radius must be a float or None, got str"),
    (lambda d, t, h, s: d.set_constraints(handles=h, static=s, roi_radius=1.0, roi_connected="yes"),
     "roi_connected must be a bool, got str"),
    (lambda d, t, h, s: ed.Deformer(*load(SPOT), domain=5), "domain must be a str, got int"),
    (lambda d, t, h, s: ed.Deformer(*load(SPOT), clamp_negative_weights=None),
     "clamp_negative_weights must be a bool, got NoneType"),
], ids=["bool_iterations", "str_tolerance", "str_radius", "str_connected", "int_domain", "none_clamp"])
def test_wrong_type_is_a_short_type_error_naming_the_argument(spot, call, words):
    """Not pybind11's 'incompatible function arguments' with every argument's repr
    (3,000 characters, the handle arrays included)."""
    d, targets, handles, static = spot
    with pytest.raises(TypeError) as err:
        call(d, targets, handles, static)
    assert str(err.value) == words


@pytest.mark.parametrize("args, kwargs, words", [
    ((), {"max_iter": 5}, "got an unexpected keyword argument 'max_iter'"),
    ((5,), {"max_iterations": 5}, "multiple values for argument 'max_iterations'"),
    (tuple(range(len(ed.SOLVE_DEFAULTS) + 1)), {}, "too many positional arguments"),
])
def test_misbound_solve_argument_is_pythons_short_error(spot, args, kwargs, words):
    """solve()'s binding is pybind11's own; its 'incompatible function arguments' (every
    argument's value, the targets array included) never reaches the user."""
    d, targets, *_ = spot
    with pytest.raises(TypeError) as err:
        d.solve(targets, *args, **kwargs)
    assert str(err.value) == words


def test_radius_that_frees_nothing_is_a_no_free_vertex_error(spot):
    d, targets, handles, static = spot
    with pytest.raises(ed.NoFreeVertexError, match="increase the radius$") as err:
        d.set_constraints(handles=handles, static=static, roi_radius=1e-9)
    assert isinstance(err.value, ValueError)


@pytest.mark.parametrize("connected", [False, True])
def test_no_larger_radius_is_suggested_where_none_helps(connected):
    """Every vertex is a handle or static: no radius frees one, so none is suggested."""
    V, F = load(PLANE)
    d = ed.Deformer(V, F)
    with pytest.raises(ed.NoFreeVertexError) as err:
        d.set_constraints(handles=[0], static=np.arange(1, len(V)), roi_radius=1e-9, roi_connected=connected)
    assert "increase the radius" not in str(err.value)
    assert str(err.value).endswith("so no radius frees one")


@pytest.fixture
def spot_constraints(tmp_path):
    V, F = load(SPOT)
    handles, static, targets = lift(V, amount=0.1)
    return write_constraints(tmp_path / "c.json", handles, static, targets)


@pytest.mark.parametrize("option, value, words", [
    ("--iterations", "100000000000000000000",
     f"argument --iterations: must be an integer in [1, {INT_MAX}], got 100000000000000000000"),
    ("--iterations", "0", f"argument --iterations: must be an integer in [1, {INT_MAX}], got 0"),
    ("--anderson-window", "51", "argument --anderson-window: must be an integer in [1, 50], got 51"),
    ("--iterations", "1e3", "argument --iterations: expected an integer, got '1e3'"),
])
def test_cli_integer_out_of_range_is_a_usage_error(tmp_path, spot_constraints, option, value, words):
    p = run("deform", DATA / SPOT, "--constraints", spot_constraints, "--out", tmp_path / "o.obj",
            option, value)
    assert p.returncode == 2, p.stderr
    assert words in p.stderr and "internal error" not in p.stderr and "Traceback" not in p.stderr
    assert not (tmp_path / "o.obj").exists()


def test_cli_names_a_malformed_normal_before_any_work(tmp_path, spot_constraints):
    mesh = tmp_path / "bad.obj"
    text = (DATA / SPOT).read_text()
    mesh.write_text(text + "vn 0 0\nf 1//1 2//1 3//1\n")
    line = len(text.splitlines()) + 1
    p = run("deform", mesh, "--constraints", spot_constraints, "--out", tmp_path / "o.obj")
    assert p.returncode == 1
    assert f"edgedeform: error: {mesh}: OBJ line {line}: a normal (vn) needs 3 numbers" in p.stderr
    assert not (tmp_path / "o.obj").exists()


def test_cli_write_error_names_out_not_a_temporary_file(tmp_path, spot_constraints):
    out = tmp_path / "o.obj"
    out.mkdir()   # a folder where OUT should go: the rename fails (as root too)
    p = run("deform", DATA / SPOT, "--constraints", spot_constraints, "--out", out)
    assert p.returncode == 1
    assert re.search(rf"edgedeform: error: \[Errno \d+\] cannot write {re.escape(str(out))}: ", p.stderr), p.stderr
    assert ".edgedeform-" not in p.stderr
    assert sorted(x.name for x in tmp_path.iterdir()) == ["c.json", "o.obj"]   # nothing left behind


SOLVE_UNDER_A_LIMIT = r"""
import json, resource, sys
sys.path.insert(0, sys.argv[2])
import edgedeform as ed
from _meshes import SPOT, lift, load
V, F = load(SPOT)
handles, static, targets = lift(V, amount=0.1)
d = ed.Deformer(V, F)
d.set_constraints(handles=handles, static=static)
d.set_stiffness(1.0)
d.solve(targets, max_iterations=1)   # the factor and its workspace before the limit
with open("/proc/self/status") as fh:
    held = next(int(l.split()[1]) * 1024 for l in fh if l.startswith("VmSize:"))
limit = held + int(sys.argv[1])
resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
out = {}
for acceleration in ("auto", "anderson", "none"):
    r = d.solve(targets, max_iterations=%d, tolerance=1e-3, warm_start=False, acceleration=acceleration)
    out[acceleration] = [r.method, r.iterations, r.converged]
print(json.dumps(out))
""" % INT_MAX


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_AS and /proc are Linux's")
def test_the_largest_max_iterations_reserves_no_history_it_does_not_use():
    """max_iterations = 2^31 - 1 must not reserve 2^31 energies and residuals (16 GiB each):
    every method converges under an address-space limit 1 GiB above what the process holds
    (L-BFGS reserved max_iterations and ended in MemoryError here)."""
    import json
    import subprocess
    here = os.path.dirname(os.path.abspath(__file__))
    proc = subprocess.run([sys.executable, "-c", SOLVE_UNDER_A_LIMIT, str(1 << 30), here],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    assert out["auto"][0] == "lbfgs" and out["anderson"][0] == "anderson"
    assert all(converged and 0 < iterations < 2000 for _, iterations, converged in out.values()), out
