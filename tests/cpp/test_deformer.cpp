#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "deformer/deformer.h"
#include "base/errors.h"
#include "test_meshes.h"

using namespace edgedeform;

namespace {

// The dinosaur with its lowest 20% static and its top 10% as the handle.
struct LiftSetup {
  test::TestMesh mesh;
  std::vector<int> low, high;
  explicit LiftSetup(const char* file = "cgal_dino.off") : mesh(test::read_off(file)) {
    const Eigen::VectorXd z = mesh.V.col(2);
    const double zmin = z.minCoeff(), zmax = z.maxCoeff();
    for (int v = 0; v < z.size(); ++v) {
      if (z(v) < zmin + 0.2 * (zmax - zmin)) low.push_back(v);
      if (z(v) > zmin + 0.9 * (zmax - zmin)) high.push_back(v);
    }
  }
  RowMatrixX3d rows(const RowMatrixX3d& X, const std::vector<int>& idx) const {
    RowMatrixX3d out(idx.size(), 3);
    for (size_t k = 0; k < idx.size(); ++k) out.row(k) = X.row(idx[k]);
    return out;
  }
};

class DeformerBothDomains : public ::testing::TestWithParam<std::tuple<Domain, double>> {};

}  // namespace

TEST_P(DeformerBothDomains, ZeroDisplacementReturnsTheRestShape) {
  const auto [domain, lambda] = GetParam();
  LiftSetup s;
  Deformer d(s.mesh.V, s.mesh.F, domain);
  d.set_constraints({s.high, s.low, std::nullopt});
  d.set_stiffness(lambda);
  SolveOptions o;
  o.max_iterations = 3;
  const SolveResult r = d.solve(s.rows(s.mesh.V, s.high), o);
  EXPECT_LT((r.positions - s.mesh.V).norm(), 1e-9 * s.mesh.V.norm());
}

TEST_P(DeformerBothDomains, RigidlyMovedShapeIsAFixedPoint) {
  const auto [domain, lambda] = GetParam();
  LiftSetup s;
  std::vector<int> handles = s.high;
  handles.insert(handles.end(), s.low.begin(), s.low.end());
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  const RowMatrixX3d moved = (s.mesh.V * Q.transpose()).rowwise() + Eigen::RowVector3d(0.3, -1, 2);
  Deformer d(s.mesh.V, s.mesh.F, domain);
  d.set_constraints({handles, {}, std::nullopt});
  d.set_stiffness(lambda);
  SolveOptions o;
  o.max_iterations = 3;
  o.initial = moved;
  const SolveResult r = d.solve(s.rows(moved, handles), o);
  EXPECT_LT((r.positions - moved).norm(), 1e-9 * moved.norm());
  EXPECT_TRUE(r.converged);
}

INSTANTIATE_TEST_SUITE_P(LambdaAndDomain, DeformerBothDomains,
                         ::testing::Combine(::testing::Values(Domain::Edge, Domain::Primal),
                                            ::testing::Values(0.0, 0.5, 1.0)),
                         [](const auto& info) {
                           const double lambda = std::get<1>(info.param);
                           return std::string(domain_name(std::get<0>(info.param))) + "_lambda" +
                                  std::to_string(static_cast<int>(lambda * 10));
                         });

TEST(Deformer, HandlesSitOnTargetsAndStaticStaysAtRest) {
  LiftSetup s;
  Deformer d(s.mesh.V, s.mesh.F, Domain::Edge);
  d.set_constraints({s.high, s.low, std::nullopt});
  RowMatrixX3d targets = s.rows(s.mesh.V, s.high);
  targets.col(2).array() += 0.4;
  SolveOptions o;
  o.max_iterations = 5;
  const SolveResult r = d.solve(targets, o);
  EXPECT_EQ(s.rows(r.positions, s.high), targets);
  EXPECT_EQ(s.rows(r.positions, s.low), s.rows(s.mesh.V, s.low));
  EXPECT_GT((r.positions - s.mesh.V).cwiseAbs().maxCoeff(), 0.1);
}

TEST(Deformer, RigidEnergyNeverIncreases) {
  LiftSetup s;
  for (Domain domain : {Domain::Edge, Domain::Primal}) {
    Deformer d(s.mesh.V, s.mesh.F, domain);
    d.set_constraints({s.high, s.low, std::nullopt});
    d.set_stiffness(1.0);
    RowMatrixX3d targets = s.rows(s.mesh.V, s.high);
    targets.col(2).array() += 0.6;
    SolveOptions o;
    o.max_iterations = 30;
    o.tolerance = 0.0;
    const SolveResult r = d.solve(targets, o);
    for (size_t k = 1; k < r.energies.size(); ++k) EXPECT_LE(r.energies[k], r.energies[k - 1] * (1 + 1e-12));
  }
}

