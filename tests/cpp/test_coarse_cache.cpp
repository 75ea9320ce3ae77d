// CoarseCache: builds the basis once per (constraints, patches, blend), U^T A U once per
// operators, and drops exactly what a change of constraints or of operators makes stale.
#include <gtest/gtest.h>

#include "edgedeform/coarse_cache.h"
#include "grid_lift.h"

using namespace edgedeform;

namespace {

class CoarseCacheTest : public ::testing::Test {
 protected:
  test::GridLift s;
  CoarseCache cache;
  const CoarseBasis* basis(int patches, int blend) {
    return cache.basis(s.system, s.mesh.V, s.topology.edges, patches, blend);
  }
  SparseMatrix operators_A(double lambda) const {
    return assemble_system(s.system, Eigen::VectorXd::Constant(s.graph.n_nodes, lambda)).A;
  }
  // The cache's U^T A U is the one coarse_stiffness computes for `basis` and `A`.
  static bool is_stiffness_of(const SparseMatrix& kept, const CoarseBasis& basis, const SparseMatrix& A) {
    return Eigen::MatrixXd(kept).isApprox(Eigen::MatrixXd(coarse_stiffness(basis, A)));
  }
};

}  // namespace

TEST_F(CoarseCacheTest, TheBasisIsBuiltOncePerConstraintsPatchesAndBlend) {
  EXPECT_EQ(basis(0, 0), nullptr);  // none asked
  const CoarseBasis* b = basis(10, 0);
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(basis(10, 0), b);  // kept
  const int patches = b->n_patches;  // (b is replaced by the next build)
  const CoarseBasis* fewer = basis(4, 0);
  ASSERT_NE(fewer, nullptr);
  EXPECT_LT(fewer->n_patches, patches);
  const size_t disjoint_entries = fewer->entry_patch.size();  // (the next call replaces it)
  const CoarseBasis* blended = basis(4, 3);
  ASSERT_NE(blended, nullptr);
  EXPECT_GT(blended->entry_patch.size(), disjoint_entries);  // blending spreads entries
}

TEST_F(CoarseCacheTest, StiffnessFollowsTheOperatorsAndThePredictorForgets) {
  const CoarseBasis* b = basis(10, 0);
  ASSERT_NE(b, nullptr);
  const SparseMatrix A_soft = operators_A(0.0), A_stiff = operators_A(1.0);
  EXPECT_TRUE(is_stiffness_of(cache.stiffness(A_soft), *b, A_soft));
  // Still the kept one until told the operators changed (the caller owns that knowledge).
  EXPECT_TRUE(is_stiffness_of(cache.stiffness(A_stiff), *b, A_soft));
  cache.predictor().age = 3;
  cache.operators_changed();
  EXPECT_TRUE(is_stiffness_of(cache.stiffness(A_stiff), *b, A_stiff));
  EXPECT_FALSE(cache.predictor().correction.ready());
  EXPECT_GT(cache.predictor().age, kPredictorLag);  // the next prediction reassembles
  EXPECT_EQ(basis(10, 0), b);                       // the basis stays
}

TEST_F(CoarseCacheTest, NewConstraintsDropEverything) {
  const CoarseBasis* b = basis(10, 0);
  ASSERT_NE(b, nullptr);
  ASSERT_TRUE(cache.newton_correction().factor(*b, cache.stiffness(operators_A(0.5))));
  cache.constraints_changed();
  EXPECT_FALSE(cache.newton_correction().ready());
  const CoarseBasis* again = basis(10, 0);
  ASSERT_NE(again, nullptr);  // rebuilt for the constraints it is given now
  const SparseMatrix A_stiff = operators_A(1.0);
  EXPECT_TRUE(is_stiffness_of(cache.stiffness(A_stiff), *again, A_stiff));
}
