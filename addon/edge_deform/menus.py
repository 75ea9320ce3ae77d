"""Menu entries where artists look for a deform tool (and where F3 search finds them):
Object > Edge Deform, Edit Mode's Vertex menu and Weight Paint's Weights menu."""

import bpy


class EDGE_DEFORM_MT_object(bpy.types.Menu):
    bl_label = "Edge Deform"
    bl_idname = "EDGE_DEFORM_MT_object"

    def draw(self, context):
        layout = self.layout
        layout.operator("edge_deform.bind", icon='LINKED')
        layout.operator("edge_deform.live", icon='PLAY')
        layout.operator("edge_deform.solve", icon='FILE_REFRESH')
        layout.operator("edge_deform.apply", icon='CHECKMARK')
        layout.operator("edge_deform.bake", icon='REC')
        layout.separator()
        layout.operator("edge_deform.unbind", icon='UNLINKED')


def _object_menu(self, context):
    self.layout.separator()
    self.layout.menu(EDGE_DEFORM_MT_object.bl_idname)


def _edit_vertex_menu(self, context):
    layout = self.layout
    layout.separator()
    layout.operator("edge_deform.grab", text="Grab Deform", icon='VIEW_PAN')
    layout.operator("edge_deform.add_handle", text="Add Edge Deform Handle")
    layout.operator("edge_deform.set_static", text="Set Edge Deform Static")
    layout.operator("edge_deform.set_roi", text="Set Edge Deform Region")
    layout.operator_menu_enum("edge_deform.assign_stiffness", "preset",
                              text="Assign Edge Deform Stiffness")


def _weight_menu(self, context):
    layout = self.layout
    layout.separator()
    layout.operator_menu_enum("edge_deform.assign_stiffness", "preset",
                              text="Assign Edge Deform Stiffness")


# (menu class name, draw function): appended on register, removed on unregister.
ENTRIES = (("VIEW3D_MT_object", _object_menu),
           ("VIEW3D_MT_edit_mesh_vertices", _edit_vertex_menu),
           ("VIEW3D_MT_paint_weight", _weight_menu))

CLASSES = (EDGE_DEFORM_MT_object,)


def register_menus():
    for menu, draw in ENTRIES:
        getattr(bpy.types, menu).append(draw)


def unregister_menus():
    for menu, draw in ENTRIES:
        getattr(bpy.types, menu).remove(draw)
