// NumPy -> Eigen conversion with argument-naming errors. The only place that sees NumPy.
#pragma once

#include <optional>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "base/types.h"

namespace edgedeform::bindings {

namespace py = pybind11;

// (k,3) floats; throws ValueError naming `name` for another shape or a non-numeric array.
RowMatrixX3d to_points(const py::handle& obj, const char* name);
// (m,3) integers.
RowMatrixX3i to_faces(const py::handle& obj, const char* name);
// 1-D integers; None gives an empty set.
std::vector<int> to_indices(const py::handle& obj, const char* name);
// (n,) floats.
Eigen::VectorXd to_vector(const py::handle& obj, const char* name);

// A sparse matrix as (rows, cols, values, shape) NumPy arrays (COO).
py::tuple to_coo(const SparseMatrix& M);

}  // namespace edgedeform::bindings
