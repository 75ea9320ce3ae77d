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
assert "edge_deform/docs/addon.md" in names and "edge_deform/docs/img/addon_panel.png" in names

bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
addon_utils.enable("edge_deform", default_set=True, handle_error=None)
import edge_deform  # noqa: E402
from edge_deform import compat  # noqa: E402

scripts = os.path.realpath(os.environ["BLENDER_USER_SCRIPTS"])
assert os.path.realpath(compat.native_package().__file__).startswith(scripts), compat.native_package().__file__
assert hasattr(bpy.types.Object, "edge_deform")

# Preferences > Add-ons shows "Documentation" for the info Blender parsed from the file: it
# must open the manual installed with the add-on.
from urllib.parse import urlparse  # noqa: E402
from urllib.request import url2pathname  # noqa: E402
addon_utils.modules(refresh=False)
info = addon_utils.module_bl_info(addon_utils.addons_fake_modules["edge_deform"])
manual = url2pathname(urlparse(info["doc_url"]).path)
assert info["doc_url"].startswith("file://") and os.path.isfile(manual), info["doc_url"]
assert os.path.realpath(manual) == os.path.join(
    os.path.realpath(os.path.dirname(edge_deform.__file__)), "docs", "addon.md"), manual
print("add-on zip OK:", zip_path, "- manual:", info["doc_url"])
