#!/usr/bin/env bash
# Installs what bench/bench_peers.py compares against. Benchmark-only: the project builds
# and tests without any of it.
#   - libcgal-dev (Debian, CGAL 5.5 headers): CGAL's Surface_mesh_deformation, built by
#     bench/cgal/ (or -DEDGEDEFORM_BUILD_PEER_BENCH=ON)
#   - python3-matplotlib (Debian): the plot
#   - a venv under build/ with the libigl Python bindings from PyPI (igl.ARAP)
# Blender (the Laplacian Deform peer) comes from scripts/install_deps.sh.
#
#   bench/setup_peers.sh [BUILD_DIR]      # default: build
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
BUILD="${1:-$ROOT/build}"
packages=(libcgal-dev python3-matplotlib python3-venv)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup_peers: installing ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
fi
# The CGAL program (header-only CGAL: a minute or two of compiling)
cmake -S "$ROOT/bench/cgal" -B "$BUILD/cgal-peer" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD/cgal-peer" -j"$(nproc)"
echo "setup_peers: $BUILD/cgal-peer/cgal_arap_bench"
VENV="$BUILD/peers-venv"
if [ ! -x "$VENV/bin/python" ]; then
  /usr/bin/python3 -m venv "$VENV"
fi
"$VENV/bin/python" -m pip install -q --disable-pip-version-check libigl numpy
"$VENV/bin/python" -c "from importlib.metadata import version; print('setup_peers: libigl', version('libigl'), 'in $VENV')"
