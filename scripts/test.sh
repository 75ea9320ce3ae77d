#!/usr/bin/env bash
# Runs every test: C++ core (GoogleTest), the Python package (pytest), the Blender add-on
# (background mode and a real window under Xvfb) and the demo, all through ctest.
# Extra arguments go to ctest (e.g. -R pytest, -L blender).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
build_dir=${EDGEDEFORM_BUILD_DIR:-build}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" -j"$(nproc)"
ctest --test-dir "$build_dir" --output-on-failure "$@"
