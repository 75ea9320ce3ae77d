"""Small helpers shared by the operators: polls and Edit-Mode round trips."""

import contextlib

from . import compat


def poll_mesh(cls, context, modes=None, need_handles=False):
    """True for an active mesh object in one of `modes`; explains itself otherwise."""
    ob = context.active_object
    msg = None
    if ob is None or ob.type != 'MESH':
        msg = "Select a mesh object"
    elif modes is not None and ob.mode not in modes:
        msg = {"EDIT": "Enter Edit Mode first", "OBJECT": "Leave Edit Mode first"}.get(
            modes[0], "Not available in this mode")
    elif need_handles and not ob.edge_deform.handles:
        msg = "Add a handle first"
    if msg is not None:
        if hasattr(cls, "poll_message_set"):
            cls.poll_message_set(msg)
        return False
    return True


@contextlib.contextmanager
def object_mode(ob):
    """Temporarily leave Edit Mode: VertexGroup.add/remove and foreach_set need it."""
    previous = ob.mode
    if previous != 'OBJECT':
        compat.mode_set(ob, 'OBJECT')
    try:
        yield
    finally:
        if previous != 'OBJECT' and ob.mode != previous:
            compat.mode_set(ob, previous)
