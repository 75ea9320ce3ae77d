// A FixedPointProblem built from the core's pieces on the constrained grid (constrained_grid.h),
// as the Deformer offers it: the strategies' tests (test_fixed_point_iteration.cpp,
// test_quasi_newton.cpp) run on it.
#pragma once

#include <memory>

#include "constrained_grid.h"
#include "strategies/fixed_point_problem.h"
#include "linear_algebra/sparse_cholesky.h"

namespace edgedeform::test {

// The local/global map of the grid's whole set at one lambda, as the Deformer offers it.
struct GridProblem final : FixedPointProblem {
  ConstrainedGrid grid;
  ConstrainedSystem sys;
  AssembledSystem as;
  SparseCholesky cholesky;
  RowMatrixX3d x_local, nodes;
  Eigen::MatrixXd c;
  double diag = 0.0;
  int interrupt_after = -1, asked = 0;  // >= 0: ask to stop at that question

  GridProblem(Domain domain, double lambda) : grid(domain) {
    sys = grid.whole(grid.whole_sets);
    as = assemble_system(sys, Eigen::VectorXd::Constant(grid.g.n_vertices, lambda));
    cholesky.factorize(as.A);
    const int nf = sys.n_free(), nc = sys.n_fixed();
    RowMatrixX3d constrained = grid.mesh.V;
    const RowMatrixX3d t = grid.targets(grid.whole_sets, 0.4);
    for (size_t h = 0; h < sys.handles.size(); ++h) constrained.row(sys.handles[h]) = t.row(static_cast<Eigen::Index>(h));
    x_local.resize(nf + nc, 3);
    for (int k = 0; k < nc; ++k) x_local.row(nf + k) = constrained.row(sys.fixed_vertices[static_cast<size_t>(k)]);
    c = -(as.K_fixed * x_local.bottomRows(nc));
    diag = (grid.mesh.V.colwise().maxCoeff() - grid.mesh.V.colwise().minCoeff()).norm();
  }
  Eigen::MatrixXd rest_free() const {
    Eigen::MatrixXd y(sys.n_free(), 3);
    for (int k = 0; k < sys.n_free(); ++k) y.row(k) = grid.mesh.V.row(sys.free_vertices[static_cast<size_t>(k)]);
    return y;
  }
  double local_fit(const Eigen::MatrixXd& y, LocalFit& fit) override {
    x_local.topRows(y.rows()) = y;
    stencil_node_positions(sys, x_local, nodes);
    fit_local(sys.stencil, nodes, as.term_lambda, fit, as.term_similar);
    return fit.energy;
  }
  void global_step(const LocalFit& fit, Eigen::MatrixXd& rhs, Eigen::MatrixXd& g) override {
    as.H.apply(fit.rotation, fit.scale, c, rhs);
    cholesky.solve(rhs, g);
  }
  void solve_A(const Eigen::MatrixXd& r, Eigen::MatrixXd& z) override { cholesky.solve(r, z); }
  const SparseMatrix& A() const override { return as.A; }
  std::unique_ptr<FixedPointLinearization> linearize(const LocalFit& fit) override {
    return std::make_unique<FixedPointLinearization>(sys, as, fit, nodes);
  }
  bool interrupt_requested() override { return interrupt_after >= 0 && asked++ >= interrupt_after; }
};

// The fit a cold start begins with: R = I, s = 1 (not a fit of y).
inline LocalFit cold_fit(const ConstrainedSystem& sys) {
  LocalFit fit;
  const auto T = static_cast<size_t>(sys.n_terms());
  fit.rotation.assign(T, Eigen::Matrix3d::Identity());
  fit.right_vectors.assign(T, Eigen::Matrix3d::Identity());
  fit.scale = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(T));
  return fit;
}

}  // namespace edgedeform::test
