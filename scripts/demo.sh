#!/usr/bin/env bash
# The main command: from a fresh Debian machine to the demo's sheets, tables and results.
#   scripts/demo.sh [--ci] [any run_demo.py option, e.g. --samples dino --out DIR]
# Installs missing packages, builds (Release), installs the Blender add-on, makes the sample
# .blend scenes, runs the demo on them and prints where the outputs are.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
build=${EDGEDEFORM_BUILD_DIR:-$repo/build}
jobs=${EDGEDEFORM_JOBS:-2}

step() { printf '\n== %s\n' "$*"; }

step "1/5 packages"
bash scripts/install_deps.sh

step "2/5 build ($build)"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" -j"$jobs"

step "3/5 Blender add-on (installed and enabled in your Blender)"
# No `--target help | grep -q` test here: under pipefail grep's early exit broke the pipe,
# the test failed and the demo silently skipped the install.
bash scripts/install_addon.sh "$build"

step "4/5 sample scenes (blend_samples/*.blend)"
# Blender prints harmless EGL warnings without a display: keep the log readable. Old scenes
# go first, so that the check below sees this run's files, not a previous run's.
# --python-use-system-env: Blender 4.x runs its Python isolated and ignores PYTHONPATH (3.4
# reads it anyway); with it, the edgedeform module reaches make_samples.py on both.
rm -f blend_samples/*.blend blend_samples/*.blend1
PYTHONPATH="$build/python${PYTHONPATH:+:$PYTHONPATH}" \
blender -b --factory-startup --python-use-system-env --python-exit-code 1 \
  --python blend_samples/make_samples.py -- --out blend_samples 2>&1 | grep -v '^EGL Error' \
  | grep -E 'make_samples|Error|Traceback' || true
test -f blend_samples/bar.blend

step "5/5 demo"
PYTHONPATH="$build/python${PYTHONPATH:+:$PYTHONPATH}" \
blender -b --factory-startup --python-use-system-env --python-exit-code 1 \
  --python demo/run_demo.py -- --module-path "$build/python" --samples-dir blend_samples "$@" \
  2>&1 | grep -v -E '^(EGL Error|Fra:|Saved:| *Time:|Info: )|^ *$'
