"""The steps of the hosted-CI recipe (.github/workflows/wheels.yml) that check built wheels,
written once in Python so that the same script runs on the macOS and Linux runners and here
(no bash, no ctest, no Blender install on the runner: `bpy` comes from the index). Windows'
checks are scripts/windows_check.py's, which the project's machine runs under wine; of this
script the Windows job uses `extension`.

    hosted_ci.py extension WHEEL_DIR PLATFORM OUT.zip
        the extension zip of one platform (linux-x64, windows-x64, macos-x64, macos-arm64)
        from the add-on and that platform's wheels, staged by cmake/addon.cmake (script mode)
        as the `addon_extension` targets stage theirs
    hosted_ci.py pytest WHEEL_DIR [--work DIR]
        a fresh venv on this Python with its wheel (+ NumPy, SciPy, pytest from the index),
        then tests/python (but the long test_solver_methods.py) against that installed package
    hosted_ci.py bpy SERIES ZIP [--work DIR] [--python VENV_PYTHON]
        a venv with Blender SERIES as `bpy` (or an existing one), then Blender's
        `extension validate` of ZIP and the add-on's bpy suites on the installed zip
        (tests/blender/bpy_module_suite.py), as the ctest blender_bpy_* tests do on Linux
Exit status: 0 when every step passed.
"""

import argparse
import glob
import os
import shutil
import subprocess
import sys
import sysconfig
import tempfile
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# The add-on's background suites, as tests/CMakeLists.txt's EDGEDEFORM_BPY_SUITES.
SUITES = ("bind_solve", "groups", "bake_output", "robustness", "ui_draw", "findable",
          "proportional")


def run(*cmd, **kw):
    print("+ " + " ".join(str(c) for c in cmd), flush=True)
    subprocess.run([str(c) for c in cmd], check=True, **kw)


def venv_python(venv):
    scripts = "Scripts" if os.name == "nt" else "bin"
    return Path(venv) / scripts / ("python.exe" if os.name == "nt" else "python")


def make_venv(folder, *packages):
    run(sys.executable, "-m", "venv", folder)
    python = venv_python(folder)
    run(python, "-m", "pip", "install", "-q", "--no-cache-dir", *packages)
    return python


def extension(args):
    stage = Path(tempfile.mkdtemp(prefix="edge_deform_extension_"))
    run("cmake", "-DED_ACTION=stage", "-DED_ADDON_SRC=%s" % (ROOT / "addon" / "edge_deform"),
        "-DED_WHEEL_DIR=%s" % Path(args.wheel_dir).resolve(), "-DED_DEST=%s" % stage,
        "-DED_EXT_PLATFORM=%s" % args.platform, "-DED_FLAT=TRUE",
        "-P", ROOT / "cmake" / "addon.cmake")
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        for path in sorted(stage.rglob("*")):
            if path.is_file():
                z.write(path, path.relative_to(stage).as_posix())
    shutil.rmtree(stage)
    print("extension zip for %s: %s" % (args.platform, out))


def this_wheel(wheel_dir):
    """The wheel for the Python and platform running this script."""
    tag = "cp%d%d" % sys.version_info[:2]
    plat = sysconfig.get_platform()          # win-amd64, linux-x86_64, macosx-11.0-arm64
    kind = "win" if plat.startswith("win") else "macosx" if plat.startswith("macosx") else "linux"
    arch = {"win": "amd64"}.get(kind, plat.rsplit("-", 1)[1])
    wheels = [w for w in glob.glob(os.path.join(wheel_dir, "edgedeform-*-%s-*.whl" % tag))
              if kind in os.path.basename(w) and w.endswith(("_%s.whl" % arch, "_universal2.whl"))]
    if len(wheels) != 1:
        sys.exit("hosted_ci: want one %s wheel for %s in %s, found %s" % (tag, plat, wheel_dir, wheels))
    return wheels[0]


def pytest_step(args):
    work = Path(args.work or tempfile.mkdtemp(prefix="edgedeform_pytest_"))
    python = make_venv(work / "venv", this_wheel(args.wheel_dir), "numpy", "scipy", "pytest")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    where = subprocess.run([str(python), "-c", "import edgedeform; print(edgedeform.__file__)"],
                           cwd=work, env=env, capture_output=True, text=True, check=True).stdout
    assert str(work / "venv") in where, "edgedeform is not the installed wheel: " + where
    tests = ROOT / "tests" / "python"
    run(python, "-m", "pytest", "-q", "-p", "no:cacheprovider",
        "--ignore", tests / "test_solver_methods.py", tests, cwd=work, env=env)


def bpy_step(args):
    work = Path(args.work or tempfile.mkdtemp(prefix="edgedeform_bpy_"))
    major, minor = (int(x) for x in args.series.split("."))
    python = Path(args.python) if args.python else make_venv(
        work / "venv", "bpy>=%d.%d.0,<%d.%d" % (major, minor, major, minor + 1))
    suite = ROOT / "tests" / "blender" / "bpy_module_suite.py"
    zip_path = Path(args.zip).resolve()
    env = dict(os.environ, EDGEDEFORM_TEST_DATA=str(ROOT / "tests" / "data"),
               EDGEDEFORM_TEST_OUT=str(work / "out"))
    results = work / "results"
    run(python, suite, "--zip", zip_path, "--home", work / "home-validate", "--results", results,
        "--validate", env=env)
    for name in SUITES:
        run(python, suite, "--zip", zip_path, "--home", work / ("home-" + name),
            "--results", results, "--suite", ROOT / "tests" / "blender" / ("test_%s.py" % name),
            env=env)
    passed = sorted(p.name for p in results.glob("*.pass"))
    assert len(passed) == len(SUITES), passed
    print("bpy %s: validate and %d suites passed: %s" % (args.series, len(passed), ", ".join(passed)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="step", required=True)
    e = sub.add_parser("extension")
    e.add_argument("wheel_dir")
    e.add_argument("platform", choices=["linux-x64", "windows-x64", "macos-x64", "macos-arm64"])
    e.add_argument("out")
    p = sub.add_parser("pytest")
    p.add_argument("wheel_dir")
    p.add_argument("--work")
    b = sub.add_parser("bpy")
    b.add_argument("series")
    b.add_argument("zip")
    b.add_argument("--work")
    b.add_argument("--python", help="an existing venv's python with that bpy")
    args = ap.parse_args()
    {"extension": extension, "pytest": pytest_step, "bpy": bpy_step}[args.step](args)


if __name__ == "__main__":
    main()
