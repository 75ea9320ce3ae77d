"""The tables of bench/bench_live_update.py's and bench/bench_live_region.py's results
(bpy-free, for bench/report.py)."""


def markdown(result):
    info, results = result["machine"], result["results"]
    lines = [
        "`bench/bench_live_update.py`, run inside Blender %s (background). One live update "
        "= read the controller and compute the handle targets, **one warm-started "
        "iteration**, write the shape key, `mesh.update()`; the depsgraph evaluation Blender "
        "runs before drawing is listed apart. Edit: a drag of the top 10 %% of the height "
        "(one Empty moving a little every update), lowest 20 %% static, λ = 0.5. Median "
        "of %d updates after 3 warm-up updates." % (info["blender"], results[0]["updates"]),
        "",
        # the date, machine and load head the page's section (bench/report.py)
        "Solver %s, OpenMP threads %s." % (info["build"]["solver"], info["build"]["threads"]),
        "",
        "| mesh | vertices | domain | nodes | bind ms | targets ms | solve ms (local / rhs "
        "/ back-sub) | write ms | **update ms** | **updates/s** | depsgraph ms | "
        "updates/s incl. depsgraph |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in results:
        lines.append(
            "| %s | %d | %s | %d | %.0f | %.2f | %.1f (%.1f / %.1f / %.1f) | %.1f | "
            "**%.1f** | **%.0f** | %.1f | %.0f |" % (
                r["mesh"], r["vertices"], r["domain"], r["nodes"], r["bind_ms"],
                r["targets_ms"], r["solve_ms"], r["local_ms"], r["rhs_ms"], r["backsub_ms"],
                r["write_ms"], r["update_ms"], r["updates_per_s"], r["depsgraph_ms"],
                r["with_depsgraph_per_s"]))
    edge50 = [r for r in results if r["size"] == "50k" and r["domain"] == "edge"]
    if edge50:
        r = edge50[0]
        verdict = "met" if r["updates_per_s"] >= 20 else "NOT met"
        lines += ["", "Live-editing target: at least 20 updates a second at 50k vertices, edge "
                  "domain: **%s** (%.0f/s; %.0f/s counting the depsgraph evaluation)."
                  % (verdict, r["updates_per_s"], r["with_depsgraph_per_s"]),
                  "", "Where the time goes at 50k, edge: the package's `solve` call is "
                  "%.1f of %.1f ms (its own counters: local %.1f, right side %.1f, "
                  "back-substitution %.1f; the remaining %.1f ms fall outside them), "
                  "the add-on's part (targets %.2f ms, shape-key write %.1f ms) "
                  "is %.0f %%. Blender's depsgraph then spends %.1f ms evaluating the shape "
                  "key before drawing." % (
                      r["solve_ms"], r["update_ms"], r["local_ms"], r["rhs_ms"],
                      r["backsub_ms"],
                      r["solve_ms"] - r["local_ms"] - r["rhs_ms"] - r["backsub_ms"],
                      r["targets_ms"], r["write_ms"],
                      100.0 * (r["targets_ms"] + r["write_ms"]) / r["update_ms"],
                      r["depsgraph_ms"])]
    return "\n".join(lines)


def region_markdown(result):
    r = result["results"][0]
    return "\n".join([
        f"`bench/bench_live_region.py` inside Blender {result['machine']['blender']} (background): "
        f"{r['mesh']} ({r['vertices']:,} vertices), Proportional on at {r['radius_fraction']:g} of the "
        f"diagonal ({r['free_vertices']:,} free vertices), a {r['handles']}-vertex handle on an Empty "
        f"that moves a little every update, λ 0.5, edge domain. Median of {r['updates']} updates.", "",
        "| bind ms | targets ms | solve ms | write ms | **update ms** | **updates/s** | depsgraph ms | "
        "updates/s incl. depsgraph | radius step, grow / shrink, ms |",
        "|---|---|---|---|---|---|---|---|---|",
        f"| {r['bind_ms']:.0f} | {r['targets_ms']:.1f} | {r['solve_ms']:.1f} | {r['write_ms']:.1f} | "
        f"**{r['update_ms']:.1f}** | **{r['updates_per_s']:.0f}** | {r['depsgraph_ms']:.1f} | "
        f"{r['with_depsgraph_per_s']:.0f} | {r['radius_grow_ms']:.0f} / {r['radius_shrink_ms']:.0f} |"])
