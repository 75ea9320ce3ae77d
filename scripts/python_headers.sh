#!/usr/bin/env bash
# Prints the include folder (with Python.h) of a CPython <major.minor> on this machine, or
# says on stderr why there is none and exits 3. The Windows cross-build compiles each wheel's
# module against these headers (scripts/build_windows.sh), and its check asks for a wheel
# only where they are (tests/windows/check_windows_wheels.py).
#   scripts/python_headers.sh 3.11
set -euo pipefail
version=$1
if ! py=$(bash "$(dirname "$0")/find_python.sh" "$version" 2>/dev/null); then
  echo "no Python $version here for its headers" >&2
  exit 3
fi
include=$("$py" -c "import sysconfig; print(sysconfig.get_paths()['include'])")
if [ ! -f "$include/Python.h" ]; then
  echo "$py has no headers ($include/Python.h; apt-get install python$version-dev)" >&2
  exit 3
fi
echo "$include"
