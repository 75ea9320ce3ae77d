// The incremental paths of the Deformer (a change of lambda, a handle group added or
// removed, a vertex pinned) give the positions a fresh Deformer gives for the same state.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "edgedeform/deformer.h"
#include "test_meshes.h"

using namespace edgedeform;

namespace {

struct Edit {
  test::TestMesh mesh = test::read_off("cgal_dino.off");
  std::vector<int> low, high, belt;  // lowest 20 %, top 10 %, a band at 55 % of the height
  explicit Edit() {
    const Eigen::VectorXd z = mesh.V.col(2);
    const double zmin = z.minCoeff(), h = z.maxCoeff() - zmin;
    for (int v = 0; v < z.size(); ++v) {
      const double f = (z(v) - zmin) / h;
      if (f < 0.2) low.push_back(v);
      if (f > 0.9) high.push_back(v);
      if (f > 0.53 && f < 0.57) belt.push_back(v);
    }
  }
  // Handles' targets: the top raised, anything else where it is.
  RowMatrixX3d targets(const std::vector<int>& handles) const {
    RowMatrixX3d out(handles.size(), 3);
    for (size_t k = 0; k < handles.size(); ++k) {
      out.row(k) = mesh.V.row(handles[k]);
      if (k < high.size()) out(k, 2) += 0.3;
    }
    return out;
  }
};

SolveResult five_cold_iterations(Deformer& d, const RowMatrixX3d& targets) {
  SolveOptions o;
  o.max_iterations = 5;
  o.tolerance = 0.0;
  o.warm_start = false;
  return d.solve(targets, o);
}

double relative_difference(const RowMatrixX3d& a, const RowMatrixX3d& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

std::vector<int> joined(std::vector<int> a, const std::vector<int>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

RowMatrixX3d fresh_positions(const Edit& e, Domain domain, double lambda, const ConstraintSets& sets) {
  Deformer f(e.mesh.V, e.mesh.F, domain);
  f.set_stiffness(lambda);
  f.set_constraints(sets);
  return five_cold_iterations(f, e.targets(sets.handles)).positions;
}

class IncrementalFactor : public ::testing::TestWithParam<Domain> {};

}  // namespace

TEST_P(IncrementalFactor, HandleGroupAddedThenRemovedMatchesAFreshDeformer) {
  const Domain domain = GetParam();
  Edit e;
  ASSERT_GT(e.belt.size(), 20u);
  Deformer d(e.mesh.V, e.mesh.F, domain);
  d.set_stiffness(0.5);
  d.set_constraints({e.high, e.low, std::nullopt});
  five_cold_iterations(d, e.targets(e.high));
  const double first_fill = d.factor_nonzeros();

  const ConstraintSets more{joined(e.high, e.belt), e.low, std::nullopt};
  d.set_constraints(more);
  const SolveResult added = five_cold_iterations(d, e.targets(more.handles));
  EXPECT_LT(relative_difference(added.positions, fresh_positions(e, domain, 0.5, more)), 1e-9);
  // The reused order eliminates a subset: never more fill than the whole had.
  EXPECT_LE(d.factor_nonzeros(), first_fill);
  EXPECT_GT(d.factor_nonzeros(), 0.0);

  const ConstraintSets back{e.high, e.low, std::nullopt};
  d.set_constraints(back);
  const SolveResult removed = five_cold_iterations(d, e.targets(back.handles));
  EXPECT_LT(relative_difference(removed.positions, fresh_positions(e, domain, 0.5, back)), 1e-9);
  EXPECT_EQ(d.factor_nonzeros(), first_fill);
  if (std::string(SparseCholesky::backend()) == "cholmod-supernodal") {
    EXPECT_EQ(d.analyses(), 3);
    EXPECT_EQ(d.orderings(), 1);  // the first set's order, reused twice
  }
}

TEST_P(IncrementalFactor, PinningOneVertexMatchesAFreshDeformer) {
  const Domain domain = GetParam();
  Edit e;
  Deformer d(e.mesh.V, e.mesh.F, domain);
  d.set_stiffness(0.3);
  d.set_constraints({e.high, e.low, std::nullopt});
  five_cold_iterations(d, e.targets(e.high));
  const ConstraintSets pinned{e.high, joined(e.low, {e.belt[0]}), std::nullopt};
  d.set_constraints(pinned);
  const SolveResult r = five_cold_iterations(d, e.targets(pinned.handles));
  EXPECT_LT(relative_difference(r.positions, fresh_positions(e, domain, 0.3, pinned)), 1e-9);
}

TEST_P(IncrementalFactor, StiffnessChangeMatchesAFreshDeformerWithoutANewAnalysis) {
  const Domain domain = GetParam();
  Edit e;
  const ConstraintSets sets{e.high, e.low, std::nullopt};
  Deformer d(e.mesh.V, e.mesh.F, domain);
  d.set_stiffness(0.5);
  d.set_constraints(sets);
  five_cold_iterations(d, e.targets(e.high));
  for (double lambda : {0.0, 0.8, 0.5}) {
    d.set_stiffness(lambda);
    const SolveResult r = five_cold_iterations(d, e.targets(e.high));
    EXPECT_GT(r.factor_ms, 0.0);
    EXPECT_LT(relative_difference(r.positions, fresh_positions(e, domain, lambda, sets)), 1e-9) << lambda;
  }
  EXPECT_EQ(d.analyses(), 1);
}

TEST_P(IncrementalFactor, FreeingVerticesNeverFreeBeforeMatchesAFreshDeformer) {
  // The first set's handles become free: they have no rank in the kept order, so the
  // factorization orders anew.
  const Domain domain = GetParam();
  Edit e;
  Deformer d(e.mesh.V, e.mesh.F, domain);
  d.set_stiffness(0.5);
  d.set_constraints({joined(e.high, e.belt), e.low, std::nullopt});
  five_cold_iterations(d, e.targets(joined(e.high, e.belt)));
  const ConstraintSets fewer{e.high, e.low, std::nullopt};
  d.set_constraints(fewer);
  const SolveResult r = five_cold_iterations(d, e.targets(fewer.handles));
  EXPECT_EQ(d.orderings(), 2);
  EXPECT_LT(relative_difference(r.positions, fresh_positions(e, domain, 0.5, fewer)), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(BothDomains, IncrementalFactor, ::testing::Values(Domain::Edge, Domain::Primal),
                         [](const auto& info) { return std::string(domain_name(info.param)); });
