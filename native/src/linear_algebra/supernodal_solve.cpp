#include "linear_algebra/supernodal_solve.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "base/parallel.h"

namespace edgedeform {

namespace {

// The right-hand sides are kept row-interleaved (row r's k values side by side), so that one
// factor entry updates all of them from one cache line. K is fixed at compile time for the
// global step's 3 (0: the count is a runtime argument, at most kMaxRightHandSides), so that the
// inner loops unroll. One column at a time: applying panels of 2-4 columns per row of the
// work array was slower on the koala's factors (measured, 2026-11-30).
// Subtrees are opened until the larger half has at most kMaxHalfShare of their work; a tail
// (the opened supernodes) above kMaxTailShare of all the work gains too little: no split.
constexpr double kMaxHalfShare = 0.7;
constexpr double kMaxTailShare = 0.3;

struct Supernode {
  int first_column, columns, height;  // height: rows stored, the diagonal block's included
  const int* rows;
  const double* block;  // column-major, height rows per column
  const double* column(int j) const { return block + static_cast<ptrdiff_t>(j) * height; }
  double entries() const { return static_cast<double>(columns) * height; }
};

// A supernode's pattern only (no values: a symbolic factor has none, and the split needs none).
Supernode supernode_shape(const SupernodalFactor& L, int s) {
  return {L.super[s], L.super[s + 1] - L.super[s], L.pi[s + 1] - L.pi[s], L.rows + L.pi[s], nullptr};
}

Supernode supernode(const SupernodalFactor& L, int s) {
  Supernode sn = supernode_shape(L, s);
  sn.block = L.values + L.px[s];
  return sn;
}

// Where the forward substitution of one subtree writes: its own rows (columns below
// `own_end`) in w, the rows of its ancestors in the tail, which both halves update, in its
// half's buffer (they are added up afterwards in a fixed order).
struct Target {
  double* w;
  int own_end;            // columns from here on are the tail's (everything: n)
  double* tail;           // a tail column's row at tail + tail_slot[column] k
  const int* tail_slot;
  double* row(int r, int k) const {
    return r < own_end ? w + static_cast<ptrdiff_t>(r) * k : tail + static_cast<ptrdiff_t>(tail_slot[r]) * k;
  }
};

// L y = b over supernodes [first, end), column by column: each solved unknown (copied to
// locals, which cannot alias the rows written) is subtracted from the rows below it.
template <int K>
void forward(const SupernodalFactor& L, int first, int end, const Target& out, int k_runtime) {
  const int k = K > 0 ? K : k_runtime;
  double x[K > 0 ? K : kMaxRightHandSides];
  for (int s = first; s < end; ++s) {
    const Supernode sn = supernode(L, s);
    for (int j = 0; j < sn.columns; ++j) {
      const double* col = sn.column(j);
      double* wj = out.w + static_cast<ptrdiff_t>(sn.first_column + j) * k;
      const double inv = 1.0 / col[j];
      for (int c = 0; c < k; ++c) x[c] = wj[c] *= inv;
      for (int i = j + 1; i < sn.height; ++i) {
        double* wi = out.row(sn.rows[i], k);
        const double l = col[i];
        for (int c = 0; c < k; ++c) wi[c] -= l * x[c];
      }
    }
  }
}

// L^T x = y over supernodes [first, end), from the last: each unknown loses the dot product
// of its column below the diagonal with the rows solved before it.
template <int K>
void backward(const SupernodalFactor& L, int first, int end, double* w, int k_runtime) {
  const int k = K > 0 ? K : k_runtime;
  double sum[K > 0 ? K : kMaxRightHandSides];
  for (int s = end - 1; s >= first; --s) {
    const Supernode sn = supernode(L, s);
    for (int j = sn.columns - 1; j >= 0; --j) {
      const double* col = sn.column(j);
      double* wj = w + static_cast<ptrdiff_t>(sn.first_column + j) * k;
      for (int c = 0; c < k; ++c) sum[c] = wj[c];
      for (int i = j + 1; i < sn.height; ++i) {
        const double* wi = w + static_cast<ptrdiff_t>(sn.rows[i]) * k;
        const double l = col[i];
        for (int c = 0; c < k; ++c) sum[c] -= l * wi[c];
      }
      const double inv = 1.0 / col[j];
      for (int c = 0; c < k; ++c) wj[c] = sum[c] * inv;
    }
  }
}

template <int K>
void substitute(const SupernodalFactor& L, const TreeSplit& split, double* w, SolveWork& work, int k) {
  if (!split.parallel()) {
    forward<K>(L, 0, L.supernodes, Target{w, L.n, nullptr, nullptr}, k);
    backward<K>(L, 0, L.supernodes, w, k);
    return;
  }
  const auto tail_entries = static_cast<size_t>(split.tail_columns) * static_cast<size_t>(k);
  for (auto& buffer : work.tail) buffer.assign(tail_entries, 0.0);
  parallel_for(2, 1, 2, [&](int begin, int end) {
    for (int h = begin; h < end; ++h)
      for (const auto& range : split.halves[h])
        forward<K>(L, range.first, range.second,
                   Target{w, L.super[range.second], work.tail[h].data(), split.tail_slot.data()}, k);
  });
  for (int s : split.tail)
    for (int c = L.super[s]; c < L.super[s + 1]; ++c) {
      const auto slot = static_cast<size_t>(split.tail_slot[static_cast<size_t>(c)]) * static_cast<size_t>(k);
      for (int e = 0; e < k; ++e) w[static_cast<ptrdiff_t>(c) * k + e] += work.tail[0][slot + e] + work.tail[1][slot + e];
    }
  for (int s : split.tail) forward<K>(L, s, s + 1, Target{w, L.n, nullptr, nullptr}, k);
  for (auto s = split.tail.rbegin(); s != split.tail.rend(); ++s) backward<K>(L, *s, *s + 1, w, k);
  parallel_for(2, 1, 2, [&](int begin, int end) {
    for (int h = begin; h < end; ++h)
      for (const auto& range : split.halves[h]) backward<K>(L, range.first, range.second, w, k);
  });
}

}  // namespace

TreeSplit split_elimination_tree(const SupernodalFactor& L, double min_entries) {
  const int S = L.supernodes;
  // Not on the thread count: the split changes the order of the tail's sums, so a factor
  // solved split on 2 threads and unsplit on 1 gave positions 9e-15 apart (head sample).
  // Split, the halves run one after the other on 1 thread with the same arithmetic.
  if (S < 2) return {};
  // The supernodal elimination tree: a supernode's parent holds the first row below its
  // diagonal block.
  std::vector<int> owner(static_cast<size_t>(L.n));
  for (int s = 0; s < S; ++s)
    for (int c = L.super[s]; c < L.super[s + 1]; ++c) owner[static_cast<size_t>(c)] = s;
  std::vector<std::vector<int>> children(static_cast<size_t>(S) + 1);  // [S]: the roots
  std::vector<int> first(static_cast<size_t>(S)), size(static_cast<size_t>(S), 1);
  std::vector<double> work(static_cast<size_t>(S));
  double total = 0.0;
  for (int s = 0; s < S; ++s) {
    const auto u = static_cast<size_t>(s);
    const Supernode sn = supernode_shape(L, s);
    first[u] = s;
    work[u] += sn.entries();
    total += sn.entries();
    for (int c : children[u]) {  // all before s, so complete
      first[u] = std::min(first[u], first[static_cast<size_t>(c)]);
      size[u] += size[static_cast<size_t>(c)];
      work[u] += work[static_cast<size_t>(c)];
    }
    // Subtrees must be the contiguous ranges of a postorder, else no split.
    if (first[u] != s - size[u] + 1) return {};
    const int parent = sn.height > sn.columns ? owner[static_cast<size_t>(sn.rows[sn.columns])] : S;
    if (parent <= s) return {};
    children[static_cast<size_t>(parent)].push_back(s);
  }
  if (total < min_entries) return {};
  // Open the heaviest subtree (its root joins the tail, its children become subtrees) until
  // the subtrees fall into two halves of about equal work: largest first, each to the
  // lighter half.
  std::vector<int> subtrees = children[static_cast<size_t>(S)], tail;
  double tail_work = 0.0;
  const auto heavier = [&](int a, int b) { return work[static_cast<size_t>(a)] > work[static_cast<size_t>(b)]; };
  for (;;) {
    std::sort(subtrees.begin(), subtrees.end(), heavier);
    double half_work[2] = {0.0, 0.0};
    TreeSplit split;
    for (int c : subtrees) {
      const int h = half_work[0] <= half_work[1] ? 0 : 1;
      half_work[h] += work[static_cast<size_t>(c)];
      split.halves[h].emplace_back(first[static_cast<size_t>(c)], c + 1);
    }
    if (subtrees.size() >= 2 && std::max(half_work[0], half_work[1]) <= kMaxHalfShare * (half_work[0] + half_work[1])) {
      std::sort(tail.begin(), tail.end());
      split.tail_slot.assign(static_cast<size_t>(L.n), -1);
      for (int s : tail)
        for (int c = L.super[s]; c < L.super[s + 1]; ++c) split.tail_slot[static_cast<size_t>(c)] = split.tail_columns++;
      split.tail = std::move(tail);
      return split;
    }
    const int open = subtrees.front();
    const Supernode sn = supernode_shape(L, open);
    tail_work += sn.entries();
    if (tail_work > kMaxTailShare * total || children[static_cast<size_t>(open)].empty()) return {};
    tail.push_back(open);
    subtrees.erase(subtrees.begin());
    subtrees.insert(subtrees.end(), children[static_cast<size_t>(open)].begin(), children[static_cast<size_t>(open)].end());
  }
}

void supernodal_solve(const SupernodalFactor& L, const TreeSplit& split, const Eigen::MatrixXd& B,
                      Eigen::MatrixXd& X, SolveWork& work) {
  const int n = L.n, k = static_cast<int>(B.cols());
  if (B.rows() != n || k < 1 || k > kMaxRightHandSides)
    throw std::invalid_argument("supernodal_solve: B must have the factor's rows and 1.." +
                                std::to_string(kMaxRightHandSides) + " columns");
  work.w.resize(static_cast<size_t>(n) * static_cast<size_t>(k));
  double* w = work.w.data();
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < k; ++c) w[static_cast<ptrdiff_t>(r) * k + c] = B(L.perm[r], c);
  if (k == 3)
    substitute<3>(L, split, w, work, k);
  else
    substitute<0>(L, split, w, work, k);
  X.resize(n, k);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < k; ++c) X(L.perm[r], c) = w[static_cast<ptrdiff_t>(r) * k + c];
}

}  // namespace edgedeform
