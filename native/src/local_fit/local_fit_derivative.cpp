#include "local_fit/local_fit_derivative.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "base/parallel.h"
#include "local_fit/rotation_fit.h"

namespace edgedeform {

namespace {

constexpr int kMinParallelTerms = 4096;  // as the local step (local_step.cpp)
constexpr int kTermsPerChunk = 256;

// dS = sum_a w_a e0_a de_a^T of term t for node displacements dp.
Eigen::Matrix3d covariance_change(const NodeStencil& st, const RowMatrixX3d& dp, int t) {
  Eigen::Matrix3d dS = Eigen::Matrix3d::Zero();
  const Eigen::Vector3d self = dp.row(st.self[static_cast<size_t>(t)]).transpose();
  for (int a = st.offsets[static_cast<size_t>(t)]; a < st.offsets[static_cast<size_t>(t) + 1]; ++a) {
    const Eigen::Vector3d de = st.weight[static_cast<size_t>(a)] * (self - dp.row(st.neighbour[static_cast<size_t>(a)]).transpose());
    dS.noalias() += st.rest_edge.row(a).transpose() * de.transpose();
  }
  return dS;
}

// H^-1 where H is clearly positive definite (almost every term), else the pseudo-inverse
// without the directions whose eigenvalue is below kDegenerateRatio of the largest.
Eigen::Matrix3d clamped_inverse(const Eigen::Matrix3d& H) {
  const Eigen::LLT<Eigen::Matrix3d> llt(H);
  if (llt.info() == Eigen::Success) {
    const Eigen::Vector3d pivots = llt.matrixLLT().diagonal().cwiseAbs2();
    if (pivots.minCoeff() > 1e3 * kDegenerateRatio * pivots.maxCoeff()) return llt.solve(Eigen::Matrix3d::Identity());
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(H);
  const Eigen::Vector3d h = eig.eigenvalues();
  const double floor = kDegenerateRatio * h.cwiseAbs().maxCoeff();
  Eigen::Vector3d inverse = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k)
    if (h(k) > floor) inverse(k) = 1.0 / h(k);
  return eig.eigenvectors() * inverse.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace

FitLinearization linearize_fit(const NodeStencil& st, const RowMatrixX3d& p, const LocalFit& fit) {
  const int T = st.n_terms;
  FitLinearization lin;
  lin.omega_map.assign(static_cast<size_t>(T), Eigen::Matrix3d::Zero());
  lin.scale_gain.setZero(T);
  parallel_for(T, kTermsPerChunk, kMinParallelTerms, [&](int begin, int end) {
    for (int t = begin; t < end; ++t) {
      const double rest_norm = st.rest_norm(t);
      if (!(rest_norm > 0.0)) continue;  // R = I, s = 1 whatever the positions
      const Eigen::Matrix3d S = covariance_change(st, p, t);  // the covariance itself: dp = p
      const Eigen::Matrix3d& R = fit.rotation[static_cast<size_t>(t)];
      const Eigen::Matrix3d N = R * S;
      const Eigen::Matrix3d sym = 0.5 * (N + N.transpose());
      const Eigen::Matrix3d hessian = sym.trace() * Eigen::Matrix3d::Identity() - sym;
      lin.omega_map[static_cast<size_t>(t)] = -clamped_inverse(hessian);
      const double raw_scale = N.trace() / rest_norm;
      if (raw_scale > kMinScale && raw_scale < kMaxScale) lin.scale_gain(t) = 1.0 / rest_norm;
    }
  });
  return lin;
}

void differentiate_fit(const NodeStencil& st, const LocalFit& fit, const FitLinearization& lin, const RowMatrixX3d& dp,
                       RowMatrixX3d& omega, Eigen::VectorXd& dscale) {
  const int T = st.n_terms;
  omega.resize(T, 3);
  dscale.resize(T);
  parallel_for(T, kTermsPerChunk, kMinParallelTerms, [&](int begin, int end) {
    for (int t = begin; t < end; ++t) {
      Eigen::Vector3d w = Eigen::Vector3d::Zero();
      double ds = 0.0;
      if (st.rest_norm(t) > 0.0)
        fit_response(fit.rotation[static_cast<size_t>(t)], lin.omega_map[static_cast<size_t>(t)], lin.scale_gain(t),
                     covariance_change(st, dp, t), w, ds);
      omega.row(t) = w.transpose();
      dscale(t) = ds;
    }
  });
}

}  // namespace edgedeform
