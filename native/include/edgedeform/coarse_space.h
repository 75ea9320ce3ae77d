// The coarse space of the Newton-Krylov step (docs/design.md §4): the free vertices split into connected patches, each moving by the affine
// functions of its rest positions. Their span U carries the smooth, large-scale rotation
// fields that the constant matrix A treats as stiff and the one-step map barely contracts.
//
// Coarse unknown (patch p, function f, coordinate c) is offset[p] + 3 f + c; function 0 is
// the constant, the others the patch's rest coordinates along its principal axes, centred
// and scaled to unit root-mean-square (axes along which the patch is flat are left out, so
// that U has full rank).
//
// Blending: with blend_steps = 0 each free vertex moves with its own patch only (U is
// piecewise affine, discontinuous across patch borders). With blend_steps > 0 the patches'
// indicator functions are smoothed over the free vertices' mesh edges and normalized to sum
// to one (a partition of unity w_p), and column (p, f, c) is w_p(v) phi_pf(v) e_c: the span
// still holds every affine motion of each component, and a slowly varying rotation field is
// approximated without jumps at the borders. Jumps cost energy in the very norm the
// coarse correction works in (docs/decisions/0021-blended-coarse-space.md).
#pragma once

#include <memory>
#include <vector>

#include "edgedeform/constrained_system.h"
#include "edgedeform/fixed_point_linearization.h"

namespace edgedeform {

struct CoarseBasis {
  int n_patches = 0;
  std::vector<int> patch;                      // per free vertex (local id): the patch it was grown into
  std::vector<int> offset{0};                  // per patch, and the total at the end
  std::vector<int> functions;                  // per patch: 1 (a single vertex) .. 4
  std::vector<Eigen::Vector3d> centre;         // per patch, and its axes (columns) and scales:
  std::vector<Eigen::Matrix3d> axes;           //   phi_f(v) = (x_v - centre) . axes.col(f-1) / scale(f-1)
  std::vector<Eigen::Vector3d> scale;
  // The patches whose functions are nonzero at each free vertex: entries
  // [entry_offset[v], entry_offset[v + 1]), in increasing patch order, each with
  // w_p(v) phi_pf(v) for f < functions[p]. One entry (weight 1) per vertex when unblended.
  std::vector<int> entry_offset{0};
  std::vector<int> entry_patch;
  std::vector<Eigen::Vector4d> entry_value;

  int dimension() const { return offset.back(); }
  int n_free() const { return static_cast<int>(patch.size()); }
};

// Patches grown from farthest-point seeds over the free vertices' mesh edges (each
// connected free component gets its own seeds), about `target_patches` of them but never
// fewer than kMinPatchVertices free vertices per patch on average. Deterministic.
// blend_steps: smoothing steps of the partition of unity (0: disjoint patches; see above).
constexpr int kMinPatchVertices = 16;
CoarseBasis build_coarse_basis(const ConstrainedSystem& system, const RowMatrixX3d& rest,
                               const RowMatrixX2i& mesh_edges, int target_patches, int blend_steps = 0);

// U as a sparse matrix, rows v + nf c (all x, then all y, then all z), for inspection.
SparseMatrix coarse_basis_matrix(const CoarseBasis& basis);

// q = U^T x (x: #free x 3).
void restrict_to_coarse(const CoarseBasis& basis, const Eigen::MatrixXd& x, Eigen::VectorXd& q);
// x = U q.
void prolong_from_coarse(const CoarseBasis& basis, const Eigen::VectorXd& q, Eigen::MatrixXd& x);

// U^T A U, the lambda-dependent but position-free part of the coarse operator.
SparseMatrix coarse_stiffness(const CoarseBasis& basis, const SparseMatrix& A);

// The coarse Newton operator U^T K U = U^T A U - U^T D U at a linearization, with U^T A U
// given (coarse_stiffness); U^T D U is assembled term by term (each term touches the few
// patches of its vertices' entries), never by products with U's columns. Fixed-order sums: thread-count free.
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
