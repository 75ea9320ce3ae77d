"""Find the compiled `edgedeform` package.

An installed add-on carries its own copy (``edge_deform/edgedeform/``, copied by the
``install_addon`` target); a development checkout falls back to a top-level
``import edgedeform`` (tests put ``build/python`` on ``sys.path``). Imported lazily so that
the add-on still registers and can report a clear error when the module is missing.
"""

import importlib
import os

_module = None


def get():
    """Return the `edgedeform` module or raise ImportError with a message for the user."""
    global _module
    if _module is not None:
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
        "Reinstall with 'cmake --build <build> --target install_addon' for this Blender's "
        "Python." % "; ".join(errors))
