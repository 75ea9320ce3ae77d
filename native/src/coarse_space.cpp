#include "edgedeform/coarse_space.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <utility>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SparseLU>

#include "edgedeform/parallel.h"

namespace edgedeform {

namespace {

// A principal axis whose spread is below this fraction of the patch's largest is flat: its
// function would be round-off of the others.
constexpr double kFlatAxis = 1e-2;

struct FreeGraph {
  std::vector<int> offsets, adjacency;
  std::vector<double> length;
};

FreeGraph free_vertex_graph(const ConstrainedSystem& sys, const RowMatrixX3d& rest, const RowMatrixX2i& edges) {
  const int nf = sys.n_free();
  std::vector<int> local(static_cast<size_t>(sys.n_vertices), -1);
  for (int k = 0; k < nf; ++k) local[static_cast<size_t>(sys.free_vertices[static_cast<size_t>(k)])] = k;
  FreeGraph g;
  g.offsets.assign(static_cast<size_t>(nf) + 1, 0);
  std::vector<std::pair<int, int>> pairs;
  for (Eigen::Index e = 0; e < edges.rows(); ++e) {
    const int a = local[static_cast<size_t>(edges(e, 0))], b = local[static_cast<size_t>(edges(e, 1))];
    if (a < 0 || b < 0 || a == b) continue;
    pairs.emplace_back(a, b);
    ++g.offsets[static_cast<size_t>(a) + 1];
    ++g.offsets[static_cast<size_t>(b) + 1];
  }
  for (int v = 0; v < nf; ++v) g.offsets[static_cast<size_t>(v) + 1] += g.offsets[static_cast<size_t>(v)];
  g.adjacency.resize(static_cast<size_t>(g.offsets.back()));
  g.length.resize(g.adjacency.size());
  std::vector<int> cursor(g.offsets.begin(), g.offsets.end() - 1);
  for (const auto& [a, b] : pairs) {
    const double len = (rest.row(sys.free_vertices[static_cast<size_t>(a)]) - rest.row(sys.free_vertices[static_cast<size_t>(b)])).norm();
    const auto ia = static_cast<size_t>(cursor[static_cast<size_t>(a)]++), ib = static_cast<size_t>(cursor[static_cast<size_t>(b)]++);
    g.adjacency[ia] = b;
    g.length[ia] = len;
    g.adjacency[ib] = a;
    g.length[ib] = len;
  }
  return g;
}

// Farthest-point seeds, each claiming the vertices closer to it than to any earlier seed
// (Dijkstra from each new seed, visiting only the vertices it takes over).
std::vector<int> grow_patches(const FreeGraph& g, int nf, int n_patches, int& made) {
  std::vector<double> dist(static_cast<size_t>(nf), std::numeric_limits<double>::infinity());
  std::vector<int> patch(static_cast<size_t>(nf), -1);
  using Entry = std::pair<double, int>;
  made = 0;
  for (int p = 0; p < n_patches; ++p) {
    int seed = -1;
    double farthest = -1.0;
    for (int v = 0; v < nf; ++v)  // the lowest index among ties: deterministic
      if (dist[static_cast<size_t>(v)] > farthest) {
        farthest = dist[static_cast<size_t>(v)];
        seed = v;
      }
    if (seed < 0 || farthest == 0.0) break;  // every vertex is a seed already
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    dist[static_cast<size_t>(seed)] = 0.0;
    patch[static_cast<size_t>(seed)] = p;
    queue.emplace(0.0, seed);
    while (!queue.empty()) {
      const auto [d, v] = queue.top();
      queue.pop();
      if (d > dist[static_cast<size_t>(v)]) continue;
      for (int k = g.offsets[static_cast<size_t>(v)]; k < g.offsets[static_cast<size_t>(v) + 1]; ++k) {
        const int u = g.adjacency[static_cast<size_t>(k)];
        const double du = d + g.length[static_cast<size_t>(k)];
        if (du < dist[static_cast<size_t>(u)]) {
          dist[static_cast<size_t>(u)] = du;
          patch[static_cast<size_t>(u)] = p;
          queue.emplace(du, u);
        }
      }
    }
    ++made;
  }
  return patch;
}

}  // namespace

namespace {

// Partition-of-unity weights below this are dropped (and the rest renormalized): they would
// widen every vertex's entries for a jump of at most this size.
constexpr double kBlendDrop = 1e-3;

// Per free vertex, its (patch, weight) pairs after `steps` smoothing steps of the patch
// indicators, w <- (w + mean of the neighbours' w) / 2 over the free vertices' edges, then
// normalized to sum to one. Sorted by patch: deterministic.
std::vector<std::vector<std::pair<int, double>>> blend_weights(const FreeGraph& g, const std::vector<int>& patch,
                                                               int n_patches, int steps) {
  const auto nf = patch.size();
  std::vector<std::vector<std::pair<int, double>>> w(nf), next(nf);
  for (size_t v = 0; v < nf; ++v) w[v] = {{patch[v], 1.0}};
  std::vector<double> sum(static_cast<size_t>(n_patches), 0.0);
  std::vector<int> touched;
  auto add = [&](const std::vector<std::pair<int, double>>& from, double scale) {
    for (const auto& [p, x] : from) {
      if (sum[static_cast<size_t>(p)] == 0.0) touched.push_back(p);
      sum[static_cast<size_t>(p)] += scale * x;
    }
  };
  for (int step = 0; step < steps; ++step) {
    for (size_t v = 0; v < nf; ++v) {
      touched.clear();
      const int begin = g.offsets[v], end = g.offsets[v + 1];
      add(w[v], end > begin ? 0.5 : 1.0);
      for (int k = begin; k < end; ++k) add(w[static_cast<size_t>(g.adjacency[static_cast<size_t>(k)])], 0.5 / (end - begin));
      std::sort(touched.begin(), touched.end());
      next[v].clear();
      for (int p : touched) {
        next[v].emplace_back(p, sum[static_cast<size_t>(p)]);
        sum[static_cast<size_t>(p)] = 0.0;
      }
    }
    w.swap(next);
  }
  for (auto& entries : w) {
    double total = 0.0;
    for (const auto& e : entries) total += e.second;
    double kept = 0.0;
    std::vector<std::pair<int, double>> big;
    for (const auto& e : entries)
      if (e.second >= kBlendDrop * total) {
        big.push_back(e);
        kept += e.second;
      }
    for (auto& e : big) e.second /= kept;
    entries.swap(big);
  }
  return w;
}

}  // namespace

CoarseBasis build_coarse_basis(const ConstrainedSystem& sys, const RowMatrixX3d& rest, const RowMatrixX2i& edges,
                               int target_patches, int blend_steps) {
  CoarseBasis basis;
  const int nf = sys.n_free();
  const int n_patches = std::min(target_patches, nf / kMinPatchVertices);
  if (n_patches < 1) return basis;  // too small for a coarse space: the caller goes without
  const FreeGraph graph = free_vertex_graph(sys, rest, edges);
  int made = 0;
  basis.patch = grow_patches(graph, nf, n_patches, made);
  // Vertices no seed reached (more free components than patches) join the last patch
  // alone; their component then moves by that patch's functions, which is still a span.
  for (int& p : basis.patch)
    if (p < 0) p = std::max(made - 1, 0);
  basis.n_patches = std::max(made, 1);
  const auto P = static_cast<size_t>(basis.n_patches);
  basis.centre.assign(P, Eigen::Vector3d::Zero());
  basis.axes.assign(P, Eigen::Matrix3d::Identity());
  basis.scale.assign(P, Eigen::Vector3d::Ones());
  basis.functions.assign(P, 1);
  std::vector<int> count(P, 0);
  for (int v = 0; v < nf; ++v) {
    const auto p = static_cast<size_t>(basis.patch[static_cast<size_t>(v)]);
    basis.centre[p] += rest.row(sys.free_vertices[static_cast<size_t>(v)]).transpose();
    ++count[p];
  }
  std::vector<Eigen::Matrix3d> covariance(P, Eigen::Matrix3d::Zero());
  for (size_t p = 0; p < P; ++p)
    if (count[p] > 0) basis.centre[p] /= count[p];
  for (int v = 0; v < nf; ++v) {
    const auto p = static_cast<size_t>(basis.patch[static_cast<size_t>(v)]);
    const Eigen::Vector3d d = rest.row(sys.free_vertices[static_cast<size_t>(v)]).transpose() - basis.centre[p];
    covariance[p].noalias() += d * d.transpose();
  }
  for (size_t p = 0; p < P; ++p) {
    if (count[p] == 0) continue;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(covariance[p] / count[p]);
    const Eigen::Vector3d spread = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();  // ascending
    const double largest = spread(2);
    int kept = 0;
    for (int axis = 2; axis >= 0; --axis)  // largest first
      if (largest > 0.0 && spread(axis) > kFlatAxis * largest) {
        basis.axes[p].col(kept) = eig.eigenvectors().col(axis);
        basis.scale[p](kept) = spread(axis);
        ++kept;
      }
    basis.functions[p] = 1 + kept;
  }
  basis.offset.assign(P + 1, 0);
  for (size_t p = 0; p < P; ++p) basis.offset[p + 1] = basis.offset[p] + 3 * basis.functions[p];
  const auto weights = blend_weights(graph, basis.patch, basis.n_patches, std::max(blend_steps, 0));
  basis.entry_offset.assign(static_cast<size_t>(nf) + 1, 0);
  for (int v = 0; v < nf; ++v) {
    const Eigen::Vector3d x = rest.row(sys.free_vertices[static_cast<size_t>(v)]).transpose();
    for (const auto& [p, w] : weights[static_cast<size_t>(v)]) {
      const auto q = static_cast<size_t>(p);
      Eigen::Vector4d phi = Eigen::Vector4d::Zero();
      phi(0) = w;
      for (int f = 1; f < basis.functions[q]; ++f) phi(f) = w * (x - basis.centre[q]).dot(basis.axes[q].col(f - 1)) / basis.scale[q](f - 1);
      basis.entry_patch.push_back(p);
      basis.entry_value.push_back(phi);
    }
    basis.entry_offset[static_cast<size_t>(v) + 1] = static_cast<int>(basis.entry_patch.size());
  }
  return basis;
}

void restrict_to_coarse(const CoarseBasis& b, const Eigen::MatrixXd& x, Eigen::VectorXd& q) {
  q.setZero(b.dimension());
  for (Eigen::Index v = 0; v < x.rows(); ++v)
    for (int e = b.entry_offset[static_cast<size_t>(v)]; e < b.entry_offset[static_cast<size_t>(v) + 1]; ++e) {
      const auto p = static_cast<size_t>(b.entry_patch[static_cast<size_t>(e)]);
      const Eigen::Vector4d& phi = b.entry_value[static_cast<size_t>(e)];
      for (int f = 0; f < b.functions[p]; ++f)
        for (int c = 0; c < 3; ++c) q(b.offset[p] + 3 * f + c) += phi(f) * x(v, c);
    }
}

void prolong_from_coarse(const CoarseBasis& b, const Eigen::VectorXd& q, Eigen::MatrixXd& x) {
  const auto nf = static_cast<Eigen::Index>(b.n_free());
  x.setZero(nf, 3);
  for (Eigen::Index v = 0; v < nf; ++v)
    for (int e = b.entry_offset[static_cast<size_t>(v)]; e < b.entry_offset[static_cast<size_t>(v) + 1]; ++e) {
      const auto p = static_cast<size_t>(b.entry_patch[static_cast<size_t>(e)]);
      const Eigen::Vector4d& phi = b.entry_value[static_cast<size_t>(e)];
      for (int f = 0; f < b.functions[p]; ++f)
        for (int c = 0; c < 3; ++c) x(v, c) += phi(f) * q(b.offset[p] + 3 * f + c);
    }
}

namespace {
// The scalar basis: column 4 p + f is w_p phi_pf over the free vertices (f < functions[p]).
SparseMatrix scalar_basis(const CoarseBasis& b) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(b.entry_value.size() * 4);
  for (int v = 0; v < b.n_free(); ++v)
    for (int e = b.entry_offset[static_cast<size_t>(v)]; e < b.entry_offset[static_cast<size_t>(v) + 1]; ++e) {
      const int p = b.entry_patch[static_cast<size_t>(e)];
      for (int f = 0; f < b.functions[static_cast<size_t>(p)]; ++f)
        entries.emplace_back(v, 4 * p + f, b.entry_value[static_cast<size_t>(e)](f));
    }
  SparseMatrix S(b.n_free(), 4 * b.n_patches);
  S.setFromTriplets(entries.begin(), entries.end());
  return S;
}
}  // namespace

