"""help() is the API doc: typed signatures with shapes and defaults, and a description."""

import pydoc
import re

import edgedeform as ed


def text(obj):
    return pydoc.render_doc(obj, renderer=pydoc.plaintext)


def test_solve_shows_arguments_shapes_and_defaults():
    doc = text(ed.Deformer.solve)
    for part in ("targets: numpy.ndarray[float64[h, 3]]", "max_iterations: int = 2000",
                 "tolerance: float = 0.001", "warm_start: bool = True",
                 "initial: Optional[numpy.ndarray[float64[n, 3]]] = None",
                 "acceleration: str = 'auto'", "anderson_window: int = 5",
                 "-> edgedeform._core.SolveResult", "bounding-box diagonal"):
        assert part in doc, part


def test_no_argument_is_shown_as_a_bare_handle():
    for method in (ed.Deformer.__init__, ed.Deformer.set_constraints, ed.Deformer.set_stiffness,
                   ed.Deformer.solve, ed.Deformer.energy, ed.metrics):
        doc = method.__doc__
        assert doc, method
        assert not re.search(r": handle[,)]", doc), doc.splitlines()[0]


def test_constructor_and_constraints_describe_their_arrays():
    assert "V: (n, 3) rest positions" in ed.Deformer.__init__.__doc__
    assert "weld" in ed.Deformer.__init__.__doc__
    assert "handles: numpy.ndarray[int[k]]" in ed.Deformer.set_constraints.__doc__
    assert "stiffness: Union[float, numpy.ndarray[float64[n]]]" in ed.Deformer.set_stiffness.__doc__
    assert "arap_energy_normalized" in ed.metrics.__doc__


def test_result_fields_are_documented():
    for name in ("positions", "iterations", "energies", "residuals", "converged",
                 "distance_estimate", "warnings", "factor_ms"):
        assert getattr(ed.SolveResult, name).__doc__, name


def test_solve_help_names_the_real_default_acceleration():
    # The docstring once called "newton" the default while the signature said "anderson".
    import re
    default = re.search(r'acceleration: str = [\'"](\w+)[\'"]', ed.Deformer.solve.__doc__).group(1)
    assert f'"{default}" (default' in ed.Deformer.solve.__doc__
