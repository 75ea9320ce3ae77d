#!/usr/bin/env bash
# Installs the Debian packages edgedeform builds, tests and demos with.
# Skips apt entirely when everything is already there (fast on a developer machine).
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libeigen3-dev libsuitesparse-dev libopenblas-dev pybind11-dev python3-dev python3-venv
  python3-numpy python3-scipy python3-pytest
  libgtest-dev googletest
  blender xvfb xauth
  clang libclang-rt-14-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install_deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}"