SparseMatrix coarse_basis_matrix(const CoarseBasis& b) {
  // The scalar basis on each coordinate: row v + nf c, column offset[p] + 3 f + c.
  const SparseMatrix S = scalar_basis(b);
  const int nf = b.n_free();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<size_t>(S.nonZeros()) * 3);
  for (int col = 0; col < S.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(S, col); it; ++it)
      for (int c = 0; c < 3; ++c)
        entries.emplace_back(static_cast<int>(it.row()) + nf * c, b.offset[static_cast<size_t>(col / 4)] + 3 * (col % 4) + c,
                             it.value());
  SparseMatrix U(3 * nf, b.dimension());
  U.setFromTriplets(entries.begin(), entries.end());
  return U;
}

SparseMatrix coarse_stiffness(const CoarseBasis& b, const SparseMatrix& A) {
  // A acts on each coordinate alike: U^T A U is S^T A S (S the scalar basis) on each.
  const SparseMatrix S = scalar_basis(b);
  const SparseMatrix SAS = SparseMatrix(S.transpose()) * (A * S);  // sequential products: a fixed order
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<size_t>(SAS.nonZeros()) * 3);
  for (int col = 0; col < SAS.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(SAS, col); it; ++it) {
      const int p = static_cast<int>(it.row()) / 4, f = static_cast<int>(it.row()) % 4, q = col / 4, g = col % 4;
      for (int c = 0; c < 3; ++c) entries.emplace_back(b.offset[static_cast<size_t>(p)] + 3 * f + c, b.offset[static_cast<size_t>(q)] + 3 * g + c, it.value());
    }
  SparseMatrix C(b.dimension(), b.dimension());
  C.setFromTriplets(entries.begin(), entries.end());
  return C;
}

