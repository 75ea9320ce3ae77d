#!/usr/bin/env bash
# Cross-builds edgedeform for 64-bit Windows with Debian's mingw-w64
# (cmake/toolchains/mingw-w64-x86_64.cmake): the core, the C++ tests, the solve_lift program,
# and the `_core` module for python.org's CPython 3.11 and 3.13, each packed as a wheel.
# Prints the wheels' paths, one a line.
#   scripts/build_windows.sh [build dir, default build/windows] [Python versions, default "3.11 3.13"]
# The solver is CHOLMOD with OpenBLAS's DLL (scripts/windows_provision.py cholmod builds it once
# into the cache from Debian's sources; docs/decisions/0063), or Eigen's with
# EDGEDEFORM_WINDOWS_SOLVER=eigen. The CPython headers are this machine's (Debian's
# python3-dev, or pyenv's), with cmake/windows/pyconfig.h; a version whose headers are missing
# is reported and skipped, no wheel at all is an error. Exit 3 when mingw-w64 is not
# installed (scripts/install_deps.sh --windows installs it), which ctest counts as skipped.
set -euo pipefail
cd "$(dirname "$0")/.."
build=$(realpath -m "${1:-build/windows}")
versions=${2:-3.11 3.13}
export PATH="/usr/bin:/bin:$PATH"   # Debian's tools, as scripts/test.sh

for tool in x86_64-w64-mingw32-g++-posix x86_64-w64-mingw32-dlltool x86_64-w64-mingw32-objdump; do
  if ! command -v "$tool" >/dev/null; then
    echo "build_windows: $tool not found: install mingw-w64 (scripts/install_deps.sh --windows); skipped" >&2
    exit 3
  fi
done
mkdir -p "$build"

# pybind11's headers (>= 2.12, < 3, as cmake/pybind11.cmake) from a host tools venv.
tools=$build/tools_venv
if ! "$tools/bin/python" -c "import pybind11, sys; sys.exit(pybind11.version_info < (2, 12))" 2>/dev/null; then
  rm -rf "$tools"
  /usr/bin/python3 -m venv "$tools"
  "$tools/bin/python" -m pip install --no-cache-dir -q "pybind11>=2.12,<3" >&2
fi
pybind11_include=$("$tools/bin/python" -c "import pybind11; print(pybind11.get_include())")

pythons=()
for version in $versions; do
  tag=cp${version/./}
  if ! include=$(bash scripts/python_headers.sh "$version" 2>"$build/headers.log"); then
    echo "build_windows: $(cat "$build/headers.log"): no $tag wheel" >&2
    continue
  fi
  pythons+=("$tag=$include")
done
if [ ${#pythons[@]} -eq 0 ]; then
  echo "build_windows: no headers for any of Python $versions: no wheel" >&2
  exit 1
fi
python_list=$(IFS=';'; echo "${pythons[*]}")

if [ "${EDGEDEFORM_WINDOWS_SOLVER:-cholmod}" = eigen ]; then
  solver=(-DEDGEDEFORM_USE_CHOLMOD=OFF)
  rm -f "$build"/python-cp*/edgedeform/edgedeform_openblas.dll   # a CHOLMOD build's, if any
else
  cholmod=$(/usr/bin/python3 scripts/windows_provision.py cholmod)
  solver=(-DEDGEDEFORM_USE_CHOLMOD=ON -DCHOLMOD_INCLUDE_DIR="$cholmod/include"
          -DCHOLMOD_LIBRARY="$cholmod/lib/libcholmod.a"
          -DEDGEDEFORM_CHOLMOD_BLAS="$cholmod/lib/libedgedeform_openblas.dll.a"
          -DEDGEDEFORM_BLAS_DLL="$cholmod/bin/edgedeform_openblas.dll")
fi

cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_TOOLCHAIN_FILE="$PWD/cmake/toolchains/mingw-w64-x86_64.cmake" \
  -DEigen3_DIR=/usr/share/eigen3/cmake \
  "${solver[@]}" -DEDGEDEFORM_BUILD_PYTHON=OFF \
  -DEDGEDEFORM_WINDOWS_PYTHON="$python_list" -DEDGEDEFORM_PYBIND11_INCLUDE="$pybind11_include" \
  > "$build/configure.log" || { cat "$build/configure.log" >&2; exit 1; }
cmake --build "$build" -j"$(nproc)" >&2

rm -f "$build"/wheels/edgedeform-*.whl
for pair in "${pythons[@]}"; do
  tag=${pair%%=*}
  wheel=$(/usr/bin/python3 scripts/pack_wheel.py "$build/python-$tag/edgedeform" \
          "$tag-$tag-win_amd64" "$build/wheels")
  echo "build_windows: $wheel" >&2
  echo "$wheel"
done
