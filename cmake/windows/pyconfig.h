/* pyconfig.h for compiling an extension module with mingw-w64 against python.org's CPython
 * for 64-bit Windows (3.11, 3.13; the default build: no free threading, no debug build).
 *
 * Written for edgedeform, not copied: python.org's own (PC/pyconfig.h) is not in Debian 12's
 * packages nor in any package on the index, and its mingw branch leaves MS_WIN64 undefined
 * (Py_ssize_t then comes out 4 bytes). It holds only what the public headers read; each
 * value is what MSVC's x64 ABI has (LLP64: long is 4 bytes), which mingw-w64 shares.
 * cmake/windows_module.cmake puts it in place of the Linux pyconfig.h of a copy of a CPython
 * X.Y Include/ folder (the rest of that folder is the same on every platform). */
#ifndef Py_CONFIG_H
#define Py_CONFIG_H

#if !defined(_WIN64) || !defined(__MINGW64__)
#error "this pyconfig.h is for 64-bit Windows with mingw-w64"
#endif

#define MS_WIN32
#define MS_WIN64
#define MS_WINDOWS
#define NT_THREADS
#define WITH_THREAD
#define PLATFORM "win32"

/* The interpreter is pythonXY.dll: its functions and data are __declspec(dllimport), the
 * module's PyInit_ __declspec(dllexport) (pyport.h, exports.h). */
#define Py_ENABLE_SHARED 1
#define HAVE_DECLSPEC_DLL

#define SIZEOF_SHORT 2
#define SIZEOF_INT 4
#define SIZEOF_LONG 4
#define SIZEOF_LONG_LONG 8
#define SIZEOF_FLOAT 4
#define SIZEOF_DOUBLE 8
#define SIZEOF_VOID_P 8
#define SIZEOF_SIZE_T 8
#define SIZEOF_TIME_T 8
#define SIZEOF_OFF_T 4
#define SIZEOF_FPOS_T 8
#define SIZEOF_HKEY 8
#define SIZEOF_WCHAR_T 2
#define SIZEOF__BOOL 1
#define SIZEOF_PID_T SIZEOF_INT
#define ALIGNOF_SIZE_T 8
#define ALIGNOF_MAX_ALIGN_T 8
#define HAVE_LONG_LONG 1
#define PY_LONG_LONG long long
#define PY_LLONG_MIN LLONG_MIN
#define PY_LLONG_MAX LLONG_MAX
#define PY_ULLONG_MAX ULLONG_MAX

/* Py_ssize_t as python.org defines it (pyport.h uses it when HAVE_PY_SSIZE_T). */
#include <limits.h>
typedef long long Py_ssize_t;
#define PY_SSIZE_T_MAX LLONG_MAX
#define HAVE_PY_SSIZE_T 1

#define DOUBLE_IS_LITTLE_ENDIAN_IEEE754 1
#define HAVE_WCHAR_H 1
#define HAVE_STDARG_PROTOTYPES 1
#define HAVE_COPYSIGN 1
#define HAVE_ROUND 1
#define HAVE_HYPOT 1
#define HAVE_ERF 1
#define HAVE_ERFC 1
#define HAVE_STRFTIME 1
#define HAVE_SYS_UTIME_H 1
#define HAVE_IO_H 1
#define HAVE_PROCESS_H 1
#define HAVE_DIRECT_H 1
#define HAVE_ZLIB_COPY 1
#define _Py_HAVE_ZLIB 1
#define PY_SUPPORT_TIER 1

#endif /* Py_CONFIG_H */
