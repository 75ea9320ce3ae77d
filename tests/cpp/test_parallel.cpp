#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "base/parallel.h"

using edgedeform::parallel_for;

namespace {

// Runs parallel_for and counts how often each index was visited.
std::vector<int> visits(int n, int grain, int min_parallel) {
  std::vector<std::atomic<int>> count(static_cast<size_t>(n));
  parallel_for(n, grain, min_parallel, [&](int begin, int end) {
    ASSERT_LE(0, begin);
    ASSERT_LT(begin, end);
    ASSERT_LE(end, n);
    for (int i = begin; i < end; ++i) count[static_cast<size_t>(i)]++;
  });
  std::vector<int> out;
  for (auto& c : count) out.push_back(c.load());
  return out;
}

}  // namespace

TEST(ParallelFor, VisitsEveryIndexOnceForAnySizeAndGrain) {
  for (int n : {0, 1, 7, 256, 1000, 4099})
    for (int grain : {1, 3, 64, 5000})
      for (int min_parallel : {0, 512}) {
        const std::vector<int> v = visits(n, grain, min_parallel);
        for (int i = 0; i < n; ++i) ASSERT_EQ(v[static_cast<size_t>(i)], 1) << "n=" << n << " grain=" << grain << " i=" << i;
      }
}

TEST(ParallelFor, BelowTheThresholdRunsAsOneCallOnTheCaller) {
  int calls = 0;
  const auto caller = std::this_thread::get_id();
  parallel_for(100, 10, 101, [&](int begin, int end) {
    ++calls;
    EXPECT_EQ(begin, 0);
    EXPECT_EQ(end, 100);
    EXPECT_EQ(std::this_thread::get_id(), caller);
  });
  EXPECT_EQ(calls, 1);
}

TEST(ParallelFor, NestedAndConcurrentCallsCompleteWithEveryIndexOnce) {
  // A loop inside a loop (runs serially inside) and two threads sharing the pool.
  constexpr int kOuter = 64, kInner = 300;
  std::vector<std::atomic<int>> count(static_cast<size_t>(kOuter * kInner));
  auto nested = [&] {
    parallel_for(kOuter, 4, 0, [&](int b, int e) {
      for (int o = b; o < e; ++o)
        parallel_for(kInner, 16, 0, [&](int ib, int ie) {
          for (int i = ib; i < ie; ++i) count[static_cast<size_t>(o * kInner + i)]++;
        });
    });
  };
  std::thread other(nested);
  nested();
  other.join();
  for (auto& c : count) ASSERT_EQ(c.load(), 2);
}

TEST(ParallelFor, ThreadCountIsAtLeastOne) { EXPECT_GE(edgedeform::parallel_threads(), 1); }
