"""Unit tests (pytest, no Blender) of rules the add-on's source keeps:
  - every mode switch goes through compat.mode_set (Blender 5.0.1's crash guard);
  - foreach_get/foreach_set appear only in mesh_io.py (one place moves bpy arrays);
  - messages reach the user only through op_common.tell (where the tests listen);
  - only mesh_io.py writes what the mesh stores (`edge_deform_state`, the rest and hold
    attributes): one owner per stored fact;
  - panels and lists are drawn only in ui.py, which defines no operator;
  - every module says in its docstring what it is for;
  - module-level state (a mutable global) lives only in the module that owns it, listed
    here with its job: a new one must be added on purpose;
  - the modules the benchmark and the unit tests load by path import nothing from bpy.

    /usr/bin/python3 -m pytest tests/blender/test_unit_addon_rules.py
"""

import ast
import os

ADDON = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__)))), "addon", "edge_deform")


def sources():
    for name in sorted(os.listdir(ADDON)):
        if name.endswith(".py"):
            with open(os.path.join(ADDON, name), encoding="utf-8") as f:
                yield name, ast.parse(f.read(), name)


def attribute_calls(tree, attribute):
    """Lines calling `<anything>.attribute(...)`."""
    return [node.lineno for node in ast.walk(tree)
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
            and node.func.attr == attribute]


def test_every_mode_set_goes_through_compat():
    found = {name: attribute_calls(tree, "mode_set") for name, tree in sources()}
    # compat.mode_set itself calls bpy.ops.object.mode_set; everyone else calls compat's.
    bypass = {}
    for name, tree in sources():
        lines = [node.lineno for node in ast.walk(tree)
                 if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
                 and node.func.attr == "mode_set"
                 and not (isinstance(node.func.value, ast.Name)
                          and node.func.value.id == "compat")]
        if name != "compat.py" and lines:
            bypass[name] = lines
    assert not bypass, "bpy.ops.object.mode_set outside compat.py: %s" % bypass
    assert found["compat.py"], "compat.mode_set calls Blender's operator"
    assert sum(len(v) for k, v in found.items() if k != "compat.py") >= 5, found


def test_foreach_only_in_mesh_io():
    outside = {name: attribute_calls(tree, "foreach_get") + attribute_calls(tree, "foreach_set")
               for name, tree in sources() if name != "mesh_io.py"}
    outside = {k: v for k, v in outside.items() if v}
    assert not outside, "foreach_get/foreach_set outside mesh_io.py: %s" % outside


def test_messages_go_through_tell():
    # op_common.tell feeds the tests' listeners; a direct report() is unseen by them.
    outside = {name: attribute_calls(tree, "report") for name, tree in sources() if name != "op_common.py"}
    outside = {k: v for k, v in outside.items() if v}
    assert not outside, "report() outside op_common.tell: %s" % outside


def imported_addon_modules(tree):
    """The add-on's own modules a source imports (`from . import a, b`, `from .a import x`)."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level == 1:
            if node.module:
                names.add(node.module.split(".")[0])
            else:
                names.update(alias.name for alias in node.names)
    return names


def test_only_mesh_io_writes_the_stored_state():
    # The state's fields (`st.x = ...`, `setattr(st, ...)` with st the mesh's
    # edge_deform_state) and the stored attributes are written in mesh_io.py alone.
    writers = set()
    for name, tree in sources():
        for node in ast.walk(tree):
            targets = node.targets if isinstance(node, ast.Assign) else []
            flat = [e for t in targets for e in (t.elts if isinstance(t, ast.Tuple) else [t])]
            if any(isinstance(t, ast.Attribute) and (
                    ast.unparse(t.value) == "st" or ast.unparse(t.value).endswith(
                        ".edge_deform_state")) for t in flat):
                writers.add(name)
            if isinstance(node, ast.Call) and ast.unparse(node.func) == "setattr" \
                    and ast.unparse(node.args[0]) == "st":
                writers.add(name)
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) \
                    and node.func.attr in ("write_vector_attribute", "remove_attribute") \
                    and name != "mesh_io.py":
                writers.add(name)
    assert writers == {"mesh_io.py"}, writers


def base_names(tree):
    """{class name: the last part of each base's name} of a module's top-level classes."""
    return {node.name: [b.attr if isinstance(b, ast.Attribute) else getattr(b, "id", "")
                        for b in node.bases]
            for node in tree.body if isinstance(node, ast.ClassDef)}


def test_panels_only_in_ui():
    for name, tree in sources():
        kinds = {base for bases in base_names(tree).values() for base in bases}
        if name == "ui.py":
            assert "Operator" not in kinds, "ui.py draws; operators live in operators_*.py"
        else:
            assert not kinds & {"Panel", "UIList"}, "%s draws a panel: ui.py's job" % name


def test_every_module_says_what_it_is_for():
    missing = [name for name, tree in sources() if not ast.get_docstring(tree)]
    assert not missing, missing


# The add-on's module-level state, each piece in the one module that changes it.
OWNED_STATE = {
    "__init__.py": {"bl_info"},              # Blender's metadata (register sets the manual)
    "compat.py": {"_module"},                # the loaded package
    "engine.py": {"_bindings"},              # the solver cache: one Binding per mesh
    "lifecycle.py": {"_generation"},         # undo/redo/load count the tools compare
    "modal.py": {"_running"},                # the modal tool running (one at a time)
    "op_common.py": {"listeners", "progress_listeners"},   # who hears messages, progress
    "operators_bind.py": {"_problems", "_holds"},   # the frame handler's problems; Bake's hold
}


def module_state(tree):
    """Lower-case names bound at module level to a list, dict or set, and names a function
    declares `global`."""
    names = set()
    for node in tree.body:
        if isinstance(node, ast.Assign) and isinstance(node.value, (ast.List, ast.Dict, ast.Set)):
            names.update(t.id for t in node.targets
                         if isinstance(t, ast.Name) and not t.id.isupper())
    for node in ast.walk(tree):
        if isinstance(node, ast.Global):
            names.update(node.names)
    return names


def test_module_state_has_one_owner():
    found = {name: module_state(tree) for name, tree in sources()}
    found = {name: names for name, names in found.items() if names}
    assert found == OWNED_STATE, found


def test_path_loaded_modules_are_bpy_free():
    for name, tree in sources():
        if name != "modal_rules.py":
            continue
        imported = [alias.name for node in ast.walk(tree)
                    if isinstance(node, (ast.Import, ast.ImportFrom))
                    for alias in node.names]
        relative = [node.module for node in ast.walk(tree)
                    if isinstance(node, ast.ImportFrom) and node.level]
        assert not relative and not any(m.split(".")[0] in ("bpy", "mathutils", "blf")
                                        for m in imported), (name, imported, relative)
