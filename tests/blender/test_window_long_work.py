"""Real-window test (Xvfb, --enable-event-simulate) of long work on a 50k-vertex
mesh (a generated grid, 224 x 224 vertices):
  - Esc right after Bind starts cancels it: not bound, nothing recorded;
  - Bind from the UI shows its progress: the fraction rises from 0 to 1 over the stages, and
    the status bar is redrawn with each stage's text ("factoring 150k graph nodes…")
    before that stage runs, so the user sees it while waiting;
  - a long Solve from the UI runs in chunks: Esc in the middle stops it and the mesh is
    byte-identical to before (vertices, no shape key, the add-on's stored state);
  - a domain switch during Live: the status bar names the graph building and the
    factoring before each runs, Live goes on and the mesh follows; Esc between the
    stages keeps the previous graph with the mesh unchanged;
  - an uncancelled chunked Solve (on the small plane) writes exactly what the one-call
    Solve of a script writes."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from helpers import (Told, activate, add_group, add_handle, bpy, key_positions,  # noqa: E402
                     np, positions)
from window_harness import main, override, setup, tap, until  # noqa: E402

N = 224   # grid side: 50176 vertices


def big_grid():
    """A 2 x 2 grid in the XZ plane, N x N vertices, quads, added with bulk writes."""
    s = np.linspace(-1.0, 1.0, N)
    x, z = np.meshgrid(s, s)
    V = np.c_[x.ravel(), np.zeros(N * N), z.ravel()]
    i, j = np.meshgrid(np.arange(N - 1), np.arange(N - 1))
    a = (j * N + i).ravel()
    quads = np.c_[a, a + 1, a + N + 1, a + N]
    mesh = bpy.data.meshes.new("big")
    mesh.vertices.add(len(V))
    mesh.vertices.foreach_set("co", V.ravel())
    mesh.loops.add(quads.size)
    mesh.loops.foreach_set("vertex_index", quads.ravel())
    mesh.polygons.add(len(quads))
    mesh.polygons.foreach_set("loop_start", np.arange(0, quads.size, 4))
    mesh.polygons.foreach_set("loop_total", np.full(len(quads), 4))
    mesh.update(calc_edges=True)
    assert not mesh.validate()
    ob = bpy.data.objects.new("big", mesh)
    bpy.context.scene.collection.objects.link(ob)
    handle = np.flatnonzero(V[:, 0] > 0.8)
    add_group(ob, "BH", handle)
    add_group(ob, "BS", np.flatnonzero(V[:, 0] < -0.8))
    ob.edge_deform.static_group = "BS"
    ctrl = add_handle(ob, "BH", V[handle].mean(axis=0))
    activate(ob)
    return ob, ctrl


def stored_state(mesh):
    st = mesh.edge_deform_state
    return {name: getattr(st, name) for name in
            ("output", "output_key", "topology", "written", "base", "baked_keys")}


def marked_graph_work(seen):
    """Record in `seen` when the graph work really runs: ('ran', 'build' or 'factor',
    domain) at the start of Binding.build and Binding.sync (which factors). Returns the
    function that puts the originals back."""
    from edge_deform import engine
    build, sync = engine.Binding.build, engine.Binding.sync

    def marked_build(binding, ed, domain):
        seen.append(('ran', 'build', domain))
        return build(binding, ed, domain)

    def marked_sync(binding, ed, inputs, owner):
        seen.append(('ran', 'factor', inputs.domain))
        return sync(binding, ed, inputs, owner)

    engine.Binding.build, engine.Binding.sync = marked_build, marked_sync

    def unmark():
        engine.Binding.build, engine.Binding.sync = build, sync
    return unmark


def first(seen, predicate, start=0):
    return next((i for i in range(start, len(seen)) if predicate(*seen[i])), None)


def live_domain_switch(ob, ctrl, seen):
    """During Live on the 50k grid the domain changes (as the Solver sub-panel sets it;
    Live has no domain key): the status bar names the rebuild's stages before they run,
    Live goes on with the new graph and the mesh follows the controller. A second switch
    cancelled by Esc keeps the graph and leaves the mesh as it was; Enter keeps."""
    from edge_deform import engine, mesh_io, modal, op_common
    s = ob.edge_deform
    s.iterations, s.tolerance = 20, 1e-3
    rest = positions(ob.data)
    handle = np.flatnonzero(rest[:, 0] > 0.8)
    with Told() as told:
        with override():
            assert bpy.ops.edge_deform.live('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
        tool = modal.running_tool(ob)
        yield from until(lambda: "settled" in (tool.status_text or ""), 120)
        assert "settled" in tool.status_text, tool.status_text
        at_cancel = []

        def capture(level, text):   # the key at the moment the switch is cancelled
            if "cancelled" in text:
                at_cancel.append(key_positions(ob).tobytes())
        unmark = marked_graph_work(seen)
        try:
            seen.clear()
            s.domain = 'PRIMAL'
            yield from until(lambda: any(k == 'end' for k, _, _ in seen), 120)
            built = first(seen, lambda k, what, d: (k, what, d) == ('ran', 'build', 'PRIMAL'))
            assert built is not None, seen
            drawn = first(seen, lambda k, text, _: k == 'drawn'
                          and "building the vertex graph of" in text)
            assert drawn is not None and drawn < built, \
                "the status bar showed the graph building before it ran: %s" % seen
            factored = first(seen, lambda k, what, d: k == 'ran' and what == 'factor', built)
            assert factored is not None, seen
            drawn = first(seen, lambda k, text, _: k == 'drawn' and "factoring" in text
                          and "graph nodes" in text, built)
            assert drawn is not None and drawn < factored, \
                "the status bar showed the factoring before it ran: %s" % seen
            kinds = [k for k, _, _ in seen]
            assert kinds.count('begin') == 1 and kinds.count('end') == 1, kinds
            assert modal.running_tool(ob) is tool, "Live goes on after the switch"
            assert engine.cached_binding(ob.data.as_pointer()).domain == 'PRIMAL'
            print("live domain switch: %d stages drawn before they ran: ok"
                  % kinds.count('drawn'))

            # The mesh follows the controller with the new graph.
            ctrl.location.z += 0.2
            bpy.context.view_layer.update()
            offset = (key_positions(ob)[handle] - rest[handle]).mean(axis=0) + [0, 0, 0.2]
            yield from until(lambda: np.abs((key_positions(ob)[handle] - rest[handle])
                                            .mean(axis=0) - offset).max() < 1e-4, 60)
            moved = (key_positions(ob)[handle] - rest[handle]).mean(axis=0)
            assert np.abs(moved - offset).max() < 1e-4, (moved, offset)
            print("after the switch the mesh follows the controller (%s): ok"
                  % tool.status_text)

            # Esc between the stages: the vertex graph stays, the mesh as it was when the
            # switch began (Live may go on settling afterwards: read it at the cancel).
            op_common.listeners.append(capture)
            before = key_positions(ob).tobytes()
            seen.clear()
            s.domain = 'EDGE'
            yield from until(lambda: any(k == 'update' and "building" in t
                                         for k, t, _ in seen), 60)
            tap('ESC')
            yield from until(lambda: told.has('WARNING', "domain switch cancelled"), 60)
        finally:
            unmark()
            if capture in op_common.listeners:
                op_common.listeners.remove(capture)
        assert told.has('WARNING', "Domain switch cancelled: the vertex graph is kept"), \
            told.messages
        assert modal.running_tool(ob) is tool, "Esc ended the switch, not Live"
        assert s.domain == 'PRIMAL' and engine.cached_binding(ob.data.as_pointer()).domain == 'PRIMAL'
        assert at_cancel == [before], "a cancelled switch writes nothing"
        assert [k for k, _, _ in seen if k in ('begin', 'end')] == ['begin', 'end'], seen
        tap('RET')
        yield from until(lambda: modal.running_tool() is None, 60)
    assert told.has('INFO', "Live Deform kept the shape"), told.messages
    assert mesh_io.owned_key(ob.data) is not None
    print("Esc during a domain switch keeps the vertex graph, mesh unchanged; Enter "
          "keeps: ok")


def steps():
    from edge_deform import op_common
    tap('ESC')   # dismiss the splash screen
    yield
    setup()
    ob, ctrl = big_grid()
    assert len(ob.data.vertices) == N * N
    seen = []
    op_common.progress_listeners.append(
        lambda kind, text, fraction: seen.append((kind, text, fraction)))

    # ------------------------------------------------------------ Esc stops a Bind
    from edge_deform import lifecycle
    state, rest_matrix = stored_state(ob.data), ob.edge_deform.handles[0].rest_matrix.copy()
    ctrl.location.y += 0.1   # a Bind would record this as the controller's rest
    bpy.context.view_layer.update()
    with Told() as told:
        with override():
            assert bpy.ops.edge_deform.bind('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
        tap('ESC')
        yield from until(lambda: told.has('WARNING', "cancelled"), 60)
    assert told.has('WARNING', "Bind of 'big' cancelled"), told.messages
    assert not lifecycle.is_bound(ob.data) and stored_state(ob.data) == state
    assert ob.edge_deform.handles[0].rest_matrix == rest_matrix, "the rest is not recorded"
    ctrl.location.y -= 0.1
    bpy.context.view_layer.update()
    seen.clear()
    print("Esc during Bind: nothing changed: ok")

    # ------------------------------------------------------------ Bind shows its stages
    with Told() as told:
        with override():
            assert bpy.ops.edge_deform.bind('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
        yield from until(lambda: told.has('INFO', "Bound"), 120)
    assert told.has('INFO', "Bound 50176 vertices"), told.messages
    kinds = [k for k, _, _ in seen]
    assert kinds[0] == 'begin' and kinds[-1] == 'end' and kinds.count('end') == 1, kinds
    updates = [(text, f) for k, text, f in seen if k == 'update']
    fractions = [f for _, f in updates]
    assert len(updates) >= 3 and fractions == sorted(fractions), updates
    assert 0.0 <= fractions[0] and fractions[-1] < 1.0 and seen[-1][2] == 1.0, updates
    factoring = [i for i, (k, text, _) in enumerate(seen)
                 if k == 'update' and "factoring 150k graph nodes" in text]
    assert factoring, updates
    shown = [k for k, text, _ in seen[factoring[0]:] if "factoring" in text and k == 'drawn']
    assert shown, "the status bar showed the factoring stage before it ran: %s" % seen
    print("bind: %d stages, fractions %s, status drawn %d times: ok"
          % (len(updates), fractions, kinds.count('drawn')))

    # ------------------------------------------------------------ Esc stops a long Solve
    s = ob.edge_deform
    s.iterations, s.tolerance = 1000, 1e-9   # far more than fit in the time before Esc
    ctrl.location.y += 0.4
    bpy.context.view_layer.update()
    before = positions(ob.data).tobytes()
    state = stored_state(ob.data)
    assert ob.data.shape_keys is None
    seen.clear()
    with Told() as told:
        with override():
            assert bpy.ops.edge_deform.solve('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
        # Wait until some chunks of iterations ran (the fraction moved), then Esc.
        yield from until(lambda: any(k == 'update' and f > 0.0 for k, _, f in seen), 120)
        ran = max(f for k, _, f in seen if k == 'update')
        assert 0.0 < ran < 1.0, seen
        tap('ESC')
        yield from until(lambda: told.has('WARNING', "cancelled"), 60)
    assert told.has('WARNING', "Solve of 'big' cancelled"), told.messages
    assert not told.has('INFO', "Solved"), told.messages
    for _ in range(3):
        yield
    assert positions(ob.data).tobytes() == before, "Esc: the vertices as before"
    assert ob.data.shape_keys is None, "Esc: no shape key was written"
    assert stored_state(ob.data) == state, "Esc: the stored state as before"
    assert [k for k, _, _ in seen if k in ('begin', 'end')] == ['begin', 'end'], seen
    print("a long solve stopped by Esc after %d of its 1000 iterations; mesh byte-identical: "
          "ok" % round(1000 * ran))

    # ------------------------------------------------------------ Live: a domain switch
    yield from live_domain_switch(ob, ctrl, seen)

    # ------------------------------------------------------------ chunks = one call
    bpy.data.objects.remove(ob)
    plane = bpy.data.objects["plane"]
    activate(plane)
    plane.edge_deform.iterations, plane.edge_deform.tolerance = 60, 1e-9
    bpy.data.objects["H_ctrl"].location.y += 0.3
    bpy.context.view_layer.update()
    seen.clear()
    with Told() as told:
        with override():
            assert bpy.ops.edge_deform.solve('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
        yield from until(lambda: told.has('INFO', "Solved"), 60)
    assert told.has('INFO', "Solved"), told.messages
    chunks = [f for k, _, f in seen if k == 'update']
    assert len(chunks) >= 2, "the solve ran in more than one chunk: %s" % chunks
    chunked = key_positions(plane).copy()
    with override():
        assert bpy.ops.edge_deform.solve('EXEC_DEFAULT') == {'FINISHED'}
    assert np.array_equal(key_positions(plane), chunked), \
        "the chunked Solve writes what the one-call Solve writes"
    assert not np.array_equal(chunked, positions(plane.data)), "it deformed"
    print("chunked solve (%d chunks) equals the one-call solve bit for bit: ok" % len(chunks))


main(steps)
