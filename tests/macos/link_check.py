"""The macOS link check: the `_core` module for python.org's CPython 3.11 and 3.13 on macOS
x86_64 and arm64, compiled and linked on this Linux machine with PyPI's Zig (`zig c++`: clang
with a macOS SDK's libraries), never run (no Mac here: docs/decisions/0065). Each module must be
a 64-bit Mach-O library for its architecture and macOS 11 (Blender 4.2's oldest), export
PyInit__core, load nothing but libSystem (Zig links libc++ in) and leave undefined only names
that libSystem or the interpreter provides (Python's `Py`/`_Py` C API, which a macOS CPython
resolves at load: -undefined dynamic_lookup, as setuptools links).

    link_check.py BUILD_DIR SOURCES_FILE PYTHON [VERSION ...]      e.g. ... 3.11 3.13

SOURCES_FILE (tests/macos/CMakeLists.txt writes it): "core PATH" and "binding PATH" lines.
PYTHON has pybind11 (>= 2.12) importable. The headers are this machine's CPython X.Y headers
with cmake/macos/pyconfig.h in place of theirs (scripts/python_headers.sh); a version without
them is reported and left out. Exit 3 (ctest: skipped) when no version has headers.
"""

import os
import re
import shutil
import struct
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
import windows_provision  # noqa: E402  (the cache: ziglang)

TARGETS = {"x86_64": ("x86_64-macos.11.0", 0x01000007), "arm64": ("aarch64-macos.11.0", 0x0100000C)}
FLAGS = ["-std=c++17", "-O1", "-DNDEBUG", "-fvisibility=hidden", '-DEDGEDEFORM_VERSION="%s"']
LC_SYMTAB, LC_LOAD_DYLIB, LC_BUILD_VERSION = 0x2, 0xC, 0x32
MH_DYLIB, MH_BUNDLE = 6, 8


def macho(path):
    """(cpu type, file type, dylibs loaded, minimum macOS, exported names, undefined names)."""
    data = Path(path).read_bytes()
    magic, cpu, _, filetype, ncmds, _, _, _ = struct.unpack_from("<IiiIIIII", data, 0)
    assert magic == 0xFEEDFACF, "%s: not a 64-bit Mach-O file" % path
    dylibs, minos, exported, undefined = [], None, set(), set()
    offset = 32
    for _ in range(ncmds):
        cmd, size = struct.unpack_from("<II", data, offset)
        if cmd == LC_LOAD_DYLIB:
            name_at = struct.unpack_from("<I", data, offset + 8)[0]
            dylibs.append(data[offset + name_at:offset + size].split(b"\0")[0].decode())
        elif cmd == LC_BUILD_VERSION:
            version = struct.unpack_from("<I", data, offset + 12)[0]
            minos = (version >> 16, (version >> 8) & 0xFF)
        elif cmd == LC_SYMTAB:
            symoff, nsyms, stroff, _ = struct.unpack_from("<IIII", data, offset + 8)
            for k in range(nsyms):
                strx, ntype, sect, _, _ = struct.unpack_from("<IBBhQ", data, symoff + 16 * k)
                name = data[stroff + strx:].split(b"\0", 1)[0].decode()
                if ntype & 0x01 and ntype & 0x0E == 0x0E:        # external, defined in a section
                    exported.add(name)
                elif ntype & 0x01 and ntype & 0x0E == 0:        # external, undefined
                    undefined.add(name)
        offset += size
    return cpu, filetype, dylibs, minos, exported, undefined


def headers(version, build):
    """A copy of this machine's CPython `version` headers with the macOS pyconfig.h."""
    done = subprocess.run(["bash", str(ROOT / "scripts" / "python_headers.sh"), version],
                          capture_output=True, text=True)
    if done.returncode != 0:
        print("macos: %s: no cp%s module checked" % (done.stderr.strip(), version.replace(".", "")))
        return None
    include = build / ("python-%s" % version) / "include"
    shutil.rmtree(include, ignore_errors=True)
    shutil.copytree(done.stdout.strip(), include)
    shutil.copy(ROOT / "cmake" / "macos" / "pyconfig.h", include / "pyconfig.h")
    return include


