// A linear contraction with slow modes, shared by the Anderson and convergence-monitor tests.
#pragma once

#include <cstdint>

#include <Eigen/Dense>

namespace edgedeform::test {

// glibc's rand() (its TYPE_3 additive feedback generator), written out: std::rand differs
// between C libraries (Windows's MSVCRT has another generator and RAND_MAX 32767), and so
// would every map drawn from it. With this one each platform tests the same map: on Linux,
// the very numbers Eigen's Random drew after std::srand(1) before.
class GlibcRand {
 public:
  explicit GlibcRand(std::int32_t seed) {
    r_[0] = seed;
    for (int i = 1; i < 31; ++i) {
      const std::int64_t word = (16807LL * r_[i - 1]) % 2147483647LL;
      r_[i] = static_cast<std::int32_t>(word < 0 ? word + 2147483647LL : word);
    }
    for (int i = 31; i < 34; ++i) r_[i] = r_[i - 31];
    for (int i = 34; i < 344; ++i) step(i);
    n_ = 344;
  }
  // In [0, 2^31 - 1], glibc's RAND_MAX.
  int next() {
    const int i = n_++;
    step(i);
    return static_cast<int>(static_cast<std::uint32_t>(at(i)) >> 1);
  }
  // Eigen's Random for double: -1 + 2 rand() / RAND_MAX.
  double uniform() { return -1.0 + 2.0 * double(next()) / 2147483647.0; }

 private:
  std::int32_t& at(int i) { return r_[i % kSize]; }
  void step(int i) {
    at(i) = static_cast<std::int32_t>(static_cast<std::uint32_t>(at(i - 31)) +
                                      static_cast<std::uint32_t>(at(i - 3)));
  }
  static constexpr int kSize = 64;  // a ring larger than the 31-word lag
  std::int32_t r_[kSize] = {};
  int n_ = 0;
};

// A rows x cols matrix of GlibcRand::uniform() in column-major order (Eigen's fill order).
inline Eigen::MatrixXd glibc_random(int rows, int cols, GlibcRand& rand) {
  Eigen::MatrixXd A(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) A(i, j) = rand.uniform();
  return A;
}

// A linear contraction G(x) = M x + b with slow modes (eigenvalues up to 0.99), the
// situation of plain local/global near its fixed point.
struct LinearMap {
  Eigen::MatrixXd M;
  Eigen::VectorXd b, fixed_point;
  explicit LinearMap(int n) {
    // A generator of its own, seeded here, so that the map depends neither on which tests
    // ran before in the same process (the Eigen-fallback build runs them all in one; a map
    // drawn after other tests' draws broke the estimate test's margin) nor on the platform's
    // C library (GlibcRand).
    GlibcRand rand(1);
    Eigen::MatrixXd Q = glibc_random(n, n, rand).householderQr().householderQ();
    Eigen::VectorXd eig = Eigen::VectorXd::LinSpaced(n, 0.1, 0.99);
    M = Q * eig.asDiagonal() * Q.transpose();
    b = glibc_random(n, 1, rand);
    fixed_point = (Eigen::MatrixXd::Identity(n, n) - M).lu().solve(b);
  }
  Eigen::VectorXd operator()(const Eigen::VectorXd& x) const { return M * x + b; }
};

}  // namespace edgedeform::test
