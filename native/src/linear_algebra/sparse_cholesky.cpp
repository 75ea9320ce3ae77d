#include "linear_algebra/sparse_cholesky.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "base/errors.h"
#include "base/serial_blas.h"
#include "base/serial_openmp.h"
#include "linear_algebra/supernodal_solve.h"

#ifdef EDGEDEFORM_HAS_CHOLMOD
#include <cholmod.h>
#else
#include <Eigen/SparseCholesky>
#endif

namespace edgedeform {

namespace {

// Same size and the same stored entries as last time: the symbolic analysis still holds.
struct Pattern {
  std::vector<int> outer, inner;
  bool matches(const SparseMatrix& A) const {
    const auto n = static_cast<size_t>(A.cols());
    if (outer.size() != n + 1 || inner.size() != static_cast<size_t>(A.nonZeros())) return false;
    return std::equal(outer.begin(), outer.end(), A.outerIndexPtr()) &&
           std::equal(inner.begin(), inner.end(), A.innerIndexPtr());
  }
  void remember(const SparseMatrix& A) {
    outer.assign(A.outerIndexPtr(), A.outerIndexPtr() + A.cols() + 1);
    inner.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
  }
};

}  // namespace

#ifdef EDGEDEFORM_HAS_CHOLMOD

struct SparseCholesky::Impl {
  cholmod_common common;
  cholmod_factor* factor = nullptr;
  SolveWork work;     // supernodal_solve's scratch: a solve allocates nothing after the first
  TreeSplit split;    // of the current analysis's elimination tree
  Pattern pattern;
  bool factored = false;
  int analyses = 0;
  int orderings = 0;
  int factorizations = 0;

  Impl() {
    cholmod_start(&common);
    common.supernodal = CHOLMOD_SUPERNODAL;
    least_fill_orderings();
    common.print = 0;
    common.error_handler = nullptr;
  }
  // Try AMD and METIS and keep the ordering with less fill: on these surface meshes METIS
  // saves ~10% of the factor, and every iteration's back-substitution reads all of it.
  void least_fill_orderings() {
    common.nmethods = 2;
    common.method[0].ordering = CHOLMOD_AMD;
    common.method[1].ordering = CHOLMOD_METIS;
  }
  void quick_ordering() {
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_AMD;
  }
  void given_ordering() {
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_GIVEN;
  }
  ~Impl() {
    cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
  }

  static SupernodalFactor supernodal(const cholmod_factor& F) {
    SupernodalFactor L;
    L.n = static_cast<int>(F.n);
    L.supernodes = static_cast<int>(F.nsuper);
    L.super = static_cast<const int*>(F.super);
    L.pi = static_cast<const int*>(F.pi);
    L.px = static_cast<const int*>(F.px);
    L.rows = static_cast<const int*>(F.s);
    L.values = static_cast<const double*>(F.x);
    L.perm = static_cast<const int*>(F.Perm);
    return L;
  }

  // A view of Eigen's compressed column storage; stype -1 reads the lower triangle.
  static cholmod_sparse view(const SparseMatrix& A) {
    cholmod_sparse s{};
    s.nrow = static_cast<size_t>(A.rows());
    s.ncol = static_cast<size_t>(A.cols());
    s.nzmax = static_cast<size_t>(A.nonZeros());
    s.p = const_cast<int*>(A.outerIndexPtr());
    s.i = const_cast<int*>(A.innerIndexPtr());
    s.x = const_cast<double*>(A.valuePtr());
    s.stype = -1;
    s.itype = CHOLMOD_INT;
    s.xtype = CHOLMOD_REAL;
    s.dtype = CHOLMOD_DOUBLE;
    s.sorted = 1;
    s.packed = 1;
    return s;
  }
};

SparseCholesky::SparseCholesky() : impl_(std::make_unique<Impl>()) {}
SparseCholesky::~SparseCholesky() = default;

void SparseCholesky::factorize(const SparseMatrix& A, Ordering ordering) { factorize(A, {}, ordering); }

void SparseCholesky::factorize(const SparseMatrix& A, const std::vector<int>& order) {
  factorize(A, order, Ordering::LeastFill);
}

void SparseCholesky::factorize(const SparseMatrix& A, const std::vector<int>& order, Ordering ordering) {
  const SerialOpenMP serial;  // CHOLMOD's fixed team of 4 (serial_openmp.h)
  const SerialBlas serial_blas;  // the same factor on any number of threads (serial_blas.h)
  Impl& m = *impl_;
  m.factored = false;
  cholmod_sparse view = Impl::view(A);
  if (!m.factor || !m.pattern.matches(A)) {
    cholmod_free_factor(&m.factor, &m.common);
    m.pattern = Pattern{};
    if (order.empty()) {
      if (ordering == Ordering::Quick) m.quick_ordering();
      m.factor = cholmod_analyze(&view, &m.common);
      m.least_fill_orderings();
      ++m.orderings;
    } else {
      if (order.size() != static_cast<size_t>(A.cols())) throw std::invalid_argument("elimination order has the wrong size");
      m.given_ordering();
      m.factor = cholmod_analyze_p(&view, const_cast<int*>(order.data()), nullptr, 0, &m.common);
      m.least_fill_orderings();
    }
    if (!m.factor) throw FactorizationError("CHOLMOD could not analyze the matrix (status " + std::to_string(m.common.status) + ")");
    m.pattern.remember(A);
    ++m.analyses;
    // The symbolic supernodal factor already holds the supernodes and their rows.
    m.split = split_elimination_tree(Impl::supernodal(*m.factor));
  }
  ++m.factorizations;
  const int ok = cholmod_factorize(&view, m.factor, &m.common);
  if (!ok || m.common.status == CHOLMOD_NOT_POSDEF || m.factor->minor < m.factor->n)
    throw FactorizationError(
        "the deformation matrix is not positive definite (column " + std::to_string(m.factor->minor) +
        " of " + std::to_string(m.factor->n) + "): a free region without constraints, or degenerate triangles "
        "whose weights were all clamped to zero");
  if (!m.factor->is_super || !m.factor->is_ll)  // solve() reads the supernodal layout
    throw FactorizationError("CHOLMOD returned a simplicial factor where a supernodal one was asked for");
  m.factored = true;
}

void SparseCholesky::solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) {
  Impl& m = *impl_;
  if (!m.factored) throw FactorizationError("solve called without a factorization");
  // common.supernodal = CHOLMOD_SUPERNODAL: the factor is always supernodal LL^T, solved
  // here without cholmod_solve2 (supernodal_solve.h says why).
  const SupernodalFactor L = Impl::supernodal(*m.factor);
  supernodal_solve(L, m.split, B, X, m.work);
}

