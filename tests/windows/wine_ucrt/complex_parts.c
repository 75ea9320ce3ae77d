/* The parts of a complex number, for a ucrtbase.dll that stands in front of wine's own
 * (scripts/windows_provision.py, docs/decisions/0064): wine 8 and 10 leave these UCRT
 * functions unimplemented, and a call aborts the process. SciPy's scipy.special (every SciPy with a cp313 wheel) calls
 * crealf when it loads, NumPy 2.3's FFT cimag.
 *
 * MSVC's complex types are structs of two numbers (_Fcomplex, _Dcomplex, _Lcomplex, whose long
 * double is a double); the x64 ABI passes the 8-byte one in a register and the 16-byte ones
 * by reference, as gcc does for these structs. */
typedef struct { float re, im; } fcomplex;
typedef struct { double re, im; } dcomplex;

float crealf(fcomplex z) { return z.re; }
float cimagf(fcomplex z) { return z.im; }
double creal(dcomplex z) { return z.re; }
double cimag(dcomplex z) { return z.im; }
double creall(dcomplex z) { return z.re; }
double cimagl(dcomplex z) { return z.im; }

int __stdcall DllMain(void *instance, unsigned long reason, void *reserved) {
  (void)instance; (void)reason; (void)reserved;
  return 1;
}
