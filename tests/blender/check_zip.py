"""The legacy add-on zip (Blender 3.x): its contents and an install the way Preferences >
Add-ons > Install does it (into private folders). The 4.2+ extension zip is checked by
bpy_module_suite.py --validate."""

import os
import sys
import zipfile

import addon_utils
import bpy

zip_path = sys.argv[sys.argv.index("--") + 1]

names = zipfile.ZipFile(zip_path).namelist()
assert "edge_deform/__init__.py" in names, names
assert "edge_deform/blender_manifest.toml" not in names
assert any(n.startswith("edge_deform/edgedeform/_core") and n.endswith(".so") for n in names)
assert not any("__pycache__" in n for n in names)

bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
addon_utils.enable("edge_deform", default_set=True, handle_error=None)
import edge_deform  # noqa: E402
from edge_deform import native  # noqa: E402

scripts = os.path.realpath(os.environ["BLENDER_USER_SCRIPTS"])
assert os.path.realpath(native.get().__file__).startswith(scripts), native.get().__file__
assert hasattr(bpy.types.Object, "edge_deform")
print("add-on zip OK:", zip_path)
