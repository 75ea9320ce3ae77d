#!/usr/bin/env bash
# Makes (once) a virtual environment with Blender as a Python module (`pip install bpy`) for
# one Blender series, cached under the build folder so later runs do not download again.
#   scripts/bpy_venv.sh <build dir> <series, e.g. 4.5>
# Prints the venv's python on the last line of stdout. Exit 3 when this series cannot be
# installed here (no wheel for this Python/platform, no index reachable): callers skip it.
set -euo pipefail
build=$(realpath -m "$1")
series=$2
venv=$build/bpy_venvs/bpy-$series
major=${series%%.*}
minor=${series#*.}
# Each bpy is built for the Python its Blender embeds: 4.2–5.0 are cp311, 5.1 and later cp313.
if [ "$major" -lt 5 ] || { [ "$major" -eq 5 ] && [ "$minor" -lt 1 ]; }; then
  python_version=3.11
else
  python_version=3.13
fi
if ! py=$(bash "$(dirname "$0")/find_python.sh" "$python_version"); then
  echo "bpy_venv: Blender $series needs Python $python_version, which this machine lacks; skipping" >&2
  exit 3
fi
spec="bpy>=$series.0,<$major.$((minor + 1))"

ok() { "$venv/bin/python" -c "import bpy, sys; v = bpy.app.version; sys.exit(0 if '%d.%d' % v[:2] == '$series' else 1)" 2>/dev/null; }

if [ -x "$venv/bin/python" ] && [ -f "$venv/.complete" ] && ok; then
  echo "bpy_venv: cached $venv ($(cat "$venv/.complete"))" >&2
  echo "$venv/bin/python"
  exit 0
fi
rm -rf "$venv"
mkdir -p "$build/bpy_venvs"
if ! "$py" -m venv "$venv" >&2; then
  echo "bpy_venv: could not make a venv with $py (apt-get install python3-venv)" >&2
  exit 3
fi
# --no-cache-dir: the venv is the cache; pip's own cache would hold a second ~400 MB copy.
if ! "$venv/bin/python" -m pip install --no-cache-dir -q "$spec" >&2; then
  echo "bpy_venv: '$spec' cannot be installed on this machine (Python $("$py" -c 'import platform; print(platform.python_version())'), $(uname -m)); skipping Blender $series" >&2
  rm -rf "$venv"
  exit 3
fi
if ! ok; then
  echo "bpy_venv: '$spec' installed but 'import bpy' fails or reports another version" >&2
  "$venv/bin/python" -c "import bpy; print(bpy.app.version_string)" >&2 || true
  rm -rf "$venv"
  exit 3
fi
"$venv/bin/python" -c "import bpy; print(bpy.app.version_string)" > "$venv/.complete"
echo "bpy_venv: made $venv ($(cat "$venv/.complete"))" >&2
echo "$venv/bin/python"
