"""Background test: every default the manual (docs/addon.md, "Scripting contract") states
equals the add-on's. Reads the defaults from the table's "default X" cells (and from
"(defaults A and B)" phrasing, so an old wording cannot hide a wrong figure) and compares
each with the property's own default; and the defaults the add-on mirrors from the core
(properties.CORE_*) equal the package's."""

import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from helpers import ROOT, bpy, run  # noqa: E402

MANUAL = os.path.join(ROOT, "docs", "addon.md")


def contract_rows():
    """{field: default text} from the scripting contract's table."""
    with open(MANUAL, encoding="utf-8") as f:
        text = f.read()
    start = text.index("## Scripting contract")
    table = text[start:text.index("\n\n", text.index("| field |", start))]
    stated = {}
    for line in table.splitlines()[2:]:
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        fields = re.findall(r"`(\w+)`", cells[0])
        meaning = cells[-1]
        many = re.search(r"defaults? ([^;)|]+?)(?:\)|;|$)", meaning)
        if not many:
            continue
        values = re.split(r"\s+and\s+|,\s*", many.group(1).strip())
        if len(values) == len(fields):
            stated.update(zip(fields, values))
        elif len(fields) == 1:
            stated[fields[0]] = many.group(1).strip()
    return stated


def parse(text):
    text = text.strip().strip("`")
    if text in ("True", "False"):
        return text == "True"
    if text[:1] in "'\"" and text[-1:] == text[:1]:
        return text[1:-1]
    try:
        return int(text)
    except ValueError:
        return float(text)


def test_manual_states_the_code_defaults():
    stated = contract_rows()
    props = bpy.types.Object.bl_rna.properties["edge_deform"].fixed_type.properties
    checked = []
    for field, text in stated.items():
        if field == "acceleration":
            # Automatic: the add-on names no method, the package's default rule chooses
            # (docs/decisions/0043). A dynamic enum: read from an object's settings.
            assert text.startswith("`'AUTO'`") and "package's default" in text, text
            mesh = bpy.data.meshes.new("defaults")
            holder = bpy.data.objects.new("defaults_mesh", mesh)
            try:
                assert holder.edge_deform.acceleration == 'AUTO', \
                    holder.edge_deform.acceleration
            finally:
                bpy.data.objects.remove(holder)
                bpy.data.meshes.remove(mesh)
            checked.append(field)
            continue
        value = parse(text)
        default = props[field].default
        if isinstance(value, float):
            assert abs(default - value) <= 1e-9 * max(1.0, abs(value)), (field, value, default)
        else:
            assert default == value, (field, value, default)
        checked.append(field)
    for field in ("stiffness", "domain", "iterations", "tolerance", "output",
                  "shape_key_name", "animate"):
        assert field in stated, "the manual states no default for %s: %s" % (field, stated)
    print("  manual defaults checked:", sorted(checked))


def test_core_defaults_are_the_packages():
    from edge_deform import compat, properties
    ed = compat.native_package()
    props = bpy.types.Object.bl_rna.properties["edge_deform"].fixed_type.properties
    assert properties.CORE_TOLERANCE == ed.SOLVE_DEFAULTS["tolerance"], ed.SOLVE_DEFAULTS
    # (Blender stores a float property's default as a float32.)
    assert abs(props["tolerance"].default - properties.CORE_TOLERANCE) < 1e-9
    X = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (1.0, 1.0, 0.0)]
    for domain in ("edge", "primal"):
        d = ed.Deformer(X, [(0, 1, 2), (1, 3, 2)], domain=domain)
        assert set(d.node_stiffness().tolist()) == {properties.CORE_STIFFNESS}, domain
    assert abs(props["stiffness"].default - properties.CORE_STIFFNESS) < 1e-9


if __name__ == "__main__":
    run([test_manual_states_the_code_defaults, test_core_defaults_are_the_packages])
