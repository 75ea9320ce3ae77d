#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "local_fit/metrics.h"
#include "test_meshes.h"

using namespace edgedeform;

TEST(Metrics, RestShapeScoresZero) {
  const auto m = test::read_off("cgal_plane.off");
  const QualityMetrics q = compute_metrics(m.V, m.F, m.V, {0}, m.V.topRows(1));
  EXPECT_EQ(q.handle_error, 0.0);
  EXPECT_EQ(q.mean_edge_strain, 0.0);
  EXPECT_EQ(q.max_edge_strain, 0.0);
  EXPECT_EQ(q.mean_dihedral_change, 0.0);
  EXPECT_LT(q.arap_energy, 1e-20);
}

TEST(Metrics, RigidMotionScoresZeroAndScaleShowsAsStrain) {
  const auto m = test::grid(8, 8, 0.3);
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, 1, 0.4).normalized()).toRotationMatrix();
  const RowMatrixX3d moved = m.V * Q.transpose();
  const QualityMetrics rigid = compute_metrics(m.V, m.F, moved, {}, RowMatrixX3d(0, 3));
  EXPECT_LT(rigid.max_edge_strain, 1e-12);
  EXPECT_LT(rigid.mean_dihedral_change, 1e-10);
  EXPECT_LT(rigid.arap_energy_normalized, 1e-20);
  const QualityMetrics scaled = compute_metrics(m.V, m.F, 1.1 * m.V, {}, RowMatrixX3d(0, 3));
  EXPECT_NEAR(scaled.mean_edge_strain, 0.1, 1e-12);
  EXPECT_NEAR(scaled.max_edge_strain, 0.1, 1e-12);
  EXPECT_LT(scaled.mean_dihedral_change, 1e-10);  // scaling keeps angles
  EXPECT_NEAR(scaled.arap_energy_normalized, 0.01, 1e-10);
}

TEST(Metrics, BendingShowsAsDihedralChange) {
  const auto m = test::grid(9, 9);
  RowMatrixX3d bent = m.V;
  for (Eigen::Index v = 0; v < bent.rows(); ++v) bent(v, 2) = 0.5 * bent(v, 0) * bent(v, 0);
  const QualityMetrics q = compute_metrics(m.V, m.F, bent, {}, RowMatrixX3d(0, 3));
  EXPECT_GT(q.mean_dihedral_change, 1e-3);
}

TEST(Metrics, HandleErrorIsTheLargestMiss) {
  const auto m = test::grid(4, 4);
  RowMatrixX3d targets = m.V.topRows(2);
  targets(1, 0) += 0.25;
  const QualityMetrics q = compute_metrics(m.V, m.F, m.V, {0, 1}, targets);
  EXPECT_DOUBLE_EQ(q.handle_error, 0.25);
  EXPECT_THROW(compute_metrics(m.V, m.F, m.V.topRows(3), {}, RowMatrixX3d(0, 3)), std::invalid_argument);
}

TEST(Metrics, FinFoldCountsOnlyTheFinsHinges) {
  const auto m = test::grid_with_fin(6, 5);
  EXPECT_EQ(compute_metrics(m.V, m.F, m.V, {}, RowMatrixX3d(0, 3)).mean_dihedral_change, 0.0);
  // Fold the fin flat onto the grid: the hinges with a fin face change by 90 degrees, the
  // grid's own hinges not at all, so the mean lies strictly between.
  RowMatrixX3d folded = m.V;
  for (Eigen::Index v = 6 * 5; v < folded.rows(); ++v) {
    folded(v, 1) += folded(v, 2);
    folded(v, 2) = 0.0;
  }
  const QualityMetrics q = compute_metrics(m.V, m.F, folded, {}, RowMatrixX3d(0, 3));
  EXPECT_GT(q.mean_dihedral_change, 0.1);
  EXPECT_LT(q.mean_dihedral_change, 3.14159265358979323846 / 2);
}
