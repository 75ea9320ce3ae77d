#!/usr/bin/env bash
# Builds the fuzz target with Debian's clang (libFuzzer, ASan + UBSan) in a build folder of its
# own and fuzzes the core for a bounded time, starting from the committed seed corpus.
# Usage: run_fuzz.sh SOURCE_DIR BUILD_DIR SECONDS
# A crash, a sanitizer report or a broken contract stops the run with the input saved as
# BUILD_DIR/crash-* (reproduce: BUILD_DIR/tests/fuzz/edgedeform_fuzz_core BUILD_DIR/crash-...).
set -euo pipefail
source_dir=$1
build_dir=$2
seconds=${3:-60}
command -v clang++ > /dev/null || { echo "run_fuzz: clang++ not found (scripts/install_deps.sh installs it)"; exit 1; }
CC=clang CXX=clang++ cmake -S "$source_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DEDGEDEFORM_BUILD_PYTHON=OFF -DEDGEDEFORM_FUZZ=ON -DEDGEDEFORM_SANITIZE=address,undefined \
  > "$build_dir.configure.log"
cmake --build "$build_dir" -j"$(nproc)" --target edgedeform_fuzz_core
# New inputs go to a working copy; the committed seeds stay as they are.
corpus="$build_dir/corpus"
mkdir -p "$corpus"
export ASAN_OPTIONS=halt_on_error=1:detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
cd "$build_dir"
"$build_dir/tests/fuzz/edgedeform_fuzz_core" -max_total_time="$seconds" -max_len=4096 -timeout=20 -rss_limit_mb=2048 \
  -print_final_stats=1 "$corpus" "$source_dir/tests/fuzz/corpus"
