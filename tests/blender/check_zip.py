"""The add-on zip and the extension zip: their contents, the manifest, and an install of
the add-on zip the way Preferences > Add-ons > Install does it (into private folders)."""

import os
import sys
import tomllib
import zipfile

import addon_utils
import bpy

zip_path, ext_path = sys.argv[sys.argv.index("--") + 1:][:2]

names = zipfile.ZipFile(zip_path).namelist()
assert "edge_deform/__init__.py" in names, names
assert "edge_deform/blender_manifest.toml" not in names
assert any(n.startswith("edge_deform/edgedeform/_core") and n.endswith(".so") for n in names)
assert not any("__pycache__" in n for n in names)

ext = zipfile.ZipFile(ext_path)
ext_names = ext.namelist()
assert "blender_manifest.toml" in ext_names and "__init__.py" in ext_names, ext_names
assert any(n.startswith("edgedeform/_core") and n.endswith(".so") for n in ext_names)
manifest = tomllib.loads(ext.read("blender_manifest.toml").decode())
assert manifest["id"] == "edge_deform" and manifest["type"] == "add-on"
assert manifest["blender_version_min"] == "4.2.0" and manifest["platforms"]
# Rules Blender 4.2's `extension validate` applies to these fields.
assert manifest["schema_version"] == "1.0.0" and manifest["version"].count(".") == 2
assert len(manifest["tagline"]) <= 64 and manifest["tagline"][-1] not in ".!?"
assert all(lic.startswith("SPDX:") for lic in manifest["license"])

bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
addon_utils.enable("edge_deform", default_set=True, handle_error=None)
import edge_deform  # noqa: E402
from edge_deform import native  # noqa: E402

scripts = os.path.realpath(os.environ["BLENDER_USER_SCRIPTS"])
assert os.path.realpath(native.get().__file__).startswith(scripts), native.get().__file__
assert hasattr(bpy.types.Object, "edge_deform")
print("zips OK:", zip_path, ext_path)
