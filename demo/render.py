"""Blender side of the demo: mesh objects for result cells, camera framing, labelled renders.

Workbench renders in background mode here (no GPU, no display needed): studio light, cavity
and shadows make bending and stretching visible at a few hundred pixels. bpy <-> NumPy goes
through foreach_get/foreach_set only.
"""
import os

import bpy
import numpy as np

# stiffness colours: soft (0) blue, in-between (0.5) light grey, rigid (1) orange
_SOFT, _MID, _RIGID = np.array([0.25, 0.45, 0.95]), np.array([0.85, 0.85, 0.85]), np.array([0.95, 0.55, 0.15])
GREY = np.array([0.8, 0.8, 0.8])
HANDLE = np.array([0.1, 0.75, 0.2])
STATIC = np.array([0.85, 0.1, 0.1])


def stiffness_colours(lam):
    lam = np.clip(np.asarray(lam, float), 0, 1)[:, None]
    lo = _SOFT + (_MID - _SOFT) * (lam / 0.5)
    hi = _MID + (_RIGID - _MID) * ((lam - 0.5) / 0.5)
    return np.where(lam < 0.5, lo, hi)


def vertex_colours(n, handles, static, lam=None):
    """(n,3) colours: stiffness (or grey), with handle vertices green and static ones red."""
    c = stiffness_colours(lam) if lam is not None else np.tile(GREY, (n, 1))
    c[static] = STATIC
    c[handles] = HANDLE
    return c


def reset_scene(name="Scene"):
    """An empty scene, by deleting data rather than reloading factory settings (which would
    unregister add-ons such as edge_deform)."""
    for coll in (bpy.data.objects, bpy.data.meshes, bpy.data.cameras, bpy.data.lights,
                 bpy.data.curves, bpy.data.materials, bpy.data.images):
        for item in list(coll):
            coll.remove(item)
    sc = bpy.context.window.scene if bpy.context.window else bpy.context.scene
    for other in [s for s in bpy.data.scenes if s != sc]:
        bpy.data.scenes.remove(other)
    sc.name = name
    return sc


def new_mesh_object(name, V, F, colours=None, collection=None):
    me = bpy.data.meshes.new(name)
    me.vertices.add(len(V))
    me.vertices.foreach_set("co", np.asarray(V, np.float32).ravel())
    F = np.asarray(F)
    me.loops.add(F.size)
    me.loops.foreach_set("vertex_index", F.astype(np.int32).ravel())
    me.polygons.add(len(F))
    me.polygons.foreach_set("loop_start", np.arange(0, F.size, 3, dtype=np.int32))
    me.polygons.foreach_set("loop_total", np.full(len(F), 3, np.int32))
    me.update()
    me.validate()
    if colours is not None:
        set_colours(me, colours)
    ob = bpy.data.objects.new(name, me)
    (collection or bpy.context.scene.collection).objects.link(ob)
    return ob


def set_colours(me, colours):
    attr = me.color_attributes.get("Col") or me.color_attributes.new("Col", "FLOAT_COLOR", "POINT")
    rgba = np.ones((len(me.vertices), 4), np.float32)
    rgba[:, :3] = colours
    attr.data.foreach_set("color", rgba.ravel())
    me.color_attributes.active_color = attr


def set_positions(ob, V):
    ob.data.vertices.foreach_set("co", np.asarray(V, np.float32).ravel())
    ob.data.update()