namespace {

using Block = Eigen::Matrix<double, 12, 12>;
using PatchPair = std::pair<int, int>;
// Terms per chunk of the coarse assembly: chunks are fixed, so partial sums (merged in chunk
// order) do not depend on how many threads ran them.
constexpr int kCoarseChunk = 16384;

// The block of `patch` in a term's short list of patch blocks, appended (zero) if new.
template <class Block>
Block& patch_block(std::vector<std::pair<int, Block>>& blocks, int patch) {
  for (auto& [p, block] : blocks)
    if (p == patch) return block;
  blocks.emplace_back(patch, Block::Zero());
  return blocks.back().second;
}

// Per term: the free vertices its fit reads, with the covariance vector m_w that a unit
// move of each carries (dS = m_w dx_w^T).
void term_inputs(const ConstrainedSystem& sys, int t, std::vector<int>& vertex, std::vector<Eigen::Vector3d>& m) {
  const NodeStencil& st = sys.stencil;
  const int nf = sys.n_free();
  vertex.clear();
  m.clear();
  auto add = [&](int node, const Eigen::Vector3d& weight) {
    for (int slot = 0; slot < 2; ++slot) {
      const int w = sys.stencil_node_vertices(node, slot);
      if (w >= nf) continue;  // a fixed vertex does not move
      size_t k = 0;
      while (k < vertex.size() && vertex[k] != w) ++k;
      if (k == vertex.size()) {
        vertex.push_back(w);
        m.push_back(Eigen::Vector3d::Zero());
      }
      m[k] += 0.5 * weight;
    }
  };
  const int self = st.self[static_cast<size_t>(t)];
  add(self, st.rest_laplacian.row(t).transpose());
  for (int a = st.offsets[static_cast<size_t>(t)]; a < st.offsets[static_cast<size_t>(t) + 1]; ++a)
    add(st.neighbour[static_cast<size_t>(a)], -st.weight[static_cast<size_t>(a)] * st.rest_edge.row(a).transpose());
}

}  // namespace

