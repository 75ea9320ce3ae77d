// A linear contraction with slow modes, shared by the Anderson and convergence-monitor tests.
#pragma once

#include <cstdlib>

#include <Eigen/Dense>

namespace edgedeform::test {

// A linear contraction G(x) = M x + b with slow modes (eigenvalues up to 0.99), the
// situation of plain local/global near its fixed point.
struct LinearMap {
  Eigen::MatrixXd M;
  Eigen::VectorXd b, fixed_point;
  explicit LinearMap(int n) {
    // Eigen's Random draws from std::rand: seeded here, so that the map does not depend on
    // which tests ran before in the same process (the Eigen-fallback build runs them all in
    // one; a map drawn after other tests' draws broke the estimate test's margin).
    std::srand(1);
    Eigen::MatrixXd Q = Eigen::MatrixXd::Random(n, n).householderQr().householderQ();
    Eigen::VectorXd eig = Eigen::VectorXd::LinSpaced(n, 0.1, 0.99);
    M = Q * eig.asDiagonal() * Q.transpose();
    b = Eigen::VectorXd::Random(n);
    fixed_point = (Eigen::MatrixXd::Identity(n, n) - M).lu().solve(b);
  }
  Eigen::VectorXd operator()(const Eigen::VectorXd& x) const { return M * x + b; }
};

}  // namespace edgedeform::test
