// Flexible GMRES (Saad 1993) for K x = b with a right preconditioner that may change from
// one iteration to the next: the Krylov solver of the Newton step (newton_krylov.h).
// Dot products and norms run in a fixed order on one thread, so a solve is the same with any
// number of threads.
#pragma once

#include <functional>

#include <Eigen/Core>

namespace edgedeform {

using LinearMap = std::function<void(const Eigen::VectorXd& in, Eigen::VectorXd& out)>;

struct KrylovResult {
  int iterations = 0;              // products with K
  double relative_residual = 1.0;  // |b - K x| / |b| as FGMRES tracks it
  bool converged = false;          // relative_residual <= the tolerance asked
};

// Solves K x = b to |b - K x| <= tolerance |b| or max_iterations products (no restart:
// the Newton step's systems need few), starting from x = 0. `precondition` may be empty
// (the identity). `stop` is asked before every product; returning true ends the solve with
// the iterate so far.
KrylovResult fgmres(const LinearMap& K, const LinearMap& precondition, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                    double tolerance, int max_iterations, const std::function<bool()>& stop = {});

}  // namespace edgedeform
