#!/usr/bin/env bash
# Runs the tests through ctest: the C++ core (GoogleTest), the Python package (pytest), the
# Blender add-on (background mode and a real window under Xvfb) and the demo.
#
#   scripts/test.sh               everything, as CI's .ci/run: installs the Debian packages,
#                                 configures, builds, runs every test but the `timing` label,
#                                 then the timing label alone (wall-clock bounds, measured
#                                 with nothing else of ours running)
#   scripts/test.sh --quick [A]   the fast tier (ctest -L unit: C++ unit tests, pytest, the
#                                 add-on's bpy-free tests, the docs checks; no Blender): no
#                                 install_deps, builds only what it needs (target unit_tier)
#   scripts/test.sh A...          everything built, then ctest with the arguments A only
#                                 (e.g. -R pytest, -L blender)
# EDGEDEFORM_WINDOWS_TESTS=ON adds the `windows` label (the mingw-w64 cross-build under wine,
# tests/windows; .ci/run sets it after scripts/install_deps.sh --windows);
# EDGEDEFORM_MACOS_TESTS=ON the `macos` label (the macOS link check, tests/macos).
#
# Each run writes its phases' times and ctest's per-test times (JUnit) to
# $build_dir/ci_times/; scripts/ci_times.py record turns them into a docs/ci_runs/ record
# for the generated page docs/ci_times.md.
set -euo pipefail
cd "$(dirname "$0")/.."
# Debian's tools first: Debian's Blender finds its Python's home through PATH, so a pyenv or
# conda python3 (or a pip-installed cmake/ctest wrapper that puts one first) breaks every
# Blender 3.4 test with "No module named numpy".
export PATH="/usr/bin:/bin:$PATH"
build_dir=${EDGEDEFORM_BUILD_DIR:-build}
jobs=$(nproc)

kind=full
[ "${1:-}" = "--quick" ] && { kind=quick; shift; }
[ "$kind" = full ] && [ $# -gt 0 ] && kind=custom

times="$build_dir/ci_times"
mkdir -p "$times"
times=$(cd "$times" && pwd)
log="$times/$kind.txt"
now() { date +%s%N; }
{
  echo "kind $kind"
  echo "started $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
  echo "load_start $(cut -d' ' -f1 /proc/loadavg)"
} > "$log"
run_start=$(now)
# phase NAME COMMAND...: runs it and appends its wall time; the run stops on a failure.
phase() {
  local name=$1 t0 rc=0
  shift
  t0=$(now)
  "$@" || rc=$?
  echo "phase $name $(( ($(now) - t0) / 1000000 ))" >> "$log"
  return $rc
}
finish() {
  local rc=$?
  echo "load_end $(cut -d' ' -f1 /proc/loadavg)" >> "$log"
  echo "total $(( ($(now) - run_start) / 1000000 ))" >> "$log"
  echo "exit $rc" >> "$log"
}
trap finish EXIT

if [ "$kind" = quick ]; then
  # The CMake that made the build folder, if any: another CMake (a pip-installed one first
  # on PATH) writes the flags in another order, and every object would be rebuilt.
  cmake=cmake ctest=ctest
  if [ -f "$build_dir/CMakeCache.txt" ]; then
    cmake=$(sed -n 's/^CMAKE_COMMAND:INTERNAL=//p' "$build_dir/CMakeCache.txt")
    ctest=$(sed -n 's/^CMAKE_CTEST_COMMAND:INTERNAL=//p' "$build_dir/CMakeCache.txt")
  fi
  phase configure "$cmake" -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release
  phase build "$cmake" --build "$build_dir" -j"$jobs" --target unit_tier
  phase ctest_unit "$ctest" --test-dir "$build_dir" -L unit -j"$jobs" --output-on-failure \
    --output-junit "$times/quick_ctest.xml" "$@"
  exit 0
fi

phase install_deps scripts/install_deps.sh
phase configure cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release \
  -DEDGEDEFORM_WINDOWS_TESTS="${EDGEDEFORM_WINDOWS_TESTS:-OFF}" \
  -DEDGEDEFORM_MACOS_TESTS="${EDGEDEFORM_MACOS_TESTS:-OFF}"
phase build cmake --build "$build_dir" -j"$jobs"
if [ "$kind" = custom ]; then
  phase ctest ctest --test-dir "$build_dir" --output-on-failure "$@"
  exit 0
fi
status=0
phase ctest ctest --test-dir "$build_dir" --output-on-failure -LE timing \
  --output-junit "$times/ctest.xml" || status=$?
phase ctest_timing ctest --test-dir "$build_dir" --output-on-failure -L timing \
  --output-junit "$times/ctest_timing.xml" || status=$?
exit $status
