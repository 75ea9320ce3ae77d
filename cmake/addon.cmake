# Blender add-on packaging, included by the root CMakeLists.txt.
#
#   install_addon    copy the add-on and the built `edgedeform` package into Blender's user
#                    add-on folder ($BLENDER_USER_SCRIPTS/addons when set, else the folder
#                    Blender reports), enable the add-on and save the user preferences
#   addon_zip        build/edge_deform-<ver>-<platform>-cp<py>.zip: Preferences > Add-ons >
#                    Install (3.4+)
#   wheel            build/wheels/edgedeform-<ver>-cp<py>-<platform>.whl (scripts/build_wheel.sh:
#                    scikit-build-core, as `pip install .`; its first run downloads the tool)
#   addon_extension  build/edge_deform-<ver>-extension-linux-x64.zip: Blender 4.2+ extension,
#                    the add-on plus the Linux wheels, listed in blender_manifest.toml (not in
#                    ALL: the ctest fixture blender_extension_build makes it)
#   addon_extension_windows
#                    build/edge_deform-<ver>-extension-windows-x64.zip, the same with the
#                    win_amd64 wheels of scripts/build_windows.sh (build/windows/wheels)
# One zip per platform, each listing only its own wheels and naming only its platform, as
# `blender --command extension build --split-platforms` makes them (that command needs a
# Blender 4.2+, which Debian's 3.4 is not; each zip passes `extension validate`).
#
# The same file runs in script mode (cmake -P) to do the copying at build time, so the
# targets see the environment (BLENDER_USER_SCRIPTS) of the build command, not of configure.

