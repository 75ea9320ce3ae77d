"""The win_amd64 wheels of the cross-build (scripts/build_windows.sh): one per asked Python,
each a valid wheel (RECORD hashes, WHEEL tag, METADATA, the console script) holding the whole
package and a `_core` module for that Python that exports PyInit__core and needs no DLL but
that Python's, Windows's own, the C runtime named in docs/decisions/0045-windows-cross-build.md
(libstdc++, libgcc, libgomp and winpthreads are linked in) and OpenBLAS's DLL, which CHOLMOD
calls (docs/decisions/0063): in the wheel beside the module, itself needing only Windows and
its Universal C Runtime (api-ms-win-crt-*). EDGEDEFORM_WINDOWS_SOLVER=eigen (a build with
Eigen's solver, scripts/build_windows.sh) expects no BLAS.

    check_windows_wheels.py WHEEL_DIR OBJDUMP TAG [TAG ...]      e.g. ... cp311 cp313

A tag whose Python (its headers) this machine lacks is not built (build_windows.sh says so):
Debian 13 has no Python 3.11, so there only cp313 is asked for, and the test says which tag
it left out. Hosted CI builds the release's wheels where both Pythons are.
"""

import base64
import hashlib
import os
import re
import shutil
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SYSTEM_DLLS = {"kernel32.dll", "msvcrt.dll"}   # the C runtime: MSVCRT (decision record 0045)
BLAS_DLL = "edgedeform_openblas.dll"            # CHOLMOD's OpenBLAS (decision record 0063)
CHOLMOD = os.environ.get("EDGEDEFORM_WINDOWS_SOLVER", "cholmod") == "cholmod"


def check_record(z, names):
    record_name, = [n for n in names if n.endswith(".dist-info/RECORD")]
    listed = {}
    for line in z.read(record_name).decode().splitlines():
        name, digest, size = line.rsplit(",", 2)
        listed[name] = (digest, size)
    assert set(listed) == set(names), set(listed) ^ set(names)
    for name, (digest, size) in listed.items():
        if name == record_name:
            continue
        data = z.read(name)
        want = "sha256=" + base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
        assert digest == want and int(size) == len(data), (name, digest, want)


def pe_headers(objdump, data):
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "file.dll")
        Path(path).write_bytes(data)
        return subprocess.run([objdump, "-p", path], capture_output=True, text=True,
                              check=True).stdout


def imported_dlls(headers):
    return {d.lower() for d in re.findall(r"DLL Name: (\S+)", headers)}


def check_blas(objdump, data, wheel_name):
    """OpenBLAS's DLL needs nothing but Windows and its Universal C Runtime."""
    headers = pe_headers(objdump, data)
    assert "file format pei-x86-64" in headers, "%s: %s is not a 64-bit DLL" % (wheel_name, BLAS_DLL)
    assert re.search(r"\sopenblas_set_num_threads$", headers, re.M), "no thread control to limit"
    extra = {d for d in imported_dlls(headers)
             if d != "kernel32.dll" and not d.startswith("api-ms-win-crt-")}
    assert not extra, "%s: %s needs %s" % (wheel_name, BLAS_DLL, sorted(extra))


def check_module(objdump, data, tag):
    headers = pe_headers(objdump, data)
    assert "file format pei-x86-64" in headers, "%s: not a 64-bit Windows DLL" % tag
    dlls = imported_dlls(headers)
    python_dll = "python%s.dll" % tag[2:]
    assert python_dll in dlls, (tag, dlls)
    if CHOLMOD:
        assert BLAS_DLL in dlls, "%s: a CHOLMOD module calls %s: %s" % (tag, BLAS_DLL, sorted(dlls))
    extra = dlls - SYSTEM_DLLS - {python_dll, BLAS_DLL}
    assert not extra, "%s: the module needs DLLs no Windows Python has: %s" % (tag, sorted(extra))
    # binutils 2.40 (Debian 12) lists "[   0] PyInit__core"; 2.44 (Debian 13) adds the
    # ordinal and hint: "[   0] +base[   1]  0000 PyInit__core".
    assert re.search(r"\[\s*\d+\][^\n]*\sPyInit__core$", headers, re.M), \
        "%s: no PyInit__core export" % tag
    return sorted(dlls)


def has_headers(tag):
    """Whether build_windows.sh can build `tag` here (scripts/python_headers.sh, which it
    uses too, finds that Python's Python.h)."""
    version = "%s.%s" % (tag[2], tag[3:])
    return subprocess.run(["bash", str(ROOT / "scripts" / "python_headers.sh"), version],
                          capture_output=True).returncode == 0


def main():
    wheel_dir, objdump, asked = Path(sys.argv[1]), sys.argv[2], sys.argv[3:]
    tags = [t for t in asked if has_headers(t)]
    for tag in sorted(set(asked) - set(tags)):
        print("windows: no Python %s.%s with headers here: no %s wheel asked for" % (tag[2], tag[3:], tag))
    version = re.search(r"project\(edgedeform VERSION ([0-9.]+)",
                        (ROOT / "CMakeLists.txt").read_text()).group(1)
    sources = sorted(p.relative_to(ROOT / "native" / "python").as_posix()
                     for p in (ROOT / "native" / "python" / "edgedeform").rglob("*.py"))
    wheels = sorted(wheel_dir.glob("edgedeform-*.whl"))
    if not wheels and not shutil.which(objdump):
        print("windows: no wheels in %s and no %s (windows_build skipped: no mingw-w64?): "
              "skipped" % (wheel_dir, objdump))
        return 3
    found = [w.name.split("-")[2] for w in wheels]
    assert sorted(found) == sorted(tags), "wheels for %s, asked for %s" % (found, tags)
    for wheel in wheels:
        tag = wheel.name.split("-")[2]
        assert wheel.name == "edgedeform-%s-%s-%s-win_amd64.whl" % (version, tag, tag), wheel.name
        with zipfile.ZipFile(wheel) as z:
            names = z.namelist()
            check_record(z, names)
            dist = "edgedeform-%s.dist-info/" % version
            wheel_meta = z.read(dist + "WHEEL").decode()
            assert "Tag: %s-%s-win_amd64" % (tag, tag) in wheel_meta, wheel_meta
            assert "Root-Is-Purelib: false" in wheel_meta, wheel_meta
            meta = z.read(dist + "METADATA").decode()
            assert "Name: edgedeform\n" in meta and "Version: %s\n" % version in meta, meta
            assert "Requires-Dist: numpy\n" in meta, meta
            assert "edgedeform = edgedeform.cli:main" in z.read(dist + "entry_points.txt").decode()
            missing = [s for s in sources if s not in names]
            assert not missing, "%s lacks %s" % (wheel.name, missing)
            module = "edgedeform/_core.%s-win_amd64.pyd" % tag
            assert module in names, (wheel.name, names)
            assert not any(n.endswith((".so", ".pyc")) or "__pycache__" in n for n in names), names
            dlls = check_module(objdump, z.read(module), tag)
            blas = "edgedeform/" + BLAS_DLL
            assert (blas in names) == CHOLMOD, (wheel.name, "has" if blas in names else "lacks", blas)
            if CHOLMOD:
                check_blas(objdump, z.read(blas), wheel.name)
        print("%s: %d files, RECORD verified; %s imports only %s" % (
            wheel.name, len(names), module, ", ".join(dlls)), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
