"""Metrics tables of the demo: one JSON document and the same figures as Markdown."""
import json
import math

COLUMNS = [  # (json key, Markdown header, format)
    ("handle_error", "handle err", "%.1e"),
    ("mean_edge_strain", "mean strain", "%.4f"),
    ("max_edge_strain", "max strain", "%.3f"),
    ("mean_dihedral_change", "mean dihedral Δ (°)", "deg"),
    ("arap_energy", "ARAP energy", "%.4g"),
    ("iterations", "iterations", "%d"),
    ("ms", "ms", "%.0f"),
]


def _fmt(value, fmt):
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "–"
    if fmt == "deg":
        return "%.3f" % math.degrees(value)
    return fmt % value


def cell_row(cell):
    lam = cell["lambda"] if isinstance(cell["lambda"], str) else "%g" % cell["lambda"]
    cells = [cell["key"], cell["domain"], lam]
    cells += [_fmt(cell[k], f) for k, _, f in COLUMNS]
    cells.append("yes" if cell["converged"] else "**no**")
    return "| " + " | ".join(cells) + " |"


def not_converged_note(cells):
    """Lines naming the cells that stopped at the iteration cap, and whether the solver warned;
    empty when every cell converged."""
    late = [c for c in cells if not c["converged"]]
    if not late:
        return []
    return ["", "Not converged: " + "; ".join(
        "%s (stopped after %d iterations, %s)" % (
            c["key"], c["iterations"],
            "with the solver's warning" if c.get("warnings") else "**without a warning**")
        for c in late) + "."]


def sample_markdown(sample):
    out = ["### %s" % sample["title"], "",
           "%d vertices, %d faces; %d handle and %d static vertices." % (
               sample["vertices"], sample["faces"], sample["handle_vertices"],
               sample["static_vertices"]), ""]
    head = ["cell", "domain", "λ"] + [h for _, h, _ in COLUMNS] + ["converged"]
    out.append("| " + " | ".join(head) + " |")
    out.append("|" + "---|" * len(head))
    out += [cell_row(c) for c in sample["cells"]]
    out += not_converged_note(sample["cells"])
    if sample.get("painted_regions"):
        out += ["", "Painted materials, per region (edge domain; free vertices only; strain and "
                "bending over the edges inside the region; distance = mean vertex distance to the uniform result):",
                "", "| region | λ | vertices | painted strain | uniform 0 / 0.5 / 1 strain | "
                "painted bending (°) | uniform 0 / 0.5 / 1 bending (°) | distance to uniform "
                "0 / 0.5 / 1 | nearest by shape | nearest by position |", "|---|---|---|---|---|---|---|---|---|---|"]
        for r in sample["painted_regions"]:
            u = r["uniform"]
            ks = ("0", "0.5", "1")
            out.append("| %s | %g | %d | %s | %s | %s | %s | %s | %s | %g |" % (
                r["region"], r["lambda"], r["vertices"],
                _fmt(r["painted"]["mean_edge_strain"], "%.4f"),
                " / ".join(_fmt(u[k]["mean_edge_strain"], "%.4f") for k in ks),
                _fmt(r["painted"]["mean_dihedral_change"], "deg"),
                " / ".join(_fmt(u[k]["mean_dihedral_change"], "deg") for k in ks),
                " / ".join("%.4f" % r["distance_to_uniform"][k] for k in ks),
                "%g" % r["nearest_uniform_by_local_shape"]
                if "nearest_uniform_by_local_shape" in r else "–",
                r["nearest_uniform_by_position"]))
    if sample.get("addon_check"):
        a = sample["addon_check"]
        out += ["", "Add-on check (bind + solve on the sample .blend, painted, edge): %s" % (
            a.get("message") or "max |add-on − package| = %.2e" % a["max_difference"])]
    return "\n".join(out)


def write(doc, json_path, md_path):
    with open(json_path, "w") as f:
        json.dump(doc, f, indent=1, default=float)
    parts = ["# edgedeform demo: metrics", "",
             "Strain: |l − l0| / l0 over mesh edges. Dihedral Δ: mean |θ − θ0| over interior "
             "edges. ARAP energy: classic primal ARAP energy of the result against the rest "
             "shape. ms: wall time of one solve from the naive Laplacian, factorization "
             "included. Settings: %s." % json.dumps(doc["settings"]), ""]
    for s in doc["samples"]:
        parts += [sample_markdown(s), ""]
    with open(md_path, "w") as f:
        f.write("\n".join(parts))
