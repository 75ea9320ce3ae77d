"""solve()'s options come from one table in the bindings (native/bindings/bind_solve.cpp):
its signature in help(), its argument checks, and the SOLVE_DEFAULTS and ACCELERATIONS that
the command line, the add-on and the docs read."""

import re

import numpy as np
import pytest

import edgedeform as ed

V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


@pytest.fixture
def tetra():
    d = ed.Deformer(V, F)
    d.set_constraints(handles=[3], static=[0])
    return d


def signature_defaults():
    """name -> default text, from the first line of help(Deformer.solve)."""
    line = ed.Deformer.solve.__doc__.splitlines()[0]
    inside = line[line.index("(") + 1:line.rindex(")")]
    parts, depth, start = [], 0, 0
    for i, c in enumerate(inside + ","):
        depth += {"[": 1, "]": -1}.get(c, 0)
        if c == "," and depth == 0:
            parts.append(inside[start:i].strip())
            start = i + 1
    return dict(p.split(": ", 1)[0:1] + [p.split(" = ", 1)[1]] for p in parts if " = " in p)


def test_the_signature_lists_every_default_in_order():
    shown = signature_defaults()
    assert list(shown) == list(ed.SOLVE_DEFAULTS)
    for name, value in ed.SOLVE_DEFAULTS.items():
        assert shown[name] == repr(value), name


def test_defaults_are_the_ones_a_plain_solve_uses(tetra):
    targets = V[[3]] + 0.2
    plain = tetra.solve(targets, warm_start=False)
    spelled = ed.Deformer(V, F)
    spelled.set_constraints(handles=[3], static=[0])
    explicit = spelled.solve(targets, **{k: v for k, v in ed.SOLVE_DEFAULTS.items()})
    np.testing.assert_array_equal(plain.positions, explicit.positions)
    assert plain.iterations == explicit.iterations


def test_defaults_cannot_be_changed_by_a_caller():
    with pytest.raises(TypeError):
        ed.SOLVE_DEFAULTS["tolerance"] = 1.0
    assert ed.SOLVE_DEFAULTS["tolerance"] == ed._core.SOLVE_DEFAULTS["tolerance"]


def test_every_listed_method_solves_and_the_core_knows_no_other(tetra):
    for name in ed.ACCELERATIONS:
        r = tetra.solve(V[[3]] + 0.1, max_iterations=3, acceleration=name)
        assert r.iterations >= 1, name
    # The core's parser names every method it takes: a method added there but not to the
    # bindings' table would be missing from ACCELERATIONS.
    with pytest.raises(ValueError) as err:
        tetra.solve(V[[3]], acceleration="no such method")
    assert set(re.findall(r'"([a-z_]+)"', str(err.value))) - {"no such method"} == set(ed.ACCELERATIONS)
    assert ed.SOLVE_DEFAULTS["acceleration"] in ed.ACCELERATIONS


def test_help_describes_every_option_and_method():
    doc = ed.Deformer.solve.__doc__
    for name in ed.SOLVE_DEFAULTS:
        assert re.search(rf"^{name}: \S", doc, re.M), name
    for name in ed.ACCELERATIONS:
        assert re.search(rf'^    "{name}"( \(default\))?: \S', doc, re.M), name


def test_positional_and_keyword_arguments_bind_as_in_python(tetra):
    T = V[[3]] + 0.1
    a = tetra.solve(T, 4, 0.0, False)
    b = tetra.solve(targets=T, max_iterations=4, tolerance=0.0, warm_start=False)
    np.testing.assert_array_equal(a.positions, b.positions)
    assert a.iterations == b.iterations == 4


@pytest.mark.parametrize("args, kwargs, error, words", [
    ((), {"max_iterations": "10"}, TypeError, "max_iterations must be an int, got str"),
    ((), {"tolerance": None}, TypeError, "tolerance must be a float, got NoneType"),
    ((), {"warm_start": "yes"}, TypeError, "warm_start must be a bool, got str"),
    ((), {"acceleration": 3}, TypeError, "acceleration must be a str, got int"),
    ((), {"acceleration": "fast"}, ValueError, 'got "fast"'),
    ((), {"max_iter": 10}, TypeError, "unexpected keyword argument 'max_iter'"),
    ((10,), {"max_iterations": 10}, TypeError, "multiple values for argument 'max_iterations'"),
    (tuple(range(len(ed.SOLVE_DEFAULTS) + 1)), {}, TypeError, "too many positional arguments"),
    ((), {"initial": np.zeros((2, 3))}, ValueError, "initial"),
])
def test_bad_options_name_the_argument_and_change_nothing(tetra, args, kwargs, error, words):
    before = tetra.solve(V[[3]] + 0.1, max_iterations=2, tolerance=0.0).positions
    with pytest.raises(error) as err:
        tetra.solve(V[[3]] + 0.1, *args, **kwargs)
    assert words in str(err.value)
    after = tetra.solve(V[[3]] + 0.1, max_iterations=2, tolerance=0.0).positions
    assert np.isfinite(after).all() and after.shape == before.shape
