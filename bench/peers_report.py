"""Tables, ratios, plot and Markdown section of bench/bench_peers.py's results."""

from pathlib import Path

import numpy as np


LABELS = {
    "edgedeform_edge_0.5": "edgedeform edge λ=0.5",
    "edgedeform_primal_1": "edgedeform primal λ=1",
    "cgal_original_arap": "CGAL ORIGINAL_ARAP",
    "cgal_spokes_and_rims": "CGAL SPOKES_AND_RIMS",
    "libigl_spokes": "libigl ARAP spokes",
    "libigl_spokes_and_rims": "libigl ARAP spokes+rims",
    "blender_laplacian_deform": "Blender Laplacian Deform",
}
EDGE, PRIMAL = "edgedeform_edge_0.5", "edgedeform_primal_1"
CGAL, IGL = "cgal_original_arap", "libigl_spokes"
BLENDER = "blender_laplacian_deform"


def label(method):
    """Display name; edgedeform run with a fixed thread count carries it ("_t1")."""
    base, _, t = method.partition("_t")
    if method.startswith("edgedeform_") and t.isdigit():
        return f"{LABELS.get(base, base)}, {t} thread{'s' if t != '1' else ''}"
    return LABELS.get(method, method)


def _suffixes(methods):
    """The thread variants of ours present: '' (the package's default) and '_tN'."""
    return sorted({m[len(EDGE):] for m in methods if m.startswith(EDGE)}
                  | {m[len(PRIMAL):] for m in methods if m.startswith(PRIMAL)})


def derive(row, eps):
    """Numbers every method gets from its raw measurements (in place)."""
    row["eps"] = eps
    its, ms = row.get("eps_iterations"), row.get("ms_per_it")
    row["time_to_eps_ms"] = (row["precompute_ms"] + its * ms) if its and ms else None
    if row.get("acc_eps_iterations"):
        row["acc_time_to_eps_ms"] = row["precompute_ms"] + row["acc_solve_to_eps_ms"]
    return row


def best_time_to_eps(row):
    times = [t for t in (row.get("time_to_eps_ms"), row.get("acc_time_to_eps_ms")) if t]
    return min(times) if times else None


def _fmt(x, spec=".1f", none="—"):
    return none if x is None else format(x, spec)


def one_line(row):
    name = label(row["method"])
    if "error" in row:
        return f"{row['size']:>5} {row['edit']:<6} {name:<26} FAILED: {row['error']}"
    if row["method"] == BLENDER:
        return (f"{row['size']:>5} {row['edit']:<6} {name:<26} bind+first frame "
                f"{row['precompute_ms']:8.0f} ms | frame {row['frame_ms']:7.1f} ms "
                f"(LD {row['ld_ms']:.1f}) | {row['peak_rss_mb']:6.0f} MB")
    return (f"{row['size']:>5} {row['edit']:<6} {name:<26} pre {row['precompute_ms']:8.0f} ms"
            f" | {row['ms_per_it']:7.2f} ms/it | to eps {_fmt(row.get('eps_iterations'), 'd')} it"
            f" {_fmt(row.get('time_to_eps_ms') and row['time_to_eps_ms'] / 1e3, '.2f')} s"
            f" (ref {row['ref_iterations']} it"
            f"{'' if row.get('ref_converged') or not row['ref_iterations'] else ', not conv.'})"
            f" | {row['peak_rss_mb']:6.0f} MB"
            + (f" | live {row['live_update_ms']:.1f} ms" if row.get("live_update_ms") else ""))


def _by_case(rows):
    cases = {}
    for r in rows:
        if "error" not in r:
            cases.setdefault((r["size"], r["edit"]), {})[r["method"]] = r
    return cases


