#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>

#include "mesh/mesh_checks.h"
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

namespace {
std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}
}  // namespace

TEST(MeshChecks, WholeMeshAtOnePointIsNamed) {
  auto m = test::grid(4, 4);
  m.V.rowwise() = Eigen::RowVector3d(1, 2, 3);
  const std::string msg = message_of([&] { check_geometry(m.V, m.F); });
  EXPECT_NE(msg.find("the mesh is degenerate: all its 16 vertices are at one point (1, 2, 3)"), std::string::npos)
      << msg;
}

TEST(MeshChecks, ZeroAreaEverywhereIsNamed) {
  auto m = test::grid(4, 4);
  m.V.col(1).setZero();  // every vertex on the x axis
  const std::string msg = message_of([&] { check_geometry(m.V, m.F); });
  EXPECT_NE(msg.find("every face has zero area"), std::string::npos) << msg;
}

TEST(MeshChecks, DegeneratePieceBesideAGoodOneIsNamed) {
  const auto good = test::grid(4, 4);
  test::TestMesh m;
  m.V.resize(19, 3);
  m.V.topRows(16) = good.V;
  m.V.bottomRows(3).rowwise() = Eigen::RowVector3d(5, 5, 5);
  m.F.resize(good.F.rows() + 1, 3);
  m.F.topRows(good.F.rows()) = good.F;
  m.F.row(good.F.rows()) << 16, 17, 18;
  const std::string msg = message_of([&] { check_geometry(m.V, m.F); });
  EXPECT_NE(msg.find("1 of the mesh's 2 connected pieces are degenerate; in the one with face 18, all its 3 "
                     "vertices are at one point"),
            std::string::npos)
      << msg;
  EXPECT_NO_THROW(check_geometry(good.V, good.F));
}

TEST(MeshChecks, DistanceBeyondTheSafeRangeIsNamed) {
  RowMatrixX3d X(2, 3);
  X << 0, 0, 0, 1e300, 0, 0;
  const double limit = largest_safe_distance(100.0);
  EXPECT_GT(limit, 1e140);
  EXPECT_LT(limit, 1e154);
  const std::string msg = message_of([&] { check_distance(X, Eigen::RowVector3d::Zero(), limit, "targets"); });
  EXPECT_EQ(msg.rfind("targets[1] = (1e+300, 0, 0)", 0), 0u) << msg;
  X(1, 0) = 1e10;
  EXPECT_NO_THROW(check_distance(X, Eigen::RowVector3d::Zero(), limit, "targets"));
}
