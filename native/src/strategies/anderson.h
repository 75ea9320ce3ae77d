// Anderson acceleration of a fixed-point map x -> G(x) (Peng et al., "Anderson Acceleration
// for Geometry Optimization and Physics Simulation", 2018, Alg. 2): from the last m+1 pairs
// (x_j, G(x_j)) it returns the combination of the G(x_j) whose residuals f_j = G(x_j) - x_j
// combine to the least norm. The safeguard (when to keep the result) is the caller's.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace edgedeform {

class AndersonAccelerator {
 public:
  // Vectors of `dimension` entries, up to `window` differences kept. All memory is
  // allocated here, none in step().
  void resize(Eigen::Index dimension, int window);
  // Forget the history (after a rejected step or when the map changes).
  void reset() { stored_ = 0; next_ = 0; has_last_ = false; }

  // Records the pair (x, g = G(x)) and writes the accelerated point to `out` (which may
  // alias neither x nor g). Returns false, and writes g, while there is no history yet.
  bool step(const Eigen::Ref<const Eigen::VectorXd>& x, const Eigen::Ref<const Eigen::VectorXd>& g,
            Eigen::Ref<Eigen::VectorXd> out);

  int window() const { return static_cast<int>(dF_.cols()); }
  int stored() const { return stored_; }

 private:
  Eigen::MatrixXd dF_, dG_;     // columns: differences of consecutive residuals and images
  Eigen::VectorXd last_f_, last_g_;
  Eigen::MatrixXd normal_;      // m x m Gram matrix of the normalised residual differences
  Eigen::VectorXd rhs_, theta_, scratch_;
  Eigen::LDLT<Eigen::MatrixXd> ldlt_;  // reallocates only while the history fills
  int stored_ = 0;              // valid columns
  int next_ = 0;                // the column the next difference overwrites (ring buffer)
  bool has_last_ = false;
};

}  // namespace edgedeform