def _case_ratios(m, sfx):
    """Ratios of one (mesh, edit) for ours run with thread variant `sfx`."""
    edge, primal = EDGE + sfx, PRIMAL + sfx
    first = next(iter(m.values()))
    r = {"size": first["size"], "edit": first["edit"], "mesh": first["mesh"],
         "vertices": first["vertices"], "threads": sfx[2:] if sfx else "default"}

    def put(key, a, b, value_a, value_b=None):
        if a in m and b in m:
            x, y = value_a(m[a]), (value_b or value_a)(m[b])
            r[key] = x / y if x and y else None

    def field(name):
        return lambda row: row.get(name)

    put("edge_cgal_it", edge, CGAL, field("ms_per_it"))
    put("edge_cgal_cpu_it", edge, CGAL, field("cpu_ms_per_it"))
    put("primal_cgal_cpu_it", primal, CGAL, field("cpu_ms_per_it"))
    put("primal_libigl_cpu_it", primal, IGL, field("cpu_ms_per_it"))
    put("primal_cgal_it", primal, CGAL, field("ms_per_it"))
    put("primal_libigl_it", primal, IGL, field("ms_per_it"))
    put("primal_libigl_sr_it", primal, "libigl_spokes_and_rims", field("ms_per_it"))
    put("edge_cgal_pre", edge, CGAL, field("precompute_ms"))
    put("primal_cgal_pre", primal, CGAL, field("precompute_ms"))
    put("edge_cgal_eps", edge, CGAL, best_time_to_eps)
    put("primal_cgal_eps", primal, CGAL, best_time_to_eps)
    put("primal_libigl_eps", primal, IGL, best_time_to_eps)
    put("edge_cgal_mem", edge, CGAL, field("peak_rss_mb"))
    put("blender_over_edge_live", BLENDER, edge, field("frame_ms"), field("live_update_ms"))
    put("blender_over_primal_live", BLENDER, primal, field("frame_ms"), field("live_update_ms"))
    return r


def ratios(rows):
    """Per (mesh, edit, our thread setting): ours over the peer (below 1 = ours faster), and
    Blender's frame over our live update (above 1 = ours faster)."""
    return [_case_ratios(m, sfx) for m in _by_case(rows).values() for sfx in _suffixes(m) or [""]]


