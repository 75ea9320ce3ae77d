// Live editing's coarse predictor (docs/design.md §4, "Where it starts"): when the targets
// of a warm solve moved, one two-level Newton step carries the soft modes along with the
// handles at once, instead of leaving them to hundreds of plain or Anderson iterations.
//
// At the warm iterate y: b = A (G(y) - y) with the warm fit (as the plain step), and the step
// solves K delta = b approximately with the coarse space, multiplicatively:
//   delta = c + A^-1 (b - K c),   c = U (U^T K U)^-1 U^T b,
// i.e. the plain step plus J_G c, with K linearized at y fitted anew (the handles moved).
// U^T K U is lagged over several predictions (its assembly is the costly part).
// Safeguard: the predicted point is kept only if its |A (G(x) - x)| is below the start's
// (coarse_predictor.cpp says why not the plain step's); otherwise y moves to the plain
// step, and the iterates are those of a warm solve without predictor.
#pragma once

#include "edgedeform/coarse_space.h"
#include "edgedeform/newton_krylov.h"

namespace edgedeform {

struct SolveResult;

// Kept by the caller between solves: the lagged coarse factor and its age.
struct PredictorMemory {
  CoarseCorrection correction;
  int age = 1 << 20;  // predictions since the coarse operator was assembled
  // Stale: the basis or the operators changed.
  void forget() { *this = PredictorMemory(); }
};

// Predictions that may reuse one assembled coarse operator (the targets move a little per
// tick; measured in bench/bench_live_settle.py).
constexpr int kPredictorLag = 8;

struct PredictorOutcome {
  bool kept = false;            // the predicted point was kept (else y is the plain step)
  int evaluations = 0;          // global steps taken (counted in result.iterations)
};

// fit: the warm fit on entry (where the handles were). Moves y (free vertices; the problem's
// fixed rows already at the new targets) and sets fit = fit(y) and energy = E(y). Two
// global steps (counted in result.iterations): G at y and at the prediction.
PredictorOutcome coarse_predict(FixedPointProblem& problem, const CoarseBasis& basis, const SparseMatrix& coarse_stiffness,
                                PredictorMemory& memory, double diag, Eigen::MatrixXd& y, LocalFit& fit,
                                double& energy, SolveResult& result);

}  // namespace edgedeform
