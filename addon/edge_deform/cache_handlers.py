"""Keep the session cache honest across file loads and undo, and tell running tools.

Undo and file loads replace mesh datablocks, so cached bindings may point at freed meshes
(whose addresses Blender may reuse). Every cache hit is re-checked anyway (topology and rest
shape, solver_cache.py); this frees memory early, and counts undo/redo steps so that a modal
tool notices that the data it holds were replaced and ends cleanly.
"""

import bpy
from bpy.app.handlers import persistent

from . import solver_cache

_generation = [0]


def generation():
    """Changes after every undo, redo and file load."""
    return _generation[0]


@persistent
def _on_load(*_args):
    _generation[0] += 1
    solver_cache.forget_all()


@persistent
def _on_undo(*_args):
    _generation[0] += 1
    solver_cache.forget_all_but({mesh.as_pointer() for mesh in bpy.data.meshes})


_HANDLERS = ((bpy.app.handlers.load_post, _on_load),
             (bpy.app.handlers.undo_post, _on_undo),
             (bpy.app.handlers.redo_post, _on_undo))


def register_handlers():
    for handlers, fn in _HANDLERS:
        if fn not in handlers:
            handlers.append(fn)


def unregister_handlers():
    for handlers, fn in _HANDLERS:
        if fn in handlers:
            handlers.remove(fn)