def main():
    build, sources_file, python = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3]
    versions = sys.argv[4:] or ["3.11", "3.13"]
    sources = {"core": [], "binding": []}
    for line in sources_file.read_text().splitlines():
        kind, path = line.split(" ", 1)
        sources[kind].append(path)
    build.mkdir(parents=True, exist_ok=True)
    includes = {v: headers(v, build) for v in versions}
    includes = {v: i for v, i in includes.items() if i is not None}
    if not includes:
        print("macos: no CPython headers here: skipped")
        return 3
    pybind11 = subprocess.run([python, "-c", "import pybind11; print(pybind11.get_include())"],
                              check=True, capture_output=True, text=True).stdout.strip()
    zig = str(windows_provision.zig())
    libsystem = libsystem_names(zig)
    # Zig keeps what it builds once (libc++ for each target: minutes) in the cache too.
    env = dict(os.environ, ZIG_GLOBAL_CACHE_DIR=str(windows_provision.cache_root() / "zig-cache"))
    version_define = FLAGS[-1] % next(line for line in (ROOT / "CMakeLists.txt").read_text()
                                      .splitlines() if "project(edgedeform" in line).split()[2]
    common = [*FLAGS[:-1], version_define, "-I%s" % (ROOT / "native" / "include"),
              "-I/usr/include/eigen3"]

    def compile_one(job):
        target, source, out, extra = job
        subprocess.run([zig, "-m", "ziglang", "c++", "-target", target, *common, *extra,
                        "-c", source, "-o", str(out)], check=True, env=env)
        return out

    jobs = []
    for arch, (target, _) in TARGETS.items():
        objects = build / arch
        objects.mkdir(exist_ok=True)
        jobs += [(target, s, objects / ("core-%s.o" % Path(s).stem), []) for s in sources["core"]]
        for version, include in includes.items():
            jobs += [(target, s, objects / ("cp%s-%s.o" % (version.replace(".", ""), Path(s).stem)),
                      ["-isystem", str(include), "-isystem", pybind11]) for s in sources["binding"]]
    with ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
        list(pool.map(compile_one, jobs))

    failed = False
    for arch, (target, cpu_type) in TARGETS.items():
        for version in includes:
            tag = version.replace(".", "")
            module = build / arch / ("_core.cpython-%s-darwin.so" % tag)
            objects = sorted((build / arch).glob("core-*.o")) + sorted((build / arch).glob("cp%s-*.o" % tag))
            subprocess.run([zig, "-m", "ziglang", "c++", "-target", target, "-shared",
                            "-Wl,-undefined,dynamic_lookup", "-o", str(module)]
                           + [str(o) for o in objects], check=True, env=env)
            cpu, filetype, dylibs, minos, exported, undefined = macho(module)
            foreign = sorted(u for u in undefined
                             if not u.startswith(("_Py", "__Py")) and u not in libsystem)
            problems = []
            if cpu != cpu_type or filetype not in (MH_DYLIB, MH_BUNDLE):
                problems.append("cpu %#x, file type %d" % (cpu, filetype))
            if minos != (11, 0):
                problems.append("minimum macOS %s" % (minos,))
            if "_PyInit__core" not in exported:
                problems.append("no PyInit__core")
            if dylibs != ["/usr/lib/libSystem.B.dylib"]:
                problems.append("loads %s" % dylibs)
            if foreign:
                problems.append("undefined beyond Python and libSystem: %s" % foreign[:10])
            python_names = sum(1 for u in undefined if u.startswith(("_Py", "__Py")))
            print("%s: %s, macOS %d.%d+, loads %s; %d Python names left to the interpreter: %s"
                  % (module.relative_to(build), arch, *(minos or (0, 0)), ", ".join(dylibs),
                     python_names, "; ".join(problems) or "OK"), flush=True)
            failed |= bool(problems)
    return 1 if failed else 0


def libsystem_names(zig_python):
    """Every name macOS's libSystem and the libraries it re-exports provide, from the
    text-based stub Zig links against (libc/darwin/libSystem.tbd in the ziglang package)."""
    tbd = subprocess.run([zig_python, "-c", "import ziglang, os; print(os.path.dirname(ziglang.__file__))"],
                         check=True, capture_output=True, text=True).stdout.strip()
    text = (Path(tbd) / "lib" / "libc" / "darwin" / "libSystem.tbd").read_text()
    names = set()
    for block in re.findall(r"symbols:\s*\[(.*?)\]", text, re.S):   # symbols, weak-symbols, ...
        names.update(n.strip().strip("'") for n in block.split(",") if n.strip())
    return names


if __name__ == "__main__":
    sys.exit(main())
