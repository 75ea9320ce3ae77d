// The incremental paths of the Deformer (a change of lambda, a handle group added or
// removed, a vertex pinned) give the positions a fresh Deformer gives for the same state.
#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "deformer/deformer.h"
#include "mesh/mesh_checks.h"
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

RowMatrixX3d fresh_positions(const Edit& e, Domain domain, const Eigen::VectorXd& vertex_lambda,
                             const ConstraintSets& sets) {
  Deformer f(e.mesh.V, e.mesh.F, domain);
  f.set_stiffness(vertex_lambda);
  f.set_constraints(sets);
  return five_cold_iterations(f, e.targets(sets.handles)).positions;
}

RowMatrixX3d fresh_positions(const Edit& e, Domain domain, double lambda, const ConstraintSets& sets) {
  return fresh_positions(e, domain, Eigen::VectorXd::Constant(e.mesh.V.rows(), lambda), sets);
}

class IncrementalFactor : public ::testing::TestWithParam<Domain> {};

// Domain, lambda, with a region of interest.
class RestrictedHandleSets : public ::testing::TestWithParam<std::tuple<Domain, double, bool>> {};

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
  EXPECT_EQ(d.factorizations(), 2);  // released: the first set's factorization, kept aside

  d.set_constraints(more);  // pinned again: the belt's analysis, kept aside in turn
  const SolveResult again = five_cold_iterations(d, e.targets(more.handles));
  EXPECT_LT(relative_difference(again.positions, added.positions), 1e-12);
  EXPECT_EQ(d.factorizations(), 3);
  EXPECT_EQ(d.assemblies(), 1);  // the belt's operators were sliced from the first set's
  if (std::string(SparseCholesky::backend()) == "cholmod-supernodal") {
    EXPECT_EQ(d.analyses(), 2);
    EXPECT_EQ(d.orderings(), 1);  // the first set's order, reused for the belt
  }
}