# ------------------------------------------------------------------ script mode
if(CMAKE_SCRIPT_MODE_FILE)
  function(ed_stage dest flat)
    # flat: the extension layout (add-on files at the root of `dest`, the edgedeform wheel in
    # wheels/); else the legacy layout dest/edge_deform with the package folder copied in.
    if(flat)
      set(root ${dest})
    else()
      set(root ${dest}/edge_deform)
    endif()
    file(REMOVE_RECURSE ${root})
    file(MAKE_DIRECTORY ${root})
    file(GLOB items ${ED_ADDON_SRC}/*)
    file(COPY ${items} DESTINATION ${root} PATTERN __pycache__ EXCLUDE PATTERN *.pyc EXCLUDE)
    # The manual, docs/addon.md with its pictures: bl_info's "doc_url" opens this copy.
    get_filename_component(docs ${ED_ADDON_SRC}/../../docs ABSOLUTE)
    file(GLOB pictures ${docs}/img/addon_*.png)
    file(COPY ${docs}/addon.md DESTINATION ${root}/docs)
    file(COPY ${pictures} DESTINATION ${root}/docs/img)
    if(flat)
      ed_stage_wheel(${root})
    else()
      file(COPY ${ED_PKG_DIR} DESTINATION ${root} PATTERN __pycache__ EXCLUDE
           PATTERN *.pyc EXCLUDE)
      file(REMOVE ${root}/blender_manifest.toml)   # 3.x installs read bl_info only
    endif()
  endfunction()

  function(ed_stage_wheel root)
    # The manifest lists the wheels of one platform (ED_EXT_PLATFORM) built here, one per
    # Blender Python (scripts/build_wheel.sh, scripts/build_windows.sh), generated: Blender
    # installs the one matching its Python. Its `platforms` names that platform only.
    set(linux-x64 "-linux_x86_64\\.whl$|-manylinux[^-]*_x86_64\\.whl$")
    set(windows-x64 "-win_amd64\\.whl$")
    set(macos-x64 "-macosx_[0-9_]+_(x86_64|universal2)\\.whl$")
    set(macos-arm64 "-macosx_[0-9_]+_(arm64|universal2)\\.whl$")
    if(NOT DEFINED ${ED_EXT_PLATFORM})
      message(FATAL_ERROR "No extension platform '${ED_EXT_PLATFORM}' (linux-x64, windows-x64, macos-x64, macos-arm64)")
    endif()
    file(GLOB all_wheels ${ED_WHEEL_DIR}/edgedeform-*.whl)
    set(wheels "")
    foreach(wheel ${all_wheels})
      if(wheel MATCHES "${${ED_EXT_PLATFORM}}")
        list(APPEND wheels ${wheel})
      endif()
    endforeach()
    if(NOT wheels)
      message(FATAL_ERROR "No ${ED_EXT_PLATFORM} wheel in ${ED_WHEEL_DIR}: run "
        "scripts/build_wheel.sh (Linux) or scripts/build_windows.sh (Windows)")
    endif()
    list(SORT wheels)
    set(entries "")
    foreach(wheel ${wheels})
      get_filename_component(name ${wheel} NAME)
      string(APPEND entries "  \"./wheels/${name}\",\n")
    endforeach()
    file(READ ${root}/blender_manifest.toml manifest)
    if(manifest MATCHES "\nwheels *=")
      message(FATAL_ERROR "addon/edge_deform/blender_manifest.toml must not list wheels: "
        "the extension build writes them")
    endif()
    string(REGEX REPLACE "\nplatforms = [^\n]*\n"
           "\nplatforms = [\"${ED_EXT_PLATFORM}\"]\nwheels = [\n${entries}]\n"
           generated "${manifest}")
    if(generated STREQUAL manifest)
      message(FATAL_ERROR "blender_manifest.toml has no `platforms = ...` line to put the wheels after")
    endif()
    file(WRITE ${root}/blender_manifest.toml "${generated}")
    file(COPY ${wheels} DESTINATION ${root}/wheels)
  endfunction()

  function(ed_blender_query expr var)
    execute_process(COMMAND ${ED_BLENDER} -b --factory-startup --python-expr "${expr}"
                    OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc TIMEOUT 300)
    if(NOT out MATCHES "EDGEDEFORM_ANSWER=([^\n]*)")
      message(FATAL_ERROR "Could not ask Blender (${ED_BLENDER}), exit ${rc}:\n${out}\n${err}")
    endif()
    set(${var} "${CMAKE_MATCH_1}" PARENT_SCOPE)
  endfunction()

  # A Blender that uses the system's Python (Debian's) finds that Python's home through
  # PATH: with pyenv or conda first on PATH it loads their standard library and cannot
  # import numpy. Put the folder of the Python the module was built for first.
  if(ED_PYTHON_DIR)
    set(ENV{PATH} "${ED_PYTHON_DIR}:$ENV{PATH}")
  endif()

  if(ED_ACTION STREQUAL "stage")
    ed_stage(${ED_DEST} ${ED_FLAT})
  elseif(ED_ACTION STREQUAL "install")
    ed_blender_query("import sys; print('EDGEDEFORM_ANSWER=%d.%d' % sys.version_info[:2])"
                     blender_py)
    if(NOT blender_py STREQUAL ED_MODULE_PY)
      message(FATAL_ERROR
        "Blender (${ED_BLENDER}) embeds Python ${blender_py}, but edgedeform was built for "
        "Python ${ED_MODULE_PY}. Reconfigure with -DPython_EXECUTABLE=<a Python "
        "${blender_py} interpreter> so that the module matches Blender.")
    endif()
    if(NOT "$ENV{BLENDER_USER_SCRIPTS}" STREQUAL "")
      set(addons "$ENV{BLENDER_USER_SCRIPTS}/addons")
    else()
      ed_blender_query(
        "import bpy; print('EDGEDEFORM_ANSWER=' + bpy.utils.user_resource('SCRIPTS', path='addons'))"
        addons)
    endif()
    ed_stage(${addons} FALSE)
    message(STATUS "Edge Deform installed in ${addons}/edge_deform")
    # Enable with the user's own preferences loaded (no --factory-startup), then save them.
    execute_process(
      COMMAND ${ED_BLENDER} -b --python-exit-code 1 --python-expr
        "import addon_utils, bpy, sys
mod = addon_utils.enable('edge_deform', default_set=True, handle_error=None)
from edge_deform import compat
compat.native_package()   # the bundled module must load in this Blender
assert hasattr(bpy.types.Object, 'edge_deform')
bpy.ops.wm.save_userpref()
print('EDGEDEFORM_ENABLED', mod.__file__, compat.native_package().__file__)"
      RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
    if(NOT rc EQUAL 0 OR NOT out MATCHES "EDGEDEFORM_ENABLED")
      message(FATAL_ERROR "Installed, but enabling the add-on failed:\n${out}\n${err}")
    endif()
    message(STATUS "Edge Deform enabled and user preferences saved; open Blender: "
                   "3D Viewport > Sidebar (N) > Edge Deform")
  else()
    message(FATAL_ERROR "addon.cmake: unknown ED_ACTION '${ED_ACTION}'")
  endif()
  return()
endif()

# ------------------------------------------------------------------ configure
set(ED_ADDON_SRC ${CMAKE_SOURCE_DIR}/addon/edge_deform)
set(ED_PKG_DIR ${CMAKE_BINARY_DIR}/python/edgedeform)
set(ED_VERSION ${PROJECT_VERSION})

execute_process(COMMAND ${Python_EXECUTABLE} -c
                  "import sys; print('%d.%d' % sys.version_info[:2])"
                OUTPUT_VARIABLE ED_MODULE_PY OUTPUT_STRIP_TRAILING_WHITESPACE)
string(REPLACE "." "" ED_PY_TAG "cp${ED_MODULE_PY}")
string(TOLOWER "${CMAKE_SYSTEM_NAME}-${CMAKE_SYSTEM_PROCESSOR}" ED_PLATFORM)

get_filename_component(_ed_python_dir ${Python_EXECUTABLE} DIRECTORY)
find_program(BLENDER_EXECUTABLE blender)
if(BLENDER_EXECUTABLE AND NOT EDGEDEFORM_BLENDER_PYTHON)
  execute_process(
    COMMAND ${BLENDER_EXECUTABLE} -b --factory-startup --python-expr
      "import sys, bpy; print('EDGEDEFORM_ANSWER=%d.%d %s' % (sys.version_info[:2] + (bpy.app.version_string,)))"
    OUTPUT_VARIABLE _ed_out ERROR_QUIET TIMEOUT 300)
  if(_ed_out MATCHES "EDGEDEFORM_ANSWER=([0-9]+\\.[0-9]+) ([^\n]*)")
    set(EDGEDEFORM_BLENDER_PYTHON ${CMAKE_MATCH_1} CACHE STRING "Python version Blender embeds")
    set(EDGEDEFORM_BLENDER_VERSION ${CMAKE_MATCH_2} CACHE STRING "Blender version")
  endif()
endif()

if(NOT BLENDER_EXECUTABLE)
  message(STATUS "edgedeform: Blender not found; install_addon will fail (set BLENDER_EXECUTABLE)")
  set(_ed_install_error "Blender was not found: configure with -DBLENDER_EXECUTABLE=/path/to/blender")
elseif(NOT EDGEDEFORM_BLENDER_PYTHON STREQUAL ED_MODULE_PY)
  set(_ed_install_error
    "Blender ${EDGEDEFORM_BLENDER_VERSION} embeds Python ${EDGEDEFORM_BLENDER_PYTHON} but the module is built for Python ${ED_MODULE_PY} (${Python_EXECUTABLE}): reconfigure with -DPython_EXECUTABLE=<Python ${EDGEDEFORM_BLENDER_PYTHON}>")
  message(WARNING "edgedeform: ${_ed_install_error}")
else()
  message(STATUS "edgedeform: Blender ${EDGEDEFORM_BLENDER_VERSION} (${BLENDER_EXECUTABLE}) embeds Python ${EDGEDEFORM_BLENDER_PYTHON}, as the module: OK")
endif()

if(_ed_install_error)
  add_custom_target(install_addon
    COMMAND ${CMAKE_COMMAND} -E echo "install_addon: ${_ed_install_error}"
    COMMAND ${CMAKE_COMMAND} -E false)
else()
  add_custom_target(install_addon
    COMMAND ${CMAKE_COMMAND} -DED_ACTION=install -DED_ADDON_SRC=${ED_ADDON_SRC}
            -DED_PKG_DIR=${ED_PKG_DIR} -DED_BLENDER=${BLENDER_EXECUTABLE}
            -DED_MODULE_PY=${ED_MODULE_PY} -DED_PYTHON_DIR=${_ed_python_dir}
            -P ${CMAKE_CURRENT_LIST_FILE}
    DEPENDS edgedeform_python
    COMMENT "Installing the Edge Deform add-on into Blender's user add-on folder"
    USES_TERMINAL)
endif()

# The zips: add-on + native module for this platform and Python.
set(ED_ZIP ${CMAKE_BINARY_DIR}/edge_deform-${ED_VERSION}-${ED_PLATFORM}-${ED_PY_TAG}.zip)
set(ED_EXT_ZIP ${CMAKE_BINARY_DIR}/edge_deform-${ED_VERSION}-extension-linux-x64.zip)
set(ED_EXT_ZIP_WINDOWS ${CMAKE_BINARY_DIR}/edge_deform-${ED_VERSION}-extension-windows-x64.zip)
set(EDGEDEFORM_ADDON_ZIP ${ED_ZIP} CACHE INTERNAL "")
set(EDGEDEFORM_EXTENSION_ZIP ${ED_EXT_ZIP} CACHE INTERNAL "")
set(EDGEDEFORM_EXTENSION_ZIP_WINDOWS ${ED_EXT_ZIP_WINDOWS} CACHE INTERNAL "")
set(_ed_stage ${CMAKE_BINARY_DIR}/addon_stage)
file(MAKE_DIRECTORY ${_ed_stage}/zip ${_ed_stage}/extension ${_ed_stage}/extension-windows)  # working directories of the zip commands
file(GLOB_RECURSE _ed_sources CONFIGURE_DEPENDS ${ED_ADDON_SRC}/*.py ${ED_ADDON_SRC}/*.toml
     ${CMAKE_SOURCE_DIR}/docs/addon.md ${CMAKE_SOURCE_DIR}/docs/img/addon_*.png)

add_custom_target(addon_zip ALL
  COMMAND ${CMAKE_COMMAND} -DED_ACTION=stage -DED_ADDON_SRC=${ED_ADDON_SRC}
          -DED_PKG_DIR=${ED_PKG_DIR} -DED_DEST=${_ed_stage}/zip -DED_FLAT=FALSE
          -P ${CMAKE_CURRENT_LIST_FILE}
  COMMAND ${CMAKE_COMMAND} -E rm -f ${ED_ZIP}
  COMMAND ${CMAKE_COMMAND} -E tar cf ${ED_ZIP} --format=zip edge_deform
  WORKING_DIRECTORY ${_ed_stage}/zip
  DEPENDS edgedeform_python ${_ed_sources}
  BYPRODUCTS ${ED_ZIP}
  COMMENT "Add-on zip (Preferences > Add-ons > Install): ${ED_ZIP}")

add_custom_target(wheel
  COMMAND ${CMAKE_SOURCE_DIR}/scripts/build_wheel.sh ${CMAKE_BINARY_DIR}
  COMMENT "edgedeform wheel (scikit-build-core) -> ${CMAKE_BINARY_DIR}/wheels"
  USES_TERMINAL)

add_custom_target(addon_extension
  COMMAND ${CMAKE_COMMAND} -DED_ACTION=stage -DED_ADDON_SRC=${ED_ADDON_SRC}
          -DED_WHEEL_DIR=${CMAKE_BINARY_DIR}/wheels -DED_DEST=${_ed_stage}/extension
          -DED_EXT_PLATFORM=linux-x64 -DED_FLAT=TRUE -P ${CMAKE_CURRENT_LIST_FILE}
  COMMAND ${CMAKE_COMMAND} -E rm -f ${ED_EXT_ZIP}
  COMMAND ${CMAKE_COMMAND} -E tar cf ${ED_EXT_ZIP} --format=zip .
  WORKING_DIRECTORY ${_ed_stage}/extension
  DEPENDS ${_ed_sources}
  BYPRODUCTS ${ED_EXT_ZIP}
  COMMENT "Blender 4.2+ extension zip: ${ED_EXT_ZIP}")
add_dependencies(addon_extension wheel)

# The Windows wheels come from the cross-build (scripts/build_windows.sh, or the `windows`
# ctest fixture), which this target does not start: it is a second, optional toolchain.
add_custom_target(addon_extension_windows
  COMMAND ${CMAKE_COMMAND} -DED_ACTION=stage -DED_ADDON_SRC=${ED_ADDON_SRC}
          -DED_WHEEL_DIR=${CMAKE_BINARY_DIR}/windows/wheels -DED_DEST=${_ed_stage}/extension-windows
          -DED_EXT_PLATFORM=windows-x64 -DED_FLAT=TRUE -P ${CMAKE_CURRENT_LIST_FILE}
  COMMAND ${CMAKE_COMMAND} -E rm -f ${ED_EXT_ZIP_WINDOWS}
  COMMAND ${CMAKE_COMMAND} -E tar cf ${ED_EXT_ZIP_WINDOWS} --format=zip .
  WORKING_DIRECTORY ${_ed_stage}/extension-windows
  DEPENDS ${_ed_sources}
  BYPRODUCTS ${ED_EXT_ZIP_WINDOWS}
  COMMENT "Blender 4.2+ extension zip for Windows: ${ED_EXT_ZIP_WINDOWS}")
