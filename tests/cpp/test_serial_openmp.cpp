// SerialOpenMP: OpenMP regions run on one thread while a guard lives, and the setting is
// restored when the last guard goes (guards nest and may overlap across threads).
#include <gtest/gtest.h>

#include <thread>

#include "base/serial_openmp.h"

#ifdef _OPENMP
#include <omp.h>

using edgedeform::SerialOpenMP;

namespace {
int team_size(int requested) {
  int size = 0;
#pragma omp parallel num_threads(requested)
  {
#pragma omp single
    size = omp_get_num_threads();
  }
  return size;
}
}  // namespace

TEST(SerialOpenMP, ARegionAskingForFourThreadsGetsOneWhileAGuardLives) {
  const int before = omp_get_max_active_levels();
  ASSERT_GT(before, 0);
  {
    const SerialOpenMP outer;
    EXPECT_EQ(team_size(4), 1);
    {
      const SerialOpenMP inner;
      EXPECT_EQ(team_size(4), 1);
    }
    EXPECT_EQ(team_size(4), 1);  // the outer guard still lives
  }
  EXPECT_EQ(omp_get_max_active_levels(), before);
}

TEST(SerialOpenMP, GuardsOnTwoThreadsRestoreTheSettingOnlyWhenBothAreGone) {
  const int before = omp_get_max_active_levels();
  auto* first = new SerialOpenMP;
  std::thread other([] { const SerialOpenMP guard; });
  other.join();
  EXPECT_EQ(omp_get_max_active_levels(), 0);  // the other thread's guard went; ours lives
  delete first;
  EXPECT_EQ(omp_get_max_active_levels(), before);
}
#endif
