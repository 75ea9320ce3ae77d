// Live editing's coarse predictor (coarse_predictor.h) through the Deformer: it runs once
// per warm solve whose targets moved, counts its global steps, and a prediction that does
// not beat the plain step leaves the solve exactly as it would be without it. (That it
// carries a drag's soft motion along is tested on the dino in
// tests/python/test_coarse_predictor.py.)
#include <gtest/gtest.h>

#include "edgedeform/convergence.h"
#include "edgedeform/deformer.h"
#include "edgedeform/errors.h"
#include "test_meshes.h"

using namespace edgedeform;

namespace {

// A 30 x 30 grid, its left column static, its right column lifted by a third of its size
// and drawn inwards: a soft, large-scale bend.
struct Bend {
  test::TestMesh mesh = test::grid(30, 30);
  ConstraintSets sets;
  RowMatrixX3d rest_targets, targets;
  double diag = 0.0;
  Bend() {
    const double xmin = mesh.V.col(0).minCoeff(), xmax = mesh.V.col(0).maxCoeff();
    for (int v = 0; v < mesh.V.rows(); ++v) {
      if (mesh.V(v, 0) <= xmin + 1e-9) sets.statics.push_back(v);
      if (mesh.V(v, 0) >= xmax - 1e-9) sets.handles.push_back(v);
    }
    diag = (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm();
    rest_targets.resize(static_cast<Eigen::Index>(sets.handles.size()), 3);
    for (size_t k = 0; k < sets.handles.size(); ++k) rest_targets.row(static_cast<Eigen::Index>(k)) = mesh.V.row(sets.handles[k]);
    targets = rest_targets;
    targets.col(2).array() += 0.33 * (xmax - xmin);
    targets.col(0).array() -= 0.2 * (xmax - xmin);
  }
  RowMatrixX3d at(double s) const { return rest_targets + s * (targets - rest_targets); }
};

SolveOptions tick(bool predictor, int iterations) {
  SolveOptions o;
  o.max_iterations = iterations;
  o.coarse_predictor = predictor;
  o.coarse_patches = 40;
  return o;
}

}  // namespace

TEST(CoarsePredictor, RunsOncePerMovedTargetAndCountsItsGlobalSteps) {
  Bend s;
  Deformer d(s.mesh.V, s.mesh.F, Domain::Edge);
  d.set_constraints(s.sets);
  d.set_stiffness(0.5);
  EXPECT_EQ(d.solve(s.at(0.0), tick(true, 4)).predictions, 0);  // nothing to continue yet
  for (int k = 1; k <= 5; ++k) {
    const SolveResult r = d.solve(s.at(k / 5.0), tick(true, 4));
    EXPECT_EQ(r.predictions, 1);
    EXPECT_LE(r.iterations, 4);
    EXPECT_EQ(r.residuals.size(), static_cast<size_t>(r.iterations));
    EXPECT_EQ(r.energies.size(), static_cast<size_t>(r.iterations));
    EXPECT_GT(r.coarse_dimension, 0);
  }
  EXPECT_EQ(d.solve(s.at(1.0), tick(true, 4)).predictions, 0);  // standing still: continue
}

TEST(CoarsePredictor, ARejectedPredictionChangesNothing) {
  // The flat grid's bend: the plain step from the warm fit lands on the fixed point at once,
  // so no prediction can beat it and the drag must end exactly where it ends without them.
  Bend s;
  RowMatrixX3d end[2];
  int kept = 0, predictions = 0;
  for (int predictor = 0; predictor < 2; ++predictor) {
    Deformer d(s.mesh.V, s.mesh.F, Domain::Edge);
    d.set_constraints(s.sets);
    d.set_stiffness(1.0);
    d.solve(s.at(0.0), tick(false, 1));
    for (int k = 1; k <= 20; ++k) {
      const SolveResult r = d.solve(s.at(k / 20.0), tick(predictor == 1, 4));
      kept += r.predictions_kept;
      predictions += r.predictions;
      end[predictor] = r.positions;
    }
  }
  EXPECT_EQ(predictions, 20);
  EXPECT_EQ(kept, 0);
  EXPECT_EQ(max_row_distance(end[0], end[1]), 0.0);
}

TEST(CoarsePredictor, AnInterruptStopsItAndTheDeformerStaysUsable) {
  Bend s;
  Deformer d(s.mesh.V, s.mesh.F, Domain::Edge);
  d.set_constraints(s.sets);
  d.set_stiffness(0.5);
  d.solve(s.at(0.0), tick(true, 4));
  SolveOptions asked = tick(true, 4);
  int calls = 0;
  asked.interrupt_requested = [&calls] { return ++calls >= 1; };
  EXPECT_THROW(d.solve(s.at(0.5), asked), SolveInterrupted);
  EXPECT_EQ(calls, 1);  // asked once, before anything moved
  const SolveResult r = d.solve(s.at(0.5), tick(true, 4));
  EXPECT_TRUE(r.positions.allFinite());
  EXPECT_LE(r.iterations, 4);
}
