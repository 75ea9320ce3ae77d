"""Keep the session cache honest across file loads and undo.

Undo and file loads replace mesh datablocks, so cached bindings may point at freed meshes
(whose addresses Blender may reuse). Every cache hit is re-checked anyway (topology and rest
shape), this only frees memory early and never lets a stale entry linger.
"""

import bpy
from bpy.app.handlers import persistent

from . import session


@persistent
def _on_load(*_args):
    session.clear()


@persistent
def _on_undo(*_args):
    session.prune({mesh.as_pointer() for mesh in bpy.data.meshes})


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
