#!/usr/bin/env bash
# Builds the core without CHOLMOD (Eigen SimplicialLDLT fallback) and runs the C++ tests
# there, so the fallback keeps compiling and giving the same results.
set -euo pipefail
source_dir=$1
build_dir=$2
cmake -S "$source_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DEDGEDEFORM_USE_CHOLMOD=OFF > "$build_dir.configure.log"
grep -q "sparse solver = eigen-simplicial-ldlt" "$build_dir.configure.log"
cmake --build "$build_dir" -j"$(nproc)" --target edgedeform_cpp_tests
"$build_dir/tests/cpp/edgedeform_cpp_tests" --gtest_brief=1
