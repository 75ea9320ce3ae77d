"""Find the compiled `edgedeform` package.

The legacy add-on (Blender 3.x, ``install_addon`` target, add-on zip) carries its own copy
in ``edge_deform/edgedeform/``. Everywhere else it is a top-level ``import edgedeform``:
the 4.2+ extension installs its wheel into Blender's extension site-packages, and a
development checkout puts ``build/python`` on ``sys.path``. Imported lazily so that
the add-on still registers and can report a clear error when the module is missing.
"""

import importlib
import os
import sys

_module = None


def get():
    """Return the `edgedeform` module or raise ImportError with a message for the user."""
    global _module
    if _module is not None:
        return _module
    # A script (make_samples.py, a pipeline) that imported a top-level edgedeform first: use
    # that copy. A second copy of the compiled module cannot load in the same Python
    # (pybind11: 'type "SolveResult" is already registered!', seen on Debian 13's 4.3).
    if sys.modules.get("edgedeform") is not None:
        _module = sys.modules["edgedeform"]
        return _module
    bundled = os.path.join(os.path.dirname(__file__), "edgedeform", "__init__.py")
    errors = []
    if os.path.exists(bundled):
        try:
            _module = importlib.import_module(__package__ + ".edgedeform")
            return _module
        except ImportError as exc:  # e.g. built for another Python version
            errors.append("bundled module: %s" % exc)
    try:
        _module = importlib.import_module("edgedeform")
        return _module
    except ImportError as exc:
        errors.append("top-level module: %s" % exc)
    raise ImportError(
        "Edge Deform: the native package 'edgedeform' could not be loaded (%s). "
        "Reinstall: on Blender 4.2+ the extension zip (its wheels are for Python 3.11 and 3.13, Linux "
        "x86_64), on 3.x 'cmake --build <build> --target install_addon' for this Blender's "
        "Python." % "; ".join(errors))
