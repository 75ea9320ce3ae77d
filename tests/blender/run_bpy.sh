#!/usr/bin/env bash
# ctest's entry to bpy_module_suite.py with Blender <series>'s venv:
#   run_bpy.sh <build dir> <series> <bpy_module_suite.py arguments>
# Exit 3 (ctest: skipped) when scripts/bpy_venv.sh could not install that bpy here.
set -euo pipefail
build=$1 series=$2
shift 2
venv=$build/bpy_venvs/bpy-$series
if [ ! -f "$venv/.complete" ]; then
  echo "bpy $series is not installed on this machine (see the test blender_bpy_${series}_venv): skipped"
  exit 3
fi
exec "$venv/bin/python" "$(dirname "$0")/bpy_module_suite.py" "$@"
