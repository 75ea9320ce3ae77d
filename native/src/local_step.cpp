#include "edgedeform/local_step.h"

#include <algorithm>
#include <cmath>


#include "edgedeform/node_graph.h"
#include "edgedeform/parallel.h"

namespace edgedeform {

NodeStencil build_stencil(const NodeGraph& g, const RowMatrixX3d& rest_nodes, const std::vector<int>& term_nodes,
                          const std::vector<int>& position_index) {
  NodeStencil st;
  const int T = static_cast<int>(term_nodes.size());
  st.n_terms = T;
  st.self.resize(static_cast<size_t>(T));
  st.offsets.assign(1, 0);
  std::vector<Eigen::Vector3d> rest_edges;
  for (int t = 0; t < T; ++t) {
    const int i = term_nodes[static_cast<size_t>(t)];
    st.self[static_cast<size_t>(t)] = position_index[static_cast<size_t>(i)];
    for (int k = g.offsets[static_cast<size_t>(i)]; k < g.offsets[static_cast<size_t>(i) + 1]; ++k) {
      const double w = g.adjacency_weights[static_cast<size_t>(k)];
      const int j = g.adjacency[static_cast<size_t>(k)];
      st.neighbour.push_back(position_index[static_cast<size_t>(j)]);
      st.weight.push_back(w);
      rest_edges.push_back((rest_nodes.row(i) - rest_nodes.row(j)).transpose());
    }
    st.offsets.push_back(static_cast<int>(st.neighbour.size()));
  }
  const int n_arcs = st.n_arcs();
  st.rest_edge.resize(n_arcs, 3);
  for (int a = 0; a < n_arcs; ++a) st.rest_edge.row(a) = rest_edges[static_cast<size_t>(a)].transpose();
  st.rest_laplacian.setZero(T, 3);
  st.rest_norm.setZero(T);
  for (int t = 0; t < T; ++t)
    for (int a = st.offsets[static_cast<size_t>(t)]; a < st.offsets[static_cast<size_t>(t) + 1]; ++a) {
      st.rest_laplacian.row(t) += st.weight[static_cast<size_t>(a)] * st.rest_edge.row(a);
      st.rest_norm(t) += st.weight[static_cast<size_t>(a)] * st.rest_edge.row(a).squaredNorm();
    }
  return st;
}

namespace {

// sum_j e0_j e_j^T over every arc of a term, weight or not: the neighbourhood's shape alone.
Eigen::Matrix3d unweighted_covariance(const NodeStencil& st, const RowMatrixX3d& p, const Eigen::Vector3d& pi,
                                      int begin, int end) {
  Eigen::Matrix3d S2 = Eigen::Matrix3d::Zero();
  for (int a = begin; a < end; ++a)
    S2.noalias() += st.rest_edge.row(a).transpose() * (pi - p.row(st.neighbour[static_cast<size_t>(a)]).transpose()).transpose();
  return S2;
}

// One term's fit: R_t, s_t and its energy.
double fit_term(const NodeStencil& st, const RowMatrixX3d& p, double lambda, double similar, int t,
                Eigen::Matrix3d& R, Eigen::Matrix3d& V, double& s, bool R_is_previous) {
  const Eigen::Vector3d pi = p.row(st.self[static_cast<size_t>(t)]).transpose();
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  Eigen::Vector3d laplacian = Eigen::Vector3d::Zero();
  const int begin = st.offsets[static_cast<size_t>(t)], end = st.offsets[static_cast<size_t>(t) + 1];
  for (int a = begin; a < end; ++a) {
    const Eigen::Vector3d we =
        st.weight[static_cast<size_t>(a)] * (pi - p.row(st.neighbour[static_cast<size_t>(a)]).transpose());
    S.noalias() += st.rest_edge.row(a).transpose() * we.transpose();
    laplacian += we;
  }
  const double rest_norm = st.rest_norm(t);
  if (rest_norm > 0.0) {
    const Eigen::Matrix3d previous = R;  // the last iteration's rotation of this term
    const RotationFit rf = fit_rotation(S, V, R_is_previous ? &previous : nullptr);
    R = rf.R;
    if (rf.degenerate) R = rotation_about_axis(rf.u1, rf.v1, unweighted_covariance(st, p, pi, begin, end));
    s = std::clamp((R * S).trace() / rest_norm, kMinScale, kMaxScale);
  } else {
    R.setIdentity();
    s = 1.0;
  }
  // The rigid residual in a second pass rather than expanded through S: at a fixed point
  // the expansion would cancel to round-off of the rest scale instead of ~0.
  double rigid = 0.0, similarity = 0.0;
  if (lambda > 0.0 || similar > 0.0) {
    for (int a = begin; a < end; ++a) {
      const Eigen::Vector3d e = pi - p.row(st.neighbour[static_cast<size_t>(a)]).transpose();
      const Eigen::Vector3d Re0 = R * st.rest_edge.row(a).transpose();
      rigid += st.weight[static_cast<size_t>(a)] * (e - Re0).squaredNorm();
      if (similar > 0.0) similarity += st.weight[static_cast<size_t>(a)] * (e - s * Re0).squaredNorm();
    }
  }
  const double smooth = (laplacian - s * (R * st.rest_laplacian.row(t).transpose())).squaredNorm();
  return lambda * rigid + similar * similarity + (1.0 - lambda - similar) * smooth;
}

// Threads only for stencils of at least this many terms. The 1k-vertex edge-domain lift
// (1,892 terms) took 1.16 ms on two threads and 0.81 ms on one with another process keeping
// a core busy (0.36 vs 0.76 ms without it): below ~4k terms a second thread is not worth
// a wake-up that a busy core can delay.
constexpr int kMinParallelTerms = 4096;
constexpr int kTermsPerChunk = 256;

}  // namespace

void fit_local(const NodeStencil& st, const RowMatrixX3d& p, const Eigen::VectorXd& lambda, LocalFit& fit,
               const Eigen::VectorXd& similar) {
  const bool has_similar = similar.size() != 0;
  const int T = st.n_terms;
  const bool warm = fit.rotation.size() == static_cast<size_t>(T);  // rotations to start from
  fit.rotation.resize(static_cast<size_t>(T));
  fit.scale.resize(T);
  fit.term_energy.resize(T);
  if (fit.right_vectors.size() != static_cast<size_t>(T)) fit.right_vectors.assign(static_cast<size_t>(T), Eigen::Matrix3d::Identity());
  parallel_for(T, kTermsPerChunk, kMinParallelTerms, [&](int begin, int end) {
    for (int t = begin; t < end; ++t) {
      double s = 1.0;
      fit.term_energy(t) = fit_term(st, p, lambda(t), has_similar ? similar(t) : 0.0, t,
                                    fit.rotation[static_cast<size_t>(t)],
                                    fit.right_vectors[static_cast<size_t>(t)], s, warm);
      fit.scale(t) = s;
    }
  });
  fit.energy = fit.term_energy.sum();  // a fixed order: the same energy on every run
}

}  // namespace edgedeform