def method_table(rows):
    head = ("| mesh | vertices | edit | method | precompute ms (CPU) | ms/it | CPU ms/it "
            "| iterations to ε (reference) | time to ε s | peak RSS MB | live update / frame ms |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    for r in rows:
        name = label(r["method"])
        lead = f"| {r['mesh']} | {r['vertices']:,} | {r['edit']} | {name} |"
        if "error" in r:
            lines.append(lead + " failed | | | | | | |")
        elif r["method"] == BLENDER:
            lines.append(lead + f" {r['precompute_ms']:.0f} (bind + 1st frame) | — "
                         f"| {_fmt(r.get('frame_cpu_ms'))} per frame | — (direct solve) | — | {r['peak_rss_mb']:.0f} "
                         f"| {r['frame_ms']:.1f} per frame (LD {r['ld_ms']:.1f}) |")
        else:
            ref = r["ref_iterations"]
            if ref:
                its = (f"{_fmt(r.get('eps_iterations'), 'd', 'none')} ({ref}"
                       f"{'' if r.get('ref_converged') else ', not conv.'})")
                if r.get("acc_eps_iterations"):
                    its += f"; accelerated {r['acc_eps_iterations']}"
            else:
                its = "not run"
            t = best_time_to_eps(r)
            live = r.get("live_update_ms")
            cpu = r.get("precompute_cpu_ms")
            lines.append(lead + f" {r['precompute_ms']:.0f}{f' ({cpu:.0f})' if cpu else ''} "
                         f"| {r['ms_per_it']:.2f} "
                         f"| {_fmt(r.get('cpu_ms_per_it'), '.2f')} | {its} "
                         f"| {_fmt(t and t / 1e3, '.2f')} | {r['peak_rss_mb']:.0f} "
                         f"| {_fmt(live, '.1f')}{' live' if live else ''} |")
    return "\n".join(lines)


PER_ITERATION_RATIOS = (
    ("edge_cgal_it", "edge / CGAL ARAP"), ("primal_cgal_it", "primal / CGAL ARAP"),
    ("primal_libigl_it", "primal / libigl spokes"), ("primal_libigl_sr_it", "primal / libigl s+r"),
    ("edge_cgal_cpu_it", "CPU: edge / CGAL ARAP"), ("primal_cgal_cpu_it", "CPU: primal / CGAL ARAP"),
    ("primal_libigl_cpu_it", "CPU: primal / libigl spokes"))
OTHER_RATIOS = (
    ("edge_cgal_pre", "precompute edge / CGAL"), ("primal_cgal_pre", "precompute primal / CGAL"),
    ("edge_cgal_eps", "time to ε edge / CGAL ARAP"),
    ("primal_cgal_eps", "time to ε primal / CGAL ARAP"),
    ("primal_libigl_eps", "time to ε primal / libigl spokes"),
    ("edge_cgal_mem", "memory edge / CGAL"),
    ("blender_over_edge_live", "Blender frame / edge live update"),
    ("blender_over_primal_live", "Blender frame / primal live update"))


def ratio_table(ratio_rows, columns):
    cols = [c for c in columns if any(r.get(c[0]) for r in ratio_rows)]
    ratio_rows = [r for r in ratio_rows if any(r.get(k) for k, _ in cols)]
    lines = ["| mesh | edit | our threads | " + " | ".join(t for _, t in cols) + " |",
             "|---|---|---|" + "---|" * len(cols)]
    for r in ratio_rows:
        lines.append(f"| {r['mesh']} ({r['vertices']:,}) | {r['edit']} | {r['threads']} | "
                     + " | ".join(_fmt(r.get(k), ".2f") for k, _ in cols) + " |")
    return "\n".join(lines)


def plot(result, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = [r for r in result["rows"] if "error" not in r and r["edit"] == "lift"]
    panels = (("precompute_ms", "precompute (ms)"),
              ("ms_per_it", "per iteration (ms); Blender: per frame"),
              ("time_to_eps", f"time to within {rows[0]['eps'] if rows else 1e-3:g}·diag (s)"))
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6))
    for ax, (field, title) in zip(axes, panels):
        for method in sorted({r["method"] for r in rows}):
            pts = sorted((r["vertices"], _value(r, field)) for r in rows if r["method"] == method)
            pts = [(n, v) for n, v in pts if v]
            if pts:   # ours solid (one thread dashed), peers dotted with squares
                style = ("o--" if "_t" in method else "o-") if method.startswith("edgedeform") \
                    else "s:"
                ax.plot(*zip(*pts), style, label=label(method))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("vertices")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    m = result["machine"]
    fig.suptitle(f"'lift' edit — {m['cpu']}, {m['cores']} cores (shared), {m['date']}")
    fig.tight_layout()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _value(r, field):
    if field == "ms_per_it":
        return r.get("frame_ms") if r["method"] == BLENDER else r.get("ms_per_it")
    if field == "time_to_eps":
        t = best_time_to_eps(r)
        return t / 1e3 if t else None
    return r.get(field)


def _verdicts(result):
    """The speed targets this run can speak to, measured (never assumed)."""
    out = []
    rat = {(r["size"], r["edit"], r["threads"]): r for r in result.get("ratios", [])}
    rows = {(r["size"], r["edit"], r["method"]): r for r in result["rows"] if "error" not in r}
    for edit, sfx in ((e, s) for e in ("lift", "twist") for s in _suffixes(
            [k[2] for k in rows])):
        threads = f"{sfx[2:]} thread(s)" if sfx else "default threads"
        big = rows.get(("140k", edit, EDGE + sfx))
        if big:
            out.append(f"- 140k, edge λ=0.5, {edit}, {threads}, load {big['load_1min']:.0f}: "
                       f"{big['ms_per_it']:.1f} ms/it (CPU {_fmt(big.get('cpu_ms_per_it'))}) (target ≤ 70: "
                       f"{'met' if big['ms_per_it'] <= 70 else 'missed'}), precompute "
                       f"{big['precompute_ms'] / 1e3:.2f} s (≤ 2.5 s: "
                       f"{'met' if big['precompute_ms'] <= 2500 else 'missed'}), peak memory "
                       f"{big['peak_rss_mb']:.0f} MB (≤ 1.5 GB: "
                       f"{'met' if big['peak_rss_mb'] <= 1536 else 'missed'}).")
        r = rat.get(("50k", edit, sfx[2:] if sfx else "default"))
        if r:
            for key, target, what in (("edge_cgal", 0.35, "edge / CGAL ARAP per iteration"),
                                      ("primal_cgal", 0.15, "primal / CGAL ARAP per iteration"),
                                      ("primal_libigl", 0.5,
                                       "primal / libigl ARAP per iteration")):
                wall, cpu = r.get(key + "_it"), r.get(key + "_cpu_it")
                if wall:
                    out.append(f"- 50k, {edit}, {threads}: {what} {wall:.2f} wall (target ≤ "
                               f"{target}: {'met' if wall <= target else 'missed'}), "
                               f"{_fmt(cpu, '.2f')} CPU.")
            if r.get("blender_over_edge_live"):
                v = r["blender_over_edge_live"]
                out.append(f"- 50k, {edit}, {threads}: Blender Laplacian Deform frame / one edge live update "
                           f"= {v:.1f}× (target ≥ 10×: {'met' if v >= 10 else 'missed'}).")
    return "\n".join(out)


