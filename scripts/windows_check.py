"""The Windows checks in Windows' own CPython (python.org's embeddable 3.11 and 3.13) and
Windows' own Blender (`bpy` 4.5 and 5.3), all from scripts/windows_provision.py's cache:
under wine here (ctest's `windows` label, tests/windows/CMakeLists.txt), natively on the hosted
Windows runner (.github/workflows/wheels.yml). One script for both, so that what the hosted
job runs is what ran here.

    windows_check.py pytest 3.11 WHEEL_DIR [-m EXPR]
        that Python's wheel installed in a fresh folder (as pip installs it), then
        tests/python against it, with NumPy, SciPy and pytest (pins group tests-cp311)
    windows_check.py lift WHEEL_DIR INPUT [REFERENCE]
        solve_lift.py's solve of INPUT (make_lift_input.py) in both Pythons, on 2 and 1
        threads: the same bits every time, and within 1e-9 of the diagonal of REFERENCE
        (the Linux module's output) where given
    windows_check.py ucrt
        under wine: in both Pythons, the stand-in ucrtbase.dll is the one loaded, gives the
        six complex parts right (called through ctypes, as the x64 ABI passes them), forwards
        the rest to wine's, and lets NumPy's FFT and SciPy's scipy.special run
    windows_check.py bpy 4.5 ZIP [--validate | --suite tests/blender/test_X.py]
        Blender 4.5 (or 5.3) as a module: Blender's `extension validate` of the zip, or the zip
        installed from disk and one suite run (tests/blender/bpy_module_suite.py); neither
        option: the validation and every suite, one after another
Options: --work DIR (a folder of its own for the files; default a fresh temporary one).
Exit status: 0 when everything passed. Under wine, stdout and stderr of the Windows programs
come through a pipe (wine 8's python.exe dies writing to a regular file) and only one
Blender runs at a time on this machine.
"""

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import windows_provision as provision  # noqa: E402

from hosted_ci import SUITES  # noqa: E402  (the add-on's background suites)

ROOT = provision.ROOT


def native_path(path):
    """A path as the Windows program sees it: under wine, through its Z: drive (the root)."""
    path = str(Path(path).resolve())
    return "Z:" + path.replace("/", "\\") if provision.WINE else path


