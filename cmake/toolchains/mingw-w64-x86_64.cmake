# Cross-build for 64-bit Windows with Debian's mingw-w64 (gcc 12, the POSIX thread model,
# which OpenMP's libgomp and std::thread need): scripts/build_windows.sh uses it.
#   cmake -S . -B build/windows -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/mingw-w64-x86_64.cmake
#
# C runtime: MSVCRT.DLL, the only one Debian 12's mingw-w64 (10.0) builds its runtime for
# (its UCRT toolchain, gcc-mingw-w64-ucrt64, starts with Debian 13). python.org's CPython uses
# the UCRT; the two live side by side in one process as long as no C runtime object (FILE*,
# file descriptor, malloc'd block, locale) crosses between them, and the module passes none:
# docs/decisions/0045-windows-cross-build.md. Everything else from gcc (libstdc++, libgcc,
# libgomp, winpthreads) is linked statically, so a module or program needs no DLL of ours.
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR AMD64)

set(EDGEDEFORM_MINGW_PREFIX x86_64-w64-mingw32)
set(CMAKE_C_COMPILER ${EDGEDEFORM_MINGW_PREFIX}-gcc-posix)
set(CMAKE_CXX_COMPILER ${EDGEDEFORM_MINGW_PREFIX}-g++-posix)
set(CMAKE_RC_COMPILER ${EDGEDEFORM_MINGW_PREFIX}-windres)
set(CMAKE_DLLTOOL ${EDGEDEFORM_MINGW_PREFIX}-dlltool)

# Target headers and libraries from the mingw sysroot only; programs from the host.
set(CMAKE_FIND_ROOT_PATH /usr/${EDGEDEFORM_MINGW_PREFIX})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# OpenMP's runtime linked in too: FindOpenMP would take libgomp.dll.a (the import library of
# libgomp-1.dll, which no Windows Python has), and Windows-GNU.cmake puts .dll.a first.
execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libgomp.a
                OUTPUT_VARIABLE _ed_libgomp OUTPUT_STRIP_TRAILING_WHITESPACE)
if(IS_ABSOLUTE "${_ed_libgomp}")
  set(OpenMP_gomp_LIBRARY ${_ed_libgomp} CACHE FILEPATH "libgomp, static (mingw-w64 toolchain)" FORCE)
endif()
set(CMAKE_EXE_LINKER_FLAGS_INIT "-static")
set(CMAKE_SHARED_LINKER_FLAGS_INIT "-static")
set(CMAKE_MODULE_LINKER_FLAGS_INIT "-static")

# ctest and gtest discovery would run target programs through this.
find_program(EDGEDEFORM_WINE NAMES wine wine64)
if(EDGEDEFORM_WINE)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${EDGEDEFORM_WINE})
endif()
