#include "system/rotation_operator.h"

#include <stdexcept>

#include <Eigen/Geometry>
#include <string>

#include "base/parallel.h"

namespace edgedeform {

namespace {
// Threads only for at least this many rows (about 0.4 ms of work at ~500 instructions a
// row); the bound of the former OpenMP loop, not measured apart: the right-hand side is
// under 10 % of an iteration.
constexpr int kMinParallelRows = 4096;
constexpr int kRowsPerChunk = 512;
}  // namespace

RotationOperator::RotationOperator(const SparseMatrixRowMajor& H) {
  lambda_.assign(static_cast<size_t>(H.cols() / 6), 1.0);
  similar_.assign(lambda_.size(), 0.0);
  offsets_.assign(1, 0);
  offsets_.reserve(static_cast<size_t>(H.rows()) + 1);
  term_.reserve(static_cast<size_t>(H.nonZeros() / 3));
  coef_.reserve(static_cast<size_t>(2 * H.nonZeros()));
  for (Eigen::Index r = 0; r < H.rows(); ++r) {
    int current = -1;
    for (SparseMatrixRowMajor::InnerIterator it(H, r); it; ++it) {  // columns ascend
      const int t = static_cast<int>(it.col() / 6), k = static_cast<int>(it.col() % 6);
      if (t != current) {
        current = t;
        term_.push_back(t);
        coef_.insert(coef_.end(), 6, 0.0);
      }
      coef_[coef_.size() - 6 + static_cast<size_t>(k)] = it.value();
    }
    offsets_.push_back(static_cast<int>(term_.size()));
  }
}

RotationOperator::RotationOperator(std::vector<int> offsets, std::vector<int> term, std::vector<double> coef, int terms)
    : offsets_(std::move(offsets)), term_(std::move(term)), coef_(std::move(coef)), lambda_(static_cast<size_t>(terms), 1.0),
      similar_(static_cast<size_t>(terms), 0.0) {
  if (offsets_.empty() || offsets_.front() != 0 || static_cast<size_t>(offsets_.back()) != term_.size() ||
      coef_.size() != 6 * term_.size())
    throw std::invalid_argument("RotationOperator: offsets, terms and coefficients do not agree");
  for (int t : term_)
    if (t < 0 || t >= terms) throw std::out_of_range("RotationOperator: term " + std::to_string(t) + " out of range");
}

RotationOperator RotationOperator::restricted(const std::vector<int>& rows, const std::vector<int>& term_map,
                                              int terms) const {
  if (term_map.size() != lambda_.size())
    throw std::invalid_argument("term_map has " + std::to_string(term_map.size()) + " entries, expected " +
                                std::to_string(lambda_.size()) + " (one per term)");
  std::vector<int> offsets(1, 0), term;
  std::vector<double> coef;
  size_t blocks = 0;
  for (int r : rows) {
    if (r < 0 || r >= this->rows()) throw std::out_of_range("RotationOperator: row " + std::to_string(r) + " out of range");
    blocks += static_cast<size_t>(offsets_[static_cast<size_t>(r) + 1] - offsets_[static_cast<size_t>(r)]);
  }
  offsets.reserve(rows.size() + 1);
  term.reserve(blocks);
  coef.reserve(6 * blocks);
  for (int r : rows) {
    const auto begin = static_cast<size_t>(offsets_[static_cast<size_t>(r)]);
    const auto end = static_cast<size_t>(offsets_[static_cast<size_t>(r) + 1]);
    for (size_t b = begin; b < end; ++b) {
      const int t = term_map[static_cast<size_t>(term_[b])];
      if (t < 0) throw std::invalid_argument("RotationOperator: row " + std::to_string(r) + " uses a dropped term");
      term.push_back(t);
    }
    coef.insert(coef.end(), coef_.begin() + static_cast<long>(6 * begin), coef_.begin() + static_cast<long>(6 * end));
    offsets.push_back(static_cast<int>(term.size()));
  }
  return RotationOperator(std::move(offsets), std::move(term), std::move(coef), terms);
}

void RotationOperator::set_term_lambda(const Eigen::VectorXd& term_lambda, const Eigen::VectorXd& term_similar) {
  const auto expected = static_cast<Eigen::Index>(lambda_.size());
  if (term_lambda.size() != expected || (term_similar.size() != 0 && term_similar.size() != expected))
    throw std::invalid_argument("term_lambda has " + std::to_string(term_lambda.size()) + " entries and term_similar " +
                                std::to_string(term_similar.size()) + ", expected " + std::to_string(expected) +
                                " (one per term)");
  lambda_.assign(term_lambda.data(), term_lambda.data() + term_lambda.size());
  if (term_similar.size() == 0)
    similar_.assign(lambda_.size(), 0.0);
  else
    similar_.assign(term_similar.data(), term_similar.data() + term_similar.size());
}

void RotationOperator::apply(const std::vector<Eigen::Matrix3d>& rotation, const Eigen::VectorXd& scale,
                             const Eigen::MatrixXd& c, Eigen::MatrixXd& y, std::vector<double>& term_weights) const {
  // Each term's two weights first, side by side: a block then gathers one cache line for
  // them instead of three (lambda, phi, s), which made the row loop ~20 % slower (koala).
  const int T = terms();
  term_weights.resize(2 * static_cast<size_t>(T));
  double* weight = term_weights.data();
  parallel_for(T, kRowsPerChunk, kMinParallelRows, [&](int begin, int end) {
    for (int t = begin; t < end; ++t) {
      const auto k = static_cast<size_t>(t);
      const double s = scale(t);
      const TermShares share = term_shares(lambda_[k], similar_[k]);
      weight[2 * k] = share.rigid + share.similar * s;  // on h_R
      weight[2 * k + 1] = share.smooth * s;             // on h_T
    }
  });
  const int n = rows();
  y.resize(n, 3);
  parallel_for(n, kRowsPerChunk, kMinParallelRows, [&](int begin, int end) {
    for (int r = begin; r < end; ++r) {
      Eigen::Vector3d sum = c.row(r).transpose();
      for (int b = offsets_[static_cast<size_t>(r)]; b < offsets_[static_cast<size_t>(r) + 1]; ++b) {
        const auto t = static_cast<size_t>(term_[static_cast<size_t>(b)]);
        const double* h = &coef_[6 * static_cast<size_t>(b)];
        const double rigid = weight[2 * t], smooth = weight[2 * t + 1];
        const Eigen::Vector3d g(rigid * h[0] + smooth * h[3], rigid * h[1] + smooth * h[4], rigid * h[2] + smooth * h[5]);
        sum.noalias() += rotation[t] * g;
      }
      y.row(r) = sum.transpose();
    }
  });
}

void RotationOperator::apply_derivative(const std::vector<Eigen::Matrix3d>& rotation, const Eigen::VectorXd& scale,
                                        const RowMatrixX3d& omega, const Eigen::VectorXd& dscale,
                                        Eigen::MatrixXd& dy) const {
  const int n = rows();
  dy.resize(n, 3);
  parallel_for(n, kRowsPerChunk, kMinParallelRows, [&](int begin, int end) {
    Eigen::Vector3d g, k;
    for (int r = begin; r < end; ++r) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int b = offsets_[static_cast<size_t>(r)]; b < offsets_[static_cast<size_t>(r) + 1]; ++b) {
        const int t = term_[static_cast<size_t>(b)];
        block_vectors(b, scale(t), g, k);
        const Eigen::Matrix3d& R = rotation[static_cast<size_t>(t)];
        sum.noalias() += omega.row(t).transpose().cross(R * g) + dscale(t) * (R * k);
      }
      dy.row(r) = sum.transpose();
    }
  });
}

}  // namespace edgedeform
