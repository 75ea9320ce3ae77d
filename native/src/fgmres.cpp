#include "edgedeform/fgmres.h"

#include <cmath>
#include <vector>

namespace edgedeform {

KrylovResult fgmres(const LinearMap& K, const LinearMap& precondition, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                    double tolerance, int max_iterations, const std::function<bool()>& stop) {
  KrylovResult result;
  const Eigen::Index n = b.size();
  x.setZero(n);
  const double beta = b.norm();
  if (!(beta > 0.0) || !std::isfinite(beta)) {
    result.relative_residual = beta > 0.0 ? 1.0 : 0.0;
    result.converged = beta == 0.0;
    return result;
  }
  const int m = std::max(1, max_iterations);
  std::vector<Eigen::VectorXd> V(1, b / beta), Z;  // Arnoldi basis; preconditioned directions
  Eigen::MatrixXd Hess = Eigen::MatrixXd::Zero(m + 1, m);
  Eigen::VectorXd cs = Eigen::VectorXd::Zero(m), sn = Eigen::VectorXd::Zero(m), g = Eigen::VectorXd::Zero(m + 1);
  g(0) = beta;
  Eigen::VectorXd w(n), z(n);
  int k = 0;
  for (; k < m; ++k) {
    if (stop && stop()) break;
    if (precondition) precondition(V[static_cast<size_t>(k)], z); else z = V[static_cast<size_t>(k)];
    Z.push_back(z);
    K(z, w);
    // Modified Gram-Schmidt, twice where the first pass cancels much (stability).
    const double w_norm = w.norm();
    for (int pass = 0; pass < 2; ++pass) {
      for (int j = 0; j <= k; ++j) {
        const double h = V[static_cast<size_t>(j)].dot(w);
        Hess(j, k) += h;
        w.noalias() -= h * V[static_cast<size_t>(j)];
      }
      if (w.norm() > 0.5 * w_norm) break;
    }
    const double h_next = w.norm();
    Hess(k + 1, k) = h_next;
    for (int j = 0; j < k; ++j) {  // earlier Givens rotations
      const double t = cs(j) * Hess(j, k) + sn(j) * Hess(j + 1, k);
      Hess(j + 1, k) = -sn(j) * Hess(j, k) + cs(j) * Hess(j + 1, k);
      Hess(j, k) = t;
    }
    const double r = std::hypot(Hess(k, k), Hess(k + 1, k));
    if (!(r > 0.0) || !std::isfinite(r)) break;  // a breakdown: keep what we have
    cs(k) = Hess(k, k) / r;
    sn(k) = Hess(k + 1, k) / r;
    Hess(k, k) = r;
    Hess(k + 1, k) = 0.0;
    g(k + 1) = -sn(k) * g(k);
    g(k) = cs(k) * g(k);
    result.iterations = k + 1;
    result.relative_residual = std::abs(g(k + 1)) / beta;
    if (result.relative_residual <= tolerance) { ++k; break; }
    if (!(h_next > 1e-300)) { ++k; break; }  // the Krylov space is invariant: exact
    V.push_back(w / h_next);
  }
  const int used = std::min<int>(result.iterations, static_cast<int>(Z.size()));
  if (used == 0) return result;
  const Eigen::VectorXd y = Hess.topLeftCorner(used, used).triangularView<Eigen::Upper>().solve(g.head(used));
  for (int j = 0; j < used; ++j) x.noalias() += y(j) * Z[static_cast<size_t>(j)];
  result.converged = result.relative_residual <= tolerance;
  return result;
}

}  // namespace edgedeform