SparseMatrix coarse_operator(const CoarseBasis& b, const SparseMatrix& coarse_A, const FixedPointLinearization& lin) {
  const ConstrainedSystem& sys = lin.system();
  const RotationOperator& H = lin.assembled().H;
  const LocalFit& fit = lin.fit();
  const FitLinearization& fl = lin.fit_linearization();
  const int T = sys.n_terms(), nf = sys.n_free();
  // Term-major view of the operator's blocks (its rows are vertices).
  std::vector<int> term_offset(static_cast<size_t>(T) + 1, 0), term_block, block_row(static_cast<size_t>(H.blocks()));
  for (int r = 0; r < nf; ++r)
    for (int k = H.offsets()[static_cast<size_t>(r)]; k < H.offsets()[static_cast<size_t>(r) + 1]; ++k) {
      block_row[static_cast<size_t>(k)] = r;
      ++term_offset[static_cast<size_t>(H.block_term(k)) + 1];
    }
  for (int t = 0; t < T; ++t) term_offset[static_cast<size_t>(t) + 1] += term_offset[static_cast<size_t>(t)];
  term_block.resize(static_cast<size_t>(H.blocks()));
  {
    std::vector<int> cursor(term_offset.begin(), term_offset.end() - 1);
    for (int k = 0; k < H.blocks(); ++k) term_block[static_cast<size_t>(cursor[static_cast<size_t>(H.block_term(k))]++)] = k;
  }

  // The patch pairs a term couples (its right-side patches x its fit's input patches): a
  // slot per pair, found through a P x P table.
  const int P = b.n_patches;
  std::vector<int> slot_of(static_cast<size_t>(P) * static_cast<size_t>(P), -1);
  std::vector<PatchPair> slots;
  {
    std::vector<int> vertex, in_p, out_p;
    std::vector<Eigen::Vector3d> m;
    for (int t = 0; t < T; ++t) {
      if (!(sys.stencil.rest_norm(t) > 0.0)) continue;
      term_inputs(sys, t, vertex, m);
      in_p.clear();
      out_p.clear();
      const auto entries_of = [&](int v, std::vector<int>& into) {
        for (int e = b.entry_offset[static_cast<size_t>(v)]; e < b.entry_offset[static_cast<size_t>(v) + 1]; ++e)
          into.push_back(b.entry_patch[static_cast<size_t>(e)]);
      };
      for (int w : vertex) entries_of(w, in_p);
      for (int k = term_offset[static_cast<size_t>(t)]; k < term_offset[static_cast<size_t>(t) + 1]; ++k)
        entries_of(block_row[static_cast<size_t>(term_block[static_cast<size_t>(k)])], out_p);
      for (int p : out_p)
        for (int q : in_p) {
          int& s = slot_of[static_cast<size_t>(p) * static_cast<size_t>(P) + static_cast<size_t>(q)];
          if (s < 0) {
            s = static_cast<int>(slots.size());
            slots.emplace_back(p, q);
          }
        }
    }
  }
  const int n_chunks = (T + kCoarseChunk - 1) / kCoarseChunk;
  std::vector<std::vector<Block>> partial(static_cast<size_t>(n_chunks));
  parallel_for(n_chunks, 1, 2, [&](int chunk_begin, int chunk_end) {
    std::vector<int> vertex;
    std::vector<Eigen::Vector3d> m;
    std::vector<std::pair<int, Eigen::Matrix<double, 4, 12>>> in_patch;   // U restricted, through the fit's response
    std::vector<std::pair<int, Eigen::Matrix<double, 12, 4>>> out_patch;  // U^T of the right side's response
    for (int chunk = chunk_begin; chunk < chunk_end; ++chunk) {
      std::vector<Block>& sum = partial[static_cast<size_t>(chunk)];
      sum.assign(slots.size(), Block::Zero());
      const int t_end = std::min(T, (chunk + 1) * kCoarseChunk);
      for (int t = chunk * kCoarseChunk; t < t_end; ++t) {
        if (!(sys.stencil.rest_norm(t) > 0.0)) continue;
        const Eigen::Matrix3d& R = fit.rotation[static_cast<size_t>(t)];
        term_inputs(sys, t, vertex, m);
        in_patch.clear();
        for (size_t k = 0; k < vertex.size(); ++k) {
          const int w = vertex[k];
          Eigen::Matrix<double, 4, 3> response;  // column c: the fit's response to dx_w = e_c
          for (int c = 0; c < 3; ++c) {
            const Eigen::Matrix3d dS = m[k] * Eigen::RowVector3d::Unit(c);
            Eigen::Vector3d omega;
            double ds = 0.0;
            fit_response(R, fl.omega_map[static_cast<size_t>(t)], fl.scale_gain(t), dS, omega, ds);
            response.col(c) << omega(0), omega(1), omega(2), ds;
          }
          for (int e = b.entry_offset[static_cast<size_t>(w)]; e < b.entry_offset[static_cast<size_t>(w) + 1]; ++e) {
            const int q = b.entry_patch[static_cast<size_t>(e)];
            auto& block = patch_block(in_patch, q);
            const Eigen::Vector4d& phi = b.entry_value[static_cast<size_t>(e)];
            for (int f = 0; f < b.functions[static_cast<size_t>(q)]; ++f) block.middleCols<3>(3 * f) += phi(f) * response;
          }
        }
        out_patch.clear();
        for (int k = term_offset[static_cast<size_t>(t)]; k < term_offset[static_cast<size_t>(t) + 1]; ++k) {
          const int block = term_block[static_cast<size_t>(k)];
          const int r = block_row[static_cast<size_t>(block)];
          Eigen::Vector3d g, kv;
          H.block_vectors(block, fit.scale(t), g, kv);
          const Eigen::Vector3d Rg = R * g, Rk = R * kv;
          Eigen::Matrix<double, 3, 4> O;  // d rhs_r = omega x (R g) + ds R k
          O << 0, Rg(2), -Rg(1), Rk(0),   //
              -Rg(2), 0, Rg(0), Rk(1),    //
              Rg(1), -Rg(0), 0, Rk(2);
          for (int e = b.entry_offset[static_cast<size_t>(r)]; e < b.entry_offset[static_cast<size_t>(r) + 1]; ++e) {
            const int p = b.entry_patch[static_cast<size_t>(e)];
            auto& block = patch_block(out_patch, p);
            const Eigen::Vector4d& phi = b.entry_value[static_cast<size_t>(e)];
            for (int f = 0; f < b.functions[static_cast<size_t>(p)]; ++f) block.middleRows<3>(3 * f) += phi(f) * O;
          }
        }
        for (const auto& [p, out] : out_patch)
          for (const auto& [q, in] : in_patch)
            sum[static_cast<size_t>(slot_of[static_cast<size_t>(p) * static_cast<size_t>(P) + static_cast<size_t>(q)])].noalias() -= out * in;
      }
    }
  });
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(slots.size() * 144 + static_cast<size_t>(coarse_A.nonZeros()));
  for (int col = 0; col < coarse_A.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(coarse_A, col); it; ++it) entries.emplace_back(static_cast<int>(it.row()), col, it.value());
  for (size_t s = 0; s < slots.size(); ++s) {
    Block total = Block::Zero();
    for (const auto& chunk : partial) total += chunk[s];  // chunk order: thread-count free
    const auto p = static_cast<size_t>(slots[s].first), q = static_cast<size_t>(slots[s].second);
    for (int i = 0; i < 3 * b.functions[p]; ++i)
      for (int j = 0; j < 3 * b.functions[q]; ++j)
        entries.emplace_back(b.offset[p] + i, b.offset[q] + j, total(i, j));  // zeros too: a fixed pattern
  }
  SparseMatrix C(b.dimension(), b.dimension());
  C.setFromTriplets(entries.begin(), entries.end());
  return C;
}

