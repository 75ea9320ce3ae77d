#!/usr/bin/env bash
# The main command's install step (scripts/demo.sh step 3), also run alone by ctest
# (blender_install_addon) into throwaway user folders:
#   scripts/install_addon.sh [build dir]
# Copies the add-on with its edgedeform module into Blender's user add-on folder
# ($BLENDER_USER_SCRIPTS/addons when set), enables it and saves the user preferences.
# Fails, with the reason, when it cannot: never leaves the user with an add-on that is not
# there (the demo used to fall back to the source tree silently).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cmake --build "$build" --target install_addon
