// system_restriction: the operators of a constraint set freeing a subset of another's free
// vertices, sliced from the other's, against the set's own assembly -- values, sparsity and
// the right-hand-side operator -- in both domains, with and without a region of interest.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <stdexcept>

#include "mesh/mesh_checks.h"
#include "system/system_restriction.h"
#include "constrained_grid.h"
#include "test_meshes.h"

using namespace edgedeform;

namespace {

constexpr int kNx = test::ConstrainedGrid::kNx;

// The shared grid's sets, optionally within a region of interest, with one more static
// vertex in the part.
struct Case : test::ConstrainedGrid {
  Case(Domain domain, bool with_roi) : ConstrainedGrid(domain) {
    if (with_roi) {
      std::vector<int> roi;
      for (int v = 0; v < static_cast<int>(mesh.V.rows()); ++v)
        if (v % kNx >= 2) roi.push_back(v);  // the two left columns stay out
      whole_sets.roi = roi;
      part_sets.roi = roi;
    }
    part_sets.statics.push_back(2 * kNx + 5);
  }
  ConstrainedSystem whole() const { return ConstrainedGrid::whole(whole_sets); }
  ConstrainedSystem part_layout() const { return layout(part_sets); }
  ConstrainedSystem part_whole() const { return ConstrainedGrid::whole(part_sets); }
};

Eigen::VectorXd random_lambda(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::VectorXd lambda(n);
  for (int i = 0; i < n; ++i) lambda(i) = i % 5 == 0 ? 1.0 : unit(rng);  // some terms exactly rigid
  return lambda;
}

bool same_pattern(const SparseMatrix& a, const SparseMatrix& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols() || a.nonZeros() != b.nonZeros()) return false;
  return std::equal(a.outerIndexPtr(), a.outerIndexPtr() + a.cols() + 1, b.outerIndexPtr()) &&
         std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.innerIndexPtr());
}

class Restriction : public ::testing::TestWithParam<std::tuple<Domain, bool>> {};

}  // namespace

TEST_P(Restriction, SlicedOperatorsEqualTheSetsOwnAssembly) {
  const auto [domain, with_roi] = GetParam();
  const Case c(domain, with_roi);
  const ConstrainedSystem whole = c.whole(), layout = c.part_layout(), own = c.part_whole();
  ASSERT_LT(layout.n_free(), whole.n_free());
  ASSERT_LT(layout.n_terms(), whole.n_terms());  // some terms drop out with the band
  EXPECT_FALSE(layout.has_jacobians);
  EXPECT_TRUE(frees_subset(layout, whole));
  std::mt19937 rng(11);
  for (int pass = 0; pass < 2; ++pass) {  // lambda < 1 somewhere; then lambda = 1 everywhere
    const Eigen::VectorXd lambda = pass == 0 ? random_lambda(c.g.n_vertices, rng) : Eigen::VectorXd::Ones(c.g.n_vertices);
    ASSERT_TRUE(restriction_keeps_pattern(whole, layout, lambda));
    const AssembledSystem sliced = restrict_assembly(assemble_system(whole, lambda), whole, layout, lambda);
    const AssembledSystem expected = assemble_system(own, lambda);
    EXPECT_EQ(sliced.laplacian_term, expected.laplacian_term);
    EXPECT_EQ(sliced.term_lambda, expected.term_lambda);
    // The same sparsity: the kept elimination order meets the pattern it would have met.
    EXPECT_TRUE(same_pattern(sliced.A, expected.A)) << pass;
    EXPECT_TRUE(same_pattern(sliced.K_fixed, expected.K_fixed)) << pass;
    const Eigen::MatrixXd A = expected.A, K = expected.K_fixed;
    EXPECT_LT((Eigen::MatrixXd(sliced.A) - A).norm(), 1e-14 * A.norm()) << pass;
    EXPECT_LT((Eigen::MatrixXd(sliced.K_fixed) - K).norm(), 1e-14 * A.norm()) << pass;
    // H: the same right side for random rotations and scales.
    ASSERT_EQ(sliced.H.rows(), expected.H.rows());
    ASSERT_EQ(sliced.H.terms(), expected.H.terms());
    EXPECT_EQ(sliced.H.blocks(), expected.H.blocks());
    std::vector<Eigen::Matrix3d> rotation(static_cast<size_t>(own.n_terms()));
    for (auto& R : rotation) R = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
    const Eigen::VectorXd scale = Eigen::VectorXd::Random(own.n_terms()).array() + 1.5;
    const Eigen::MatrixXd rhs_c = Eigen::MatrixXd::Random(own.n_free(), 3);
    Eigen::MatrixXd y_sliced, y_expected;
    sliced.H.apply(rotation, scale, rhs_c, y_sliced);
    expected.H.apply(rotation, scale, rhs_c, y_expected);
    EXPECT_LT((y_sliced - y_expected).cwiseAbs().maxCoeff(), 1e-13 * y_expected.cwiseAbs().maxCoeff()) << pass;
  }
}

