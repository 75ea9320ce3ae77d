#include "edgedeform/newton_matrix.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "edgedeform/parallel.h"

namespace edgedeform {

namespace {

constexpr int kMinParallelRows = 2048;
constexpr int kRowsPerChunk = 256;

// The slot of block (r, v) (columns ascend within a row).
int find_slot(const std::vector<int>& row_start, const std::vector<int>& slot_column, int r, int v) {
  const auto begin = slot_column.begin() + row_start[static_cast<size_t>(r)];
  const auto end = slot_column.begin() + row_start[static_cast<size_t>(r) + 1];
  const auto it = std::lower_bound(begin, end, v);
  if (it == end || *it != v) throw std::logic_error("NewtonMatrix: a block outside the pattern");
  return static_cast<int>(it - slot_column.begin());
}

// Free vertex slots (local id < nf) of stencil node `node`, with their weight in the node's
// position (each slot 1/2; both slots are the same vertex in the primal domain).
template <typename Visit>
void node_vertices(const ConstrainedSystem& sys, int node, int nf, Visit&& visit) {
  for (int c = 0; c < 2; ++c) {
    const int v = sys.stencil_node_vertices(node, c);
    if (v < nf) visit(v, 0.5);
  }
}

}  // namespace

NewtonMatrix::NewtonMatrix(const ConstrainedSystem& system, const AssembledSystem& assembled)
    : system_(&system), assembled_(&assembled), nf_(system.n_free()) {
  const NodeStencil& st = system.stencil;
  const RotationOperator& H = assembled.H;
  const int T = st.n_terms;
  if (H.rows() != nf_ || H.terms() != T || assembled.A.rows() != nf_)
    throw std::invalid_argument("NewtonMatrix: the operators are not the system's");

  // Each term's free vertices: those its weighted arcs touch (a clamped arc adds nothing to
  // the covariance, so its vertices do not move the fit).
  term_start_.assign(1, 0);
  std::vector<int> scratch;
  for (int t = 0; t < T; ++t) {
    scratch.clear();
    const auto add = [&](int v, double) { scratch.push_back(v); };
    for (int a = st.offsets[static_cast<size_t>(t)]; a < st.offsets[static_cast<size_t>(t) + 1]; ++a) {
      if (st.weight[static_cast<size_t>(a)] == 0.0) continue;
      node_vertices(system, st.self[static_cast<size_t>(t)], nf_, add);
      node_vertices(system, st.neighbour[static_cast<size_t>(a)], nf_, add);
    }
    std::sort(scratch.begin(), scratch.end());
    scratch.erase(std::unique(scratch.begin(), scratch.end()), scratch.end());
    term_vertex_.insert(term_vertex_.end(), scratch.begin(), scratch.end());
    term_start_.push_back(static_cast<int>(term_vertex_.size()));
  }

  // Each term's right-side rows (the rows of its blocks in H): together with its vertices
  // they span the term's block of D. The pattern takes (rows u vertices)^2, symmetric.
  std::vector<std::vector<int>> term_rows(static_cast<size_t>(T));
  for (int r = 0; r < nf_; ++r)
    for (int b = H.offsets()[static_cast<size_t>(r)]; b < H.offsets()[static_cast<size_t>(r) + 1]; ++b)
      term_rows[static_cast<size_t>(H.block_term(b))].push_back(r);
  std::vector<int> span_start(1, 0), span;
  for (int t = 0; t < T; ++t) {
    scratch.assign(term_vertex_.begin() + term_start_[static_cast<size_t>(t)],
                   term_vertex_.begin() + term_start_[static_cast<size_t>(t) + 1]);
    scratch.insert(scratch.end(), term_rows[static_cast<size_t>(t)].begin(), term_rows[static_cast<size_t>(t)].end());
    std::sort(scratch.begin(), scratch.end());
    scratch.erase(std::unique(scratch.begin(), scratch.end()), scratch.end());
    span.insert(span.end(), scratch.begin(), scratch.end());
    span_start.push_back(static_cast<int>(span.size()));
  }
  term_rows.clear();
  term_rows.shrink_to_fit();
  // Vertex -> the terms whose span holds it.
  std::vector<int> incidence_start(static_cast<size_t>(nf_) + 1, 0), incidence(span.size());
  for (int v : span) ++incidence_start[static_cast<size_t>(v) + 1];
  for (int v = 0; v < nf_; ++v) incidence_start[static_cast<size_t>(v) + 1] += incidence_start[static_cast<size_t>(v)];
  {
    std::vector<int> fill(incidence_start.begin(), incidence_start.end() - 1);
    for (int t = 0; t < T; ++t)
      for (int k = span_start[static_cast<size_t>(t)]; k < span_start[static_cast<size_t>(t) + 1]; ++k)
        incidence[static_cast<size_t>(fill[static_cast<size_t>(span[static_cast<size_t>(k)])]++)] = t;
  }

  // Block row v (the pattern is symmetric: also column v): A's rows in column v, and every
  // vertex of every span that holds v.
  const SparseMatrix& A = assembled.A;
  std::vector<int> seen(static_cast<size_t>(nf_), -1);
  row_start_.assign(1, 0);
  for (int v = 0; v < nf_; ++v) {
    scratch.clear();
    const auto mark = [&](int r) {
      if (seen[static_cast<size_t>(r)] != v) {
        seen[static_cast<size_t>(r)] = v;
        scratch.push_back(r);
      }
    };
    mark(v);
    for (SparseMatrix::InnerIterator it(A, v); it; ++it) mark(static_cast<int>(it.row()));
    for (int k = incidence_start[static_cast<size_t>(v)]; k < incidence_start[static_cast<size_t>(v) + 1]; ++k) {
      const int t = incidence[static_cast<size_t>(k)];
      for (int j = span_start[static_cast<size_t>(t)]; j < span_start[static_cast<size_t>(t) + 1]; ++j)
        mark(span[static_cast<size_t>(j)]);
    }
    std::sort(scratch.begin(), scratch.end());
    slot_column_.insert(slot_column_.end(), scratch.begin(), scratch.end());
    row_start_.push_back(static_cast<int>(slot_column_.size()));
  }

  // Scatter positions: H's blocks against their term's vertices, and A's entries.
  block_scatter_start_.assign(1, 0);
  for (int r = 0; r < nf_; ++r)
    for (int b = H.offsets()[static_cast<size_t>(r)]; b < H.offsets()[static_cast<size_t>(r) + 1]; ++b) {
      const int t = H.block_term(b);
      for (int j = term_start_[static_cast<size_t>(t)]; j < term_start_[static_cast<size_t>(t) + 1]; ++j)
        block_scatter_.push_back(find_slot(row_start_, slot_column_, r, term_vertex_[static_cast<size_t>(j)]));
      block_scatter_start_.push_back(static_cast<long>(block_scatter_.size()));
    }
  a_scatter_.resize(static_cast<size_t>(A.nonZeros()));
  for (int j = 0; j < nf_; ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
      a_scatter_[static_cast<size_t>(&it.value() - A.valuePtr())] =
          find_slot(row_start_, slot_column_, j, static_cast<int>(it.row()));

  // The scalar matrix K^T: its column 3r + i is K's row 3r + i, the entries 3v + c of row r's blocks.
  const long slots = static_cast<long>(slot_column_.size());
  K_.resize(3 * nf_, 3 * nf_);
  K_.resizeNonZeros(9 * slots);
  int* outer = K_.outerIndexPtr();
  int* inner = K_.innerIndexPtr();
  for (int r = 0; r < nf_; ++r) {
    const int first = row_start_[static_cast<size_t>(r)], blocks = row_start_[static_cast<size_t>(r) + 1] - first;
    for (int i = 0; i < 3; ++i) {
      const long start = 9L * first + 3L * i * blocks;
      outer[3 * r + i] = static_cast<int>(start);
      for (int k = 0; k < blocks; ++k)
        for (int c = 0; c < 3; ++c) inner[start + 3 * k + c] = 3 * slot_column_[static_cast<size_t>(first + k)] + c;
    }
  }
  outer[3 * nf_] = static_cast<int>(9 * slots);
  std::fill(K_.valuePtr(), K_.valuePtr() + 9 * slots, 0.0);
}

long NewtonMatrix::position(int slot, int r, int i, int c) const {
  const int first = row_start_[static_cast<size_t>(r)], blocks = row_start_[static_cast<size_t>(r) + 1] - first;
  return 9L * first + 3L * i * blocks + 3L * (slot - first) + c;
}

void NewtonMatrix::assemble(const FixedPointLinearization& lin) {
  if (&lin.system() != system_ || &lin.assembled() != assembled_)
    throw std::logic_error("NewtonMatrix::assemble: a linearization of another system");
  const ConstrainedSystem& sys = *system_;
  const NodeStencil& st = sys.stencil;
  const RotationOperator& H = assembled_->H;
  const LocalFit& fit = lin.fit();
  const FitLinearization& fl = lin.fit_linearization();
  const int T = st.n_terms;

  // In_t: how (omega_t, ds_t) respond to each of the term's vertices, a 4 x 3 block per
  // vertex (rows: omega, then ds), from the covariance change dS = sum_a w_a e0_a de_a^T:
  // vee(R dS - (R dS)^T) = sum_a w_a (de_a x u_a) and tr(R dS) = sum_a w_a u_a . de_a, u_a = R e0_a.
  std::vector<double> response(12 * term_vertex_.size(), 0.0);
  parallel_for(T, kRowsPerChunk, kMinParallelRows, [&](int begin, int end) {
    for (int t = begin; t < end; ++t) {
      if (!(st.rest_norm(t) > 0.0)) continue;  // R = I, s = 1 whatever the positions
      const int first = term_start_[static_cast<size_t>(t)], last = term_start_[static_cast<size_t>(t) + 1];
      const Eigen::Matrix3d& R = fit.rotation[static_cast<size_t>(t)];
      const Eigen::Matrix3d& omega_map = fl.omega_map[static_cast<size_t>(t)];
      const double gain = fl.scale_gain(t);
      for (int a = st.offsets[static_cast<size_t>(t)]; a < st.offsets[static_cast<size_t>(t) + 1]; ++a) {
        const double w = st.weight[static_cast<size_t>(a)];
        if (w == 0.0) continue;
        const Eigen::Vector3d u = R * st.rest_edge.row(a).transpose();
        Eigen::Matrix3d cross;  // de -> de x u = -[u]x de
        cross << 0.0, u(2), -u(1), -u(2), 0.0, u(0), u(1), -u(0), 0.0;
        Eigen::Matrix<double, 4, 3> Q;
        Q.topRows<3>() = w * omega_map * cross;
        Q.row(3) = (w * gain) * u.transpose();
        // de_a = p_self - p_neighbour, each node the mean of its vertex slots.
        const auto add = [&](int v, double coefficient) {
          const int j = static_cast<int>(std::lower_bound(term_vertex_.begin() + first, term_vertex_.begin() + last, v) -
                                         term_vertex_.begin());
          Eigen::Map<Eigen::Matrix<double, 4, 3>> block(&response[12 * static_cast<size_t>(j)]);
          block += coefficient * Q;
        };
        node_vertices(sys, st.self[static_cast<size_t>(t)], nf_, add);
        node_vertices(sys, st.neighbour[static_cast<size_t>(a)], nf_,
                      [&](int v, double coefficient) { add(v, -coefficient); });
      }
    }
  });

  // K = A (x) I3 - sum over right-side blocks b = (r, t) of Out_b In_t, Out_b = [-[R g]x, R k]
  // (rotation_operator.h's apply_derivative). Rows in parallel: each row's entries are its own,
  // and stored together (K^T's columns).
  double* values = K_.valuePtr();
  std::fill(values, values + K_.nonZeros(), 0.0);
  const SparseMatrix& A = assembled_->A;
  parallel_for(nf_, kRowsPerChunk, kMinParallelRows, [&](int begin, int end) {
    Eigen::Vector3d g, k;
    for (int r = begin; r < end; ++r) {
      const long row_stride = 3L * (row_start_[static_cast<size_t>(r) + 1] - row_start_[static_cast<size_t>(r)]);
      for (SparseMatrix::InnerIterator it(A, r); it; ++it) {  // A symmetric: column r is row r
        const int slot = a_scatter_[static_cast<size_t>(&it.value() - A.valuePtr())];
        for (int c = 0; c < 3; ++c) values[position(slot, r, c, c)] += it.value();
      }
      for (int b = H.offsets()[static_cast<size_t>(r)]; b < H.offsets()[static_cast<size_t>(r) + 1]; ++b) {
        const int t = H.block_term(b);
        const Eigen::Matrix3d& R = fit.rotation[static_cast<size_t>(t)];
        H.block_vectors(b, fit.scale(t), g, k);
        const Eigen::Vector3d Rg = R * g;
        Eigen::Matrix<double, 3, 4> out;
        out << 0.0, Rg(2), -Rg(1), 0.0, -Rg(2), 0.0, Rg(0), 0.0, Rg(1), -Rg(0), 0.0, 0.0;  // -[Rg]x
        out.col(3) = R * k;
        const long scatter = block_scatter_start_[static_cast<size_t>(b)];
        const int first = term_start_[static_cast<size_t>(t)];
        for (int j = first; j < term_start_[static_cast<size_t>(t) + 1]; ++j) {
          const Eigen::Map<const Eigen::Matrix<double, 4, 3>> in(&response[12 * static_cast<size_t>(j)]);
          const Eigen::Matrix3d block = out * in;
          const long at = position(block_scatter_[static_cast<size_t>(scatter + (j - first))], r, 0, 0);
          for (int i = 0; i < 3; ++i)
            for (int c = 0; c < 3; ++c) values[at + i * row_stride + c] -= block(i, c);
        }
      }
    }
  });
}

SparseMatrix NewtonMatrix::block_pattern() const {  // symmetric: rows serve as columns
  SparseMatrix P(nf_, nf_);
  P.resizeNonZeros(static_cast<Eigen::Index>(slot_column_.size()));
  std::copy(row_start_.begin(), row_start_.end(), P.outerIndexPtr());
  std::copy(slot_column_.begin(), slot_column_.end(), P.innerIndexPtr());
  std::fill(P.valuePtr(), P.valuePtr() + slot_column_.size(), 1.0);
  return P;
}

std::vector<int> NewtonMatrix::coordinate_order(const std::vector<int>& vertex_order) {
  std::vector<int> order;
  order.reserve(3 * vertex_order.size());
  for (int v : vertex_order)
    for (int c = 0; c < 3; ++c) order.push_back(3 * v + c);
  return order;
}

}  // namespace edgedeform
