"""Packs a built package folder into a wheel, for builds that pip cannot drive here (the
mingw-w64 cross-build for Windows: scripts/build_windows.sh).

    pack_wheel.py PACKAGE_DIR TAG OUT_DIR       e.g. build/windows/python-cp311/edgedeform
                                                     cp311-cp311-win_amd64 build/windows/wheels

Name, version, summary, requirements and the console script come from pyproject.toml and
CMakeLists.txt, as scikit-build-core writes them for `pip install .`. Prints the wheel's path.
"""

import base64
import hashlib
import re
import sys
import tomllib
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def record_line(name, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return "%s,sha256=%s,%d" % (name, digest, len(data))


def metadata(project, version):
    lines = ["Metadata-Version: 2.1", "Name: " + project["name"], "Version: " + version,
             "Summary: " + project["description"],
             "License: " + project["license"]["text"],
             "Requires-Python: " + project["requires-python"]]
    lines += ["Requires-Dist: " + d for d in project.get("dependencies", [])]
    for extra, deps in project.get("optional-dependencies", {}).items():
        lines.append("Provides-Extra: " + extra)
        lines += ['Requires-Dist: %s; extra == "%s"' % (d, extra) for d in deps]
    return "\n".join(lines) + "\n"


def main():
    package, tag, out = Path(sys.argv[1]), sys.argv[2], Path(sys.argv[3])
    if not (package / "__init__.py").is_file():
        sys.exit("pack_wheel: %s is not a package folder" % package)
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    version = re.search(r"project\(edgedeform VERSION ([0-9.]+)",
                        (ROOT / "CMakeLists.txt").read_text()).group(1)
    name = project["name"]
    dist_info = "%s-%s.dist-info" % (name, version)
    files = {}
    for path in sorted(package.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts and path.suffix != ".pyc":
            files["%s/%s" % (package.name, path.relative_to(package).as_posix())] = path.read_bytes()
    files[dist_info + "/METADATA"] = metadata(project, version).encode()
    files[dist_info + "/WHEEL"] = ("Wheel-Version: 1.0\nGenerator: edgedeform pack_wheel.py\n"
                                   "Root-Is-Purelib: false\nTag: %s\n" % tag).encode()
    files[dist_info + "/entry_points.txt"] = ("[console_scripts]\n" + "".join(
        "%s = %s\n" % item for item in project.get("scripts", {}).items())).encode()
    record = [record_line(n, d) for n, d in files.items()] + [dist_info + "/RECORD,,"]
    files[dist_info + "/RECORD"] = ("\n".join(record) + "\n").encode()
    out.mkdir(parents=True, exist_ok=True)
    wheel = out / ("%s-%s-%s.whl" % (name, version, tag))
    tmp = wheel.with_suffix(".part")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        for n, d in files.items():
            info = zipfile.ZipInfo(n, date_time=(1980, 1, 1, 0, 0, 0))   # reproducible
            info.external_attr = 0o644 << 16
            info.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(info, d)
    tmp.replace(wheel)
    print(wheel)


if __name__ == "__main__":
    main()
