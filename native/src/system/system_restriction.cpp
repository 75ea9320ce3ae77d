#include "system/system_restriction.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace edgedeform {

namespace {

// Local id in `sys` (free, then fixed) of every vertex its terms touch; -1 for the others.
std::vector<int> local_ids(const ConstrainedSystem& sys) {
  std::vector<int> local(static_cast<size_t>(sys.n_vertices), -1);
  for (int k = 0; k < sys.n_free(); ++k) local[static_cast<size_t>(sys.free_vertices[static_cast<size_t>(k)])] = k;
  for (int k = 0; k < sys.n_fixed(); ++k)
    local[static_cast<size_t>(sys.fixed_vertices[static_cast<size_t>(k)])] = sys.n_free() + k;
  return local;
}

// Columns picked from other matrices, their rows renumbered by row_map (-1: dropped). With
// a row_map that keeps the rows' order, each column stays sorted, as CHOLMOD needs.
class ColumnGather {
 public:
  explicit ColumnGather(const std::vector<int>& row_map) : row_map_(row_map) {}
  void add(const SparseMatrix& from, int column) {
    for (SparseMatrix::InnerIterator it(from, column); it; ++it) {
      const int r = row_map_[static_cast<size_t>(it.row())];
      if (r < 0) continue;
      inner_.push_back(r);
      value_.push_back(it.value());
    }
    outer_.push_back(static_cast<int>(inner_.size()));
  }
  SparseMatrix matrix(int rows) const {  // copied array by array (Eigen's generic copy is ~3x slower)
    SparseMatrix m(rows, static_cast<Eigen::Index>(outer_.size()) - 1);
    m.resizeNonZeros(static_cast<Eigen::Index>(inner_.size()));
    std::copy(outer_.begin(), outer_.end(), m.outerIndexPtr());
    std::copy(inner_.begin(), inner_.end(), m.innerIndexPtr());
    std::copy(value_.begin(), value_.end(), m.valuePtr());
    return m;
  }

 private:
  const std::vector<int>& row_map_;
  std::vector<int> outer_{0}, inner_;
  std::vector<double> value_;
};

// whole's term t -> part's term (-1: inactive in part). Both term lists ascend by node.
std::vector<int> term_map(const ConstrainedSystem& whole, const ConstrainedSystem& part) {
  std::vector<int> map(static_cast<size_t>(whole.n_terms()), -1);
  size_t k = 0;
  for (size_t t = 0; t < map.size() && k < part.term_nodes.size(); ++t)
    if (whole.term_nodes[t] == part.term_nodes[k]) map[t] = static_cast<int>(k++);
  if (k != part.term_nodes.size()) throw std::logic_error("restrict_assembly: part has a term the whole set lacks");
  return map;
}

// Some term with lambda < 1 (AssembledSystem::laplacian_term).
bool has_laplacian_term(const ConstrainedSystem& sys, const Eigen::VectorXd& vertex_lambda) {
  return (term_stiffness(sys, vertex_lambda).array() < 1.0).any();
}

}  // namespace

bool frees_subset(const ConstrainedSystem& part, const ConstrainedSystem& whole) {
  if (part.n_vertices != whole.n_vertices || part.n_free() > whole.n_free()) return false;
  std::vector<char> free(static_cast<size_t>(whole.n_vertices), 0);
  for (int v : whole.free_vertices) free[static_cast<size_t>(v)] = 1;
  for (int v : part.free_vertices)
    if (!free[static_cast<size_t>(v)]) return false;
  return true;
}

bool restriction_keeps_pattern(const ConstrainedSystem& whole, const ConstrainedSystem& part,
                               const Eigen::VectorXd& vertex_lambda) {
  return frees_subset(part, whole) && has_laplacian_term(part, vertex_lambda) == has_laplacian_term(whole, vertex_lambda);
}

AssembledSystem restrict_assembly(const AssembledSystem& whole_assembled, const ConstrainedSystem& whole,
                                  const ConstrainedSystem& part, const Eigen::VectorXd& vertex_lambda) {
  if (!assembled_at(whole_assembled, whole, vertex_lambda))
    throw std::logic_error("restrict_assembly: the whole set's operators hold another stiffness");
  const int nf_whole = whole.n_free(), nf = part.n_free();
  const std::vector<int> whole_local = local_ids(whole);
  // Part's free id of each of whole's free vertices (-1: fixed in part), and its inverse.
  std::vector<int> part_row(static_cast<size_t>(nf_whole), -1), whole_row(static_cast<size_t>(nf));
  for (int p = 0; p < nf; ++p) {
    const int w = whole_local[static_cast<size_t>(part.free_vertices[static_cast<size_t>(p)])];
    if (w < 0 || w >= nf_whole) throw std::logic_error("restrict_assembly: part frees a vertex the whole set fixes");
    part_row[static_cast<size_t>(w)] = p;
    whole_row[static_cast<size_t>(p)] = w;
  }

  AssembledSystem out;
  ColumnGather A(part_row);
  for (int p = 0; p < nf; ++p) A.add(whole_assembled.A, whole_row[static_cast<size_t>(p)]);
  out.A = A.matrix(nf);
  // A fixed vertex of part was free in whole (its coupling is in A_whole) or fixed there too.
  ColumnGather K(part_row);
  for (int u : part.fixed_vertices) {
    const int w = whole_local[static_cast<size_t>(u)];
    if (w < 0) throw std::logic_error("restrict_assembly: part's terms touch a vertex the whole set's do not");
    if (w < nf_whole)
      K.add(whole_assembled.A, w);
    else
      K.add(whole_assembled.K_fixed, w - nf_whole);
  }
  out.K_fixed = K.matrix(nf);
  out.H = whole_assembled.H.restricted(whole_row, term_map(whole, part), part.n_terms());
  set_term_stiffness(out, part, vertex_lambda);
  return out;
}

}  // namespace edgedeform
