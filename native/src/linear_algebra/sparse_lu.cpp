#include "edgedeform/sparse_lu.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "edgedeform/errors.h"
#include "edgedeform/serial_blas.h"
#include "edgedeform/serial_openmp.h"

#ifdef EDGEDEFORM_HAS_UMFPACK
#include <umfpack.h>
#else
#include <Eigen/OrderingMethods>
#include <Eigen/SparseLU>
#endif

namespace edgedeform {

namespace {

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

void check_compressed(const SparseMatrix& A) {
  if (A.rows() != A.cols()) throw std::invalid_argument("SparseLU: the matrix must be square");
  if (!A.isCompressed()) throw std::invalid_argument("SparseLU: the matrix must be compressed");
}

}  // namespace

#ifdef EDGEDEFORM_HAS_UMFPACK

struct SparseLU::Impl {
  double control[UMFPACK_CONTROL];
  double info[UMFPACK_INFO];
  void* symbolic = nullptr;
  void* numeric = nullptr;
  Pattern pattern;
  std::vector<int> outer, inner;         // copies: solve() needs A's pattern and values
  std::vector<double> values;
  bool factored = false;
  int analyses = 0, factorizations = 0;
  double lu_entries = 0.0;
  Impl() {
    umfpack_di_defaults(control);
    control[UMFPACK_STRATEGY] = UMFPACK_STRATEGY_SYMMETRIC;  // pivots on the diagonal first
    control[UMFPACK_IRSTEP] = 0;  // no iterative refinement: a Newton step needs no more
  }
  ~Impl() {
    umfpack_di_free_numeric(&numeric);
    umfpack_di_free_symbolic(&symbolic);
  }
};

SparseLU::SparseLU() : impl_(std::make_unique<Impl>()) {}
SparseLU::~SparseLU() = default;

void SparseLU::factorize(const SparseMatrix& A, const std::vector<int>& order) {
  check_compressed(A);
  const SerialOpenMP serial;
  const SerialBlas serial_blas;  // the same factor on any number of threads (serial_blas.h)
  Impl& m = *impl_;
  m.factored = false;
  umfpack_di_free_numeric(&m.numeric);
  const int n = static_cast<int>(A.rows());
  if (!m.symbolic || !m.pattern.matches(A)) {
    umfpack_di_free_symbolic(&m.symbolic);
    m.pattern = Pattern{};
    if (!order.empty() && order.size() != static_cast<size_t>(n))
      throw std::invalid_argument("elimination order has the wrong size");
    const int status =
        order.empty() ? umfpack_di_symbolic(n, n, A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(), &m.symbolic,
                                            m.control, m.info)
                      : umfpack_di_qsymbolic(n, n, A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(), order.data(),
                                             &m.symbolic, m.control, m.info);
    if (status != UMFPACK_OK)
      throw FactorizationError("UMFPACK could not analyze the Newton matrix (status " + std::to_string(status) + ")");
    m.pattern.remember(A);
    ++m.analyses;
  }
  ++m.factorizations;
  const int status = umfpack_di_numeric(A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(), m.symbolic, &m.numeric,
                                        m.control, m.info);
  if (status != UMFPACK_OK) {
    umfpack_di_free_numeric(&m.numeric);
    throw FactorizationError(status == UMFPACK_WARNING_singular_matrix
                                 ? "the Newton matrix is singular"
                                 : "UMFPACK could not factor the Newton matrix (status " + std::to_string(status) + ")");
  }
  m.outer = m.pattern.outer;
  m.inner = m.pattern.inner;
  m.values.assign(A.valuePtr(), A.valuePtr() + A.nonZeros());
  m.lu_entries = m.info[UMFPACK_LNZ] + m.info[UMFPACK_UNZ];
  m.factored = true;
}

void SparseLU::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, bool transposed) {
  Impl& m = *impl_;
  if (!m.factored) throw FactorizationError("solve called without a factorization");
  if (b.size() != static_cast<Eigen::Index>(m.outer.size()) - 1)
    throw std::invalid_argument("SparseLU::solve: b has the wrong size");
  const SerialBlas serial_blas;
  Eigen::VectorXd out(b.size());
  const int status = umfpack_di_solve(transposed ? UMFPACK_At : UMFPACK_A, m.outer.data(), m.inner.data(), m.values.data(), out.data(), b.data(),
                                      m.numeric, m.control, m.info);
  if (status != UMFPACK_OK && status != UMFPACK_WARNING_singular_matrix)
    throw FactorizationError("UMFPACK could not solve with the Newton matrix (status " + std::to_string(status) + ")");
  x.swap(out);
}

bool SparseLU::factored() const { return impl_->factored; }
int SparseLU::analyses() const { return impl_->analyses; }
int SparseLU::factorizations() const { return impl_->factorizations; }
double SparseLU::factor_nonzeros() const { return impl_->lu_entries; }
const char* SparseLU::backend() { return "umfpack"; }

#else  // Eigen fallback

struct SparseLU::Impl {
  Eigen::SparseLU<SparseMatrix, Eigen::COLAMDOrdering<int>> lu;
  Pattern pattern;
  bool analyzed = false, factored = false;
  int analyses = 0, factorizations = 0;
};

SparseLU::SparseLU() : impl_(std::make_unique<Impl>()) {}
SparseLU::~SparseLU() = default;

void SparseLU::factorize(const SparseMatrix& A, const std::vector<int>&) {
  check_compressed(A);
  Impl& m = *impl_;
  m.factored = false;
  if (!m.analyzed || !m.pattern.matches(A)) {
    m.lu.analyzePattern(A);
    m.pattern.remember(A);
    m.analyzed = true;
    ++m.analyses;
  }
  ++m.factorizations;
  m.lu.factorize(A);
  if (m.lu.info() != Eigen::Success) throw FactorizationError("the Newton matrix is singular");
  m.factored = true;
}

void SparseLU::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, bool transposed) {
  Impl& m = *impl_;
  if (!m.factored) throw FactorizationError("solve called without a factorization");
  if (b.size() != m.lu.rows()) throw std::invalid_argument("SparseLU::solve: b has the wrong size");
  x = transposed ? Eigen::VectorXd(m.lu.transpose().solve(b)) : Eigen::VectorXd(m.lu.solve(b));
}

bool SparseLU::factored() const { return impl_->factored; }
int SparseLU::analyses() const { return impl_->analyses; }
int SparseLU::factorizations() const { return impl_->factorizations; }
double SparseLU::factor_nonzeros() const {
  return impl_->factored ? static_cast<double>(impl_->lu.nnzL() + impl_->lu.nnzU()) : 0.0;
}
const char* SparseLU::backend() { return "eigen-sparse-lu"; }

#endif

}  // namespace edgedeform
