# The `_core` module for python.org's CPython on 64-bit Windows, one per Python version,
# in the mingw-w64 cross-build (scripts/build_windows.sh). Included by native/CMakeLists.txt.
#
#   EDGEDEFORM_WINDOWS_PYTHON   list of TAG=INCLUDE pairs, e.g. cp311=/usr/include/python3.11:
#                               the CPython X.Y headers of any platform (the host's), of
#                               which only pyconfig.h is platform-specific
#   EDGEDEFORM_PYBIND11_INCLUDE pybind11's headers (>= 2.12, < 3: cmake/pybind11.cmake)
#
# Per tag: build/python-<tag>/edgedeform/_core.<tag>-win_amd64.pyd next to the package's
# Python files. No Windows Python is reachable here: the headers are the host's with
# cmake/windows/pyconfig.h in place of theirs, and the module links against an import library
# for pythonXY.dll made from the names it uses (cmake/windows/python_def.cmake).
if(NOT EDGEDEFORM_PYBIND11_INCLUDE OR NOT EXISTS ${EDGEDEFORM_PYBIND11_INCLUDE}/pybind11/pybind11.h)
  message(FATAL_ERROR "EDGEDEFORM_WINDOWS_PYTHON needs EDGEDEFORM_PYBIND11_INCLUDE (pybind11's include folder)")
endif()
if(NOT CMAKE_DLLTOOL)
  find_program(CMAKE_DLLTOOL NAMES x86_64-w64-mingw32-dlltool dlltool REQUIRED)
endif()

foreach(pair ${EDGEDEFORM_WINDOWS_PYTHON})
  if(NOT pair MATCHES "^cp([0-9])([0-9]+)=(.+)$")
    message(FATAL_ERROR "EDGEDEFORM_WINDOWS_PYTHON: '${pair}' is not TAG=INCLUDE (cp311=/usr/include/python3.11)")
  endif()
  set(major ${CMAKE_MATCH_1})
  set(minor ${CMAKE_MATCH_2})
  set(host_include ${CMAKE_MATCH_3})
  set(tag cp${major}${minor})
  set(dll python${major}${minor}.dll)
  if(NOT EXISTS ${host_include}/Python.h OR NOT EXISTS ${host_include}/patchlevel.h)
    message(FATAL_ERROR "${host_include} has no CPython headers (Python.h)")
  endif()
  file(STRINGS ${host_include}/patchlevel.h _ed_pv REGEX "^#define[ \t]+PY_VERSION[ \t]+\"")
  if(NOT _ed_pv MATCHES "\"${major}\\.${minor}\\.")
    message(FATAL_ERROR "${host_include} holds ${_ed_pv}, not the headers of ${tag}")
  endif()

  # The headers with the Windows pyconfig.h: a copy, since Python.h's #include "pyconfig.h"
  # finds the file next to it before any -I folder. (Copied over, not afresh: unchanged
  # files keep their times, so a reconfigure does not recompile the module.)
  set(include ${CMAKE_BINARY_DIR}/windows_python/${tag}/include)
  file(COPY ${host_include}/ DESTINATION ${include} PATTERN pyconfig.h EXCLUDE)
  configure_file(${PROJECT_SOURCE_DIR}/cmake/windows/pyconfig.h ${include}/pyconfig.h COPYONLY)

  add_library(_core_objects_${tag} OBJECT ${EDGEDEFORM_BINDING_SOURCES})
  target_include_directories(_core_objects_${tag} SYSTEM PRIVATE ${include} ${EDGEDEFORM_PYBIND11_INCLUDE})
  target_link_libraries(_core_objects_${tag} PRIVATE edgedeform_core)   # its headers
  target_compile_options(_core_objects_${tag} PRIVATE -fvisibility=hidden)

  set(def ${CMAKE_BINARY_DIR}/windows_python/${tag}/${dll}.def)
  set(implib ${CMAKE_BINARY_DIR}/windows_python/${tag}/lib${dll}.a)
  add_custom_command(OUTPUT ${implib}
    COMMAND ${CMAKE_COMMAND} -DNM=${CMAKE_NM} -DDLL=${dll} -DDEF=${def}
            "-DOBJECTS=$<JOIN:$<TARGET_OBJECTS:_core_objects_${tag}>,|>"
            -P ${PROJECT_SOURCE_DIR}/cmake/windows/python_def.cmake
    COMMAND ${CMAKE_DLLTOOL} -d ${def} -D ${dll} -l ${implib}
    DEPENDS $<TARGET_OBJECTS:_core_objects_${tag}> ${PROJECT_SOURCE_DIR}/cmake/windows/python_def.cmake
    VERBATIM
    COMMENT "Import library for ${dll} (${tag})")
  add_custom_target(python_import_${tag} DEPENDS ${implib})
  add_dependencies(python_import_${tag} _core_objects_${tag})

  set(package ${CMAKE_BINARY_DIR}/python-${tag}/edgedeform)
  add_library(_core_${tag} MODULE $<TARGET_OBJECTS:_core_objects_${tag}>)
  add_dependencies(_core_${tag} python_import_${tag})
  target_link_libraries(_core_${tag} PRIVATE edgedeform_core ${implib})
  set_target_properties(_core_${tag} PROPERTIES PREFIX "" OUTPUT_NAME _core
    SUFFIX ".${tag}-win_amd64.pyd" LIBRARY_OUTPUT_DIRECTORY ${package})
  edgedeform_beside_blas_dll(_core_${tag})   # a CHOLMOD build's OpenBLAS DLL, in the package
  add_custom_target(edgedeform_python_${tag} ALL
    COMMAND ${CMAKE_COMMAND} -E copy_directory ${CMAKE_CURRENT_SOURCE_DIR}/python/edgedeform ${package}
    COMMAND ${CMAKE_COMMAND} -E rm -rf ${package}/__pycache__
    DEPENDS _core_${tag}
    COMMENT "Python package edgedeform for Windows ${tag} -> ${package}")
  message(STATUS "edgedeform: Windows module for ${tag} (${dll}) from ${host_include}")
endforeach()