def view_basis(azimuth, elevation):
    """Camera (right, up, forward) for a view from azimuth/elevation degrees (Z up;
    azimuth 0 looks along +Y, i.e. the camera sits on -Y)."""
    a, e = np.radians(azimuth), np.radians(elevation)
    fwd = np.array([np.sin(a) * np.cos(e), np.cos(a) * np.cos(e), -np.sin(e)])
    right = np.cross(fwd, [0, 0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    return right, up, fwd


def setup_render(sc, width, height):
    sc.render.engine = "BLENDER_WORKBENCH"
    sc.render.resolution_x, sc.render.resolution_y = width, height
    sc.render.resolution_percentage = 100
    sc.render.image_settings.file_format = "PNG"
    sc.render.image_settings.color_mode = "RGB"
    sc.render.film_transparent = False
    sh = sc.display.shading
    sh.light = "STUDIO"
    sh.studio_light = "outdoor.sl" if "outdoor.sl" in _studio_lights() else sh.studio_light
    sh.color_type = "VERTEX"
    sh.show_cavity = True
    sh.cavity_type = "BOTH"
    sh.show_shadows = True
    sh.shadow_intensity = 0.35
    sh.show_specular_highlight = True
    sc.display.light_direction = (0.5, -0.4, 0.75)
    sc.display.render_aa = "8"
    if sc.world is None:
        sc.world = bpy.data.worlds.new("World")
    sc.world.color = (1.0, 1.0, 1.0)
    sc.view_settings.view_transform = "Standard"


def _studio_lights():
    return {sl.name for sl in bpy.context.preferences.studio_lights}


def add_camera(sc, points, azimuth, elevation, aspect, margin=1.08, name="Camera"):
    """Orthographic camera looking at `points` (k,3) from the given view, framing all of them."""
    right, up, fwd = view_basis(azimuth, elevation)
    pts = np.asarray(points)
    u, v, w = pts @ right, pts @ up, pts @ fwd
    cu, cv = (u.min() + u.max()) / 2, (v.min() + v.max()) / 2
    # leave a top strip for the label
    span = max(u.max() - u.min(), (v.max() - v.min()) * aspect * 1.15)
    centre = cu * right + (cv + 0.06 * span / aspect) * up
    cam = bpy.data.objects.new(name, bpy.data.cameras.new(name))
    cam.data.type = "ORTHO"
    cam.data.ortho_scale = span * margin
    cam.data.clip_start, cam.data.clip_end = 0.01, 100.0
    M = np.eye(4)
    M[:3, 0], M[:3, 1], M[:3, 2] = right, up, -fwd   # a camera looks down its local -Z
    M[:3, 3] = centre + (w.min() - 5.0) * fwd        # in front of the nearest point
    cam.matrix_world = _matrix(M)
    sc.collection.objects.link(cam)
    sc.camera = cam
    return cam


def _matrix(M):
    from mathutils import Matrix
    return Matrix(M.tolist())


def add_label(sc, cam, text, aspect, size=0.075, name="Label"):
    """Black text in the camera's top-left corner (a child of the camera). Converted to a mesh
    with black vertex colours, because the Workbench colour mode is per scene (VERTEX)."""
    curve = bpy.data.curves.new(name, "FONT")
    font = _label_font()
    if font is not None:
        curve.font = font
    else:                          # Blender's built-in font has no Greek letters
        text = text.replace("λ", "lambda ")
    curve.body = text
    curve.size = cam.data.ortho_scale * size
    tmp = bpy.data.objects.new(name + "_curve", curve)
    sc.collection.objects.link(tmp)
    me = bpy.data.meshes.new_from_object(tmp.evaluated_get(bpy.context.evaluated_depsgraph_get()))
    bpy.data.objects.remove(tmp)
    bpy.data.curves.remove(curve)
    set_colours(me, np.zeros((len(me.vertices), 3)))
    ob = bpy.data.objects.new(name, me)
    half_w = cam.data.ortho_scale / 2
    half_h = half_w / aspect
    ob.parent = cam
    # just past the near clip plane: in front of everything, even a result that blew up
    ob.location = (-half_w * 0.96, half_h - cam.data.ortho_scale * size * 1.2, -0.02)
    sc.collection.objects.link(ob)
    return ob


def _label_font(path="/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"):
    font = bpy.data.fonts.get("DejaVuSans")
    if font is None and os.path.exists(path):
        font = bpy.data.fonts.load(path)
        font.name = "DejaVuSans"
    return font


def render_to(sc, path):
    sc.render.filepath = path
    bpy.ops.render.render(write_still=True)
    return path


def load_png(path):
    """(h,w,3) float32 RGB of a PNG, top row first."""
    img = bpy.data.images.load(path)
    w, h = img.size
    px = np.empty(w * h * 4, np.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    return px.reshape(h, w, 4)[::-1, :, :3]
