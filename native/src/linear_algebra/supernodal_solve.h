// Forward and back substitution with a supernodal LL^T factor (CHOLMOD's layout) for the
// global step's three right-hand sides, in plain loops, on two threads where the
// elimination tree splits.
//
// Why not cholmod_solve2: per supernode it calls BLAS (dtrsm, dgemm) on blocks a few
// columns wide with 3 right-hand sides, and OpenBLAS spends much of that in call overhead
// and packing copies (perf, koala 50k, edge lambda 0.5, 200 iterations: the packing copies
// alone took 5.5 % of all samples; these loops took 3.3 ms where it took 5.6, primal
// lambda = 1).
#pragma once

#include <utility>
#include <vector>

#include "base/types.h"

namespace edgedeform {

// A supernodal factor as CHOLMOD stores it (cholmod_factor with is_super, is_ll, int
// indices), borrowed: supernode s holds columns super[s] .. super[s+1]-1; its row indices
// are rows[pi[s] .. pi[s+1]) (the first ones are its own columns, in order), and its values
// a column-major block at values + px[s] with one row per row index. perm[k] is the row of A
// that became row k (L L^T = P A P^T).
struct SupernodalFactor {
  int n = 0;
  int supernodes = 0;
  const int* super = nullptr;
  const int* pi = nullptr;
  const int* px = nullptr;
  const int* rows = nullptr;
  const double* values = nullptr;
  const int* perm = nullptr;
};

// The elimination tree cut in two halves of about equal work that solve in parallel. Each
// half is a list of whole subtrees (supernode ranges: subtrees are contiguous in CHOLMOD's
// postorder), which touch only their own columns and the tail's; the tail (the subtrees'
// ancestors) is solved alone. Depends on the analysis only. `halves` are empty when the
// tree does not split well or the factor is too small to be worth a second thread.
struct TreeSplit {
  std::vector<std::pair<int, int>> halves[2];  // [first, end) supernode ranges
  std::vector<int> tail;                       // the other supernodes, ascending
  std::vector<int> tail_slot;                  // per column: its row in a tail buffer, or -1
  int tail_columns = 0;
  bool parallel() const { return !halves[0].empty() && !halves[1].empty(); }
};
// Reads the pattern only (values may be null, as in a symbolic factor). Factors with fewer
// stored entries than min_entries are solved on one thread (a wake-up costs more).
constexpr double kMinParallelSolveEntries = 200000;
TreeSplit split_elimination_tree(const SupernodalFactor& L, double min_entries = kMinParallelSolveEntries);

// Most right-hand sides one solve takes (the global step has 3).
constexpr int kMaxRightHandSides = 16;

// Scratch a caller keeps, so that a solve allocates nothing after the first.
struct SolveWork {
  std::vector<double> w;        // the permuted right-hand sides, row-interleaved
  std::vector<double> tail[2];  // each half's updates of the tail's rows
};

// Solves A X = B. B and X are (n x k), column-major, 1 <= k <= kMaxRightHandSides (std::invalid_argument
// otherwise, X untouched). The result does not depend on which thread ran which half.
void supernodal_solve(const SupernodalFactor& L, const TreeSplit& split, const Eigen::MatrixXd& B,
                      Eigen::MatrixXd& X, SolveWork& work);

}  // namespace edgedeform
