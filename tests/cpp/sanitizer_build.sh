#!/usr/bin/env bash
# Builds the core and its C++ tests with AddressSanitizer + UndefinedBehaviorSanitizer (GCC,
# OpenMP on, so the threaded paths are checked too) and runs the tests there. Any report
# aborts the run (-fno-sanitize-recover, halt_on_error), so a green run means none.
set -euo pipefail
source_dir=$1
build_dir=$2
cmake -S "$source_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DEDGEDEFORM_BUILD_PYTHON=OFF \
  -DEDGEDEFORM_SANITIZE=address,undefined > "$build_dir.configure.log"
cmake --build "$build_dir" -j"$(nproc)" --target edgedeform_cpp_tests
export ASAN_OPTIONS=halt_on_error=1:detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
"$build_dir/tests/cpp/edgedeform_cpp_tests" --gtest_brief=1