TEST(Deformer, ChangingStiffnessKeepsTheSymbolicAnalysis) {
  LiftSetup s;
  Deformer d(s.mesh.V, s.mesh.F, Domain::Edge);
  d.set_constraints({s.high, s.low, std::nullopt});
  const RowMatrixX3d targets = s.rows(s.mesh.V, s.high);
  SolveOptions o;
  o.max_iterations = 1;
  d.set_stiffness(0.2);
  d.solve(targets, o);
  d.set_stiffness(0.7);
  const SolveResult r = d.solve(targets, o);
  EXPECT_GT(r.factor_ms, 0.0);
  EXPECT_EQ(d.analyses(), 1);
}

TEST(Deformer, FailedCallsLeaveItUsable) {
  LiftSetup s;
  Deformer d(s.mesh.V, s.mesh.F, Domain::Edge);
  d.set_constraints({s.high, s.low, std::nullopt});
  EXPECT_THROW(d.set_constraints({{}, s.low, std::nullopt}), std::invalid_argument);
  EXPECT_THROW(d.set_constraints({{s.low[0]}, s.low, std::nullopt}), std::invalid_argument);
  EXPECT_THROW(d.set_stiffness(1.5), std::invalid_argument);
  EXPECT_THROW(d.solve(RowMatrixX3d::Zero(2, 3), SolveOptions{}), std::invalid_argument);
  const SolveResult r = d.solve(s.rows(s.mesh.V, s.high), SolveOptions{});
  EXPECT_LT((r.positions - s.mesh.V).norm(), 1e-9 * s.mesh.V.norm());
}

TEST(Deformer, IntegerOptionsOutsideTheirRangeNameTheRange) {
  LiftSetup s;
  Deformer d(s.mesh.V, s.mesh.F, Domain::Edge);
  d.set_constraints({s.high, s.low, std::nullopt});
  const RowMatrixX3d targets = s.rows(s.mesh.V, s.high);
  SolveOptions none;
  none.max_iterations = 0;
  SolveOptions wide;
  wide.anderson_window = 51;
  for (const auto& [options, message] : {std::pair{none, "max_iterations must be an integer in [1, 2147483647], got 0"},
                                          std::pair{wide, "anderson_window must be an integer in [1, 50], got 51"}}) {
    try {
      d.solve(targets, options);
      ADD_FAILURE() << "accepted: " << message;
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()), message);
    }
  }
}

TEST(Deformer, RegionOfInterestLimitsTheActiveTerms) {
  LiftSetup s;
  // ROI: the handle plus everything within a band below it.
  const Eigen::VectorXd z = s.mesh.V.col(2);
  std::vector<int> roi;
  for (int v = 0; v < z.size(); ++v)
    if (z(v) > z.minCoeff() + 0.75 * (z.maxCoeff() - z.minCoeff())) roi.push_back(v);
  Deformer d(s.mesh.V, s.mesh.F, Domain::Edge);
  d.set_constraints({s.high, {}, roi});
  RowMatrixX3d targets = s.rows(s.mesh.V, s.high);
  targets.col(2).array() += 0.2;
  const SolveResult r = d.solve(targets, SolveOptions{});
  EXPECT_LT(r.active_nodes, d.graph().n_nodes / 2);
  std::vector<bool> in_roi(z.size(), false);
  for (int v : roi) in_roi[v] = true;
  for (int v = 0; v < z.size(); ++v)
    if (!in_roi[v]) EXPECT_EQ(r.positions.row(v), s.mesh.V.row(v));
}

TEST_P(DeformerBothDomains, ARegionIsSolvedOnItsOwnGraphAsOnTheWholeOne) {
  // A radius around the handle (painted lambda, a region change, a stiffness change): a fresh
  // Deformer builds only the region's graph; one whose whole graph was built lays the
  // region out on that. Both must give the same positions, bit for bit.
  const auto [domain, lambda] = GetParam();
  LiftSetup s;
  Eigen::VectorXd painted(s.mesh.V.rows());
  for (Eigen::Index v = 0; v < painted.size(); ++v) painted(v) = v % 3 == 0 ? lambda : 0.5 * lambda + 0.25;
  Deformer on_region(s.mesh.V, s.mesh.F, domain), on_whole(s.mesh.V, s.mesh.F, domain);
  ASSERT_GT(on_whole.graph().n_nodes, 0);  // builds it
  RowMatrixX3d targets = s.rows(s.mesh.V, s.high);
  targets.col(2).array() += 0.1;
  SolveOptions o;
  o.max_iterations = 6;
  o.tolerance = 0.0;
  for (Deformer* d : {&on_region, &on_whole}) d->set_stiffness(painted);
  for (double radius : {0.25, 0.4}) {
    for (Deformer* d : {&on_region, &on_whole}) {
      ConstraintSets sets{s.high, {}, std::nullopt};
      sets.roi_radius = radius;
      d->set_constraints(sets);
    }
    const SolveResult a = on_region.solve(targets, o), b = on_whole.solve(targets, o);
    EXPECT_GT(a.active_nodes, 0);
    EXPECT_EQ(a.active_nodes, b.active_nodes);
    EXPECT_EQ(a.positions, b.positions) << "radius " << radius;
    for (Deformer* d : {&on_region, &on_whole}) d->set_stiffness(std::min(lambda + 0.2, 1.0));
  }
  EXPECT_FALSE(on_region.whole_graph_built());
  EXPECT_EQ(on_region.n_nodes(), on_whole.graph().n_nodes);
  // Constraints whose region reaches half the faces or more use the whole graph, built then.
  on_region.set_constraints({s.high, s.low, std::nullopt});
  EXPECT_TRUE(on_region.whole_graph_built());
}

