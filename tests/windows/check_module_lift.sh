#!/usr/bin/env bash
# The koala lift through the Python module: Linux's (this build's package) writes the
# reference, then the installed win_amd64 wheels in Windows' CPython 3.11 and 3.13, on 2 and 1
# threads (scripts/windows_check.py lift): within 1e-9 of the diagonal of Linux's, and all
# four Windows runs bit-identical.
#   check_module_lift.sh <windows build dir> <python> <work dir> MESH EDIT LAMBDA ITERATIONS
set -euo pipefail
win=$1 python=$2 work=$3 mesh=$4 edit=$5 lambda=$6 iterations=$7
here=$(cd "$(dirname "$0")" && pwd)
if ! ls "$win"/wheels/edgedeform-*-win_amd64.whl >/dev/null 2>&1; then
  echo "windows: no Windows wheel (windows_build skipped): skipped"
  exit 3
fi
rm -rf "$work"
mkdir -p "$work"
"$python" "$here/make_lift_input.py" "$mesh" "$edit" "$lambda" "$work/input.txt"
"$python" "$here/solve_lift.py" "$work/input.txt" "$work/linux.txt" "$iterations"
exec "$python" "$here/../../scripts/windows_check.py" lift "$win/wheels" "$work/input.txt" \
  "$work/linux.txt" --iterations "$iterations" --work "$work/windows"
