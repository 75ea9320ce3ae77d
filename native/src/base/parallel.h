// Parallel loops for the per-iteration work (local step, right-hand side).
//
// Not OpenMP: Blender links libgomp and starts it before any add-on runs, so its wait policy
// (spin ~300k iterations at every barrier) cannot be changed from here; with another process
// on one of two cores, those spinning threads made a 1k-vertex local step 19x slower than
// one thread (record 0011). This pool's workers sleep on a condition variable, and the calling
// thread never waits for a worker that has not started: chunks nobody claimed are run by
// the caller itself, so a descheduled worker costs at most the chunk it holds.
#pragma once

#include <functional>

namespace edgedeform {

// Calls body(begin, end) over [0, n) in chunks of `grain`. Serial when n < min_parallel,
// when only one thread is configured, or when another parallel_for is running (a nested
// call, or a second Deformer in another thread). body must not throw.
void parallel_for(int n, int grain, int min_parallel, const std::function<void(int, int)>& body);

// Threads a parallel_for may use, the caller included: OMP_NUM_THREADS when set (so that
// one setting governs this pool and the OpenMP/BLAS code of the libraries), else the
// hardware's.
int parallel_threads();

}  // namespace edgedeform
