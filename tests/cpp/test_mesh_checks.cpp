#include <gtest/gtest.h>

#include <limits>

#include "edgedeform/mesh_checks.h"
#include "test_meshes.h"

using namespace edgedeform;

TEST(MeshChecks, AcceptsAValidMesh) {
  const auto m = test::grid(4, 4);
  EXPECT_NO_THROW(check_mesh(m.V, m.F));
}

TEST(MeshChecks, RejectsNonFiniteCoordinates) {
  auto m = test::grid(4, 4);
  m.V(5, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(check_mesh(m.V, m.F), std::invalid_argument);
  m.V(5, 1) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(check_mesh(m.V, m.F), std::invalid_argument);
}

TEST(MeshChecks, RejectsOutOfRangeAndNegativeFaceIndices) {
  auto m = test::grid(4, 4);
  m.F(3, 2) = 16;
  EXPECT_THROW(check_mesh(m.V, m.F), std::out_of_range);
  m.F(3, 2) = -1;
  EXPECT_THROW(check_mesh(m.V, m.F), std::out_of_range);
}

TEST(MeshChecks, RejectsAFaceThatRepeatsAVertex) {
  auto m = test::grid(4, 4);
  m.F(0, 1) = m.F(0, 0);
  EXPECT_THROW(check_mesh(m.V, m.F), std::invalid_argument);
}

TEST(MeshChecks, RejectsEmptyMeshes) {
  EXPECT_THROW(check_mesh(RowMatrixX3d(0, 3), RowMatrixX3i(0, 3)), std::invalid_argument);
  EXPECT_THROW(check_mesh(test::grid(3, 3).V, RowMatrixX3i(0, 3)), std::invalid_argument);
}

TEST(MeshChecks, IndexSetsNameTheProblem) {
  EXPECT_THROW(check_index_set({0, 5}, 5, "handles"), std::out_of_range);
  EXPECT_THROW(check_index_set({-2}, 5, "handles"), std::out_of_range);
  EXPECT_THROW(check_index_set({1, 1}, 5, "handles"), std::invalid_argument);
  try {
    check_index_set({0, 7}, 5, "static");
    FAIL();
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("static[1] = 7"), std::string::npos);
  }
}

TEST(MeshChecks, FindsUnreferencedVertices) {
  auto m = test::grid(3, 3);
  RowMatrixX3d V(m.V.rows() + 1, 3);
  V << m.V, Eigen::RowVector3d(5, 5, 5);
  const auto used = referenced_vertices(m.F, static_cast<int>(V.rows()));
  EXPECT_TRUE(used[0]);
  EXPECT_FALSE(used[9]);
}
