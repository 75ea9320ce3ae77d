#include "base/parallel.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <mutex>
#include <thread>
#include <vector>

namespace edgedeform {

namespace {

int configured_threads() {
  if (const char* env = std::getenv("OMP_NUM_THREADS")) {
    const int n = std::atoi(env);  // "4" or "4,2": the outer level
    if (n >= 1) return n;
  }
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

class WorkerPool {
 public:
  explicit WorkerPool(int threads) {
    for (int k = 1; k < threads; ++k) workers_.emplace_back([this] { worker_loop(); });
  }
  // Never destroyed (see pool()): workers sleep until the process ends.

  int threads() const { return static_cast<int>(workers_.size()) + 1; }

  void run(int n, int grain, const std::function<void(int, int)>& body) {
    const int chunks = (n + grain - 1) / grain;
    if (workers_.empty() || chunks < 2 || !job_mutex_.try_lock()) {
      body(0, n);
      return;
    }
    uint32_t generation;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      generation = ++generation_;
      body_ = &body;
      n_ = n;
      grain_ = grain;
      chunks_ = chunks;
      remaining_.store(chunks);
      cursor_.store(static_cast<uint64_t>(generation) << 32);
    }
    wake_.notify_all();
    work(generation, body, n, grain, chunks);
    {
      std::unique_lock<std::mutex> lock(mutex_);
      done_.wait(lock, [this] { return remaining_.load() == 0; });
    }
    job_mutex_.unlock();
  }

 private:
  // Claims chunks of job `generation` until none is left. A worker that wakes after the job
  // ended fails the generation check and touches nothing of it.
  void work(uint32_t generation, const std::function<void(int, int)>& body, int n, int grain, int chunks) {
    uint64_t cursor = cursor_.load();
    for (;;) {
      if (static_cast<uint32_t>(cursor >> 32) != generation) return;
      const auto chunk = static_cast<uint32_t>(cursor);
      if (chunk >= static_cast<uint32_t>(chunks)) return;
      if (!cursor_.compare_exchange_weak(cursor, cursor + 1)) continue;  // cursor reloaded
      const int begin = static_cast<int>(chunk) * grain;
      body(begin, std::min(n, begin + grain));
      if (remaining_.fetch_sub(1) == 1) {
        std::lock_guard<std::mutex> lock(mutex_);  // so that the caller cannot miss it
        done_.notify_one();
      }
      cursor = cursor_.load();
    }
  }

  void worker_loop() {
    uint32_t seen = 0;
    for (;;) {
      const std::function<void(int, int)>* body;
      int n, grain, chunks;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return generation_ != seen; });
        seen = generation_;
        body = body_;
        n = n_;
        grain = grain_;
        chunks = chunks_;
      }
      work(seen, *body, n, grain, chunks);
    }
  }

  std::mutex job_mutex_;  // one job at a time
  std::mutex mutex_;      // guards the job description and both condition variables
  std::condition_variable wake_, done_;
  uint32_t generation_ = 0;
  const std::function<void(int, int)>* body_ = nullptr;
  int n_ = 0, grain_ = 1, chunks_ = 0;
  std::atomic<uint64_t> cursor_{0};  // generation << 32 | next chunk
  std::atomic<int> remaining_{0};    // chunks of the current job not yet finished
  std::vector<std::thread> workers_;
};

WorkerPool& pool() {
  // Leaked on purpose: joining threads from a static destructor at interpreter exit (or in
  // a forked child, where the workers do not exist) could hang; sleeping threads cannot.
  static WorkerPool* instance = new WorkerPool(configured_threads());
  return *instance;
}

}  // namespace

void parallel_for(int n, int grain, int min_parallel, const std::function<void(int, int)>& body) {
  if (n <= 0) return;
  if (n < min_parallel || grain >= n) {
    body(0, n);
    return;
  }
  pool().run(n, grain, body);
}

int parallel_threads() { return pool().threads(); }

}  // namespace edgedeform
