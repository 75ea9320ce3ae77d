#!/usr/bin/env bash
# Prints the path of a CPython <major.minor> interpreter on this machine, or exits 3 when
# there is none. The Blender series need their own Python: 4.2–5.0 embed 3.11, 5.1–5.3 embed
# 3.13 (their wheels and bpy modules are built for exactly that version).
#   scripts/find_python.sh 3.13
# Looks at Debian's /usr/bin/python3.X first, then pyenv's versions, then PATH. An
# interpreter counts only if it can make a venv (Debian: python3-venv).
set -euo pipefail
want=$1
candidates=("/usr/bin/python$want")
pyenv_root=${PYENV_ROOT:-$HOME/.pyenv}
for d in "$pyenv_root"/versions/"$want".*; do
  [ -x "$d/bin/python$want" ] && candidates+=("$d/bin/python$want")
done
command -v "python$want" >/dev/null 2>&1 && candidates+=("$(command -v "python$want")")
for py in "${candidates[@]}"; do
  if [ -x "$py" ] &&
     [ "$("$py" -c 'import sys; print("%d.%d" % sys.version_info[:2])' 2>/dev/null)" = "$want" ] &&
     "$py" -c 'import venv, ensurepip' 2>/dev/null; then
    echo "$py"
    exit 0
  fi
done
echo "find_python: no Python $want here (looked at ${candidates[*]})" >&2
exit 3
