"""Runs the add-on's background tests inside Blender as a Python module (`pip install bpy`).

    <venv>/bin/python bpy_module_suite.py --zip EXTENSION.zip --home DIR --results DIR
                                          (--validate | --suite tests/blender/test_X.py)

--validate  Blender's own extension check of the zip: what `blender --command extension
            validate` runs (the `bpy` module has no command line).
--suite     Installs the zip the way a user does (Install from Disk:
            bpy.ops.extensions.package_install_files) into fresh user folders under DIR,
            checks that the add-on is enabled and that `edgedeform` is the extension's wheel,
            then runs the suite file unchanged, with the same assertions as on Blender 3.4.
            On success it writes RESULTS/<blender version>-<suite>.pass, which
            check_bpy_results.py reads.
"""

import argparse
import importlib
import importlib.machinery
import io
import os
import re
import runpy
import shutil
import sys
import tomllib
import zipfile


def parse():
    p = argparse.ArgumentParser()
    p.add_argument("--zip", required=True)
    p.add_argument("--home", required=True, help="throwaway folder for Blender's user files")
    p.add_argument("--results", required=True)
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--validate", action="store_true")
    what.add_argument("--suite")
    return p.parse_args()


def private_user_folders(home):
    """Point every Blender user folder into `home` (must happen before `import bpy`)."""
    shutil.rmtree(home, ignore_errors=True)
    for var, sub in (("BLENDER_USER_RESOURCES", "resources"), ("BLENDER_USER_CONFIG", "config"),
                     ("BLENDER_USER_SCRIPTS", "scripts"), ("BLENDER_USER_DATAFILES", "datafiles"),
                     ("BLENDER_USER_EXTENSIONS", "extensions")):
        os.environ[var] = os.path.join(home, sub)
        os.makedirs(os.environ[var])
    # The suite must get `edgedeform` from the extension's wheel, not from a build folder.
    os.environ.pop("PYTHONPATH", None)
    sys.path[:] = [p for p in sys.path if not os.path.isfile(os.path.join(p, "edgedeform",
                                                                         "__init__.py"))]


# Per extension platform: how its wheels end, its module's file name, and the file that shows
# CHOLMOD's BLAS travels inside (Linux: libcholmod and OpenBLAS, by auditwheel; Windows:
# CHOLMOD linked into the module, OpenBLAS's DLL beside it, decision record 0063; macOS uses
# the Eigen solver, record 0045).
PLATFORMS = {
    "linux-x64": (("_x86_64.whl",), ".so", "libcholmod"),
    "windows-x64": (("-win_amd64.whl",), ".pyd", "edgedeform/edgedeform_openblas.dll"),
    "macos-x64": (("_x86_64.whl", "_universal2.whl"), ".so", None),
    "macos-arm64": (("_arm64.whl", "_universal2.whl"), ".so", None),
}


def check_contents(zip_path):
    """What Blender's validation does not check: the zip is for one platform and ships
    exactly the wheels its manifest names, one per Python, each the package at the add-on's
    version with its module for that Python and platform; a zip for this machine's platform
    has a wheel for the Python running this check."""
    ext = zipfile.ZipFile(zip_path)
    names = ext.namelist()
    manifest = tomllib.loads(ext.read("blender_manifest.toml").decode())
    assert "__init__.py" in names, names
    assert not any(n.startswith("edgedeform/") or "__pycache__" in n for n in names), names
    assert len(manifest["platforms"]) == 1, "one zip per platform: %s" % manifest["platforms"]
    platform = manifest["platforms"][0]
    endings, module_suffix, cholmod_file = PLATFORMS[platform]
    wheels = sorted(n for n in names if n.startswith("wheels/") and n.endswith(".whl"))
    assert ["./" + n for n in wheels] == sorted(manifest["wheels"]), (wheels, manifest["wheels"])
    tags = [os.path.basename(w).split("-")[2] for w in wheels]
    assert len(set(tags)) == len(tags), "two wheels for one Python: %s" % wheels
    if platform == "linux-x64":
        this_python = "cp%d%d" % sys.version_info[:2]
        assert this_python in tags, "no %s wheel for this Python in %s" % (this_python, wheels)
    init = ext.read("__init__.py").decode()
    bl_info = re.search(r'"version": \((\d+), (\d+), (\d+)\)', init)
    for name in wheels:
        wheel = zipfile.ZipFile(io.BytesIO(ext.read(name)))
        tag = os.path.basename(name).split("-")[2]
        assert name.endswith(endings), (name, "is not a %s wheel" % platform)
        assert any(n.startswith("edgedeform/_core.c") and tag[2:] in n and n.endswith(module_suffix)
                   for n in wheel.namelist()), (name, "has no _core module for its Python")
        versions = {manifest["version"], os.path.basename(name).split("-")[1],
                    ".".join(bl_info.groups())}
        assert len(versions) == 1, "manifest, wheel and bl_info versions differ: %s" % versions
        if cholmod_file:
            # Self-contained: CHOLMOD and its BLAS travel in the wheel.
            assert any(cholmod_file in n for n in wheel.namelist()), name + ": no CHOLMOD inside"
    assert "permissions" not in manifest, "the add-on touches no files, network or devices"
    print("%s zip holds the wheels %s, as its manifest lists" % (platform, ", ".join(tags)),
          flush=True)


