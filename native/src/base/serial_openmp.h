// Runs the OpenMP regions that libraries open on the calling thread with one thread, for
// the lifetime of the guard.
//
// Why: CHOLMOD 3 (Debian 12's SuiteSparse 5.12) runs the scatter loops of its supernodal
// factorization with a fixed team of CHOLMOD_OMP_NUM_THREADS = 4 OpenMP threads, whatever
// OMP_NUM_THREADS says. Those loops copy memory and do not scale; on 2 shared cores the
// team's spinning and futex waits cost more than the loops (koala 50k, edge domain, with a
// second process busy: a numeric refactorization 141-149 ms with the team, 100-102 ms with
// one thread, median of 3 interleaved runs each).
//
// How: OpenMP's max-active-levels is set to 0 (every region then runs on its encountering
// thread alone) while at least one guard lives, and restored when the last one goes. The
// setting is process-wide, so guards on several threads share one count.
#pragma once

namespace edgedeform {

class SerialOpenMP {
 public:
  SerialOpenMP();
  ~SerialOpenMP();
  SerialOpenMP(const SerialOpenMP&) = delete;
  SerialOpenMP& operator=(const SerialOpenMP&) = delete;
};

}  // namespace edgedeform
