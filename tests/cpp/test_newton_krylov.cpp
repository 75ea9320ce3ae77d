#include <gtest/gtest.h>

#include "edgedeform/convergence.h"
#include "edgedeform/deformer.h"
#include "edgedeform/errors.h"
#include "test_meshes.h"

using namespace edgedeform;

namespace {

// The dinosaur (a closed mesh, the paper's Fig. 5 stand-in): its lowest 20 % static, its top
// 10 % lifted by a quarter of the height.
struct Lift {
  test::TestMesh mesh = test::read_off("cgal_dino.off");
  ConstraintSets sets;
  RowMatrixX3d targets;
  double diag = 0.0;
  Lift() {
    const Eigen::VectorXd z = mesh.V.col(2);
    const double zmin = z.minCoeff(), zmax = z.maxCoeff();
    for (int v = 0; v < z.size(); ++v) {
      if (z(v) < zmin + 0.2 * (zmax - zmin)) sets.statics.push_back(v);
      if (z(v) > zmin + 0.9 * (zmax - zmin)) sets.handles.push_back(v);
    }
    diag = (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm();
    targets.resize(static_cast<Eigen::Index>(sets.handles.size()), 3);
    for (size_t k = 0; k < sets.handles.size(); ++k)
      targets.row(static_cast<Eigen::Index>(k)) = mesh.V.row(sets.handles[k]) + Eigen::RowVector3d(0.0, 0.0, 0.25 * diag);
  }
};

class NewtonKrylov : public ::testing::TestWithParam<std::tuple<Domain, double>> {};

}  // namespace

TEST_P(NewtonKrylov, ReachesThePlainMethodsFixedPointAndSaysSo) {
  const auto [domain, lambda] = GetParam();
  Lift s;
  Deformer reference(s.mesh.V, s.mesh.F, domain), newton(s.mesh.V, s.mesh.F, domain);
  for (Deformer* d : {&reference, &newton}) {
    d->set_constraints(s.sets);
    d->set_stiffness(lambda);
  }
  SolveOptions tight;
  tight.acceleration = Acceleration::Anderson;
  tight.tolerance = 1e-10;
  tight.max_iterations = 20000;
  const SolveResult ref = reference.solve(s.targets, tight);
  ASSERT_LT(ref.residuals.back(), 1e-9);
  SolveOptions o;
  o.acceleration = Acceleration::Newton;
  const SolveResult r = newton.solve(s.targets, o);
  ASSERT_TRUE(r.converged) << (r.warnings.empty() ? "" : r.warnings.back());
  EXPECT_GT(r.newton_steps, 0);
  EXPECT_LE(max_row_distance(r.positions, ref.positions), 2.0 * o.tolerance * s.diag);
  EXPECT_EQ(r.energies.size(), static_cast<size_t>(r.iterations));
  EXPECT_EQ(r.residuals.size(), static_cast<size_t>(r.iterations));
  if (lambda == 1.0)
    for (size_t k = 1; k < r.energies.size(); ++k) EXPECT_LE(r.energies[k], r.energies[k - 1] * (1 + 1e-12));
}

TEST(NewtonKrylovStop, AnInterruptStopsTheSolveAndTheDeformerStaysUsable) {
  Lift s;
  Deformer d(s.mesh.V, s.mesh.F, Domain::Edge);
  d.set_constraints(s.sets);
  d.set_stiffness(1.0);
  SolveOptions o;
  o.acceleration = Acceleration::Newton;
  int asked = 0;
  o.interrupt_requested = [&] { return ++asked > 5; };
  EXPECT_THROW(d.solve(s.targets, o), SolveInterrupted);
  o.interrupt_requested = nullptr;
  const SolveResult r = d.solve(s.targets, o);
  EXPECT_TRUE(r.converged) << (r.warnings.empty() ? "" : r.warnings.back());
}

TEST(NewtonKrylovStop, MaxIterationsEndsUnconvergedWithAReason) {
  Lift s;
  Deformer d(s.mesh.V, s.mesh.F, Domain::Edge);
  d.set_constraints(s.sets);
  SolveOptions o;
  o.acceleration = Acceleration::Newton;
  o.max_iterations = 2;
  const SolveResult r = d.solve(s.targets, o);
  EXPECT_FALSE(r.converged);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings.back().find("not converged"), std::string::npos);
  EXPECT_TRUE(r.positions.allFinite());
}

INSTANTIATE_TEST_SUITE_P(DomainsAndStiffness, NewtonKrylov,
                         ::testing::Combine(::testing::Values(Domain::Edge, Domain::Primal),
                                            ::testing::Values(0.5, 1.0)));

TEST(NewtonKrylovLambda0, ConvergesToThePlainFixedPointOrSaysItDidNot) {
  // lambda = 0 is the hardest cell (the similarity floor's soft scale modes): a short
  // solve must either be right or say that it is not converged.
  for (Domain domain : {Domain::Edge, Domain::Primal}) {
    Lift s;
    Deformer d(s.mesh.V, s.mesh.F, domain);
    d.set_constraints(s.sets);
    d.set_stiffness(0.0);
    SolveOptions o;
    o.acceleration = Acceleration::Newton;
    o.max_iterations = 60;
    const SolveResult r = d.solve(s.targets, o);
    ASSERT_TRUE(r.positions.allFinite());
    if (!r.converged) {
      ASSERT_FALSE(r.warnings.empty());
      EXPECT_NE(r.warnings.back().find("not converged"), std::string::npos);
      continue;
    }
    SolveOptions tight;
    tight.acceleration = Acceleration::Anderson;
    tight.tolerance = 1e-10;
    tight.max_iterations = 20000;
    tight.warm_start = false;
    const SolveResult ref = d.solve(s.targets, tight);
    EXPECT_LE(max_row_distance(r.positions, ref.positions), 2.0 * o.tolerance * s.diag);
  }
}
