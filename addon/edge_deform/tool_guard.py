"""While Live Deform or Grab Deform runs on a mesh it owns that mesh's shape: the
operators that would rewrite or rebind it (Bind, Solve, Apply, Unbind, Bake) fail their
poll, so Blender greys their buttons and menu entries and their tooltip says why, instead
of looking enabled and then refusing (docs/decisions/0040, 0068). The frame handler
leaves such a mesh alone too: Live follows animated controllers itself.
"""

from . import modal_tool
from .op_common import deformed_object, poll_mesh


def poll(cls, context, on_controller=True):
    """The poll of an Object-Mode operator that rewrites or rebinds a mesh: a mesh with
    handles (with `on_controller`, also the mesh of the active controller; else the active
    object, handles or not) on which no modal tool runs."""
    if not poll_mesh(cls, context, ('OBJECT',), need_handles=on_controller,
                     follow_controller=on_controller):
        return False
    return idle(cls, deformed_object(context) if on_controller else context.active_object)


def idle(cls, ob):
    """For an operator's poll: False while a modal tool runs on `ob`, with the reason as
    the poll message (the greyed button's tooltip; a script's error)."""
    tool = modal_tool.running_tool(ob) if ob is not None else None
    if tool is None:
        return True
    if hasattr(cls, "poll_message_set"):
        cls.poll_message_set("%s is running on '%s' and deforms it already: press Enter "
                             "over the view to keep its shape or Esc to cancel"
                             % (tool.bl_label, ob.name))
    return False


def busy(ob):
    """Is a modal tool deforming `ob` now (the frame handler then leaves it alone)?"""
    return modal_tool.running_tool(ob) is not None