def markdown(result):
    """The peers section's body (bench/report.py gives it its heading)."""
    m, s, bi = result["machine"], result["settings"], result.get("build_info", {})
    versions = sorted({r["version"] for r in result["rows"] if r.get("version")})
    skipped = "".join(f"\n- skipped {k}: {v}" for k, v in result.get("skipped", {}).items())
    body = f"""
Machine: {m['cpu']}, {m['cores']} cores, **shared with other work while this ran** (1-minute
load average when each row finished is in bench/results/peers.json; {m.get('load_1min', 0):.1f}
at the end), so absolute times are noisy; ratios compare runs made minutes apart in one
invocation. Date: {m['date']} (the last invocation). Ours: solver `{bi.get('solver', '?')}`, OpenMP threads
{bi.get('threads', '?')}. Peers: {', '.join(versions)}; CGAL uses its default solver (Eigen
SparseLU) on one thread.

Same meshes, same edits for everyone (bench/edits.py): lowest 20 % of the height static,
top 10 % the handle; "lift" raises it by ¼ of the bounding-box diagonal, "twist" turns it
90° about the height axis. Every vertex is in the region of interest. Each method runs in
its own process:
- **precompute**: everything before the first iteration (graph, weights, assembly,
  factorization); median of {s['repeat']}; CPU time in brackets (all threads; for ours it
  also covers the first solve's one iteration). Blender: bind + the first frame (which
  builds and factors its system).
- **ms/it**: wall time of {s['block']} iterations / {s['block']}, median of {s['repeat']}.
  Blender: one animation frame with the hook moving the handles (its Laplacian Deform part
  in brackets: the frame minus the same frame with the modifier off).
- **time to ε**: precompute + iterations until every vertex is within ε = {s['eps']:g} ×
  diagonal of the method's *own* converged shape (reference: iterated one step at a time
  until its estimated distance to the fixed point, last move × rate / (1 − rate), is
  ≤ {s['ref_tol']:g} × diagonal, at most {s['ref_iterations']} iterations; "not conv." = the
  budget ran out first, so the count is against the last iterate). Accelerated: fewest iterations of one cold accelerated solve, when the build has
  acceleration. Large meshes are not converged (too slow on this machine for every peer).
- **peak RSS**: the child process's resident-memory high-water mark (VmHWM, polled and
  read by the child at its end), including its interpreter (Python with NumPy ≈ 30 MB,
  Blender ≈ 150–200 MB; "base" in the JSON).
- **live update**: ours, after converging, the handles dragged by 0.005 × diagonal per
  update, one warm-started iteration (accelerated when available); compared with one
  Blender frame.

{method_table(result['rows'])}

Ratios per iteration, ours / peer (below 1: ours faster), wall clock and CPU time (all
threads of the process):

{ratio_table(result['ratios'], PER_ITERATION_RATIOS)}

Other ratios: ours / peer (below 1: ours faster or smaller), and Blender's frame / our live
update (above 1: ours faster):

{ratio_table(result['ratios'], OTHER_RATIOS)}

Speed targets this benchmark measures (record 0013):
{_verdicts(result) or '- (no 50k / 140k rows in this run)'}
{skipped}

Commands (after `bench/setup_peers.sh`; rows merge across runs):
{chr(10).join('- `PYTHONPATH=build/python /usr/bin/python3 ' + c + '`' for c in result.get('commands', []))}
"""
    return body