struct CoarseCorrection::Factor {
  Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>> lu;
  std::vector<int> outer, inner;  // the analysed pattern
};

bool CoarseCorrection::factor(const CoarseBasis& basis, const SparseMatrix& coarse) {
  ready_ = false;
  if (basis.dimension() == 0 || coarse.rows() != basis.dimension()) return false;
  SparseMatrix C = coarse;
  C.makeCompressed();
  const std::vector<int> outer(C.outerIndexPtr(), C.outerIndexPtr() + C.outerSize() + 1);
  const std::vector<int> inner(C.innerIndexPtr(), C.innerIndexPtr() + C.nonZeros());
  if (!factor_ || basis_ != &basis || factor_->outer != outer || factor_->inner != inner) {
    factor_ = std::make_shared<Factor>();  // a new pattern: a new ordering and analysis
    factor_->lu.analyzePattern(C);
    factor_->outer = outer;
    factor_->inner = inner;
  }
  basis_ = &basis;
  factor_->lu.factorize(C);
  if (factor_->lu.info() != Eigen::Success || !std::isfinite(factor_->lu.logAbsDeterminant())) return false;
  ready_ = true;
  return true;
}

void CoarseCorrection::apply(const Eigen::MatrixXd& r, Eigen::MatrixXd& out) const {
  if (!ready_) {
    out.setZero(r.rows(), 3);
    return;
  }
  Eigen::VectorXd q;
  restrict_to_coarse(*basis_, r, q);
  const Eigen::VectorXd solved = factor_->lu.solve(q);
  prolong_from_coarse(*basis_, solved, out);
}

}  // namespace edgedeform
