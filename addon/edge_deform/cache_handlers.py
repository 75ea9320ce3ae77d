"""Keep the session cache honest across file loads and undo, and tell running tools; keep
no deleted controller in a saved file.

Undo and file loads replace mesh datablocks, so cached bindings may point at freed meshes
(whose addresses Blender may reuse). Every cache hit is re-checked anyway (topology and rest
shape, solver_cache.py); this frees memory early, and counts undo/redo steps so that a modal
tool notices that the data it holds were replaced and ends cleanly. Before a save, handles
let go of controllers deleted from every scene (lifecycle.forget_deleted_controllers), so
the file does not keep them outside every collection.
"""

import bpy
from bpy.app.handlers import persistent

from . import lifecycle, solver_cache

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


@persistent
def _on_save(*_args):
    for ob in bpy.data.objects:
        if ob.type == 'MESH' and getattr(ob, "edge_deform", None) is not None:
            lifecycle.forget_deleted_controllers(ob)


_HANDLERS = ((bpy.app.handlers.load_post, _on_load),
             (bpy.app.handlers.save_pre, _on_save),
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
