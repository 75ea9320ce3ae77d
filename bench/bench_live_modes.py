"""Live Deform as a modal tool (what the add-on does) against Live as a mode that stays on
and re-solves from Blender's dependency-graph updates (`depsgraph_update_post`), measured
in a real window (Xvfb: the modal tool needs one).

Both drive the same warm-started solve and write through lifecycle.py, with the same
iteration budget per update (engine.IterationBudget: at most the settings' iterations and
about 40 ms). A timer moves the controller a little every 0.1 s (a slow drag, scripted as
a driver or G would); for each move the bench records the time from the move to the first
write whose handle targets were read after it (the latency the artist sees, before
Blender draws). Also counted: handler calls per move (each write is a mesh update, so the
handler is called again by its own writes), handler calls for 20 moves of an unrelated
object, whether the shape settles after the drag, and whether the mouse wheel still zooms.

    xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup \
        --enable-event-simulate --python bench/bench_live_modes.py -- \
        [--sizes 10k,50k] [--moves 30] [--markdown]

Prints a table, writes bench/results/live_modes.json and, with --markdown, rewrites its
section of docs/addon.md.
"""

import json
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path[:0] = [str(HERE), str(ROOT / "tests" / "blender")]
from bench_live_update import SIZES, scene_for  # noqa: E402
from edits import SHARED_MESHES  # noqa: E402
from machine import machine_info  # noqa: E402
from md_section import replace_section  # noqa: E402
from window_harness import center, main, override, tap, until, view3d  # noqa: E402

import bpy  # noqa: E402
import numpy as np  # noqa: E402

from edge_deform import engine, lifecycle, op_common  # noqa: E402

ARGS = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []


def option(name, default):
    return ARGS[ARGS.index(name) + 1] if name in ARGS else default


class Recorder:
    """Times of target reads and writes, from the add-on's own calls (wrapped)."""

    def __init__(self):
        self.reads, self.writes, self.draws = [], [], []
        self._targets, self._write = engine.handle_targets, lifecycle._write
        self._draw = bpy.types.SpaceView3D.draw_handler_add(
            lambda: self.draws.append(time.perf_counter()), (), 'WINDOW', 'POST_PIXEL')

        def targets(*a, **k):
            self.reads.append(time.perf_counter())
            return self._targets(*a, **k)

        def write(*a, **k):
            self._write(*a, **k)
            self.writes.append((self.reads[-1] if self.reads else 0.0, time.perf_counter()))
        engine.handle_targets, lifecycle._write = targets, write

    def latency_ms(self, t_move):
        """From a move to the first write whose targets were read after it, and to the
        first draw of the viewport after that write (what the artist sees)."""
        for read, wrote in self.writes:
            if read >= t_move:
                shown = next((t for t in self.draws if t >= wrote), None)
                return ((wrote - t_move) * 1e3,
                        None if shown is None else (shown - t_move) * 1e3)
        return None, None

    def close(self):
        engine.handle_targets, lifecycle._write = self._targets, self._write
        bpy.types.SpaceView3D.draw_handler_remove(self._draw, 'WINDOW')


class DepsgraphMode:
    """The alternative: re-solve from depsgraph_update_post while the mode is on."""

    def __init__(self, ob):
        self.ob, self.bound = ob, lifecycle.prepare(ob)
        self.budget = engine.IterationBudget()
        self.state, self.converged = None, False
        self.calls = self.solves = 0
        bpy.app.handlers.depsgraph_update_post.append(self.on_update)

    def on_update(self, scene, depsgraph=None):
        self.calls += 1
        state = engine.controller_state(self.ob, self.bound.inputs)
        if state == self.state and self.converged:
            return
        self.state = state
        s = self.ob.edge_deform
        t0 = time.perf_counter()
        r = self.bound.solve(self.bound.targets(), self.budget.iterations(s.iterations),
                             s.tolerance, warm=True)
        self.budget.record(r, (time.perf_counter() - t0) * 1e3)
        self.bound.write(r.positions)   # (a mesh update: the handler is called again)
        self.converged = bool(r.converged)
        self.solves += 1

    def stop(self):
        bpy.app.handlers.depsgraph_update_post.remove(self.on_update)


def wheel_zooms():
    rv3d = view3d()[1].spaces.active.region_3d
    d0 = rv3d.view_distance
    tap('WHEELUPMOUSE', at=center())
    yield from until(lambda: rv3d.view_distance < d0 - 1e-9, 3)
    zoomed = rv3d.view_distance < d0 - 1e-9
    rv3d.view_distance = d0
    return zoomed


