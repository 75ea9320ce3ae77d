#include "numpy_convert.h"

#include <limits>
#include <stdexcept>
#include <string>

namespace edgedeform::bindings {

namespace {

py::array as_array(const py::handle& obj, const char* name) {
  if (obj.is_none()) throw std::invalid_argument(std::string(name) + " is None");
  py::array a = py::array::ensure(obj);
  if (!a) throw std::invalid_argument(std::string(name) + " is not array-like");
  return a;
}

char kind_of(const py::array& a) { return a.dtype().kind(); }

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

void require_numeric(const py::array& a, const char* name, const char* kinds) {
  if (std::string(kinds).find(kind_of(a)) == std::string::npos)
    throw std::invalid_argument(std::string(name) + " has dtype " + std::string(py::str(a.dtype())) +
                                (std::string(kinds) == "iu" ? ", expected integers" : ", expected numbers"));
}

int checked_index(int64_t v, const char* name, py::ssize_t k) {
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
    throw std::out_of_range(std::string(name) + "[" + std::to_string(k) + "] = " + std::to_string(v) + " is out of range");
  return static_cast<int>(v);
}

}  // namespace

RowMatrixX3d to_points(const py::handle& obj, const char* name) {
  py::array a = as_array(obj, name);
  require_numeric(a, name, "iuf");
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw std::invalid_argument(std::string(name) + " must have shape (k, 3), got " + shape_text(a));
  auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  return Eigen::Map<const RowMatrixX3d>(d.data(), d.shape(0), 3);
}

RowMatrixX3i to_faces(const py::handle& obj, const char* name) {
  py::array a = as_array(obj, name);
  require_numeric(a, name, "iu");
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw std::invalid_argument(std::string(name) + " must have shape (m, 3) (triangles), got " + shape_text(a));
  auto d = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
  RowMatrixX3i F(d.shape(0), 3);
  for (py::ssize_t k = 0; k < d.size(); ++k) F.data()[k] = checked_index(d.data()[k], name, k / 3);
  return F;
}

std::vector<int> to_indices(const py::handle& obj, const char* name) {
  if (obj.is_none()) return {};
  py::array a = as_array(obj, name);
  if (a.size() == 0) return {};  // an empty list arrives as float64
  require_numeric(a, name, "iu");
  if (a.ndim() != 1) throw std::invalid_argument(std::string(name) + " must be 1-D, got shape " + shape_text(a));
  auto d = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
  std::vector<int> out(static_cast<size_t>(d.size()));
  for (py::ssize_t k = 0; k < d.size(); ++k) out[static_cast<size_t>(k)] = checked_index(d.data()[k], name, k);
  return out;
}

Eigen::VectorXd to_vector(const py::handle& obj, const char* name) {
  py::array a = as_array(obj, name);
  require_numeric(a, name, "iuf");
  if (a.ndim() != 1) throw std::invalid_argument(std::string(name) + " must be 1-D, got shape " + shape_text(a));
  auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  return Eigen::Map<const Eigen::VectorXd>(d.data(), d.shape(0));
}

py::tuple to_coo(const SparseMatrix& M) {
  const auto nnz = static_cast<py::ssize_t>(M.nonZeros());
  py::array_t<int64_t> rows(nnz), cols(nnz);
  py::array_t<double> vals(nnz);
  auto r = rows.mutable_unchecked<1>();
  auto c = cols.mutable_unchecked<1>();
  auto v = vals.mutable_unchecked<1>();
  py::ssize_t k = 0;
  for (Eigen::Index j = 0; j < M.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(M, j); it; ++it, ++k) {
      r(k) = it.row();
      c(k) = it.col();
      v(k) = it.value();
    }
  return py::make_tuple(rows, cols, vals, py::make_tuple(M.rows(), M.cols()));
}

}  // namespace edgedeform::bindings
