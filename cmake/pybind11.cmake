# pybind11 >= 2.12, from the package index, for every build of the module (CMake, wheel,
# add-on). Older pybind11 (Debian 12's pybind11-dev is 2.10) predates NumPy 2: a module built
# with it returns per-iteration arrays (r.energies, r.residuals) whose elements all equal the
# first one when NumPy 2 is loaded. Below 3: pybind11 3.x builds it, but freeing a Deformer
# then aborts (free(): invalid pointer); the same bound as pyproject.toml's. Included by native/CMakeLists.txt after find_package(Python).
#
# 1. The building Python has it (pip / scikit-build-core: pyproject.toml's build requirement).
# 2. Else (the CMake build) a tools venv in the build folder, made once with pip.
set(EDGEDEFORM_PYBIND11_MIN 2.12)
set(EDGEDEFORM_PYBIND11_SPEC "pybind11>=${EDGEDEFORM_PYBIND11_MIN},<3")

function(_ed_pybind11_dir python out)
  execute_process(
    COMMAND ${python} -c "import pybind11; print(pybind11.__version__); print(pybind11.get_cmake_dir())"
    OUTPUT_VARIABLE answer ERROR_QUIET RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE)
  set(${out} "" PARENT_SCOPE)
  if(rc EQUAL 0)
    string(REPLACE "\n" ";" answer "${answer}")
    list(GET answer 0 version)
    list(GET answer 1 dir)
    if(version VERSION_GREATER_EQUAL EDGEDEFORM_PYBIND11_MIN)
      set(${out} "${dir}" PARENT_SCOPE)
    endif()
  endif()
endfunction()

_ed_pybind11_dir(${Python_EXECUTABLE} _ed_pybind11)
if(NOT _ed_pybind11 AND NOT SKBUILD)
  set(_ed_tools ${CMAKE_BINARY_DIR}/tools_venv)
  _ed_pybind11_dir(${_ed_tools}/bin/python _ed_pybind11)
  if(NOT _ed_pybind11)
    message(STATUS "edgedeform: installing ${EDGEDEFORM_PYBIND11_SPEC} into ${_ed_tools}")
    file(REMOVE_RECURSE ${_ed_tools})
    execute_process(COMMAND ${Python_EXECUTABLE} -m venv ${_ed_tools} RESULT_VARIABLE rc)
    if(rc EQUAL 0)
      execute_process(
        COMMAND ${_ed_tools}/bin/python -m pip install --no-cache-dir -q ${EDGEDEFORM_PYBIND11_SPEC}
        RESULT_VARIABLE rc)
    endif()
    _ed_pybind11_dir(${_ed_tools}/bin/python _ed_pybind11)
  endif()
endif()
if(NOT _ed_pybind11)
  message(FATAL_ERROR "edgedeform needs ${EDGEDEFORM_PYBIND11_SPEC} (NumPy 2 support), and "
    "could not get it: `${Python_EXECUTABLE} -m venv` + pip install failed (no python3-venv, "
    "or no package index?). Install it for ${Python_EXECUTABLE} or pass -Dpybind11_DIR=<its "
    "share/cmake/pybind11>.")
endif()
# FORCE: a build folder configured before may still cache the system's old pybind11.
set(pybind11_DIR ${_ed_pybind11} CACHE PATH "pybind11 >= ${EDGEDEFORM_PYBIND11_MIN}" FORCE)
find_package(pybind11 ${EDGEDEFORM_PYBIND11_MIN} CONFIG REQUIRED)
message(STATUS "edgedeform: pybind11 ${pybind11_VERSION} (${pybind11_DIR})")
