// The coarse space of the Newton-Krylov step (DESIGN §2, "The preconditioner: a coarse
// space"): the free vertices split into connected patches, each moving by the affine
// functions of its rest positions. Their span U carries the smooth, large-scale rotation
// fields that the constant matrix A treats as stiff and the one-step map barely contracts.
//
// Coarse unknown (patch p, function f, coordinate c) is offset[p] + 3 f + c; function 0 is
// the constant, the others the patch's rest coordinates along its principal axes, centred
// and scaled to unit root-mean-square (axes along which the patch is flat are left out, so
// that U has full rank).
#pragma once

#include <memory>
#include <vector>

#include "edgedeform/constrained_system.h"
#include "edgedeform/fixed_point_linearization.h"

namespace edgedeform {

struct CoarseBasis {
  int n_patches = 0;
  std::vector<int> patch;                      // per free vertex (local id)
  std::vector<int> offset{0};                  // per patch, and the total at the end
  std::vector<int> functions;                  // per patch: 1 (a single vertex) .. 4
  std::vector<Eigen::Vector4d> value;          // per free vertex: phi_f(v), f < functions[patch]
  std::vector<Eigen::Vector3d> centre;         // per patch, and its axes (columns) and scales:
  std::vector<Eigen::Matrix3d> axes;           //   phi_f(v) = (x_v - centre) . axes.col(f-1) / scale(f-1)
  std::vector<Eigen::Vector3d> scale;

  int dimension() const { return offset.back(); }
};

// Patches grown from farthest-point seeds over the free vertices' mesh edges (each
// connected free component gets its own seeds), about `target_patches` of them but never
// fewer than kMinPatchVertices free vertices per patch on average. Deterministic.
constexpr int kMinPatchVertices = 16;
CoarseBasis build_coarse_basis(const ConstrainedSystem& system, const RowMatrixX3d& rest,
                               const RowMatrixX2i& mesh_edges, int target_patches);

// q = U^T x (x: #free x 3).
void restrict_to_coarse(const CoarseBasis& basis, const Eigen::MatrixXd& x, Eigen::VectorXd& q);
// x = U q.
void prolong_from_coarse(const CoarseBasis& basis, const Eigen::VectorXd& q, Eigen::MatrixXd& x);

// U^T A U, the lambda-dependent but position-free part of the coarse operator.
SparseMatrix coarse_stiffness(const CoarseBasis& basis, const SparseMatrix& A);

// The coarse Newton operator U^T K U = U^T A U - U^T D U at a linearization, with U^T A U
// given (coarse_stiffness); U^T D U is assembled term by term (each term touches one or two
// patches), never by products with U's columns. Fixed-order sums: thread-count free.
SparseMatrix coarse_operator(const CoarseBasis& basis, const SparseMatrix& coarse_A,
                             const FixedPointLinearization& linearization);

// A factored coarse operator: apply() gives U (U^T K U)^-1 U^T r.
class CoarseCorrection {
 public:
  // False (and the correction stays empty) when the coarse operator is singular or its
  // factor not finite: the caller then goes on with the one-level preconditioner.
  bool factor(const CoarseBasis& basis, const SparseMatrix& coarse);
  bool ready() const { return ready_; }
  void apply(const Eigen::MatrixXd& r, Eigen::MatrixXd& out) const;

 private:
  struct Factor;
  std::shared_ptr<Factor> factor_;
  const CoarseBasis* basis_ = nullptr;
  bool ready_ = false;
};

}  // namespace edgedeform
