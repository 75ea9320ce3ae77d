// The constant sparse operator that maps the local step's rotations and scales to the right
// side of the global step. Its blocks pair a free vertex v with a term t whose energy
// touches v, and hold six numbers (h_R, h_T) that do not depend on the stiffness, so that
//     rhs_v = c_v + sum_blocks R_t ((lambda_t + phi_t s_t) h_R + (1 - lambda_t - phi_t) s_t h_T),
// phi_t the term's share of the similarity 1-form term (stiffness.h; 0 but in the primal
// domain at lambda below its floor).
// This is H Z of constrained_system.h with H's six columns per term folded into one block:
// one product per iteration, and no stacked Z to build; a change of lambda only replaces the
// per-term lambda_t.
#pragma once

#include <vector>

#include "local_fit/term_shares.h"
#include "base/types.h"

namespace edgedeform {

class RotationOperator {
 public:
  RotationOperator() = default;
  // From H at lambda = 1 for the 1-form columns and lambda = 0 for the Laplacian ones
  // (rows x 6 #terms; column 6t+k carries R_t(.,k), 6t+3+k carries s_t R_t(.,k)). Every
  // lambda_t starts at 1.
  explicit RotationOperator(const SparseMatrixRowMajor& H);
  // From its blocks directly: row r's blocks are offsets[r] .. offsets[r+1), each with its
  // term and six coefficients (h_R, h_T); `terms` = #terms.
  RotationOperator(std::vector<int> offsets, std::vector<int> term, std::vector<double> coef, int terms);

  // The operator of a subset of the rows (rows[k] becomes row k) with terms renumbered:
  // term t becomes term_map[t] (#terms entries; -1 for a term the subset drops, which none
  // of the kept rows may use: std::invalid_argument), of `terms` in all. term_map must keep
  // the terms' order, so that each row's blocks still ascend. Every lambda_t starts at 1.
  RotationOperator restricted(const std::vector<int>& rows, const std::vector<int>& term_map, int terms) const;

  // lambda_t of every term (#terms), and phi_t (#terms, or empty for none); throws
  // std::invalid_argument on a size mismatch.
  void set_term_lambda(const Eigen::VectorXd& term_lambda, const Eigen::VectorXd& term_similar = {});

  // y = c + (the operator applied to R, s); rows in parallel. c and y are (rows x 3).
  // term_weights is scratch (two per term, resized here) that a caller keeps, so that an
  // iteration allocates nothing.
  void apply(const std::vector<Eigen::Matrix3d>& rotation, const Eigen::VectorXd& scale,
             const Eigen::MatrixXd& c, Eigen::MatrixXd& y, std::vector<double>& term_weights) const;
  void apply(const std::vector<Eigen::Matrix3d>& rotation, const Eigen::VectorXd& scale,
             const Eigen::MatrixXd& c, Eigen::MatrixXd& y) const {
    std::vector<double> term_weights;
    apply(rotation, scale, c, y, term_weights);
  }

  // The derivative of apply() along a change of the fit: omega_t (#terms x 3, the rotation
  // change dR_t = [omega_t]x R_t) and ds_t (#terms) give, per row,
  //     dy_r = sum_blocks omega_t x (R_t g) + ds_t R_t k,
  //     g = (lambda_t + phi_t s_t) h_R + (1 - lambda_t - phi_t) s_t h_T,  k = phi_t h_R + (1 - lambda_t - phi_t) h_T
  // (local_fit_derivative.h): d(rhs)/dx, J_G's products (the claim check), one pass over the blocks.
  void apply_derivative(const std::vector<Eigen::Matrix3d>& rotation, const Eigen::VectorXd& scale,
                        const RowMatrixX3d& omega, const Eigen::VectorXd& dscale, Eigen::MatrixXd& dy) const;

  // One block's two vectors at the current stiffness: g (what R_t multiplies) and k (what
  // ds_t R_t multiplies), as in apply_derivative.
  void block_vectors(int block, double scale, Eigen::Vector3d& g, Eigen::Vector3d& k) const {
    const auto t = static_cast<size_t>(term_[static_cast<size_t>(block)]);
    const double* h = &coef_[6 * static_cast<size_t>(block)];
    const TermShares share = term_shares(lambda_[t], similar_[t]);
    const double on_R = share.rigid + share.similar * scale, on_T = share.smooth * scale;
    g = Eigen::Vector3d(on_R * h[0] + on_T * h[3], on_R * h[1] + on_T * h[4], on_R * h[2] + on_T * h[5]);
    k = Eigen::Vector3d(share.similar * h[0] + share.smooth * h[3], share.similar * h[1] + share.smooth * h[4],
                        share.similar * h[2] + share.smooth * h[5]);
  }

  int rows() const { return static_cast<int>(offsets_.size()) - 1; }
  int blocks() const { return static_cast<int>(term_.size()); }
  int terms() const { return static_cast<int>(lambda_.size()); }

 private:
  std::vector<int> offsets_{0};  // blocks of row r: offsets_[r] .. offsets_[r+1)
  std::vector<int> term_;        // per block
  std::vector<double> coef_;     // per block: h_R (3), then h_T (3)
  std::vector<double> lambda_;   // per term
  std::vector<double> similar_;  // per term, phi_t
};

}  // namespace edgedeform
