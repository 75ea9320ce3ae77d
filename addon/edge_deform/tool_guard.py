"""While Live Deform or Grab Deform runs on a mesh it owns that mesh's shape: the
operators that would rewrite or rebind it (Bind, Solve, Apply, Unbind, Bake) refuse with
the reason, in the reports (status bar, Info log) and over the view, instead of putting a
shape of their own under the tool's "settled" (docs/decisions/0040). The frame handler
leaves such a mesh alone too: Live follows animated controllers itself.
"""

from . import engine, modal_tool


def refuse_while_a_tool_runs(ob, action):
    """Raise EdgeDeformError naming the running tool and what to do, before `action`
    (the operator's name, e.g. "Solve") changes anything."""
    tool = modal_tool.running_tool(ob)
    if tool is None:
        return
    text = ("%s is running on '%s' and deforms it already: press Enter over the view to "
            "keep its shape or Esc to cancel, then %s" % (tool.bl_label, ob.name, action))
    note = getattr(tool, "text", None)   # Live's text over the view
    if note is not None:
        note.tell(text)
    raise engine.EdgeDeformError(text)


def busy(ob):
    """Is a modal tool deforming `ob` now (the frame handler then leaves it alone)?"""
    return modal_tool.running_tool(ob) is not None
