// Array and matrix types shared by the whole core.
#pragma once

#include <string>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace edgedeform {

// Positions are (n,3) row-major float64, faces (m,3) row-major int32: the NumPy layout.
using RowMatrixX3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using RowMatrixX3i = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
using RowMatrixX2i = Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor>;
using SparseMatrix = Eigen::SparseMatrix<double>;                     // column-major
using SparseMatrixRowMajor = Eigen::SparseMatrix<double, Eigen::RowMajor>;

enum class Domain { Edge, Primal };

const char* domain_name(Domain domain);
// "edge" | "primal"; anything else throws std::invalid_argument.
Domain parse_domain(const std::string& name);

}  // namespace edgedeform