def with_bad_tagline(zip_path, home):
    """A copy of the zip whose manifest breaks a rule: the validation must refuse it."""
    bad = os.path.join(home, "bad_manifest.zip")
    with zipfile.ZipFile(zip_path) as src, zipfile.ZipFile(bad, "w") as dst:
        for item in src.infolist():
            data = src.read(item)
            if item.filename == "blender_manifest.toml":
                data = re.sub(rb'tagline = "[^"]*"', b'tagline = "Ends with a period."', data)
            dst.writestr(item, data)
    return bad


def validate(bpy, zip_path, home):
    """Blender's `extension validate` (bl_pkg.cli_extension is what the command line calls)."""
    check_contents(zip_path)
    bl_pkg = sys.modules.get("bl_pkg") or importlib.import_module("bl_pkg")
    print("bpy %s: extension validate %s" % (bpy.app.version_string, zip_path), flush=True)
    if bl_pkg.cli_extension(["validate", with_bad_tagline(zip_path, home)]) == 0:
        print("the validation accepted a broken manifest: it checks nothing")
        return 1
    return bl_pkg.cli_extension(["validate", zip_path])


def install(bpy, zip_path):
    """Install from Disk + enable; returns the add-on's module."""
    import addon_utils
    result = bpy.ops.extensions.package_install_files(
        filepath=zip_path, repo="user_default", enable_on_install=True)
    assert result == {'FINISHED'}, result
    name = "bl_ext.user_default.edge_deform"
    assert name in bpy.context.preferences.addons, list(bpy.context.preferences.addons.keys())
    assert addon_utils.check(name)[1], "installed but not enabled"
    module = sys.modules[name]
    ext_dir = os.path.realpath(bpy.utils.user_resource('EXTENSIONS'))
    assert os.path.realpath(module.__file__).startswith(
        os.path.join(ext_dir, "user_default", "edge_deform")), module.__file__
    assert ext_dir.startswith(os.path.realpath(os.environ["BLENDER_USER_EXTENSIONS"])), ext_dir
    import edgedeform
    wheel_site = os.path.join(ext_dir, ".local")
    assert os.path.realpath(edgedeform.__file__).startswith(wheel_site), (
        "edgedeform should come from the extension's wheel, not " + edgedeform.__file__)
    # Blender picked the wheel of its own Python out of the several the zip holds: the
    # module carries this Python's own tagged suffix (the first one the import system
    # tries: .cpython-311-x86_64-linux-gnu.so, .cp311-win_amd64.pyd, .cpython-311-darwin.so).
    suffix = importlib.machinery.EXTENSION_SUFFIXES[0]
    assert edgedeform._core.__file__.endswith(suffix), (edgedeform._core.__file__, suffix)
    assert hasattr(bpy.types.Object, "edge_deform")
    print("bpy %s: installed %s; edgedeform %s from %s" % (
        bpy.app.version_string, module.__file__, edgedeform.__version__,
        edgedeform.__file__), flush=True)
    return module


def alias_as_edge_deform(module):
    """The suites `import edge_deform` (as on 3.4, where it is a top-level add-on). An
    extension lives at bl_ext.user_default.edge_deform: make that same module (and so the
    same session state the operators use) answer to the suites' name."""
    prefix = module.__name__
    for name, mod in list(sys.modules.items()):
        if name == prefix or name.startswith(prefix + "."):
            sys.modules["edge_deform" + name[len(prefix):]] = mod
    site = os.path.dirname(os.path.dirname(sys.modules["edgedeform"].__file__))
    # helpers.py puts these folders first on sys.path: point them at the installed copies.
    os.environ["EDGEDEFORM_PYTHONPATH"] = site
    os.environ["EDGEDEFORM_ADDON_DIR"] = site


def run_suite(bpy, args):
    version = "%d.%d.%d" % bpy.app.version
    suite = os.path.splitext(os.path.basename(args.suite))[0]
    marker = os.path.join(args.results, "%s-%s.pass" % (version, suite))
    os.makedirs(args.results, exist_ok=True)
    if os.path.exists(marker):
        os.remove(marker)
    alias_as_edge_deform(install(bpy, os.path.abspath(args.zip)))
    try:
        runpy.run_path(args.suite, run_name="__main__")
    except SystemExit as exc:   # helpers.run raises it when a test failed
        if exc.code not in (None, 0):
            print(exc.code, flush=True)
            return 1
    open(marker, "w").write(bpy.app.version_string + "\n")
    print("bpy %s: %s passed" % (bpy.app.version_string, suite), flush=True)
    return 0


def main():
    args = parse()
    private_user_folders(os.path.abspath(args.home))
    import bpy
    if bpy.app.version < (4, 2, 0):
        print("bpy %s has no extensions (4.2+)" % bpy.app.version_string)
        return 1
    if args.validate:
        return validate(bpy, os.path.abspath(args.zip), os.path.abspath(args.home))
    return run_suite(bpy, args)


if __name__ == "__main__":
    try:
        code = main()
    except BaseException:
        import traceback
        traceback.print_exc()
        code = 1
    sys.stdout.flush()
    sys.stderr.flush()
    # bpy 4.5's module deadlocks in a static destructor at interpreter exit once its
    # delayed-close thread has started (~GlobalState waits on a condition variable the thread
    # still holds); everything is flushed and checked by now, so leave without destructors.
    os._exit(code)
