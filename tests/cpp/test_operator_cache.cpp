// operator_cache: a constraint set within the base set's free vertices takes its operators
// by restriction (no assembly), a new stiffness updates the base's values in place, and a
// set freeing more (or a rigid part of a soft base) becomes the base.
#include <gtest/gtest.h>

#include "constrained_grid.h"
#include "system/operator_cache.h"

using namespace edgedeform;

namespace {

using Grid = test::ConstrainedGrid;

double relative_difference(const SparseMatrix& a, const SparseMatrix& b) {
  return (Eigen::MatrixXd(a) - Eigen::MatrixXd(b)).cwiseAbs().maxCoeff() / Eigen::MatrixXd(b).cwiseAbs().maxCoeff();
}

class OperatorCacheTest : public ::testing::TestWithParam<Domain> {};

}  // namespace

TEST_P(OperatorCacheTest, ASubsetIsRestrictedInsteadOfReassembled) {
  const Grid c(GetParam());
  const Eigen::VectorXd lambda = Eigen::VectorXd::Constant(c.g.n_vertices, 0.5);
  OperatorCache cache;
  auto whole = cache.set_system(c.layout(c.whole_sets));
  EXPECT_TRUE(whole->has_jacobians);  // the first set is the base
  auto base_ops = cache.operators_for(*whole, lambda);
  EXPECT_TRUE(cache.is_base(base_ops));
  EXPECT_EQ(cache.assemblies(), 1);

  auto part = cache.set_system(c.layout(c.part_sets));
  EXPECT_FALSE(part->has_jacobians);  // within the base: a layout only
  auto part_ops = cache.operators_for(*part, lambda);
  EXPECT_FALSE(cache.is_base(part_ops));
  EXPECT_EQ(cache.assemblies(), 1);
  const AssembledSystem own = assemble_system(c.whole(c.part_sets), lambda);
  ASSERT_EQ(part_ops->A.rows(), own.A.rows());
  EXPECT_LT(relative_difference(part_ops->A, own.A), 1e-12);
  EXPECT_LT(relative_difference(part_ops->K_fixed, own.K_fixed), 1e-12);

  // Released again: the base's operators themselves, still one assembly.
  auto back = cache.set_system(c.layout(c.whole_sets));
  EXPECT_FALSE(back->has_jacobians);
  EXPECT_EQ(cache.operators_for(*back, lambda), base_ops);
  EXPECT_EQ(cache.assemblies(), 1);
}

TEST_P(OperatorCacheTest, AStiffnessChangeUpdatesTheBaseInPlace) {
  const Grid c(GetParam());
  OperatorCache cache;
  auto sys = cache.set_system(c.layout(c.whole_sets));
  auto first = cache.operators_for(*sys, Eigen::VectorXd::Constant(c.g.n_vertices, 0.5));
  const long values = cache.base_values();
  EXPECT_EQ(cache.operators_for(*sys, Eigen::VectorXd::Constant(c.g.n_vertices, 0.5)), first);
  EXPECT_EQ(cache.base_values(), values);  // same stiffness: the same values

  const Eigen::VectorXd soft = Eigen::VectorXd::Constant(c.g.n_vertices, 0.2);
  auto second = cache.operators_for(*sys, soft);
  EXPECT_EQ(cache.base_values(), values + 1);
  EXPECT_EQ(cache.assemblies(), 1);
  EXPECT_LT(relative_difference(second->A, assemble_system(c.whole(c.whole_sets), soft).A), 1e-12);
}

TEST_P(OperatorCacheTest, ASetFreeingMoreBecomesTheBase) {
  const Grid c(GetParam());
  const Eigen::VectorXd lambda = Eigen::VectorXd::Constant(c.g.n_vertices, 0.5);
  OperatorCache cache;
  auto part = cache.set_system(c.layout(c.part_sets));
  cache.operators_for(*part, lambda);
  auto whole = cache.set_system(c.layout(c.whole_sets));  // frees the band too
  EXPECT_TRUE(whole->has_jacobians);
  auto ops = cache.operators_for(*whole, lambda);
  EXPECT_TRUE(cache.is_base(ops));
  EXPECT_EQ(cache.assemblies(), 2);
}

TEST_P(OperatorCacheTest, ARigidPartOfASoftBaseIsAssembledOnItsOwn) {
  // Restricted, the part's A would carry the Laplacian's pattern as explicit zeros.
  const Grid c(GetParam());
  OperatorCache cache;
  auto whole = cache.set_system(c.layout(c.whole_sets));
  auto part = cache.set_system(c.layout(c.part_sets));
  Eigen::VectorXd lambda = Eigen::VectorXd::Constant(c.g.n_vertices, 0.5);
  for (int node : part->term_nodes)  // every vertex of the part's term nodes rigid
    for (int k = 0; k < 2; ++k) lambda(c.g.node_vertices(node, k)) = 1.0;
  ASSERT_LT(part->term_nodes.size(), whole->term_nodes.size());
  auto ops = cache.operators_for(*part, lambda);
  EXPECT_FALSE(ops->laplacian_term);
  EXPECT_TRUE(cache.is_base(ops));
  EXPECT_EQ(cache.assemblies(), 1);  // the whole set was never assembled
  EXPECT_EQ(ops->A.nonZeros(), assemble_system(c.whole(c.part_sets), lambda).A.nonZeros());
}

INSTANTIATE_TEST_SUITE_P(Domains, OperatorCacheTest, ::testing::Values(Domain::Edge, Domain::Primal));