TEST(Deformer, InterruptStopsBetweenIterationsAndLeavesItUsable) {
  LiftSetup s;
  Deformer d(s.mesh.V, s.mesh.F, Domain::Edge);
  d.set_constraints({s.high, s.low, std::nullopt});
  RowMatrixX3d targets = s.rows(s.mesh.V, s.high);
  targets.col(2).array() += 5.0;
  SolveOptions o;
  o.max_iterations = 1000;
  o.tolerance = 0.0;
  int asked = 0;
  o.interrupt_requested = [&] { return ++asked == 3; };
  EXPECT_THROW(d.solve(targets, o), SolveInterrupted);
  EXPECT_EQ(asked, 3);
  SolveOptions ten;
  ten.max_iterations = 10;
  ten.tolerance = 0.0;
  const SolveResult r = d.solve(targets, ten);
  EXPECT_EQ(r.iterations, 10);
  EXPECT_EQ(s.rows(r.positions, s.high), targets);
  EXPECT_TRUE(r.positions.allFinite());
}

TEST(Deformer, TargetsThatWouldOverflowAreRejectedBeforeAnyWork) {
  LiftSetup s;
  Deformer d(s.mesh.V, s.mesh.F, Domain::Edge);
  d.set_constraints({s.high, s.low, std::nullopt});
  RowMatrixX3d targets = s.rows(s.mesh.V, s.high);
  targets(1, 0) = 1e308;
  try {
    d.solve(targets, SolveOptions{});
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("targets[1] = (1e+308", 0), 0u) << e.what();
  }
  EXPECT_EQ(d.analyses(), 0);  // rejected before the factorization
  const RowMatrixX3d far = RowMatrixX3d::Constant(s.mesh.V.rows(), 3, 1e200);
  EXPECT_THROW(Deformer(far + s.mesh.V * 1e190, s.mesh.F, Domain::Edge), std::invalid_argument);
}

namespace {
double max_vertex_distance(const RowMatrixX3d& A, const RowMatrixX3d& B) {
  return (A - B).rowwise().norm().maxCoeff();
}
double bbox_diagonal(const RowMatrixX3d& V) { return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm(); }
}  // namespace

TEST(Deformer, ConvergedMeansWithinTheToleranceOfTheFixedPoint) {
  LiftSetup s("cgal_three_peaks.off");  // small: the plain reference takes thousands of iterations
  const double diag = bbox_diagonal(s.mesh.V);
  RowMatrixX3d targets = s.rows(s.mesh.V, s.high);
  targets.col(2).array() += 0.25 * diag;
  for (Domain domain : {Domain::Edge, Domain::Primal}) {
    Deformer d(s.mesh.V, s.mesh.F, domain);
    d.set_constraints({s.high, s.low, std::nullopt});
    d.set_stiffness(1.0);
    SolveOptions plain;
    plain.acceleration = Acceleration::None;
    plain.tolerance = 0.0;
    plain.max_iterations = 400;
    plain.warm_start = false;
    SolveResult ref = d.solve(targets, plain);
    plain.warm_start = true;  // continue the same plain iteration
    for (int chunk = 0; chunk < 100 && ref.residuals.back() >= 1e-10; ++chunk) ref = d.solve(targets, plain);
    ASSERT_LT(ref.residuals.back(), 1e-10);

    SolveOptions o;
    o.warm_start = false;
    const SolveResult r = d.solve(targets, o);
    ASSERT_TRUE(r.converged);
    EXPECT_EQ(r.residuals.size(), r.energies.size());
    EXPECT_LE(max_vertex_distance(r.positions, ref.positions), 2 * o.tolerance * diag);
    EXPECT_GT(r.accelerated_steps, 0);
    for (size_t k = 1; k < r.energies.size(); ++k) EXPECT_LE(r.energies[k], r.energies[k - 1] * (1 + 1e-12));
  }
}

TEST(Deformer, StoppingUnconvergedWarns) {
  LiftSetup s;
  Deformer d(s.mesh.V, s.mesh.F, Domain::Edge);
  d.set_constraints({s.high, s.low, std::nullopt});
  RowMatrixX3d targets = s.rows(s.mesh.V, s.high);
  targets.col(2).array() += 0.5;
  SolveOptions o;
  o.max_iterations = 3;
  const SolveResult r = d.solve(targets, o);
  EXPECT_FALSE(r.converged);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings.back().find("not converged"), std::string::npos);
}
