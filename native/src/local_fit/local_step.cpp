#include "local_fit/local_step.h"

#include <algorithm>
#include <cmath>


#include "local_fit/lanes.h"
#include "local_fit/term_shares.h"
#include "mesh/node_graph.h"
#include "base/parallel.h"

namespace edgedeform {

NodeStencil build_stencil(const NodeGraph& g, const RowMatrixX3d& rest_vertices, const std::vector<int>& term_nodes,
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
    const Eigen::RowVector3d pi = g.node_position(rest_vertices, i);
    for (int k = g.offsets[static_cast<size_t>(i)]; k < g.offsets[static_cast<size_t>(i) + 1]; ++k) {
      const double w = g.adjacency_weights[static_cast<size_t>(k)];
      const int j = g.adjacency[static_cast<size_t>(k)];
      st.neighbour.push_back(position_index[static_cast<size_t>(j)]);
      st.weight.push_back(w);
      rest_edges.push_back((pi - g.node_position(rest_vertices, j)).transpose());
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

// A term's covariance S = sum_j w e0_j e_j^T and its weighted Laplacian sum_j w e_j.
struct TermCovariance {
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  Eigen::Vector3d laplacian = Eigen::Vector3d::Zero();
  Eigen::Vector3d self;
  int begin = 0, end = 0;
};

TermCovariance start_covariance(const NodeStencil& st, const RowMatrixX3d& p, int t) {
  TermCovariance c;
  c.self = p.row(st.self[static_cast<size_t>(t)]).transpose();
  c.begin = st.offsets[static_cast<size_t>(t)];
  c.end = st.offsets[static_cast<size_t>(t) + 1];
  return c;
}

// Adds arcs [from, c.end) of the term to its covariance, in order.
void add_arcs(const NodeStencil& st, const RowMatrixX3d& p, int from, TermCovariance& c) {
  for (int a = from; a < c.end; ++a) {
    const Eigen::Vector3d we =
        st.weight[static_cast<size_t>(a)] * (c.self - p.row(st.neighbour[static_cast<size_t>(a)]).transpose());
    c.S.noalias() += st.rest_edge.row(a).transpose() * we.transpose();
    c.laplacian += we;
  }
}

// The covariances of terms t and t + 1: their first arcs (as many as the shorter term has)
// side by side in SIMD lanes, then the longer term's remaining arcs alone. Each lane does
// add_arcs' operations in add_arcs' order, so the results are the same, bit for bit.
void covariance_pair(const NodeStencil& st, const RowMatrixX3d& p, int t, TermCovariance c[2]) {
  const double* rest = st.rest_edge.data();
  for (int k = 0; k < 2; ++k) c[k] = start_covariance(st, p, t + k);
  const int shared = std::min(c[0].end - c[0].begin, c[1].end - c[1].begin);
  Lanes self[3], S[9], laplacian[3];
  for (int i = 0; i < 3; ++i) {
    self[i] = Lanes{c[0].self(i), c[1].self(i)};
    laplacian[i] = Lanes{0.0, 0.0};
  }
  for (auto& entry : S) entry = Lanes{0.0, 0.0};
  for (int m = 0; m < shared; ++m) {
    const int a0 = c[0].begin + m, a1 = c[1].begin + m;
    const double* p0 = p.data() + 3 * static_cast<ptrdiff_t>(st.neighbour[static_cast<size_t>(a0)]);
    const double* p1 = p.data() + 3 * static_cast<ptrdiff_t>(st.neighbour[static_cast<size_t>(a1)]);
    const Lanes w{st.weight[static_cast<size_t>(a0)], st.weight[static_cast<size_t>(a1)]};
    Lanes we[3], e0[3];
    for (int i = 0; i < 3; ++i) {
      we[i] = w * (self[i] - Lanes{p0[i], p1[i]});
      e0[i] = Lanes{rest[3 * static_cast<ptrdiff_t>(a0) + i], rest[3 * static_cast<ptrdiff_t>(a1) + i]};
    }
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) S[3 * i + j] += e0[i] * we[j];
    for (int i = 0; i < 3; ++i) laplacian[i] += we[i];
  }
  for (int k = 0; k < 2; ++k) {
    for (int i = 0; i < 3; ++i) {
      c[k].laplacian(i) = laplacian[i][k];
      for (int j = 0; j < 3; ++j) c[k].S(i, j) = S[3 * i + j][k];
    }
    add_arcs(st, p, c[k].begin + shared, c[k]);
  }
}

// The rest of term t's fit: R_t (unless Newton already refined it from the last iteration's
// rotation), s_t, and the term's energy.
double finish_term(const NodeStencil& st, const RowMatrixX3d& p, double lambda, double similar, int t,
                   const TermCovariance& c, bool refined, Eigen::Matrix3d& R, Eigen::Matrix3d& V, double& s) {
  const double rest_norm = st.rest_norm(t);
  if (rest_norm > 0.0) {
    if (!refined) {  // no previous rotation, or Newton declined it: the SVD
      const RotationFit rf = fit_rotation(c.S, V);
      R = rf.R;
      if (rf.degenerate) R = rotation_about_axis(rf.u1, rf.v1, unweighted_covariance(st, p, c.self, c.begin, c.end));
    }
    s = std::clamp((R * c.S).trace() / rest_norm, kMinScale, kMaxScale);
  } else {
    R.setIdentity();
    s = 1.0;
  }
  // The rigid residual in a second pass rather than expanded through S: at a fixed point
  // the expansion would cancel to round-off of the rest scale instead of ~0.
  // The similarity share (stiffness.h) uses the same R and s: they are its optimum too.
  double rigid = 0.0, similarity = 0.0;
  if (lambda > 0.0 || similar > 0.0) {
    for (int a = c.begin; a < c.end; ++a) {
      const Eigen::Vector3d e = c.self - p.row(st.neighbour[static_cast<size_t>(a)]).transpose();
      const Eigen::Vector3d Re0 = R * st.rest_edge.row(a).transpose();
      if (lambda > 0.0) rigid += st.weight[static_cast<size_t>(a)] * (e - Re0).squaredNorm();
      if (similar > 0.0) similarity += st.weight[static_cast<size_t>(a)] * (e - s * Re0).squaredNorm();
    }
  }
  const double smooth = (c.laplacian - s * (R * st.rest_laplacian.row(t).transpose())).squaredNorm();
  const TermShares share = term_shares(lambda, similar);
  return share.rigid * rigid + share.similar * similarity + share.smooth * smooth;
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
  const int T = st.n_terms;
  const bool has_similar = similar.size() != 0;
  const bool warm = fit.rotation.size() == static_cast<size_t>(T);  // rotations to start from
  fit.rotation.resize(static_cast<size_t>(T));
  fit.scale.resize(T);
  fit.term_energy.resize(T);
  if (fit.right_vectors.size() != static_cast<size_t>(T)) fit.right_vectors.assign(static_cast<size_t>(T), Eigen::Matrix3d::Identity());
  parallel_for(T, kTermsPerChunk, kMinParallelTerms, [&](int begin, int end) {
    // Two terms at a time: their covariances and Newton refinements share SIMD instructions.
    for (int t = begin; t < end; t += 2) {
      const int count = std::min(2, end - t);
      TermCovariance c[2];
      bool refine[2] = {false, false}, refined[2] = {false, false};
      if (count == 2) {
        covariance_pair(st, p, t, c);
      } else {
        c[0] = start_covariance(st, p, t);
        add_arcs(st, p, c[0].begin, c[0]);
      }
      for (int k = 0; k < count; ++k) refine[k] = warm && st.rest_norm(t + k) > 0.0;
      Eigen::Matrix3d* const R[2] = {&fit.rotation[static_cast<size_t>(t)],
                                     &fit.rotation[static_cast<size_t>(t + count - 1)]};
      if (count == 2 && refine[0] && refine[1]) {
        const Eigen::Matrix3d* const S[2] = {&c[0].S, &c[1].S};
        const int mask = refine_rotation_pair(S, R);
        refined[0] = mask & 1;
        refined[1] = mask & 2;
      } else {
        for (int k = 0; k < count; ++k)
          if (refine[k]) refined[k] = refine_rotation(c[k].S, *R[k]);
      }
      for (int k = 0; k < count; ++k) {
        double s = 1.0;
        fit.term_energy(t + k) = finish_term(st, p, lambda(t + k), has_similar ? similar(t + k) : 0.0, t + k, c[k],
                                             refined[k], *R[k],
                                             fit.right_vectors[static_cast<size_t>(t + k)], s);
        fit.scale(t + k) = s;
      }
    }
  });
  fit.energy = fit.term_energy.sum();  // a fixed order: the same energy on every run
}

}  // namespace edgedeform
