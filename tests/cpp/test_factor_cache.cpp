// factor_cache: a repeated request factors once; a released handle group swaps the base's
// factor back without refactoring, and pinning it again finds its analysis; new base values
// refactor; each pattern of A is ordered once and its order reused.
#include <gtest/gtest.h>

#include <string>

#include "constrained_grid.h"
#include "system/factor_cache.h"
#include "system/operator_cache.h"

using namespace edgedeform;

namespace {

using Grid = test::ConstrainedGrid;

bool cholmod() { return std::string(SparseCholesky::backend()) == "cholmod-supernodal"; }

// Relative residual of A x = b solved with `factor`.
double solve_residual(SparseCholesky& factor, const SparseMatrix& A) {
  const Eigen::MatrixXd b = Eigen::MatrixXd::Ones(A.rows(), 3);
  Eigen::MatrixXd x;
  factor.solve(b, x);
  return (A * x - b).norm() / b.norm();
}

// The operator and factor caches as the Deformer wires them.
struct Caches {
  OperatorCache operators;
  FactorCache factors;
  std::shared_ptr<const AssembledSystem> ops;
  SparseCholesky& request(const std::shared_ptr<const ConstrainedSystem>& sys, const Eigen::VectorXd& lambda) {
    ops = operators.operators_for(*sys, lambda);
    return factors.factor_for(*sys, *ops, operators.is_base(ops), operators.base_values());
  }
};

class FactorCacheTest : public ::testing::TestWithParam<Domain> {};

}  // namespace

TEST_P(FactorCacheTest, ARepeatedRequestFactorsOnce) {
  const Grid c(GetParam());
  const Eigen::VectorXd lambda = Eigen::VectorXd::Constant(c.g.n_vertices, 0.5);
  Caches k;
  auto sys = k.operators.set_system(c.layout(c.whole_sets));
  k.request(sys, lambda);
  SparseCholesky& f = k.request(sys, lambda);
  EXPECT_EQ(k.factors.factorizations(), 1);
  EXPECT_EQ(k.factors.analyses(), 1);
  EXPECT_EQ(&f, &k.factors.factor());
  EXPECT_LT(solve_residual(f, k.ops->A), 1e-10);
}

TEST_P(FactorCacheTest, AReleasedGroupSwapsTheBaseFactorBack) {
  const Grid c(GetParam());
  const Eigen::VectorXd lambda = Eigen::VectorXd::Constant(c.g.n_vertices, 0.5);
  Caches k;
  auto whole = k.operators.set_system(c.layout(c.whole_sets));
  k.request(whole, lambda);
  auto part = k.operators.set_system(c.layout(c.part_sets));  // a group pinned
  SparseCholesky& part_factor = k.request(part, lambda);
  EXPECT_LT(solve_residual(part_factor, k.ops->A), 1e-10);
  EXPECT_EQ(k.factors.factorizations(), 2);

  whole = k.operators.set_system(c.layout(c.whole_sets));  // released
  SparseCholesky& base = k.request(whole, lambda);
  EXPECT_EQ(k.factors.factorizations(), 2);  // swapped back, not refactored
  EXPECT_LT(solve_residual(base, k.ops->A), 1e-10);

  part = k.operators.set_system(c.layout(c.part_sets));  // pinned again
  SparseCholesky& again = k.request(part, lambda);
  EXPECT_LT(solve_residual(again, k.ops->A), 1e-10);
  EXPECT_EQ(k.factors.factorizations(), 3);
  if (cholmod()) {
    EXPECT_EQ(k.factors.analyses(), 2);   // the part's analysis was kept aside
    EXPECT_EQ(k.factors.orderings(), 1);  // the part was ordered by the whole set's order
  }
}

TEST_P(FactorCacheTest, NewBaseValuesRefactorInsteadOfSwappingAStaleFactor) {
  const Grid c(GetParam());
  Caches k;
  auto whole = k.operators.set_system(c.layout(c.whole_sets));
  k.request(whole, Eigen::VectorXd::Constant(c.g.n_vertices, 0.5));
  auto part = k.operators.set_system(c.layout(c.part_sets));
  k.request(part, Eigen::VectorXd::Constant(c.g.n_vertices, 0.5));
  const Eigen::VectorXd soft = Eigen::VectorXd::Constant(c.g.n_vertices, 0.3);
  k.request(part, soft);  // the base's values change while the group is pinned
  EXPECT_EQ(k.factors.factorizations(), 3);
  whole = k.operators.set_system(c.layout(c.whole_sets));
  SparseCholesky& base = k.request(whole, soft);
  EXPECT_EQ(k.factors.factorizations(), 4);
  EXPECT_LT(solve_residual(base, k.ops->A), 1e-10);
}

TEST_P(FactorCacheTest, EachPatternOfAIsOrderedOnce) {
  if (!cholmod()) GTEST_SKIP() << "the Eigen fallback orders by itself";
  const Grid c(GetParam());
  Caches k;
  auto sys = k.operators.set_system(c.layout(c.whole_sets));
  const Eigen::VectorXd soft = Eigen::VectorXd::Constant(c.g.n_vertices, 0.5);
  const Eigen::VectorXd rigid = Eigen::VectorXd::Ones(c.g.n_vertices);
  k.request(sys, soft);   // Laplacian pattern: least fill
  k.request(sys, rigid);  // lambda = 1 everywhere: another pattern, ordered once
  EXPECT_EQ(k.factors.orderings(), 2);
  k.request(sys, soft);   // back: re-analyzed with the remembered order
  k.request(sys, rigid);
  EXPECT_EQ(k.factors.orderings(), 2);
  EXPECT_EQ(k.factors.analyses(), 4);
  EXPECT_EQ(k.factors.factorizations(), 4);
  EXPECT_LT(solve_residual(k.factors.factor(), k.ops->A), 1e-10);
}

INSTANTIATE_TEST_SUITE_P(Domains, FactorCacheTest, ::testing::Values(Domain::Edge, Domain::Primal));
