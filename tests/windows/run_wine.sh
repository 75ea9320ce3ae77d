#!/usr/bin/env bash
# Runs a program of the Windows cross-build under wine, in that build's own wine prefix.
#   run_wine.sh <windows build dir> <program.exe> [arguments]
# Exit 3 (ctest: skipped) when wine is not installed. The prefix is made once (about 10 s).
set -euo pipefail
win=$(realpath -m "$1")
shift
wine=$(command -v wine || command -v wine64 || true)
if [ -z "$wine" ]; then
  echo "windows: wine is not installed (scripts/install_deps.sh --windows): skipped"
  exit 3
fi
if [ ! -f "$1" ]; then
  echo "windows: $1 was not built (windows_build skipped: no mingw-w64?): skipped"
  exit 3
fi
export WINEPREFIX=$win/wineprefix WINEDEBUG=-all WINEDLLOVERRIDES="mscoree,mshtml="
if [ ! -f "$WINEPREFIX/system.reg" ]; then
  ( flock 9; [ -f "$WINEPREFIX/system.reg" ] || "$wine" wineboot -i >/dev/null 2>&1 ) 9> "$win/wineprefix.lock"
fi
# From the program's folder: it finds the DLLs and files next to it by name.
cd "$(dirname "$1")"
exec "$wine" "$(basename "$1")" "${@:2}"
