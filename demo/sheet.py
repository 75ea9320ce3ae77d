"""One sample's results as a Blender scene laid out like the paper's figures, rendered cell by
cell and composed into a comparison sheet PNG.

Layout (2 rows x 4 columns, like Figs. 1 and 5 with the material cell of Figs. 8-10):
    rest (painted λ) | edge λ=0   | edge λ=0.5   | edge λ=1
    painted, edge    | primal λ=0 | primal λ=0.5 | primal λ=1
Every cell uses the same orthographic view and scale, so sizes compare directly.
"""
import os

import bpy
import numpy as np

import png
import render

GRID = [["rest", "edge_0", "edge_0.5", "edge_1"],
        ["painted_edge", "primal_0", "primal_0.5", "primal_1"]]
LETTERS = "abcdefgh"
GUTTER = 6


def cell_label(key, cell, letter):
    if key == "rest":
        return "(%s) rest, painted λ\nblue 0  grey .5  orange 1\ngreen handle  red static" % letter
    if key == "painted_edge":
        head = "(%s) painted λ, edge" % letter
    else:
        head = "(%s) %s  λ=%g" % (letter, cell["domain"], cell["lambda"])
    conv = "" if cell["converged"] else " (max)"
    return "%s\n%d it%s  %.0f ms" % (head, cell["iterations"], conv, cell["ms"])


def frame_points(V, cells, limit=2.5):
    """Points the view must hold: the rest shape and every result that stays within `limit`
    rest radii of the rest centre (a result that blew up would shrink all others to dots;
    it is then drawn clipped, and its metrics say what happened)."""
    c = V.mean(0)
    r = np.linalg.norm(V - c, axis=1).max()
    keep = [x["positions"] for x in cells
            if np.linalg.norm(x["positions"] - c, axis=1).max() <= limit * r]
    return np.vstack([V] + keep)


def build(scene_def, V, F, setup, cells, width, height):
    """Make a Blender scene holding the rest shape and every cell side by side; returns
    (scene, {key: (collection, camera)})."""
    sc = bpy.data.scenes.new(scene_def["name"])
    render.setup_render(sc, width, height)
    sc["edge_deform_title"] = scene_def["title"]
    aspect = width / height
    by_key = {c["key"]: c for c in cells}
    everything = frame_points(V, cells)
    right, up, _ = render.view_basis(*scene_def["view"])
    hidx, static, lam = setup["handle_index"], setup["static"], setup["stiffness"]
    painted_colours = render.vertex_colours(len(V), hidx, static, lam)
    plain_colours = render.vertex_colours(len(V), hidx, static)

    probe = render.add_camera(sc, everything, *scene_def["view"], aspect=aspect, name="probe")
    step_x = probe.data.ortho_scale * 1.04
    step_y = step_x / aspect
    base = np.array(probe.matrix_world)
    bpy.data.objects.remove(probe)

    cameras = {}
    for row, keys in enumerate(GRID):
        for col, key in enumerate(keys):
            letter = LETTERS[row * 4 + col]
            offset = col * step_x * right - row * step_y * up
            coll = bpy.data.collections.new("%s_%s" % (scene_def["name"], key))
            sc.collection.children.link(coll)
            X = V if key == "rest" else by_key[key]["positions"]
            colours = painted_colours if key in ("rest", "painted_edge") else plain_colours
            ob = render.new_mesh_object("%s_%s" % (scene_def["name"], key), X, F, colours, coll)
            ob.location = offset
            cam = render.add_camera(sc, everything, *scene_def["view"], aspect=aspect,
                                    name="cam_%s_%s" % (scene_def["name"], key))
            M = base.copy()
            M[:3, 3] += offset
            cam.matrix_world = render._matrix(M)
            sc.collection.objects.unlink(cam)
            coll.objects.link(cam)
            label = render.add_label(sc, cam, cell_label(key, by_key.get(key), letter),
                                     aspect, size=0.05, name="label_%s_%s" % (scene_def["name"], key))
            sc.collection.objects.unlink(label)
            coll.objects.link(label)
            cameras[key] = (coll, cam)
    overview = render.add_camera(sc, everything, *scene_def["view"], aspect=aspect,
                                 name="cam_%s_overview" % scene_def["name"])
    M = base.copy()
    M[:3, 3] += 1.5 * step_x * right - 0.5 * step_y * up
    overview.matrix_world = render._matrix(M)
    overview.data.ortho_scale = 4.2 * step_x
    sc.camera = overview
    return sc, cameras


def render_cells(sc, cameras, folder, name):
    """Render each cell alone (others hidden); returns {key: (h,w,3) float image}."""
    images = {}
    for key, (coll, cam) in cameras.items():
        for other, _ in cameras.values():
            other.hide_render = other is not coll
        sc.camera = cam
        path = os.path.join(folder, "%s_%s.png" % (name, key))
        sc.render.filepath = path
        bpy.ops.render.render(write_still=True, scene=sc.name)
        images[key] = render.load_png(path)
    for coll, _ in cameras.values():
        coll.hide_render = False
    return images


def compose(images, path):
    """Sheet PNG from the cell images; returns {key: [x, y, w, h]} pixel boxes."""
    h, w, _ = next(iter(images.values())).shape
    rows, cols = len(GRID), len(GRID[0])
    sheet = np.full((rows * h + (rows + 1) * GUTTER, cols * w + (cols + 1) * GUTTER, 3), 0.6)
    boxes = {}
    for r, keys in enumerate(GRID):
        for c, key in enumerate(keys):
            x, y = GUTTER + c * (w + GUTTER), GUTTER + r * (h + GUTTER)
            sheet[y:y + h, x:x + w] = images[key]
            boxes[key] = [x, y, w, h]
    png.write_png(path, sheet)
    return boxes


def small_copy(png_path, jpg_path, width=820, quality=82):
    """A downscaled JPEG of a sheet, small enough to commit under docs/img."""
    img = bpy.data.images.load(png_path)
    w, h = img.size
    img.scale(width, max(1, round(h * width / w)))
    sc = bpy.data.scenes.new("_jpeg")
    sc.render.image_settings.file_format = "JPEG"
    sc.render.image_settings.quality = quality
    sc.view_settings.view_transform = "Standard"
    img.save_render(jpg_path, scene=sc)
    bpy.data.scenes.remove(sc)
    bpy.data.images.remove(img)
    return jpg_path