std::vector<int> SparseCholesky::order() const {
  const cholmod_factor* L = impl_->factor;
  if (!L) return {};
  const int* perm = static_cast<const int*>(L->Perm);
  return std::vector<int>(perm, perm + L->n);
}

bool SparseCholesky::factored() const { return impl_->factored; }
int SparseCholesky::analyses() const { return impl_->analyses; }
int SparseCholesky::orderings() const { return impl_->orderings; }
int SparseCholesky::factorizations() const { return impl_->factorizations; }
double SparseCholesky::factor_nonzeros() const { return impl_->factor ? impl_->common.lnz : 0.0; }
bool SparseCholesky::solves_in_parallel() const { return impl_->factored && impl_->split.parallel(); }
const char* SparseCholesky::backend() { return "cholmod-supernodal"; }

#else  // Eigen fallback

struct SparseCholesky::Impl {
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower> ldlt;
  Pattern pattern;
  bool analyzed = false;
  bool factored = false;
  int analyses = 0;
  int factorizations = 0;
};

SparseCholesky::SparseCholesky() : impl_(std::make_unique<Impl>()) {}
SparseCholesky::~SparseCholesky() = default;

void SparseCholesky::factorize(const SparseMatrix& A, const std::vector<int>&) { factorize(A); }

void SparseCholesky::factorize(const SparseMatrix& A, const std::vector<int>&, Ordering) { factorize(A); }

std::vector<int> SparseCholesky::order() const { return {}; }

void SparseCholesky::factorize(const SparseMatrix& A, Ordering) {
  Impl& m = *impl_;
  m.factored = false;
  if (!m.analyzed || !m.pattern.matches(A)) {
    m.ldlt.analyzePattern(A);
    m.pattern.remember(A);
    m.analyzed = true;
    ++m.analyses;
  }
  ++m.factorizations;
  m.ldlt.factorize(A);
  if (m.ldlt.info() != Eigen::Success || (m.ldlt.vectorD().array() <= 0.0).any())
    throw FactorizationError("the deformation matrix is not positive definite: a free region without "
                             "constraints, or degenerate triangles whose weights were all clamped to zero");
  m.factored = true;
}

void SparseCholesky::solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) {
  if (!impl_->factored) throw FactorizationError("solve called without a factorization");
  if (B.rows() != impl_->ldlt.rows() || B.cols() < 1 || B.cols() > kMaxRightHandSides)
    throw std::invalid_argument("solve: B must have the matrix's rows and 1.." +
                                std::to_string(kMaxRightHandSides) + " columns");
  X = impl_->ldlt.solve(B);
}

bool SparseCholesky::factored() const { return impl_->factored; }
int SparseCholesky::analyses() const { return impl_->analyses; }
int SparseCholesky::orderings() const { return impl_->analyses; }
int SparseCholesky::factorizations() const { return impl_->factorizations; }
double SparseCholesky::factor_nonzeros() const {
  return impl_->factored ? static_cast<double>(impl_->ldlt.matrixL().nestedExpression().nonZeros()) : 0.0;
}
bool SparseCholesky::solves_in_parallel() const { return false; }
const char* SparseCholesky::backend() { return "eigen-simplicial-ldlt"; }

#endif

}  // namespace edgedeform