TEST_P(IncrementalFactor, LambdaChangeWhileAGroupIsPinnedRefactorsTheBaseWhenReleased) {
  // The base set's kept factorization holds the old lambda: releasing the group after a
  // lambda change must factor again, not swap the stale factor back.
  const Domain domain = GetParam();
  Edit e;
  Deformer d(e.mesh.V, e.mesh.F, domain);
  d.set_stiffness(0.5);
  const ConstraintSets first{e.high, e.low, std::nullopt};
  d.set_constraints(first);
  five_cold_iterations(d, e.targets(e.high));
  const ConstraintSets more{joined(e.high, e.belt), e.low, std::nullopt};
  d.set_constraints(more);
  five_cold_iterations(d, e.targets(more.handles));
  d.set_stiffness(0.3);
  five_cold_iterations(d, e.targets(more.handles));
  d.set_constraints(first);
  const SolveResult r = five_cold_iterations(d, e.targets(first.handles));
  EXPECT_EQ(d.factorizations(), 4);
  EXPECT_LT(relative_difference(r.positions, fresh_positions(e, domain, 0.3, first)), 1e-9);
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

TEST_P(IncrementalFactor, LambdaAcrossOneOrdersTheNewPatternAfresh) {
  // Lambda = 1 everywhere drops the Laplacian's pattern from A. The order kept from the
  // other pattern fills badly (4.9x the factor of a fresh Deformer on koala), so a crossing
  // orders anew (AMD); its factor stays near a fresh Deformer's least-fill one.
  const Domain domain = GetParam();
  Edit e;
  const ConstraintSets sets{e.high, e.low, std::nullopt};
  for (const auto& [from, to] : {std::pair{1.0, 0.5}, std::pair{0.5, 1.0}}) {
    Deformer d(e.mesh.V, e.mesh.F, domain);
    d.set_stiffness(from);
    d.set_constraints(sets);
    five_cold_iterations(d, e.targets(e.high));
    d.set_stiffness(to);
    const SolveResult r = five_cold_iterations(d, e.targets(e.high));
    Deformer fresh(e.mesh.V, e.mesh.F, domain);
    fresh.set_stiffness(to);
    fresh.set_constraints(sets);
    five_cold_iterations(fresh, e.targets(e.high));
    if (std::string(SparseCholesky::backend()) == "cholmod-supernodal") {
      EXPECT_EQ(d.orderings(), 2) << from << " -> " << to;
      EXPECT_LT(d.factor_nonzeros(), 1.2 * fresh.factor_nonzeros()) << from << " -> " << to;
    }
    EXPECT_LT(relative_difference(r.positions, fresh_positions(e, domain, to, sets)), 1e-9) << from << " -> " << to;
    // Back and forth again: each pattern keeps its order, nothing is ordered anew.
    for (double lambda : {from, to, from}) {
      d.set_stiffness(lambda);
      const SolveResult again = five_cold_iterations(d, e.targets(e.high));
      EXPECT_LT(relative_difference(again.positions, fresh_positions(e, domain, lambda, sets)), 1e-9) << lambda;
    }
    if (std::string(SparseCholesky::backend()) == "cholmod-supernodal") EXPECT_EQ(d.orderings(), 2);
  }
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

TEST_P(IncrementalFactor, RigidRemainderOfAPaintedMeshAssemblesItsOwnSystem) {
  // Lambda < 1 only just above the static vertices; pinning that band leaves lambda = 1 on
  // every remaining term. Sliced from the first set, A would keep the Laplacian's pattern:
  // the set is assembled whole instead.
  const Domain domain = GetParam();
  Edit e;
  const Eigen::VectorXd z = e.mesh.V.col(2);
  const double zmin = z.minCoeff(), h = z.maxCoeff() - zmin;
  Eigen::VectorXd lambda = Eigen::VectorXd::Ones(z.size());
  std::vector<int> band;
  for (int v = 0; v < z.size(); ++v) {
    const double f = (z(v) - zmin) / h;
    if (f >= 0.2 && f < 0.3) lambda(v) = 0.4;
    if (f >= 0.2 && f < 0.45) band.push_back(v);
  }
  Deformer d(e.mesh.V, e.mesh.F, domain);
  d.set_stiffness(lambda);
  d.set_constraints({e.high, e.low, std::nullopt});
  five_cold_iterations(d, e.targets(e.high));
  const ConstraintSets pinned{e.high, joined(e.low, band), std::nullopt};
  const ConstrainedSystem layout = constrained_layout(d.graph(), d.rest(), d.neighbours(),
                                                      referenced_vertices(d.faces(), d.n_vertices()), pinned);
  const Eigen::VectorXd node_lambda = d.node_lambda();
  for (int i : layout.term_nodes) ASSERT_EQ(node_lambda(i), 1.0) << "the band does not cover lambda < 1";
  d.set_constraints(pinned);
  const SolveResult r = five_cold_iterations(d, e.targets(pinned.handles));
  EXPECT_EQ(d.assemblies(), 2);
  EXPECT_LT(relative_difference(r.positions, fresh_positions(e, domain, lambda, pinned)), 1e-9);
}

TEST_P(RestrictedHandleSets, GroupAddedVertexPinnedLambdaChangedGroupRemovedMatchAFreshDeformer) {
  const auto [domain, lambda, with_roi] = GetParam();
  Edit e;
  std::optional<std::vector<int>> roi;
  if (with_roi) {  // the half with x above the median; the other half stays at rest
    std::vector<double> x(e.mesh.V.col(0).data(), e.mesh.V.col(0).data() + e.mesh.V.rows());
    std::nth_element(x.begin(), x.begin() + static_cast<long>(x.size() / 2), x.end());
    roi.emplace();
    for (int v = 0; v < e.mesh.V.rows(); ++v)
      if (e.mesh.V(v, 0) > x[x.size() / 2]) roi->push_back(v);
  }
  const double other_lambda = lambda == 1.0 ? 0.6 : 1.0;  // across the Laplacian's pattern
  Deformer d(e.mesh.V, e.mesh.F, domain);
  d.set_stiffness(lambda);
  const ConstraintSets first{e.high, e.low, roi};
  d.set_constraints(first);
  five_cold_iterations(d, e.targets(e.high));
  const ConstraintSets belt{joined(e.high, e.belt), e.low, roi};
  const ConstraintSets pin{e.high, joined(e.low, {e.belt[e.belt.size() / 2]}), roi};
  struct Step {
    const ConstraintSets* sets;
    double lambda;
  };
  for (const Step& step : {Step{&belt, lambda}, Step{&pin, lambda}, Step{&belt, lambda}, Step{&belt, other_lambda},
                           Step{&first, other_lambda}}) {
    d.set_stiffness(step.lambda);
    d.set_constraints(*step.sets);
    const SolveResult r = five_cold_iterations(d, e.targets(step.sets->handles));
    const RowMatrixX3d fresh = fresh_positions(e, domain, step.lambda, *step.sets);
    double moved = 0.0;  // the largest move of a vertex that is not a handle
    std::vector<bool> handle(static_cast<size_t>(e.mesh.V.rows()), false);
    for (int v : step.sets->handles) handle[static_cast<size_t>(v)] = true;
    for (int v = 0; v < e.mesh.V.rows(); ++v)
      if (!handle[static_cast<size_t>(v)]) moved = std::max(moved, (fresh.row(v) - e.mesh.V.row(v)).norm());
    EXPECT_GT(moved, 1e-3);
    EXPECT_LT(relative_difference(r.positions, fresh), 1e-9)
        << step.sets->handles.size() << " handles, lambda " << step.lambda;
  }
  EXPECT_EQ(d.assemblies(), 1);  // every later set was sliced from the first one's operators
  // The first set's order, reused for the belt, the pin and the belt again; a new one where
  // lambda crosses the Laplacian's pattern (belt); and one for the first set at that lambda,
  // which frees the belt, unranked in the belt's order.
  if (std::string(SparseCholesky::backend()) == "cholmod-supernodal") EXPECT_EQ(d.orderings(), 3);
}

INSTANTIATE_TEST_SUITE_P(DomainsStiffnessRegion, RestrictedHandleSets,
                         ::testing::Combine(::testing::Values(Domain::Edge, Domain::Primal), ::testing::Values(0.5, 1.0),
                                            ::testing::Bool()),
                         [](const auto& info) {
                           return std::string(domain_name(std::get<0>(info.param))) +
                                  (std::get<1>(info.param) == 1.0 ? "_rigid" : "_half") +
                                  (std::get<2>(info.param) ? "_roi" : "_whole");
                         });

INSTANTIATE_TEST_SUITE_P(BothDomains, IncrementalFactor, ::testing::Values(Domain::Edge, Domain::Primal),
                         [](const auto& info) { return std::string(domain_name(info.param)); });
