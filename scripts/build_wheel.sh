#!/usr/bin/env bash
# Builds the edgedeform wheel for Debian's python3 (cp311 on this platform) with
# scikit-build-core, the way `pip install .` does, into <build>/wheels, and prints its path.
#   scripts/build_wheel.sh [build dir, default build]
# The packaging tools live in a venv under the build folder and the CMake build of the wheel
# in <build>/wheel_build, so a second run neither downloads nor recompiles what is unchanged.
set -euo pipefail
cd "$(dirname "$0")/.."
build=$(realpath -m "${1:-build}")
venv=$build/wheel_venv
if ! "$venv/bin/python" -c "import scikit_build_core" 2>/dev/null; then
  rm -rf "$venv"
  /usr/bin/python3 -m venv "$venv"
  "$venv/bin/python" -m pip install --no-cache-dir -q "scikit-build-core>=0.10" >&2
fi
rm -rf "$build/wheels"
# --no-build-isolation: use the venv's scikit-build-core (no download per build);
# --no-deps: the wheel only (numpy and meshio are the installer's business).
"$venv/bin/python" -m pip wheel . --no-build-isolation --no-deps -q -w "$build/wheels" \
  --config-settings=build-dir="$build/wheel_build" >&2
wheel=$(ls "$build"/wheels/edgedeform-*.whl)
echo "build_wheel: $wheel" >&2
echo "$wheel"
