# cmake -P script: the import library's definition for pythonXY.dll, from what the module's
# objects import from it. python.org ships python3XY.lib for MSVC, which is not reachable here,
# and mingw's linker needs an import library naming the DLL; an import library maps each
# name to the DLL, so listing exactly the names the objects use (every one declared
# PyAPI_FUNC/PyAPI_DATA in the public headers, which the DLL exports) is enough.
#   cmake -DNM=<nm> -DDLL=python311.dll -DDEF=<out.def> -DOBJECTS=<a|b|c> -P python_def.cmake
string(REPLACE "|" ";" OBJECTS "${OBJECTS}")
set(names "")
foreach(object ${OBJECTS})
  execute_process(COMMAND ${NM} -u ${object} OUTPUT_VARIABLE out RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${NM} -u ${object} failed")
  endif()
  # Through the import table (__imp_X), or directly where an initializer takes a function's
  # address (the import library's thunk X then serves).
  string(REGEX MATCHALL "U (__imp_)?_?Py[A-Za-z0-9_]*" found "${out}")
  list(APPEND names ${found})
endforeach()
list(TRANSFORM names REPLACE "^U (__imp_)?" "")
list(REMOVE_DUPLICATES names)
list(SORT names)
list(LENGTH names count)
if(count EQUAL 0)
  message(FATAL_ERROR "no Python symbol imported by ${OBJECTS}: not a Python module?")
endif()
list(JOIN names "\n  " lines)
file(WRITE ${DEF} "LIBRARY ${DLL}\nEXPORTS\n  ${lines}\n")
message(STATUS "${DEF}: ${count} names imported from ${DLL}")
