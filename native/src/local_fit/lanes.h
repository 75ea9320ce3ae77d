// Two doubles in one SIMD register (SSE2 on x86-64, NEON on arm64), through the GCC/Clang
// vector extension: the local step runs two terms side by side, one per lane, with exactly
// the arithmetic of a scalar run (so with the same results, bit for bit).
#pragma once

namespace edgedeform {

typedef double Lanes __attribute__((vector_size(16)));
typedef long long LaneMask __attribute__((vector_size(16)));  // per lane: all ones or zero

inline bool any(LaneMask m) { return (m[0] | m[1]) != 0; }

}  // namespace edgedeform
