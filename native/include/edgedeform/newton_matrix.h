// The Newton matrix K = A - D of fixed_point_linearization.h assembled as a sparse matrix,
// for a direct factorization (docs/design.md §4, "Reaching the fixed point").
//
// Unknowns are the free coordinates, interleaved: row and column 3v + c is coordinate c of
// free vertex v, so that every vertex pair is a dense 3x3 block and a fill-reducing order of
// the vertices (nf x nf) serves the whole matrix.
//
// D is a sum over the energy terms: term t's fitted rotation and scale (omega_t, ds_t) respond
// to the positions of the free vertices its arcs touch (In_t, 4 x 3 per vertex), and move the
// right side of the same vertices (Out, 3 x 4 per right-side block of t). So term t adds a
// dense block over its vertices x its vertices, and K's block pattern is A's plus each term's
// vertex set squared (in the edge domain the two triangles of an edge: the opposite vertices
// of a diamond couple, which A does not couple).
//
// The pattern and the scatter positions are computed once per constraint set (analysis); each
// assemble() writes the values, in parallel over block rows: every entry is summed by one
// thread in a fixed order, the same on any number of threads. Each row's entries are stored
// together (the compressed columns of K^T), so that a row's thread writes one region; where
// K is symmetric that is K itself.
#pragma once

#include <vector>

#include "edgedeform/constrained_system.h"
#include "edgedeform/fixed_point_linearization.h"
#include "edgedeform/types.h"

namespace edgedeform {

class NewtonMatrix {
 public:
  // The pattern of K for `system` with the operators `assembled` (A's pattern included).
  NewtonMatrix(const ConstrainedSystem& system, const AssembledSystem& assembled);

  // K at the linearization point of `lin` (which must be of the same system and operators),
  // into transpose(): 3 nf x 3 nf, both triangles stored (symmetric where lambda = 1 on every
  // term; with the per-node positive model of `lin` positive semi-definite there).
  void assemble(const FixedPointLinearization& lin);

  // K^T as assembled (values of the last assemble(); zeros before): K itself where K is symmetric.
  const SparseMatrix& transpose() const { return K_; }
  // The block pattern as an nf x nf matrix (ones): for a fill-reducing order of the vertices.
  SparseMatrix block_pattern() const;
  // A vertex order (order[k] = the vertex eliminated k-th) expanded to the coordinates.
  static std::vector<int> coordinate_order(const std::vector<int>& vertex_order);

  int free_vertices() const { return nf_; }

 private:
  // Position in K^T's values of K's entry (3 r + i, 3 v + c), `slot` block (r, v)'s slot.
  long position(int slot, int r, int i, int c) const;

  // What the pattern was made for: assemble() refuses another linearization's (the owner
  // keeps both alive and makes a new NewtonMatrix when they change).
  const ConstrainedSystem* system_;
  const AssembledSystem* assembled_;
  int nf_ = 0;
  std::vector<int> row_start_;    // per block row r: its first slot (nf + 1 entries)
  std::vector<int> slot_column_;  // per slot: its block column v (ascending within a row)
  // Per term: its free vertices term_vertex_[term_start_[t] .. term_start_[t+1]), sorted.
  std::vector<int> term_start_, term_vertex_;
  // Per right-side block b (RotationOperator's, in its row order) and each vertex j of b's
  // term: the slot of (row of b, that vertex).
  std::vector<long> block_scatter_start_;
  std::vector<int> block_scatter_;
  // Per entry of A (column-major: entry (i, j)): the slot of block (j, i), so that column r
  // of the symmetric A serves as its row r.
  std::vector<int> a_scatter_;
  SparseMatrix K_;
};

}  // namespace edgedeform
