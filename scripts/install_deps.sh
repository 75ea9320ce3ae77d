#!/usr/bin/env bash
# Installs the Debian packages edgedeform builds, tests and demos with, on Debian 12
# (bookworm) and 13 (trixie): every name below exists on both.
# Skips apt entirely when everything is already there (fast on a developer machine).
#   scripts/install_deps.sh           install what is missing
#   scripts/install_deps.sh --windows also the Windows cross-build's tools (mingw-w64, wine:
#                                     the `windows` tests, tests/windows; .ci/run)
#   scripts/install_deps.sh --list    print the package names, one a line
#   scripts/install_deps.sh --check   fail, naming them, if apt has no candidate for some,
#                                     the Windows ones included (tests/packaging: install_deps_names)
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libeigen3-dev libsuitesparse-dev libopenblas-dev python3-dev python3-venv
  python3-numpy python3-scipy python3-pytest
  libgtest-dev googletest
  # libegl1: Blender 4.x aborts at start (even with -b) without libEGL.so.1.
  # x11-apps (xwd): the window tests' screenshots where Blender's own come out black (4.3).
  blender libegl1 xvfb xauth x11-apps
  # libclang-rt-dev: the sanitizer/fuzzer runtimes of Debian's default clang (14 on 12,
  # 19 on 13), not a fixed version that exists on one release only.
  clang libclang-rt-dev
  unzip
)
# The Windows cross-build (scripts/build_windows.sh): gcc's POSIX-thread variant (OpenMP),
# with binutils and the mingw-w64 runtime; wine64 runs its programs and Windows' CPython and
# Blender; osslsigncode and openssl check python.org's Authenticode signatures
# (scripts/windows_provision.py).
windows_packages=(g++-mingw-w64-x86-64-posix wine wine64 osslsigncode openssl)
# pybind11 is not here: the build takes >= 2.12 from the package index (cmake/pybind11.cmake);
# Debian 12's pybind11-dev 2.10 breaks the module under NumPy 2.

# Names apt cannot install here (no candidate version), one a line.
unknown_packages() {
  for p in "$@"; do
    # The output in a variable first: `| grep -q` under pipefail fails when grep exits early.
    policy=$(LC_ALL=C apt-cache policy "$p" 2>/dev/null || true)
    [[ "$policy" == *$'\n  Candidate: '[^\(]* ]] || echo "$p"
  done
}

release() { . /etc/os-release && echo "${PRETTY_NAME:-unknown}"; }

case "${1:-}" in
  --list)
    printf '%s\n' "${packages[@]}"
    exit 0 ;;
  --windows)
    packages+=("${windows_packages[@]}") ;;
  --check)
    packages+=("${windows_packages[@]}")
    bad=$(unknown_packages "${packages[@]}")
    if [ -n "$bad" ]; then
      echo "install_deps: no such package on $(release) (apt-cache policy: no candidate):" $bad >&2
      exit 1
    fi
    echo "install_deps: all ${#packages[@]} package names have an install candidate on $(release)"
    exit 0 ;;
  "") ;;
  *) echo "usage: install_deps.sh [--windows | --list | --check]" >&2; exit 2 ;;
esac

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
# Fail before apt does, with the names: apt's own message stops at the first one.
bad=$(unknown_packages "${missing[@]}")
if [ -n "$bad" ]; then
  echo "install_deps: no such package on $(release):" $bad >&2
  exit 1
fi
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}"
