// The elimination-tree split of supernodal_solve.h on hand-made factor layouts, and a solve
// with a hand-made factor against the dense one it stores.
#include <gtest/gtest.h>

#include <algorithm>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "base/parallel.h"
#include "linear_algebra/supernodal_solve.h"

using namespace edgedeform;

namespace {

// A factor layout of single-column supernodes: column c's rows are c and below[c] (the
// parent first, then any further ancestors), values from the dense lower-triangular Ld.
struct Layout {
  std::vector<int> super, pi, px, rows, perm;
  std::vector<double> values;
  SupernodalFactor view() const {
    SupernodalFactor L;
    L.n = static_cast<int>(super.size()) - 1;
    L.supernodes = L.n;
    L.super = super.data();
    L.pi = pi.data();
    L.px = px.data();
    L.rows = rows.data();
    L.values = values.data();
    L.perm = perm.data();
    return L;
  }
};

Layout single_columns(const Eigen::MatrixXd& Ld) {
  Layout f;
  const int n = static_cast<int>(Ld.rows());
  for (int c = 0; c < n; ++c) {
    f.super.push_back(c);
    f.pi.push_back(static_cast<int>(f.rows.size()));
    f.px.push_back(static_cast<int>(f.values.size()));
    for (int r = c; r < n; ++r)
      if (r == c || Ld(r, c) != 0.0) {
        f.rows.push_back(r);
        f.values.push_back(Ld(r, c));
      }
    f.perm.push_back(c);
  }
  f.super.push_back(n);
  f.pi.push_back(static_cast<int>(f.rows.size()));
  f.px.push_back(static_cast<int>(f.values.size()));
  return f;
}

// Lower-triangular factor of a tree: parent[c] > c (or -1), L(parent, c) = -0.5, L(c, c) = 2.
Eigen::MatrixXd tree_factor(const std::vector<int>& parent) {
  const int n = static_cast<int>(parent.size());
  Eigen::MatrixXd Ld = Eigen::MatrixXd::Zero(n, n);
  for (int c = 0; c < n; ++c) {
    Ld(c, c) = 2.0;
    if (parent[static_cast<size_t>(c)] >= 0) Ld(parent[static_cast<size_t>(c)], c) = -0.5;
  }
  return Ld;
}

}  // namespace

TEST(SupernodalSolve, SplitsTwoEqualBranchesUnderTheirRoot) {
  // 0-1-2 and 3-4-5 are two chains joined at 6, the root: the tail is {6}.
  const Layout f = single_columns(tree_factor({1, 2, 6, 4, 5, 6, -1}));
  SupernodalFactor pattern = f.view();
  pattern.values = nullptr;  // as after the symbolic analysis: the split reads no values
  const TreeSplit split = split_elimination_tree(pattern, 0.0);
  ASSERT_TRUE(split.parallel());  // on any number of threads: the split fixes the sums' order
  EXPECT_EQ(split.tail, std::vector<int>{6});
  EXPECT_EQ(split.tail_columns, 1);
  EXPECT_EQ(split.tail_slot[6], 0);
  EXPECT_EQ(split.tail_slot[2], -1);
  std::vector<std::pair<int, int>> both = split.halves[0];
  both.insert(both.end(), split.halves[1].begin(), split.halves[1].end());
  std::sort(both.begin(), both.end());
  EXPECT_EQ(both, (std::vector<std::pair<int, int>>{{0, 3}, {3, 6}}));
}

TEST(SupernodalSolve, OpensTheHeavierSubtreeUntilTheHalvesBalance) {
  // Root 8 has children 0 (a leaf) and 7, whose subtree 1..7 forks at 7 into 1-2-3 and 4-5-6:
  // the split opens 8, then 7.
  const Layout f = single_columns(tree_factor({8, 2, 3, 7, 5, 6, 7, 8, -1}));
  const TreeSplit split = split_elimination_tree(f.view(), 0.0);
  if (parallel_threads() < 2) return;
  ASSERT_TRUE(split.parallel());
  EXPECT_EQ(split.tail, (std::vector<int>{7, 8}));
}

TEST(SupernodalSolve, KeepsOneThreadForAChainSmallFactorsOrANonPostorder) {
  const Layout chain = single_columns(tree_factor({1, 2, 3, 4, -1}));
  EXPECT_FALSE(split_elimination_tree(chain.view(), 0.0).parallel());  // nothing to split
  const Layout forked = single_columns(tree_factor({1, 2, 6, 4, 5, 6, -1}));
  EXPECT_FALSE(split_elimination_tree(forked.view()).parallel());  // below the size bound
  Layout scrambled = forked;
  // Column 3's parent listed as 0, an earlier column: not a postorder.
  scrambled.rows[static_cast<size_t>(scrambled.pi[3]) + 1] = 0;
  EXPECT_FALSE(split_elimination_tree(scrambled.view(), 0.0).parallel());
}

TEST(SupernodalSolve, SolvesWithAHandMadeFactorSplitOrNot) {
  const std::vector<int> parent = {8, 2, 3, 7, 5, 6, 7, 8, -1};
  const Eigen::MatrixXd Ld = tree_factor(parent);
  const Eigen::MatrixXd A = Ld * Ld.transpose();
  Layout f = single_columns(Ld);
  f.perm = {3, 0, 8, 1, 7, 2, 6, 4, 5};  // L L^T = P A P^T: row k of PAP^T is row perm[k] of A
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(9, 9);
  for (int k = 0; k < 9; ++k) P(k, f.perm[static_cast<size_t>(k)]) = 1.0;
  const Eigen::MatrixXd Aperm = P.transpose() * A * P;  // the matrix this factor solves
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(9, 3);
  const Eigen::MatrixXd expected = Aperm.llt().solve(B);
  SolveWork work;
  for (const TreeSplit& split : {TreeSplit{}, split_elimination_tree(f.view(), 0.0)}) {
    Eigen::MatrixXd X;
    supernodal_solve(f.view(), split, B, X, work);
    EXPECT_LT((X - expected).norm() / expected.norm(), 1e-13) << "parallel: " << split.parallel();
  }
}
