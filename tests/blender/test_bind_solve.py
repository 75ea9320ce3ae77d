"""Background tests of bind, solve, apply and unbind (and the error paths)."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from helpers import (Matrix, activate, add_group, add_handle, bpy, ed, expect_error,  # noqa
                     key_positions,
                     load, loop_triangles, make_object, np, positions, run, transform)


def plane_setup(name="plane", stiffness=0.5):
    """cgal_plane.off: handles on one strip, static on the opposite strip."""
    V, F = load("cgal_plane.off")
    ob = make_object(name, V, F)
    x = V[:, 0]
    handle = np.flatnonzero(x > x.max() - 0.1 * np.ptp(x))
    static = np.flatnonzero(x < x.min() + 0.1 * np.ptp(x))
    add_group(ob, "H", handle)
    add_group(ob, "S", static)
    s = ob.edge_deform
    s.static_group = "S"
    s.stiffness = stiffness
    s.iterations = 20
    ctrl = add_handle(ob, "H", V[handle].mean(axis=0))
    return ob, V, F, handle, static, ctrl


def move(ctrl, offset=(0.0, 0.0, 0.3), angle=0.4):
    ctrl.matrix_world = (Matrix.Translation(ctrl.matrix_world.translation + __import__(
        "mathutils").Vector(offset)) @ Matrix.Rotation(angle, 4, 'Y'))
    bpy.context.view_layer.update()


def expected_targets(ob, ctrl, rest_matrix, X, handle):
    M = np.array(ctrl.matrix_world) @ np.linalg.inv(np.array(rest_matrix))
    return transform(M, X[handle])


def api_solve(X, F, handle, static, targets, lam, domain="edge", iterations=20, tol=1e-3):
    d = ed.Deformer(X.astype(float), F, domain=domain)
    d.set_constraints(handles=handle, static=static, roi=None)
    d.set_stiffness(lam)
    # verify_claims: as the add-on's solves (session.Binding.solve)
    return d.solve(targets, max_iterations=iterations, tolerance=tol, warm_start=False,
                   verify_claims=True)


def test_solve_matches_api():
    ob, V, F, handle, static, ctrl = plane_setup()
    rest = positions(ob.data).copy()
    rest_matrix = ctrl.matrix_world.copy()
    assert bpy.ops.edge_deform.bind() == {'FINISHED'}
    move(ctrl)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    out = key_positions(ob)
    T = expected_targets(ob, ctrl, rest_matrix, rest.astype(float), handle)
    assert np.abs(out[handle] - T).max() < 1e-5, "handles reach their targets"
    assert np.array_equal(out[static], rest[static]), "static vertices bit-exact"
    assert np.array_equal(positions(ob.data), rest), "SHAPE_KEY output leaves the base mesh"
    r = api_solve(rest, loop_triangles(ob.data), handle, static, T, 0.5)
    assert np.abs(out - r.positions).max() < 1e-5, "equals the Python API"
    free = np.setdiff1d(np.arange(len(rest)), np.union1d(handle, static))
    assert np.abs(out[free] - rest[free]).max() > 0.05, "the free vertices moved"


def test_output_mesh_keeps_rest():
    ob, V, F, handle, static, ctrl = plane_setup()
    rest = positions(ob.data).copy()
    ob.edge_deform.output = 'MESH'
    rest_matrix = ctrl.matrix_world.copy()
    move(ctrl)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    out = positions(ob.data)
    assert ob.data.shape_keys is None
    T = expected_targets(ob, ctrl, rest_matrix, rest.astype(float), handle)
    assert np.abs(out[handle] - T).max() < 1e-5
    r = api_solve(rest, loop_triangles(ob.data), handle, static, T, 0.5)
    assert np.abs(out - r.positions).max() < 1e-5
    # A second solve must start from the stored rest, not from the deformed base mesh:
    # controller back at rest -> the mesh returns to rest.
    from edge_deform import engine
    engine.forget_all()                       # as after a reload: only the .blend is left
    ctrl.matrix_world = rest_matrix
    bpy.context.view_layer.update()
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    assert np.abs(positions(ob.data) - rest).max() < 1e-5


def test_settings_change_rebinds():
    ob, V, F, handle, static, ctrl = plane_setup()
    rest = positions(ob.data).astype(float)
    rest_matrix = ctrl.matrix_world.copy()
    bpy.ops.edge_deform.bind()
    move(ctrl)
    T = expected_targets(ob, ctrl, rest_matrix, rest, handle)
    tris = loop_triangles(ob.data)
    for domain, lam in (("PRIMAL", 0.5), ("PRIMAL", 1.0), ("EDGE", 0.0)):
        ob.edge_deform.domain = domain
        ob.edge_deform.stiffness = lam
        assert bpy.ops.edge_deform.solve() == {'FINISHED'}
        r = api_solve(rest, tris, handle, static, T, lam, domain=domain.lower())
        assert np.abs(key_positions(ob) - r.positions).max() < 1e-5, (domain, lam)
    # Changing the static group's contents is a settings change too.
    small = static[: len(static) // 2]
    ob.vertex_groups["S"].remove(static[len(static) // 2:].tolist())
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    r = api_solve(rest, tris, handle, small, T, 0.0)
    assert np.abs(key_positions(ob) - r.positions).max() < 1e-5


def test_stiffness_group():
    ob, V, F, handle, static, ctrl = plane_setup()
    rest = positions(ob.data).astype(float)
    lam = np.where(rest[:, 1] > np.median(rest[:, 1]), 1.0, 0.25)
    add_group(ob, "stiff", np.flatnonzero(lam == 1.0), 1.0)
    add_group(ob, "stiff", np.flatnonzero(lam == 0.25), 0.25)
    ob.edge_deform.stiffness_group = "stiff"
    rest_matrix = ctrl.matrix_world.copy()
    move(ctrl)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    T = expected_targets(ob, ctrl, rest_matrix, rest, handle)
    r = api_solve(rest, loop_triangles(ob.data), handle, static, T, lam)
    assert np.abs(key_positions(ob) - r.positions).max() < 1e-5


def test_quads_and_ngons():
    # A quad grid and a cylinder (quads + two n-gon caps): internal triangulation only.
    for kind in ("grid", "cylinder"):
        if kind == "grid":
            bpy.ops.mesh.primitive_grid_add(x_subdivisions=12, y_subdivisions=12, size=2)
        else:
            bpy.ops.mesh.primitive_cylinder_add(vertices=16, depth=2)
        ob = bpy.context.active_object
        ob.modifiers.new("subsurf", 'SUBSURF')   # other modifiers must not disturb reads
        me = ob.data
        counts = (len(me.vertices), len(me.edges), len(me.polygons))
        sizes = {p.loop_total for p in me.polygons}
        rest = positions(me).copy()
        axis = 0 if kind == "grid" else 2
        handle = np.flatnonzero(rest[:, axis] > rest[:, axis].max() - 1e-4)
        static = np.flatnonzero(rest[:, axis] < rest[:, axis].min() + 1e-4)
        add_group(ob, "H", handle)
        add_group(ob, "S", static)
        ob.edge_deform.static_group = "S"
        ob.edge_deform.iterations = 20
        ctrl = add_handle(ob, "H", rest[handle].mean(axis=0))
        rest_matrix = ctrl.matrix_world.copy()
        move(ctrl, (0.3, 0.2, 0.4), 0.3)
        assert bpy.ops.edge_deform.solve() == {'FINISHED'}, kind
        out = key_positions(ob)
        T = expected_targets(ob, ctrl, rest_matrix, rest.astype(float), handle)
        assert np.abs(out[handle] - T).max() < 1e-5, kind
        assert np.array_equal(out[static], rest[static]), kind
        assert (len(me.vertices), len(me.edges), len(me.polygons)) == counts, kind
        assert {p.loop_total for p in me.polygons} == sizes and max(sizes) > 3, kind
        assert ob.modifiers["subsurf"].show_viewport, kind
        r = api_solve(rest, loop_triangles(me), handle, static, T, 0.5)
        assert np.abs(out - r.positions).max() < 1e-5, kind
        bpy.data.objects.remove(ob)


def test_object_transform_and_warm_start():
    """Targets live in object space: a rotated, scaled object with a moved controller."""
    ob, V, F, handle, static, ctrl = plane_setup()
    ob.matrix_world = Matrix.Translation((1, 2, 3)) @ Matrix.Rotation(0.7, 4, 'Z') \
        @ Matrix.Scale(2.0, 4)
    bpy.context.view_layer.update()
    bpy.ops.edge_deform.bind()   # records the controller's rest
    rest_matrix = ctrl.matrix_world.copy()
    rest = positions(ob.data).astype(float)
    move(ctrl, (0, 0, 0.5), 0.0)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    obmw = np.array(ob.matrix_world)
    A = np.linalg.inv(obmw) @ np.array(ctrl.matrix_world) @ np.linalg.inv(
        np.array(rest_matrix)) @ obmw
    T = transform(A, rest[handle])
    out = key_positions(ob)
    assert np.abs(out[handle] - T).max() < 1e-5
    # World-space handle motion equals the controller's motion (0.5 up).
    world = transform(obmw, out[handle].astype(float)) - transform(obmw, rest[handle])
    assert np.allclose(world, [0, 0, 0.5], atol=1e-4)
    # Warm start from the previous solve, same targets: stays at the solution.
    assert bpy.ops.edge_deform.solve(warm_start=True) == {'FINISHED'}
    assert np.abs(key_positions(ob) - out).max() < 1e-3


def test_topology_change_never_wrong():
    ob, V, F, handle, static, ctrl = plane_setup()
    bpy.ops.edge_deform.bind()
    move(ctrl)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    ob.shape_key_clear()
    # Change the topology: subdivide every face in Edit Mode.
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='SELECT')
    bpy.ops.mesh.subdivide()
    bpy.ops.object.mode_set(mode='OBJECT')
    n = len(ob.data.vertices)
    assert n > len(V)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}   # rebinds by itself
    out = key_positions(ob)
    assert out.shape == (n, 3)
    vg = {name: np.flatnonzero([ob.vertex_groups[name].index in
                                [g.group for g in v.groups] for v in ob.data.vertices])
          for name in ("H", "S")}   # test-side membership (slow but independent)
    rest = positions(ob.data).astype(float)
    h = ob.edge_deform.handles[0]
    T = transform(np.array(ctrl.matrix_world) @ np.linalg.inv(np.array(h.rest_matrix)),
                  rest[vg["H"]])
    r = api_solve(rest, loop_triangles(ob.data), vg["H"], vg["S"], T, 0.5)
    assert np.abs(out - r.positions).max() < 1e-5

    # Base-mesh output after a topology change: refuse, leave the mesh alone.
    ob.shape_key_clear()
    ob.edge_deform.output = 'MESH'
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='SELECT')
    bpy.ops.mesh.subdivide()
    bpy.ops.object.mode_set(mode='OBJECT')
    before = positions(ob.data).copy()
    expect_error(bpy.ops.edge_deform.solve, "topology changed")
    assert np.array_equal(positions(ob.data), before)
    assert bpy.ops.edge_deform.bind() == {'FINISHED'}    # accepts the current mesh
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}


def _untouched_after(ob, fragment, op="solve"):
    before = positions(ob.data).copy()
    expect_error(getattr(bpy.ops.edge_deform, op), fragment)
    assert np.array_equal(positions(ob.data), before)
    assert ob.data.shape_keys is None


def test_bad_input_cancels():
    ob, V, F, handle, static, ctrl = plane_setup()
    # Handle and static overlap.
    add_group(ob, "S", handle[:3])
    _untouched_after(ob, "both handle and static")
    _untouched_after(ob, "both handle and static", "bind")
    ob.vertex_groups["S"].remove(handle[:3].tolist())
    # Empty handle group.
    ob.vertex_groups.new(name="E")
    ob.edge_deform.handles.add().vertex_group = "E"
    _untouched_after(ob, "handle group 'E' is empty")
    ob.edge_deform.handles.remove(1)
    # Missing and empty groups.
    ob.edge_deform.roi_group = "nope"
    _untouched_after(ob, "'nope' does not exist")
    ob.edge_deform.roi_group = "E"
    _untouched_after(ob, "region group 'E' is empty")
    ob.edge_deform.roi_group = ""
    # Two handles sharing vertices.
    add_group(ob, "H2", handle[:2])
    add_handle(ob, "H2")
    _untouched_after(ob, "two handle groups")
    ob.edge_deform.handles.remove(1)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}   # and now it is fine
    # No handles: the operator is not available (poll), nothing changes.
    ob.shape_key_clear()
    ob.edge_deform.handles.clear()
    assert not bpy.ops.edge_deform.solve.poll()

    # Non-manifold (three triangles on one edge) deforms like any mesh (docs/api.md): the
    # solve finishes and writes its shape key.
    V = np.array([[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0], [0.5, 0, 1]], float)
    bad = make_object("fin", V, [[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    add_group(bad, "H", [2])
    add_group(bad, "S", [3])
    bad.edge_deform.static_group = "S"
    add_handle(bad, "H")
    activate(bad)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    assert bad.data.shape_keys is not None
    # A core error (every vertex at one point) cancels with the mesh untouched.
    point = make_object("point", np.zeros_like(V), [[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    add_group(point, "H", [2])
    add_handle(point, "H")
    activate(point)
    _untouched_after(point, "at one point")


def test_apply_and_unbind():
    ob, V, F, handle, static, ctrl = plane_setup()
    rest_matrix = ctrl.matrix_world.copy()
    move(ctrl)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    shown = key_positions(ob).copy()
    assert bpy.ops.edge_deform.apply() == {'FINISHED'}
    assert ob.data.shape_keys is None, "only our keys existed: they are gone"
    assert np.array_equal(positions(ob.data), shown), "the base mesh holds what was shown"
    h = ob.edge_deform.handles[0]
    assert np.allclose(np.array(h.rest_matrix), np.array(ctrl.matrix_world))
    assert not np.allclose(np.array(h.rest_matrix), np.array(rest_matrix))
    # New rest: solving again without moving keeps the shape.
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    assert np.abs(key_positions(ob) - shown).max() < 1e-5
    from edge_deform import engine
    assert engine.cached_binding(ob.data.as_pointer()) is not None
    assert bpy.ops.edge_deform.unbind() == {'FINISHED'}
    assert engine.cached_binding(ob.data.as_pointer()) is None


def test_solve_names_a_graph_rebuild():
    """After a domain change from the panel (only a setting), the next Solve from the UI
    builds the new graph in stages it names; closed between them (Esc), the cached graph
    and the mesh stay as they were."""
    from edge_deform import engine, lifecycle
    ob, V, F, handle, static, ctrl = plane_setup("plane_domain")
    assert bpy.ops.edge_deform.bind() == {'FINISHED'}
    move(ctrl)
    ob.edge_deform.domain = 'PRIMAL'
    pointer = ob.data.as_pointer()
    assert engine.cached_binding(pointer).domain == 'EDGE', "a domain change alone rebuilds nothing"
    steps = lifecycle.deform_steps(ob)
    texts = [next(steps)[1], next(steps)[1]]   # the graph is built after the second
    assert "building the vertex graph of %d triangles" % len(loop_triangles(ob.data)) \
        in texts[0] and "factoring" in texts[1], texts
    steps.close()
    assert engine.cached_binding(pointer).domain == 'EDGE' and ob.data.shape_keys is None
    bound, r, _ = lifecycle._to_end(lifecycle.deform_steps(ob))
    assert engine.cached_binding(pointer).domain == 'PRIMAL' and bound.binding.domain == 'PRIMAL'
    assert ob.data.shape_keys is not None and r.iterations > 0


class _Results:
    """solve(n, check_claims) for settle.Settle: real warm solves of the plane, n
    iterations each, checking their claim when asked (as the add-on's solves)."""

    def __init__(self, d, targets, tol):
        self.d, self.targets, self.tol = d, targets, tol

    def __call__(self, n, check_claims):
        return self.d.solve(self.targets, max_iterations=n, tolerance=self.tol,
                            warm_start=True, verify_claims=check_claims)


def test_modal_tools_stop_settling_at_the_limit():
    """settle.describe, on real solve results: 'settled' only when converged; past
    SETTLE_LIMIT iterations without it, the tools stop and say how far the shape may be."""
    from edge_deform import modal_rules
    ob, V, F, handle, static, ctrl = plane_setup()
    rest = positions(ob.data).astype(float)
    T = rest[handle] + np.array([0.0, 0.0, 0.3])
    d = ed.Deformer(rest, F, domain="edge")
    d.set_constraints(handles=handle, static=static)
    d.set_stiffness(0.5)
    done = modal_rules.Settle(limit=5000)
    while not done.at_rest:
        done.tick(_Results(d, T, 1e-3), moving=False)
    assert done.settled and done.result.converged
    # The still ticks' claim was checked by the core (or is a fixed point to round-off).
    assert done.result.claim_checks >= 1 or done.result.residuals[-1] <= 1e-9
    text = modal_rules.describe(done, "move a controller")
    assert text.startswith("settled, %d iterations" % done.iterations), text
    d.set_constraints(handles=handle, static=static)   # (a new solve)
    going = modal_rules.Settle(limit=10 ** 6)   # (one tick never reaches this limit)
    going.tick(_Results(d, T, 0.0), moving=False)
    assert not going.result.converged and not going.at_rest
    text = modal_rules.describe(going, "move a controller")
    assert text.startswith("settling…"), text
    going = modal_rules.Settle(limit=60)
    while not going.at_rest:
        going.tick(_Results(d, T, 0.0), moving=False)
    assert going.gave_up and going.iterations == 60, going.iterations
    text = modal_rules.describe(going, "move a controller")
    assert "settled" not in text, text
    assert text.startswith("stopped after 60 iterations, not converged"), text
    assert text.endswith("; move a controller to go on"), text
    estimate = float(going.result.distance_estimate)
    assert (("estimated %.0e of the size away" % estimate) in text if np.isfinite(estimate)
            else "distance unknown" in text), text


def test_acceleration_choices_follow_the_package():
    """The Acceleration setting lists the add-on's methods this build of the package solves
    with, defaults to Automatic (no method named: the package's rule), and each choice solves."""
    from edge_deform import engine
    ob, V, F, handle, static, ctrl = plane_setup()
    s = ob.edge_deform
    d = ed.Deformer(V.astype(float), F)
    d.set_constraints(handles=handle)
    names = []
    for name in [n for _, n in engine.ACCELERATIONS] + ["newton"]:   # newton: retired (0070)
        try:
            d.solve(V[handle].astype(float), max_iterations=1, acceleration=name)
            names.append(name)
        except ValueError:
            pass
    assert engine.offered_accelerations() == names, (engine.offered_accelerations(), names)
    assert engine.acceleration(s) is None
    items = []
    for item, name in engine.ACCELERATIONS:   # (a dynamic enum lists items only to a UI)
        try:
            s.acceleration = item
            items.append(item)
        except TypeError:
            pass
        assert (item in items) == (name in names), (item, names)
    ctrl.location.z += 0.3
    bpy.context.view_layer.update()
    for item in items:
        s.acceleration = item
        assert bpy.ops.edge_deform.solve() == {'FINISHED'}
        assert engine.acceleration(s) == dict(engine.ACCELERATIONS)[item]


def test_automatic_names_no_method():
    """Acceleration defaults to Automatic: the add-on's solves name no method, so the
    package's default rule chooses (docs/decisions/0043); an explicit choice is named."""
    from edge_deform import engine
    ob, V, F, handle, static, ctrl = plane_setup("plane_auto")
    s = ob.edge_deform
    assert s.acceleration == engine.AUTOMATIC, s.acceleration
    assert bpy.ops.edge_deform.bind() == {'FINISHED'}
    binding = engine.cached_binding(ob.data.as_pointer())
    calls = []

    class Spy:
        """The binding's Deformer, recording the keywords of each solve."""
        def __init__(self, deformer):
            self.deformer = deformer

        def solve(self, *args, **kwargs):
            calls.append(kwargs)
            return self.deformer.solve(*args, **kwargs)

        def __getattr__(self, name):
            return getattr(self.deformer, name)
    binding._deformer = Spy(binding.deformer)
    move(ctrl)
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    assert calls and all("acceleration" not in k for k in calls), calls
    s.acceleration = 'ANDERSON'
    calls.clear()
    assert bpy.ops.edge_deform.solve() == {'FINISHED'}
    assert calls and all(k.get("acceleration") == "anderson" for k in calls), calls


def test_solves_check_their_convergence_claim():
    """The add-on's solves ask the core to check a convergence claim against J_G's slowest
    mode (verify_claims, docs/decisions/0025) unless told not to (a drag tick): the same
    shape, the check counted."""
    from edge_deform import lifecycle
    ob, V, F, handle, static, ctrl = plane_setup("plane_claims")
    ob.edge_deform.iterations = 2000
    move(ctrl)
    solver, checked = lifecycle.deform(ob)
    assert checked.converged and checked.claim_checks >= 1, (checked.converged, checked.claim_checks)
    assert checked.refused_claims < checked.claim_checks   # the last check kept the claim
    unchecked = solver.solve(solver.targets(), 2000, ob.edge_deform.tolerance, warm=False,
                             check_claims=False)
    assert unchecked.converged and unchecked.claim_checks == 0
    assert unchecked.iterations <= checked.iterations
    diag = np.linalg.norm(np.ptp(V, axis=0))
    apart = np.linalg.norm(checked.positions - unchecked.positions, axis=1).max() / diag
    assert apart <= 2 * ob.edge_deform.tolerance, apart


if __name__ == "__main__":
    run([test_solve_matches_api, test_output_mesh_keeps_rest, test_settings_change_rebinds,
         test_stiffness_group, test_quads_and_ngons, test_object_transform_and_warm_start,
         test_topology_change_never_wrong, test_bad_input_cancels, test_apply_and_unbind,
         test_solve_names_a_graph_rebuild, test_modal_tools_stop_settling_at_the_limit,
         test_acceleration_choices_follow_the_package, test_automatic_names_no_method,
         test_solves_check_their_convergence_claim])