def wine_environment():
    """wine's settings: the cache's own prefix (made once), no debug output or debugger on a
    crash, no Mono or Gecko, and the Python folder's ucrtbase.dll first (windows_provision)."""
    prefix = provision.cache_root() / "wineprefix"
    env = dict(WINEPREFIX=str(prefix), WINEDEBUG="-all",
               WINEDLLOVERRIDES="mscoree,mshtml=;winedbg.exe=d;ucrtbase=n,b")
    wine = shutil.which("wine") or shutil.which("wine64")
    with provision.locked("wineprefix"):
        if not (prefix / "system.reg").is_file():
            subprocess.run([wine, "wineboot", "-i"], env=dict(os.environ, **env), check=True,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    # A server that outlives each program by a minute, so that every python.exe starts in a
    # second, not four; and wine's own services started now, apart from our pipes (started by
    # the first python.exe, they hold its output pipe open until they end: a minute's wait).
    subprocess.run(["wineserver", "-p60"], env=dict(os.environ, **env),
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    subprocess.run([wine, "cmd", "/c", "exit"], env=dict(os.environ, **env),
                   stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return wine, env


def run_python(version, args, paths=(), env=None, cwd=None):
    """python.exe of CPython `version` with `args`; PYTHONPATH is `paths`. Its output comes
    to ours; returns its exit status."""
    python = provision.python(version) / "python.exe"
    full_env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    full_env.update(env or {})
    full_env["PYTHONPATH"] = ";".join(native_path(p) for p in paths)
    full_env["PYTHONDONTWRITEBYTECODE"] = "1"
    command = [str(python)] + [str(a) for a in args]
    if provision.WINE:
        wine, wine_env = wine_environment()
        full_env.update(wine_env)
        command = [wine] + command
    shown = [a if "\n" not in a else "<script>" for a in command]
    print("+ %s (PYTHONPATH=%s)" % (" ".join(shown), full_env["PYTHONPATH"]), flush=True)
    proc = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, env=full_env, cwd=cwd)
    for line in proc.stdout:
        sys.stdout.buffer.write(line)
        sys.stdout.flush()
    return proc.wait()


def tag_of(version):
    return "cp" + version.replace(".", "")


def skip(reason):
    print("windows: %s: skipped" % reason, flush=True)
    sys.exit(3)


def installed_wheel(wheel_dir, version, work):
    """This Python's edgedeform wheel installed into work/site, as pip installs it."""
    tag = tag_of(version)
    if not list(Path(wheel_dir).glob("edgedeform-*-win_amd64.whl")):
        skip("no Windows wheel in %s (windows_build skipped)" % wheel_dir)
    wheels = sorted(Path(wheel_dir).glob("edgedeform-*-%s-%s-win_amd64.whl" % (tag, tag)))
    if not wheels:
        skip("no %s wheel (scripts/build_windows.sh found no Python %s headers here)" % (tag, version))
    if len(wheels) != 1:
        sys.exit("windows_check: want one %s win_amd64 wheel in %s, found %s" % (tag, wheel_dir, wheels))
    site = work / ("site-" + tag)
    shutil.rmtree(site, ignore_errors=True)
    provision.install_wheels(wheels, site, version)
    return site


# Run first in each Python: the package is the installed wheel's, and its module loads.
WHICH_EDGEDEFORM = r"""
import os, sys
import edgedeform
where = os.path.dirname(os.path.dirname(edgedeform.__file__))
assert os.path.normcase(where) == os.path.normcase(sys.argv[1]), (edgedeform.__file__, sys.argv[1])
print("edgedeform %s from %s: %s" % (edgedeform.__version__, where, edgedeform.build_info()))
"""


def check_installed(version, site, deps):
    if run_python(version, ["-c", WHICH_EDGEDEFORM, native_path(site)], [site, deps]) != 0:
        sys.exit("windows_check: the installed wheel does not load in CPython %s" % version)


def pytest_step(args, work):
    deps = provision.site("tests-" + tag_of(args.version))
    site = installed_wheel(args.wheel_dir, args.version, work)
    check_installed(args.version, site, deps)
    marks = ["-m", args.m] if args.m else []
    return run_python(args.version, ["-m", "pytest", "-q", "-p", "no:cacheprovider", "-rs",
                                     "--durations=10"] + marks
                      + [native_path(ROOT / "tests" / "python")], [site, deps], cwd=work)


def lift_step(args, work):
    here = ROOT / "tests" / "windows"
    outputs = []
    for version in ("3.11", "3.13"):
        deps = provision.site("tests-" + tag_of(version))
        site = installed_wheel(args.wheel_dir, version, work)
        check_installed(version, site, deps)
        for threads in ("2", "1"):
            out = work / ("lift-%s-%s.txt" % (tag_of(version), threads))
            status = run_python(version, [native_path(here / "solve_lift.py"), native_path(args.input),
                                          native_path(out), args.iterations],
                                [site, deps], env={"OMP_NUM_THREADS": threads})
            if status != 0:
                return status
            outputs.append(out)
    # compare_positions.py in a Windows Python too: the hosted runner's own has no NumPy.
    compare = [native_path(here / "compare_positions.py")]
    deps = [provision.site("tests-cp313")]
    status = run_python("3.13", compare + ["0", native_path(args.input)]
                        + [native_path(o) for o in outputs], deps)
    if args.reference and status == 0:
        status = run_python("3.13", compare + ["1e-9", native_path(args.input),
                                               native_path(args.reference), native_path(outputs[0])], deps)
    return status


UCRT_CHECK = r"""
import ctypes, os, sys
import numpy as np
import scipy.special

ucrt = ctypes.CDLL("ucrtbase")
path = ctypes.create_unicode_buffer(1024)
ctypes.windll.kernel32.GetModuleFileNameW(ctypes.c_void_p(ucrt._handle), path, 1024)
here = os.path.dirname(sys.executable)
assert os.path.normcase(path.value) == os.path.normcase(os.path.join(here, "ucrtbase.dll")), path.value

class F(ctypes.Structure):
    _fields_ = [("re", ctypes.c_float), ("im", ctypes.c_float)]

class D(ctypes.Structure):
    _fields_ = [("re", ctypes.c_double), ("im", ctypes.c_double)]

for name, kind, result, want in (("crealf", F, ctypes.c_float, 1.5), ("cimagf", F, ctypes.c_float, -2.25),
                                 ("creal", D, ctypes.c_double, 1.5), ("cimag", D, ctypes.c_double, -2.25),
                                 ("creall", D, ctypes.c_double, 1.5), ("cimagl", D, ctypes.c_double, -2.25)):
    f = getattr(ucrt, name)
    f.restype, f.argtypes = result, [kind]
    got = f(kind(1.5, -2.25))
    assert got == want, (name, got, want)
assert ucrt.strlen(b"wine") == 4           # forwarded to wine's own ucrtbase
assert np.allclose(np.fft.fft(np.arange(4.0)), [6, -2 + 2j, -2, -2 - 2j])
assert abs(scipy.special.gamma(5.0) - 24.0) < 1e-12
print("CPython %s: %s stands in for ucrtbase: complex parts right, the rest wine's; NumPy %s, SciPy %s"
      % (sys.version.split()[0], path.value, np.__version__, scipy.__version__))
"""


def ucrt_step(args, work):
    if not provision.WINE:
        skip("Windows' own UCRT: nothing stands in for it")
    for version in ("3.11", "3.13"):
        status = run_python(version, ["-c", UCRT_CHECK], [provision.site("tests-" + tag_of(version))])
        if status != 0:
            return status
    return 0


def bpy_step(args, work):
    series = args.series
    version = "3.11" if tuple(map(int, series.split("."))) < (5, 1) else "3.13"
    if not Path(args.zip).is_file():
        skip("no Windows zip %s (windows_build skipped)" % args.zip)
    with zipfile.ZipFile(args.zip) as z:
        if not any("-%s-" % tag_of(version) in n for n in z.namelist() if n.endswith(".whl")):
            skip("the zip has no %s wheel for Blender %s" % (tag_of(version), series))
    site = provision.site("bpy-" + series)
    suite = ROOT / "tests" / "blender" / "bpy_module_suite.py"
    env = {"EDGEDEFORM_TEST_DATA": native_path(ROOT / "tests" / "data"),
           "EDGEDEFORM_TEST_OUT": native_path(work / "out")}
    if args.validate:
        runs = [("validate", ["--validate"])]
    elif args.suite:
        runs = [(Path(args.suite).stem, ["--suite", native_path(args.suite)])]
    else:
        runs = [("validate", ["--validate"])] + [
            (name, ["--suite", native_path(ROOT / "tests" / "blender" / ("test_%s.py" % name))])
            for name in SUITES]
    for name, what in runs:
        command = [native_path(suite), "--zip", native_path(args.zip), "--home",
                   native_path(work / ("home-" + name)), "--results", native_path(work / "results")]
        with provision.locked("blender"):   # one Blender at a time on this machine
            status = run_python(version, command + what, [site], env=env, cwd=work)
        if status != 0:
            print("windows_check: bpy %s: %s failed (exit %d)" % (series, name, status), flush=True)
            return status or 1
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="step", required=True)
    p = sub.add_parser("pytest")
    p.add_argument("version", choices=["3.11", "3.13"])
    p.add_argument("wheel_dir")
    p.add_argument("-m", help="pytest's marker expression")
    lift = sub.add_parser("lift")
    lift.add_argument("wheel_dir")
    lift.add_argument("input")
    lift.add_argument("reference", nargs="?")
    lift.add_argument("--iterations", default="30")
    u = sub.add_parser("ucrt")
    b = sub.add_parser("bpy")
    b.add_argument("series", choices=["4.5", "5.3"])
    b.add_argument("zip")
    what = b.add_mutually_exclusive_group()
    what.add_argument("--validate", action="store_true")
    what.add_argument("--suite")
    for parser in (p, lift, u, b):
        parser.add_argument("--work")
    args = ap.parse_args()
    provision.require_tools()
    work = Path(args.work) if args.work else Path(tempfile.mkdtemp(prefix="edgedeform_windows_"))
    work.mkdir(parents=True, exist_ok=True)
    step = {"pytest": pytest_step, "lift": lift_step, "ucrt": ucrt_step, "bpy": bpy_step}[args.step]
    sys.exit(step(args, work.resolve()))


if __name__ == "__main__":
    main()
