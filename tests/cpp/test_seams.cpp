#include <gtest/gtest.h>

#include "mesh/seams.h"
#include "test_meshes.h"

using namespace edgedeform;

namespace {

// Two triangles that share an edge position but not its vertices: 0-1-2 and 3-4-5 with
// vertices 3, 4 copies of 1, 2. Vertex 6 (unused) also sits at vertex 0's position.
test::TestMesh split_pair() {
  test::TestMesh m;
  m.V.resize(7, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 0, 0;
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 3, 5, 4;
  return m;
}

}  // namespace

TEST(Seams, FindsCopiesOfOnePositionAmongFaceVertices) {
  const auto m = split_pair();
  const SeamCopies s = find_seam_copies(m.V, m.F);
  ASSERT_EQ(s.groups.size(), 2u);  // unused vertex 6 is not a copy of 0
  EXPECT_EQ(s.groups[0], (std::vector<int>{2, 4}));  // sorted by position: (0,1,0) < (1,0,0)
  EXPECT_EQ(s.groups[1], (std::vector<int>{1, 3}));
  EXPECT_NE(s.piece[1], s.piece[3]);
  EXPECT_TRUE(find_seam_copies(test::grid(4, 4).V, test::grid(4, 4).F).groups.empty());
}

TEST(Seams, WarnsOnlyWhenCopiesMoveApart) {
  const auto m = split_pair();
  const SeamCopies s = find_seam_copies(m.V, m.F);
  RowMatrixX3d X = m.V;
  X.rowwise() += Eigen::RowVector3d(5, 5, 5);  // moved together: no warning
  EXPECT_FALSE(seam_warning(s, X, 1e-9));
  X(3, 2) += 0.5;  // one copy lifted
  const auto w = seam_warning(s, X, 1e-9);
  ASSERT_TRUE(w);
  EXPECT_EQ(w->rfind("unwelded seam: 2 coincident vertices (1 shared positions, in 2 connected pieces) "
                     "moved apart, by up to 0.5",
                     0),
            0u)
      << *w;
  EXPECT_FALSE(seam_warning(s, X, 0.6));  // within the tolerance
}
