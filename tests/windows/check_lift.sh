#!/usr/bin/env bash
# A benchmark edit solved by the Windows build under wine (OMP_NUM_THREADS=2 and 1) and by
# this Linux build: Windows's positions within 1e-9 of the diagonal of Linux's, and the
# same bits on 1 and 2 threads.
#   check_lift.sh <windows build dir> <Linux solve_lift> <python> MESH EDIT LAMBDA ITERATIONS
set -euo pipefail
win=$1 linux_solve=$2 python=$3 mesh=$4 edit=$5 lambda=$6 iterations=$7
here=$(cd "$(dirname "$0")" && pwd)
work=$win/tests/windows/lift
rm -rf "$work"
mkdir -p "$work"
"$python" "$here/make_lift_input.py" "$mesh" "$edit" "$lambda" "$work/input.txt"
"$linux_solve" "$work/input.txt" "$work/linux.txt" "$iterations"
# solve_lift.exe runs from its own folder: give it its files there.
exe_dir=$win/tests/windows
cp "$work/input.txt" "$exe_dir/lift_input.txt"
for threads in 2 1; do
  OMP_NUM_THREADS=$threads bash "$here/run_wine.sh" "$win" "$exe_dir/solve_lift.exe" \
    lift_input.txt "lift_windows_$threads.txt" "$iterations"
  mv "$exe_dir/lift_windows_$threads.txt" "$work/windows-$threads.txt"
done
"$python" "$here/compare_positions.py" 1e-9 "$work/input.txt" "$work/linux.txt" "$work/windows-2.txt"
"$python" "$here/compare_positions.py" 0 "$work/input.txt" "$work/windows-2.txt" "$work/windows-1.txt"
