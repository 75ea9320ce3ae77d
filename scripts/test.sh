#!/usr/bin/env bash
# Runs every test: C++ core (GoogleTest), the Python package (pytest), the Blender add-on
# (background mode and a real window under Xvfb) and the demo, all through ctest.
# Extra arguments go to ctest (e.g. -R pytest, -L blender). --quick runs only the fast tier
# (ctest -L unit: the C++ unit tests and pytest, no Blender), for everyday work.
# EDGEDEFORM_WINDOWS_TESTS=ON adds the `windows` label (the mingw-w64 cross-build under wine,
# tests/windows; .ci/run sets it after scripts/install_deps.sh --windows).
set -euo pipefail
if [ "${1:-}" = "--quick" ]; then shift; set -- -L unit "$@"; fi
cd "$(dirname "$0")/.."
# Debian's tools first: Debian's Blender finds its Python's home through PATH, so a pyenv or
# conda python3 (or a pip-installed cmake/ctest wrapper that puts one first) breaks every
# Blender 3.4 test with "No module named numpy".
export PATH="/usr/bin:/bin:$PATH"
scripts/install_deps.sh
build_dir=${EDGEDEFORM_BUILD_DIR:-build}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release \
  -DEDGEDEFORM_WINDOWS_TESTS="${EDGEDEFORM_WINDOWS_TESTS:-OFF}"
cmake --build "$build_dir" -j"$(nproc)"
ctest --test-dir "$build_dir" --output-on-failure "$@"
