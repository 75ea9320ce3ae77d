"""Differences between the Blender versions the add-on runs on (3.4 to 5.3), and between
the ways it is installed (finding the compiled `edgedeform` package, at the end).

Checked on Debian's 3.4.1 and 4.3.2 and on the `bpy` modules 4.5 LTS, 5.0, 5.1, 5.2 and 5.3
(tests/blender; docs/install.md, "Blender versions"). The
known API breaks of 4.0-5.0 do not reach this add-on: it passes no context-override dicts
to operators (4.0), never touches auto smooth (4.1), draws nothing with `bgl` (5.0) and
reads its PropertyGroup settings as attributes, never with dict syntax (5.0).
"""

import importlib
import os
import sys

import bpy


def repair_selection_attributes(mesh):
    """Drop a selection attribute stored with the wrong type, so mode switches cannot crash.

    Blender 5.0.1's Mesh.from_pydata (used by scripts and importers) stores ".select_edge"
    as INT32_2D instead of BOOLEAN; leaving Weight Paint with the vertex-selection mask on,
    or writing the edge selection, then crashes Blender. A missing selection attribute means
    "nothing selected", so removing the broken one loses nothing that was readable.
    """
    attributes = getattr(mesh, "attributes", None)   # (3.x meshes keep selection as flags)
    if attributes is None:
        return
    for name in (".select_vert", ".select_edge", ".select_poly"):
        attribute = attributes.get(name)
        if attribute is not None and attribute.data_type != 'BOOLEAN':
            attributes.remove(attribute)


def mode_set(ob, mode):
    """bpy.ops.object.mode_set for `ob` (the active object), safe on Blender 5.0.1 meshes."""
    if ob.type == 'MESH':
        repair_selection_attributes(ob.data)
    bpy.ops.object.mode_set(mode=mode)


def status_bar(workspace, draw):
    """Show `draw(layout)` in the status bar (key hints, as Blender's G shows them), or
    clear it with None. 3.x and 4.x+ both take a callable (header, context); only the
    layout differs in what icons exist, which `draw` keeps to the ones all versions have."""
    if workspace is None:
        return
    try:
        if draw is None:
            workspace.status_text_set(None)
        else:
            workspace.status_text_set(lambda header, context: draw(header.layout))
    except ReferenceError:   # the workspace went away (a file load)
        pass


def icon(*names):
    """The first of `names` this Blender has (icons get renamed: SEQUENCE_COLOR_01 is
    STRIP_COLOR_01 from 4.4 on)."""
    known = bpy.types.UILayout.bl_rna.functions["label"].parameters["icon"].enum_items
    for name in names:
        if name in known:
            return name
    return 'NONE'


# ------------------------------------------------------------------ the compiled package
# Find the compiled `edgedeform` package.
#
# The legacy add-on (Blender 3.x, ``install_addon`` target, add-on zip) carries its own copy
# in ``edge_deform/edgedeform/``. Everywhere else it is a top-level ``import edgedeform``:
# the 4.2+ extension installs its wheel into Blender's extension site-packages, and a
# development checkout puts ``build/python`` on ``sys.path``. Imported lazily so that
# the add-on still registers and can report a clear error when the module is missing.

_module = None


def native_package():
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