TEST_P(Restriction, RefusesASetThatFreesMoreOrAnotherStiffness) {
  const auto [domain, with_roi] = GetParam();
  const Case c(domain, with_roi);
  // The roles reversed: the whole set is not within the part.
  const ConstrainedSystem part = c.part_whole(), whole_layout = constrained_layout(c.g, c.mesh.V, c.neighbours(),
                                                                                     c.referenced, c.whole_sets);
  EXPECT_FALSE(frees_subset(whole_layout, part));
  const Eigen::VectorXd half = Eigen::VectorXd::Constant(c.g.n_vertices, 0.5);
  EXPECT_FALSE(restriction_keeps_pattern(part, whole_layout, half));
  const AssembledSystem part_assembled = assemble_system(part, half);
  EXPECT_THROW(restrict_assembly(part_assembled, part, whole_layout, half), std::logic_error);
  // The right sets, but the whole set's operators hold another lambda.
  const ConstrainedSystem whole = c.whole(), layout = c.part_layout();
  const AssembledSystem whole_assembled = assemble_system(whole, half);
  EXPECT_THROW(restrict_assembly(whole_assembled, whole, layout, Eigen::VectorXd::Constant(c.g.n_vertices, 0.25)),
               std::logic_error);
  // A layout has no J1, J2 to assemble from.
  EXPECT_THROW(assemble_system(layout, half), std::logic_error);
}

TEST_P(Restriction, ARigidPartOfASmoothWholeKeepsNoLaplacianPattern) {
  const auto [domain, with_roi] = GetParam();
  const Case c(domain, with_roi);
  const ConstrainedSystem whole = c.whole(), layout = c.part_layout();
  // lambda = 1 on the part's terms, below 1 on a term only the whole set has: a vertex of
  // that term's node that no node of the part's terms uses is softened.
  Eigen::VectorXd lambda = Eigen::VectorXd::Ones(c.g.n_vertices);
  std::vector<bool> in_part(static_cast<size_t>(c.g.n_vertices), false);
  for (int i : layout.term_nodes)
    for (int k = 0; k < 2; ++k) in_part[static_cast<size_t>(c.g.node_vertices(i, k))] = true;
  int only_whole = -1;
  for (int i : whole.term_nodes)
    for (int k = 0; k < 2; ++k)
      if (!in_part[static_cast<size_t>(c.g.node_vertices(i, k))]) only_whole = c.g.node_vertices(i, k);
  ASSERT_GE(only_whole, 0);
  lambda(only_whole) = 0.5;
  EXPECT_FALSE(restriction_keeps_pattern(whole, layout, lambda));
  lambda(only_whole) = 1.0;
  EXPECT_TRUE(restriction_keeps_pattern(whole, layout, lambda));
}

INSTANTIATE_TEST_SUITE_P(DomainsAndRegion, Restriction,
                         ::testing::Combine(::testing::Values(Domain::Edge, Domain::Primal), ::testing::Bool()),
                         [](const auto& info) {
                           return std::string(domain_name(std::get<0>(info.param))) +
                                  (std::get<1>(info.param) ? "_roi" : "_whole");
                         });