def run_mode(mode, ob, empty, other, step, moves):
    rec = Recorder()
    handler = None
    if mode == "modal":
        with override():
            assert bpy.ops.edge_deform.live('INVOKE_DEFAULT') == {'RUNNING_MODAL'}
    else:
        handler = DepsgraphMode(ob)
    for _ in range(10):   # settle the start
        yield
    t_moves, calls0 = [], handler.calls if handler else 0
    for _ in range(moves):
        empty.location = tuple(np.array(empty.location) + step)
        t_moves.append(time.perf_counter())
        yield
    calls_drag = (handler.calls - calls0) if handler else None
    tool = op_common.running_tool()
    solves0 = tool.updates if mode == "modal" else handler.solves
    yield from until(lambda: (tool.converged if mode == "modal" else handler.converged), 60)
    solves_after = (tool.updates if mode == "modal" else handler.solves) - solves0
    settled = (op_common.running_tool().converged if mode == "modal" else handler.converged)
    latencies = [rec.latency_ms(t) for t in t_moves]
    passes = len([t for t in rec.draws if t_moves[0] <= t <= t_moves[-1]])
    pass_ms = (t_moves[-1] - t_moves[0]) * 1e3 / max(1, passes)
    zoomed = yield from wheel_zooms()
    calls0 = handler.calls if handler else 0
    for _ in range(20):   # an unrelated edit: another object moves
        other.location.x += 0.01
        yield
    calls_other = (handler.calls - calls0) if handler else None
    if mode == "modal":
        tap('RET')
        yield from until(lambda: op_common.running_tool() is None)
    else:
        handler.stop()
    rec.close()
    wrote = [w for w, _ in latencies if w is not None]
    shown = [d for _, d in latencies if d is not None]
    return {"mode": mode, "moves": moves, "answered": len(wrote),
            "write_latency_median_ms": float(np.median(wrote)) if wrote else None,
            "shown_latency_median_ms": float(np.median(shown)) if shown else None,
            "shown_latency_max_ms": float(np.max(shown)) if shown else None,
            "viewport_draw_interval_ms": pass_ms,
            "handler_calls_per_move": None if calls_drag is None else calls_drag / moves,
            "handler_calls_unrelated_20": calls_other,
            "solves_after_drag": solves_after,
            "settled_after_drag": bool(settled), "wheel_zooms": bool(zoomed)}


def markdown(machine, results):
    lines = ["## Live as a modal tool or as a depsgraph-driven mode (measured)", "",
             "`bench/bench_live_modes.py`, Blender 3.4.1 in a real window (Xvfb). The same "
             "warm solve and write per update; a controller moved every 0.1 s (30 moves); "
             "Latency: from the move to the first write whose targets were read after it "
             "(*written*), and to the next draw of the viewport after that write (*shown*, "
             "what the artist sees). Draw interval: the mean time between viewport draws "
             "during the drag (one pass of Blender's event loop).", "",
             "Machine: %s, %s cores (shared with other jobs; 1-min load %.1f). Date: %s."
             % (machine["cpu"], machine["cores"], machine["load_1min"] or 0.0,
                machine["date"]),
             "", "| mesh | vertices | mode | written, median ms | shown, median / max ms "
             "| draw interval ms | handler calls per move | handler calls, 20 unrelated moves "
             "| solves after the drag (60 s) | settled | wheel zooms |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        lines.append("| %s | %d | %s | %.1f | %.1f / %.1f | %.1f | %s | %s | %d | %s | %s |" % (
            r["mesh"], r["vertices"], r["mode"], r["write_latency_median_ms"],
            r["shown_latency_median_ms"], r["shown_latency_max_ms"],
            r["viewport_draw_interval_ms"],
            "-" if r["handler_calls_per_move"] is None else "%.1f" % r["handler_calls_per_move"],
            "-" if r["handler_calls_unrelated_20"] is None else r["handler_calls_unrelated_20"],
            r["solves_after_drag"], "yes" if r["settled_after_drag"] else "no", "yes" if r["wheel_zooms"] else "no"))
    return "\n".join(lines)


def steps():
    tap('ESC')   # the splash screen
    yield
    from helpers import register
    register()
    meshes = option("--meshes", str(SHARED_MESHES))
    moves = int(option("--moves", "30"))
    results = []
    for size in option("--sizes", "10k,50k").split(","):
        ob, empty, n, step = scene_for(meshes, SIZES[size])
        other = bpy.data.objects.new("Other", None)
        bpy.context.scene.collection.objects.link(other)
        s = ob.edge_deform
        s.iterations, s.tolerance = 4, 1e-3   # the add-on's defaults
        with override():
            bpy.ops.view3d.view_all()
            assert bpy.ops.edge_deform.bind('EXEC_DEFAULT') == {'FINISHED'}
        for mode in ("modal", "depsgraph"):
            r = yield from run_mode(mode, ob, empty, other, step, moves)
            r.update(mesh=SIZES[size], vertices=n)
            print(r)
            results.append(r)
    machine = machine_info()
    out = HERE / "results" / "live_modes.json"
    out.write_text(json.dumps({"machine": machine, "results": results}, indent=1))
    body = markdown(machine, results)
    print(body)
    if "--markdown" in ARGS:
        replace_section(ROOT / "docs" / "addon.md", "live-modes", body)


main(steps, limit_s=1500)
