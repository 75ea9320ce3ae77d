# Current Blender (4.5 LTS, 5.0 on Python 3.11; 5.1, 5.2 LTS, 5.3 on Python 3.13) as the `bpy`
# module from the package index, in venvs cached under the build folder (scripts/bpy_venv.sh,
# each on the Python its Blender embeds). Each suite installs the 4.2+ extension zip the way
# a user does and runs the same background suite as Blender 3.4 above.
#
#   blender_extension_build      the wheel + extension zip (target addon_extension)
#   blender_bpy_<v>_venv         makes or reuses the venv; SKIPPED when bpy <v> cannot be
#                                installed here (exit 3), and so are that version's tests
#   blender_bpy_<v>_validate     Blender's own `extension validate` of the zip
#   blender_bpy_<v>_<suite>      install from disk, enable, run tests/blender/test_<suite>.py
#   blender_bpy_results_check    runs last: fails unless some Blender >= 4.2 passed a suite,
#                                and, where the machine has Python 3.13, some Blender >= 5.1
set(_bpy_default 4.5 5.0 5.1 5.2 5.3)
set(EDGEDEFORM_BPY_SERIES ${_bpy_default} CACHE STRING "Blender series tested through pip's bpy")
if(EDGEDEFORM_BPY_SERIES STREQUAL "4.5;5.0")   # the old default, cached by an older configure
  set(EDGEDEFORM_BPY_SERIES ${_bpy_default} CACHE STRING "Blender series tested through pip's bpy" FORCE)
endif()
execute_process(COMMAND bash ${CMAKE_SOURCE_DIR}/scripts/find_python.sh 3.13
                RESULT_VARIABLE _no_python313 OUTPUT_QUIET ERROR_QUIET)
set(_bpy_required 4.2)
if(_no_python313 EQUAL 0)
  list(APPEND _bpy_required 5.1)   # a cp313 bpy can be installed here: one must pass
endif()
set(_bpy_results ${CMAKE_CURRENT_BINARY_DIR}/bpy_results)

add_test(NAME blender_extension_build
  COMMAND ${CMAKE_COMMAND} --build ${CMAKE_BINARY_DIR} --target addon_extension)
set_tests_properties(blender_extension_build PROPERTIES
  FIXTURES_SETUP edge_deform_extension LABELS "blender;bpy" TIMEOUT 1800
  RESOURCE_LOCK edgedeform_build)

add_test(NAME blender_bpy_results_reset
  COMMAND ${CMAKE_COMMAND} -E rm -rf ${_bpy_results})
add_test(NAME blender_bpy_results_check
  COMMAND ${Python_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/check_bpy_results.py
          ${_bpy_results} ${_bpy_required})
set_tests_properties(blender_bpy_results_reset PROPERTIES
  FIXTURES_SETUP bpy_results LABELS "blender;bpy")
set_tests_properties(blender_bpy_results_check PROPERTIES
  FIXTURES_CLEANUP bpy_results LABELS "blender;bpy")

foreach(series ${EDGEDEFORM_BPY_SERIES})
  set(_venv_test blender_bpy_${series}_venv)
  add_test(NAME ${_venv_test}
    COMMAND bash ${CMAKE_SOURCE_DIR}/scripts/bpy_venv.sh ${CMAKE_BINARY_DIR} ${series})
  set_tests_properties(${_venv_test} PROPERTIES
    FIXTURES_SETUP bpy_${series} LABELS "blender;bpy" TIMEOUT 1800 SKIP_RETURN_CODE 3
    RESOURCE_LOCK bpy_venv_${series})

  set(_run bash ${CMAKE_CURRENT_SOURCE_DIR}/run_bpy.sh ${CMAKE_BINARY_DIR} ${series}
      --zip ${EDGEDEFORM_EXTENSION_ZIP} --results ${_bpy_results})
  add_test(NAME blender_bpy_${series}_validate
    COMMAND ${_run} --home ${CMAKE_CURRENT_BINARY_DIR}/bpy_home/${series}-validate --validate)
  set_tests_properties(blender_bpy_${series}_validate PROPERTIES
    FIXTURES_REQUIRED "bpy_${series};edge_deform_extension"
    LABELS "blender;bpy" TIMEOUT 300 SKIP_RETURN_CODE 3)
  set(_tests)
  foreach(suite ${EDGEDEFORM_BPY_SUITES})
    add_test(NAME blender_bpy_${series}_${suite}
      COMMAND ${_run} --home ${CMAKE_CURRENT_BINARY_DIR}/bpy_home/${series}-${suite}
              --suite ${CMAKE_CURRENT_SOURCE_DIR}/test_${suite}.py)
    list(APPEND _tests blender_bpy_${series}_${suite})
  endforeach()
  set_tests_properties(${_tests} PROPERTIES
    FIXTURES_REQUIRED "bpy_${series};edge_deform_extension;bpy_results"
    ENVIRONMENT "EDGEDEFORM_TEST_DATA=${CMAKE_SOURCE_DIR}/tests/data;EDGEDEFORM_TEST_OUT=${_out}"
    LABELS "blender;bpy" TIMEOUT 600 SKIP_RETURN_CODE 3 FAIL_REGULAR_EXPRESSION "FAIL test_")
endforeach()
